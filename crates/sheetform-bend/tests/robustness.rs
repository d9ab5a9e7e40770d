//! Regression tests for inputs that once broke the mesher, each named after what it
//! guards. Every one must give a mesh that covers the sheet exactly and is isometric.

use sheetform_bend::{bend, BendModel, BendScene};
use sheetform_mesh::isometry_error;

fn bend_json(json: &str) -> sheetform_bend::BentSheet {
    let scene = BendScene::from_json(json).unwrap();
    let model = BendModel::from_scene(&scene).unwrap();
    let sheet = bend(&model).unwrap();
    assert!((sheet.mesh.flat_area() - model.sheet.area()).abs() <= 1e-9 * model.sheet.area());
    assert!(isometry_error(&sheet.mesh).max_relative <= 1e-10);
    sheet
}

const S_CURVE: &str = r#"{"type":"bezier","control_points":[[0,0,0],[40,0,30],[80,0,-30],[120,0,0]]}"#;
/// Arc length of `S_CURVE`, rounded the way a person types it.
const S_LENGTH_ROUNDED: &str = "126.3998";

#[test]
fn outline_typed_with_a_rounded_curve_length() {
    // The last geodesic point lies a hair outside (or inside) the end edge; the ruling
    // there runs along that edge.
    for l in [S_LENGTH_ROUNDED, "126.39983332160021", "126.3998333216"] {
        let json = format!(
            r#"{{"outline":[[0,-20],[{l},-20],[{l},20],[0,20]],"regions":[{{"flat_start":[0,0],"flat_direction":[1,0],"curve":{S_CURVE}}}],"tessellation":{{"length_tolerance":1e-5}}}}"#
        );
        let scene = BendScene::from_json(&json).unwrap();
        if let Ok(model) = BendModel::from_scene(&scene) {
            let sheet = bend(&model).unwrap();
            assert!(
                (sheet.mesh.flat_area() - model.sheet.area()).abs() <= 1e-9 * model.sheet.area(),
                "length {l}"
            );
        }
    }
}

#[test]
fn hole_tangent_to_the_flat_geodesic() {
    let hole: Vec<String> = (0..32)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / 32.0 - std::f64::consts::FRAC_PI_2;
            format!("[{},{}]", 60.0 + 10.0 * a.cos(), 10.0 + 10.0 * a.sin())
        })
        .collect();
    let json = format!(
        r#"{{"outline":[[0,-30],[130,-30],[130,30],[0,30]],"holes":[[{}]],"regions":[{{"flat_start":[0,0],"flat_direction":[1,0],"curve":{S_CURVE}}}]}}"#,
        hole.join(",")
    );
    bend_json(&json);
}

#[test]
fn ruling_along_part_of_the_outline() {
    // A T-shaped sheet: the first ruling runs along the bar's edge on both sides of the
    // stem, passing through the two reflex corners.
    let json = format!(
        r#"{{"outline":[[-60,-40],[0,-40],[0,-10],[140,-10],[140,10],[0,10],[0,40],[-60,40]],
            "regions":[{{"flat_start":[0,0],"flat_direction":[1,0],"curve":{S_CURVE}}}]}}"#
    );
    let sheet = bend_json(&json);
    // The bar stays planar: one planar piece before the first ruling.
    assert!(sheet
        .mesh
        .pieces
        .iter()
        .any(|p| p.kind == sheetform_mesh::PieceKind::Planar));
}

//! Non-geodesic control curves (Bo & Wang 2007, §5): the control curve's flat image is a
//! planar curve whose curvature the bent curve keeps as its geodesic curvature.

use sheetform_bend::{bend, BendError, BendModel, BendScene};
use sheetform_geometry::Vec2;
use sheetform_mesh::isometry_error;

fn scene(curve: &str, flat: &str, outline: &str) -> String {
    format!(r#"{{"outline":{outline},"regions":[{{{flat},"curve":{curve}}}]}}"#)
}

/// An annular band between radii 45 and 75 around the origin, from −95° to −20°.
fn band() -> String {
    let arc = |r: f64, from: f64, to: f64| -> Vec<String> {
        (0..=24)
            .map(|i| {
                let a = (from + (to - from) * i as f64 / 24.0).to_radians();
                format!("[{},{}]", r * a.cos(), r * a.sin())
            })
            .collect()
    };
    let mut pts = arc(75.0, -95.0, -20.0);
    pts.extend(arc(45.0, -20.0, -95.0));
    format!("[{}]", pts.join(","))
}

const RING: &str = "[[-20,-75],[75,-75],[75,20],[-20,20]]";

#[test]
fn arc_control_curve_keeps_its_geodesic_curvature() {
    // A band around a flat circular arc of radius 60, bent along a helix of curvature
    // 40 / (40² + 10²) ≈ 0.0235 > 1/60.
    let curve =
        r#"{"type":"helix","radius":40,"rise_per_radian":10,"start_angle":-1.5707963267948966,"end_angle":0.0}"#;
    let flat = r#""flat_start":[0,-60],"flat_direction":[1,0],"flat_curve":{"type":"arc","radius":60,"turn":"left"}"#;
    let json = scene(curve, flat, &band());
    let model = BendModel::from_scene(&BendScene::from_json(&json).unwrap()).unwrap();
    let sheet = bend(&model).unwrap();
    assert!(isometry_error(&sheet.mesh).max_relative <= 1e-10);
    // The flat geodesic vertices lie on the arc (radius 60 about the origin).
    let g = &sheet.geometries[0];
    for s in &g.samples {
        assert!((s.flat_point.norm() - 60.0).abs() < 1e-9, "{}", s.flat_point);
        // The surface normal is orthogonal to the tangent and the in-surface side direction
        // carries exactly the flat curvature: p'' · b = κ_g.
    }
    // The bent curve stays on the control curve (discretisation tolerance).
    assert!(
        sheet.regions[0].curve_deviation < 0.05,
        "{}",
        sheet.regions[0].curve_deviation
    );
}

#[test]
fn geodesic_curvature_is_preserved_by_the_mesh() {
    // Check p''·b = κ_g on the samples directly: curvature vector of the 3D curve
    // projected on the side direction equals the flat curvature 1/60.
    let curve =
        r#"{"type":"helix","radius":40,"rise_per_radian":10,"start_angle":-1.5707963267948966,"end_angle":0.0}"#;
    let flat = r#""flat_start":[0,-60],"flat_direction":[1,0],"flat_curve":{"type":"arc","radius":60,"turn":"left"}"#;
    let model = BendModel::from_scene(&BendScene::from_json(&scene(curve, flat, RING)).unwrap()).unwrap();
    let g = sheetform_bend::region_geometry(&model, 0).unwrap();
    let c = model.regions[0].curve.shape();
    for s in &g.samples {
        let d = sheetform_geometry::ParametricCurve::derivatives4(c, s.parameter);
        let f = sheetform_geometry::curve_frame(&d).unwrap();
        assert!(
            (f.curvature_vector.dot(&s.side) - 1.0 / 60.0).abs() < 1e-9,
            "at s = {}",
            s.arc_length
        );
        assert!(s.normal.dot(&s.tangent).abs() < 1e-12);
    }
}

#[test]
fn control_curve_flatter_than_its_flat_curve_is_refused() {
    // A planar 3D arc of radius 100 cannot carry a flat arc of radius 60.
    let curve = r#"{"type":"helix","radius":100,"start_angle":0,"end_angle":1.0}"#;
    let flat = r#""flat_start":[0,0],"flat_direction":[1,0],"flat_curve":{"type":"arc","radius":60,"turn":"right"}"#;
    let err = BendModel::from_scene(&BendScene::from_json(&scene(curve, flat, RING)).unwrap())
        .and_then(|m| bend(&m).map(|_| ()));
    match err {
        Err(BendError::DegenerateCurve { reason, .. }) => {
            assert!(reason.contains("not larger than the flat curve"), "{reason}")
        }
        other => panic!("expected a curvature error, got {other:?}"),
    }
}

#[test]
fn flat_bezier_path_length_must_match() {
    let curve = r#"{"type":"bezier","control_points":[[0,0,0],[40,0,10],[80,0,0]]}"#;
    let flat = r#""flat_curve":{"type":"bezier","control_points":[[0,0],[30,10],[60,0]]}"#;
    let err = BendModel::from_scene(&BendScene::from_json(&scene(curve, flat, RING)).unwrap()).unwrap_err();
    assert!(matches!(err, BendError::LengthMismatch { .. }), "{err}");
}

#[test]
fn straight_path_gives_the_same_sheet_as_before() {
    // A flat arc of huge radius converges to the straight geodesic case.
    let curve = r#"{"type":"bezier","control_points":[[0,0,0],[70,0,10],[140,8,60],[160,12,120]]}"#;
    let outline = "[[0,-60],[240,-60],[240,60],[0,60]]";
    let straight = BendModel::from_scene(
        &BendScene::from_json(&scene(curve, r#""flat_start":[0,0],"flat_direction":[1,0]"#, outline)).unwrap(),
    )
    .unwrap();
    let arc = BendModel::from_scene(
        &BendScene::from_json(&scene(
            curve,
            r#""flat_start":[0,0],"flat_direction":[1,0],"flat_curve":{"type":"arc","radius":1e12,"turn":"left"}"#,
            outline,
        ))
        .unwrap(),
    )
    .unwrap();
    let (a, b) = (bend(&straight).unwrap(), bend(&arc).unwrap());
    let end = |s: &sheetform_bend::BentSheet| s.geometries[0].samples.last().unwrap().flat_point;
    assert!((end(&a) - end(&b)).norm() < 1e-5);
    let _ = Vec2::zeros();
}

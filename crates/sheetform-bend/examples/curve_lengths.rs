//! Prints the arc length of every region's control curve in a scene (handy when drawing
//! the flat outline of a new scene): `cargo run -p sheetform-bend --example curve_lengths -- SCENE.json`.
use sheetform_bend::{curve_shape, BendScene, ControlCurve};
fn main() {
    let path = std::env::args().nth(1).expect("usage: curve_lengths SCENE.json");
    let scene = BendScene::from_json(&std::fs::read_to_string(&path).expect("readable scene")).expect("valid JSON");
    for (k, r) in scene.regions.iter().enumerate() {
        let shape = curve_shape(&r.curve, "curve").expect("valid curve");
        let length = ControlCurve::new(shape).expect("non-degenerate curve").length();
        println!("region {k}: length {length:.12}");
    }
}

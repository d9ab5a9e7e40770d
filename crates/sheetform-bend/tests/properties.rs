//! Property tests with fixed seeds (proptest's default deterministic RNG per test name is
//! not relied upon: every case is seeded explicitly) and invariants at extreme scales.

use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use sheetform_bend::{bend, BendError, BendModel, BendScene};
use sheetform_mesh::{developability_error, isometry_error};

/// A planar cubic Bézier in the xz-plane, a rectangle around its flat image, at `scale`.
fn planar_scene(p1: (f64, f64), p2: (f64, f64), p3: (f64, f64), width: f64, scale: f64) -> String {
    let pts = [(0.0, 0.0), p1, p2, p3]
        .map(|(x, z)| format!("[{},0,{}]", x * scale, z * scale))
        .join(",");
    // Generous length: the flat geodesic (the curve's length) must fit; the outline is
    // cut to 3× the chord so that long curves fit too.
    let l = 3.0 * (p3.0 * p3.0 + p3.1 * p3.1).sqrt().max(1.0) * scale;
    let w = width * scale;
    format!(
        r#"{{"outline":[[0,{}],[{l},{}],[{l},{w}],[0,{w}]],"regions":[{{"flat_start":[0,0],"flat_direction":[1,0],"curve":{{"type":"bezier","control_points":[{pts}]}}}}]}}"#,
        -w, -w
    )
}

fn check_invariants(json: &str) -> Result<(), TestCaseError> {
    let scene = BendScene::from_json(json).unwrap();
    let model = match BendModel::from_scene(&scene) {
        Ok(m) => m,
        // A curve longer than the sheet: a clean error, not a panic.
        Err(BendError::GeodesicLeavesSheet { .. }) => return Ok(()),
        Err(e) => return Err(TestCaseError::fail(format!("unexpected error {e}"))),
    };
    match bend(&model) {
        Ok(sheet) => {
            let mesh = &sheet.mesh;
            prop_assert!(
                isometry_error(mesh).max_relative <= 1e-10,
                "isometry {}",
                isometry_error(mesh).max_relative
            );
            prop_assert!(developability_error(mesh).max_radians <= 1e-9);
            let area = model.sheet.area();
            prop_assert!((mesh.flat_area() - area).abs() <= 1e-9 * area);
            prop_assert!((mesh.area() - area).abs() <= 1e-9 * area);
            prop_assert!(mesh.positions.iter().all(|p| p.iter().all(|c| c.is_finite())));
            Ok(())
        }
        // Planar curves are always admissible (their rulings are parallel); straight
        // curves are refused by name.
        Err(BendError::DegenerateCurve { reason, .. }) if reason.contains("straight") => Ok(()),
        Err(e) => Err(TestCaseError::fail(format!("planar curve refused: {e}"))),
    }
}

#[test]
fn planar_curves_always_bend_into_exact_isometries() {
    let config = Config {
        cases: 48,
        ..Config::default()
    };
    let mut runner = TestRunner::new_with_rng(config, TestRng::from_seed(RngAlgorithm::ChaCha, &[7; 32]));
    let coord = -80.0..80.0f64;
    let strategy = (
        (20.0..80.0f64, coord.clone()),
        (60.0..140.0f64, coord.clone()),
        (100.0..200.0f64, coord),
        5.0..60.0f64,
    );
    runner
        .run(&strategy, |(p1, p2, p3, width)| {
            check_invariants(&planar_scene(p1, p2, p3, width, 1.0))
        })
        .unwrap();
}

#[test]
fn invariants_hold_at_extreme_scales() {
    for scale in [1e-6, 1.0, 1e6] {
        let json = planar_scene((40.0, 30.0), (80.0, -30.0), (120.0, 0.0), 20.0, scale);
        check_invariants(&json).unwrap();
        // The same shape at every scale: ruling counts agree.
        let model = BendModel::from_scene(&BendScene::from_json(&json).unwrap()).unwrap();
        let unit = BendModel::from_scene(
            &BendScene::from_json(&planar_scene((40.0, 30.0), (80.0, -30.0), (120.0, 0.0), 20.0, 1.0)).unwrap(),
        )
        .unwrap();
        assert_eq!(
            bend(&model).unwrap().regions[0].ruling_count,
            bend(&unit).unwrap().regions[0].ruling_count,
            "scale {scale}"
        );
    }
}

#[test]
fn straight_span_inside_a_bspline_stays_planar() {
    // Collinear control points 2..5 give a straight middle span (planar sheet there),
    // joined to bends in the same plane: no NaN, the span has no fold.
    let json = r#"{"outline":[[0,-20],[400,-20],[400,20],[0,20]],"regions":[{"flat_start":[0,0],"flat_direction":[1,0],
        "curve":{"type":"bspline","degree":3,"control_points":[[0,0,0],[30,0,20],[60,0,30],[90,0,40],[120,0,50],[150,0,60],[180,0,50],[210,0,20]]}}]}"#;
    let model = BendModel::from_scene(&BendScene::from_json(json).unwrap()).unwrap();
    let sheet = bend(&model).unwrap();
    let g = &sheet.geometries[0];
    assert!(g.samples.iter().any(|s| s.straight), "expected a straight span");
    assert!(g.samples.iter().all(|s| s.angle.is_finite() && s.fold_rate.is_finite()));
    for (s, fold) in g.samples.iter().zip(&sheet.strips[0].fold_angles) {
        if s.straight {
            assert_eq!(*fold, 0.0);
        }
    }
    assert!(isometry_error(&sheet.mesh).max_relative <= 1e-10);
}

#[test]
fn straight_span_between_bends_in_different_planes_is_refused_with_its_range() {
    // Bend in the xz-plane, straight span, then bend in the xy-plane: the planar span
    // cannot carry both tangent planes.
    let json = r#"{"outline":[[0,-20],[400,-20],[400,20],[0,20]],"regions":[{"flat_start":[0,0],"flat_direction":[1,0],
        "curve":{"type":"bspline","degree":3,"control_points":[[0,0,0],[30,0,20],[60,0,30],[90,0,30],[120,0,30],[150,0,30],[180,20,30],[210,50,30]]}}]}"#;
    let model = BendModel::from_scene(&BendScene::from_json(json).unwrap()).unwrap();
    match bend(&model) {
        Err(BendError::DegenerateCurve { reason, .. }) => assert!(reason.contains("straight for s in"), "{reason}"),
        other => panic!("expected a straight-span error, got {:?}", other.map(|_| ())),
    }
}

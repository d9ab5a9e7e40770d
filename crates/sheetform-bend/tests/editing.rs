//! Editing operations of §4.1 (issue 2): control points, end handles, length-preserving
//! drags; each keeps the last admissible state.

use sheetform_bend::{BendEditor, BendModel, BendScene, EndHandle, EndHandleOptions, LengthPreservation};
use sheetform_geometry::{ParametricCurve, Vec3};
use sheetform_mesh::isometry_error;

fn editor() -> BendEditor {
    let scene = BendScene::from_json(include_str!("../../../examples/bent-rectangle.json")).unwrap();
    BendEditor::new(BendModel::from_scene(&scene).unwrap()).unwrap()
}

fn end_normals(e: &BendEditor) -> (Vec3, Vec3) {
    let c = e.model().regions[0].curve.shape();
    let (u0, u1) = c.domain();
    let n = |u: f64| {
        let d = c.derivatives4(u);
        d[1].cross(&d[2]).cross(&d[1]).normalize()
    };
    (n(u0), n(u1))
}

#[test]
fn moving_a_control_point_rebends_the_sheet() {
    let mut e = editor();
    let before = e.sheet().mesh.positions.clone();
    let info = e.move_control_point(0, 3, Vec3::new(165.0, 10.0, 110.0)).unwrap();
    assert!(info.applied, "{info:?}");
    assert_ne!(info.curve_length_before, info.curve_length_after);
    assert_ne!(before, e.sheet().mesh.positions);
    assert!(isometry_error(&e.sheet().mesh).max_relative < 1e-10);
}

#[test]
fn an_edit_that_creates_a_singularity_keeps_the_last_admissible_state() {
    let mut e = editor();
    let model_before = e.model().regions[0].curve.shape().control_points().to_vec();
    let mesh_before = e.sheet().mesh.clone();
    // Strong torsion: the curve of regression enters the 120 mm wide sheet.
    let info = e.move_control_point(0, 1, Vec3::new(80.0, 10.0, 0.0)).unwrap();
    let info = if info.applied {
        e.move_control_point(0, 2, Vec3::new(150.0, -20.0, 60.0)).unwrap()
    } else {
        info
    };
    assert!(!info.applied);
    assert!(
        info.rejected_because.as_deref().unwrap().contains("inadmissible"),
        "{info:?}"
    );
    if e.model().regions[0].curve.shape().control_points() == model_before.as_slice() {
        assert_eq!(e.sheet().mesh, mesh_before);
    }
    assert!(sheetform_bend::bend(e.model()).is_ok());
}

#[test]
fn end_handles_reach_the_wanted_normals() {
    let mut e = editor();
    let (n0, n1) = end_normals(&e);
    // Turn both end normals by ~10 degrees.
    let rot = nalgebra::Rotation3::from_axis_angle(&Vec3::x_axis(), 0.17);
    let (t0, t1) = (rot * n0, rot * n1);
    let options = EndHandleOptions {
        regularization: 1e-3,
        ..Default::default()
    };
    let info = e
        .drag_end_handles(
            0,
            EndHandle {
                position: None,
                normal: Some(t0),
            },
            EndHandle {
                position: None,
                normal: Some(t1),
            },
            &options,
        )
        .unwrap();
    assert!(info.applied, "{info:?}");
    let solver = info.solver.unwrap();
    assert!(solver.converged, "{solver:?}");
    let (m0, m1) = end_normals(&e);
    assert!(
        (m0 - t0).norm() < 1e-4 && (m1 - t1).norm() < 1e-4,
        "{m0} vs {t0}, {m1} vs {t1}"
    );
}

#[test]
fn end_handle_regularization_keeps_changes_gradual() {
    let mut stiff = editor();
    let mut loose = editor();
    let (n0, _) = end_normals(&stiff);
    let target = nalgebra::Rotation3::from_axis_angle(&Vec3::x_axis(), 0.17) * n0;
    let handle = EndHandle {
        position: None,
        normal: Some(target),
    };
    let none = EndHandle {
        position: None,
        normal: None,
    };
    let a = stiff
        .drag_end_handles(
            0,
            handle,
            none,
            &EndHandleOptions {
                regularization: 10.0,
                ..Default::default()
            },
        )
        .unwrap();
    let b = loose
        .drag_end_handles(
            0,
            handle,
            none,
            &EndHandleOptions {
                regularization: 1e-6,
                ..Default::default()
            },
        )
        .unwrap();
    assert!(a.applied && b.applied);
    let moved = |e: &BendEditor| {
        let original = editor();
        e.model().regions[0]
            .curve
            .shape()
            .control_points()
            .iter()
            .zip(original.model().regions[0].curve.shape().control_points())
            .map(|(p, q)| (p - q).norm())
            .sum::<f64>()
    };
    assert!(moved(&stiff) < moved(&loose));
    assert!((end_normals(&loose).0 - target).norm() < (end_normals(&stiff).0 - target).norm());
}

#[test]
fn length_preserving_drags_keep_the_length_exactly() {
    for method in [LengthPreservation::Trim, LengthPreservation::Scale] {
        let mut e = editor();
        let length = e.model().regions[0].curve.length();
        let drop = Vec3::new(150.0, 5.0, 75.0);
        let info = e.drag_preserving_length(0, 2, drop, method).unwrap();
        assert!(info.applied, "{method:?}: {info:?}");
        let after = e.model().regions[0].curve.length();
        assert!(
            (after - length).abs() <= 1e-9 * length,
            "{method:?}: {after} vs {length}"
        );
        let p = e.model().regions[0].curve.shape().control_points()[2];
        assert!(
            (p - drop).norm() <= 1e-9 * length,
            "{method:?}: dragged point at {p}, dropped at {drop}"
        );
    }
}

#[test]
fn bad_edits_are_errors() {
    let mut e = editor();
    assert!(e.move_control_point(0, 9, Vec3::zeros()).is_err());
    assert!(e.move_control_point(3, 0, Vec3::zeros()).is_err());
    assert!(e.move_control_point(0, 1, Vec3::new(f64::NAN, 0.0, 0.0)).is_err());
}

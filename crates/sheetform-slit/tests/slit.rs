//! System B end to end: the chair converges, quads stay congruent, the Jacobian is exact,
//! E is right on a known gap, the mould is closed, bad input names the field.

use nalgebra::{DMatrix, DVector, Vector3};
use sheetform_slit::strip_folding::{fold_strip, StripState};
use sheetform_slit::strip_solver::StripProblem;
use sheetform_slit::*;
use sheetform_solve::LeastSquaresProblem;

fn chair() -> SlitModel {
    let text = include_str!("../../../examples/slit/chair.json");
    SlitModel::from_scene(&SlitScene::from_json(text).unwrap(), None).unwrap()
}

#[test]
fn chair_converges_from_the_initial_state_with_congruent_quads() {
    let model = chair();
    let design = solve_design(&model);
    assert!(design.normalised_error <= 1e-6, "E = {}", design.normalised_error);
    assert!(design.strips.iter().all(|s| s.normalised_error <= 1e-6));
    let w = model.layout.strip_width;
    for (k, state) in design.states.iter().enumerate() {
        let f = fold_strip(&model.strip_start(k), state);
        for i in 1..=state.quads() {
            let flat = [
                Vector3::new(state.left[i - 1], 0.0, 0.0),
                Vector3::new(state.right[i - 1], w, 0.0),
                Vector3::new(state.right[i], w, 0.0),
                Vector3::new(state.left[i], 0.0, 0.0),
            ];
            let q = f.quad(i);
            for a in 0..4 {
                for b in a + 1..4 {
                    let (d3, d2) = ((q[a] - q[b]).norm(), (flat[a] - flat[b]).norm());
                    assert!((d3 - d2).abs() <= 1e-12 * d2, "strip {k} quad {i}: {d3} vs {d2}");
                }
            }
        }
    }
    // The whole sheet mesh carries its flat sheet: isometric up to the welded middle line.
    let mesh = slit_mesh(&model, &design);
    mesh.validate().unwrap();
    let iso = sheetform_mesh::isometry_error(&mesh);
    assert!(iso.max_relative < 1e-6, "{iso:?}");
    let flat_area = 2.0 * (model.layout.half_length() * model.layout.width)
        - (model.layout.strip_count - 1) as f64 * model.layout.slit_width * 2.0 * model.layout.strip_length;
    assert!((mesh.flat_area() - flat_area).abs() < 1e-6 * flat_area);
}

#[test]
fn penalty_jacobian_matches_finite_differences() {
    let mut model = chair();
    let x = wavy_problem(&mut model);
    let mut terms = model.strip_terms(1, 0);
    terms.gap_shift = [0.01, -0.02];
    let problem = StripProblem { terms, stop: None };
    let exact: DMatrix<f64> = problem.jacobian(&x);
    for k in 0..x.len() {
        let h = 1e-6;
        let mut p = x.clone();
        p[k] += h;
        let mut m = x.clone();
        m[k] -= h;
        let fd = (problem.residuals(&p) - problem.residuals(&m)) / (2.0 * h);
        for r in 0..fd.len() {
            assert!(
                (fd[r] - exact[(r, k)]).abs() <= 1e-6 * (1.0 + exact[(r, k)].abs()),
                "row {r} col {k}: exact {} fd {}",
                exact[(r, k)],
                fd[r]
            );
        }
    }
}

/// A wavy state of strip 1 of the chair with an anchor: every kind of row is non-zero.
fn wavy_problem(model: &mut SlitModel) -> DVector<f64> {
    model
        .add_anchor(AnchorSpec {
            strip: 1,
            ridge: 4,
            side: StripSide::Right,
            position: [150.0, 380.0, 90.0],
        })
        .unwrap();
    let mut state = StripState::initial(10, model.layout.strip_length);
    for i in 1..10 {
        state.angles[i] = 0.2 * (i as f64).sin();
        state.left[i] += 4.0 * (i as f64 * 0.8).cos();
        state.right[i] -= 3.0 * (i as f64 * 0.5).sin();
    }
    DVector::from_vec(state.to_vector())
}

#[test]
fn hessians_match_differences_of_the_exact_gradients() {
    use sheetform_solve::ConstrainedLeastSquaresProblem;
    let mut model = chair();
    let x = wavy_problem(&mut model);
    let mut terms = model.strip_terms(1, 0);
    terms.gap_shift = [0.01, -0.02];
    let problem = StripProblem { terms, stop: None };
    let n = x.len();
    let gradient = |x: &DVector<f64>| problem.jacobian(x).transpose() * problem.residuals(x);
    let multipliers = DVector::from_vec(vec![0.7, -1.3]);
    let lagrangian = |x: &DVector<f64>| problem.constraint_jacobian(x).transpose() * &multipliers;
    // The penalty's Hessian: JᵀJ + Σ r ∇²r; the constraints': Σ λ ∇²g.
    let j = problem.jacobian(&x);
    let penalty = j.transpose() * &j + problem.residual_curvature(&x).unwrap();
    let constraint = problem.constraint_curvature(&x, &multipliers).unwrap();
    assert!(penalty.norm() > 0.0 && constraint.norm() > 0.0);
    let h = 1e-6;
    for k in 0..n {
        let (mut p, mut m) = (x.clone(), x.clone());
        p[k] += h;
        m[k] -= h;
        let fd_penalty = (gradient(&p) - gradient(&m)) / (2.0 * h);
        let fd_constraint = (lagrangian(&p) - lagrangian(&m)) / (2.0 * h);
        for a in 0..n {
            let (e, f) = (penalty[(a, k)], fd_penalty[a]);
            assert!(
                (e - f).abs() <= 1e-5 * (1.0 + e.abs()),
                "penalty ({a}, {k}): exact {e} fd {f}"
            );
            let (e, f) = (constraint[(a, k)], fd_constraint[a]);
            assert!(
                (e - f).abs() <= 1e-5 * (1.0 + e.abs()),
                "constraint ({a}, {k}): exact {e} fd {f}"
            );
        }
    }
}

#[test]
fn normalised_error_is_reported_on_a_known_gap() {
    // A vertical leg 10 mm closer to the symmetry plane than the strips are long: the
    // straight initial strips overshoot the plane by exactly 10 mm.
    let text = r#"{"sheet":{"l1_width":200,"l2_panel_length":300,"l3_strip_length":400,"l4_slit_width":4,"strip_count":3},
        "leg_curve":{"control_points":[[390,0],[390,350]]}}"#;
    let model = SlitModel::from_scene(&SlitScene::from_json(text).unwrap(), None).unwrap();
    let design = SlitDesign::initial(&model);
    assert!((design.gap - 10.0).abs() < 1e-9, "{}", design.gap);
    assert!((design.normalised_error - 10.0 / 700.0).abs() < 1e-12);
}

#[test]
fn subdivision_then_solving_keeps_the_strips_closed() {
    let mut model = chair();
    model.solver.subdivisions = 1;
    let design = solve_design(&model);
    assert_eq!(design.states[0].quads(), 20);
    assert!(design.normalised_error <= 1e-6);
}

#[test]
fn joint_solve_closes_every_strip() {
    let mut model = chair();
    model.solver.mode = SolveMode::Joint;
    let design = solve_design(&model);
    assert!(design.normalised_error <= 1e-6, "{}", design.normalised_error);
}

#[test]
fn mould_is_closed_and_outward() {
    let model = chair();
    let design = solve_design(&model);
    let mould = build_mould(&model, &design).unwrap();
    assert!(mould.is_watertight());
    assert!(mould.volume() > 0.0);
    // For a 2 mm sheet the top sinks 1 mm under the model (the sheet's mid-surface):
    // every top vertex 1 mm from the profile it came from, still closed, less volume.
    let mut thick = chair();
    thick.mould.sheet_thickness = 2.0;
    let lowered = build_mould(&thick, &design).unwrap();
    assert!(lowered.is_watertight());
    assert!(lowered.volume() > 0.0 && lowered.volume() < mould.volume());
    // The top's points come first, profile after profile (each in its plane z = const):
    // every moved point lies 1 mm from the lines of the segments on either side of it.
    let top = mould.positions.len() - 4;
    let mut checked = 0;
    let mut start = 0;
    while start < top {
        let z = mould.positions[start].z;
        let end = (start..top).find(|&i| mould.positions[i].z != z).unwrap_or(top);
        let (p, q) = (&mould.positions[start..end], &lowered.positions[start..end]);
        for (i, moved) in q.iter().enumerate() {
            assert_eq!(moved.z, z);
            for (a, b) in [(i.wrapping_sub(1), i), (i, i + 1)] {
                if b >= p.len() || a >= p.len() || (p[b] - p[a]).xy().norm() == 0.0 {
                    continue;
                }
                let d = (p[b] - p[a]).xy().normalize();
                let r = (moved - p[a]).xy();
                let distance = (d.x * r.y - d.y * r.x).abs();
                assert!((distance - 1.0).abs() < 1e-9, "profile z = {z}, point {i}: {distance}");
                checked += 1;
            }
        }
        start = end;
    }
    assert!(checked > 100);
    // A sheet thicker than half a strip is refused, naming the field.
    let mut scene = SlitScene::from_json(include_str!("../../../examples/slit/chair.json")).unwrap();
    scene.mould.sheet_thickness = 1e6;
    let error = SlitModel::from_scene(&scene, None).unwrap_err();
    assert!(error.to_string().contains("mould.sheet_thickness"), "{error}");
}

/// Issue 35: a sheet thickness of 1e-320 (a subnormal) passed the check (it lies between 0
/// and half a strip) and was refused by the mould's triangulation without naming the
/// field. A thickness is 0 or within the sheet's scale, as the base's, and a refusal
/// names `mould.sheet_thickness`, its bounds and the value.
#[test]
fn a_sheet_thickness_off_the_sheets_scale_is_refused_naming_the_field_and_its_bounds() {
    let chair = || SlitScene::from_json(include_str!("../../../examples/slit/chair.json")).unwrap();
    for fine in [0.0, 2.0] {
        let mut scene = chair();
        scene.mould.sheet_thickness = fine;
        assert!(SlitModel::from_scene(&scene, None).is_ok(), "{fine}");
    }
    for (thickness, shown) in [
        // Subnormals, printed as the doubles they are (1e-320 is 9.99989e-321).
        (1e-320, "got 9.99989e-321"),
        (5e-324, "got 4.94066e-324"),
        (1e-12, "got 1e-12"),
        (-1.0, "got -1"),
        (1e6, "got 1e6"),
    ] {
        let mut scene = chair();
        scene.mould.sheet_thickness = thickness;
        let e = SlitModel::from_scene(&scene, None).unwrap_err().to_string();
        assert!(
            e.contains("`mould.sheet_thickness`: must be 0 (a sheet of no thickness) or from a millionth of the sheet's largest length (")
                && e.contains(") to half the strip width (")
                && e.ends_with(shown),
            "{thickness:e}: {e}"
        );
    }
}

#[test]
fn fits_a_point_cloud_sampled_from_another_design() {
    // Points on the chair's strips; a model with a different seat curve pulled to them.
    let target_model = chair();
    let target = solve_design(&target_model);
    let mut points = Vec::new();
    for f in target.folded(&target_model) {
        for i in 0..f.left.len() - 1 {
            for t in 0..=4 {
                let s = t as f64 / 4.0;
                let [a, b, c, d] = f.quad(i + 1);
                for u in [0.0, 0.5, 1.0] {
                    let p = (a * (1.0 - s) + b * s) * (1.0 - u) + (d * (1.0 - s) + c * s) * u;
                    points.push([p.x, p.y, p.z]);
                }
            }
        }
    }
    let text = include_str!("../../../examples/slit/chair.json").replace(
        "[[0, 360], [140, 300], [300, 330], [420, 470]]",
        "[[0, 330], [420, 330]]",
    );
    let mut scene = SlitScene::from_json(&text).unwrap();
    let plain = solve_design(&SlitModel::from_scene(&scene, None).unwrap());
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scan.xyz");
    std::fs::write(
        &path,
        points
            .iter()
            .map(|p| format!("{} {} {}\n", p[0], p[1], p[2]))
            .collect::<String>(),
    )
    .unwrap();
    scene.scan = Some(ScanSpec {
        points: path.display().to_string(),
    });
    scene.weights.scan = 1.0;
    let fitted_model = SlitModel::from_scene(&scene, Some(&std::fs::read(&path).unwrap())).unwrap();
    let fitted = solve_design(&fitted_model);
    let distance = |d: &SlitDesign, m: &SlitModel| {
        let scan = m.scan.as_ref().unwrap();
        let all: Vec<f64> = d
            .folded(m)
            .iter()
            .flat_map(|f| {
                f.left
                    .iter()
                    .chain(&f.right)
                    .map(|v| (v - scan.nearest(v)).norm())
                    .collect::<Vec<_>>()
            })
            .collect();
        all.iter().sum::<f64>() / all.len() as f64
    };
    let before = distance(&plain, &fitted_model);
    let after = distance(&fitted, &fitted_model);
    assert!(after < 0.5 * before, "scan fitting: {before} -> {after}");
    assert!(fitted.normalised_error <= 1e-6);
}

#[test]
fn bad_input_names_the_field() {
    let base =
        r#"{"sheet":{"l1_width":200,"l2_panel_length":300,"l3_strip_length":400,"l4_slit_width":4,"strip_count":3}"#;
    let case = |extra: &str, sheet_patch: Option<(&str, &str)>, expect: &str| {
        let mut text = format!("{base}{extra}}}");
        if let Some((a, b)) = sheet_patch {
            text = text.replace(a, b);
        }
        let err = SlitScene::from_json(&text)
            .and_then(|s| SlitModel::from_scene(&s, None))
            .expect_err(&text)
            .to_string();
        assert!(err.contains(expect), "expected `{expect}` in `{err}`");
    };
    case("", Some(("\"l1_width\":200", "\"l1_width\":0")), "sheet.l1_width");
    case(
        "",
        Some(("\"l3_strip_length\":400", "\"l3_strip_length\":-1")),
        "sheet.l3_strip_length",
    );
    case(
        "",
        Some(("\"strip_count\":3", "\"strip_count\":0")),
        "sheet.strip_count",
    );
    case(
        "",
        Some(("\"l4_slit_width\":4", "\"l4_slit_width\":150")),
        "sheet.l4_slit_width",
    );
    case(
        r#","seat_curve":{"control_points":[[50,300],[150,300]]}"#,
        None,
        "seat_curve",
    );
    case(
        r#","seat_curve":{"control_points":[[0,900],[200,900]]}"#,
        None,
        "unreachable",
    );
    case(
        r#","leg_curve":{"control_points":[[600,0],[600,400]]}"#,
        None,
        "leg_curve",
    );
    case(
        r#","anchors":[{"strip":5,"ridge":2,"side":"left","position":[0,0,0]}]"#,
        None,
        "anchors[0].strip",
    );
    case(
        r#","anchors":[{"strip":1,"ridge":11,"side":"left","position":[0,0,0]}]"#,
        None,
        "anchors[0].ridge",
    );
    case(
        r#","anchors":[{"strip":1,"ridge":0,"side":"left","position":[0,0,0]}]"#,
        None,
        "anchors[0].ridge",
    );
}

/// The points an editor offers to anchor are the ridge lines' ends on the sheet (mesh
/// vertices), 2 per ridge line 1..=M of every strip, at every subdivision level; an
/// anchor at one of them leaves the design where it was, one dragged away pulls its
/// strip towards it.
#[test]
fn anchorable_points_are_ridge_ends_on_the_sheet_and_anchors_pull_them() {
    for subdivisions in [0, 1] {
        let mut model = chair();
        model.solver.subdivisions = subdivisions;
        let design = solve_design(&model);
        let points = design.anchorable_points(&model);
        let (strips, quads) = (model.layout.strip_count, model.layout.quads_per_strip);
        assert_eq!(points.len(), strips * quads * 2);
        let mesh = slit_mesh(&model, &design);
        for p in &points {
            let position = Vector3::from(p.position);
            let nearest = mesh
                .positions
                .iter()
                .map(|v| (v - position).norm())
                .fold(f64::INFINITY, f64::min);
            // (The last ridge line's ends are snapped onto the symmetry plane in the
            // mesh, within the strip's gap.)
            assert!(nearest <= design.gap + 1e-9, "{p:?}: {nearest}");
        }
        if subdivisions == 0 {
            let chosen = points[2 * (quads - 1)];
            let mut held = model.clone();
            held.add_anchor(chosen).unwrap();
            let same = solve_design(&held).anchorable_points(&held);
            let drift = (Vector3::from(same[2 * (quads - 1)].position) - Vector3::from(chosen.position)).norm();
            // (Within the solver's stopping point: 0.015 mm.)
            assert!(drift < 0.05, "{drift}");
            let mut pulled = model.clone();
            let target = Vector3::from(chosen.position) + Vector3::new(0.0, 30.0, 0.0);
            pulled
                .add_anchor(AnchorSpec {
                    position: target.into(),
                    ..chosen
                })
                .unwrap();
            let moved = Vector3::from(solve_design(&pulled).anchorable_points(&pulled)[2 * (quads - 1)].position);
            assert!((moved - target).norm() < (Vector3::from(chosen.position) - target).norm() - 1.0);
        }
    }
}

/// Issue 35: the slit solve looked at no cancel flag, so two abandoned editor requests held
/// both solve slots until they finished (minutes at the largest sizes). A stop set from
/// another thread while the strips are solved ends the solve with `Cancelled`.
#[test]
fn a_stop_from_another_thread_cancels_the_solve() {
    use std::sync::atomic::{AtomicBool, Ordering};
    let mut scene: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/slit/chair.json")).unwrap(),
    )
    .unwrap();
    // Eight strips of 256 quads: some 40 s of solving on 2 cores.
    scene["sheet"]["strip_count"] = 8.into();
    scene["sheet"]["quads_per_strip"] = 256.into();
    scene["solver"] = serde_json::json!({ "max_iterations": 10000, "gap_tolerance": 1e-14 });
    let scene = sheetform_slit::SlitScene::from_json(&scene.to_string()).unwrap();
    let model = sheetform_slit::SlitModel::from_scene(&scene, None).unwrap();
    let stop = AtomicBool::new(false);
    let result = std::thread::scope(|s| {
        s.spawn(|| {
            std::thread::sleep(std::time::Duration::from_millis(300));
            stop.store(true, Ordering::Relaxed);
        });
        sheetform_slit::solve_design_until(&model, Some(&stop))
    });
    assert!(
        matches!(result, Err(sheetform_slit::SlitError::Cancelled)),
        "{:?}",
        result.map(|_| ())
    );
}

/// Issue 35: a weight whose square overflows (1e200) made the strip solve loop forever on
/// a matrix of infinities; weights are bounded, the field named.
#[test]
fn weights_beyond_their_bound_are_refused_naming_the_field() {
    for field in ["no_gap", "smooth", "fair", "user_control", "scan", "neighbour"] {
        let mut scene: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/slit/chair.json")).unwrap(),
        )
        .unwrap();
        scene["weights"] = serde_json::json!({ field: 1e200 });
        let scene = sheetform_slit::SlitScene::from_json(&scene.to_string()).unwrap();
        let e = sheetform_slit::SlitModel::from_scene(&scene, None)
            .unwrap_err()
            .to_string();
        assert!(e.contains(&format!("weights.{field}")) && e.contains("1e200"), "{e}");
    }
}

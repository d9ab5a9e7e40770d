//! `sheetform ffd`: the examples, bad input.

use crate::common::{obj_isometry_error, read_obj, repo, report, sheetform};

#[test]
fn ffd_examples_restore_developability_and_write_every_output() {
    for name in ["two-panels", "duct", "skirt-springs", "duct-large-bend"] {
        let tmp = tempfile::tempdir().unwrap();
        let scene = repo().join("examples/ffd").join(format!("{name}.json"));
        let o = sheetform(&["ffd", scene.to_str().unwrap(), "-o", tmp.path().to_str().unwrap()]);
        assert!(o.status.success(), "{name}: {}", String::from_utf8_lossy(&o.stderr));
        let r = report(tmp.path());
        assert_eq!(r["command"], "ffd");
        assert_eq!(r["status"], "ok");
        let ffd = &r["ffd"];
        // skirt-springs: the springs alone (the paper's energy), no bending term.
        let bending = if name == "skirt-springs" { 0.0 } else { 3e-3 };
        assert_eq!(ffd["bending_weight"].as_f64().unwrap(), bending, "{name}");
        assert_eq!(ffd["line_search_memory"].as_u64().unwrap(), 12, "{name}");
        // No step of these examples stalls, so none falls back to the bending term.
        for step in ffd["steps"].as_array().unwrap() {
            assert!(step["bending_fallback_iteration"].is_null(), "{name}");
            // duct-large-bend restores along the deformation's path (continuation): its
            // deformation five times the duct's is cut into sub-steps.
            let sub_steps = step["sub_steps"].as_u64().unwrap();
            assert!(
                if name == "duct-large-bend" {
                    sub_steps >= 8
                } else {
                    sub_steps == 1
                },
                "{name}: {sub_steps}"
            );
            assert_eq!(step["bending_weight"].as_f64().unwrap(), bending, "{name}");
        }
        let before = ffd["angle_defects_before"]["angle_defect_max_rad"].as_f64().unwrap();
        let after = ffd["angle_defects_after"]["angle_defect_max_rad"].as_f64().unwrap();
        assert!(before > 1e-3 && after <= 1e-8, "{name}: {before} -> {after}");
        assert!((ffd["angle_defects_after"]["developability_d"].as_f64().unwrap() - 1.0).abs() < 1e-12);
        assert_eq!(
            ffd["linked_vertex_gap_max_mm"].as_f64().unwrap(),
            0.0,
            "{name}: no crack"
        );
        let step = &ffd["steps"][0];
        assert!(step["deviation_max_mm"].as_f64().unwrap() > 0.0);
        // Fairness: the default's fold angles stay those of the deformed mesh (duct 0.213
        // -> 0.201 rad, two panels 0.249 -> 0.251); the springs alone crinkle the skirt
        // (0.09 -> 0.56).
        let folds = (
            step["fold_angle_max_before_rad"].as_f64().unwrap(),
            step["fold_angle_max_after_rad"].as_f64().unwrap(),
        );
        let (crinkled, fair) = (folds.1 > 3.0 * folds.0, folds.1 < 1.1 * folds.0);
        assert!(
            folds.0 > 0.05 && crinkled == (name == "skirt-springs") && fair != crinkled,
            "{name}: {folds:?}"
        );
        assert!(step["time_ms"].as_f64().unwrap() > 0.0);
        // model.obj: one group per panel, vt = each panel's exact flat pattern at 1:1.
        let obj = read_obj(&tmp.path().join("model.obj"));
        assert!(obj_isometry_error(&obj) < 1e-9, "{name}: vt is the flat pattern at 1:1");
        let text = std::fs::read_to_string(tmp.path().join("model.obj")).unwrap();
        let groups = text.lines().filter(|l| l.starts_with("g ")).count();
        assert_eq!(groups as u64, ffd["panel_count"].as_u64().unwrap());
        // The plain FFD's panels do not flatten exactly; the restored ones do.
        assert!(ffd["deformed_pattern_edge_length_max_relative"].as_f64().unwrap() > 1e-4);
        for file in [
            "deformed.obj",
            "deformed.glb",
            "developability-before.ply",
            "developability-after.ply",
            "developability-before.glb",
            "developability-after.glb",
            "model.glb",
            "model.stl",
            "pattern.svg",
            "pattern.dxf",
            "pattern.pdf",
        ] {
            assert!(tmp.path().join(file).metadata().unwrap().len() > 0, "{name}: {file}");
        }
        // The SVG cuts one outline per panel.
        let svg = std::fs::read_to_string(tmp.path().join("pattern.svg")).unwrap();
        let cut = &svg[svg.find("<g id=\"cut\"").unwrap()..];
        let cut = &cut[..cut.find("</g>").unwrap()];
        assert_eq!(
            cut.matches("d=\"M").count() as u64,
            ffd["panel_count"].as_u64().unwrap(),
            "{name}"
        );
    }
    // A mesh file as the model: the restored two panels (model.obj, one group per panel,
    // seam vertices duplicated) deformed again; the seam is linked by position.
    let first = tempfile::tempdir().unwrap();
    let scene = repo().join("examples/ffd/two-panels.json");
    assert!(
        sheetform(&["ffd", scene.to_str().unwrap(), "-o", first.path().to_str().unwrap()])
            .status
            .success()
    );
    let again = first.path().join("again.json");
    std::fs::write(
        &again,
        r#"{"model": {"mesh": "model.obj"}, "lattice": {"degrees": [2, 2, 2], "counts": [3, 3, 3]},
            "deformations": [{"edits": [{"move": {"points": [[1, 1, 2]], "by": [10, 10, 10]}}]}]}"#,
    )
    .unwrap();
    let out = first.path().join("again");
    let o = sheetform(&["ffd", again.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let ffd = &report(&out)["ffd"];
    assert_eq!(ffd["panel_count"], 2);
    assert!(ffd["linked_node_count"].as_u64().unwrap() > 0, "the seam is linked");
    assert!(ffd["angle_defects_before"]["angle_defect_max_rad"].as_f64().unwrap() > 1e-5);
    assert!(ffd["angle_defects_after"]["angle_defect_max_rad"].as_f64().unwrap() <= 1e-8);
    // The paper's solver runs from the command line too and lowers G; it stops on the
    // change of G, short of the 1e-10 rad defect tolerance, and the report says so
    // (status `out of tolerance`, exit 5) instead of `ok`.
    let tmp = tempfile::tempdir().unwrap();
    let scene = repo().join("examples/ffd/two-panels.json");
    let o = sheetform(&[
        "ffd",
        scene.to_str().unwrap(),
        "-o",
        tmp.path().to_str().unwrap(),
        "--solver",
        "paper",
    ]);
    assert_eq!(o.status.code(), Some(5), "{}", String::from_utf8_lossy(&o.stderr));
    let r = report(tmp.path());
    assert_eq!(r["status"], "out of tolerance");
    let step = &r["ffd"]["steps"][0];
    assert_eq!(step["solver"], "paper");
    assert!(step["angle_defect_max_after_rad"].as_f64().unwrap() > 1e-10);
    assert!(
        step["developability_g_after_rad2"].as_f64().unwrap()
            < 0.1 * step["developability_g_before_rad2"].as_f64().unwrap()
    );
}

#[test]
fn ffd_bad_input_is_an_error_naming_the_problem() {
    let tmp = tempfile::tempdir().unwrap();
    // A non-manifold panel in a mesh file: three faces on one edge.
    std::fs::write(
        tmp.path().join("fan.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\ng fan\nf 1 2 3\nf 2 1 4\nf 1 2 5\n",
    )
    .unwrap();
    let cases = [
        (
            r#"{"model": {"mesh": "fan.obj"}, "deformations": [{"edits": []}]}"#,
            "non-manifold",
        ),
        (
            r#"{"model": {"procedural": {"kind": "duct"}}, "lattice": {"degrees": [3, 3, 3], "counts": [3, 4, 4]}, "deformations": [{"edits": []}]}"#,
            "lattice.counts[0]",
        ),
        (
            r#"{"model": {"procedural": {"kind": "duct"}}, "lattice": {"degrees": [1, 1, 1], "counts": [2, 2, 2], "knots": [[0, 0, 1, 1], [0, 1, 0.5, 1], [0, 0, 1, 1]]}, "deformations": [{"edits": []}]}"#,
            "lattice.knots[1]",
        ),
        (
            r#"{"model": {"procedural": {"kind": "duct"}}, "lattice": {"degrees": [1, 1, 1], "counts": [2, 2, 2], "weights": [1, 1, 1, 0, 1, 1, 1, 1]}, "deformations": [{"edits": []}]}"#,
            "lattice.weights[3]",
        ),
        (
            r#"{"model": {"procedural": {"kind": "duct"}}, "lattice": {"box_min": [-100, -100, 0], "box_max": [50, 100, 300]}, "deformations": [{"edits": []}]}"#,
            "outside the lattice volume",
        ),
        (
            r#"{"model": {"procedural": {"kind": "duct"}}, "deformations": [{"edits": [{"move": {"points": [[9, 0, 0]], "by": [1, 0, 0]}}]}]}"#,
            "deformations[0].edits[0].move.points[0]",
        ),
    ];
    for (k, (scene, expected)) in cases.iter().enumerate() {
        let path = tmp.path().join(format!("bad-{k}.json"));
        std::fs::write(&path, scene).unwrap();
        let out = tmp.path().join(format!("out-{k}"));
        let o = sheetform(&["ffd", path.to_str().unwrap(), "-o", out.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(1), "case {k}");
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(stderr.contains(expected), "case {k}: {stderr}");
        assert!(!out.exists(), "case {k}: no partial output");
    }
}

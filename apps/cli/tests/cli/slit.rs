//! `sheetform slit`: the examples, the scan fit.

use crate::common::{obj_isometry_error, read_obj, repo, report, sheetform, Obj};

/// The chair's own vertices as a scan (`.xyz`), next to a scene with a rough, level seat:
/// the fit pulls the strips onto the scan, and `report.json` says how close they are.
fn slit_scan_fit(chair: &std::path::Path, chair_obj: &Obj) {
    let tmp = tempfile::tempdir().unwrap();
    let xyz: String = chair_obj
        .v
        .iter()
        .map(|p| format!("{} {} {}\n", p[0], p[1], p[2]))
        .collect();
    std::fs::write(tmp.path().join("scan.xyz"), xyz).unwrap();
    let mut scene: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(chair).unwrap()).unwrap();
    scene["seat_curve"] = serde_json::json!({ "control_points": [[0, 330], [420, 330]] });
    scene["scan"] = serde_json::json!({ "points": "scan.xyz" });
    scene["weights"] = serde_json::json!({ "scan": 1.0 });
    let path = tmp.path().join("fit.json");
    std::fs::write(&path, scene.to_string()).unwrap();
    let out = tmp.path().join("out");
    let o = sheetform(&["slit", path.to_str().unwrap(), "-o", out.to_str().unwrap(), "-q"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r = report(&out);
    let fit = &r["slit"]["scan_fit"];
    assert_eq!(fit["scanned_point_count"].as_u64().unwrap() as usize, chair_obj.v.len());
    let (mean, max) = (
        fit["distance_mean_mm"].as_f64().unwrap(),
        fit["distance_max_mm"].as_f64().unwrap(),
    );
    assert!(mean < 0.5 && max < 4.0, "fitted to the scan: {fit}");
    assert!(r["slit"]["normalised_error"].as_f64().unwrap() <= 1e-6);
    // A missing cloud is an error naming the file.
    std::fs::remove_file(tmp.path().join("scan.xyz")).unwrap();
    let out = tmp.path().join("out2");
    let o = sheetform(&["slit", path.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("scan.xyz"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(!out.exists());
}

#[test]
fn slit_examples_write_model_pattern_mould_and_report() {
    for name in ["chair", "bench", "monument"] {
        let tmp = tempfile::tempdir().unwrap();
        let scene = repo().join("examples/slit").join(format!("{name}.json"));
        let o = sheetform(&["slit", scene.to_str().unwrap(), "-o", tmp.path().to_str().unwrap()]);
        assert!(o.status.success(), "{name}: {}", String::from_utf8_lossy(&o.stderr));
        let r = report(tmp.path());
        assert_eq!(r["command"], "slit");
        let slit = &r["slit"];
        assert!(slit["normalised_error"].as_f64().unwrap() <= 1e-6, "{name}: {slit}");
        assert!(r["isometry_error_max_relative"].as_f64().unwrap() < 1e-6);
        let obj = read_obj(&tmp.path().join("model.obj"));
        assert!(obj_isometry_error(&obj) < 1e-6, "{name}: vt is the flat sheet at 1:1");
        // The pattern cuts the outline and the slits: one outer loop and N − 1 holes, the
        // outline 2 (L2 + L3) long and L1 wide; ridge lines are folds.
        let text = std::fs::read_to_string(&scene).unwrap();
        let sheet: serde_json::Value = serde_json::from_str::<serde_json::Value>(&text).unwrap()["sheet"].clone();
        let f = |k: &str| sheet[k].as_f64().unwrap();
        let svg = std::fs::read_to_string(tmp.path().join("pattern.svg")).unwrap();
        let cut = &svg[svg.find("<g id=\"cut\"").unwrap()..];
        let cut = &cut[..cut.find("</g>").unwrap()];
        let loops: Vec<Vec<[f64; 2]>> = cut
            .split("d=\"M")
            .skip(1)
            .map(|d| {
                d[..d.find('"').unwrap()]
                    .split(['L', 'Z'])
                    .filter_map(|p| {
                        let v: Vec<f64> = p.trim().split(',').filter_map(|x| x.trim().parse().ok()).collect();
                        (v.len() == 2).then(|| [v[0], v[1]])
                    })
                    .collect()
            })
            .collect();
        assert_eq!(
            loops.len(),
            sheet["strip_count"].as_u64().unwrap() as usize,
            "{name}: outline + slits"
        );
        let extent = |l: &Vec<[f64; 2]>, i: usize| {
            l.iter().map(|p| p[i]).fold(f64::NEG_INFINITY, f64::max)
                - l.iter().map(|p| p[i]).fold(f64::INFINITY, f64::min)
        };
        let outline = loops
            .iter()
            .max_by(|a, b| extent(a, 0).total_cmp(&extent(b, 0)))
            .unwrap();
        let (length, width) = (2.0 * (f("l2_panel_length") + f("l3_strip_length")), f("l1_width"));
        let (ex, ey) = (extent(outline, 0), extent(outline, 1));
        assert!(
            ((ex - length).abs() < 0.01 && (ey - width).abs() < 0.01)
                || ((ey - length).abs() < 0.01 && (ex - width).abs() < 0.01),
            "{name}: outline {ex} x {ey}, sheet {length} x {width}"
        );
        let folds =
            r["pattern"]["mountain_fold_count"].as_u64().unwrap() + r["pattern"]["valley_fold_count"].as_u64().unwrap();
        assert!(folds > 0, "{name}: ridge lines on the fold layer");
        if name != "monument" {
            assert_eq!(slit["mould"]["watertight"], true, "{name}");
            assert!(tmp.path().join("mould.stl").exists());
        }
        assert!(slit["scan_fit"].is_null(), "{name}: no scan, no fit");
        if name == "chair" {
            slit_scan_fit(&scene, &obj);
        }
    }
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("bad.json");
    std::fs::write(
        &path,
        r#"{"sheet":{"l1_width":200,"l2_panel_length":300,"l3_strip_length":-4,"l4_slit_width":4,"strip_count":3}}"#,
    )
    .unwrap();
    let out = tmp.path().join("out");
    let o = sheetform(&["slit", path.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("sheet.l3_strip_length"));
    assert!(!out.exists());
}

//! `sheetform flatten`: exact unfolding, charts, LSCM.

use crate::common::{
    cut_intersections, example_mesh, ezdxf_cut, grid_obj, obj_isometry_error, read_obj, report, sheetform,
    svg_cut_loops, svg_labels_over_lines, svg_texts, validate_glb,
};

#[test]
fn flatten_unfolds_the_crumpled_sheet_at_least_as_well_as_its_stored_pattern() {
    let tmp = tempfile::tempdir().unwrap();
    let o = sheetform(&[
        "flatten",
        example_mesh("crumpled-developable.obj").to_str().unwrap(),
        "-o",
        tmp.path().to_str().unwrap(),
        "-q",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r = report(tmp.path());
    assert_eq!(r["status"], "ok");
    let chart = &r["charts"][0];
    assert!(chart["edge_length_max_relative"].as_f64().unwrap() <= 2.6e-5);
    assert_eq!(chart["flipped_face_count"], 0);
    assert_eq!(chart["boundary_crossing_count"], 0);
    assert_eq!(r["solver"]["converged"], true);
    // The written OBJ carries the pattern as vt: check it from the file.
    let obj = read_obj(&tmp.path().join("model.obj"));
    assert!(obj_isometry_error(&obj) <= 2.6e-5);
    let svg = std::fs::read_to_string(tmp.path().join("pattern.svg")).unwrap();
    assert!(svg.contains("id=\"cut\""));
    validate_glb(&[tmp.path().join("model.glb")]);
}

#[test]
fn flatten_without_charts_refuses_a_closed_mesh_with_the_reason() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let o = sheetform(&[
        "flatten",
        example_mesh("wingnut.obj").to_str().unwrap(),
        "--charts",
        "never",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("0 boundary loop(s)"));
    assert!(!out.exists());
}

#[test]
fn flatten_cuts_the_wingnut_into_flat_charts_with_seam_ids_tabs_and_sheets() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let o = sheetform(&[
        "flatten",
        example_mesh("wingnut.obj").to_str().unwrap(),
        "--charts",
        "smooth",
        "--scale",
        "40",
        "--tabs",
        "alternate",
        "--sheet",
        "600x400",
        "--min-fold-angle",
        "10",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r = report(&out);
    assert_eq!(r["status"], "ok");
    let seg = &r["segmentation"];
    let charts = seg["chart_count"].as_u64().unwrap() as usize;
    assert!(charts > 1 && seg["seam_edge_count"].as_u64().unwrap() > 0);
    // Slivers left by the splitting are joined to their neighbours.
    assert!(seg["merged_chart_count"].as_u64().unwrap() > 0, "{seg}");
    assert_eq!(r["charts"].as_array().unwrap().len(), charts);
    for c in r["charts"].as_array().unwrap() {
        assert!(c["edge_length_max_relative"].as_f64().unwrap() <= 0.01, "{c}");
        assert_eq!(c["flipped_face_count"], 0);
        assert_eq!(c["boundary_crossing_count"], 0);
    }
    assert!(r["isometry_error_max_relative"].as_f64().unwrap() <= 0.01);
    // The OBJ's vt is the pattern: every 3D edge within 1 % of its flat length.
    let obj = read_obj(&out.join("model.obj"));
    assert!(obj_isometry_error(&obj) <= 0.01 + 1e-12);
    // The cut layer (pieces with their tabs) touches itself nowhere.
    let svg = std::fs::read_to_string(out.join("pattern.svg")).unwrap();
    let loops = svg_cut_loops(&svg);
    assert_eq!(loops.len(), charts);
    assert_eq!(cut_intersections(&loops), 0);
    let p = &r["pattern"];
    let tabs = &p["tabs"];
    assert!(tabs["placed"].as_u64().unwrap() > 20, "{tabs}");
    // Tabs lie outside the pieces: the cut area is the flat area plus the tabs.
    let area = |l: &Vec<[f64; 2]>| {
        0.5 * (0..l.len())
            .map(|i| {
                let (a, b) = (l[i], l[(i + 1) % l.len()]);
                a[0] * b[1] - b[0] * a[1]
            })
            .sum::<f64>()
    };
    let cut_area: f64 = loops.iter().map(|l| area(l).abs()).sum();
    let flat_area = r["flat_area_mm2"].as_f64().unwrap() * 40.0 * 40.0;
    assert!(cut_area > flat_area, "{cut_area} vs {flat_area}");
    // Seam IDs: every seam's ID is printed on both of its sides, but where a side had no
    // room off every line (counted in the report); no label lies over a line.
    let ids = svg_texts(&svg, "seam");
    let seams = p["seam_count"].as_u64().unwrap() as usize;
    assert!(seams > 0);
    let mut missing = 0;
    for id in 1..=seams {
        let n = ids.iter().filter(|t| **t == id.to_string()).count();
        assert!(n <= 2, "seam {id} is labelled {n} times");
        missing += 2 - n;
    }
    assert!(missing as u64 <= p["label_dropped_count"].as_u64().unwrap());
    assert!(missing * 20 <= 2 * seams, "{missing} of {} seam IDs missing", 2 * seams);
    assert_eq!(svg_labels_over_lines(&svg), 0);
    // Packed onto 600 × 400 sheets: each sheet file's cut loops lie inside its sheet.
    let sheets = p["sheet_count"].as_u64().unwrap() as usize;
    assert!(sheets >= 1);
    let mut pieces = 0;
    for s in 1..=sheets {
        let sheet_svg = std::fs::read_to_string(out.join(format!("sheets/sheet-{s:02}.svg"))).unwrap();
        assert!(sheet_svg.contains(r#"width="600.0000mm" height="400.0000mm""#));
        for l in svg_cut_loops(&sheet_svg) {
            pieces += 1;
            for q in l {
                assert!(q[0] >= 5.0 - 1e-6 && q[0] <= 595.0 + 1e-6 && q[1] >= 5.0 - 1e-6 && q[1] <= 395.0 + 1e-6);
            }
        }
        let dxf = ezdxf_cut(&out.join(format!("sheets/sheet-{s:02}.dxf")));
        assert_eq!(dxf["errors"], 0);
    }
    assert_eq!(pieces, charts);
}

#[test]
fn flatten_with_lscm_handles_a_nearly_developable_mesh() {
    let tmp = tempfile::tempdir().unwrap();
    // A shallow paraboloid cap: not developable, flattens with small distortion.
    let obj = grid_obj(20, |x, y| 10.0 * (1.0 - x * x - y * y));
    let path = tmp.path().join("cap.obj");
    std::fs::write(&path, obj).unwrap();
    let out = tmp.path().join("out");
    let o = sheetform(&[
        "flatten",
        path.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--method",
        "lscm",
        "-q",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r = report(&out);
    assert_eq!(r["charts"][0]["method"], "lscm");
    assert_eq!(r["charts"][0]["flipped_face_count"], 0);
    let e = r["charts"][0]["edge_length_max_relative"].as_f64().unwrap();
    assert!(
        e > 1e-6 && e < 0.05,
        "a shallow cap flattens with small, nonzero distortion: {e}"
    );
    let lscm_mean = r["charts"][0]["edge_length_mean_relative"].as_f64().unwrap();
    let out = tmp.path().join("arap");
    let o = sheetform(&[
        "flatten",
        path.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--method",
        "arap",
        "-q",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r = report(&out);
    assert_eq!(r["charts"][0]["method"], "arap");
    assert_eq!(r["charts"][0]["flipped_face_count"], 0);
    assert!(r["charts"][0]["edge_length_mean_relative"].as_f64().unwrap() < lscm_mean);
}

/// A disk that cannot flatten within the distortion bound (a deep dome flattened whole,
/// as the default chart mode leaves a disk) is written but never called ok: status
/// `out of tolerance`, exit 5; with a bound it meets, ok.
#[test]
fn a_flattening_over_the_distortion_bound_is_flagged() {
    let tmp = tempfile::tempdir().unwrap();
    // A hemisphere-like dome over a square grid: far from developable.
    let obj = grid_obj(16, |x, y| 60.0 * (1.0 - 2.0 * (x * x + y * y)));
    let path = tmp.path().join("dome.obj");
    std::fs::write(&path, obj).unwrap();
    let out = tmp.path().join("out");
    let run = |extra: &[&str]| {
        let mut args = vec!["flatten", path.to_str().unwrap(), "-o", out.to_str().unwrap(), "-q"];
        args.extend_from_slice(extra);
        sheetform(&args)
    };
    let o = run(&["--method", "lscm"]);
    assert_eq!(o.status.code(), Some(5), "{}", String::from_utf8_lossy(&o.stderr));
    let r = report(&out);
    assert_eq!(r["status"], "out of tolerance");
    let e = r["charts"][0]["edge_length_max_relative"].as_f64().unwrap();
    assert!(e > 0.01, "the dome stretches its edges: {e}");
    assert!(out.join("pattern.svg").exists(), "written all the same");
    let o = run(&["--method", "lscm", "--max-distortion", "0.9"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(report(&out)["status"], "ok");
}

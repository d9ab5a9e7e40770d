//! `sheetform check`: developability and topology of meshes, bad mesh files.

use crate::common::{example_mesh, report, sheetform, validate_glb};

#[test]
fn check_calls_the_crumpled_sheet_developable_and_measures_its_flattening() {
    let tmp = tempfile::tempdir().unwrap();
    let o = sheetform(&[
        "check",
        example_mesh("crumpled-developable.obj").to_str().unwrap(),
        "-o",
        tmp.path().to_str().unwrap(),
        "-q",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r = report(tmp.path());
    assert_eq!(r["status"], "developable");
    assert_eq!(r["vertex_count"], 289);
    assert_eq!(r["face_count"], 512);
    let d = &r["angle_defects"];
    assert!(d["angle_defect_max_rad"].as_f64().unwrap() < 3e-5);
    assert!((d["developability_d"].as_f64().unwrap() - 1.0).abs() < 1e-12);
    // The stored flattening agrees with the 3D edges to the file's precision (~1e-5).
    let iso = r["isometry_error_max_relative"].as_f64().unwrap();
    assert!(iso > 1e-7 && iso < 1e-4, "{iso}");
    assert_eq!(r["topology"]["boundary_loop_count"], 1);
    // The colour map has one coloured vertex per mesh vertex.
    let ply = std::fs::read_to_string(tmp.path().join("developability.ply")).unwrap();
    assert!(ply.contains("element vertex 289") && ply.contains("property uchar red"));
    validate_glb(&[tmp.path().join("developability.glb")]);
}

#[test]
fn check_measures_the_wingnut() {
    let tmp = tempfile::tempdir().unwrap();
    let o = sheetform(&[
        "check",
        example_mesh("wingnut.obj").to_str().unwrap(),
        "-o",
        tmp.path().to_str().unwrap(),
        "-q",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r = report(tmp.path());
    assert_eq!(r["status"], "not developable");
    assert_eq!(r["topology"]["boundary_edge_count"], 0, "closed mesh");
    assert_eq!(r["topology"]["euler_characteristic"], 2);
    let mean = r["angle_defects"]["angle_defect_mean_rad"].as_f64().unwrap();
    assert!(
        (mean - 0.01).abs() < 0.002,
        "mean angle defect {mean} (the data set's README says ~0.01)"
    );
    assert!(r["isometry_error_max_relative"].is_null(), "no vt in the file");
}

fn bad_mesh(name: &str, content: &str, expect: &str) {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join(name);
    std::fs::write(&path, content).unwrap();
    let out = tmp.path().join("out");
    let o = sheetform(&["check", path.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{name}: {stderr}");
    assert!(stderr.contains(expect), "{name}: expected `{expect}` in {stderr}");
    assert!(!out.exists(), "{name}: output written for bad input");
}

#[test]
fn check_rejects_bad_mesh_files_with_the_place() {
    bad_mesh("empty.obj", "", "no vertices");
    bad_mesh("nan.obj", "v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n", "nan.obj:2");
    bad_mesh("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "range.obj:4");
    bad_mesh("counts.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n", "expected 4 vertices");
    bad_mesh(
        "faces.off",
        "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
        "expected 2 faces",
    );
    bad_mesh("noface.obj", "v 0 0 0\nv 1 0 0\n", "no faces");
    bad_mesh("format.xyz", "0 0 0\n", "unknown mesh format");
    let tmp = tempfile::tempdir().unwrap();
    let o = sheetform(&[
        "check",
        example_mesh("wingnut.obj").to_str().unwrap(),
        "-o",
        tmp.path().join("o").to_str().unwrap(),
        "--weld=-1",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--weld"));
}

#[test]
fn check_reports_topology_problems_instead_of_failing() {
    let tmp = tempfile::tempdir().unwrap();
    // A fin (three faces on one edge) and a zero-area face.
    let path = tmp.path().join("fin.obj");
    std::fs::write(
        &path,
        "v 0 0 0\nv 1 0 0\nv 0.5 1 0\nv 0.5 -1 0\nv 0.5 0 1\nv 2 0 0\nf 1 2 3\nf 2 1 4\nf 1 2 5\nf 1 2 6\n",
    )
    .unwrap();
    let out = tmp.path().join("out");
    let o = sheetform(&["check", path.to_str().unwrap(), "-o", out.to_str().unwrap(), "-q"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r = report(&out);
    assert_eq!(r["status"], "not developable");
    assert_eq!(r["topology"]["non_manifold_edges"], serde_json::json!([[0, 1]]));
    assert_eq!(r["topology"]["degenerate_faces"], serde_json::json!([3]));
}

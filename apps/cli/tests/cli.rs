//! End-to-end tests of the `sheetform` command, run in temporary directories. They check
//! the geometry in the files written, not only that the files exist.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .canonicalize()
        .unwrap()
}

fn sheetform(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sheetform"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn report(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap()
}

/// Minimal OBJ reader: positions, texture coordinates, faces (v/vt/vn), groups.
struct Obj {
    v: Vec<[f64; 3]>,
    vt: Vec<[f64; 2]>,
    faces: Vec<[(usize, usize); 3]>,
    groups: Vec<String>,
}

fn read_obj(path: &Path) -> Obj {
    let mut o = Obj {
        v: vec![],
        vt: vec![],
        faces: vec![],
        groups: vec![],
    };
    for line in std::fs::read_to_string(path).unwrap().lines() {
        let p: Vec<&str> = line.split_whitespace().collect();
        match p.first().copied() {
            Some("v") => {
                o.v.push([p[1].parse().unwrap(), p[2].parse().unwrap(), p[3].parse().unwrap()])
            }
            Some("vt") => o.vt.push([p[1].parse().unwrap(), p[2].parse().unwrap()]),
            Some("g") => o.groups.push(p[1..].join(" ")),
            Some("f") => {
                let idx = |s: &str| {
                    let mut it = s.split('/');
                    let v: usize = it.next().unwrap().parse().unwrap();
                    let t: usize = it.next().unwrap().parse().unwrap();
                    (v - 1, t - 1)
                };
                o.faces.push([idx(p[1]), idx(p[2]), idx(p[3])]);
            }
            _ => {}
        }
    }
    o
}

/// Largest relative difference between 3D (`v`) and flat (`vt`) edge lengths.
fn obj_isometry_error(o: &Obj) -> f64 {
    let mut worst: f64 = 0.0;
    for f in &o.faces {
        for k in 0..3 {
            let (a, b) = (f[k], f[(k + 1) % 3]);
            let d3 = (0..3).map(|i| (o.v[a.0][i] - o.v[b.0][i]).powi(2)).sum::<f64>().sqrt();
            let d2 = (0..2)
                .map(|i| (o.vt[a.1][i] - o.vt[b.1][i]).powi(2))
                .sum::<f64>()
                .sqrt();
            if d2 > 0.0 {
                worst = worst.max((d3 - d2).abs() / d2);
            }
        }
    }
    worst
}

fn examples() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(repo().join("examples"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    v.sort();
    v
}

#[test]
fn every_example_bends_into_an_exact_isometry_with_all_outputs() {
    let examples = examples();
    assert!(examples.len() >= 6, "examples missing: {examples:?}");
    let tmp = tempfile::tempdir().unwrap();
    let mut glbs = Vec::new();
    for scene in &examples {
        let out = tmp.path().join(scene.file_stem().unwrap());
        let o = sheetform(&["bend", scene.to_str().unwrap(), "-o", out.to_str().unwrap(), "--quiet"]);
        assert!(
            o.status.success(),
            "{}: {}",
            scene.display(),
            String::from_utf8_lossy(&o.stderr)
        );
        let r = report(&out);
        assert_eq!(r["status"], "ok");
        assert_eq!(r["admissible"], true);
        assert!(
            r["isometry_error_max_relative"].as_f64().unwrap() <= 1e-9,
            "{}: {r}",
            scene.display()
        );
        assert!(r["developability_error_max_rad"].as_f64().unwrap() <= 1e-9);
        assert!(r["ruling_count"].as_u64().unwrap() > 10);
        assert!(r["timings"]["total_ms"].as_f64().unwrap() > 0.0);
        // The OBJ itself: vt is the flat pattern at 1:1, so edge lengths agree.
        let obj = read_obj(&out.join("model.obj"));
        assert_eq!(obj.v.len(), obj.vt.len());
        assert_eq!(obj.faces.len() as u64, r["face_count"].as_u64().unwrap());
        assert!(
            obj_isometry_error(&obj) <= 1e-9,
            "{}: OBJ isometry {}",
            scene.display(),
            obj_isometry_error(&obj)
        );
        assert_eq!(obj.groups.len() as u64, r["piece_count"].as_u64().unwrap());
        // Areas agree (flat vs 3D) to the isometry tolerance.
        let (a, b) = (r["flat_area_mm2"].as_f64().unwrap(), r["area_mm2"].as_f64().unwrap());
        assert!((a - b).abs() <= 1e-9 * a);
        // STL: header + count + 50 bytes per triangle.
        let stl = std::fs::read(out.join("model.stl")).unwrap();
        let n = u32::from_le_bytes(stl[80..84].try_into().unwrap()) as usize;
        assert_eq!(n, obj.faces.len());
        assert_eq!(stl.len(), 84 + 50 * n);
        // GLB header.
        let glb = std::fs::read(out.join("model.glb")).unwrap();
        assert_eq!(&glb[0..4], b"glTF");
        assert_eq!(u32::from_le_bytes(glb[8..12].try_into().unwrap()) as usize, glb.len());
        glbs.push(out.join("model.glb"));
        // SVG at true size: width = flat extent + 2 × 10 mm margin.
        let svg = std::fs::read_to_string(out.join("pattern.svg")).unwrap();
        let (minx, maxx) = obj
            .vt
            .iter()
            .fold((f64::MAX, f64::MIN), |(lo, hi), t| (lo.min(t[0]), hi.max(t[0])));
        let width: f64 = svg
            .split("width=\"")
            .nth(1)
            .unwrap()
            .split("mm")
            .next()
            .unwrap()
            .parse()
            .unwrap();
        assert!(
            (width - (maxx - minx) - 20.0).abs() < 1e-3,
            "{}: svg width {width}",
            scene.display()
        );
        for layer in ["id=\"cut\"", "id=\"fold\"", "id=\"labels\""] {
            assert!(svg.contains(layer));
        }
    }
    validate_glb(&glbs);
}

/// Runs the Khronos glTF validator (npm `gltf-validator`, installed by `scripts/test.sh`).
fn validate_glb(files: &[PathBuf]) {
    let tool = repo().join("tools/gltf-validate");
    assert!(
        tool.join("node_modules/gltf-validator").exists(),
        "the glTF validator is not installed: run `npm ci --prefix tools/gltf-validate` (scripts/test.sh does)"
    );
    let o = Command::new("node")
        .arg(tool.join("validate.js"))
        .args(files)
        .output()
        .expect("node runs");
    assert!(
        o.status.success(),
        "glTF validator found errors:\n{}",
        String::from_utf8_lossy(&o.stdout)
    );
    for line in String::from_utf8_lossy(&o.stdout).lines() {
        let v: serde_json::Value = serde_json::from_str(line).unwrap();
        assert_eq!(v["errors"], 0, "{line}");
        assert_eq!(v["warnings"], 0, "{line}");
    }
}

#[test]
fn animation_frames_are_isometric_and_start_flat() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = repo().join("examples/two-piece-composite.json");
    let o = sheetform(&[
        "bend",
        scene.to_str().unwrap(),
        "-o",
        tmp.path().to_str().unwrap(),
        "--animate",
        "5",
        "-q",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for i in 0..5 {
        let obj = read_obj(&tmp.path().join(format!("frames/frame-{i:04}.obj")));
        assert!(obj_isometry_error(&obj) <= 1e-9);
        if i == 0 {
            // Frame 0 is the flat sheet: every vertex in one plane.
            let p = |k: usize| nalgebra::Vector3::from(obj.v[k]);
            let n = (p(1) - p(0)).cross(&(p(2) - p(0))).normalize();
            let off = obj
                .v
                .iter()
                .map(|v| (nalgebra::Vector3::from(*v) - p(0)).dot(&n).abs())
                .fold(0.0, f64::max);
            assert!(off < 1e-9, "frame 0 not flat: {off}");
        }
    }
    let last = read_obj(&tmp.path().join("frames/frame-0004.obj"));
    let model = read_obj(&tmp.path().join("model.obj"));
    let gap = last
        .v
        .iter()
        .zip(&model.v)
        .map(|(a, b)| (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt())
        .fold(0.0, f64::max);
    assert!(gap < 1e-9, "last frame differs from the model by {gap}");
}

fn bad_input(name: &str, scene: &str, expect: &str) {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join(format!("{name}.json"));
    std::fs::write(&path, scene).unwrap();
    let out = tmp.path().join("out");
    let o = sheetform(&["bend", path.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{name}: {stderr}");
    assert!(stderr.contains(expect), "{name}: expected `{expect}` in: {stderr}");
    assert!(!out.exists(), "{name}: output written for bad input");
}

const CURVE: &str = r#"{"type":"bezier","control_points":[[0,0,0],[40,0,10],[80,0,0]]}"#;

#[test]
fn bad_input_gets_a_clear_error_and_no_output() {
    let rect = "[[0,-20],[100,-20],[100,20],[0,20]]";
    let scene = |outline: &str, region: &str| format!(r#"{{"outline":{outline},"regions":[{region}]}}"#);
    let region = |extra: &str, curve: &str| format!(r#"{{"flat_start":[0,0],{extra},"curve":{curve}}}"#);
    bad_input("malformed", "{\"outline\": [[0,0],", "line 1");
    bad_input(
        "unknown field",
        &format!(r#"{{"outline":{rect},"regions":[],"colour":1}}"#),
        "unknown field `colour`",
    );
    bad_input(
        "nan",
        &scene(
            rect,
            &region(
                r#""flat_direction":[1,0]"#,
                r#"{"type":"bezier","control_points":[[0,0,0],[NaN,0,0],[1,1,0]]}"#,
            ),
        ),
        "line 1",
    );
    bad_input(
        "infinite",
        &scene(
            rect,
            &region(
                r#""flat_direction":[1,0]"#,
                r#"{"type":"bezier","control_points":[[0,0,0],[1e999,0,0],[1,1,0]]}"#,
            ),
        ),
        "line 1",
    );
    bad_input(
        "self-crossing outline",
        &scene(
            "[[0,0],[100,40],[100,0],[0,40]]",
            &region(r#""flat_direction":[1,0]"#, CURVE),
        ),
        "crosses",
    );
    bad_input(
        "length mismatch",
        &scene(rect, &region(r#""flat_end":[90,0]"#, CURVE)),
        "bending cannot stretch the sheet",
    );
    bad_input(
        "geodesic leaves sheet",
        &scene(
            "[[0,-20],[60,-20],[60,20],[0,20]]",
            &region(r#""flat_direction":[1,0]"#, CURVE),
        ),
        "leaves the sheet",
    );
    bad_input(
        "degree one",
        &scene(
            rect,
            &region(
                r#""flat_direction":[1,0]"#,
                r#"{"type":"bezier","control_points":[[0,0,0],[80,0,0]]}"#,
            ),
        ),
        "degree-1",
    );
    bad_input(
        "zero length",
        &scene(
            rect,
            &region(
                r#""flat_direction":[1,0]"#,
                r#"{"type":"bezier","control_points":[[5,5,5],[5,5,5],[5,5,5]]}"#,
            ),
        ),
        "zero-length",
    );
    bad_input(
        "straight",
        &scene(
            rect,
            &region(
                r#""flat_direction":[1,0]"#,
                r#"{"type":"bezier","control_points":[[0,0,0],[40,0,0],[80,0,0]]}"#,
            ),
        ),
        "straight everywhere",
    );
    bad_input(
        "no regions",
        &format!(r#"{{"outline":{rect},"regions":[]}}"#),
        "at least one curved region",
    );
    bad_input(
        "hole outside",
        &format!(
            r#"{{"outline":{rect},"holes":[[[200,0],[210,0],[210,5]]],"regions":[{}]}}"#,
            region(r#""flat_direction":[1,0]"#, CURVE)
        ),
        "hole 0",
    );
}

#[test]
fn missing_scene_file_is_an_error() {
    let tmp = tempfile::tempdir().unwrap();
    let o = sheetform(&[
        "bend",
        tmp.path().join("nope.json").to_str().unwrap(),
        "-o",
        tmp.path().join("out").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("cannot read"));
}

#[test]
fn inadmissible_shape_writes_only_the_report_saying_where() {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("twisted.json");
    // Strong torsion on a wide sheet: the curve of regression crosses it.
    std::fs::write(
        &path,
        r#"{"outline":[[0,-60],[240,-60],[240,60],[0,60]],"regions":[{"flat_start":[0,0],"flat_direction":[1,0],
            "curve":{"type":"bezier","control_points":[[0,0,0],[80,10,0],[150,-20,60],[170,10,120]]}}]}"#,
    )
    .unwrap();
    let out = tmp.path().join("out");
    let o = sheetform(&["bend", path.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(3), "{}", String::from_utf8_lossy(&o.stderr));
    let files: Vec<_> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(files, vec![std::ffi::OsString::from("report.json")]);
    let r = report(&out);
    assert_eq!(r["admissible"], false);
    let entry = &r["regression_entry"];
    assert!(entry["message"].as_str().unwrap().contains("Eq. 6"));
    let [x, y] = [
        entry["flat_point_mm"][0].as_f64().unwrap(),
        entry["flat_point_mm"][1].as_f64().unwrap(),
    ];
    assert!(
        (-1e-6..=240.0).contains(&x) && (-60.0..=60.0).contains(&y),
        "entry point must be on the sheet: {x}, {y}"
    );
}

#[test]
fn schemas_are_printed_and_match_the_docs() {
    for kind in ["bend", "slit", "ffd"] {
        let o = sheetform(&["schema", kind]);
        assert!(o.status.success());
        let printed: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        let file = format!("docs/schema/{kind}-scene.schema.json");
        let documented: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(repo().join(&file)).unwrap()).unwrap();
        assert_eq!(
            printed, documented,
            "{file} is stale: regenerate with `sheetform schema {kind} > {file}`"
        );
    }
}

fn shared(name: &str) -> PathBuf {
    repo().join("../shared/testdata").join(name)
}

#[test]
fn check_calls_the_crumpled_sheet_developable_and_measures_its_flattening() {
    let tmp = tempfile::tempdir().unwrap();
    let o = sheetform(&[
        "check",
        shared("crumpled-developable.obj").to_str().unwrap(),
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
        shared("wingnut.obj").to_str().unwrap(),
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
        shared("wingnut.obj").to_str().unwrap(),
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

#[test]
fn flatten_unfolds_the_crumpled_sheet_at_least_as_well_as_its_stored_pattern() {
    let tmp = tempfile::tempdir().unwrap();
    let o = sheetform(&[
        "flatten",
        shared("crumpled-developable.obj").to_str().unwrap(),
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
        shared("wingnut.obj").to_str().unwrap(),
        "--charts",
        "never",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("0 boundary loop(s)"));
    assert!(!out.exists());
}

/// Cut loops of an SVG pattern (layer `cut`) as point lists (mm, SVG coordinates).
fn svg_cut_loops(svg: &str) -> Vec<Vec<[f64; 2]>> {
    let layer = &svg[svg.find(r#"<g id="cut""#).unwrap()..];
    let layer = &layer[..layer.find("</g>").unwrap()];
    layer
        .split(r#"<path d=""#)
        .skip(1)
        .map(|d| {
            d[..d.find('"').unwrap()]
                .split_whitespace()
                .filter(|t| t.starts_with('M') || t.starts_with('L'))
                .map(|t| {
                    let (x, y) = t[1..].split_once(',').unwrap();
                    [x.parse().unwrap(), y.parse().unwrap()]
                })
                .collect()
        })
        .collect()
}

/// Texts of one class in the SVG's label layer.
fn svg_texts(svg: &str, class: &str) -> Vec<String> {
    let marker = format!(r#"<text class="{class}""#);
    svg.split(&marker)
        .skip(1)
        .map(|t| t[t.find('>').unwrap() + 1..t.find("</text>").unwrap()].to_string())
        .collect()
}

/// Pairs of cut segments that meet, other than neighbours in one loop at their shared
/// point.
fn cut_intersections(loops: &[Vec<[f64; 2]>]) -> usize {
    let mut segments = Vec::new();
    for (l, points) in loops.iter().enumerate() {
        for i in 0..points.len() {
            segments.push((l, i, points.len(), points[i], points[(i + 1) % points.len()]));
        }
    }
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
    let mut hits = 0;
    for (x, &(la, ia, na, a0, a1)) in segments.iter().enumerate() {
        for &(lb, ib, _, b0, b1) in &segments[x + 1..] {
            if la == lb && (ib == (ia + 1) % na || ia == (ib + 1) % na) {
                continue;
            }
            let (d1, d2) = (cross(a0, a1, b0), cross(a0, a1, b1));
            let (d3, d4) = (cross(b0, b1, a0), cross(b0, b1, a1));
            if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
                hits += 1;
            }
        }
    }
    hits
}

#[test]
fn flatten_cuts_the_wingnut_into_flat_charts_with_seam_ids_tabs_and_sheets() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let o = sheetform(&[
        "flatten",
        shared("wingnut.obj").to_str().unwrap(),
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
    // Seam IDs: every seam's ID is printed on both of its sides.
    let ids = svg_texts(&svg, "seam");
    let seams = p["seam_count"].as_u64().unwrap() as usize;
    assert!(seams > 0);
    for id in 1..=seams {
        let n = ids.iter().filter(|t| **t == id.to_string()).count();
        assert_eq!(n, 2, "seam {id} is labelled {n} times");
    }
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
fn a_piece_larger_than_the_sheet_is_named() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let o = sheetform(&[
        "flatten",
        shared("crumpled-developable.obj").to_str().unwrap(),
        "--units",
        "cm",
        "--scale",
        "5",
        "--sheet",
        "50x50",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("piece `crumpled-developable`") && err.contains("does not fit"),
        "{err}"
    );
    assert!(!out.exists());
}

/// CUT layer of a DXF as read by ezdxf (an independent reader): audit error count,
/// polyline count, total signed area and bounds.
fn ezdxf_cut(path: &Path) -> serde_json::Value {
    let script = r#"
import ezdxf, json, sys
doc = ezdxf.readfile(sys.argv[1])
auditor = doc.audit()
polys = [e for e in doc.modelspace().query('LWPOLYLINE') if e.dxf.layer == 'CUT']
area, xs, ys = 0.0, [], []
for p in polys:
    pts = [(x, y) for x, y, *_ in p.get_points()]
    area += 0.5 * sum(a[0] * b[1] - b[0] * a[1] for a, b in zip(pts, pts[1:] + pts[:1]))
    xs += [x for x, _ in pts]; ys += [y for _, y in pts]
print(json.dumps({"errors": len(auditor.errors), "closed": all(p.closed for p in polys), "count": len(polys),
  "area": area, "width": max(xs) - min(xs), "height": max(ys) - min(ys),
  "layers": sorted(l.dxf.name for l in doc.layers), "insunits": doc.header.get('$INSUNITS', 0),
  "folds": len([e for e in doc.modelspace().query('LINE') if e.dxf.layer == 'FOLD'])}))
"#;
    let o = Command::new("python3")
        .arg("-c")
        .arg(script)
        .arg(path)
        .output()
        .expect("python3 runs");
    assert!(
        o.status.success(),
        "ezdxf could not read {}: {}",
        path.display(),
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_slice(&o.stdout).unwrap()
}

#[test]
fn patterns_are_readable_and_at_true_scale_in_dxf_and_pdf() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = repo().join("examples/sheet-with-hole.json");
    let o = sheetform(&[
        "bend",
        scene.to_str().unwrap(),
        "-o",
        tmp.path().to_str().unwrap(),
        "-q",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r = report(tmp.path());
    let flat_area = r["flat_area_mm2"].as_f64().unwrap();
    let d = ezdxf_cut(&tmp.path().join("pattern.dxf"));
    assert_eq!(d["errors"], 0, "{d}");
    assert_eq!(d["closed"], true);
    assert_eq!(d["count"], 2, "outline and one hole: {d}");
    assert_eq!(d["insunits"], 4, "millimetres");
    assert!(d["folds"].as_u64().unwrap() > 10);
    for layer in ["CUT", "FOLD", "LABEL"] {
        assert!(d["layers"].as_array().unwrap().iter().any(|l| l == layer), "{d}");
    }
    // Outline counter-clockwise, hole clockwise: the signed sum is the sheet's area.
    assert!(
        (d["area"].as_f64().unwrap() - flat_area).abs() <= 1e-6 * flat_area,
        "{d} vs {flat_area}"
    );
    assert!(
        (d["width"].as_f64().unwrap() - 300.0).abs() < 1e-6 && (d["height"].as_f64().unwrap() - 140.0).abs() < 1e-6,
        "{d}"
    );
    // The PDF renders, one page per tile, A4.
    let pages = r["pattern"]["tile_rows"].as_u64().unwrap() * r["pattern"]["tile_columns"].as_u64().unwrap();
    let render = Command::new("pdftoppm")
        .args(["-r", "10", "-png"])
        .arg(tmp.path().join("pattern.pdf"))
        .arg(tmp.path().join("page"))
        .output()
        .expect("pdftoppm runs");
    assert!(render.status.success(), "{}", String::from_utf8_lossy(&render.stderr));
    let rendered = std::fs::read_dir(tmp.path())
        .unwrap()
        .filter(|e| e.as_ref().unwrap().file_name().to_string_lossy().starts_with("page"))
        .count();
    assert_eq!(rendered as u64, pages);
    let info = Command::new("pdfinfo")
        .arg(tmp.path().join("pattern.pdf"))
        .output()
        .expect("pdfinfo runs");
    assert!(
        String::from_utf8_lossy(&info.stdout).contains("595.276 x 841.89"),
        "{}",
        String::from_utf8_lossy(&info.stdout)
    );
}

#[test]
fn pattern_scale_units_and_paper_options() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = repo().join("examples/bent-rectangle.json");
    let o = sheetform(&[
        "bend",
        scene.to_str().unwrap(),
        "-o",
        tmp.path().to_str().unwrap(),
        "-q",
        "--scale",
        "0.5",
        "--pattern-units",
        "in",
        "--page",
        "letter",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r = report(tmp.path());
    assert!((r["pattern"]["width_mm"].as_f64().unwrap() - 120.0).abs() < 1e-9);
    assert_eq!(r["pattern"]["page"], "Letter");
    let d = ezdxf_cut(&tmp.path().join("pattern.dxf"));
    assert_eq!(d["insunits"], 1, "inches");
    assert!((d["width"].as_f64().unwrap() - 120.0 / 25.4).abs() < 1e-9, "{d}");
    let info = Command::new("pdfinfo")
        .arg(tmp.path().join("pattern.pdf"))
        .output()
        .expect("pdfinfo runs");
    assert!(
        String::from_utf8_lossy(&info.stdout).contains("612 x 792"),
        "{}",
        String::from_utf8_lossy(&info.stdout)
    );
    let bad = sheetform(&[
        "bend",
        scene.to_str().unwrap(),
        "-o",
        tmp.path().join("x").to_str().unwrap(),
        "--scale=-1",
    ]);
    assert_eq!(bad.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("scale"));
}

#[test]
fn flatten_with_lscm_handles_a_nearly_developable_mesh() {
    let tmp = tempfile::tempdir().unwrap();
    // A shallow paraboloid cap: not developable, flattens with small distortion.
    let n = 20;
    let mut obj = String::new();
    for i in 0..=n {
        for j in 0..=n {
            let (x, y) = (i as f64 / n as f64 - 0.5, j as f64 / n as f64 - 0.5);
            obj += &format!("v {} {} {}\n", 100.0 * x, 100.0 * y, 10.0 * (1.0 - x * x - y * y));
        }
    }
    let id = |i: usize, j: usize| i * (n + 1) + j + 1;
    for i in 0..n {
        for j in 0..n {
            obj += &format!(
                "f {} {} {}\nf {} {} {}\n",
                id(i, j),
                id(i + 1, j),
                id(i + 1, j + 1),
                id(i, j),
                id(i + 1, j + 1),
                id(i, j + 1)
            );
        }
    }
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

#[test]
fn ffd_examples_restore_developability_and_write_every_output() {
    for name in ["two-panels", "duct", "skirt-springs"] {
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
    // The paper's solver runs from the command line too and lowers G.
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
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let step = &report(tmp.path())["ffd"]["steps"][0];
    assert_eq!(step["solver"], "paper");
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

#[test]
fn photo_examples_are_reconstructed_with_every_output() {
    for annotation in [
        "examples/photo/coffee-cup.json",
        "examples/photo/coffee-cup.svg",
        "examples/photo/synthetic/cone-ortho.json",
    ] {
        let tmp = tempfile::tempdir().unwrap();
        let o = sheetform(&[
            "photo",
            repo().join(annotation).to_str().unwrap(),
            "-o",
            tmp.path().to_str().unwrap(),
        ]);
        assert!(
            o.status.success(),
            "{annotation}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let r = report(tmp.path());
        assert_eq!(r["command"], "photo");
        assert_eq!(r["status"], "ok", "{annotation}");
        let photo = &r["photo"];
        assert_eq!(
            photo["patch_count"], 1,
            "{annotation}: the body; the mouth is an opening"
        );
        assert_eq!(photo["opening_count"], 1);
        assert!(photo["ruling_count"].as_u64().unwrap() >= 20);
        assert!(photo["symmetric_pair_count"].as_u64().unwrap() >= 20);
        // The paper's metric, after its linear solve and after the refinement (degrees).
        assert!(photo["developability_error_linear"]["mean_deg"].as_f64().unwrap() < 6.0);
        assert!(photo["developability_error_refined"]["mean_deg"].as_f64().unwrap() <= 0.1);
        assert!(photo["reprojection_error_max_px"].as_f64().unwrap() < 2.0);
        // The body is a ruled strip: it unfolds exactly, and model.obj's vt is that pattern.
        let obj = read_obj(&tmp.path().join("model.obj"));
        assert!(
            obj_isometry_error(&obj) < 1e-9,
            "{annotation}: vt is the flat pattern at 1:1"
        );
        validate_glb(&[tmp.path().join("model.glb")]);
        let dxf = ezdxf_cut(&tmp.path().join("pattern.dxf"));
        assert_eq!(dxf["errors"], 0);
        assert_eq!(dxf["count"], 1, "one piece");
        // The pattern's area is the model's (mm²).
        let area = dxf["area"].as_f64().unwrap().abs();
        let model_area = r["area_mm2"].as_f64().unwrap();
        assert!(
            (area / model_area - 1.0).abs() < 0.02,
            "{annotation}: {area} vs {model_area}"
        );
        // A drawing from Inkscape also leaves the annotation it was read as.
        let converted = tmp.path().join("annotation.json");
        assert_eq!(converted.exists(), annotation.ends_with(".svg"), "{annotation}");
        if converted.exists() {
            let text = std::fs::read_to_string(&converted).unwrap();
            let json: serde_json::Value = serde_json::from_str(&text).unwrap();
            assert_eq!(json["curves"].as_array().unwrap().len(), 4);
        }
        let overlay = std::fs::read_to_string(tmp.path().join("overlay.svg")).unwrap();
        for layer in ["patches", "rulings", "symmetry", "curves", "reprojected"] {
            assert!(overlay.contains(&format!("id=\"{layer}\"")), "{layer}");
        }
        assert!(overlay.contains("data:image/png;base64,"));
        // Every ruling; mirror pairs thinned to at most 60 so the photo shows.
        let pairs = photo["symmetric_pair_count"].as_u64().unwrap() as usize;
        assert_eq!(
            overlay.matches("class=\"ruling\"").count(),
            photo["ruling_count"].as_u64().unwrap() as usize
        );
        assert_eq!(
            overlay.matches("class=\"pair\"").count(),
            pairs.div_ceil(pairs.div_ceil(60).max(1))
        );
        // The PNG overlay: the photo's size, and not the photo alone (curves drawn on it).
        let png = std::fs::read(tmp.path().join("overlay.png")).unwrap();
        assert_eq!(&png[1..4], b"PNG");
        let (w, h) = (
            u32::from_be_bytes([png[16], png[17], png[18], png[19]]),
            u32::from_be_bytes([png[20], png[21], png[22], png[23]]),
        );
        let expected: (u32, u32) = if annotation.contains("coffee") {
            (600, 400)
        } else {
            (480, 480)
        };
        assert_eq!((w, h), expected);
    }
}

#[test]
fn photo_bad_input_is_an_error_and_writes_nothing() {
    let good: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(repo().join("examples/photo/synthetic/cone-ortho.json")).unwrap(),
    )
    .unwrap();
    let cases: Vec<(serde_json::Value, &str)> = vec![
        (
            {
                let mut v = good.clone();
                v["image"]["path"] = "missing.png".into();
                v
            },
            "missing.png",
        ),
        (
            {
                let mut v = good.clone();
                v["image"]["width"] = 481.into();
                v
            },
            "480 × 480",
        ),
        (
            {
                let mut v = good.clone();
                v["true_size"]["length"] = 0.into();
                v
            },
            "true_size.length",
        ),
    ];
    for (value, expect) in cases {
        let tmp = tempfile::tempdir().unwrap();
        // The image path is relative to the annotation: write it next to the example's PNG.
        let file = repo().join("examples/photo/synthetic").join(format!(
            ".bad-{}.json",
            tmp.path().file_name().unwrap().to_string_lossy()
        ));
        std::fs::write(&file, value.to_string()).unwrap();
        let out = tmp.path().join("out");
        let o = sheetform(&["photo", file.to_str().unwrap(), "-o", out.to_str().unwrap()]);
        std::fs::remove_file(&file).unwrap();
        assert_eq!(o.status.code(), Some(1), "{expect}");
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(stderr.contains(expect), "{expect}: {stderr}");
        assert!(!out.exists(), "nothing written");
    }
    let o = sheetform(&["schema", "photo"]);
    assert!(o.status.success());
    let printed: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let file = "docs/schema/photo-annotation.schema.json";
    let documented: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(repo().join(file)).unwrap()).unwrap();
    assert_eq!(
        printed, documented,
        "{file} is stale: regenerate with `sheetform schema photo > {file}`"
    );
}

/// A scene may read only files in its own directory: a texture named by `../` (or an
/// absolute path) outside it is refused with the field named, exit 1, nothing written.
#[test]
fn a_scene_cannot_read_files_outside_its_directory() {
    let tmp = tempfile::tempdir().unwrap();
    let project = tmp.path().join("project");
    std::fs::create_dir_all(&project).unwrap();
    std::fs::copy(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/textures/grid-240x120mm.png"),
        tmp.path().join("outside.png"),
    )
    .unwrap();
    let scene =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/textured-sheet.json"))
            .unwrap();
    let mut value: serde_json::Value = serde_json::from_str(&scene).unwrap();
    for texture in ["../outside.png", tmp.path().join("outside.png").to_str().unwrap()] {
        value["texture"] = texture.into();
        let path = project.join("scene.json");
        std::fs::write(&path, value.to_string()).unwrap();
        let out = tmp.path().join("out");
        let o = sheetform(&["bend", path.to_str().unwrap(), "-o", out.to_str().unwrap()]);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{stderr}");
        assert!(stderr.contains("texture"), "{stderr}");
        assert!(!out.exists(), "nothing is written");
    }
}

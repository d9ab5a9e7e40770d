//! `sheetform bend`: every example, animation, bad input, inadmissible shapes, assets.

use crate::common::{examples, obj_isometry_error, read_obj, repo, report, sheetform, validate_glb};
use std::path::Path;
use std::process::Command;

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
        for layer in [
            "id=\"cut\"",
            "id=\"fold-mountain\"",
            "id=\"fold-guide\"",
            "id=\"labels\"",
        ] {
            assert!(svg.contains(layer));
        }
    }
    validate_glb(&glbs);
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
        // In the user's terms: how much sheet lies ahead, what to change.
        "leaves the sheet 60 from its start, near (60, 0): shorten the curve by",
    );
    bad_input(
        "geodesic crosses a hole before the outline",
        // The outline's right side (x = 60) comes before the hole (x = 40…50) in the
        // list of edges: the crossing nearest the start is named.
        r#"{"outline":[[0,-20],[60,-20],[60,20],[0,20]],"holes":[[[40,-5],[50,-5],[50,5],[40,5]]],
            "regions":[{"flat_start":[0,0],"flat_direction":[1,0],
            "curve":{"type":"bezier","control_points":[[0,0,0],[40,0,10],[80,0,0]]}}]}"#,
        "leaves the sheet 40 from its start, near (40, 0)",
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
    let message = entry["message"].as_str().unwrap();
    assert!(
        message.contains("fold onto itself") && !message.contains("Eq. 6"),
        "{message}"
    );
    let [x, y] = [
        entry["flat_point_mm"][0].as_f64().unwrap(),
        entry["flat_point_mm"][1].as_f64().unwrap(),
    ];
    assert!(
        (-1e-6..=240.0).contains(&x) && (-60.0..=60.0).contains(&y),
        "entry point must be on the sheet: {x}, {y}"
    );
}

/// A scene may read only files in its own directory: a texture named by `../` (or an
/// absolute path) outside it is refused with the field named, exit 1, nothing written;
/// only `--assets-within DIR` lets it read elsewhere, inside DIR.
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
        assert!(
            stderr.contains("texture") && stderr.contains("--assets-within"),
            "{stderr}"
        );
        assert!(!out.exists(), "nothing is written");
        // With the explicit flag naming a directory that holds the file, it is read;
        // naming the scene's own directory does not widen anything.
        let within = |dir: &Path| {
            sheetform(&[
                "bend",
                path.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
                "-q",
                "--assets-within",
                dir.to_str().unwrap(),
            ])
        };
        let allowed = within(tmp.path());
        assert!(allowed.status.success(), "{}", String::from_utf8_lossy(&allowed.stderr));
        assert!(out.join("texture.png").exists());
        std::fs::remove_dir_all(&out).unwrap();
        let narrow = within(&project);
        assert_eq!(narrow.status.code(), Some(1));
        assert!(String::from_utf8_lossy(&narrow.stderr).contains("outside the allowed directory"));
    }
}

/// A texture printed on the bent sheet reaches the pattern: the SVG embeds the image once
/// and shows it on every piece, clipped to it; the PDF prints it (its pages, rendered by
/// pdftoppm, are tinted by the image where they were white); the OBJ names a material
/// whose map fits the 1:1 `vt` onto the image, written beside it.
#[test]
fn a_texture_is_printed_on_the_pattern_and_named_by_the_obj() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/textured-sheet.json");
    let o = sheetform(&[
        "bend",
        scene.to_str().unwrap(),
        "-o",
        tmp.path().to_str().unwrap(),
        "-q",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let source =
        std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/textures/grid-240x120mm.png"))
            .unwrap();
    assert_eq!(std::fs::read(tmp.path().join("texture.png")).unwrap(), source);
    let mtl = std::fs::read_to_string(tmp.path().join("model.mtl")).unwrap();
    assert!(mtl.contains("newmtl sheet") && mtl.contains("map_Kd -s ") && mtl.trim_end().ends_with("texture.png"));
    let obj = std::fs::read_to_string(tmp.path().join("model.obj")).unwrap();
    assert!(obj.starts_with("mtllib model.mtl\nusemtl sheet\n"));
    let r = crate::common::report(tmp.path());
    let pieces = r["pattern"]["piece_count"].as_u64().unwrap() as usize;
    let svg = std::fs::read_to_string(tmp.path().join("pattern.svg")).unwrap();
    assert_eq!(svg.matches(r#"<image id="texture-image""#).count(), 1);
    assert!(svg.contains(r#"href="data:image/png;base64,"#));
    assert_eq!(svg.matches(r##"<use href="#texture-image""##).count(), pieces);
    assert_eq!(svg.matches("<clipPath id=\"piece-").count(), pieces);
    // The PDF's pages, rendered: the image's warm squares cover a good part of them.
    let render = Command::new("pdftoppm")
        .args(["-r", "20"])
        .arg(tmp.path().join("pattern.pdf"))
        .arg(tmp.path().join("page"))
        .output()
        .expect("pdftoppm runs");
    assert!(render.status.success(), "{}", String::from_utf8_lossy(&render.stderr));
    let page = std::fs::read(tmp.path().join("page-1.ppm")).unwrap();
    // P6 header: magic, width, height, maxval, then RGB bytes.
    let mut fields = 0;
    let mut start = 0;
    let mut previous_space = true;
    for (i, &b) in page.iter().enumerate() {
        let space = b.is_ascii_whitespace();
        if space && !previous_space {
            fields += 1;
            if fields == 4 {
                start = i + 1;
                break;
            }
        }
        previous_space = space;
    }
    let pixels: Vec<&[u8]> = page[start..].chunks(3).collect();
    let warm = pixels
        .iter()
        .filter(|p| p[0] < 245 && p[0] as i32 > p[2] as i32 + 12)
        .count();
    assert!(
        warm * 10 > pixels.len(),
        "{warm} of {} pixels show the texture",
        pixels.len()
    );
}

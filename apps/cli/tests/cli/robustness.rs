//! Issue 19: bad input of every class gets a clear error naming the field or place, in
//! bounded time and memory, and nothing is written as if it had succeeded. Each case is
//! the minimal input that broke an earlier build (panic, abort on allocation, hang,
//! wrong success, corrupt output, leaked internal names).

use crate::common::{repo, sheetform, sheetform_within};
use serde_json::{json, Value};
use std::path::Path;

fn example(path: &str) -> Value {
    serde_json::from_str(&std::fs::read_to_string(repo().join(path)).unwrap()).unwrap()
}

/// Runs `command` on `scene` (written to a temporary file) and returns (exit code,
/// stderr), with a hang guard.
fn run_scene(command: &str, scene: &Value, extra: &[&str]) -> (i32, String) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.json");
    std::fs::write(&path, scene.to_string()).unwrap();
    let out = dir.path().join("out");
    let mut args = vec![command, path.to_str().unwrap(), "-o", out.to_str().unwrap(), "-q"];
    args.extend_from_slice(extra);
    let o = sheetform_within(&args, 120);
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// A message for people: no Rust type names or Debug output, no number printed in
/// hundreds of digits, not a flood.
fn assert_readable(message: &str) {
    for internal in [
        "{ ",
        "Some(",
        "ZeroPivot",
        "NonPositivePivot",
        "TooLarge",
        "ParseError",
        "LineCol",
    ] {
        assert!(!message.contains(internal), "internal name `{internal}` in: {message}");
    }
    assert!(
        !message.contains("0000000000000000"),
        "a number in hundreds of digits: {message}"
    );
    assert!(message.len() < 2000, "{} bytes of message", message.len());
}

fn assert_refused(command: &str, scene: &Value, field: &str) {
    let (code, stderr) = run_scene(command, scene, &[]);
    assert_eq!(code, 1, "{command} with bad `{field}` should be refused: {stderr}");
    assert!(
        stderr.contains(&format!("`{field}`")),
        "expected `{field}` in: {stderr}"
    );
    assert_readable(&stderr);
}

/// Sizes a user can set are bounded before anything is allocated: each of these
/// panicked (capacity overflow, `degree + 1` wrapping) or aborted on a 2–24 GB
/// allocation.
#[test]
fn sizes_over_their_documented_maxima_are_refused_naming_the_field() {
    let bend = example("examples/bent-rectangle.json");
    let mut s = bend.clone();
    s["regions"][0]["curve"] = json!({"type": "bspline", "periodic": true, "degree": u64::MAX,
        "control_points": [[0, 0, 0], [70, 0, 10], [140, 8, 60], [160, 12, 120]]});
    assert_refused("bend", &s, "regions[0].curve.degree");
    let mut s = bend.clone();
    s["tessellation"] = json!({"rulings": 100_000_000u64});
    assert_refused("bend", &s, "tessellation.rulings");
    let mut s = bend.clone();
    s["tessellation"] = json!({"max_rulings": u64::MAX});
    assert_refused("bend", &s, "tessellation.max_rulings");
    // Counts multiplied by other counts: regions (each placed against the others),
    // outline vertices (each ruling is clipped against every edge).
    let mut s = bend.clone();
    s["regions"] = json!(vec![s["regions"][0].clone(); 300]);
    assert_refused("bend", &s, "regions");
    let mut s = bend.clone();
    let circle: Vec<[f64; 2]> = (0..100_001)
        .map(|i| {
            let a = i as f64 * std::f64::consts::TAU / 100_001.0;
            [120.0 + 200.0 * a.cos(), 200.0 * a.sin()]
        })
        .collect();
    s["outline"] = json!(circle);
    assert_refused("bend", &s, "outline/holes");
    // 8 000 Bézier control points: 88 s and 860 MB of derivative nets before the cap.
    let mut s = bend.clone();
    let many: Vec<[f64; 3]> = (0..8000)
        .map(|i| [i as f64 * 0.02, 0.0, (i as f64 * 0.001).sin()])
        .collect();
    s["regions"][0]["curve"] = json!({"type": "bezier", "control_points": many});
    let (code, stderr) = run_scene("bend", &s, &[]);
    assert!(code == 1 && stderr.contains("at most 65 control points"), "{stderr}");

    let ffd = example("examples/ffd/duct.json");
    let mut s = ffd.clone();
    s["lattice"]["counts"] = json!([1000, 1000, 1000]);
    assert_refused("ffd", &s, "lattice.counts[0]");
    let mut s = ffd.clone();
    s["lattice"]["degrees"] = json!([3, u64::MAX, 3]);
    assert_refused("ffd", &s, "lattice.degrees[1]");
    let mut s = ffd.clone();
    s["model"]["procedural"]["around"] = json!(100_000_000u64);
    assert_refused("ffd", &s, "model.procedural.around");
    // Iteration counts and a tolerance below what angle sums can reach: a restoration
    // that could never end.
    for (key, value, field) in [
        ("max_iterations", json!(u64::MAX), "solver.max_iterations"),
        ("refine_iterations", json!(1_000_000), "solver.refine_iterations"),
        ("line_search_memory", json!(1_000_000), "solver.line_search_memory"),
        ("tolerance_rad", json!(1e-300), "solver.tolerance_rad"),
    ] {
        let mut s = ffd.clone();
        s["solver"][key] = value;
        assert_refused("ffd", &s, field);
    }

    // System D: the photo's area (the overlay decodes it whole) and the lists whose
    // entries each re-run a quadratic matching.
    let photo = example("examples/photo/coffee-cup.json");
    let mut s = photo.clone();
    s["image"]["width"] = json!(40_000);
    s["image"]["height"] = json!(40_000);
    assert_refused("photo", &s, "image");
    let mut s = photo.clone();
    s["occlusions"] = json!(vec![[10.0, 10.0]; 1001]);
    assert_refused("photo", &s, "occlusions");
    let mut s = photo.clone();
    s["self_symmetric_curves"] = json!(["rim", "bottom", "rim"]);
    assert_refused("photo", &s, "self_symmetric_curves[2]");
    // A weight past its bound: the field, the bounds and the value refused.
    let mut s = photo.clone();
    s["analysis"]["weights"]["symmetry"] = json!(1e300);
    assert_refused("photo", &s, "analysis.weights.symmetry");
    let (_, stderr) = run_scene("photo", &s, &[]);
    assert!(stderr.contains("0 … 1e6, got 1e300"), "{stderr}");

    let slit = example("examples/slit/bench.json");
    let mut s = slit.clone();
    s["sheet"]["quads_per_strip"] = json!(4096);
    assert_refused("slit", &s, "sheet.quads_per_strip");
    let mut s = slit.clone();
    s["sheet"]["strip_count"] = json!(10_000);
    s["sheet"]["l4_slit_width"] = json!(0.001);
    assert_refused("slit", &s, "sheet.strip_count");
    // Joint mode solves all strips together: 60 strips of 10 quads took minutes.
    let mut s = slit.clone();
    s["sheet"]["strip_count"] = json!(60);
    s["sheet"]["l4_slit_width"] = json!(1);
    s["solver"] = json!({"mode": "joint"});
    let (code, stderr) = run_scene("slit", &s, &[]);
    assert!(code == 1 && stderr.contains("joint mode"), "{stderr}");
}

/// Two zig-zag curves traced across each other 60 times each (3 600 crossings): the
/// crossing matching is quadratic, 120 rows each took 31 s (180: out of 6.5 GB after
/// 10 minutes). Now refused at once, naming the curves.
#[test]
fn a_hatching_of_crossing_curves_is_refused_at_once() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(repo().join("examples/photo/coffee.png"), dir.path().join("coffee.png")).unwrap();
    let rows = 60;
    let cubic = |path: &[[f64; 2]]| -> Vec<[f64; 2]> {
        let mut points = vec![path[0]];
        for w in path.windows(2) {
            let (p, q) = (w[0], w[1]);
            let at = |f: f64| [p[0] + (q[0] - p[0]) * f, p[1] + (q[1] - p[1]) * f];
            points.extend([at(1.0 / 3.0), at(2.0 / 3.0), q]);
        }
        points
    };
    let (mut across, mut down) = (Vec::new(), Vec::new());
    for i in 0..rows {
        let f = i as f64 / (rows - 1) as f64;
        let (y, x) = (30.0 + 340.0 * f, 50.0 + 500.0 * f);
        let (a, b) = if i % 2 == 0 { (45.0, 555.0) } else { (555.0, 45.0) };
        across.extend([[a, y], [b, y]]);
        let (a, b) = if i % 2 == 0 { (25.0, 375.0) } else { (375.0, 25.0) };
        down.extend([[x, a], [x, b]]);
    }
    let annotation = json!({"name": "grid", "image": {"path": "coffee.png", "width": 600, "height": 400},
        "curves": [{"name": "across", "kind": "boundary", "control_points": cubic(&across)},
                   {"name": "down", "kind": "boundary", "control_points": cubic(&down)}],
        "symmetry": {"frame": [[[284.26, 165.13], [290.24, 112.77]], [[290.24, 112.77], [240.04, 196.81]]],
                     "points": [[183.81, 67.94], [396.68, 157.6]]},
        "true_size": {"from": [100, 30], "to": [500, 30], "length": 62.0},
        "analysis": {"snap_distance_px": 0.5}});
    let path = dir.path().join("grid.json");
    std::fs::write(&path, annotation.to_string()).unwrap();
    let out = dir.path().join("out");
    let o = sheetform_within(
        &["photo", path.to_str().unwrap(), "-o", out.to_str().unwrap(), "-q"],
        60,
    );
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("`curves`") && stderr.contains("cross more than 2000 times"),
        "{stderr}"
    );
    assert!(stderr.contains("`across`") && stderr.contains("`down`"), "{stderr}");
}

/// Numbers near the floating-point range: the arc-length tables and the strip solver
/// iterated for minutes (or until memory ran out); now an error, in short numbers.
#[test]
fn extreme_numbers_end_in_an_error_not_a_hang() {
    let bend = example("examples/bent-rectangle.json");
    let mut s = bend.clone();
    s["regions"][0]["curve"] = json!({"type": "bezier",
        "control_points": [[0, 0, 0], [1e308, 0, 0], [1e308, 1e308, 0], [-1e308, 1e308, 1e308]]});
    let (code, stderr) = run_scene("bend", &s, &[]);
    assert!(code != 0 && stderr.contains("not finite"), "{stderr}");
    assert_readable(&stderr);
    // Six equal control points: no arc length to converge to.
    let mut s = bend.clone();
    s["regions"][0]["curve"] = json!({"type": "bspline", "control_points": vec![[1, 2, 3]; 6]});
    let (code, stderr) = run_scene("bend", &s, &[]);
    assert!(code != 0 && stderr.contains("region 0"), "{stderr}");
    assert_readable(&stderr);

    let slit = example("examples/slit/bench.json");
    for (field, value) in [
        ("l3_strip_length", 1e308),
        ("l2_panel_length", 1e100),
        ("l3_strip_length", 5e-324),
    ] {
        let mut s = slit.clone();
        s["sheet"][field] = json!(value);
        let (code, stderr) = run_scene("slit", &s, &[]);
        assert_eq!(code, 1, "{field} = {value}: {stderr}");
        assert!(stderr.contains("`sheet"), "{stderr}");
        assert_readable(&stderr);
    }
    // A lattice moved far beyond the model: an error in words (it was faer's
    // `ZeroPivot { index: 0 }`), never NaN written with status ok.
    for by in [1e6, 1e200] {
        let mut s = example("examples/ffd/duct.json");
        s["deformations"] = json!([{"name": "far", "edits": [{"move": {"points": {"k": [3, 3]}, "by": [by, 0, 0]}}]}]);
        let (code, stderr) = run_scene("ffd", &s, &[]);
        assert!(code == 1 || code == 5, "move by {by}: {stderr}");
        assert_readable(&stderr);
    }
    let mut s = slit.clone();
    s["seat_curve"]["control_points"][0] = json!([0, 1e308]);
    let (code, stderr) = run_scene("slit", &s, &[]);
    assert!(code == 1 && stderr.contains("seat_curve.control_points[0]"), "{stderr}");
    assert_readable(&stderr);
}

/// Inputs that are not regular files: `/dev/zero` was read until memory ran out and a
/// FIFO blocked forever.
#[cfg(unix)]
#[test]
fn devices_and_pipes_are_refused_as_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let fifo = dir.path().join("pipe.obj");
    assert!(std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    for args in [
        vec!["check", "/dev/zero"],
        vec!["flatten", fifo.to_str().unwrap()],
        vec!["bend", "/dev/zero"],
        vec!["ffd", fifo.to_str().unwrap()],
    ] {
        let mut args = args.clone();
        args.extend(["-o", out.to_str().unwrap()]);
        let o = sheetform_within(&args, 60);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(stderr.contains("not a regular file"), "{args:?}: {stderr}");
    }
    assert!(!Path::new(&out).join("report.json").exists());
}

/// A small flat grid (9 vertices, 8 triangles) written to `dir`.
fn grid_obj(dir: &Path) -> String {
    let mut text = String::new();
    for y in 0..3 {
        for x in 0..3 {
            text.push_str(&format!("v {} {} 0\n", 10 * x, 10 * y));
        }
    }
    for y in 0..2 {
        for x in 0..2 {
            let a = 1 + x + 3 * y;
            text.push_str(&format!("f {} {} {}\nf {} {} {}\n", a, a + 1, a + 4, a, a + 4, a + 3));
        }
    }
    let path = dir.join("grid.obj");
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

/// Options that made a run succeed wrongly: NaN tolerances accepted ("developable"),
/// a weld that merged the mesh into one vertex reported "ok" with an empty model, an
/// absurd page cap that let the PDF grow until memory ran out.
#[test]
fn option_values_that_made_a_wrong_success_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = grid_obj(dir.path());
    let out = dir.path().join("out");
    let out = out.to_str().unwrap();
    for (args, option) in [
        (vec!["check", &mesh, "--tolerance", "NaN"], "--tolerance"),
        (vec!["check", &mesh, "--tolerance=-1"], "--tolerance"),
        (vec!["check", &mesh, "--weld", "1e9"], "--weld"),
        (vec!["flatten", &mesh, "--weld", "1e9"], "--weld"),
        (vec!["flatten", &mesh, "--crease-angle", "NaN"], "--crease-angle"),
        (vec!["flatten", &mesh, "--crease-angle=-5"], "--crease-angle"),
        (vec!["flatten", &mesh, "--max-distortion", "NaN"], "--max-distortion"),
        (vec!["flatten", &mesh, "--max-distortion=-1"], "--max-distortion"),
        (
            vec!["flatten", &mesh, "--max-pages", "18446744073709551615"],
            "max_pages",
        ),
    ] {
        let mut args = args.clone();
        args.extend(["-o", out]);
        let o = sheetform_within(&args, 60);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(stderr.contains(&format!("`{option}`")), "{args:?}: {stderr}");
        assert_readable(&stderr);
        assert!(!Path::new(out).join("report.json").exists(), "{args:?} wrote a report");
    }
    // The same mesh with sound options works (the cases above fail for their option).
    let o = sheetform_within(&["flatten", &mesh, "--weld", "0.1", "-o", out], 60);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // 10 000 frames (the frame cap) of a 393-vertex sheet: 743 MB of OBJ held in memory
    // before the budget over all frames; at most 5 089 frames of this sheet now.
    let scene = repo().join("examples/bent-rectangle.json");
    let o = sheetform_within(&["bend", scene.to_str().unwrap(), "--animate", "10000", "-o", out], 60);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("`animate`") && stderr.contains("at most 5089 frames"),
        "{stderr}"
    );
    assert!(!Path::new(out).join("frames").exists());
}

/// Output sets: a later run leaves exactly its own files (stale `frames/` and `sheets/`
/// from an earlier run with `--animate`/`--sheet` are removed), an inadmissible run
/// leaves only its report (not the last good model beside it), files the user put in
/// the directory are never touched, and no staging or temporary file is left behind.
#[test]
fn an_output_directory_holds_exactly_the_files_of_its_last_run() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let out_str = out.to_str().unwrap();
    let scene = repo().join("examples/bent-rectangle.json");
    let scene = scene.to_str().unwrap();
    let run = |args: &[&str]| sheetform_within(args, 120);
    assert!(
        run(&["bend", scene, "-o", out_str, "--animate", "3", "--sheet", "a4", "-q"])
            .status
            .success()
    );
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    assert!(out.join("frames/frame-0002.obj").exists() && out.join("sheets/sheet-01.svg").exists());
    assert!(run(&["bend", scene, "-o", out_str, "--animate", "2", "-q"])
        .status
        .success());
    let listed = |out: &Path| -> Vec<String> {
        let r: Value = serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
        let mut names: Vec<String> = r["outputs"]
            .as_array()
            .unwrap()
            .iter()
            .map(|n| n.as_str().unwrap().to_string())
            .collect();
        names.sort();
        names
    };
    let on_disk = |out: &Path| -> Vec<String> {
        let mut names = Vec::new();
        for entry in walk(out) {
            let name = entry.strip_prefix(out).unwrap().to_str().unwrap().to_string();
            if name != "notes.txt" {
                names.push(name);
            }
        }
        names.sort();
        names
    };
    assert!(!out.join("frames/frame-0002.obj").exists(), "a stale frame is left");
    assert!(!out.join("sheets").exists(), "stale sheets are left");
    let mut expected = listed(&out);
    if !expected.contains(&"report.json".to_string()) {
        expected.push("report.json".into());
        expected.sort();
    }
    assert_eq!(on_disk(&out), expected);
    // An inadmissible shape: only the report, saying so.
    // Strong torsion on a wide sheet: the curve of regression crosses it.
    let bad = json!({"outline": [[0, -60], [240, -60], [240, 60], [0, 60]], "regions": [{"flat_start": [0, 0],
        "flat_direction": [1, 0], "curve": {"type": "bezier",
        "control_points": [[0, 0, 0], [80, 10, 0], [150, -20, 60], [170, 10, 120]]}}]});
    let bad_path = dir.path().join("bad.json");
    std::fs::write(&bad_path, bad.to_string()).unwrap();
    let o = run(&["bend", bad_path.to_str().unwrap(), "-o", out_str, "-q"]);
    assert_eq!(o.status.code(), Some(3), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(on_disk(&out), vec!["report.json".to_string()]);
    assert_eq!(std::fs::read_to_string(out.join("notes.txt")).unwrap(), "mine");
}

fn walk(dir: &Path) -> Vec<std::path::PathBuf> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            files.extend(walk(&path));
        } else {
            files.push(path);
        }
    }
    files
}

/// Ctrl-C (SIGINT) stops the run and writes nothing: the previous set stays as it was.
#[cfg(unix)]
#[test]
fn an_interrupted_run_leaves_the_previous_output_set_intact() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let out_str = out.to_str().unwrap();
    let two = repo().join("examples/ffd/two-panels.json");
    assert!(
        sheetform_within(&["ffd", two.to_str().unwrap(), "-o", out_str, "-q"], 120)
            .status
            .success()
    );
    let before: Vec<(std::path::PathBuf, Vec<u8>)> = walk(&out)
        .into_iter()
        .map(|p| (p.clone(), std::fs::read(&p).unwrap()))
        .collect();
    // A 16k-vertex duct: a few seconds of restoration to interrupt.
    let mut fine = example("examples/ffd/duct-100k.json");
    fine["model"]["procedural"]["around"] = json!(160);
    fine["model"]["procedural"]["along"] = json!(100);
    // Every parameter a step (the default): the slower solve leaves time to interrupt.
    fine["solver"] = json!({});
    let scene = dir.path().join("fine.json");
    std::fs::write(&scene, fine.to_string()).unwrap();
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_sheetform"))
        .args(["ffd", scene.to_str().unwrap(), "-o", out_str, "-q"])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(700));
    assert!(std::process::Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap()
        .success());
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(130), "{}", String::from_utf8_lossy(&o.stderr));
    let after: Vec<(std::path::PathBuf, Vec<u8>)> = walk(&out)
        .into_iter()
        .map(|p| (p.clone(), std::fs::read(&p).unwrap()))
        .collect();
    assert_eq!(before, after, "the previous set changed");
}

/// Every file under `dir` with its bytes, sorted: an output set to compare.
fn snapshot(dir: &Path) -> Vec<(std::path::PathBuf, Vec<u8>)> {
    let mut files: Vec<_> = walk(dir)
        .into_iter()
        .map(|p| (p.clone(), std::fs::read(&p).unwrap()))
        .collect();
    files.sort();
    files
}

/// The names in `dir` that a run left behind besides `keep`: staging directories,
/// temporary files.
fn leftovers(dir: &Path, keep: &[&str]) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !keep.contains(&n.as_str()))
        .collect()
}

/// A file-size limit (`ulimit -f`, KiB) between the first file `bend --scale 10` writes
/// (model.obj, 76 KB) and its sixth (the tiled PDF, 136 KB), measured by an unlimited
/// run so the test follows the files' sizes.
#[cfg(target_os = "linux")]
fn limit_between_the_first_file_and_the_pdf() -> u64 {
    let dir = tempfile::tempdir().unwrap();
    let scene = repo().join("examples/bent-rectangle.json");
    let out = dir.path().join("out");
    let o = sheetform_within(
        &[
            "bend",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--scale",
            "10",
            "-q",
        ],
        120,
    );
    assert!(o.status.success());
    let size = |name: &str| std::fs::metadata(out.join(name)).unwrap().len();
    let largest_before_pdf = ["model.obj", "model.glb", "model.stl", "pattern.svg", "pattern.dxf"]
        .map(size)
        .into_iter()
        .max()
        .unwrap();
    let pdf = size("pattern.pdf");
    assert!(
        pdf > largest_before_pdf + 8192,
        "the PDF ({pdf} B) must be the first file over the limit (others up to {largest_before_pdf} B)"
    );
    (largest_before_pdf + pdf) / 2 / 1024
}

/// A bend run whose sixth file (the tiled PDF at `--scale 10`) is over a file-size limit
/// (`ulimit -f`): `ignore_signal` makes the write fail with EFBIG, else SIGXFSZ kills the
/// process in the middle of writing its set.
#[cfg(target_os = "linux")]
fn bend_over_a_file_size_limit(out: &Path, ignore_signal: bool, limit_kib: u64) -> std::process::Output {
    let scene = repo().join("examples/bent-rectangle.json");
    let script = format!(
        "{}ulimit -f {limit_kib}; exec \"$0\" \"$@\"",
        if ignore_signal { "trap '' XFSZ; " } else { "" }
    );
    let output = std::process::Command::new("bash")
        .args(["-c", &script, env!("CARGO_BIN_EXE_sheetform"), "bend"])
        .arg(&scene)
        .arg("-o")
        .arg(out)
        .args(["--scale", "10", "-q"])
        .output()
        .unwrap();
    output
}

/// Issue 19's two faults in the middle of writing a set, over a good set with frames:
/// a write that fails (EFBIG: the file-size limit with its signal ignored) ends with an
/// error naming the file, and a run killed while writing (SIGXFSZ) ends without a word.
/// Both leave the previous set byte for byte; the failed run leaves no temporary file,
/// and what the killed one could not clean up is removed by the next run.
#[cfg(target_os = "linux")]
#[test]
fn a_run_failing_or_killed_mid_write_leaves_the_previous_output_set_intact() {
    use std::os::unix::process::ExitStatusExt;
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let scene = repo().join("examples/bent-rectangle.json");
    let good = sheetform_within(
        &[
            "bend",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--animate",
            "3",
            "-q",
        ],
        120,
    );
    assert!(good.status.success());
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let before = snapshot(&out);

    let limit = limit_between_the_first_file_and_the_pdf();
    let failed = bend_over_a_file_size_limit(&out, true, limit);
    let message = String::from_utf8_lossy(&failed.stderr);
    assert_eq!(failed.status.code(), Some(1), "{message}");
    assert!(
        message.contains("pattern.pdf") && message.contains("too large"),
        "{message}"
    );
    assert_eq!(snapshot(&out), before, "a failed write changed the previous set");
    assert!(
        leftovers(dir.path(), &["out"]).is_empty(),
        "{:?}",
        leftovers(dir.path(), &["out"])
    );
    assert!(leftovers(
        &out,
        &[
            "model.obj",
            "model.glb",
            "model.stl",
            "pattern.svg",
            "pattern.dxf",
            "pattern.pdf",
            "frames",
            "report.json",
            "notes.txt"
        ]
    )
    .is_empty());

    let killed = bend_over_a_file_size_limit(&out, false, limit);
    assert_eq!(
        killed.status.signal(),
        Some(25),
        "not killed by SIGXFSZ: {:?}",
        killed.status
    );
    assert_eq!(snapshot(&out), before, "a kill mid-write changed the previous set");
    let staged = leftovers(dir.path(), &["out"]);
    assert!(
        staged.len() == 1 && staged[0].starts_with(".out.sheetform-"),
        "the killed run's staging directory: {staged:?}"
    );

    // The next run replaces the set, keeps the user's file, and removes the killed
    // run's staging directory.
    let next = sheetform_within(
        &["bend", scene.to_str().unwrap(), "-o", out.to_str().unwrap(), "-q"],
        120,
    );
    assert!(next.status.success());
    assert!(leftovers(dir.path(), &["out"]).is_empty());
    assert!(!out.join("frames").exists());
    assert_eq!(std::fs::read_to_string(out.join("notes.txt")).unwrap(), "mine");
}

/// Text that broke readers or documents: a UTF-8 byte-order mark hid an OBJ's first
/// vertex (every index shifted); a 1 MB token was echoed whole into the error; a PLY
/// parse error quoted the file's first line and the parser's internals; a NUL or escape
/// character in a name made pattern.svg invalid XML and a line break split a DXF group.
#[test]
fn text_inputs_are_read_and_quoted_safely() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let out_str = out.to_str().unwrap();
    let bom = dir.path().join("bom.obj");
    std::fs::write(&bom, b"\xEF\xBB\xBFv 0 0 5\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let o = sheetform_within(&["check", bom.to_str().unwrap(), "-o", out_str, "-q"], 60);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r: Value = serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    assert_eq!(r["vertex_count"], 4);
    // Triangle (0,0,5), (0,0,0), (1,0,0): area 2.5, not the 0.5 of the shifted one.
    assert!(
        (r["area_mm2"].as_f64().unwrap() - 2.5).abs() < 1e-9,
        "{}",
        r["area_mm2"]
    );

    let long = dir.path().join("long.obj");
    std::fs::write(
        &long,
        format!("v {} 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "A".repeat(1_000_000)),
    )
    .unwrap();
    let secret = dir.path().join("secret.ply");
    std::fs::write(&secret, "TOPSECRET first line hunter2\nmore\n").unwrap();
    for (path, expected) in [(&long, "is not a number"), (&secret, "not a valid PLY file")] {
        let o = sheetform_within(&["check", path.to_str().unwrap(), "-o", out_str, "-q"], 60);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1));
        assert!(stderr.contains(expected) && !stderr.contains("hunter2"), "{stderr}");
        assert_readable(&stderr);
    }
    let mut scene = example("examples/bent-rectangle.json");
    scene["A".repeat(1_000_000)] = json!(1);
    let (code, stderr) = run_scene("bend", &scene, &[]);
    assert_eq!(code, 1);
    assert!(stderr.contains("unknown field"), "{}", &stderr[..200.min(stderr.len())]);
    assert_readable(&stderr);

    let mut scene = example("examples/bent-rectangle.json");
    scene["name"] = json!("a\u{0}b\u{1b}c\nv 1 2 3");
    scene["regions"][0]["name"] = json!("curl\nEOF\r\n0\u{0}");
    let path = dir.path().join("names.json");
    std::fs::write(&path, scene.to_string()).unwrap();
    let o = sheetform_within(&["bend", path.to_str().unwrap(), "-o", out_str, "-q"], 60);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let svg = std::fs::read_to_string(out.join("pattern.svg")).unwrap();
    assert!(!svg
        .chars()
        .any(|c| c.is_control() && c != '\n' && c != '\t' && c != '\r'));
    let obj = std::fs::read_to_string(out.join("model.obj")).unwrap();
    assert!(
        !obj.lines().any(|l| l.starts_with("v 1 2 3")),
        "the name injected a vertex"
    );
    let dxf = std::fs::read_to_string(out.join("pattern.dxf")).unwrap();
    assert!(!dxf.contains("EOF\r\n0\r\n\u{0}") && !dxf.contains('\u{0}'));
}

/// Pattern options near the floating-point range: `--kerf 1e308` and `--thickness 1e308`
/// were refused with the value in 309 digits; `--sheet-gap` had no bound (at 1e308 the
/// piece that then fitted nowhere was reported in 300-digit sizes); the page-cap error
/// of `--scale 1e300` counted "18446744073709551615 or more" pages.
#[test]
fn pattern_options_are_bounded_and_reported_in_short_numbers() {
    let scene = example("examples/bent-rectangle.json");
    for (extra, option, expected) in [
        (vec!["--kerf", "1e308"], "kerf_mm", "got 1e308"),
        (vec!["--seam-allowance", "1e308"], "seam_allowance_mm", "got 1e308"),
        (vec!["--thickness", "1e308"], "thickness_mm", "got 1e308"),
        (vec!["--tab-width=-1e308", "--tabs", "one"], "tab width", "got -1e308"),
        (
            vec!["--sheet", "a4", "--sheet-gap", "1e308"],
            "sheet_gap",
            "between 0 and 1000 mm",
        ),
        (
            vec!["--sheet", "a4", "--sheet-gap", "1001"],
            "sheet_gap",
            "between 0 and 1000 mm",
        ),
        (vec!["--scale", "1e300"], "max_pages", "(over a million)"),
    ] {
        let (code, stderr) = run_scene("bend", &scene, &extra);
        assert_eq!(code, 1, "{extra:?}: {stderr}");
        assert!(
            stderr.contains(&format!("`{option}`")) && stderr.contains(expected),
            "{extra:?}: {stderr}"
        );
        assert!(!stderr.contains("18446744073709551615"), "{stderr}");
        assert_readable(&stderr);
    }
    // The largest gap is allowed (then the sheet must be large enough).
    let (code, stderr) = run_scene("bend", &scene, &["--sheet", "3000x3000", "--sheet-gap", "1000"]);
    assert_eq!(code, 0, "{stderr}");
}

/// An OFF face with a negative vertex count (`-1 0 1 2`) panicked (`-1 as usize`); now
/// an error naming the file's line.
#[test]
fn an_off_face_with_a_negative_vertex_count_is_an_error_naming_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("negative.off");
    std::fs::write(&mesh, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n-1 0 1 2\n").unwrap();
    let out = dir.path().join("out");
    let o = sheetform_within(&["check", mesh.to_str().unwrap(), "-o", out.to_str().unwrap()], 60);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("negative.off:6"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_readable(&stderr);
    assert!(!out.join("report.json").exists());
}

/// `tools/fuzz.sh` piped cargo fuzz into `grep … || true`, so CI passed when the fuzz
/// crate did not build or libFuzzer never ran. Run here with stand-ins for `cargo` and
/// `cargo-fuzz`: a build failure and a run that ends without libFuzzer's "Done N runs"
/// fail the script; a run that reaches its time limit passes.
#[cfg(unix)]
#[test]
fn the_fuzz_smoke_fails_when_cargo_fuzz_fails() {
    use std::os::unix::fs::PermissionsExt;
    let run = |cargo_body: &str| {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path();
        for sub in ["tools", "fuzz", "bin"] {
            std::fs::create_dir_all(root.join(sub)).unwrap();
        }
        std::fs::copy(repo().join("tools/fuzz.sh"), root.join("tools/fuzz.sh")).unwrap();
        for (name, body) in [("cargo", cargo_body), ("cargo-fuzz", "exit 0")] {
            let path = root.join("bin").join(name);
            std::fs::write(&path, format!("#!/usr/bin/env bash\n{body}\n")).unwrap();
            std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
        }
        let path = format!("{}:{}", root.join("bin").display(), std::env::var("PATH").unwrap());
        let o = std::process::Command::new("bash")
            .arg(root.join("tools/fuzz.sh"))
            .args(["mesh_check", "5"])
            .env("PATH", path)
            .output()
            .unwrap();
        (o.status.code(), String::from_utf8_lossy(&o.stderr).into_owned())
    };
    let (code, stderr) = run("echo 'error: could not compile `sheetform-fuzz`' >&2; exit 101");
    assert_eq!(code, Some(1), "{stderr}");
    assert!(
        stderr.contains("could not compile") && stderr.contains("exit status 101"),
        "{stderr}"
    );
    let (code, stderr) = run("echo 'INFO: Seed: 1'; exit 0");
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("Done N runs"), "{stderr}");
    let (code, stderr) = run(
        "echo '#1234\tDONE   cov: 10 ft: 20 corp: 3/30b exec/s: 246 rss: 40Mb' >&2; \
         echo 'Done 1234 runs in 5 second(s)' >&2; exit 0",
    );
    assert_eq!(code, Some(0), "{stderr}");
}

/// Issue 35, panics by class, each now an error or a result: a flat direction with huge
/// (or tiny) components, read as the direction it is (the same direction scaled gives
/// the same bend); standard output that cannot be written (a full disk: `println!`
/// panicked, exit 101) is an output error said on stderr.
#[test]
fn huge_directions_and_unwritable_output_are_not_panics() {
    let mut reference = example("examples/arc-band.json");
    reference["regions"][0]["flat_direction"] = json!([1, 0]);
    let dir = tempfile::tempdir().unwrap();
    let run = |scene: &Value, name: &str| {
        let path = dir.path().join(format!("{name}.json"));
        std::fs::write(&path, scene.to_string()).unwrap();
        let out = dir.path().join(name);
        let o = sheetform_within(
            &["bend", path.to_str().unwrap(), "-o", out.to_str().unwrap(), "-q"],
            120,
        );
        (o.status.code(), String::from_utf8_lossy(&o.stderr).into_owned(), out)
    };
    let (code, stderr, plain) = run(&reference, "plain");
    assert_eq!(code, Some(0), "{stderr}");
    let model = |out: &Path| std::fs::read_to_string(out.join("model.obj")).unwrap();
    for (k, direction) in [json!([2e300, 0]), json!([1e-310, 0]), json!([5e-324, 0])]
        .into_iter()
        .enumerate()
    {
        let mut scene = reference.clone();
        scene["regions"][0]["flat_direction"] = direction.clone();
        let (code, stderr, out) = run(&scene, &format!("scaled-{k}"));
        assert_eq!(code, Some(0), "{direction}: {stderr}");
        assert_eq!(model(&out), model(&plain), "{direction} is the direction (1, 0)");
    }
    for (k, direction) in [json!([0, 1e300]), json!([1e300, 1e300]), json!([-1e308, 1e308])]
        .into_iter()
        .enumerate()
    {
        let mut scene = reference.clone();
        scene["regions"][0]["flat_direction"] = direction.clone();
        let (code, stderr, _) = run(&scene, &format!("turned-{k}"));
        assert!(
            matches!(code, Some(0) | Some(1) | Some(3)),
            "{direction}: {code:?} {stderr}"
        );
        assert!(!stderr.contains("panicked"), "{direction}: {stderr}");
        assert_readable(&stderr);
    }
    // Standard output on a full disk.
    let full = std::fs::OpenOptions::new().write(true).open("/dev/full").unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_sheetform"))
        .args(["schema", "report"])
        .stdout(full)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("could not write to standard output") && !stderr.contains("panicked"),
        "{stderr}"
    );
}

/// Issue 35, output directories, as a user meets them: a read-only `-o` directory is
/// refused naming it (nothing changed, no hidden copy left beside it); another tool's
/// `report.json` listing `outputs` deletes none of its files; a run from inside the
/// output directory (`-o .`) leaves the shell's directory live; a kerf or seam allowance
/// that would close a hole is refused naming the option and the hole.
#[test]
fn output_directories_keep_what_sheetform_did_not_write() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let out_str = out.to_str().unwrap();
    let scene = repo().join("examples/bent-rectangle.json");
    let scene = scene.to_str().unwrap();
    // Another tool's report with an outputs list: its files stay.
    std::fs::create_dir(&out).unwrap();
    std::fs::write(out.join("theirs.csv"), "1,2").unwrap();
    std::fs::write(out.join("report.json"), r#"{"outputs": ["theirs.csv"]}"#).unwrap();
    assert!(sheetform(&["bend", scene, "-o", out_str, "-q"]).status.success());
    assert_eq!(std::fs::read_to_string(out.join("theirs.csv")).unwrap(), "1,2");
    // Read-only: refused, nothing changed.
    let before = snapshot(&out);
    std::fs::set_permissions(&out, std::fs::Permissions::from_mode(0o555)).unwrap();
    let o = sheetform(&["bend", scene, "-o", out_str, "-q", "--animate", "2"]);
    std::fs::set_permissions(&out, std::fs::Permissions::from_mode(0o755)).unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_ne!(o.status.code(), Some(0));
    assert!(stderr.contains(out_str) && stderr.contains("read-only"), "{stderr}");
    assert_eq!(snapshot(&out), before);
    let siblings: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(siblings, vec![std::ffi::OsString::from("out")]);
    // `-o .` from inside: the directory stays the same one.
    let inode = |p: &Path| std::os::unix::fs::MetadataExt::ino(&std::fs::metadata(p).unwrap());
    let before = inode(&out);
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_sheetform"))
        .args(["bend", scene, "-o", ".", "-q"])
        .current_dir(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(inode(&out), before, "-o . replaced the directory the shell is in");
    // A kerf or allowance wider than a hole.
    let hole = repo().join("examples/sheet-with-hole.json");
    for (option, value, key) in [
        ("--kerf", "60", "kerf_mm"),
        ("--seam-allowance", "30", "seam_allowance_mm"),
    ] {
        let o = sheetform(&["bend", hole.to_str().unwrap(), "-o", out_str, "-q", option, value]);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{option}: {stderr}");
        assert!(stderr.contains(key) && stderr.contains("closes the hole"), "{stderr}");
    }
    assert_eq!(std::fs::read_to_string(out.join("theirs.csv")).unwrap(), "1,2");
}

/// Issue 35, messages: a scene that serde refuses names the field's path (into lists,
/// objects and tagged curves) and what is accepted, with the line and column after it, in
/// every mode (it named only "(line 3, column 19)").
#[test]
fn serde_errors_name_the_field_and_what_is_accepted() {
    let cases: Vec<(&str, Value, &str, &str)> = {
        let mut bend = example("examples/bent-rectangle.json");
        bend["units"] = json!("furlong");
        let mut curve = example("examples/bent-rectangle.json");
        curve["regions"][0]["curve"]["type"] = json!("spline");
        let mut point = example("examples/bent-rectangle.json");
        point["regions"][0]["flat_start"][1] = json!("x");
        let mut unknown = example("examples/bent-rectangle.json");
        unknown["regions"][0]["flat_stat"] = json!([0, 0]);
        let mut slit = example("examples/slit/bench.json");
        slit["sheet"]["strip_count"] = json!(2.5);
        let mut ffd = example("examples/ffd/duct.json");
        ffd["model"]["procedural"]["kind"] = json!("pipe");
        let mut photo = example("examples/photo/tube.json");
        photo["curves"][1]["kind"] = json!("edge");
        vec![
            ("bend", bend, "units", "expected one of `mm`, `cm`, `m`, `in`"),
            (
                "bend",
                curve,
                "regions[0].curve.type",
                "expected one of `bezier`, `bspline`, `helix`",
            ),
            ("bend", point, "regions[0].flat_start[1]", "expected f64"),
            (
                "bend",
                unknown,
                "regions[0].flat_stat",
                "expected one of `name`, `flat_start`",
            ),
            ("slit", slit, "sheet.strip_count", "expected usize"),
            ("ffd", ffd, "model.procedural.kind", "expected one of `duct`"),
            ("photo", photo, "curves[1].kind", "expected `silhouette` or `boundary`"),
        ]
    };
    for (command, scene, field, accepted) in cases {
        let (code, stderr) = run_scene(command, &scene, &[]);
        assert_eq!(code, 1, "{stderr}");
        assert!(
            stderr.contains(&format!("field `{field}`: ")) && stderr.contains(accepted),
            "{command}: expected `{field}` and {accepted:?} in: {stderr}"
        );
        assert!(
            stderr.contains("(line 1, column "),
            "the line and column kept: {stderr}"
        );
        assert_readable(&stderr);
    }
}

/// A run of `digits` or more digits in `message`: a number printed whole (`1e308` is 309
/// digits in Rust's `{}` and `{:.6}`).
fn has_long_number(message: &str, digits: usize) -> bool {
    message
        .split(|c: char| !c.is_ascii_digit())
        .any(|run| run.len() >= digits)
}

/// Issue 35, messages: every number in a message is short, whatever the input; a value of
/// 1e308 in a coordinate, a length, a weight or a tolerance was printed in 309 digits
/// (outline crossings, the flat segment leaving the sheet, slit widths, points of a photo's
/// curves, FFD weights and tolerances, a helix radius, an anchor out of reach).
#[test]
fn numbers_in_messages_are_short() {
    // (command, example, [(JSON pointer, value)])
    type Case<'a> = (&'a str, &'a str, Vec<(&'a str, f64)>);
    let cases: Vec<Case> = vec![
        (
            "bend",
            "examples/bent-rectangle.json",
            vec![
                ("/outline/1/1", 1e308),
                ("/outline/2/0", -1e308),
                ("/regions/0/flat_start/0", 1e308),
                ("/regions/0/flat_start/1", -1e308),
            ],
        ),
        ("bend", "examples/tube.json", vec![("/regions/0/curve/radius", -1e308)]),
        (
            "slit",
            "examples/slit/bench.json",
            vec![("/sheet/l4_slit_width", 1e308), ("/mould/sheet_thickness", 1e308)],
        ),
        (
            "slit",
            "examples/slit/monument.json",
            vec![("/anchors/0/position/0", 1e308)],
        ),
        (
            "ffd",
            "examples/ffd/duct.json",
            vec![("/solver/tolerance_rad", -1e308), ("/lattice/margin", -1e308)],
        ),
        (
            "photo",
            "examples/photo/tube.json",
            vec![
                ("/curves/0/control_points/7/1", 1e308),
                ("/symmetry/frame/0/1/0", -1e308),
                ("/true_size/length", -1e308),
                ("/analysis/snap_distance_px", 1e308),
            ],
        ),
    ];
    for (command, path, settings) in cases {
        for (pointer, value) in settings {
            let mut scene = example(path);
            let (parent, key) = pointer.rsplit_once('/').unwrap();
            if scene.pointer(parent).is_none() {
                // An optional object the example leaves out.
                scene[parent.trim_start_matches('/')] = json!({});
            }
            match scene.pointer_mut(parent).unwrap() {
                Value::Array(items) => items[key.parse::<usize>().unwrap()] = json!(value),
                Value::Object(fields) => {
                    fields.insert(key.to_string(), json!(value));
                }
                _ => panic!("{path}{pointer}"),
            }
            let (code, stderr) = run_scene(command, &scene, &[]);
            assert_eq!(code, 1, "{path}{pointer} = {value:e}: {stderr}");
            assert!(!has_long_number(&stderr, 17), "{path}{pointer} = {value:e}: {stderr}");
            assert_readable(&stderr);
        }
    }
    // The FFD's weight edit, through its own list.
    let mut scene = example("examples/ffd/duct.json");
    scene["deformations"][0]["edits"] = json!([{"weight": {"points": [[0, 0, 0]], "value": -1e308}}]);
    let (code, stderr) = run_scene("ffd", &scene, &[]);
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("-1e308") && !has_long_number(&stderr, 17), "{stderr}");
}

/// Issue 35: the FFD's weights had no upper bound, as the slit weights had none: a
/// bending weight of 1e300 was reported as a singular system, a lattice weight of 1e300
/// as collapsed panels, and a position weight of 1e300 ended `ok` (exit 0). Every weight
/// an FFD scene sets is bounded at 1e6, as the slit and photo weights, and a weight past
/// it is refused (exit 1) naming the field, its value and the bounds.
#[test]
fn ffd_weights_past_their_bound_are_refused_naming_field_value_and_bounds() {
    let duct = example("examples/ffd/duct.json");
    let mut cases: Vec<(Value, String)> = Vec::new();
    for key in ["position_weight", "bending_weight", "stall_bending_weight"] {
        let mut s = duct.clone();
        s["solver"] = json!({ key: 1e300 });
        cases.push((s, format!("solver.{key}")));
    }
    let mut s = duct.clone();
    let mut weights = vec![1.0; 64];
    weights[7] = 1e300;
    s["lattice"]["weights"] = json!(weights);
    cases.push((s, "lattice.weights[7]".into()));
    let mut s = duct.clone();
    s["deformations"][0]["edits"] = json!([{"weight": {"points": {"k": [3, 3]}, "value": 1e300}}]);
    cases.push((s, "deformations[0].edits[0].weight.value".into()));
    for (scene, field) in cases {
        let (code, stderr) = run_scene("ffd", &scene, &[]);
        assert_eq!(code, 1, "{field} = 1e300: {stderr}");
        assert!(
            stderr.contains(&format!("`{field}`: must be ")) && stderr.contains("to 1e6, got 1e300"),
            "{field}: {stderr}"
        );
        assert_readable(&stderr);
    }
}

/// Issue 35: a slit scene's `mould.sheet_thickness` of 1e-320 (a subnormal) lay between 0
/// and half a strip, passed, and was refused by the mould's triangulation ("a coordinate
/// is nearer to zero than …") without naming the field. It is refused naming
/// `mould.sheet_thickness` and its bounds, nothing written.
#[test]
fn a_subnormal_sheet_thickness_is_refused_naming_the_field() {
    let mut scene = example("examples/slit/bench.json");
    scene["mould"] = json!({"sheet_thickness": 1e-320});
    let (code, stderr) = run_scene("slit", &scene, &[]);
    assert_eq!(code, 1, "{stderr}");
    assert!(
        stderr.contains("`mould.sheet_thickness`: must be 0 (a sheet of no thickness) or from a millionth")
            && stderr.contains(") to half the strip width (43.125), got 9.99989e-321"),
        "{stderr}"
    );
    assert!(!stderr.contains("triangulat"), "{stderr}");
    assert_readable(&stderr);
}

/// Issue 35, messages: a value refused for crossing a bound is printed with the digits
/// that tell it from the bound ("must be between 0 and 100, got 100" for 100.0001), in
/// pattern options, scene fields and bounds computed from the image.
#[test]
fn refused_values_are_told_apart_from_their_bounds() {
    let bend = example("examples/bent-rectangle.json");
    for (option, value, field) in [
        ("--kerf", "100.0001", "kerf_mm"),
        ("--seam-allowance", "100.00000001", "seam_allowance_mm"),
        ("--thickness", "100.0000001", "thickness_mm"),
    ] {
        let (code, stderr) = run_scene("bend", &bend, &[option, value]);
        assert_eq!(code, 1, "{stderr}");
        assert!(
            stderr.contains(field) && stderr.contains(&format!("got {value}")),
            "{stderr}"
        );
    }
    let mut ffd = example("examples/ffd/duct.json");
    ffd["lattice"]["margin"] = json!(10.000_000_1);
    let mut slit = example("examples/slit/bench.json");
    slit["weights"] = json!({"smooth": 1_000_000.5});
    // The tube's photo is 480 × 360 px: ruling spacings up to a third of its diagonal.
    let mut photo = example("examples/photo/tube.json");
    photo["analysis"] = json!({"ruling_spacing_px": 200.000_000_1});
    for (command, scene, field, shown) in [
        ("ffd", ffd, "lattice.margin", "got 10.0000001"),
        ("slit", slit, "weights.smooth", "got 1.0000005e6"),
        (
            "photo",
            photo,
            "analysis.ruling_spacing_px",
            "200 px for this image (got 200.0000001)",
        ),
    ] {
        let (code, stderr) = run_scene(command, &scene, &[]);
        assert_eq!(code, 1, "{stderr}");
        assert!(
            stderr.contains(&format!("`{field}`")) && stderr.contains(shown),
            "{command}: expected {shown:?} in: {stderr}"
        );
    }
}

/// Issue 35, messages: an image that does not decode (a PNG signature followed by garbage,
/// a PNG or JPEG cut off, a damaged chunk) was accepted with status ok and embedded in the
/// GLB and the overlay. It is decoded to its end at load and refused naming the scene
/// field, the file and what is wrong, nothing written; a photo is called a photo, a bend
/// scene's image a texture.
#[test]
fn undecodable_images_are_refused_at_load() {
    let png = std::fs::read(repo().join("examples/photo/tube.png")).unwrap();
    let mut damaged = png.clone();
    let idat = damaged.windows(4).position(|w| w == b"IDAT").unwrap();
    damaged[idat + 40] ^= 0x55;
    let broken: Vec<(&str, Vec<u8>)> = vec![
        ("a PNG signature then garbage", [&png[..8], &[b'x'; 500][..]].concat()),
        ("a PNG header then garbage", [&png[..33], &[0x5a; 500][..]].concat()),
        ("a PNG cut in half", png[..png.len() / 2].to_vec()),
        ("a PNG without its end", png[..png.len() - 12].to_vec()),
        ("a PNG with damaged data", damaged),
    ];
    let run = |dir: &Path, args: &[&str]| {
        let out = dir.join("out");
        let mut all = args.to_vec();
        all.extend(["-o", out.to_str().unwrap(), "-q"]);
        let o = sheetform_within(&all, 120);
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
            out.exists(),
        )
    };
    for (what, bytes) in &broken {
        // A photo, named by an annotation and by a drawing.
        let dir = tempfile::tempdir().unwrap();
        std::fs::copy(repo().join("examples/photo/tube.json"), dir.path().join("tube.json")).unwrap();
        std::fs::write(dir.path().join("tube.png"), bytes).unwrap();
        let (code, stderr, written) = run(dir.path(), &["photo", dir.path().join("tube.json").to_str().unwrap()]);
        assert_eq!(code, Some(1), "{what}: {stderr}");
        assert!(
            stderr.contains("image.path: `tube.png`: the photo cannot be used: the PNG file is"),
            "{what}: {stderr}"
        );
        assert!(!stderr.contains("texture") && !written, "{what}: {stderr}");
        assert_readable(&stderr);
        std::fs::copy(repo().join("examples/photo/coffee-cup.svg"), dir.path().join("cup.svg")).unwrap();
        std::fs::write(dir.path().join("coffee.png"), bytes).unwrap();
        let (code, stderr, _) = run(dir.path(), &["photo", dir.path().join("cup.svg").to_str().unwrap()]);
        assert_eq!(code, Some(1), "{what}: {stderr}");
        assert!(
            stderr.contains("`coffee.png`: the photo cannot be used"),
            "{what}: {stderr}"
        );
        // A bend scene's texture.
        let mut scene = example("examples/textured-sheet.json");
        scene["texture"] = json!("grid.png");
        std::fs::write(dir.path().join("grid.png"), bytes).unwrap();
        std::fs::write(dir.path().join("sheet.json"), scene.to_string()).unwrap();
        let (code, stderr, written) = run(dir.path(), &["bend", dir.path().join("sheet.json").to_str().unwrap()]);
        assert_eq!(code, Some(1), "{what}: {stderr}");
        assert!(
            stderr.contains("texture: `grid.png`: the texture cannot be used: the PNG file is") && !written,
            "{what}: {stderr}"
        );
    }
}

/// Issue 35, messages: `flatten` of a mesh whose edge lengths do not fix its flat layout
/// said "the layout solver failed: factorisation failed (the linear system has no unique
/// solution (singular, or not positive definite)): the mesh is not rigid in the plane".
/// A needle-thin triangle does that (here one on the border of a curved cap, its third
/// corner 2.5e-8 mm off a 25 mm edge): the user is told what is wrong with the mesh,
/// which triangle and where, and what to do, in no solver's words.
#[test]
fn a_mesh_that_cannot_be_laid_flat_is_explained_in_its_own_terms() {
    let n = 4;
    let mut positions: Vec<[f64; 3]> = Vec::new();
    for i in 0..=n {
        for j in 0..=n {
            let (x, y) = (i as f64 / n as f64 - 0.5, j as f64 / n as f64 - 0.5);
            positions.push([x * 100.0, y * 100.0, 30.0 * (1.0 - x * x - y * y)]);
        }
    }
    let id = |i: usize, j: usize| i * (n + 1) + j;
    let mut faces = Vec::new();
    for i in 0..n {
        for j in 0..n {
            faces.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            faces.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    // The needle, on the border edge from (-25, -50) to (-50, -50).
    let (a, b) = (id(1, 0), id(0, 0));
    let middle: Vec<f64> = (0..3).map(|c| 0.5 * (positions[a][c] + positions[b][c])).collect();
    positions.push([middle[0], middle[1] - 2.5e-8, middle[2]]);
    faces.push([a, b, positions.len() - 1]);
    let mut obj = String::new();
    for p in &positions {
        obj.push_str(&format!("v {:?} {:?} {:?}\n", p[0], p[1], p[2]));
    }
    for f in &faces {
        obj.push_str(&format!("f {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1));
    }
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("cap.obj");
    std::fs::write(&mesh, obj).unwrap();
    let out = dir.path().join("out");
    let o = sheetform_within(
        &[
            "flatten",
            mesh.to_str().unwrap(),
            "--charts",
            "never",
            "-o",
            out.to_str().unwrap(),
            "-q",
        ],
        120,
    );
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("sheetform: the mesh cannot be laid flat as it is: it has needle-thin triangles")
            && stderr.contains("the thinnest, face 32 near (-37.5, -50, ")
            && stderr.contains("remove such triangles"),
        "{stderr}"
    );
    for internal in ["solver", "factoris", "linear system", "singular", "rigid"] {
        assert!(!stderr.contains(internal), "`{internal}` in: {stderr}");
    }
    assert!(!out.exists(), "{stderr}");
    assert_readable(&stderr);
}

/// Issue 35, messages: a piece that cannot be unfolded is explained in the terms of the
/// command that ran. An FFD panel that is not disk-like (a closed box) was told to "cut it
/// into charts first", the `flatten` command's advice: it is told to split the panel.
#[test]
fn unfolding_advice_fits_the_command() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(repo().join("examples/meshes/gift-box.obj"), dir.path().join("box.obj")).unwrap();
    let scene = json!({"name": "box", "units": "mm", "model": {"mesh": "box.obj"},
        "deformations": [{"name": "d", "edits": [{"move": {"points": {"k": [3, 3]}, "by": [5, 0, 0]}}]}]});
    let path = dir.path().join("box.json");
    std::fs::write(&path, scene.to_string()).unwrap();
    let out = dir.path().join("out");
    let o = sheetform_within(&["ffd", path.to_str().unwrap(), "-o", out.to_str().unwrap(), "-q"], 120);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("panel `") && stderr.contains("split it along a seam"),
        "{stderr}"
    );
    assert!(
        !stderr.contains("charts") && !stderr.contains("--"),
        "flatten's advice: {stderr}"
    );
}

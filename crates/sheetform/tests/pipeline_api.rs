//! The pipeline API every front end stands on: typed scenes in, a context that confines
//! the files a scene may read, reports progress, cancels and picks the outputs; the
//! outcome and the kind of every error decided in the library.

use sheetform::bend::BendScene;
use sheetform::pipeline::{
    run_bend, run_check, AssetResolver, BendRunOptions, CheckOptions, ErrorKind, Outcome, OutputSet, PipelineError,
    RunContext,
};
use sheetform::report::Status;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

fn scene(name: &str) -> BendScene {
    BendScene::from_json(&std::fs::read_to_string(examples().join(name)).unwrap()).unwrap()
}

fn asset_error(e: &PipelineError) -> (String, String) {
    match e {
        PipelineError::Asset { field, message, .. } => (field.clone(), message.clone()),
        other => panic!("expected an asset error, got {other}"),
    }
}

#[test]
fn assets_are_confined_to_the_scene_directory() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path().join("project");
    std::fs::create_dir_all(root.join("textures")).unwrap();
    std::fs::write(root.join("textures/ok.png"), b"inside").unwrap();
    std::fs::write(dir.path().join("secret.txt"), b"outside").unwrap();
    let assets = AssetResolver::new(&root);
    assert_eq!(assets.read("textures/ok.png", "texture").unwrap(), b"inside");
    // `..` that stays inside is fine.
    assert_eq!(
        assets.read("textures/../textures/ok.png", "texture").unwrap(),
        b"inside"
    );
    // Leaving the root, by `..`, by an absolute path or through a link, is refused and
    // the error names the scene field.
    let e = assets.read("../secret.txt", "texture").unwrap_err();
    assert_eq!(asset_error(&e).0, "texture");
    assert!(asset_error(&e).1.contains("outside"), "{e}");
    assert_eq!(e.kind(), ErrorKind::InvalidInput);
    let absolute = dir.path().join("secret.txt");
    let e = assets.read(absolute.to_str().unwrap(), "scan.points").unwrap_err();
    assert!(asset_error(&e).1.contains("absolute"), "{e}");
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink(dir.path().join("secret.txt"), root.join("link.txt")).unwrap();
        let e = assets.read("link.txt", "model").unwrap_err();
        assert!(asset_error(&e).1.contains("outside"), "{e}");
        // A device (it would never end) is not a regular file, even inside the root.
        std::os::unix::fs::symlink("/dev/zero", root.join("zero.png")).unwrap();
        let e = assets.read("zero.png", "texture").unwrap_err();
        assert!(e.to_string().contains("zero.png"), "{e}");
    }
    // A directory is not a file; a missing file says so.
    let e = assets.read("textures", "texture").unwrap_err();
    assert!(asset_error(&e).1.contains("regular file"), "{e}");
    let e = assets.read("missing.png", "texture").unwrap_err();
    assert!(asset_error(&e).1.contains("cannot open"), "{e}");
    // The size bound holds before anything is read.
    let small = AssetResolver::new(&root).with_max_bytes(3);
    let e = small.read("textures/ok.png", "texture").unwrap_err();
    assert!(asset_error(&e).1.contains("more than"), "{e}");
}

#[test]
fn a_textured_scene_reads_its_texture_through_the_context() {
    let textured = scene("textured-sheet.json");
    let run = run_bend(&textured, &BendRunOptions::default(), &RunContext::new(examples())).unwrap();
    assert_eq!(run.outcome, Outcome::Ok);
    // From another directory the texture is not there (and nothing outside is read).
    let dir = tempfile::tempdir().unwrap();
    let e = run_bend(&textured, &BendRunOptions::default(), &RunContext::new(dir.path())).unwrap_err();
    assert_eq!(asset_error(&e).0, "texture");
}

#[test]
fn a_preview_renders_the_model_and_the_pattern_only() {
    let desk = scene("desk.json");
    let options = BendRunOptions {
        animate_frames: 3,
        ..Default::default()
    };
    let full = run_bend(&desk, &options, &RunContext::new(examples())).unwrap();
    let names = |files: &[(String, Vec<u8>)]| files.iter().map(|f| f.0.clone()).collect::<Vec<_>>();
    let all = names(&full.files);
    for expected in [
        "model.obj",
        "model.glb",
        "model.stl",
        "pattern.svg",
        "pattern.dxf",
        "pattern.pdf",
    ] {
        assert!(all.contains(&expected.to_string()), "{all:?}");
    }
    assert_eq!(all.iter().filter(|n| n.starts_with("frames/")).count(), 3);
    let preview = run_bend(
        &desk,
        &options,
        &RunContext::new(examples()).with_outputs(OutputSet::Preview),
    )
    .unwrap();
    assert_eq!(names(&preview.files), vec!["model.glb", "pattern.svg"]);
    assert_eq!(preview.report.outputs, vec!["model.glb", "pattern.svg", "report.json"]);
    // The same model either way.
    assert_eq!(preview.sheet.mesh.positions, full.sheet.mesh.positions);
}

#[test]
fn progress_is_reported_and_a_cancelled_run_stops() {
    let desk = scene("desk.json");
    let stages = std::sync::Mutex::new(Vec::new());
    let record = |stage: &str, fraction: f64| stages.lock().unwrap().push((stage.to_string(), fraction));
    let context = RunContext::new(examples()).with_progress(&record);
    run_bend(&desk, &BendRunOptions::default(), &context).unwrap();
    let stages = stages.into_inner().unwrap();
    assert_eq!(stages.first().unwrap().0, "reading scene");
    assert_eq!(stages.last().unwrap(), &("done".to_string(), 1.0));
    assert!(stages.windows(2).all(|w| w[0].1 <= w[1].1), "{stages:?}");
    let cancel = AtomicBool::new(true);
    let e = run_bend(
        &desk,
        &BendRunOptions::default(),
        &RunContext::new(examples()).with_cancel(&cancel),
    )
    .unwrap_err();
    assert!(matches!(e, PipelineError::Cancelled));
    assert_eq!(e.kind(), ErrorKind::Cancelled);
    assert_eq!(e.kind().exit_code(), 130);
}

#[test]
fn an_inadmissible_shape_is_an_error_that_carries_its_report() {
    // Strong torsion on a wide sheet: the curve of regression crosses it (cm: the report
    // converts to mm).
    let twisted = BendScene::from_json(
        r#"{"units":"cm","outline":[[0,-6],[24,-6],[24,6],[0,6]],"regions":[{"flat_start":[0,0],"flat_direction":[1,0],
            "curve":{"type":"bezier","control_points":[[0,0,0],[8,1,0],[15,-2,6],[17,1,12]]}}]}"#,
    )
    .unwrap();
    let e = run_bend(&twisted, &BendRunOptions::default(), &RunContext::new(examples())).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::Inadmissible);
    assert_eq!(e.kind().exit_code(), 3);
    let report = e.report().expect("the report saying where");
    assert_eq!(report.status, Status::Inadmissible);
    assert_eq!(report.admissible, Some(false));
    let entry = report.regression_entry.as_ref().unwrap();
    let x = entry.flat_point_mm[0];
    assert!((0.0..=240.0 + 1e-6).contains(&x), "in mm on the 240 mm sheet: {x}");
}

#[test]
fn a_mesh_is_checked_from_memory() {
    // A half cylinder built in memory (no file at all): developable.
    let mesh = sheetform::mesh::TriangleMesh::grid(12, 4, |u, v| {
        let a = std::f64::consts::PI * u;
        [30.0 * a.cos(), 30.0 * a.sin(), 50.0 * v]
    });
    let run = run_check(mesh, &CheckOptions::default(), &RunContext::new(".")).unwrap();
    assert_eq!(run.report.status, Status::Developable);
    assert_eq!(run.outcome, Outcome::Ok);
    assert_eq!(run.report.input, None);
}

/// report.json is typed both ways: what a run writes reads back into a `Report` that
/// writes the same JSON (every command's section, the enums as their words), and the
/// schema names the enums' words.
#[test]
fn reports_read_back_into_the_same_typed_report() {
    use sheetform::pipeline::{run_photo, PhotoInput, PhotoRunOptions};
    use sheetform::report::Report;
    let bend = run_bend(
        &scene("desk.json"),
        &BendRunOptions::default(),
        &RunContext::new(examples()),
    )
    .unwrap();
    let photo_dir = examples().join("photo");
    let tube = PhotoInput::from_text(&std::fs::read_to_string(photo_dir.join("tube.json")).unwrap()).unwrap();
    let photo = run_photo(&tube, &PhotoRunOptions::default(), &RunContext::new(&photo_dir)).unwrap();
    let mesh = sheetform::mesh::TriangleMesh::grid(6, 3, |u, v| [40.0 * u, 20.0 * v, 5.0 * (u * 3.0).sin()]);
    let check = run_check(mesh, &CheckOptions::default(), &RunContext::new(".")).unwrap();
    for report in [&bend.report, &photo.report, &check.report] {
        let json = serde_json::to_string(report).unwrap();
        let back: Report = serde_json::from_str(&json).unwrap_or_else(|e| panic!("{e}: {json}"));
        // Exactly what was written (report.json leaves out per-vertex lists such as the
        // topology's boundary flags, so compare what it holds).
        assert_eq!(
            serde_json::to_value(&back).unwrap(),
            serde_json::to_value(report).unwrap()
        );
    }
    let value = serde_json::to_value(&photo.report).unwrap();
    assert_eq!(value["status"], "ok");
    assert_eq!(value["command"], "photo");
    assert_eq!(value["model_unit"], "mm");
    assert_eq!(value["charts"][0]["method"], "exact");
    let schema = Report::json_schema();
    let statuses: Vec<&str> = schema["$defs"]["Status"]["oneOf"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v["const"].as_str().unwrap())
        .collect();
    assert!(
        statuses.contains(&"depth undetermined") && statuses.contains(&"inadmissible"),
        "{statuses:?}"
    );
}

/// Issue 35: the slit solve and the cutting into charts looked at no cancel flag, so an
/// abandoned editor request held its solve slot until it finished (a slit scene of 8 × 256
/// quads some 40 s, charts of a large noisy sheet up to 45 s). A flag set from another
/// thread while they run now stops both, with `Cancelled`.
#[test]
fn slit_solves_and_chart_cutting_stop_when_cancelled() {
    use sheetform::pipeline::{run_flatten, run_slit, ChartMode, FlattenOptions, SlitRunOptions};
    use std::sync::atomic::Ordering;
    let stop_after = |cancel: &AtomicBool, run: &dyn Fn() -> Result<(), PipelineError>| {
        std::thread::scope(|s| {
            s.spawn(|| {
                std::thread::sleep(std::time::Duration::from_millis(300));
                cancel.store(true, Ordering::Relaxed);
            });
            run()
        })
    };
    let mut slit: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(examples().join("slit/chair.json")).unwrap()).unwrap();
    slit["sheet"]["strip_count"] = 8.into();
    slit["sheet"]["quads_per_strip"] = 256.into();
    slit["solver"] = serde_json::json!({ "max_iterations": 10000, "gap_tolerance": 1e-14 });
    let slit = sheetform::slit::SlitScene::from_json(&slit.to_string()).unwrap();
    let cancel = AtomicBool::new(false);
    let e = stop_after(&cancel, &|| {
        let context = RunContext::new(examples()).with_cancel(&cancel);
        run_slit(&slit, &SlitRunOptions::default(), &context).map(|_| ())
    })
    .unwrap_err();
    assert_eq!(e.kind(), ErrorKind::Cancelled, "{e}");

    // A bumpy sheet of 80 000 faces cut into smooth charts.
    let (nx, ny) = (200usize, 200usize);
    let mut mesh = sheetform::mesh::TriangleMesh {
        positions: Vec::new(),
        triangles: Vec::new(),
        face_groups: Vec::new(),
        groups: vec!["sheet".into()],
        corner_uvs: None,
        seam_edges: Vec::new(),
    };
    for j in 0..=ny {
        for i in 0..=nx {
            let (x, y) = (i as f64, j as f64);
            mesh.positions
                .push(nalgebra::Vector3::new(x, y, 3.0 * (0.3 * x).sin() * (0.2 * y).cos()));
        }
    }
    let at = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
    for j in 0..ny {
        for i in 0..nx {
            mesh.triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            mesh.triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    mesh.face_groups = vec![0; mesh.triangles.len()];
    let options = FlattenOptions {
        charts: ChartMode::Smooth,
        ..Default::default()
    };
    let cancel = AtomicBool::new(false);
    let e = stop_after(&cancel, &|| {
        let context = RunContext::new(examples()).with_cancel(&cancel);
        run_flatten(mesh.clone(), &options, &context).map(|_| ())
    })
    .unwrap_err();
    assert_eq!(e.kind(), ErrorKind::Cancelled, "{e}");
}

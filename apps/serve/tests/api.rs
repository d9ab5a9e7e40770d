//! The editor's API without a browser (issue 20, security and faults): files outside the
//! served directory are neither read nor written, malformed, hostile and oversized
//! requests get error replies and the server keeps serving, an inadmissible scene gets
//! its report, and a solve answers with a model isometric to its pattern.

use axum::body::Body;
use axum::http::{Request, StatusCode};
use serde_json::Value;
use sheetform_serve::{router, ServeOptions};
use std::path::{Path, PathBuf};
use tower::ServiceExt;

fn repository() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A served directory holding the bent rectangle, inside a directory holding a secret.
fn served() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path().join("served");
    std::fs::create_dir_all(root.join("scenes")).unwrap();
    std::fs::copy(
        repository().join("examples/bent-rectangle.json"),
        root.join("scenes/bent-rectangle.json"),
    )
    .unwrap();
    std::fs::write(dir.path().join("secret.json"), r#"{"secret": true}"#).unwrap();
    (dir, root)
}

async fn send(app: &axum::Router, method: &str, uri: &str, body: impl Into<Body>) -> (StatusCode, Vec<u8>) {
    let request = Request::builder().method(method).uri(uri).body(body.into()).unwrap();
    let response = app.clone().oneshot(request).await.unwrap();
    let status = response.status();
    let bytes = axum::body::to_bytes(response.into_body(), usize::MAX).await.unwrap();
    (status, bytes.to_vec())
}

fn json(bytes: &[u8]) -> Value {
    serde_json::from_slice(bytes).unwrap()
}

#[tokio::test]
async fn a_solve_answers_with_a_model_isometric_to_its_pattern() {
    let (_dir, root) = served();
    let app = router(&ServeOptions {
        root,
        ..Default::default()
    })
    .unwrap();
    let scene = std::fs::read(repository().join("examples/bent-rectangle.json")).unwrap();
    let (status, body) = send(&app, "POST", "/api/bend", scene).await;
    assert_eq!(status, StatusCode::OK);
    let reply = json(&body);
    assert_eq!(reply["report"]["status"], "ok");
    let model = &reply["model"];
    let vertices = model["positions"].as_array().unwrap().len() / 3;
    assert_eq!(vertices, model["flat"].as_array().unwrap().len() / 2);
    assert_eq!(reply["report"]["vertex_count"], vertices);
    // Every edge as long in 3D as in the pattern.
    let worst = isometry_error(model);
    assert!(worst < 1e-9, "isometry error {worst}");
    // The colour map: the angle defect at every vertex, zero to rounding (its largest
    // value is the report's).
    let defects: Vec<f64> = serde_json::from_value(reply["angle_defects_rad"].clone()).unwrap();
    assert_eq!(defects.len(), vertices);
    let largest = defects.iter().fold(0.0f64, |m, g| m.max(g.abs()));
    assert!(largest < 1e-9, "{largest}");
    assert_eq!(
        reply["report"]["angle_defects"]["angle_defect_max_rad"]
            .as_f64()
            .unwrap(),
        largest
    );
    let svg = reply["pattern_svg"].as_str().unwrap();
    assert!(
        svg.starts_with("<?xml") || svg.starts_with("<svg"),
        "{}",
        &svg[..40.min(svg.len())]
    );
    // True scale: millimetres, one user unit per millimetre (the 240 × 120 mm sheet and
    // a 10 mm margin).
    assert!(
        svg.contains(r#"width="260.0000mm" height="140.0000mm" viewBox="0 0 260.0000 140.0000""#),
        "{}",
        &svg[..300.min(svg.len())]
    );
}

#[tokio::test]
async fn an_inadmissible_scene_is_refused_with_its_report() {
    let (_dir, root) = served();
    let app = router(&ServeOptions {
        root,
        ..Default::default()
    })
    .unwrap();
    let bad = r#"{"outline": [[0, -60], [240, -60], [240, 60], [0, 60]], "regions": [{"flat_start": [0, 0],
        "flat_direction": [1, 0], "curve": {"type": "bezier",
        "control_points": [[0, 0, 0], [80, 10, 0], [150, -20, 60], [170, 10, 120]]}}]}"#;
    let (status, body) = send(&app, "POST", "/api/bend", bad).await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    let reply = json(&body);
    assert_eq!(reply["error"]["kind"], "inadmissible");
    assert!(reply["error"]["message"]
        .as_str()
        .unwrap()
        .contains("curve of regression"));
    assert_eq!(reply["report"]["status"], "inadmissible");
}

#[tokio::test]
async fn malformed_hostile_and_oversized_requests_get_errors_and_the_server_keeps_serving() {
    let (_dir, root) = served();
    let app = router(&ServeOptions {
        root,
        max_request_bytes: 1 << 20,
        ..Default::default()
    })
    .unwrap();
    for (body, field) in [
        ("{\"outline\": [", "line 1"),
        ("{\"outline\": 5}", "invalid type"),
        (
            "{\"outline\": [[0,0],[1,0],[1,1]], \"regions\": [], \"bogus\": 1}",
            "bogus",
        ),
        ("\u{feff}[]", "expected struct BendScene"),
    ] {
        let (status, reply) = send(&app, "POST", "/api/bend", body).await;
        assert_eq!(status, StatusCode::BAD_REQUEST, "{body}");
        let reply = json(&reply);
        assert_eq!(reply["error"]["kind"], "invalid_input");
        assert!(reply["error"]["message"].as_str().unwrap().contains(field), "{reply}");
    }
    let (status, _) = send(&app, "POST", "/api/bend", vec![b' '; 2 << 20]).await;
    assert_eq!(status, StatusCode::PAYLOAD_TOO_LARGE);
    let (status, _) = send(&app, "POST", "/api/bend", vec![0xff, 0xfe, 0x00]).await;
    assert_eq!(status, StatusCode::BAD_REQUEST, "not UTF-8");
    let (status, _) = send(&app, "GET", "/api/nothing-here", Body::empty()).await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    // Still serving.
    let scene = std::fs::read(repository().join("examples/bent-rectangle.json")).unwrap();
    let (status, _) = send(&app, "POST", "/api/bend", scene).await;
    assert_eq!(status, StatusCode::OK);
}

#[tokio::test]
async fn no_file_outside_the_served_directory_is_read_or_written() {
    let (dir, root) = served();
    let app = router(&ServeOptions {
        root: root.clone(),
        ..Default::default()
    })
    .unwrap();
    let (status, body) = send(&app, "GET", "/api/files", Body::empty()).await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(json(&body)["files"], serde_json::json!(["scenes/bent-rectangle.json"]));
    let (status, _) = send(&app, "GET", "/api/files/scenes/bent-rectangle.json", Body::empty()).await;
    assert_eq!(status, StatusCode::OK);
    // A symbolic link inside the root that points out of it.
    #[cfg(unix)]
    std::os::unix::fs::symlink(dir.path().join("secret.json"), root.join("link.json")).unwrap();
    let secret = dir.path().join("secret.json");
    let absolute = format!("/api/files/{}", secret.display().to_string().replace('/', "%2F"));
    for uri in [
        "/api/files/..%2Fsecret.json",
        "/api/files/scenes%2F..%2F..%2Fsecret.json",
        absolute.as_str(),
        "/api/files/link.json",
    ] {
        let (status, body) = send(&app, "GET", uri, Body::empty()).await;
        assert_eq!(status, StatusCode::BAD_REQUEST, "{uri}");
        assert!(
            !String::from_utf8_lossy(&body).contains("secret\": true"),
            "{uri} read the secret"
        );
    }
    for uri in [
        "/api/files/..%2Fwritten.json",
        "/api/files/scenes%2F..%2F..%2Fwritten.json",
        "/api/files/link.json",
        "/api/files/scenes/new.txt",
    ] {
        let (status, _) = send(&app, "PUT", uri, "{}").await;
        assert_eq!(status, StatusCode::BAD_REQUEST, "{uri}");
    }
    assert!(!dir.path().join("written.json").exists());
    assert_eq!(std::fs::read_to_string(&secret).unwrap(), r#"{"secret": true}"#);
    // A save inside works, atomically, and refuses what is not JSON.
    let (status, _) = send(&app, "PUT", "/api/files/scenes/saved.json", "{\"a\": 1}").await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(
        std::fs::read_to_string(root.join("scenes/saved.json")).unwrap(),
        "{\"a\": 1}"
    );
    let (status, _) = send(&app, "PUT", "/api/files/scenes/saved.json", "{not json").await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert_eq!(
        std::fs::read_to_string(root.join("scenes/saved.json")).unwrap(),
        "{\"a\": 1}"
    );
}

#[tokio::test]
async fn the_front_end_is_embedded() {
    let (_dir, root) = served();
    let app = router(&ServeOptions {
        root,
        ..Default::default()
    })
    .unwrap();
    let (status, page) = send(&app, "GET", "/", Body::empty()).await;
    assert_eq!(status, StatusCode::OK);
    assert!(String::from_utf8_lossy(&page).contains("/editor.js"));
    let (status, three) = send(&app, "GET", "/vendor/three/three.module.js", Body::empty()).await;
    assert_eq!(status, StatusCode::OK);
    assert!(three.len() > 100_000);
}

/// Largest relative difference between a triangle edge's 3D and flat lengths.
fn isometry_error(model: &Value) -> f64 {
    let p: Vec<f64> = serde_json::from_value(model["positions"].clone()).unwrap();
    let f: Vec<f64> = serde_json::from_value(model["flat"].clone()).unwrap();
    let t: Vec<usize> = serde_json::from_value(model["triangles"].clone()).unwrap();
    let mut worst: f64 = 0.0;
    for tri in t.chunks(3) {
        for (a, b) in [(tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])] {
            let d3 = ((p[3 * a] - p[3 * b]).powi(2)
                + (p[3 * a + 1] - p[3 * b + 1]).powi(2)
                + (p[3 * a + 2] - p[3 * b + 2]).powi(2))
            .sqrt();
            let d2 = ((f[2 * a] - f[2 * b]).powi(2) + (f[2 * a + 1] - f[2 * b + 1]).powi(2)).sqrt();
            worst = worst.max((d3 - d2).abs() / d2);
        }
    }
    worst
}

/// The mesh mode: a developable lamp shade is flattened exactly (opened along a seam), a
/// closed box unfolds as a net whose corners carry their angle defect (π/2 each); the
/// files `sheetform flatten` writes can be downloaded; bad names, options and meshes get
/// error replies naming what is wrong.
#[tokio::test]
async fn a_mesh_is_checked_and_flattened_into_a_pattern_isometric_to_it() {
    let (_dir, root) = served();
    let app = router(&ServeOptions {
        root,
        ..Default::default()
    })
    .unwrap();
    let shade = std::fs::read(repository().join("examples/meshes/lamp-shade.obj")).unwrap();
    let (status, body) = send(&app, "POST", "/api/mesh?name=lamp-shade.obj", shade.clone()).await;
    assert_eq!(status, StatusCode::OK, "{}", String::from_utf8_lossy(&body));
    let reply = json(&body);
    assert_eq!(reply["report"]["status"], "ok");
    assert!(
        isometry_error(&reply["model"]) < 1e-9,
        "{}",
        isometry_error(&reply["model"])
    );
    let defects: Vec<f64> = serde_json::from_value(reply["input"]["angle_defects_rad"].clone()).unwrap();
    assert_eq!(defects.len(), 7 * 48);
    assert!(
        defects.iter().all(|g| g.abs() < 1e-9),
        "the cone frustum is developable"
    );
    // The annulus is opened into a disk: its flat copy has the seam's vertices twice.
    let flat: Vec<f64> = serde_json::from_value(reply["model"]["flat"].clone()).unwrap();
    assert!(flat.len() / 2 > 7 * 48);
    assert!(
        reply["pattern_svg"].as_str().unwrap().starts_with("<?xml")
            || reply["pattern_svg"].as_str().unwrap().contains("<svg")
    );

    let gift = std::fs::read(repository().join("examples/meshes/gift-box.obj")).unwrap();
    let (status, body) = send(&app, "POST", "/api/mesh?name=gift-box.obj&charts=net", gift.clone()).await;
    assert_eq!(status, StatusCode::OK, "{}", String::from_utf8_lossy(&body));
    let reply = json(&body);
    assert_eq!(reply["report"]["layout"], "net");
    assert!(isometry_error(&reply["model"]) < 1e-9);
    let defects: Vec<f64> = serde_json::from_value(reply["input"]["angle_defects_rad"].clone()).unwrap();
    assert_eq!(defects.len(), 8);
    for g in &defects {
        assert!(
            (g - std::f64::consts::FRAC_PI_2).abs() < 1e-12,
            "a box corner's defect is π/2: {g}"
        );
    }
    let pieces: std::collections::BTreeSet<u64> = reply["model"]["face_pieces"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p.as_u64().unwrap())
        .collect();
    assert_eq!(
        pieces.len(),
        reply["report"]["net"]["piece_count"].as_u64().unwrap() as usize
    );

    // A download: the OBJ with the pattern as `vt`.
    let (status, body) = send(
        &app,
        "POST",
        "/api/mesh/file/model.obj?name=gift-box.obj&charts=net",
        gift.clone(),
    )
    .await;
    assert_eq!(status, StatusCode::OK);
    assert!(String::from_utf8_lossy(&body).lines().any(|l| l.starts_with("vt ")));
    let (status, _) = send(
        &app,
        "POST",
        "/api/mesh/file/frames.zip?name=gift-box.obj",
        gift.clone(),
    )
    .await;
    assert_eq!(status, StatusCode::NOT_FOUND);

    // Errors name what is wrong; the server keeps serving.
    for (uri, body, expected) in [
        ("/api/mesh?name=gift-box.obj&charts=zigzag", gift.clone(), "charts"),
        ("/api/mesh?name=gift-box.obj&units=furlong", gift.clone(), "units"),
        ("/api/mesh?name=..%2Fgift-box.obj", gift.clone(), "name"),
        ("/api/mesh?name=gift-box.obj&colour=red", gift.clone(), "colour"),
        ("/api/mesh", gift.clone(), "name"),
        (
            "/api/mesh?name=bad.obj",
            b"v 0 0 0\nv 1 0 0\nf 1 2 9\n".to_vec(),
            "bad.obj",
        ),
        ("/api/mesh?name=gift-box.xyz", gift.clone(), "xyz"),
    ] {
        let (status, reply) = send(&app, "POST", uri, body).await;
        assert_eq!(
            status,
            StatusCode::BAD_REQUEST,
            "{uri}: {}",
            String::from_utf8_lossy(&reply)
        );
        // A JSON error naming what is wrong (malformed queries too).
        let reply = json(&reply);
        assert_eq!(reply["error"]["kind"], "invalid_input", "{uri}");
        assert!(
            reply["error"]["message"].as_str().unwrap().contains(expected),
            "{uri}: {reply}"
        );
    }
    // A closed box cannot be laid out whole.
    let (status, body) = send(&app, "POST", "/api/mesh?name=gift-box.obj&charts=never", gift).await;
    assert!(status.is_client_error(), "{status}: {}", String::from_utf8_lossy(&body));
    let (status, _) = send(&app, "POST", "/api/mesh?name=lamp-shade.obj", shade).await;
    assert_eq!(status, StatusCode::OK);
}

/// The listing names the meshes under the served directory, and a binary mesh opens as
/// it is.
#[tokio::test]
async fn meshes_are_listed_and_opened_as_bytes() {
    let (_dir, root) = served();
    std::fs::create_dir_all(root.join("meshes")).unwrap();
    // A binary STL of one triangle.
    let mut stl = vec![0u8; 80];
    stl.extend(1u32.to_le_bytes());
    for value in [0.0f32, 0.0, 1.0, 0.0, 0.0, 0.0, 10.0, 0.0, 0.0, 0.0, 10.0, 0.0] {
        stl.extend(value.to_le_bytes());
    }
    stl.extend([0u8, 0]);
    std::fs::write(root.join("meshes/triangle.stl"), &stl).unwrap();
    let app = router(&ServeOptions {
        root,
        ..Default::default()
    })
    .unwrap();
    let (status, body) = send(&app, "GET", "/api/files", Body::empty()).await;
    assert_eq!(status, StatusCode::OK);
    let listing = json(&body);
    assert_eq!(listing["meshes"], serde_json::json!(["meshes/triangle.stl"]));
    assert_eq!(listing["files"], serde_json::json!(["scenes/bent-rectangle.json"]));
    let (status, body) = send(&app, "GET", "/api/files/meshes/triangle.stl", Body::empty()).await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(body, stl);
    let (status, body) = send(&app, "POST", "/api/mesh?name=triangle.stl", stl).await;
    assert_eq!(status, StatusCode::OK, "{}", String::from_utf8_lossy(&body));
    assert!(isometry_error(&json(&body)["model"]) < 1e-9);
}

/// The slit mode: the chair is solved as `sheetform slit` solves it (every strip closed
/// at the seat curve, the sheet isometric to its pattern), its files download, and an
/// invalid scene is refused naming the field.
#[tokio::test]
async fn a_slit_scene_is_solved_with_its_gap_per_strip() {
    let (_dir, root) = served();
    let app = router(&ServeOptions {
        root,
        ..Default::default()
    })
    .unwrap();
    let chair = std::fs::read_to_string(repository().join("examples/slit/chair.json")).unwrap();
    let (status, body) = send(&app, "POST", "/api/slit", chair.clone()).await;
    assert_eq!(status, StatusCode::OK, "{}", String::from_utf8_lossy(&body));
    let reply = json(&body);
    assert_eq!(reply["report"]["status"], "ok");
    assert!(
        isometry_error(&reply["model"]) < 1e-8,
        "{}",
        isometry_error(&reply["model"])
    );
    let strips = reply["report"]["slit"]["strips"].as_array().unwrap();
    assert_eq!(strips.len(), 6);
    assert!(strips.iter().all(|s| s["gap_mm"].as_f64().unwrap() < 1e-6));
    // Every ridge line but E0 of every strip, both ends, offered to anchor, as anchors.
    let offered: Vec<sheetform::slit::AnchorSpec> = serde_json::from_value(reply["anchorable_points"].clone()).unwrap();
    assert_eq!(offered.len(), 6 * 10 * 2);
    assert!(offered.iter().all(|a| (1..=10).contains(&a.ridge) && a.strip < 6));
    assert!(reply["pattern_svg"].as_str().unwrap().contains("<svg"));
    let (status, body) = send(&app, "POST", "/api/slit/file/model.obj", chair.clone()).await;
    assert_eq!(status, StatusCode::OK);
    assert!(String::from_utf8_lossy(&body).lines().any(|l| l.starts_with("vt ")));
    let (status, body) = send(&app, "POST", "/api/slit/file/mould.stl", chair.clone()).await;
    assert_eq!(status, StatusCode::OK);
    assert!(body.len() > 84, "a binary STL with triangles");
    let mut scene: Value = serde_json::from_str(&chair).unwrap();
    scene["sheet"]["strip_count"] = 0.into();
    let (status, body) = send(&app, "POST", "/api/slit", scene.to_string()).await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert!(String::from_utf8_lossy(&body).contains("strip_count"));
}

/// The FFD mode: progress lines, then the restored panels (developable to the solver's
/// tolerance, isometric to their pattern), the plain FFD's defects and the deformed
/// lattice; a scene that does not parse is refused before anything streams, one the run
/// refuses ends the stream with the error.
#[tokio::test]
async fn an_ffd_scene_streams_its_progress_then_the_restored_panels() {
    let (_dir, root) = served();
    let app = router(&ServeOptions {
        root,
        ..Default::default()
    })
    .unwrap();
    let duct = std::fs::read_to_string(repository().join("examples/ffd/duct.json")).unwrap();
    let (status, body) = send(&app, "POST", "/api/ffd", duct.clone()).await;
    assert_eq!(status, StatusCode::OK);
    let lines: Vec<Value> = String::from_utf8(body)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let (last, progress) = lines.split_last().unwrap();
    assert!(progress.len() >= 3, "{progress:?}");
    let fractions: Vec<f64> = progress
        .iter()
        .map(|p| p["progress"]["fraction"].as_f64().unwrap())
        .collect();
    assert!(fractions.windows(2).all(|w| w[0] <= w[1]), "{fractions:?}");
    let reply = &last["result"];
    assert_eq!(reply["report"]["status"], "ok", "{last}");
    let largest = |values: &Value| {
        values
            .as_array()
            .unwrap()
            .iter()
            .map(|g| g.as_f64().unwrap().abs())
            .fold(0.0, f64::max)
    };
    assert!(largest(&reply["plain"]["angle_defects_rad"]) > 1e-3);
    assert!(largest(&reply["restored"]["angle_defects_rad"]) <= 1e-8);
    assert!(isometry_error(&reply["model"]) < 1e-8);
    let counts: Vec<usize> = serde_json::from_value(reply["lattice"]["counts"].clone()).unwrap();
    assert_eq!(
        reply["lattice"]["control_points"].as_array().unwrap().len(),
        3 * counts.iter().product::<usize>()
    );
    let (status, body) = send(&app, "POST", "/api/ffd/file/deformed.obj", duct.clone()).await;
    assert_eq!(status, StatusCode::OK);
    assert!(String::from_utf8_lossy(&body).lines().any(|l| l.starts_with("v ")));
    // A scene that does not parse is refused before anything streams; one whose values
    // the run refuses ends its stream with the error, naming the field.
    let (status, body) = send(
        &app,
        "POST",
        "/api/ffd",
        r#"{"model": {"procedural": {"kind": "duct"}}, "lattice": "#,
    )
    .await;
    assert_eq!(status, StatusCode::BAD_REQUEST, "{}", String::from_utf8_lossy(&body));
    let mut scene: Value = serde_json::from_str(&duct).unwrap();
    scene["lattice"]["counts"] = serde_json::json!([1000, 4, 4]);
    let (status, body) = send(&app, "POST", "/api/ffd", scene.to_string()).await;
    assert_eq!(status, StatusCode::OK);
    let last: Value = serde_json::from_str(String::from_utf8(body).unwrap().lines().last().unwrap()).unwrap();
    assert_eq!(last["error"]["kind"], "invalid_input");
    assert!(
        last["error"]["message"].as_str().unwrap().contains("lattice.counts"),
        "{last}"
    );
}

/// Save as, into another directory: the server says which asset paths name the same
/// files from there (the editor applies them); directories outside the served one and
/// bodies that are not JSON are refused.
#[tokio::test]
async fn a_scene_moved_to_another_directory_gets_its_asset_paths_rewritten() {
    let (_dir, root) = served();
    let app = router(&ServeOptions {
        root,
        ..Default::default()
    })
    .unwrap();
    let photo = std::fs::read_to_string(repository().join("examples/photo/coffee-cup.json")).unwrap();
    let (status, body) = send(
        &app,
        "POST",
        "/api/relocate?from=examples/photo&to=designs/cups",
        photo.clone(),
    )
    .await;
    assert_eq!(status, StatusCode::OK, "{}", String::from_utf8_lossy(&body));
    let moves = json(&body)["moves"].clone();
    assert_eq!(
        moves,
        serde_json::json!([{"pointer": "/image/path", "field": "image.path", "from": "coffee.png", "to": "../../examples/photo/coffee.png"}])
    );
    // Nothing to move within the same directory.
    let (_, body) = send(
        &app,
        "POST",
        "/api/relocate?from=examples/photo&to=examples/photo",
        photo.clone(),
    )
    .await;
    assert_eq!(json(&body)["moves"], serde_json::json!([]));
    for query in ["from=../secret&to=a", "from=a&to=/etc", "from=a"] {
        let (status, body) = send(&app, "POST", &format!("/api/relocate?{query}"), photo.clone()).await;
        assert_eq!(
            status,
            StatusCode::BAD_REQUEST,
            "{query}: {}",
            String::from_utf8_lossy(&body)
        );
    }
    let (status, _) = send(&app, "POST", "/api/relocate?from=a&to=b", "{not json").await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
}

/// The last line of an FFD reply (`result` or `error`).
async fn ffd_reply(app: &axum::Router, scene: &Value) -> Value {
    let (status, body) = send(app, "POST", "/api/ffd", scene.to_string()).await;
    assert_eq!(status, StatusCode::OK);
    serde_json::from_str(String::from_utf8(body).unwrap().lines().last().unwrap()).unwrap()
}

/// A drag in the editor appends a deformation: the server resumes from its last design,
/// restores the new deformation alone and answers with exactly the panels a fresh server
/// restores from scratch; an undo (the shorter scene again) restores nothing; a failed
/// run leaves the last good design to resume from.
#[tokio::test]
async fn a_drag_is_restored_from_the_last_design() {
    let (_dir, root) = served();
    let options = ServeOptions {
        root,
        ..Default::default()
    };
    let (app, fresh) = (router(&options).unwrap(), router(&options).unwrap());
    let full: Value =
        serde_json::from_str(&std::fs::read_to_string(repository().join("examples/ffd/skirt-drag.json")).unwrap())
            .unwrap();
    let mut first = full.clone();
    first["deformations"].as_array_mut().unwrap().truncate(1);
    let reply = ffd_reply(&app, &first).await;
    assert_eq!(reply["result"]["resumed_deformations"], 0, "{reply}");
    // A scene the run refuses changes nothing (its first deformation differs, so a
    // design cached from it would resume nothing below).
    let mut broken = full.clone();
    broken["deformations"][0]["edits"] = serde_json::json!([{"move": {"points": {"i": [40, 40]}, "by": [1, 0, 0]}}]);
    assert!(ffd_reply(&app, &broken).await["error"].is_object());
    let warm = ffd_reply(&app, &full).await;
    assert_eq!(warm["result"]["resumed_deformations"], 1, "{warm}");
    assert_eq!(warm["result"]["report"]["ffd"]["resumed_deformations"], 1);
    assert_eq!(warm["result"]["report"]["ffd"]["embedding_time_ms"], 0.0);
    let cold = ffd_reply(&fresh, &full).await;
    assert_eq!(cold["result"]["resumed_deformations"], 0);
    for key in ["model", "restored", "plain"] {
        assert_eq!(warm["result"][key], cold["result"][key], "{key}");
    }
    // The report's figures too, but for the solver times.
    let figures = |reply: &Value| {
        let mut steps = reply["result"]["report"]["ffd"]["steps"].clone();
        for step in steps.as_array_mut().unwrap() {
            step.as_object_mut().unwrap().retain(|key, _| !key.ends_with("time_ms"));
        }
        steps
    };
    assert_eq!(figures(&warm), figures(&cold));
    let undo = ffd_reply(&app, &first).await;
    assert_eq!(undo["result"]["resumed_deformations"], 1);
    assert_eq!(undo["result"]["report"]["ffd"]["steps"].as_array().unwrap().len(), 1);
}

/// The photo mode: an annotation's photograph is read relative to `?dir=` (the
/// annotation's directory inside the served one, never outside it), the reconstruction
/// answers with a model isometric to its pattern, and the photograph itself opens as an
/// image.
#[tokio::test]
async fn a_photo_annotation_is_reconstructed_with_its_photograph_beside_it() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path().join("served");
    std::fs::create_dir_all(root.join("photos")).unwrap();
    for name in ["coffee-cup.json", "coffee.png"] {
        std::fs::copy(
            repository().join("examples/photo").join(name),
            root.join("photos").join(name),
        )
        .unwrap();
    }
    let app = router(&ServeOptions {
        root,
        ..Default::default()
    })
    .unwrap();
    let annotation = std::fs::read_to_string(repository().join("examples/photo/coffee-cup.json")).unwrap();
    let (status, body) = send(&app, "POST", "/api/photo?dir=photos", annotation.clone()).await;
    assert_eq!(status, StatusCode::OK, "{}", String::from_utf8_lossy(&body));
    let reply = json(&body);
    assert_eq!(reply["report"]["status"], "ok");
    assert!(isometry_error(&reply["model"]) < 1e-8);
    // Without the directory the photograph is not found; outside the root is refused.
    let (status, body) = send(&app, "POST", "/api/photo", annotation.clone()).await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert!(String::from_utf8_lossy(&body).contains("coffee.png"));
    for dir in ["..", "%2Ftmp", "photos%2F..%2F..", "missing"] {
        let (status, body) = send(&app, "POST", &format!("/api/photo?dir={dir}"), annotation.clone()).await;
        assert_eq!(status, StatusCode::BAD_REQUEST, "{dir}");
        assert!(
            String::from_utf8_lossy(&body).contains("dir"),
            "{dir}: {}",
            String::from_utf8_lossy(&body)
        );
    }
    let (status, body) = send(&app, "POST", "/api/photo/file/model.obj?dir=photos", annotation).await;
    assert_eq!(status, StatusCode::OK);
    assert!(String::from_utf8_lossy(&body).lines().any(|l| l.starts_with("vt ")));
    let request = Request::builder()
        .uri("/api/files/photos/coffee.png")
        .body(Body::empty())
        .unwrap();
    let response = app.clone().oneshot(request).await.unwrap();
    assert_eq!(response.status(), StatusCode::OK);
    assert_eq!(response.headers()["content-type"], "image/png");
    let bytes = axum::body::to_bytes(response.into_body(), usize::MAX).await.unwrap();
    assert_eq!(&bytes[1..4], b"PNG");
}

/// An FFD scene that takes minutes: a 16k-vertex duct deformed 30 times over, every
/// lattice parameter a step.
fn long_ffd_scene() -> Value {
    let path = repository().join("examples/ffd/duct-100k.json");
    let mut scene: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    scene["model"]["procedural"]["around"] = 160.into();
    scene["model"]["procedural"]["along"] = 100.into();
    scene["solver"] = serde_json::json!({});
    let step = scene["deformations"][0].clone();
    scene["deformations"] = Value::Array(vec![step; 30]);
    scene
}

/// A server over a copy of the examples that runs one solve at a time.
fn one_slot_server() -> (tempfile::TempDir, axum::Router) {
    let (dir, root) = served();
    let app = router(&ServeOptions {
        root,
        max_concurrent_solves: 1,
        ..Default::default()
    })
    .unwrap();
    (dir, app)
}

/// The duct example is restored within a minute: an abandoned run held the only slot
/// no longer.
async fn assert_the_only_slot_is_free(app: &axum::Router) {
    let duct = std::fs::read_to_string(repository().join("examples/ffd/duct.json")).unwrap();
    let next = tokio::time::timeout(std::time::Duration::from_secs(60), send(app, "POST", "/api/ffd", duct))
        .await
        .expect("the abandoned run was cancelled and freed its slot");
    assert_eq!(next.0, StatusCode::OK);
    assert!(String::from_utf8_lossy(&next.1).contains("\"result\""));
}

/// A client that leaves an FFD run cancels it: with one solve at a time, a long run (a
/// 16k-vertex duct deformed 30 times over) abandoned after its first progress line lets
/// the next request through within a minute, where the run itself would hold the only
/// slot for many minutes.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_client_that_leaves_cancels_its_ffd_run() {
    use futures_util::StreamExt;
    let (_dir, app) = one_slot_server();
    let long = long_ffd_scene();
    let request = Request::builder()
        .method("POST")
        .uri("/api/ffd")
        .body(Body::from(long.to_string()))
        .unwrap();
    let response = app.clone().oneshot(request).await.unwrap();
    assert_eq!(response.status(), StatusCode::OK);
    let mut stream = response.into_body().into_data_stream();
    let first = stream.next().await.unwrap().unwrap();
    assert!(String::from_utf8_lossy(&first).contains("progress"));
    // The client leaves.
    drop(stream);
    assert_the_only_slot_is_free(&app).await;
}

/// On loopback only pages of this machine are answered: a request whose `Host` or
/// `Origin` names another machine (a DNS-rebinding page, a cross-site post) is refused.
#[tokio::test]
async fn pages_of_other_machines_are_refused() {
    let (_dir, root) = served();
    let app = router(&ServeOptions {
        root,
        ..Default::default()
    })
    .unwrap();
    let request = |headers: &[(&str, &str)]| {
        let mut builder = Request::builder().uri("/api/files");
        for (name, value) in headers {
            builder = builder.header(*name, *value);
        }
        builder.body(Body::empty()).unwrap()
    };
    for headers in [
        vec![("host", "evil.example:8080")],
        vec![("host", "127.0.0.1:8080"), ("origin", "http://evil.example")],
        vec![("host", "localhost:8080"), ("origin", "null")],
        vec![("host", "127.0.0.1.evil.example")],
    ] {
        let response = app.clone().oneshot(request(&headers)).await.unwrap();
        assert_eq!(response.status(), StatusCode::FORBIDDEN, "{headers:?}");
        let bytes = axum::body::to_bytes(response.into_body(), usize::MAX).await.unwrap();
        assert!(json(&bytes)["error"]["message"]
            .as_str()
            .unwrap()
            .contains("this machine"));
    }
    for headers in [
        vec![],
        vec![("host", "127.0.0.1:8080")],
        vec![("host", "localhost:8080"), ("origin", "http://localhost:8080")],
        vec![("host", "[::1]:8080"), ("origin", "http://[::1]:8080")],
    ] {
        let response = app.clone().oneshot(request(&headers)).await.unwrap();
        assert_eq!(response.status(), StatusCode::OK, "{headers:?}");
    }
}

/// A client that leaves any other solve (here a download of the long FFD run's report)
/// cancels it too: its handler is dropped, which sets the run's cancel flag, and the
/// only slot is free again within seconds.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_client_that_leaves_a_download_cancels_its_run() {
    let (_dir, app) = one_slot_server();
    let long = long_ffd_scene();
    let request = Request::builder()
        .method("POST")
        .uri("/api/ffd/file/report.json")
        .body(Body::from(long.to_string()))
        .unwrap();
    // The client gives up after half a second.
    let abandoned = tokio::time::timeout(std::time::Duration::from_millis(500), app.clone().oneshot(request)).await;
    assert!(abandoned.is_err(), "the long run cannot have finished");
    assert_the_only_slot_is_free(&app).await;
}

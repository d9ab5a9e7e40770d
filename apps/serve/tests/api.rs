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
    assert_eq!(
        json(&body)["truncated"],
        serde_json::json!({"scenes": false, "meshes": false, "photos": false})
    );
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
        (
            "/api/mesh?name=gift-box.obj&charts=develop&mirror=w",
            gift.clone(),
            "mirror",
        ),
        (
            "/api/mesh?name=gift-box.obj&charts=smooth&mirror=x",
            gift.clone(),
            "develop layout",
        ),
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
    // The `develop` layout (issue 36): the box as exact pieces of whole sides, unmoved,
    // its files for download those of `sheetform develop`.
    let (status, body) = send(&app, "POST", "/api/mesh?name=gift-box.obj&charts=develop", gift.clone()).await;
    assert_eq!(status, StatusCode::OK, "{}", String::from_utf8_lossy(&body));
    let reply = json(&body);
    assert_eq!(reply["report"]["command"], "develop");
    assert_eq!(reply["report"]["status"], "ok");
    assert_eq!(reply["report"]["develop"]["hausdorff_mm"], 0.0);
    assert!(isometry_error(&reply["model"]) < 1e-9);
    let positions: Vec<f64> = serde_json::from_value(reply["model"]["positions"].clone()).unwrap();
    let corners: Vec<f64> = serde_json::from_value(reply["input"]["positions"].clone()).unwrap();
    for p in positions.chunks(3) {
        assert!(
            corners.chunks(3).any(|q| (0..3).all(|k| (p[k] - q[k]).abs() < 1e-9)),
            "a developed vertex off the box's corners: {p:?}"
        );
    }
    let (status, body) = send(
        &app,
        "POST",
        "/api/mesh/file/distance.ply?name=gift-box.obj&charts=develop",
        gift.clone(),
    )
    .await;
    assert_eq!(status, StatusCode::OK);
    assert!(String::from_utf8_lossy(&body).contains("property double distance_mm"));
    // With a mirror plane (`sheetform develop --mirror x`): the box is cut in the plane
    // through its middle, developed as a half and joined with its image, still unmoved
    // and exact, its vertices symmetric in the plane the report names.
    let (status, body) = send(
        &app,
        "POST",
        "/api/mesh?name=gift-box.obj&charts=develop&mirror=x",
        gift.clone(),
    )
    .await;
    assert_eq!(status, StatusCode::OK, "{}", String::from_utf8_lossy(&body));
    let reply = json(&body);
    let develop = &reply["report"]["develop"];
    assert_eq!(reply["report"]["status"], "ok");
    let plane = develop["mirror_plane"].as_str().unwrap();
    let middle: f64 = plane.strip_prefix("x = ").expect(plane).parse().unwrap();
    assert_eq!(develop["hausdorff_mm"], 0.0);
    assert!(isometry_error(&reply["model"]) < 1e-9);
    let positions: Vec<f64> = serde_json::from_value(reply["model"]["positions"].clone()).unwrap();
    // The half was cut on the plane (the box without a mirror has its corners only).
    assert!(
        positions.chunks(3).any(|p| (p[0] - middle).abs() < 1e-9),
        "no vertex on the cut {plane}"
    );
    for p in positions.chunks(3) {
        let image = [2.0 * middle - p[0], p[1], p[2]];
        assert!(
            positions
                .chunks(3)
                .any(|q| (0..3).all(|k| (image[k] - q[k]).abs() < 1e-9)),
            "{p:?} has no mirror image in {plane}"
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

/// A server on a free port of this machine, serving on its own thread until the test
/// process ends.
fn running(options: ServeOptions) -> std::net::SocketAddr {
    let server = sheetform_serve::Server::bind(&options).unwrap();
    let address = server.local_address().unwrap();
    let stop: &'static std::sync::atomic::AtomicBool = Box::leak(Box::new(std::sync::atomic::AtomicBool::new(false)));
    std::thread::spawn(move || server.run(stop));
    address
}

/// How a connection ended while a client waited on it.
#[derive(Debug)]
enum Ending {
    /// The server closed it, after sending these bytes (perhaps a reply).
    Closed(Vec<u8>),
    /// Still open at the limit.
    Open(Vec<u8>),
}

/// Waits up to `limit` for the server to close `stream`, sending one byte of `trickle`
/// every 200 ms meanwhile (a slow client), and keeping what the server sends.
fn wait_for_close(stream: &mut std::net::TcpStream, limit: std::time::Duration, trickle: &[u8]) -> Ending {
    use std::io::{Read, Write};
    stream
        .set_read_timeout(Some(std::time::Duration::from_millis(200)))
        .unwrap();
    let start = std::time::Instant::now();
    let mut received = Vec::new();
    let mut trickle = trickle.iter().cycle();
    while start.elapsed() < limit {
        if let Some(byte) = trickle.next() {
            if stream.write_all(&[*byte]).is_err() {
                return Ending::Closed(received);
            }
        }
        let mut buffer = [0u8; 4096];
        match stream.read(&mut buffer) {
            Ok(0) => return Ending::Closed(received),
            Ok(n) => received.extend_from_slice(&buffer[..n]),
            Err(e) if matches!(e.kind(), std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut) => {}
            Err(_) => return Ending::Closed(received),
        }
    }
    Ending::Open(received)
}

/// A request over a connection of its own, answered in full (`Connection: close`).
fn http(address: std::net::SocketAddr, method: &str, path: &str, body: &[u8]) -> String {
    use std::io::{Read, Write};
    let mut stream = std::net::TcpStream::connect(address).unwrap();
    stream
        .set_read_timeout(Some(std::time::Duration::from_secs(60)))
        .unwrap();
    write!(
        stream,
        "{method} {path} HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: {}\r\nConnection: close\r\n\r\n",
        body.len()
    )
    .unwrap();
    stream.write_all(body).unwrap();
    let mut reply = Vec::new();
    stream.read_to_end(&mut reply).unwrap();
    String::from_utf8_lossy(&reply).into_owned()
}

/// Issue 35: slow clients held their sockets for good (no header or body read timeout).
/// Headers sent a byte at a time, a connection that sends nothing, and a body that never
/// completes are each cut off at their timeout (1 s here; 10 s allowed), the body with a
/// 408; the server keeps serving.
#[test]
fn slow_clients_are_cut_off_at_the_header_and_body_timeouts() {
    let (_dir, root) = served();
    let address = running(ServeOptions {
        root,
        header_read_timeout: std::time::Duration::from_secs(1),
        body_read_timeout: std::time::Duration::from_secs(1),
        ..Default::default()
    });
    let limit = std::time::Duration::from_secs(10);
    let mut headers = std::net::TcpStream::connect(address).unwrap();
    std::io::Write::write_all(&mut headers, b"GET /api/files HTTP/1.1\r\nX-Slow: ").unwrap();
    let ending = wait_for_close(&mut headers, limit, b"a");
    assert!(
        matches!(ending, Ending::Closed(_)),
        "headers a byte at a time: {ending:?}"
    );
    let mut idle = std::net::TcpStream::connect(address).unwrap();
    let ending = wait_for_close(&mut idle, limit, b"");
    assert!(
        matches!(ending, Ending::Closed(_)),
        "a connection that sends nothing: {ending:?}"
    );
    let mut body = std::net::TcpStream::connect(address).unwrap();
    std::io::Write::write_all(
        &mut body,
        b"POST /api/bend HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 100000\r\n\r\n{",
    )
    .unwrap();
    match wait_for_close(&mut body, limit, b" ") {
        Ending::Closed(reply) => {
            let reply = String::from_utf8_lossy(&reply);
            assert!(reply.starts_with("HTTP/1.1 408"), "{reply}");
            assert!(reply.contains("\"timeout\"") && reply.contains("within 1 s"), "{reply}");
        }
        ending => panic!("a body that never completes: {ending:?}"),
    }
    assert!(http(address, "GET", "/api/files", b"").starts_with("HTTP/1.1 200"));
}

/// Issue 35: no write timeout. A client that asked for a large file and never read the
/// reply held its connection (and the reply) for good; it is now closed once the reply
/// has waited on the client for the write timeout (1 s here): reading afterwards gets
/// what the socket buffers held, then the end, never the whole file. A client that does
/// read gets all of it.
#[test]
fn a_client_that_does_not_read_its_reply_is_cut_off_at_the_write_timeout() {
    use std::io::{Read, Write};
    let (_dir, root) = served();
    // Larger than both sockets' buffers on any loopback (a few MiB each).
    let size = 48usize << 20;
    std::fs::write(root.join("large.stl"), vec![b'x'; size]).unwrap();
    let address = running(ServeOptions {
        root,
        write_timeout: std::time::Duration::from_secs(1),
        ..Default::default()
    });
    let request = b"GET /api/files/large.stl HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n";
    let read_all = |stream: &mut std::net::TcpStream| {
        stream
            .set_read_timeout(Some(std::time::Duration::from_secs(30)))
            .unwrap();
        let mut received = 0usize;
        let mut buffer = vec![0u8; 1 << 16];
        // Until the end, a reset, or 30 s without a byte.
        while let Ok(n @ 1..) = stream.read(&mut buffer) {
            received += n;
        }
        received
    };
    let mut reader = std::net::TcpStream::connect(address).unwrap();
    reader.write_all(request).unwrap();
    assert!(read_all(&mut reader) > size, "a client that reads gets the whole file");
    let mut stalled = std::net::TcpStream::connect(address).unwrap();
    stalled.write_all(request).unwrap();
    std::thread::sleep(std::time::Duration::from_secs(4));
    let received = read_all(&mut stalled);
    assert!(
        received < size,
        "a client that stopped reading for 4 s still got the whole reply ({received} bytes)"
    );
    assert!(http(address, "GET", "/api/files", b"").starts_with("HTTP/1.1 200"));
}

/// Issue 35: connections were not capped. Past the cap (2 here) a connection waits until
/// one closes, then is served.
#[test]
fn connections_past_the_cap_wait_for_one_to_close() {
    use std::io::Write;
    let (_dir, root) = served();
    let address = running(ServeOptions {
        root,
        max_connections: 2,
        ..Default::default()
    });
    let first = std::net::TcpStream::connect(address).unwrap();
    let _second = std::net::TcpStream::connect(address).unwrap();
    let mut third = std::net::TcpStream::connect(address).unwrap();
    third
        .write_all(b"GET /api/files HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n")
        .unwrap();
    match wait_for_close(&mut third, std::time::Duration::from_secs(1), b"") {
        Ending::Open(reply) => assert!(reply.is_empty(), "{}", String::from_utf8_lossy(&reply)),
        ending => panic!("a third connection was served past the cap of 2: {ending:?}"),
    }
    drop(first);
    match wait_for_close(&mut third, std::time::Duration::from_secs(10), b"") {
        Ending::Closed(reply) => {
            let reply = String::from_utf8_lossy(&reply);
            assert!(reply.starts_with("HTTP/1.1 200"), "{reply}");
        }
        ending => panic!("the third connection was not served once a slot was free: {ending:?}"),
    }
}

/// Uploads of `count` bodies of `declared` bytes that send their first kilobyte and
/// then stall, each on its connection.
fn stalled_uploads(address: std::net::SocketAddr, count: usize, declared: usize) -> Vec<std::net::TcpStream> {
    use std::io::Write;
    (0..count)
        .map(|_| {
            let mut stream = std::net::TcpStream::connect(address).unwrap();
            write!(
                stream,
                "POST /api/bend HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: {declared}\r\n\r\n"
            )
            .unwrap();
            stream.write_all(&[b' '; 1024]).unwrap();
            stream
                .set_read_timeout(Some(std::time::Duration::from_millis(50)))
                .unwrap();
            stream
        })
        .collect()
}

/// The replies the uploads got within `limit` (stopping early once `expected` came),
/// after half a second more for any other; by upload.
fn replies_within(uploads: &mut [std::net::TcpStream], expected: usize, limit: std::time::Duration) -> Vec<String> {
    use std::io::Read;
    let mut replies = vec![String::new(); uploads.len()];
    let start = std::time::Instant::now();
    let mut extra: Option<std::time::Instant> = None;
    loop {
        for (stream, reply) in uploads.iter_mut().zip(&mut replies) {
            let mut buffer = [0u8; 4096];
            if let Ok(n) = stream.read(&mut buffer) {
                reply.push_str(&String::from_utf8_lossy(&buffer[..n]));
            }
        }
        let answered = replies.iter().filter(|r| !r.is_empty()).count();
        if answered >= expected && extra.is_none() {
            extra = Some(std::time::Instant::now());
        }
        if extra.is_some_and(|t| t.elapsed() > std::time::Duration::from_millis(500)) || start.elapsed() > limit {
            return replies;
        }
    }
}

/// Issue 35: the 64 MiB bound was per request, and 40 large bodies in parallel took the
/// server to 3.8 GB. Bodies take their declared length from one budget before they are
/// read (3 MiB here, bodies of 1 MiB): of 8 stalled uploads 3 are read and 5 refused at
/// once (503, busy), and the budget is whole again once those 3 end.
#[test]
fn request_bodies_held_at_once_are_bounded_over_all_requests() {
    let (_dir, root) = served();
    let address = running(ServeOptions {
        root,
        max_request_bytes: 1 << 20,
        max_buffered_bytes: 3 << 20,
        ..Default::default()
    });
    let limit = std::time::Duration::from_secs(10);
    let mut uploads = stalled_uploads(address, 8, 1 << 20);
    let replies = replies_within(&mut uploads, 5, limit);
    let refused: Vec<&String> = replies.iter().filter(|r| !r.is_empty()).collect();
    assert_eq!(refused.len(), 5, "{replies:?}");
    for reply in refused {
        assert!(reply.starts_with("HTTP/1.1 503"), "{reply}");
        assert!(
            reply.contains("\"busy\"") && reply.contains("bound of 3 MiB"),
            "{reply}"
        );
    }
    // The three being read end (their clients leave): their shares come back.
    drop(uploads);
    std::thread::sleep(std::time::Duration::from_secs(1));
    let mut uploads = stalled_uploads(address, 4, 1 << 20);
    let replies = replies_within(&mut uploads, 1, limit);
    assert_eq!(replies.iter().filter(|r| !r.is_empty()).count(), 1, "{replies:?}");
    drop(uploads);
    std::thread::sleep(std::time::Duration::from_secs(1));
    // Small bodies take small shares: many fit beside each other, and a scene is solved.
    let mut uploads = stalled_uploads(address, 8, 64 << 10);
    let replies = replies_within(&mut uploads, 1, std::time::Duration::from_secs(1));
    assert!(replies.iter().all(String::is_empty), "{replies:?}");
    let scene = std::fs::read(repository().join("examples/bent-rectangle.json")).unwrap();
    assert!(http(address, "POST", "/api/bend", &scene).starts_with("HTTP/1.1 200"));
}

/// An upload of a body that declares no length (`Transfer-Encoding: chunked`) which sends
/// `first` bytes in one chunk and then stalls.
fn stalled_chunked_upload(address: std::net::SocketAddr, first: usize) -> std::net::TcpStream {
    use std::io::Write;
    let mut stream = std::net::TcpStream::connect(address).unwrap();
    write!(
        stream,
        "POST /api/bend HTTP/1.1\r\nHost: 127.0.0.1\r\nTransfer-Encoding: chunked\r\n\r\n{first:x}\r\n"
    )
    .unwrap();
    stream.write_all(&vec![b' '; first]).unwrap();
    stream.write_all(b"\r\n").unwrap();
    stream
        .set_read_timeout(Some(std::time::Duration::from_millis(50)))
        .unwrap();
    stream
}

/// `body` sent in chunks of `chunk` bytes with no declared length, answered in full.
fn chunked(address: std::net::SocketAddr, body: &[u8], chunk: usize) -> String {
    use std::io::{Read, Write};
    let mut stream = std::net::TcpStream::connect(address).unwrap();
    stream
        .set_read_timeout(Some(std::time::Duration::from_secs(60)))
        .unwrap();
    stream
        .write_all(
            b"POST /api/bend HTTP/1.1\r\nHost: 127.0.0.1\r\nTransfer-Encoding: chunked\r\nConnection: close\r\n\r\n",
        )
        .unwrap();
    for part in body.chunks(chunk) {
        // The server may refuse before the end: what it answered is read below.
        if write!(stream, "{:x}\r\n", part.len()).is_err() || stream.write_all(part).is_err() {
            break;
        }
        let _ = stream.write_all(b"\r\n");
    }
    let _ = stream.write_all(b"0\r\n\r\n");
    let mut reply = Vec::new();
    let _ = stream.read_to_end(&mut reply);
    String::from_utf8_lossy(&reply).into_owned()
}

/// Issue 35: a body that declares no length (chunked) took the largest body's share of
/// the bodies' budget before it was read, however small it was: with 1 MiB bodies and a
/// 3 MiB budget, 3 stalled chunked uploads of 1 KiB held the whole budget and the rest
/// were refused (503); with the defaults, 4 of them held 256 MiB. Its share now grows as
/// it arrives: 8 such uploads fit beside each other, a chunked scene is solved, and the
/// bounds still hold while it grows (past the largest body, 413; past the budget, 503).
#[test]
fn a_body_of_undeclared_length_takes_its_share_as_it_arrives() {
    let (_dir, root) = served();
    let address = running(ServeOptions {
        root,
        max_request_bytes: 1 << 20,
        max_buffered_bytes: 3 << 20,
        ..Default::default()
    });
    let mut uploads: Vec<std::net::TcpStream> = (0..8).map(|_| stalled_chunked_upload(address, 1024)).collect();
    let replies = replies_within(&mut uploads, 1, std::time::Duration::from_secs(1));
    assert!(replies.iter().all(String::is_empty), "{replies:?}");
    let scene = std::fs::read(repository().join("examples/bent-rectangle.json")).unwrap();
    let reply = chunked(address, &scene, 100);
    assert!(reply.starts_with("HTTP/1.1 200"), "{reply}");
    let reply = chunked(address, &vec![b' '; 2 << 20], 64 << 10);
    assert!(reply.starts_with("HTTP/1.1 413"), "{reply}");
    assert!(
        reply.contains("the request body: more than the 1048576 bytes a request may carry"),
        "{reply}"
    );
    drop(uploads);
    std::thread::sleep(std::time::Duration::from_secs(1));
    // Three bodies of 1 MiB so far (the largest, not past it): their buffers hold the
    // whole budget, and one byte of a fourth body does not fit.
    let mut large: Vec<std::net::TcpStream> = (0..3).map(|_| stalled_chunked_upload(address, 1 << 20)).collect();
    let replies = replies_within(&mut large, 1, std::time::Duration::from_secs(1));
    assert!(replies.iter().all(String::is_empty), "{replies:?}");
    let mut fourth = [stalled_chunked_upload(address, 1)];
    let replies = replies_within(&mut fourth, 1, std::time::Duration::from_secs(10));
    assert!(replies[0].starts_with("HTTP/1.1 503"), "{replies:?}");
    assert!(
        replies[0].contains("\"busy\"") && replies[0].contains("bound of 3 MiB"),
        "{replies:?}"
    );
    drop(large);
}

/// A JSON document of about `bytes` that a parser must read to its end before it fails
/// (an FFD scene of many deformations, then trailing garbage).
fn slow_to_parse(bytes: usize) -> String {
    let deformation = r#"{"name": "a step", "edits": [{"move": {"points": {"k": [3, 3]}, "by": [60, 0, 0]}}, {"transform": {"points": {"k": [1, 2]}, "scale": [0.8, 1.1, 1.0]}}]}"#;
    let count = bytes / (deformation.len() + 2);
    let mut text = String::with_capacity(bytes + 200);
    text.push_str(r#"{"model": {"procedural": {"kind": "duct"}}, "lattice": {"counts": [4, 4, 4]}, "deformations": ["#);
    for i in 0..count {
        if i > 0 {
            text.push_str(", ");
        }
        text.push_str(deformation);
    }
    text.push_str("]} x");
    text
}

/// Issue 35: `/api/ffd` parsed its scene on the async workers, outside the solve slots,
/// and every other request stalled for seconds. On one async worker, a request to a
/// route that does no work is answered while a large scene is still being parsed, for
/// every route that parses a large body (FFD scenes, relocations, saves).
#[tokio::test(flavor = "current_thread")]
async fn large_bodies_are_parsed_off_the_async_workers() {
    let (_dir, root) = served();
    let app = router(&ServeOptions {
        root,
        ..Default::default()
    })
    .unwrap();
    let body = slow_to_parse(24 << 20);
    for (method, uri) in [
        ("POST", "/api/ffd"),
        ("POST", "/api/relocate?from=a&to=b"),
        ("PUT", "/api/files/scenes/large.json"),
    ] {
        let heavy = {
            let (app, body) = (app.clone(), body.clone());
            tokio::spawn(async move { send(&app, method, uri, body).await })
        };
        // The heavy request starts (on the only async worker) while this one sleeps.
        tokio::time::sleep(std::time::Duration::from_millis(20)).await;
        let (status, _) = send(&app, "GET", "/api/nothing-here", Body::empty()).await;
        assert_eq!(status, StatusCode::NOT_FOUND);
        assert!(
            !heavy.is_finished(),
            "{uri}: the body was parsed on the async worker, which answered nothing else meanwhile"
        );
        let (status, reply) = heavy.await.unwrap();
        assert_eq!(
            status,
            StatusCode::BAD_REQUEST,
            "{uri}: {}",
            String::from_utf8_lossy(&reply)
        );
    }
}

/// Issue 35: saving a scene made its mode 600 (the atomic write's temporary file). A
/// save keeps the mode of the file it replaces; a new file gets what any program's new
/// file gets (0666 less the umask).
#[cfg(unix)]
#[tokio::test]
async fn a_save_keeps_the_file_mode() {
    use std::os::unix::fs::PermissionsExt;
    let (_dir, root) = served();
    let app = router(&ServeOptions {
        root: root.clone(),
        ..Default::default()
    })
    .unwrap();
    let mode = |path: &Path| std::fs::metadata(path).unwrap().permissions().mode() & 0o7777;
    let kept = root.join("scenes/bent-rectangle.json");
    for wanted in [0o644, 0o664, 0o640, 0o600] {
        std::fs::set_permissions(&kept, std::fs::Permissions::from_mode(wanted)).unwrap();
        let (status, body) = send(&app, "PUT", "/api/files/scenes/bent-rectangle.json", "{\"a\": 1}").await;
        assert_eq!(status, StatusCode::OK, "{}", String::from_utf8_lossy(&body));
        assert_eq!(std::fs::read_to_string(&kept).unwrap(), "{\"a\": 1}");
        assert_eq!(mode(&kept), wanted, "{wanted:o} became {:o}", mode(&kept));
    }
    let (status, _) = send(&app, "PUT", "/api/files/scenes/new.json", "{}").await;
    assert_eq!(status, StatusCode::OK);
    let control = root.join("scenes/control");
    std::fs::File::create(&control).unwrap();
    assert_eq!(mode(&root.join("scenes/new.json")), mode(&control));
    // No temporary file is left behind.
    let names: Vec<String> = std::fs::read_dir(root.join("scenes"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(names.iter().all(|n| !n.ends_with(".tmp")), "{names:?}");
}

/// The error message of a reply.
fn message(body: &[u8]) -> String {
    json(body)["error"]["message"].as_str().unwrap().to_string()
}

/// Issue 35: path checks followed a path before refusing it, so a refusal told whether a
/// file outside the served directory existed ("lies outside the directory /abs/root" or
/// "cannot open it"), and quoted where the served directory is; a NUL in a saved name
/// gave a 500 quoting a temporary path. Every refusal of a path outside is the same for
/// a file that exists and one that does not (by `..`, an absolute path, a symbolic link,
/// for opening, saving and a scene's assets), quotes the path as given and never the
/// served directory; a name with a control character is refused (400) naming its field.
#[tokio::test]
async fn refusals_of_paths_outside_do_not_tell_whether_a_file_exists() {
    let (dir, root) = served();
    let app = router(&ServeOptions {
        root: root.clone(),
        ..Default::default()
    })
    .unwrap();
    let outside = dir.path().canonicalize().unwrap();
    std::fs::copy(
        repository().join("examples/textures/grid-240x120mm.png"),
        outside.join("secret.png"),
    )
    .unwrap();
    std::fs::create_dir(outside.join("elsewhere")).unwrap();
    #[cfg(unix)]
    for (link, target) in [
        ("secret-link.json", "secret.json"),
        ("missing-link.json", "missing.json"),
        ("secret-dir", "elsewhere"),
        ("missing-dir", "nowhere"),
    ] {
        std::os::unix::fs::symlink(outside.join(target), root.join(link)).unwrap();
    }
    let encoded = |path: &Path| path.display().to_string().replace('/', "%2F");
    let refused = |status: StatusCode, body: &[u8], what: &str| {
        assert_eq!(
            status,
            StatusCode::BAD_REQUEST,
            "{what}: {}",
            String::from_utf8_lossy(body)
        );
        let text = message(body);
        assert!(
            !text.contains(&*root.to_string_lossy())
                && !text.contains(&*root.canonicalize().unwrap().to_string_lossy()),
            "{what} quotes where the served directory is: {text}"
        );
        text
    };
    let mut pairs = vec![
        (
            "GET",
            "/api/files/..%2Fsecret.json".to_string(),
            "/api/files/..%2Fmissing.json".to_string(),
        ),
        (
            "GET",
            "/api/files/scenes%2F..%2F..%2Fsecret.json".into(),
            "/api/files/scenes%2F..%2F..%2Fmissing.json".into(),
        ),
        (
            "GET",
            format!("/api/files/{}", encoded(&outside.join("secret.json"))),
            format!("/api/files/{}", encoded(&outside.join("missing.json"))),
        ),
        (
            "PUT",
            "/api/files/..%2Fsecret.json".into(),
            "/api/files/..%2Fmissing.json".into(),
        ),
    ];
    if cfg!(unix) {
        pairs.push((
            "GET",
            "/api/files/secret-link.json".into(),
            "/api/files/missing-link.json".into(),
        ));
        pairs.push((
            "PUT",
            "/api/files/secret-dir/saved.json".into(),
            "/api/files/missing-dir/saved.json".into(),
        ));
    }
    for (method, existing, missing) in &pairs {
        let (status, body) = send(&app, method, existing, "{}").await;
        let there = refused(status, &body, existing);
        let (status, body) = send(&app, method, missing, "{}").await;
        let absent = refused(status, &body, missing);
        assert_eq!(
            there.replace("secret", "missing"),
            absent,
            "{method} {existing} and {missing} are told apart"
        );
    }
    assert!(!outside.join("elsewhere/saved.json").exists());
    // A scene's assets: the texture of a bend scene.
    let scene: Value =
        serde_json::from_str(&std::fs::read_to_string(repository().join("examples/bent-rectangle.json")).unwrap())
            .unwrap();
    let texture = |path: String| {
        let mut scene = scene.clone();
        scene["texture"] = path.into();
        scene.to_string()
    };
    for (existing, missing) in [
        ("../secret.png".to_string(), "../missing.png".to_string()),
        (
            outside.join("secret.png").display().to_string(),
            outside.join("missing.png").display().to_string(),
        ),
    ] {
        let (status, body) = send(&app, "POST", "/api/bend", texture(existing.clone())).await;
        let there = refused(status, &body, &existing);
        assert!(there.starts_with("texture: "), "{there}");
        let (status, body) = send(&app, "POST", "/api/bend", texture(missing.clone())).await;
        let absent = refused(status, &body, &missing);
        assert_eq!(
            there.replace("secret", "missing"),
            absent,
            "{existing} and {missing} are told apart"
        );
    }
    // Control characters in names, refused naming the field; nothing is written.
    for (method, uri, field) in [
        ("PUT", "/api/files/scenes%2Fa%00b.json", "path"),
        ("PUT", "/api/files/scenes%2Fa%0Ab.json", "path"),
        ("GET", "/api/files/scenes%2Fa%00b.json", "path"),
        ("POST", "/api/bend?dir=scenes%00", "dir"),
        ("POST", "/api/relocate?from=a%1Fb&to=c", "from"),
        ("POST", "/api/mesh?name=a%7F.obj", "name"),
    ] {
        let (status, body) = send(&app, method, uri, "{}").await;
        let text = refused(status, &body, uri);
        assert!(
            text.starts_with(&format!("{field}: ")) && text.contains("control character"),
            "{uri}: {text}"
        );
        assert!(!text.contains("tmp"), "{uri}: {text}");
    }
    let names: Vec<String> = std::fs::read_dir(root.join("scenes"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["bent-rectangle.json"]);
}

/// The addresses of the fuzz target `serve_routes` (its `ROUTES` table).
fn fuzzed_routes() -> Vec<String> {
    let target = std::fs::read_to_string(repository().join("fuzz/fuzz_targets/serve_routes.rs")).unwrap();
    let table = target.split("const ROUTES").nth(1).unwrap().split("];").next().unwrap();
    table
        .lines()
        .filter_map(|line| {
            Some(
                line.trim()
                    .strip_prefix("(\"")?
                    .split("\", \"")
                    .nth(1)?
                    .split('"')
                    .next()?
                    .to_string(),
            )
        })
        .collect()
}

/// Issue 35: the fuzz target of the server's routes must exercise every route the
/// editor's front end sends a body to, for each mode, and every layout its mesh mode
/// offers; the "whole" layout (`charts=never`) was missing. Read from the front end's
/// own files, so a route or a layout added there without the fuzz target fails here.
#[test]
fn the_routes_fuzz_target_exercises_every_route_and_layout_the_editor_uses() {
    let web = repository().join("apps/serve/web/src");
    let script = std::fs::read_to_string(web.join("editor.js")).unwrap();
    let page = std::fs::read_to_string(web.join("index.html")).unwrap();
    let routes = fuzzed_routes();
    assert!(routes.len() >= 16, "{routes:?}");
    let fuzzed = |address: &str| routes.iter().any(|route| route.starts_with(address));
    // The addresses the script writes out (`/api/ffd${dirQuery()}`, `/api/mesh?${…}`):
    // up to the first substitution or query.
    for (at, _) in script.match_indices("/api/") {
        let address: String = script[at..]
            .chars()
            .take_while(|c| !matches!(c, '$' | '?' | '`' | '\'' | '"'))
            .collect();
        if address != "/api/" {
            assert!(fuzzed(&address), "{address} is not fuzzed: {routes:?}");
        }
    }
    // The addresses it makes from the mode (`/api/${mode}`, `/api/${state.mode}/file/…`).
    let modes: Vec<&str> = page
        .split("data-mode=\"")
        .skip(1)
        .filter_map(|rest| rest.split('"').next())
        .collect();
    assert!(modes.len() >= 5, "{modes:?}");
    for mode in modes {
        for address in [format!("/api/{mode}"), format!("/api/{mode}/file/")] {
            assert!(fuzzed(&address), "{address} is not fuzzed: {routes:?}");
        }
    }
    // The mesh mode's layouts (`auto`, the default, is the route without `charts`).
    let select = page
        .split("<select id=\"charts\">")
        .nth(1)
        .unwrap()
        .split("</select>")
        .next()
        .unwrap();
    for layout in select
        .split("value=\"")
        .skip(1)
        .filter_map(|rest| rest.split('"').next())
    {
        let fuzzed = routes.iter().any(|route| {
            route.starts_with("/api/mesh?")
                && (route.contains(&format!("charts={layout}")) || layout == "auto" && !route.contains("charts="))
        });
        assert!(fuzzed, "the mesh layout `{layout}` is not fuzzed: {routes:?}");
    }
}

/// The file list names each scene under the editor mode that opens it, recognised by
/// content, and lists no JSON that is no scene: a report, a package file, a schema, a
/// photo's truth file, a broken file.
#[tokio::test]
async fn scenes_are_listed_per_mode_and_other_json_files_are_not() {
    let (_dir, root) = served();
    for (from, to) in [
        ("examples/slit/chair.json", "scenes/chair.json"),
        ("examples/ffd/two-panels.json", "scenes/two-panels.json"),
        ("examples/photo/coffee-cup.json", "photo/cup.json"),
        (
            "examples/photo/synthetic/cone-ortho.truth.json",
            "photo/cone.truth.json",
        ),
        ("apps/serve/web/package.json", "package.json"),
        ("docs/schema/report.schema.json", "schema/report.schema.json"),
    ] {
        std::fs::create_dir_all(root.join(to).parent().unwrap()).unwrap();
        std::fs::copy(repository().join(from), root.join(to)).unwrap();
    }
    std::fs::create_dir_all(root.join("out")).unwrap();
    std::fs::write(root.join("out/report.json"), r#"{"command": "bend", "status": "ok"}"#).unwrap();
    std::fs::write(root.join("out/broken.json"), "{ not json").unwrap();
    let app = router(&ServeOptions {
        root,
        ..Default::default()
    })
    .unwrap();
    let (status, body) = send(&app, "GET", "/api/files", Body::empty()).await;
    assert_eq!(status, StatusCode::OK);
    let listing = json(&body);
    assert_eq!(
        listing["scenes"],
        serde_json::json!({
            "bend": ["scenes/bent-rectangle.json"],
            "slit": ["scenes/chair.json"],
            "ffd": ["scenes/two-panels.json"],
            "photo": ["photo/cup.json"],
        })
    );
    assert_eq!(
        listing["files"],
        serde_json::json!([
            "photo/cup.json",
            "scenes/bent-rectangle.json",
            "scenes/chair.json",
            "scenes/two-panels.json"
        ])
    );
}

/// Issue 38: an edit past the admissible shapes, asked to stop at their boundary, goes
/// part of the way (200, `moved_fraction` below 1, the reason it stopped); asked again
/// from there it cannot move at all (422 `at_boundary`); without the option it is
/// refused whole (422 `inadmissible`). Each region's frame comes with the reply, so the
/// desk's four legs are drawn (and dragged) where they are.
#[tokio::test]
async fn an_edit_past_the_admissible_shapes_stops_at_their_boundary() {
    let (_dir, root) = served();
    let app = router(&ServeOptions {
        root,
        ..Default::default()
    })
    .unwrap();
    let scene: Value = serde_json::from_str(
        r#"{"outline": [[0, -60], [240, -60], [240, 60], [0, 60]], "regions": [{"flat_start": [0, 0],
        "flat_direction": [1, 0], "curve": {"type": "bezier",
        "control_points": [[0, 0, 0], [80, 10, 0], [150, -10, 60], [170, 10, 120]]}}]}"#,
    )
    .unwrap();
    let edit = serde_json::json!({"kind": "move_control_point", "region": 0, "index": 2, "position": [150, -20, 60]});
    let ask = |scene: &Value, stop: bool| {
        serde_json::json!({"scene": scene, "edit": edit, "stop_at_boundary": stop}).to_string()
    };
    let (status, body) = send(&app, "POST", "/api/bend/edit", ask(&scene, false)).await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    assert_eq!(json(&body)["error"]["kind"], "inadmissible");
    let (status, body) = send(&app, "POST", "/api/bend/edit", ask(&scene, true)).await;
    assert_eq!(status, StatusCode::OK, "{}", String::from_utf8_lossy(&body));
    let reply = json(&body);
    let fraction = reply["moved_fraction"].as_f64().unwrap();
    assert!(fraction > 0.0 && fraction < 1.0, "{fraction}");
    assert!(reply["stopped_because"]
        .as_str()
        .unwrap()
        .contains("curve of regression"));
    assert_eq!(reply["report"]["status"], "ok");
    let y = reply["scene"]["regions"][0]["curve"]["control_points"][2][1]
        .as_f64()
        .unwrap();
    assert!((y - (-10.0 - 10.0 * fraction)).abs() < 1e-9, "{y}");
    // Asked again, the move creeps closer (each stop is within 1/256 of what is left to
    // go), until it cannot start at all: nothing moves, and it says so.
    let mut at = reply["scene"].clone();
    let mut ended = None;
    for _ in 0..12 {
        let (status, body) = send(&app, "POST", "/api/bend/edit", ask(&at, true)).await;
        if status == StatusCode::OK {
            let next = json(&body)["scene"].clone();
            let y_next = next["regions"][0]["curve"]["control_points"][2][1].as_f64().unwrap();
            let y_now = at["regions"][0]["curve"]["control_points"][2][1].as_f64().unwrap();
            assert!(y_next < y_now && y_now - y_next < 10.0 / 256.0, "{y_now} -> {y_next}");
            at = next;
        } else {
            ended = Some((status, json(&body)));
            break;
        }
    }
    let (status, error) = ended.expect("the creeping move reaches the boundary");
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    assert_eq!(error["error"]["kind"], "at_boundary", "{error}");
    // The desk: one frame per region, rigid, the legs' starts on the table's edges.
    let desk = std::fs::read(repository().join("examples/desk.json")).unwrap();
    let (status, body) = send(&app, "POST", "/api/bend", desk).await;
    assert_eq!(status, StatusCode::OK);
    let frames = json(&body)["region_frames"].as_array().unwrap().clone();
    assert_eq!(frames.len(), 4);
    let mut starts = Vec::new();
    for frame in &frames {
        let r: Vec<Vec<f64>> = serde_json::from_value(frame["rotation"].clone()).unwrap();
        for i in 0..3 {
            for j in 0..3 {
                let dot: f64 = (0..3).map(|k| r[i][k] * r[j][k]).sum();
                assert!((dot - f64::from(u8::from(i == j))).abs() < 1e-9, "{frame}");
            }
        }
        let t: Vec<f64> = serde_json::from_value(frame["translation"].clone()).unwrap();
        starts.push(t);
    }
    // The curves start at their origin: each leg's start is its frame's translation, on
    // the table's edge 150 mm from its middle (region 0 is placed as its curve says, so
    // the middle is 150 mm behind its start), all four different.
    let middle = [0, 1].map(|a| starts.iter().map(|t| t[a]).sum::<f64>() / 4.0);
    for t in &starts {
        assert!(
            ((t[0] - middle[0]).hypot(t[1] - middle[1]) - 150.0).abs() < 1e-6,
            "{starts:?}"
        );
        assert!(t[2].abs() < 1e-9, "{starts:?}");
    }
    for (a, b) in [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)] {
        assert!(
            (starts[a][0] - starts[b][0]).hypot(starts[a][1] - starts[b][1]) > 100.0,
            "{starts:?}"
        );
    }
}

/// Issue 38: a photograph chosen from disk is kept as `photos/NAME` in the served
/// directory and listed among the photographs; the same bytes again reuse it, other
/// bytes under the same name get the next free name; what is not a PNG or JPEG, or not
/// a plain name, is refused and nothing is written.
#[tokio::test]
async fn a_photograph_from_disk_is_kept_without_replacing_a_file() {
    let (_dir, root) = served();
    let app = router(&ServeOptions {
        root: root.clone(),
        ..Default::default()
    })
    .unwrap();
    let tube = std::fs::read(repository().join("examples/photo/tube.png")).unwrap();
    let coffee = std::fs::read(repository().join("examples/photo/coffee.png")).unwrap();
    let put = |name: &str, bytes: Vec<u8>| {
        let app = app.clone();
        let uri = format!("/api/photos/{name}");
        async move { send(&app, "PUT", &uri, bytes).await }
    };
    let (status, body) = put("shot.png", tube.clone()).await;
    assert_eq!(status, StatusCode::OK, "{}", String::from_utf8_lossy(&body));
    assert_eq!(json(&body)["path"], "photos/shot.png");
    assert_eq!(std::fs::read(root.join("photos/shot.png")).unwrap(), tube);
    let (_, body) = put("shot.png", tube.clone()).await;
    assert_eq!(json(&body)["path"], "photos/shot.png", "the same bytes: the same file");
    let (_, body) = put("shot.png", coffee.clone()).await;
    assert_eq!(json(&body)["path"], "photos/shot-2.png");
    assert_eq!(
        std::fs::read(root.join("photos/shot.png")).unwrap(),
        tube,
        "not replaced"
    );
    for (name, bytes, says) in [
        ("fake.png", b"GIF89a".to_vec(), "not a PNG image"),
        ("fake.jpg", tube.clone(), "not a JPEG image"),
        ("notes.txt", tube.clone(), "`.png`, `.jpg` or `.jpeg`"),
        (".png", tube.clone(), "not a plain file name"),
        ("..%2Fescape.png", tube.clone(), "not a plain file name"),
    ] {
        let (status, body) = put(name, bytes).await;
        assert_eq!(status, StatusCode::BAD_REQUEST, "{name}");
        let message = json(&body)["error"]["message"].as_str().unwrap().to_string();
        assert!(message.contains(says), "{name}: {message}");
    }
    assert!(!root.join("escape.png").exists() && !root.join("photos/fake.png").exists());
    let (_, body) = send(&app, "GET", "/api/files", Body::empty()).await;
    let photos = json(&body)["photos"].clone();
    assert_eq!(
        photos,
        serde_json::json!(["photos/shot-2.png", "photos/shot.png"]),
        "{photos}"
    );
}

/// `route` with `body`, asking for binary arrays: the reply's content type and body.
async fn send_for_arrays(app: &axum::Router, route: &str, body: Vec<u8>) -> (StatusCode, Option<String>, Vec<u8>) {
    let request = Request::builder()
        .method("POST")
        .uri(route)
        .header("Accept", "application/vnd.sheetform.arrays, application/json")
        .body(Body::from(body))
        .unwrap();
    let response = app.clone().oneshot(request).await.unwrap();
    let status = response.status();
    let kind = response
        .headers()
        .get("content-type")
        .map(|v| v.to_str().unwrap().to_string());
    let bytes = axum::body::to_bytes(response.into_body(), usize::MAX).await.unwrap();
    (status, kind, bytes.to_vec())
}

/// Only what changed (issue 38): the same solve asked again naming every array of the
/// first reply (path and hash) gets them all held, no array bytes at all; a stale hash
/// gets its array sent again.
#[tokio::test]
async fn arrays_the_client_holds_are_not_sent_again() {
    let (_dir, root) = served();
    let app = router(&ServeOptions {
        root,
        ..Default::default()
    })
    .unwrap();
    let gift = std::fs::read(repository().join("examples/meshes/gift-box.obj")).unwrap();
    let route = "/api/mesh?name=gift-box.obj&charts=net";
    let header_of = |body: &[u8]| -> (Value, usize) {
        let length = u32::from_le_bytes(body[4..8].try_into().unwrap()) as usize;
        (
            serde_json::from_slice(&body[8..8 + length]).unwrap(),
            (8 + length).div_ceil(8) * 8,
        )
    };
    let (status, _, first) = send_for_arrays(&app, route, gift.clone()).await;
    assert_eq!(status, StatusCode::OK);
    let (header, _) = header_of(&first);
    let entries = header["binary_arrays"].as_array().unwrap().clone();
    assert!(entries.len() >= 3, "{entries:?}");
    let pair = |e: &Value| format!("{}={}", e["path"].as_str().unwrap(), e["hash"].as_str().unwrap());
    let ask = |held: String| {
        let app = app.clone();
        let gift = gift.clone();
        async move {
            let request = Request::builder()
                .method("POST")
                .uri(route)
                .header("Accept", "application/vnd.sheetform.arrays, application/json")
                .header("X-Sheetform-Held-Arrays", held)
                .body(Body::from(gift))
                .unwrap();
            let response = app.oneshot(request).await.unwrap();
            assert_eq!(response.status(), StatusCode::OK);
            axum::body::to_bytes(response.into_body(), usize::MAX)
                .await
                .unwrap()
                .to_vec()
        }
    };
    let all: Vec<String> = entries.iter().map(pair).collect();
    let second = ask(all.join(",")).await;
    let (second_header, data_start) = header_of(&second);
    assert_eq!(second.len(), data_start, "no array bytes");
    for (a, b) in entries.iter().zip(second_header["binary_arrays"].as_array().unwrap()) {
        assert_eq!(b["held"], true, "{b}");
        assert_eq!((&a["path"], &a["hash"]), (&b["path"], &b["hash"]));
    }
    // The first array's hash stale: it alone is sent, its bytes those of the first reply.
    let mut stale = all.clone();
    stale[0] = format!("{}=0123456789abcdef", entries[0]["path"].as_str().unwrap());
    let third = ask(stale.join(",")).await;
    let (third_header, third_start) = header_of(&third);
    let sent: Vec<&Value> = third_header["binary_arrays"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| e["held"] != true)
        .collect();
    assert_eq!(sent.len(), 1);
    assert_eq!(sent[0]["path"], entries[0]["path"]);
    let (_, first_start) = header_of(&first);
    let bytes = third.len() - third_start;
    assert_eq!(
        &third[third_start..],
        &first[first_start..first_start + bytes],
        "the first array's bytes"
    );
}

/// Reads a binary-arrays reply as the editor does (the format in array_reply.rs): the
/// header, then each array put back at its path as JSON numbers (rulings as lists).
fn read_arrays_reply(body: &[u8]) -> Value {
    assert_eq!(&body[..4], b"SFA1");
    let length = u32::from_le_bytes(body[4..8].try_into().unwrap()) as usize;
    let mut reply: Value = serde_json::from_slice(&body[8..8 + length]).unwrap();
    let start = (8 + length).div_ceil(8) * 8;
    let entries = reply["binary_arrays"].as_array().unwrap().clone();
    for entry in &entries {
        let at = start + entry["offset"].as_u64().unwrap() as usize;
        assert_eq!(at % 8, 0);
        let n = entry["length"].as_u64().unwrap() as usize;
        let u32_at = |k: usize| u32::from_le_bytes(body[at + 4 * k..at + 4 * k + 4].try_into().unwrap());
        let value: Value = match entry["type"].as_str().unwrap() {
            "f64" => (0..n)
                .map(|k| f64::from_le_bytes(body[at + 8 * k..at + 8 * k + 8].try_into().unwrap()))
                .collect(),
            "u32" => (0..n).map(u32_at).collect(),
            "u32_lists" => (0..n)
                .map(|k| {
                    let (from, to) = (u32_at(k) as usize, u32_at(k + 1) as usize);
                    (from..to).map(|i| u32_at(n + 1 + i)).collect::<Value>()
                })
                .collect(),
            other => panic!("an array of type {other}"),
        };
        let path: Vec<&str> = entry["path"].as_str().unwrap().split('.').collect();
        let (last, owners) = path.split_last().unwrap();
        let owner = owners.iter().fold(&mut reply, |v, key| &mut v[*key]);
        assert_eq!(
            owner[*last],
            serde_json::json!([]),
            "{} left empty in the header",
            entry["path"]
        );
        owner[*last] = value;
    }
    reply.as_object_mut().unwrap().remove("binary_arrays");
    reply
}

/// Every solve the editor draws answers with binary arrays when asked: the same reply as
/// the JSON one, every number to the last bit; without the Accept header, JSON.
#[tokio::test]
async fn solves_answer_with_binary_arrays_equal_to_the_json_reply() {
    let (_dir, root) = served();
    let app = router(&ServeOptions {
        root,
        ..Default::default()
    })
    .unwrap();
    let scene: Value =
        serde_json::from_slice(&std::fs::read(repository().join("examples/bent-rectangle.json")).unwrap()).unwrap();
    let mut point = scene["regions"][0]["curve"]["control_points"][2].clone();
    point[2] = serde_json::json!(point[2].as_f64().unwrap() + 2.0);
    let edit = serde_json::json!({
        "scene": scene,
        "edit": {"kind": "move_control_point", "region": 0, "index": 2, "position": point},
        "stop_at_boundary": true,
    });
    let gift = std::fs::read(repository().join("examples/meshes/gift-box.obj")).unwrap();
    let cases: Vec<(&str, Vec<u8>, &[&str])> = vec![
        (
            "/api/bend",
            scene.to_string().into_bytes(),
            &["model.positions", "angle_defects_rad"],
        ),
        (
            "/api/bend/edit",
            edit.to_string().into_bytes(),
            &["model.rulings", "angle_defects_rad"],
        ),
        (
            "/api/slit",
            std::fs::read(repository().join("examples/slit/chair.json")).unwrap(),
            &["model.flat"],
        ),
        ("/api/mesh?name=gift-box.obj&charts=net", gift, &["model.face_pieces"]),
    ];
    for (route, body, taken) in cases {
        let (status, kind, binary) = send_for_arrays(&app, route, body.clone()).await;
        assert_eq!(status, StatusCode::OK, "{route}: {}", String::from_utf8_lossy(&binary));
        assert_eq!(kind.as_deref(), Some("application/vnd.sheetform.arrays"), "{route}");
        let mut from_binary = read_arrays_reply(&binary);
        let (status, plain) = send(&app, "POST", route, body).await;
        assert_eq!(status, StatusCode::OK);
        let mut from_json = json(&plain);
        // What differs from one solve to the next: the clocks.
        fn without_clocks(value: &mut Value) {
            match value {
                Value::Object(map) => {
                    for key in ["server_ms", "timings", "time_ms"] {
                        map.remove(key);
                    }
                    map.values_mut().for_each(without_clocks);
                }
                Value::Array(items) => items.iter_mut().for_each(without_clocks),
                _ => {}
            }
        }
        without_clocks(&mut from_binary);
        without_clocks(&mut from_json);
        for path in taken {
            let (owner, key) = path.split_once('.').map_or(("", *path), |(a, b)| (a, b));
            let array = if owner.is_empty() {
                &from_binary[key]
            } else {
                &from_binary[owner][key]
            };
            assert!(
                array.as_array().is_some_and(|a| !a.is_empty()),
                "{route}: {path} came back"
            );
        }
        assert!(
            from_binary == from_json,
            "{route}: the binary reply differs from the JSON one"
        );
        // (A box of integer coordinates is shorter in JSON; a bent sheet's full-precision
        // numbers are not.)
        if route.starts_with("/api/bend") {
            assert!(
                binary.len() < plain.len(),
                "{route}: {} bytes against {}",
                binary.len(),
                plain.len()
            );
        }
    }
    // An error stays JSON.
    let (status, kind, body) = send_for_arrays(&app, "/api/bend", b"{".to_vec()).await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert_eq!(kind.as_deref(), Some("application/json"));
    assert!(json(&body)["error"]["message"].is_string());
}

#[tokio::test]
async fn a_folder_of_photographs_does_not_hide_the_scenes() {
    // 2 100 photographs beside the served scene: the list holds its first 2 000 and says
    // it was cut short, and still lists the scene (whole), wherever the walk meets it.
    let (_dir, root) = served();
    std::fs::create_dir_all(root.join("camera")).unwrap();
    for k in 0..2_100 {
        std::fs::write(root.join(format!("camera/IMG_{k:04}.png")), b"").unwrap();
    }
    let app = router(&ServeOptions {
        root: root.clone(),
        ..Default::default()
    })
    .unwrap();
    let (status, body) = send(&app, "GET", "/api/files", Body::empty()).await;
    assert_eq!(status, StatusCode::OK);
    let listing = json(&body);
    assert_eq!(listing["files"], serde_json::json!(["scenes/bent-rectangle.json"]));
    assert_eq!(
        listing["scenes"]["bend"],
        serde_json::json!(["scenes/bent-rectangle.json"])
    );
    assert_eq!(listing["photos"].as_array().unwrap().len(), 2_000);
    assert_eq!(
        listing["truncated"],
        serde_json::json!({"scenes": false, "meshes": false, "photos": true})
    );
}

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
    let p: Vec<f64> = serde_json::from_value(model["positions"].clone()).unwrap();
    let f: Vec<f64> = serde_json::from_value(model["flat"].clone()).unwrap();
    let t: Vec<usize> = serde_json::from_value(model["triangles"].clone()).unwrap();
    assert_eq!(p.len() / 3, f.len() / 2);
    assert_eq!(reply["report"]["vertex_count"], p.len() / 3);
    // Every edge as long in 3D as in the pattern.
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
    assert!(worst < 1e-9, "isometry error {worst}");
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

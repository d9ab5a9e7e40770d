//! Any bytes as the body of each of the editor server's POST routes (and its save), and
//! as the edit of a bend scene, through `sheetform_serve::router` in-process: no panic,
//! and no reply that quotes one (a panic inside a solve is caught by the blocking pool
//! and answered as a 500 "the solve stopped: task … panicked"; in the FFD stream, as its
//! last line). The first byte picks the route.
//!
//! The server is built once (a served directory in the temporary directory, holding
//! the bundled coffee-cup photograph), so the FFD route's last design carries from one
//! input to the next, as it does in the editor.
#![no_main]

use axum::body::Body;
use axum::http::{Request, StatusCode};
use libfuzzer_sys::fuzz_target;
use std::path::Path;
use std::sync::OnceLock;
use tower::ServiceExt;

/// The routes, by the first byte: method and address. Every route the editor's front end
/// (`apps/serve/web/src/editor.js`) sends a body to, with the layouts its mesh mode offers
/// (auto, smooth, net, `never`, "whole", and `develop`, with a mirror plane too); new ones
/// are added at the end, so that the seeds of `tools/fuzz.sh` keep their routes.
const ROUTES: [(&str, &str); 20] = [
    ("POST", "/api/bend"),
    ("POST", "/api/bend/edit"),
    ("POST", "/api/slit"),
    ("POST", "/api/ffd"),
    ("POST", "/api/photo?dir=photo"),
    ("POST", "/api/mesh?name=m.obj"),
    ("POST", "/api/mesh?name=m.off&charts=net"),
    ("POST", "/api/mesh?name=m.ply&method=lscm"),
    ("POST", "/api/mesh?name=m.stl&charts=smooth"),
    ("POST", "/api/relocate?from=photo&to=elsewhere"),
    ("PUT", "/api/files/fuzzed.json"),
    ("POST", "/api/bend/file/model.obj"),
    ("POST", "/api/slit/file/model.obj"),
    ("POST", "/api/ffd/file/report.json"),
    ("POST", "/api/photo/file/model.obj?dir=photo"),
    ("POST", "/api/mesh/file/model.obj?name=m.obj"),
    ("POST", "/api/mesh?name=m.obj&charts=never"),
    ("POST", "/api/mesh?name=m.obj&charts=develop"),
    ("POST", "/api/mesh?name=m.obj&charts=develop&mirror=x"),
    ("PUT", "/api/photos/fuzzed.png"),
];

/// The bend scene an edit is applied to.
const EDITED_SCENE: &str = include_str!("../../examples/bent-rectangle.json");

struct Served {
    runtime: tokio::runtime::Runtime,
    app: axum::Router,
}

fn served() -> &'static Served {
    static SERVED: OnceLock<Served> = OnceLock::new();
    SERVED.get_or_init(|| {
        let root = std::env::temp_dir().join(format!("sheetform-fuzz-served-{}", std::process::id()));
        let photos = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/photo");
        std::fs::create_dir_all(root.join("photo")).expect("a served directory");
        std::fs::copy(photos.join("coffee.png"), root.join("photo/coffee.png")).expect("the photograph");
        let app = sheetform_serve::router(&sheetform_serve::ServeOptions {
            root,
            ..Default::default()
        })
        .expect("the router");
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .expect("a runtime");
        Served { runtime, app }
    })
}

/// Panics when a reply's error says its solve stopped (a panic caught by the pool).
fn assert_no_panic(route: &str, status: StatusCode, message: &str) {
    assert!(
        !message.starts_with("the solve stopped") && !(status.is_server_error() && message.contains("panicked")),
        "{route}: {status} {message}"
    );
}

fuzz_target!(|data: &[u8]| {
    let Some((&choice, bytes)) = data.split_first() else {
        return;
    };
    let (method, route) = ROUTES[usize::from(choice) % ROUTES.len()];
    let body = if route == "/api/bend/edit" {
        // The bytes are the edit's JSON.
        let mut body = format!("{{\"scene\": {EDITED_SCENE}, \"edit\": ").into_bytes();
        body.extend_from_slice(bytes);
        body.push(b'}');
        body
    } else {
        bytes.to_vec()
    };
    let served = served();
    served.runtime.block_on(async {
        let request = Request::builder()
            .method(method)
            .uri(route)
            .body(Body::from(body))
            .expect("a request");
        let response = served.app.clone().oneshot(request).await.expect("the router answers");
        let status = response.status();
        let reply = axum::body::to_bytes(response.into_body(), usize::MAX)
            .await
            .expect("the reply's body");
        // One JSON reply, or NDJSON lines (the FFD route): each error's message.
        for line in reply.split(|&b| b == b'\n') {
            let Ok(value) = serde_json::from_slice::<serde_json::Value>(line) else {
                continue;
            };
            if let Some(message) = value["error"]["message"].as_str() {
                assert_no_panic(route, status, message);
            }
        }
    });
});

//! The front end, embedded in the binary: our files from `web/src/` and the pinned
//! three.js files `build.rs` copies from npm.

use crate::AppState;
use axum::http::{header, StatusCode, Uri};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::Router;
use std::sync::Arc;

/// `(served path, content type, bytes)`.
const ASSETS: [(&str, &str, &[u8]); 6] = [
    (
        "index.html",
        "text/html; charset=utf-8",
        include_bytes!("../web/src/index.html"),
    ),
    (
        "editor.js",
        "text/javascript; charset=utf-8",
        include_bytes!("../web/src/editor.js"),
    ),
    (
        "editor.css",
        "text/css; charset=utf-8",
        include_bytes!("../web/src/editor.css"),
    ),
    (
        "vendor/three/three.module.js",
        "text/javascript; charset=utf-8",
        include_bytes!(concat!(env!("OUT_DIR"), "/vendor/three/three.module.js")),
    ),
    (
        "vendor/three/three.core.js",
        "text/javascript; charset=utf-8",
        include_bytes!(concat!(env!("OUT_DIR"), "/vendor/three/three.core.js")),
    ),
    (
        "vendor/three/addons/controls/OrbitControls.js",
        "text/javascript; charset=utf-8",
        include_bytes!(concat!(
            env!("OUT_DIR"),
            "/vendor/three/addons/controls/OrbitControls.js"
        )),
    ),
];

pub(crate) fn routes() -> Router<Arc<AppState>> {
    Router::new()
        .route("/", get(|| async { asset("index.html") }))
        .fallback(get(|uri: Uri| async move { asset(uri.path().trim_start_matches('/')) }))
}

fn asset(path: &str) -> Response {
    match ASSETS.iter().find(|(name, _, _)| *name == path) {
        Some((_, content_type, bytes)) => (
            [
                (header::CONTENT_TYPE, *content_type),
                (header::CACHE_CONTROL, "no-cache"),
            ],
            *bytes,
        )
            .into_response(),
        None => (StatusCode::NOT_FOUND, "not found").into_response(),
    }
}

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

/// Whether the editor's three.js is embedded (`build.rs` goes on without it, with a
/// warning, where npm is missing).
pub const EDITOR_EMBEDDED: bool = !cfg!(sheetform_without_three);

/// The page served instead of the editor by a binary built without three.js.
const WITHOUT_EDITOR: &str = "<!doctype html><meta charset=utf-8><title>sheetform</title>\
<h1>sheetform serve: built without its editor</h1>\
<p>This binary was built where npm was missing, so the web editor's three.js was not \
embedded. The server's API (<code>/api/…</code>) and every command work.</p>\
<p>For the editor, install Node.js and npm, then build again (<code>cargo build --release</code>; \
or <code>npm ci --prefix apps/serve/web</code> first).</p>";

pub(crate) fn routes() -> Router<Arc<AppState>> {
    Router::new()
        .route("/", get(|| async { asset("index.html") }))
        .fallback(get(|uri: Uri| async move { asset(uri.path().trim_start_matches('/')) }))
}

fn asset(path: &str) -> Response {
    asset_of(path, EDITOR_EMBEDDED)
}

/// [`asset`] of a binary with (`embedded`) or without the editor's three.js.
fn asset_of(path: &str, embedded: bool) -> Response {
    if !embedded && (path == "index.html" || path.starts_with("vendor/")) {
        let status = if path == "index.html" {
            StatusCode::OK
        } else {
            StatusCode::NOT_FOUND
        };
        return (
            status,
            [(header::CONTENT_TYPE, "text/html; charset=utf-8")],
            WITHOUT_EDITOR,
        )
            .into_response();
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    fn body(response: Response) -> (StatusCode, String) {
        let status = response.status();
        let bytes = tokio::runtime::Builder::new_current_thread()
            .build()
            .unwrap()
            .block_on(axum::body::to_bytes(response.into_body(), usize::MAX))
            .unwrap();
        (status, String::from_utf8_lossy(&bytes).into_owned())
    }

    /// Built where npm was missing: the editor page says so and how to get it, three.js is
    /// not found, our other files are still served; built with it, the editor.
    #[test]
    fn a_binary_built_without_npm_says_so_instead_of_the_editor() {
        let (status, page) = body(asset_of("index.html", false));
        assert_eq!(status, StatusCode::OK);
        assert!(
            page.contains("built without its editor") && page.contains("npm"),
            "{page}"
        );
        let (status, _) = body(asset_of("vendor/three/three.module.js", false));
        assert_eq!(status, StatusCode::NOT_FOUND);
        let (status, script) = body(asset_of("editor.js", false));
        assert_eq!(status, StatusCode::OK);
        assert!(!script.is_empty());
        let (status, page) = body(asset_of("index.html", true));
        assert_eq!(status, StatusCode::OK);
        assert!(page.contains("sheetform editor"), "{page}");
    }
}

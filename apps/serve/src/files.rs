//! Listing scene and mesh files, opening them, and saving scene files, confined to the served directory through the
//! pipeline's [`AssetResolver`] (the same rules as the files a scene may read: no
//! absolute or escaping path, also not through a symbolic link; regular files only;
//! bounded sizes).

use crate::api::{ApiBody, ApiError};
use crate::AppState;
use axum::extract::{Path, State};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::{Json, Router};
use sheetform::pipeline::{AssetResolver, PipelineError};
use std::path::PathBuf;
use std::sync::Arc;

/// Most scene files listed.
const MAX_LISTED_FILES: usize = 2_000;
/// Deepest directory level listed below the served directory.
const MAX_LISTED_DEPTH: usize = 4;

pub(crate) fn routes() -> Router<Arc<AppState>> {
    Router::new()
        .route("/api/files", get(list))
        .route("/api/files/{*path}", get(open).put(save))
        .route("/api/relocate", axum::routing::post(relocate))
}

/// `?from=DIR&to=DIR`: a scene file's directory before and after a "save as", both
/// inside the served one.
#[derive(Debug, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RelocateQuery {
    from: String,
    to: String,
}

/// `POST /api/relocate?from=…&to=…` with a scene: the asset paths to rewrite so that the
/// scene, saved in `to`, names the same files it named in `from`
/// (`pipeline::relocated_scene_assets`). The editor applies them to its scene (keeping
/// the file's field order) before it saves.
async fn relocate(
    crate::api::ApiQuery(query): crate::api::ApiQuery<RelocateQuery>,
    ApiBody(body): ApiBody<String>,
) -> Result<Response, ApiError> {
    for (name, dir) in [("from", &query.from), ("to", &query.to)] {
        if !dir.is_empty() && !sheetform::io::is_plain_relative(dir) {
            return Err(ApiError::invalid(format!(
                "{name}: `{}` is not a directory inside the served one",
                sheetform::geometry::shortened_message(dir)
            )));
        }
    }
    let scene: serde_json::Value =
        serde_json::from_str(&body).map_err(|e| ApiError::invalid(format!("not a JSON document: {e}")))?;
    let moves = sheetform::pipeline::relocated_scene_assets(
        &scene,
        std::path::Path::new(&query.from),
        std::path::Path::new(&query.to),
    );
    Ok(Json(serde_json::json!({ "moves": moves })).into_response())
}

/// Extensions of the mesh files the mesh mode reads.
pub(crate) const MESH_EXTENSIONS: [&str; 4] = ["obj", "ply", "stl", "off"];

/// Whether `name` is a mesh file by its extension.
fn is_mesh(name: &str) -> bool {
    name.rsplit_once('.')
        .is_some_and(|(_, extension)| MESH_EXTENSIONS.contains(&extension.to_ascii_lowercase().as_str()))
}

/// The scene files (`*.json`) and the meshes (`*.obj`, `*.ply`, `*.stl`, `*.off`) below
/// the served directory, as relative paths with `/`, sorted; hidden directories,
/// `target` and `node_modules` are skipped.
fn listed_files(root: &std::path::Path) -> (Vec<String>, Vec<String>) {
    let (mut scenes, mut meshes) = (Vec::new(), Vec::new());
    let mut pending = vec![(PathBuf::new(), 0usize)];
    'walk: while let Some((relative, depth)) = pending.pop() {
        let Ok(entries) = std::fs::read_dir(root.join(&relative)) else {
            continue;
        };
        for entry in entries.flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            let Ok(kind) = entry.file_type() else { continue };
            let path = relative.join(&name);
            if kind.is_dir() {
                if depth < MAX_LISTED_DEPTH && !name.starts_with('.') && name != "target" && name != "node_modules" {
                    pending.push((path, depth + 1));
                }
                continue;
            }
            if !kind.is_file() || name.starts_with('.') {
                continue;
            }
            let list = if name.ends_with(".json") {
                &mut scenes
            } else if is_mesh(&name) {
                &mut meshes
            } else {
                continue;
            };
            list.push(
                path.components()
                    .map(|c| c.as_os_str().to_string_lossy())
                    .collect::<Vec<_>>()
                    .join("/"),
            );
            if scenes.len() + meshes.len() >= MAX_LISTED_FILES {
                break 'walk;
            }
        }
    }
    scenes.sort();
    meshes.sort();
    (scenes, meshes)
}

async fn list(State(state): State<Arc<AppState>>) -> Response {
    let root = state.root.clone();
    let (files, meshes) = tokio::task::spawn_blocking(move || listed_files(&root))
        .await
        .unwrap_or_default();
    Json(serde_json::json!({ "files": files, "meshes": meshes })).into_response()
}

fn resolver(state: &AppState) -> AssetResolver {
    AssetResolver::new(&state.root).with_max_bytes(sheetform::io::MAX_SCENE_FILE_BYTES)
}

/// The content type of an image a scene names (photographs, textures), by extension.
fn image_type(name: &str) -> Option<&'static str> {
    match name.rsplit_once('.')?.1.to_ascii_lowercase().as_str() {
        "png" => Some("image/png"),
        "jpg" | "jpeg" => Some("image/jpeg"),
        _ => None,
    }
}

async fn open(State(state): State<Arc<AppState>>, Path(path): Path<String>) -> Result<Response, ApiError> {
    let resolver = resolver(&state);
    let image = image_type(&path);
    let mesh = is_mesh(&path) || image.is_some();
    let bytes = tokio::task::spawn_blocking(move || -> Result<Vec<u8>, ApiError> {
        let bytes = resolver.read(&path, "path")?;
        // Scenes are JSON text; meshes and images go out as they are.
        if !mesh && std::str::from_utf8(&bytes).is_err() {
            return Err(ApiError::invalid(format!("`{path}` is not UTF-8 text")));
        }
        Ok(bytes)
    })
    .await
    .map_err(|e| ApiError::invalid(e.to_string()))??;
    let content_type = image.unwrap_or(if mesh {
        "application/octet-stream"
    } else {
        "application/json"
    });
    Ok(([(axum::http::header::CONTENT_TYPE, content_type)], bytes).into_response())
}

async fn save(
    State(state): State<Arc<AppState>>,
    Path(path): Path<String>,
    ApiBody(body): ApiBody<String>,
) -> Result<Response, ApiError> {
    if !path.ends_with(".json") {
        return Err(ApiError::invalid("scenes are saved as `.json` files"));
    }
    if let Err(e) = serde_json::from_str::<serde_json::Value>(&body) {
        return Err(ApiError::invalid(format!("not a JSON document: {e}")));
    }
    let resolver = resolver(&state);
    tokio::task::spawn_blocking(move || -> Result<(), ApiError> {
        let full = resolver.resolve_for_writing(&path, "path")?;
        sheetform::io::write_atomic(&full, body.as_bytes()).map_err(|e| ApiError::from(PipelineError::from(e)))?;
        Ok(())
    })
    .await
    .map_err(|e| ApiError::invalid(e.to_string()))??;
    Ok(Json(serde_json::json!({ "saved": true })).into_response())
}

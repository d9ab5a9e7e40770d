//! Listing scene and mesh files, opening them, and saving scene files, confined to the served directory through the
//! pipeline's [`AssetResolver`] (the same rules as the files a scene may read: no
//! absolute or escaping path, also not through a symbolic link; regular files only;
//! bounded sizes).
//!
//! A path that names no file inside the served directory gets one refusal whether it is
//! missing or lies outside, quoting the path as the client gave it (never where the
//! served directory is), and a name with a control character is refused before any file
//! is looked at. A save replaces the file atomically and keeps its mode (and owner where
//! the OS allows); a new file gets the mode any program's new file gets (0666 less the
//! umask).

use crate::api::{not_inside, printable, solve_stopped, ApiBody, ApiError};
use crate::AppState;
use axum::extract::{Path, State};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::{Json, Router};
use sheetform::pipeline::AssetResolver;
use std::path::PathBuf;
use std::sync::Arc;

/// Most files of each kind listed (scenes, meshes, photographs: a folder of photographs
/// does not hide the scenes), the JSON files looked at counting as scenes.
const MAX_LISTED_FILES: usize = 2_000;
/// Most directory entries looked at in one listing (the walk's own bound: a tree of
/// many small files is not walked whole).
const MAX_WALKED_ENTRIES: usize = 100_000;
/// Deepest directory level listed below the served directory.
const MAX_LISTED_DEPTH: usize = 4;

pub(crate) fn routes() -> Router<Arc<AppState>> {
    Router::new()
        .route("/api/files", get(list))
        .route("/api/files/{*path}", get(open).put(save))
        .route("/api/relocate", axum::routing::post(relocate))
        .route("/api/photos/{name}", axum::routing::put(upload_photo))
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
        printable(name, dir)?;
        if !dir.is_empty() && !sheetform::io::is_plain_relative(dir) {
            return Err(ApiError::invalid(format!(
                "{name}: `{}` is not a directory inside the served one",
                sheetform::geometry::shortened_message(dir)
            )));
        }
    }
    // Parsed on the blocking pool: a large body takes a while.
    let moves = tokio::task::spawn_blocking(move || -> Result<_, ApiError> {
        let scene: serde_json::Value =
            serde_json::from_str(&body).map_err(|e| ApiError::invalid(format!("not a JSON document: {e}")))?;
        Ok(sheetform::pipeline::relocated_scene_assets(
            &scene,
            std::path::Path::new(&query.from),
            std::path::Path::new(&query.to),
        ))
    })
    .await
    .map_err(|e| solve_stopped(&e))??;
    Ok(Json(serde_json::json!({ "moves": moves })).into_response())
}

/// Extensions of the mesh files the mesh mode reads.
pub(crate) const MESH_EXTENSIONS: [&str; 4] = ["obj", "ply", "stl", "off"];

/// Whether `name` is a mesh file by its extension.
fn is_mesh(name: &str) -> bool {
    name.rsplit_once('.')
        .is_some_and(|(_, extension)| MESH_EXTENSIONS.contains(&extension.to_ascii_lowercase().as_str()))
}

/// Largest JSON file read to tell which editor mode it opens in when the files are listed
/// (a scene is a few KiB; a larger JSON is not listed).
const MAX_LISTED_SCENE_BYTES: u64 = 4 << 20;
/// Most bytes of JSON read over one listing (past it, the remaining JSON files are not
/// listed): the editor lists after every save, and a tree of reports is not read whole.
const MAX_LISTING_BYTES: u64 = 64 << 20;

/// The editor mode a JSON document opens in, recognised by its content as the editor's
/// `load` does: `bend` (an `outline` and `regions`), `slit` (a `sheet` object), `ffd` (a
/// `model` object and `deformations`), `photo` (an `image` object and `curves`); `None`
/// for any other JSON (a report, a schema, package.json, a photo's truth file).
fn scene_mode(text: &str) -> Option<&'static str> {
    let value: serde_json::Value = serde_json::from_str(text).ok()?;
    let object = value.as_object()?;
    let array = |key: &str| object.get(key).is_some_and(serde_json::Value::is_array);
    let map = |key: &str| object.get(key).is_some_and(serde_json::Value::is_object);
    if array("outline") && array("regions") {
        Some("bend")
    } else if map("sheet") {
        Some("slit")
    } else if map("model") && array("deformations") {
        Some("ffd")
    } else if map("image") && array("curves") {
        Some("photo")
    } else {
        None
    }
}

/// What [`listed_files`] finds.
#[derive(Default)]
struct Listed {
    /// Scenes with the editor mode each opens in.
    scenes: Vec<(String, &'static str)>,
    /// Meshes.
    meshes: Vec<String>,
    /// Photographs.
    photos: Vec<String>,
    /// Which lists a bound cut short (`[scenes, meshes, photos]`): [`MAX_LISTED_FILES`]
    /// of that kind, `MAX_LISTING_BYTES` (scenes), [`MAX_WALKED_ENTRIES`] (all three).
    truncated: [bool; 3],
}

/// The scenes (`*.json` files a mode of the editor opens, by content: `(path, mode)`),
/// the meshes (`*.obj`, `*.ply`, `*.stl`, `*.off`) and the photographs (`*.png`, `*.jpg`,
/// `*.jpeg`) below the served directory, as relative paths with `/`, sorted; hidden
/// directories, `target` and `node_modules` are skipped, and JSON files that are no
/// scene (reports, schemas, package files) are not listed.
fn listed_files(root: &std::path::Path) -> Listed {
    let mut listed = Listed::default();
    let Listed {
        scenes,
        meshes,
        photos,
        truncated,
    } = &mut listed;
    // Every JSON file looked at counts towards MAX_LISTED_FILES, listed or not; every
    // entry towards MAX_WALKED_ENTRIES.
    let (mut examined, mut bytes_read, mut walked) = (0usize, 0u64, 0usize);
    let mut pending = vec![(PathBuf::new(), 0usize)];
    'walk: while let Some((relative, depth)) = pending.pop() {
        let Ok(entries) = std::fs::read_dir(root.join(&relative)) else {
            continue;
        };
        for entry in entries.flatten() {
            walked += 1;
            if walked > MAX_WALKED_ENTRIES {
                *truncated = [true; 3];
                break 'walk;
            }
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
            let relative_name = path
                .components()
                .map(|c| c.as_os_str().to_string_lossy())
                .collect::<Vec<_>>()
                .join("/");
            if name.ends_with(".json") {
                if examined >= MAX_LISTED_FILES {
                    truncated[0] = true;
                    continue;
                }
                examined += 1;
                let size = entry.metadata().map_or(u64::MAX, |m| m.len());
                let readable = size <= MAX_LISTED_SCENE_BYTES && bytes_read + size <= MAX_LISTING_BYTES;
                if readable {
                    bytes_read += size;
                } else if size <= MAX_LISTED_SCENE_BYTES {
                    truncated[0] = true;
                }
                let mode = readable
                    .then(|| std::fs::read_to_string(root.join(&path)).ok())
                    .flatten()
                    .and_then(|text| scene_mode(&text));
                match mode {
                    Some(mode) => scenes.push((relative_name, mode)),
                    None => continue,
                }
            } else {
                let (list, kind) = if is_mesh(&name) {
                    (&mut *meshes, 1)
                } else if image_type(&name).is_some() {
                    (&mut *photos, 2)
                } else {
                    continue;
                };
                if list.len() >= MAX_LISTED_FILES {
                    truncated[kind] = true;
                } else {
                    list.push(relative_name);
                }
            }
        }
    }
    scenes.sort();
    meshes.sort();
    photos.sort();
    listed
}

/// `GET /api/files`: `files` (every scene), `scenes` (per editor mode), `meshes` and
/// `photos` (PNG and JPEG images, to annotate), and `truncated`: for `scenes`, `meshes`
/// and `photos`, whether a bound of the listing left files of that kind out.
async fn list(State(state): State<Arc<AppState>>) -> Response {
    let root = state.root.clone();
    let Listed {
        scenes,
        meshes,
        photos,
        truncated,
    } = tokio::task::spawn_blocking(move || listed_files(&root))
        .await
        .unwrap_or_default();
    let mut by_mode: serde_json::Map<String, serde_json::Value> = ["bend", "slit", "ffd", "photo"]
        .iter()
        .map(|m| (m.to_string(), serde_json::json!([])))
        .collect();
    for (path, mode) in &scenes {
        if let Some(serde_json::Value::Array(list)) = by_mode.get_mut(*mode) {
            list.push(serde_json::json!(path));
        }
    }
    let files: Vec<&String> = scenes.iter().map(|(path, _)| path).collect();
    Json(serde_json::json!({
        "files": files, "scenes": by_mode, "meshes": meshes, "photos": photos,
        "truncated": { "scenes": truncated[0], "meshes": truncated[1], "photos": truncated[2] },
    }))
    .into_response()
}

/// The directory inside the served one where photographs chosen from disk are kept.
const PHOTO_DIRECTORY: &str = "photos";
/// Most copies of one photograph's name tried (`name-2.png`, `name-3.png`, …).
const MAX_PHOTO_NAME_TRIES: usize = 1_000;

/// `PUT /api/photos/{name}` with a PNG or JPEG: the photograph chosen from disk (or
/// dropped) in the editor, kept as `photos/NAME` in the served directory so that an
/// annotation can name it. A file already there is never replaced: the photograph gets
/// the next free name (`NAME-2.png`, …), or the existing one's when it is the same
/// bytes. Answers `{"path": …}`.
async fn upload_photo(
    State(state): State<Arc<AppState>>,
    Path(name): Path<String>,
    ApiBody(body): ApiBody<axum::body::Bytes>,
) -> Result<Response, ApiError> {
    printable("name", &name)?;
    let Some((stem, extension)) = name.rsplit_once('.') else {
        return Err(ApiError::invalid(
            "name: a photograph is a `.png`, `.jpg` or `.jpeg` file",
        ));
    };
    let kind =
        image_type(&name).ok_or_else(|| ApiError::invalid("name: a photograph is a `.png`, `.jpg` or `.jpeg` file"))?;
    if stem.is_empty() || name.contains(['/', '\\']) || name.starts_with('.') {
        return Err(ApiError::invalid(format!(
            "name: `{}` is not a plain file name",
            sheetform::geometry::quoted_token(&name)
        )));
    }
    let signature: &[u8] = if kind == "image/png" {
        b"\x89PNG\r\n\x1a\n"
    } else {
        b"\xff\xd8\xff"
    };
    if !body.starts_with(signature) {
        return Err(ApiError::invalid(format!(
            "`{}` is not a {} image (its first bytes say otherwise)",
            sheetform::geometry::quoted_token(&name),
            if kind == "image/png" { "PNG" } else { "JPEG" }
        )));
    }
    let root = state.root.clone();
    let (stem, extension) = (stem.to_string(), extension.to_string());
    let path = tokio::task::spawn_blocking(move || -> Result<String, ApiError> {
        let directory = root.join(PHOTO_DIRECTORY);
        let failed = |e: std::io::Error| {
            ApiError::new(
                axum::http::StatusCode::INTERNAL_SERVER_ERROR,
                "output",
                format!(
                    "the photograph cannot be kept in `{PHOTO_DIRECTORY}/`: {}",
                    os_reason(&e)
                ),
            )
        };
        std::fs::create_dir_all(&directory).map_err(failed)?;
        // A link out of the served directory is not followed.
        if !directory.canonicalize().is_ok_and(|full| full.starts_with(&root)) {
            return Err(ApiError::invalid(not_inside("path", PHOTO_DIRECTORY)));
        }
        for k in 1..=MAX_PHOTO_NAME_TRIES {
            let file = if k == 1 {
                format!("{stem}.{extension}")
            } else {
                format!("{stem}-{k}.{extension}")
            };
            let full = directory.join(&file);
            let relative = format!("{PHOTO_DIRECTORY}/{file}");
            if let Ok(meta) = std::fs::symlink_metadata(&full) {
                // The same photograph already kept: its name (sizes first, so that no
                // other file is read whole).
                let same = meta.is_file()
                    && meta.len() == body.len() as u64
                    && std::fs::read(&full).is_ok_and(|bytes| bytes == body.as_ref());
                if same {
                    return Ok(relative);
                }
                continue;
            }
            // Written beside it, then moved in only if the name is still free: two
            // uploads of one name at once never replace each other.
            match write_new(&directory, &full, &body) {
                Ok(()) => return Ok(relative),
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
                Err(e) => return Err(failed(e)),
            }
        }
        Err(ApiError::invalid(format!(
            "name: {MAX_PHOTO_NAME_TRIES} photographs named `{stem}` are kept already"
        )))
    })
    .await
    .map_err(|e| solve_stopped(&e))??;
    Ok(Json(serde_json::json!({ "path": path })).into_response())
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

/// The file `path` names inside the served directory, or the one refusal
/// ([`not_inside`]) whether it is missing or lies outside (by `..`, an absolute path or a
/// symbolic link): the path is checked as written before it is followed.
fn inside(root: &std::path::Path, path: &str) -> Result<PathBuf, ApiError> {
    printable("path", path)?;
    let refuse = || ApiError::invalid(not_inside("path", path));
    if !sheetform::io::is_plain_relative(path) {
        return Err(refuse());
    }
    let full = root.join(path).canonicalize().map_err(|_| refuse())?;
    if full.starts_with(root) {
        Ok(full)
    } else {
        Err(refuse())
    }
}

async fn open(State(state): State<Arc<AppState>>, Path(path): Path<String>) -> Result<Response, ApiError> {
    let resolver = resolver(&state);
    let root = state.root.clone();
    let image = image_type(&path);
    let mesh = is_mesh(&path) || image.is_some();
    let bytes = tokio::task::spawn_blocking(move || -> Result<Vec<u8>, ApiError> {
        inside(&root, &path)?;
        let bytes = resolver.read(&path, "path")?;
        // Scenes are JSON text; meshes and images go out as they are.
        if !mesh && std::str::from_utf8(&bytes).is_err() {
            return Err(ApiError::invalid(format!(
                "`{}` is not UTF-8 text",
                sheetform::geometry::quoted_token(&path)
            )));
        }
        Ok(bytes)
    })
    .await
    .map_err(|e| solve_stopped(&e))??;
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
    printable("path", &path)?;
    if !path.ends_with(".json") {
        return Err(ApiError::invalid("scenes are saved as `.json` files"));
    }
    if !sheetform::io::is_plain_relative(&path) {
        return Err(ApiError::invalid(not_inside("path", &path)));
    }
    let resolver = resolver(&state);
    let root = state.root.clone();
    tokio::task::spawn_blocking(move || -> Result<(), ApiError> {
        // Parsed on the blocking pool: a large body takes a while.
        if let Err(e) = serde_json::from_str::<serde_json::Value>(&body) {
            return Err(ApiError::invalid(format!("not a JSON document: {e}")));
        }
        // The directory must be one inside the served directory: the same refusal
        // whether it is missing or lies outside.
        let directory = std::path::Path::new(&path).parent().unwrap_or(std::path::Path::new(""));
        let inside_root = root
            .join(directory)
            .canonicalize()
            .is_ok_and(|full| full.is_dir() && full.starts_with(&root));
        if !inside_root {
            return Err(ApiError::invalid(format!(
                "path: no directory `{}` inside the served directory to save `{}` in",
                sheetform::geometry::quoted_token(&directory.to_string_lossy()),
                sheetform::geometry::quoted_token(&path)
            )));
        }
        let full = resolver.resolve_for_writing(&path, "path")?;
        write_keeping_mode(&full, body.as_bytes()).map_err(|e| {
            ApiError::new(
                axum::http::StatusCode::INTERNAL_SERVER_ERROR,
                "output",
                format!(
                    "path: `{}` cannot be saved: {}",
                    sheetform::geometry::quoted_token(&path),
                    os_reason(&e)
                ),
            )
        })
    })
    .await
    .map_err(|e| solve_stopped(&e))??;
    Ok(Json(serde_json::json!({ "saved": true })).into_response())
}

/// Replaces the file `full` by `bytes` atomically (a temporary file beside it, flushed
/// to disk, renamed over it), keeping the mode and, where the OS allows, the owner of the
/// file it replaces; a new file gets 0666 less the umask, as any program's new file
/// (`sheetform::io::write_atomic`'s temporary file is 0600, which a save made the
/// scene's mode).
/// Writes `bytes` to the new file `full` (in `directory`): a temporary file beside it,
/// flushed, then moved to `full` unless a file of that name appeared meanwhile
/// (`AlreadyExists`). Mode 0666 less the umask.
fn write_new(directory: &std::path::Path, full: &std::path::Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::io::Write;
    let mut builder = tempfile::Builder::new();
    builder.prefix(".upload.").suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let mut file = builder.tempfile_in(directory)?;
    file.write_all(bytes)?;
    file.as_file().sync_all()?;
    file.persist_noclobber(full).map(|_| ()).map_err(|e| e.error)
}

fn write_keeping_mode(full: &std::path::Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::io::Write;
    let directory = full.parent().unwrap_or(std::path::Path::new("."));
    let name = full
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let existing = std::fs::metadata(full).ok();
    let prefix = format!(".{name}.");
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        // Created with 0666: the OS takes the umask off.
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let mut file = builder.tempfile_in(directory)?;
    #[cfg(unix)]
    if let Some(existing) = &existing {
        use std::os::unix::fs::{MetadataExt, PermissionsExt};
        // The owner first (a change of owner clears the set-id bits), then the mode
        // (which the umask does not touch). Only root may give a file away, and only
        // to groups the user is in: otherwise the file is the user's, as any editor's.
        let _ = std::os::unix::fs::fchown(file.as_file(), Some(existing.uid()), Some(existing.gid()));
        file.as_file()
            .set_permissions(std::fs::Permissions::from_mode(existing.mode() & 0o7777))?;
    }
    #[cfg(not(unix))]
    if let Some(existing) = &existing {
        file.as_file().set_permissions(existing.permissions())?;
    }
    file.write_all(bytes)?;
    file.as_file().sync_all()?;
    // On failure the temporary file is removed when dropped.
    file.persist(full).map_err(|e| e.error)?;
    Ok(())
}

/// An OS error without the path the temporary-file crate adds to it (a save's message
/// names the file as the client did, never a temporary path).
fn os_reason(error: &std::io::Error) -> String {
    match error.raw_os_error() {
        Some(code) => std::io::Error::from_raw_os_error(code).to_string(),
        None => error.kind().to_string(),
    }
}

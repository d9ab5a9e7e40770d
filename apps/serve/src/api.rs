//! The solve routes: a scene in, what the editor draws out; and any output file for
//! download. Each runs the library pipeline (the same `run_bend` as `sheetform bend`)
//! on the blocking pool; nothing of a pipeline is repeated here.

use crate::array_reply::{reply_with_arrays, ArrayData, TakenArrays};
use crate::AppState;
use axum::extract::{Path, Query, State};
use axum::http::{header, HeaderMap, HeaderValue, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::routing::post;
use axum::{Json, Router};
use serde::Serialize;
use sheetform::bend::BendScene;
use sheetform::bend::EditInfo;
use sheetform::mesh::SheetMesh;
use sheetform::pipeline::{
    edit_bend_scene_with, run_bend, run_bend_bent, BendEdit, BendEditOptions, BendRunOptions, BentScene, ErrorKind,
    OutputSet, PipelineError, RenderedFiles, RunContext,
};
use sheetform::report::Report;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

pub(crate) fn routes() -> Router<Arc<AppState>> {
    Router::new()
        .route("/api/bend", post(bend))
        .route("/api/bend/edit", post(bend_edit))
        .route("/api/bend/file/{name}", post(bend_file))
}

/// `?dir=…` of a scene request: the directory of the scene file, relative to the served
/// directory (the editor sends the directory of the file it opened), against which the
/// scene's assets (textures, photos, scans) are resolved, as the CLI resolves them
/// against the scene file's directory. Absent: the served directory.
#[derive(Debug, Clone, Default, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SceneQuery {
    #[serde(default)]
    dir: Option<String>,
}

/// Where a scene's assets are read from: its directory, confined to the served one.
#[derive(Debug, Clone)]
pub(crate) struct SceneAssets {
    directory: std::path::PathBuf,
    root: std::path::PathBuf,
}

impl SceneAssets {
    /// The scene directory `query.dir` names inside `root` (canonical).
    pub fn new(root: &std::path::Path, query: &SceneQuery) -> Result<Self, ApiError> {
        let directory = match query.dir.as_deref() {
            None | Some("") => root.to_path_buf(),
            Some(dir) => {
                printable("dir", dir)?;
                let refuse = || {
                    ApiError::invalid(format!(
                        "dir: `{}` is not a directory inside the served one (such as `examples/photo`)",
                        sheetform::geometry::shortened_message(dir)
                    ))
                };
                if !sheetform::io::is_plain_relative(dir) {
                    return Err(refuse());
                }
                let full = root.join(dir).canonicalize().map_err(|_| refuse())?;
                if !full.starts_with(root) || !full.is_dir() {
                    return Err(refuse());
                }
                full
            }
        };
        Ok(Self {
            directory,
            root: root.to_path_buf(),
        })
    }

    /// A run context whose assets resolve against the scene's directory and may lie
    /// anywhere inside the served directory, nowhere else.
    pub fn context<'a>(&self) -> RunContext<'a> {
        let mut context = RunContext::new(&self.directory);
        context.assets = sheetform::pipeline::AssetResolver::new(&self.directory).with_confinement(&self.root);
        context
    }

    /// `error` as the client is told it: a file the scene names that is missing or lies
    /// outside the served directory gets the same message either way ([`not_inside`]).
    /// The library's resolver tells the two apart (it follows the path first, then says
    /// "outside the allowed directory /abs/root" or "cannot open it"): a page could probe
    /// which files exist outside the served directory, and learn where it is.
    pub fn confined(&self, mut error: ApiError) -> ApiError {
        let Some(asset) = error.asset.take() else {
            return error;
        };
        let inside = !asset.path.chars().any(char::is_control)
            && self
                .directory
                .join(&asset.path)
                .canonicalize()
                .is_ok_and(|full| full.starts_with(&self.root));
        if inside {
            // The file is there: what is wrong with it (its kind, its size) is the
            // library's message, which names it as the scene does.
            error
        } else {
            ApiError::invalid(not_inside(&asset.field, &asset.path))
        }
    }
}

/// The one refusal of a path that names no file inside the served directory, whether it
/// is missing or lies outside (also through a symbolic link): the path as the client gave
/// it, never the served directory's place.
pub(crate) fn not_inside(field: &str, path: &str) -> String {
    format!(
        "{field}: no file `{}` inside the served directory (files are named by paths relative to the \
         scene's directory, inside the served one)",
        sheetform::geometry::quoted_token(path)
    )
}

/// Refuses a name the client gave (`field`) that holds a control character (NUL, a line
/// break, DEL, …): no file the editor opens or saves has one, and a NUL reached the OS as
/// a failed write (a 500 quoting a temporary path).
pub(crate) fn printable(field: &str, name: &str) -> Result<(), ApiError> {
    match name.chars().find(|c| c.is_control()) {
        None => Ok(()),
        Some(c) => Err(ApiError::invalid(format!(
            "{field}: `{}` holds the control character U+{:04X}; names are printable text",
            sheetform::geometry::quoted_token(name),
            u32::from(c)
        ))),
    }
}

/// An error reply: `{"error": {"kind", "message"}, "report"?}` with the HTTP status of
/// its kind (400 invalid input, 422 inadmissible, 500 failed, 503 cancelled or busy,
/// 408 timeout).
#[derive(Debug)]
pub(crate) struct ApiError {
    pub status: StatusCode,
    pub kind: &'static str,
    pub message: String,
    pub report: Option<Box<Report>>,
    /// The file a scene named that could not be read ([`SceneAssets::confined`] words
    /// the message).
    pub asset: Option<Box<AssetRef>>,
}

/// A file a scene names, as the scene names it.
#[derive(Debug)]
pub(crate) struct AssetRef {
    field: String,
    path: String,
}

impl ApiError {
    /// An error of `kind` with its status.
    pub fn new(status: StatusCode, kind: &'static str, message: impl Into<String>) -> Self {
        Self {
            status,
            kind,
            message: message.into(),
            report: None,
            asset: None,
        }
    }

    /// Invalid input (400).
    pub fn invalid(message: impl Into<String>) -> Self {
        Self::new(StatusCode::BAD_REQUEST, "invalid_input", message)
    }

    /// A failure of the server (500): a solve that stopped, a file not written.
    pub fn failed(message: impl Into<String>) -> Self {
        Self::new(StatusCode::INTERNAL_SERVER_ERROR, "failed", message)
    }
}

impl From<PipelineError> for ApiError {
    fn from(error: PipelineError) -> Self {
        let (status, kind) = match error.kind() {
            ErrorKind::InvalidInput => (StatusCode::BAD_REQUEST, "invalid_input"),
            ErrorKind::Inadmissible => (StatusCode::UNPROCESSABLE_ENTITY, "inadmissible"),
            ErrorKind::Failed => (StatusCode::INTERNAL_SERVER_ERROR, "failed"),
            ErrorKind::Output => (StatusCode::INTERNAL_SERVER_ERROR, "output"),
            ErrorKind::Cancelled => (StatusCode::SERVICE_UNAVAILABLE, "cancelled"),
        };
        let asset = match &error {
            PipelineError::Asset { field, path, .. } => Some(Box::new(AssetRef {
                field: field.clone(),
                path: path.clone(),
            })),
            _ => None,
        };
        Self {
            status,
            kind,
            message: error.to_string(),
            report: error.report().cloned().map(Box::new),
            asset,
        }
    }
}

impl ApiError {
    /// The reply's body: `{"error": {"kind", "message"}, "report"}`.
    pub fn body(&self) -> serde_json::Value {
        serde_json::json!({
            "error": {"kind": self.kind, "message": self.message},
            "report": self.report,
        })
    }
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        let body = self.body();
        (self.status, Json(body)).into_response()
    }
}

/// A sheet (bent, or a flattened mesh) as flat arrays for the browser (model units).
#[derive(Debug, Serialize)]
pub(crate) struct MeshArrays {
    /// `x y z` per vertex.
    positions: Vec<f64>,
    /// `u v` per vertex: the flat pattern at 1:1.
    flat: Vec<f64>,
    /// Three vertex indices per triangle.
    triangles: Vec<u32>,
    /// Rulings as polylines of vertex indices.
    rulings: Vec<Vec<u32>>,
    /// The piece of each triangle (composite sheets, charts, net pieces).
    face_pieces: Vec<u32>,
}

impl MeshArrays {
    pub(crate) fn new(mesh: &SheetMesh) -> Self {
        Self {
            positions: mesh.positions.iter().flat_map(|p| [p.x, p.y, p.z]).collect(),
            flat: mesh.flat.iter().flat_map(|p| [p.x, p.y]).collect(),
            triangles: mesh.triangles.iter().flatten().copied().collect(),
            rulings: mesh.rulings.iter().map(|r| r.vertices.clone()).collect(),
            face_pieces: mesh.face_pieces.clone(),
        }
    }

    /// Takes the arrays out for a binary reply (the reply's field is `model`).
    pub(crate) fn take_arrays(&mut self) -> TakenArrays {
        use std::mem::take;
        vec![
            ("model.positions", ArrayData::F64(take(&mut self.positions))),
            ("model.flat", ArrayData::F64(take(&mut self.flat))),
            ("model.triangles", ArrayData::U32(take(&mut self.triangles))),
            ("model.rulings", ArrayData::U32Lists(take(&mut self.rulings))),
            ("model.face_pieces", ArrayData::U32(take(&mut self.face_pieces))),
        ]
    }
}

/// How far beyond a ruling's ends (in multiples of its length on the sheet) the editor
/// draws the curve of regression.
const REGRESSION_REACH: f64 = 1.0;

/// The reply to a solve: the model, its pattern and the report.
#[derive(Debug, Serialize)]
struct BendReply {
    model: MeshArrays,
    /// The angle defect at each vertex of `model` (radians; the colour map).
    angle_defects_rad: Vec<f64>,
    /// The curve of regression where it comes near the sheet: polylines, `x y z` per
    /// point (model units).
    regression_curves: Vec<Vec<f64>>,
    pattern_svg: String,
    report: Report,
    /// Each region's curve coordinates → the model's frame, where the editor draws the
    /// curve's handles (Bo & Wang §4.2: only region 0 is placed as its curve says).
    region_frames: Vec<RegionFrame>,
    /// Server time for parsing, solving and rendering (ms).
    server_ms: f64,
}

impl BendReply {
    /// Takes the model's arrays and the angle defects out for a binary reply.
    fn take_arrays(&mut self) -> TakenArrays {
        let mut arrays = self.model.take_arrays();
        arrays.push((
            "angle_defects_rad",
            ArrayData::F64(std::mem::take(&mut self.angle_defects_rad)),
        ));
        arrays
    }
}

/// A rigid motion `x ↦ R x + t`.
#[derive(Debug, Serialize)]
struct RegionFrame {
    /// `R`, row by row.
    rotation: [[f64; 3]; 3],
    /// `t` (model units).
    translation: [f64; 3],
}

/// Parses a bend scene at the edge (the same parser as the CLI's).
fn bend_scene(body: &str) -> Result<BendScene, ApiError> {
    BendScene::from_json(body).map_err(|e| ApiError::from(PipelineError::from(e)))
}

/// Sets its flag when dropped: the request handler holding it was dropped (its client
/// disconnected) or finished.
struct CancelOnDrop(Arc<AtomicBool>);

impl Drop for CancelOnDrop {
    fn drop(&mut self) {
        self.0.store(true, Ordering::SeqCst);
    }
}

/// Runs `job` on the blocking pool, at most `max_concurrent_solves` at a time, with a
/// cancel flag for its run context. The permit moves into the job (a client that
/// disconnects does not free its slot while its solve still runs), and the flag is set
/// when the client disconnects, so the run stops at its next check.
pub(crate) async fn solve<T: Send + 'static>(
    state: &AppState,
    job: impl FnOnce(&AtomicBool) -> Result<T, ApiError> + Send + 'static,
) -> Result<T, ApiError> {
    solve_with_slots(state, 1, job).await
}

/// [`solve`] for a job that keeps `slots` threads busy (a develop with a mirror plane
/// searches its two layouts at once): it takes that many of the solve slots (at most
/// all of them), so that the server's bound counts threads, not requests.
pub(crate) async fn solve_with_slots<T: Send + 'static>(
    state: &AppState,
    slots: usize,
    job: impl FnOnce(&AtomicBool) -> Result<T, ApiError> + Send + 'static,
) -> Result<T, ApiError> {
    let slots = slots.clamp(1, state.solve_slots) as u32;
    let permit = state
        .solves
        .clone()
        .acquire_many_owned(slots)
        .await
        .map_err(|_| ApiError::invalid("the server is stopping"))?;
    let cancel = Arc::new(AtomicBool::new(false));
    let _cancel_on_drop = CancelOnDrop(cancel.clone());
    tokio::task::spawn_blocking(move || {
        let _permit = permit;
        job(&cancel)
    })
    .await
    .unwrap_or_else(|e| Err(solve_stopped(&e)))
}

/// A job of the blocking pool that did not end (a panic: a bug).
pub(crate) fn solve_stopped(error: &tokio::task::JoinError) -> ApiError {
    ApiError::failed(format!("the solve stopped: {error}"))
}

/// A request's query, with a malformed one answered as every other error (JSON naming
/// what is wrong), not as axum's plain text.
pub(crate) struct ApiQuery<T>(pub T);

impl<T, S> axum::extract::FromRequestParts<S> for ApiQuery<T>
where
    T: serde::de::DeserializeOwned,
    S: Send + Sync,
{
    type Rejection = ApiError;

    async fn from_request_parts(parts: &mut axum::http::request::Parts, state: &S) -> Result<Self, Self::Rejection> {
        match Query::<T>::from_request_parts(parts, state).await {
            Ok(Query(value)) => Ok(Self(value)),
            Err(rejection) => Err(ApiError::invalid(format!(
                "the query: {}",
                sheetform::geometry::shortened_message(&rejection.body_text())
            ))),
        }
    }
}

/// What the body budget ([`crate::AppState::body_budget`]) counts in: KiB (a permit a
/// KiB, so that a 64 MiB body takes 65 536 permits, well within one acquisition).
pub(crate) const BUDGET_UNIT: usize = 1 << 10;

/// Permits of the body budget for `bytes`.
pub(crate) fn budget_units(bytes: usize) -> usize {
    bytes.div_ceil(BUDGET_UNIT)
}

/// A request body read into memory, holding its share of the server's body budget until
/// it is dropped (when its request is answered, or earlier once parsed).
pub(crate) struct Buffered<T> {
    value: T,
    _share: tokio::sync::OwnedSemaphorePermit,
}

impl<T> std::ops::Deref for Buffered<T> {
    type Target = T;

    fn deref(&self) -> &T {
        &self.value
    }
}

/// A request body, bounded three ways, each refusal answered as JSON: its size
/// ([`crate::ServeOptions::max_request_bytes`], 413), the bytes held over all requests
/// ([`crate::ServeOptions::max_buffered_bytes`]: a body's share is taken before it is read
/// when it declares its length, as it arrives when it does not; 503 `busy` when the
/// budget is spent) and its time ([`crate::ServeOptions::body_read_timeout`], 408
/// `timeout`).
pub(crate) struct ApiBody<T>(pub Buffered<T>);

impl<T> axum::extract::FromRequest<Arc<AppState>> for ApiBody<T>
where
    T: axum::extract::FromRequest<Arc<AppState>> + Send,
    T::Rejection: IntoResponse + Send,
{
    type Rejection = ApiError;

    async fn from_request(request: axum::extract::Request, state: &Arc<AppState>) -> Result<Self, Self::Rejection> {
        let read = async {
            let (request, share) = match declared_length(&request) {
                Some(declared) => {
                    let share = body_share(declared, state)?;
                    (request, share)
                }
                None => buffered_as_it_arrives(request, state).await?,
            };
            match T::from_request(request, state).await {
                Ok(value) => Ok(Self(Buffered { value, _share: share })),
                Err(rejection) => {
                    let response = rejection.into_response();
                    let status = response.status();
                    let bytes = axum::body::to_bytes(response.into_body(), 4096)
                        .await
                        .unwrap_or_default();
                    Err(ApiError::new(
                        status,
                        "invalid_input",
                        format!("the request body: {}", String::from_utf8_lossy(&bytes)),
                    ))
                }
            }
        };
        match tokio::time::timeout(state.body_read_timeout, read).await {
            Ok(result) => result,
            Err(_) => Err(ApiError::new(
                StatusCode::REQUEST_TIMEOUT,
                "timeout",
                format!(
                    "the request body did not arrive within {} s",
                    sheetform::geometry::short_number(state.body_read_timeout.as_secs_f64())
                ),
            )),
        }
    }
}

/// The length `request`'s body declares (`Content-Length`), if it declares one (not a
/// chunked body).
fn declared_length(request: &axum::extract::Request) -> Option<usize> {
    use axum::body::HttpBody;
    request
        .body()
        .size_hint()
        .exact()
        .map(|bytes| usize::try_from(bytes).unwrap_or(usize::MAX))
}

/// The refusal of a body larger than the largest a request may carry (413): `size` is
/// its declared length, or none when it declares none.
fn too_large(size: Option<usize>, largest: usize) -> ApiError {
    let size = size.map_or(String::new(), |bytes| format!("{bytes} bytes, "));
    ApiError::new(
        StatusCode::PAYLOAD_TOO_LARGE,
        "invalid_input",
        format!("the request body: {size}more than the {largest} bytes a request may carry"),
    )
}

/// The share of the body budget a body declared `declared` bytes long takes before it is
/// read. Refused at once when it is larger than the largest (413) or when the budget is
/// spent (503).
fn body_share(declared: usize, state: &AppState) -> Result<tokio::sync::OwnedSemaphorePermit, ApiError> {
    let largest = state.max_request_bytes;
    if declared > largest {
        return Err(too_large(Some(declared), largest));
    }
    take_budget(budget_units(declared), declared, state)
}

/// `units` more of the body budget (for a body that would then hold `bytes`), or the
/// refusal when the budget is spent (503, `busy`).
fn take_budget(units: usize, bytes: usize, state: &AppState) -> Result<tokio::sync::OwnedSemaphorePermit, ApiError> {
    let units = u32::try_from(units).unwrap_or(u32::MAX);
    state.body_budget.clone().try_acquire_many_owned(units).map_err(|_| {
        let held = state
            .body_budget_bytes
            .saturating_sub(state.body_budget.available_permits() * BUDGET_UNIT);
        ApiError::new(
            StatusCode::SERVICE_UNAVAILABLE,
            "busy",
            format!(
                "other requests' bodies hold {} MiB of the server's bound of {} MiB on bodies held at once, and \
                 this one ({} MiB) does not fit: send it again once they are answered",
                mib(held),
                mib(state.body_budget_bytes),
                mib(bytes)
            ),
        )
    })
}

/// Reads a body that declares no length (a chunked one) into one buffer, taking its share
/// of the body budget as the buffer grows: a small body takes a small share, where
/// taking the largest body's share up front let four such requests hold the whole budget
/// (256 MiB) and every other body be refused. The buffer at least doubles when it grows
/// (no quadratic copying), up to the largest body; its share is its capacity. Refused
/// once it passes the largest body (413) or finds the budget spent (503). The request is
/// given back with the buffer as its body, for the extractor to take at once.
async fn buffered_as_it_arrives(
    request: axum::extract::Request,
    state: &AppState,
) -> Result<(axum::extract::Request, tokio::sync::OwnedSemaphorePermit), ApiError> {
    use futures_util::StreamExt;
    let largest = state.max_request_bytes;
    let (parts, body) = request.into_parts();
    let mut share = take_budget(0, 0, state)?;
    let mut buffer: Vec<u8> = Vec::new();
    let mut chunks = body.into_data_stream();
    while let Some(chunk) = chunks.next().await {
        let chunk = chunk.map_err(|e| ApiError::invalid(format!("the request body: {e}")))?;
        let length = buffer.len().saturating_add(chunk.len());
        if length > largest {
            return Err(too_large(None, largest));
        }
        if length > buffer.capacity() {
            let capacity = length.max(2 * buffer.capacity()).max(8 * BUDGET_UNIT).min(largest);
            let more = budget_units(capacity).saturating_sub(share.num_permits());
            share.merge(take_budget(more, capacity, state)?);
            buffer.reserve_exact(capacity - buffer.len());
        }
        buffer.extend_from_slice(&chunk);
    }
    Ok((
        axum::extract::Request::from_parts(parts, axum::body::Body::from(buffer)),
        share,
    ))
}

/// Bytes in MiB, for messages.
fn mib(bytes: usize) -> sheetform::geometry::ShortNumber {
    sheetform::geometry::short_number(bytes as f64 / f64::from(1u32 << 20))
}

/// The pattern SVG of a run's rendered files (empty when it has none).
pub(crate) fn pattern_svg(files: &[(String, Vec<u8>)]) -> String {
    files
        .iter()
        .find(|(name, _)| name == "pattern.svg")
        .map(|(_, bytes)| String::from_utf8_lossy(bytes).into_owned())
        .unwrap_or_default()
}

/// Bends `scene` with the preview outputs: what the editor draws (`bent`: the scene
/// already bent by an edit's check, exported without bending again).
fn preview(
    scene: &BendScene,
    bent: Option<Box<BentScene>>,
    assets: &SceneAssets,
    start: Instant,
    cancel: &AtomicBool,
) -> Result<BendReply, ApiError> {
    let context = assets.context().with_outputs(OutputSet::Preview).with_cancel(cancel);
    let run =
        run_bend_bent(scene, bent, &BendRunOptions::default(), &context).map_err(|e| assets.confined(e.into()))?;
    Ok(BendReply {
        model: MeshArrays::new(&run.sheet.mesh),
        angle_defects_rad: run.angle_defects_rad,
        regression_curves: run
            .sheet
            .curves_of_regression_near_sheet(REGRESSION_REACH)
            .iter()
            .map(|stretch| stretch.iter().flat_map(|p| [p.x, p.y, p.z]).collect())
            .collect(),
        pattern_svg: pattern_svg(&run.files),
        region_frames: run
            .sheet
            .placement
            .region_motions
            .iter()
            .map(|m| RegionFrame {
                rotation: std::array::from_fn(|i| std::array::from_fn(|j| m.rotation[(i, j)])),
                translation: [m.translation.x, m.translation.y, m.translation.z],
            })
            .collect(),
        report: run.report,
        server_ms: start.elapsed().as_secs_f64() * 1e3,
    })
}

async fn bend(
    State(state): State<Arc<AppState>>,
    ApiQuery(query): ApiQuery<SceneQuery>,
    headers: HeaderMap,
    ApiBody(body): ApiBody<String>,
) -> Result<Response, ApiError> {
    let start = Instant::now();
    let assets = SceneAssets::new(&state.root, &query)?;
    let reply = solve(&state, move |cancel| {
        preview(&bend_scene(&body)?, None, &assets, start, cancel)
    })
    .await?;
    Ok(reply_with_arrays(&headers, reply, BendReply::take_arrays))
}

/// `POST /api/bend/edit`: `{"scene": …, "edit": …}`.
#[derive(Debug, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct EditRequest {
    scene: serde_json::Value,
    edit: serde_json::Value,
    /// An edit past the admissible shapes stops at their boundary instead of being
    /// refused ([`BendEditOptions::stop_at_boundary`]).
    #[serde(default)]
    stop_at_boundary: bool,
}

/// The reply to an edit: the edited scene, what the edit did, and its preview.
#[derive(Debug, Serialize)]
struct EditReply {
    scene: BendScene,
    edit: EditInfo,
    /// How much of the asked move was made (1: all of it; less: it stopped at the
    /// boundary of the admissible shapes).
    moved_fraction: f64,
    /// Why it stopped short, when it did.
    stopped_because: Option<String>,
    #[serde(flatten)]
    preview: BendReply,
}

async fn bend_edit(
    State(state): State<Arc<AppState>>,
    ApiQuery(query): ApiQuery<SceneQuery>,
    headers: HeaderMap,
    ApiBody(body): ApiBody<String>,
) -> Result<Response, ApiError> {
    let start = Instant::now();
    let assets = SceneAssets::new(&state.root, &query)?;
    let reply = solve(&state, move |cancel| {
        let request: EditRequest = serde_json::from_str(&body).map_err(|e| {
            ApiError::invalid(format!(
                "an edit request is {{\"scene\": …, \"edit\": …}}: {}",
                sheetform::geometry::shortened_message(&e.to_string())
            ))
        })?;
        let scene = bend_scene(&request.scene.to_string())?;
        let edit: BendEdit = serde_json::from_value(request.edit).map_err(|e| {
            ApiError::invalid(format!(
                "field `edit`: {}",
                sheetform::geometry::shortened_message(&e.to_string())
            ))
        })?;
        let options = BendEditOptions {
            stop_at_boundary: request.stop_at_boundary,
            ..BendEditOptions::default()
        };
        let result = edit_bend_scene_with(&scene, &edit, &options)?;
        if !result.info.applied && request.stop_at_boundary && edit.is_continuous() {
            // Already at the boundary, and the move leads out at once: nothing moves.
            return Err(ApiError::new(
                StatusCode::UNPROCESSABLE_ENTITY,
                "at_boundary",
                result
                    .stopped_because
                    .unwrap_or_else(|| "the edit would make the shape inadmissible".into()),
            ));
        }
        if !result.info.applied {
            return Err(ApiError::new(
                StatusCode::UNPROCESSABLE_ENTITY,
                "inadmissible",
                result
                    .info
                    .rejected_because
                    .unwrap_or_else(|| "the edit would make the shape inadmissible".into()),
            ));
        }
        let preview = preview(&result.scene, result.bent, &assets, start, cancel)?;
        Ok(EditReply {
            scene: result.scene,
            edit: result.info,
            moved_fraction: result.moved_fraction,
            stopped_because: result.stopped_because,
            preview,
        })
    })
    .await?;
    Ok(reply_with_arrays(&headers, reply, |reply: &mut EditReply| {
        reply.preview.take_arrays()
    }))
}

/// Content type of a file the CLI writes.
fn content_type(name: &str) -> &'static str {
    match name.rsplit('.').next() {
        Some("svg") => "image/svg+xml",
        Some("pdf") => "application/pdf",
        Some("glb") => "model/gltf-binary",
        Some("json") => "application/json",
        Some("obj" | "mtl" | "dxf") => "text/plain; charset=utf-8",
        Some("png") => "image/png",
        _ => "application/octet-stream",
    }
}

/// The file `wanted` of a run's outputs (`report.json` from its report), or a 404 naming
/// the command that does not write it.
pub(crate) fn output_file(
    files: Vec<(String, Vec<u8>)>,
    report: &Report,
    wanted: &str,
    command: &str,
) -> Result<Vec<u8>, ApiError> {
    if wanted == "report.json" {
        return Ok(serde_json::to_vec_pretty(report).expect("the report serialises"));
    }
    files
        .into_iter()
        .find(|(n, _)| n == wanted)
        .map(|(_, bytes)| bytes)
        .ok_or_else(|| {
            ApiError::new(
                StatusCode::NOT_FOUND,
                "invalid_input",
                format!(
                    "`sheetform {command}` writes no file `{}` here",
                    sheetform::geometry::shortened_message(wanted)
                ),
            )
        })
}

/// A scene command's download route: `run` parses the body and runs the command in the
/// given context (every output, assets against the scene's directory, cancelled when the
/// client leaves), both on the blocking pool under a solve slot; the file `name` of its
/// outputs goes back as an attachment.
pub(crate) async fn scene_download(
    state: &AppState,
    query: &SceneQuery,
    name: String,
    body: Buffered<String>,
    command: &'static str,
    run: impl FnOnce(&str, &RunContext) -> Result<(RenderedFiles, Report), ApiError> + Send + 'static,
) -> Result<Response, ApiError> {
    let assets = SceneAssets::new(&state.root, query)?;
    let confinement = assets.clone();
    let wanted = name.clone();
    let bytes = solve(state, move |cancel| {
        let (files, report) = run(&body, &assets.context().with_cancel(cancel))?;
        output_file(files, &report, &wanted, command)
    })
    .await
    .map_err(|e| confinement.confined(e))?;
    Ok(attachment(&name, bytes))
}

/// A download: `bytes` as the file `name`.
pub(crate) fn attachment(name: &str, bytes: Vec<u8>) -> Response {
    let disposition = HeaderValue::from_str(&format!("attachment; filename=\"{name}\""))
        .unwrap_or(HeaderValue::from_static("attachment"));
    (
        [
            (header::CONTENT_TYPE, HeaderValue::from_static(content_type(name))),
            (header::CONTENT_DISPOSITION, disposition),
        ],
        bytes,
    )
        .into_response()
}

async fn bend_file(
    State(state): State<Arc<AppState>>,
    Path(name): Path<String>,
    ApiQuery(query): ApiQuery<SceneQuery>,
    ApiBody(body): ApiBody<String>,
) -> Result<Response, ApiError> {
    scene_download(&state, &query, name, body, "bend", |body, context| {
        let run = run_bend(&bend_scene(body)?, &BendRunOptions::default(), context)?;
        Ok((run.files, run.report))
    })
    .await
}

#[cfg(test)]
mod solve_slot_tests {
    use super::*;

    /// A job that keeps two threads busy takes two of the solve slots while it runs (one
    /// left of three), a plain one takes one, and one asking more than there are takes
    /// them all instead of waiting for ever.
    #[tokio::test(flavor = "multi_thread", worker_threads = 2)]
    async fn a_two_thread_solve_takes_two_slots() {
        let slots = 3;
        let state = AppState {
            root: std::path::PathBuf::from("."),
            solves: Arc::new(tokio::sync::Semaphore::new(slots)),
            solve_slots: slots,
            last_ffd_design: std::sync::Mutex::new(None),
            body_budget: Arc::new(tokio::sync::Semaphore::new(1)),
            body_budget_bytes: 0,
            max_request_bytes: 0,
            body_read_timeout: std::time::Duration::from_secs(1),
        };
        for (asked, left) in [(1, 2), (2, 1), (5, 0)] {
            let solves = state.solves.clone();
            let free = solve_with_slots(&state, asked, move |_| Ok(solves.available_permits()))
                .await
                .unwrap();
            assert_eq!(free, left, "{asked} slots asked");
            assert_eq!(state.solves.available_permits(), slots, "given back");
        }
    }
}

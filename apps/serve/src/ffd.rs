//! The FFD mode's routes: an FFD scene in (the same JSON `sheetform ffd` reads), a stream
//! of progress lines while the restorations run, then the restored panels, the plain FFD
//! before restoration with the angle defects of both (the colour maps), the deformed
//! lattice, the pattern and the report; and any file `sheetform ffd` writes, for
//! download. Both run the library's `run_ffd`; nothing of a pipeline is repeated here.
//!
//! `POST /api/ffd` answers `application/x-ndjson`: one JSON object per line,
//! `{"progress": {"stage", "fraction"}}` as the run advances (after each restoration
//! iteration; lossy: a slow reader misses some), then `{"result": …}` or `{"error":
//! {"kind", "message"}, "report"?}`. A client that closes the connection (the editor's
//! Cancel) cancels the run at its next progress report; one that left before its run
//! started never starts it. The scene is parsed on the blocking pool under the run's
//! solve slot (as every mode's); one that does not parse is answered with its status
//! (400) before anything streams.
//!
//! The server keeps the last design it restored and resumes the next run from it
//! (`FfdRunOptions::warm_start`): an editor's drag appends one deformation to the scene,
//! and only that one is restored; an undo restores nothing. The reply's
//! `resumed_deformations` says how many were taken over. The result is the same as a
//! run from scratch.

use crate::api::{
    pattern_svg, scene_download, solve_stopped, ApiBody, ApiError, ApiQuery, MeshArrays, SceneAssets, SceneQuery,
};
use crate::AppState;
use axum::body::Body;
use axum::extract::{Path, State};
use axum::http::header;
use axum::response::{IntoResponse, Response};
use axum::routing::post;
use axum::Router;
use serde::Serialize;
use sheetform::ffd::FfdScene;
use sheetform::mesh::TriangleMesh;
use sheetform::pipeline::{run_ffd, FfdRunOptions, OutputSet, PipelineError};
use sheetform::report::Report;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

/// Progress lines buffered for a slow client before the run waits for it.
const PROGRESS_BUFFER: usize = 64;

pub(crate) fn routes() -> Router<Arc<AppState>> {
    Router::new()
        .route("/api/ffd", post(ffd))
        .route("/api/ffd/file/{name}", post(ffd_file))
}

/// Parses an FFD scene at the edge (the same parser as the CLI's).
fn ffd_scene(body: &str) -> Result<FfdScene, ApiError> {
    FfdScene::from_json(body).map_err(|e| ApiError::from(PipelineError::from(e)))
}

/// The panels (welded) at one stage, with the angle defect at each vertex.
#[derive(Debug, Serialize)]
struct DefectMesh {
    /// `x y z` per vertex.
    positions: Vec<f64>,
    /// Three vertex indices per triangle.
    triangles: Vec<u32>,
    /// `2π − Σθ` per vertex (0 on the boundary and the seams; radians).
    angle_defects_rad: Vec<f64>,
}

impl DefectMesh {
    fn new(mesh: &TriangleMesh, defects: &[f64]) -> Self {
        Self {
            positions: mesh.positions.iter().flat_map(|p| [p.x, p.y, p.z]).collect(),
            triangles: mesh.triangles.iter().flatten().copied().collect(),
            angle_defects_rad: defects.to_vec(),
        }
    }
}

/// The deformed lattice: control point `(i, j, k)` at `3 (i + nu (j + nv k))`.
#[derive(Debug, Serialize)]
struct LatticeArrays {
    counts: [usize; 3],
    control_points: Vec<f64>,
}

/// The result of an FFD scene.
#[derive(Debug, Serialize)]
struct FfdReply {
    /// The restored panels with their exact patterns (pieces = panels).
    model: MeshArrays,
    /// The last plain FFD, before restoration.
    plain: DefectMesh,
    /// The last restoration.
    restored: DefectMesh,
    /// The lattice after the last deformation's edits.
    lattice: LatticeArrays,
    pattern_svg: String,
    report: Report,
    /// Deformations taken over from the server's last design instead of restored again.
    resumed_deformations: usize,
    /// Server time for parsing, solving and rendering (ms).
    server_ms: f64,
}

/// One NDJSON line.
fn line(value: serde_json::Value) -> String {
    let mut text = value.to_string();
    text.push('\n');
    text
}

async fn ffd(
    State(state): State<Arc<AppState>>,
    ApiQuery(query): ApiQuery<SceneQuery>,
    ApiBody(body): ApiBody<String>,
) -> Result<Response, ApiError> {
    let start = Instant::now();
    let assets = SceneAssets::new(&state.root, &query)?;
    // The scene is parsed on the blocking pool under a solve slot, as every mode's scene
    // is (a large one takes seconds, which on the async workers stalled every other
    // request), and one that does not parse is answered with its status before anything
    // streams. The slot goes into the job and on to the run, so it stays taken while
    // either runs, also when the client has gone; the body's share of the budget is
    // given back once parsed.
    let slot = state
        .solves
        .clone()
        .acquire_owned()
        .await
        .map_err(|_| ApiError::invalid("the server is stopping"))?;
    let (slot, scene) = tokio::task::spawn_blocking(move || {
        let scene = ffd_scene(&body);
        drop(body);
        (slot, scene)
    })
    .await
    .map_err(|e| solve_stopped(&e))?;
    let scene = scene?;
    let (sender, mut receiver) = tokio::sync::mpsc::channel::<String>(PROGRESS_BUFFER);
    tokio::spawn(async move {
        // The client left before the run started: nothing to do.
        if sender.is_closed() {
            return;
        }
        let progress_sender = sender.clone();
        let warm_start = state
            .last_ffd_design
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .clone();
        let cache = state.clone();
        let outcome = tokio::task::spawn_blocking(move || -> Result<FfdReply, ApiError> {
            let _slot = slot;
            let cancel = AtomicBool::new(false);
            let progress = |stage: &str, fraction: f64| {
                let message = line(serde_json::json!({"progress": {"stage": stage, "fraction": fraction}}));
                // Progress is lossy: a client that reads slowly misses lines instead of
                // holding the run up. A client that is gone (the editor cancelled) stops
                // the run at its next check.
                match progress_sender.try_send(message) {
                    Ok(()) | Err(tokio::sync::mpsc::error::TrySendError::Full(_)) => {}
                    Err(tokio::sync::mpsc::error::TrySendError::Closed(_)) => cancel.store(true, Ordering::SeqCst),
                }
            };
            let context = assets
                .context()
                .with_outputs(OutputSet::Preview)
                .with_progress(&progress)
                .with_cancel(&cancel);
            let options = FfdRunOptions {
                warm_start,
                ..FfdRunOptions::default()
            };
            let run = run_ffd(&scene, &options, &context).map_err(|e| assets.confined(e.into()))?;
            let lattice = &run.design.steps.last().expect("a scene has a deformation").volume;
            let reply = FfdReply {
                model: MeshArrays::new(&run.sheet),
                plain: DefectMesh::new(&run.plain, &run.angle_defects_before_rad),
                restored: DefectMesh::new(&run.restored, &run.angle_defects_after_rad),
                lattice: LatticeArrays {
                    counts: lattice.counts(),
                    control_points: lattice.control_points().iter().flat_map(|p| [p.x, p.y, p.z]).collect(),
                },
                pattern_svg: pattern_svg(&run.files),
                resumed_deformations: run.design.resumed_deformations,
                report: run.report,
                server_ms: start.elapsed().as_secs_f64() * 1e3,
            };
            *cache
                .last_ffd_design
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner) = Some(Arc::new(run.design));
            Ok(reply)
        })
        .await;
        let last = match outcome {
            Ok(Ok(reply)) => serde_json::json!({ "result": reply }),
            Ok(Err(error)) => error.body(),
            Err(error) => solve_stopped(&error).body(),
        };
        // Nobody listens any more when the client cancelled.
        let _ = sender.send(line(last)).await;
    });
    let stream = futures_util::stream::poll_fn(move |context| {
        receiver
            .poll_recv(context)
            .map(|next| next.map(Ok::<_, std::convert::Infallible>))
    });
    Ok((
        [(header::CONTENT_TYPE, "application/x-ndjson")],
        Body::from_stream(stream),
    )
        .into_response())
}

async fn ffd_file(
    State(state): State<Arc<AppState>>,
    Path(name): Path<String>,
    ApiQuery(query): ApiQuery<SceneQuery>,
    ApiBody(body): ApiBody<String>,
) -> Result<Response, ApiError> {
    scene_download(&state, &query, name, body, "ffd", |body, context| {
        let run = run_ffd(&ffd_scene(body)?, &FfdRunOptions::default(), context)?;
        Ok((run.files, run.report))
    })
    .await
}

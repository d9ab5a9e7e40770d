//! The slit mode's routes: a slit scene in (the same JSON `sheetform slit` reads), the
//! bent sheet, the ridge-line ends an anchor can hold, its pattern and the report out; and any file `sheetform slit` writes, for
//! download. Both run the library's `run_slit`; nothing of a pipeline is repeated here.

use crate::api::{
    pattern_svg, scene_download, solve, ApiBody, ApiError, ApiQuery, MeshArrays, SceneAssets, SceneQuery,
};
use crate::array_reply::reply_with_arrays;
use crate::AppState;
use axum::extract::{Path, State};
use axum::http::HeaderMap;
use axum::response::Response;
use axum::routing::post;
use axum::Router;
use serde::Serialize;
use sheetform::pipeline::{run_slit, OutputSet, PipelineError, SlitRunOptions};
use sheetform::report::Report;
use sheetform::slit::SlitScene;
use std::sync::Arc;
use std::time::Instant;

pub(crate) fn routes() -> Router<Arc<AppState>> {
    Router::new()
        .route("/api/slit", post(slit))
        .route("/api/slit/file/{name}", post(slit_file))
}

/// Parses a slit scene at the edge (the same parser as the CLI's).
fn slit_scene(body: &str) -> Result<SlitScene, ApiError> {
    SlitScene::from_json(body).map_err(|e| ApiError::from(PipelineError::from(e)))
}

/// The reply to a slit scene: the bent sheet, its pattern and the report (per-strip gaps
/// in `report.slit.strips`).
#[derive(Debug, Serialize)]
struct SlitReply {
    model: MeshArrays,
    /// The ridge-line ends an anchor can hold (`strip`, `ridge`, `side`, `position`:
    /// an anchor at its place), for the editor to offer (Fig. 12).
    anchorable_points: Vec<sheetform::slit::AnchorSpec>,
    pattern_svg: String,
    report: Report,
    /// Server time for parsing, solving and rendering (ms).
    server_ms: f64,
}

async fn slit(
    State(state): State<Arc<AppState>>,
    ApiQuery(query): ApiQuery<SceneQuery>,
    headers: HeaderMap,
    ApiBody(body): ApiBody<String>,
) -> Result<Response, ApiError> {
    let start = Instant::now();
    let assets = SceneAssets::new(&state.root, &query)?;
    let reply = solve(&state, move |cancel| {
        let scene = slit_scene(&body)?;
        let context = assets.context().with_outputs(OutputSet::Preview).with_cancel(cancel);
        let run = run_slit(&scene, &SlitRunOptions::default(), &context).map_err(|e| assets.confined(e.into()))?;
        Ok(SlitReply {
            model: MeshArrays::new(&run.mesh),
            anchorable_points: run.design.anchorable_points(&run.model),
            pattern_svg: pattern_svg(&run.files),
            report: run.report,
            server_ms: start.elapsed().as_secs_f64() * 1e3,
        })
    })
    .await?;
    Ok(reply_with_arrays(&headers, reply, |reply: &mut SlitReply| {
        reply.model.take_arrays()
    }))
}

async fn slit_file(
    State(state): State<Arc<AppState>>,
    Path(name): Path<String>,
    ApiQuery(query): ApiQuery<SceneQuery>,
    ApiBody(body): ApiBody<String>,
) -> Result<Response, ApiError> {
    scene_download(&state, &query, name, body, "slit", |body, context| {
        let run = run_slit(&slit_scene(body)?, &SlitRunOptions::default(), context)?;
        Ok((run.files, run.report))
    })
    .await
}

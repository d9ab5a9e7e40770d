//! The photo mode's routes: a photo annotation in (the same JSON `sheetform photo`
//! reads; its photograph is read relative to `?dir=`), the reconstructed model, its
//! pattern and the report out; and any file `sheetform photo` writes, for download.
//! Both run the library's `run_photo`; nothing of a pipeline is repeated here.

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
use sheetform::pipeline::{run_photo, OutputSet, PhotoInput, PhotoRunOptions};
use sheetform::report::Report;
use std::sync::Arc;
use std::time::Instant;

pub(crate) fn routes() -> Router<Arc<AppState>> {
    Router::new()
        .route("/api/photo", post(photo))
        .route("/api/photo/file/{name}", post(photo_file))
}

/// The reply to an annotation: the reconstructed model (pieces = patches), its pattern
/// and the report.
#[derive(Debug, Serialize)]
struct PhotoReply {
    model: MeshArrays,
    pattern_svg: String,
    report: Report,
    /// Server time for parsing, reconstructing and rendering (ms).
    server_ms: f64,
}

async fn photo(
    State(state): State<Arc<AppState>>,
    ApiQuery(query): ApiQuery<SceneQuery>,
    headers: HeaderMap,
    ApiBody(body): ApiBody<String>,
) -> Result<Response, ApiError> {
    let start = Instant::now();
    let assets = SceneAssets::new(&state.root, &query)?;
    let reply = solve(&state, move |cancel| {
        let input = PhotoInput::from_text(&body)?;
        let context = assets.context().with_outputs(OutputSet::Preview).with_cancel(cancel);
        let run = run_photo(&input, &PhotoRunOptions::default(), &context).map_err(|e| assets.confined(e.into()))?;
        Ok(PhotoReply {
            model: MeshArrays::new(&run.sheet),
            pattern_svg: pattern_svg(&run.files),
            report: run.report,
            server_ms: start.elapsed().as_secs_f64() * 1e3,
        })
    })
    .await?;
    Ok(reply_with_arrays(&headers, reply, |reply: &mut PhotoReply| {
        reply.model.take_arrays()
    }))
}

async fn photo_file(
    State(state): State<Arc<AppState>>,
    Path(name): Path<String>,
    ApiQuery(query): ApiQuery<SceneQuery>,
    ApiBody(body): ApiBody<String>,
) -> Result<Response, ApiError> {
    scene_download(&state, &query, name, body, "photo", |body, context| {
        let run = run_photo(&PhotoInput::from_text(body)?, &PhotoRunOptions::default(), context)?;
        Ok((run.files, run.report))
    })
    .await
}

//! The mesh mode's routes: a mesh file's bytes in (OBJ, PLY, STL, OFF, as `sheetform
//! check` and `sheetform flatten` read them), its developability, the flattened (or,
//! with the `develop` layout, developed) model and its pattern out; and any file
//! `sheetform flatten` or `sheetform develop` writes, for download. Both run the
//! library's `run_check` and `run_flatten` or `run_develop`; nothing of a pipeline is
//! repeated here.

use crate::api::{
    attachment, output_file, pattern_svg, printable, solve_with_slots, ApiBody, ApiError, ApiQuery, MeshArrays,
};
use crate::array_reply::reply_with_arrays;
use crate::AppState;
use axum::body::Bytes;
use axum::extract::{Path, State};
use axum::http::HeaderMap;
use axum::response::Response;
use axum::routing::post;
use axum::Router;
use serde::{Deserialize, Serialize};
use sheetform::mesh::{LengthUnit, TriangleMesh};
use sheetform::pipeline::{
    run_check, run_develop, run_flatten, ChartMode, CheckOptions, DevelopRunOptions, FlattenMethod, FlattenOptions,
    FlattenRun, Mirror, OutputSet, PipelineError, RunContext,
};
use sheetform::report::Report;
use std::sync::Arc;
use std::time::Instant;

pub(crate) fn routes() -> Router<Arc<AppState>> {
    Router::new()
        .route("/api/mesh", post(mesh))
        .route("/api/mesh/file/{name}", post(mesh_file))
}

/// The query of a mesh request: the file's name (its extension picks the reader) and
/// the options of `sheetform flatten` the editor offers, spelled as on the command line.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct MeshQuery {
    /// The file's name (`box.obj`): its extension picks the format.
    name: String,
    /// `auto` (default), `smooth`, `net` or `never` (`sheetform flatten --charts`), or
    /// `develop` (`sheetform develop` with its defaults: automatic seams, exact pieces).
    #[serde(default)]
    charts: Option<String>,
    /// `exact` (default), `lscm` or `arap` (`--method`).
    #[serde(default)]
    method: Option<String>,
    /// Weld vertices closer than this (model units; `--weld`).
    #[serde(default)]
    weld: Option<f64>,
    /// `mm` (default), `cm`, `m` or `in` (`--units`).
    #[serde(default)]
    units: Option<String>,
    /// The `develop` layout's mirror plane, as `sheetform develop --mirror` spells it
    /// (`x`, `y`, `z` or placed, `x=0`); empty or absent for none.
    #[serde(default)]
    mirror: Option<String>,
}

impl MeshQuery {
    /// The flatten options, parsed at the edge like the CLI's arguments.
    fn flatten_options(&self) -> Result<FlattenOptions, ApiError> {
        printable("name", &self.name)?;
        let charts = match self.charts.as_deref().unwrap_or("auto") {
            // develop lays its pieces out itself; the other options are flatten's.
            "auto" | "develop" => ChartMode::Auto,
            "smooth" => ChartMode::Smooth,
            "net" => ChartMode::Net,
            "never" => ChartMode::Never,
            other => {
                return Err(ApiError::invalid(format!(
                    "charts: `{}` is not auto, smooth, net, never or develop",
                    short(other)
                )))
            }
        };
        let method = match self.method.as_deref().unwrap_or("exact") {
            "exact" => FlattenMethod::Exact,
            "lscm" => FlattenMethod::Lscm,
            "arap" => FlattenMethod::Arap,
            other => {
                return Err(ApiError::invalid(format!(
                    "method: `{}` is not exact, lscm or arap",
                    short(other)
                )))
            }
        };
        self.mirror()?;
        Ok(FlattenOptions {
            charts,
            method,
            weld: self.weld,
            unit: self.unit()?,
            input: Some(self.name.clone()),
            ..Default::default()
        })
    }

    fn unit(&self) -> Result<LengthUnit, ApiError> {
        Ok(match self.units.as_deref().unwrap_or("mm") {
            "mm" => LengthUnit::Mm,
            "cm" => LengthUnit::Cm,
            "m" => LengthUnit::M,
            "in" => LengthUnit::In,
            other => {
                return Err(ApiError::invalid(format!(
                    "units: `{}` is not mm, cm, m or in",
                    short(other)
                )))
            }
        })
    }

    /// Lays `mesh` out as asked: `run_flatten`, or `run_develop` for the `develop` layout.
    fn lay_out(&self, mesh: TriangleMesh, context: &RunContext) -> Result<FlattenRun, ApiError> {
        let flatten = self.flatten_options()?;
        if self.charts.as_deref() == Some("develop") {
            let options = DevelopRunOptions {
                flatten,
                mirror: self.mirror()?,
                ..Default::default()
            };
            Ok(run_develop(mesh, &options, context)?.run)
        } else {
            Ok(run_flatten(mesh, &flatten, context)?)
        }
    }

    /// The solve slots the request takes: 2 for a develop with a mirror plane (its two
    /// layouts are searched on two threads at once), 1 otherwise.
    fn solve_slots(&self) -> usize {
        if matches!(self.mirror(), Ok(Some(_))) {
            2
        } else {
            1
        }
    }

    /// The mirror plane asked for, parsed as the CLI's `--mirror`; only the `develop`
    /// layout takes one.
    fn mirror(&self) -> Result<Option<Mirror>, ApiError> {
        let mirror = match self.mirror.as_deref().map(str::trim) {
            None | Some("") => None,
            Some(text) => Some(
                text.parse::<Mirror>()
                    .map_err(|message| ApiError::invalid(format!("mirror: {message}")))?,
            ),
        };
        if mirror.is_some() && self.charts.as_deref() != Some("develop") {
            return Err(ApiError::invalid(
                "mirror: only the develop layout keeps a mirror plane (choose Layout: develop)",
            ));
        }
        Ok(mirror)
    }

    /// The mesh in the body, read by the CLI's reader for the name's extension.
    fn read(&self, body: &[u8]) -> Result<TriangleMesh, ApiError> {
        let name = std::path::Path::new(&self.name);
        if name.file_name().is_none() || self.name.contains(['/', '\\']) {
            return Err(ApiError::invalid("name: a file name such as `model.obj`"));
        }
        sheetform::io::mesh_from_bytes(name, body).map_err(|e| ApiError::from(PipelineError::from(e)))
    }
}

/// A token of a query value, cut short for a message.
fn short(value: &str) -> String {
    sheetform::geometry::shortened_message(value)
}

/// The input mesh with its angle defects, for the developability colour map.
#[derive(Debug, Serialize)]
struct CheckedMesh {
    /// `x y z` per vertex.
    positions: Vec<f64>,
    /// Three vertex indices per triangle.
    triangles: Vec<u32>,
    /// `2π − Σθ` per vertex (0 on the boundary; radians).
    angle_defects_rad: Vec<f64>,
}

/// The reply to a mesh: its check, the flattened model and pattern, both reports.
#[derive(Debug, Serialize)]
struct MeshReply {
    /// The mesh as read (and welded), with its angle defects.
    input: CheckedMesh,
    /// The flattened (or developed) model: cut where the layout cut it, `flat` its
    /// pattern at 1:1.
    model: MeshArrays,
    pattern_svg: String,
    /// `sheetform flatten`'s (or `sheetform develop`'s) report.
    report: Report,
    /// `sheetform check`'s report.
    check_report: Report,
    /// Server time for reading, checking, flattening and rendering (ms).
    server_ms: f64,
}

fn check_and_flatten(
    query: &MeshQuery,
    body: &[u8],
    root: std::path::PathBuf,
    cancel: &std::sync::atomic::AtomicBool,
) -> Result<MeshReply, ApiError> {
    let start = Instant::now();
    let options = query.flatten_options()?;
    let mesh = query.read(body)?;
    let context = RunContext::new(root)
        .with_outputs(OutputSet::Preview)
        .with_cancel(cancel);
    let check = run_check(
        mesh.clone(),
        &CheckOptions {
            weld: query.weld,
            unit: options.unit,
            input: Some(query.name.clone()),
            ..Default::default()
        },
        &context,
    )?;
    let run = query.lay_out(mesh, &context)?;
    Ok(MeshReply {
        input: CheckedMesh {
            positions: check.mesh.positions.iter().flat_map(|p| [p.x, p.y, p.z]).collect(),
            triangles: check.mesh.triangles.iter().flatten().copied().collect(),
            angle_defects_rad: check.vertices.angle_defect.clone(),
        },
        model: MeshArrays::new(&run.sheet),
        pattern_svg: pattern_svg(&run.files),
        report: run.report,
        check_report: check.report,
        server_ms: start.elapsed().as_secs_f64() * 1e3,
    })
}

/// `POST /api/mesh?name=…&charts=…`: the mesh file's bytes as the body.
async fn mesh(
    State(state): State<Arc<AppState>>,
    ApiQuery(query): ApiQuery<MeshQuery>,
    headers: HeaderMap,
    ApiBody(body): ApiBody<Bytes>,
) -> Result<Response, ApiError> {
    let root = state.root.clone();
    let slots = query.solve_slots();
    let reply = solve_with_slots(&state, slots, move |cancel| {
        check_and_flatten(&query, &body, root, cancel)
    })
    .await?;
    Ok(reply_with_arrays(&headers, reply, |reply: &mut MeshReply| {
        reply.model.take_arrays()
    }))
}

/// `POST /api/mesh/file/{name}?name=…&charts=…`: one file `sheetform flatten` (or
/// `sheetform develop`) writes.
async fn mesh_file(
    State(state): State<Arc<AppState>>,
    Path(file): Path<String>,
    ApiQuery(query): ApiQuery<MeshQuery>,
    ApiBody(body): ApiBody<Bytes>,
) -> Result<Response, ApiError> {
    let root = state.root.clone();
    let wanted = file.clone();
    let slots = query.solve_slots();
    let bytes = solve_with_slots(&state, slots, move |cancel| {
        let mesh = query.read(&body)?;
        let run = query.lay_out(mesh, &RunContext::new(root).with_cancel(cancel))?;
        let command = if query.charts.as_deref() == Some("develop") {
            "develop"
        } else {
            "flatten"
        };
        output_file(run.files, &run.report, &wanted, command)
    })
    .await?;
    Ok(attachment(&file, bytes))
}

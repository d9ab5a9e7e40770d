//! `sheetform check`: topology and developability of any mesh.

use crate::report::{Command, Report, Status, Timings};
use sheetform_io::{glb_vertex_colours, ply_vertex_colours, UpAxis};
use sheetform_mesh::{mesh_topology, LengthUnit, MeshTopology, TriangleMesh, VertexDevelopability};
use std::path::Path;

use super::context::RunContext;
use super::error::{Outcome, PipelineError};
use super::flatten::stored_flattening_error;
use super::outputs::output_names;
use super::sheet_report::{angle_defects, defect_colours, DEFAULT_ANGLE_TOLERANCE};
use std::time::Instant;

/// Knobs of `sheetform check`.
#[derive(Debug, Clone)]
pub struct CheckOptions {
    /// Merge vertices closer than this (model units); `None`: no welding.
    pub weld: Option<f64>,
    /// Angle defects up to this (radians) count as developable.
    pub tolerance: f64,
    /// Length unit of the file.
    pub unit: LengthUnit,
    /// Where the mesh came from (recorded in the report; its file stem names the GLB).
    pub input: Option<String>,
    /// The mesh's name in the outputs (default: the input's file stem, or `mesh`).
    pub name: Option<String>,
}

impl Default for CheckOptions {
    fn default() -> Self {
        Self {
            weld: None,
            tolerance: DEFAULT_ANGLE_TOLERANCE,
            unit: LengthUnit::Mm,
            input: None,
            name: None,
        }
    }
}

/// A finished check: the mesh, its per-vertex figures, the files and the report.
#[derive(Debug)]
pub struct CheckRun {
    /// The mesh as read (and welded).
    pub mesh: TriangleMesh,
    /// The input vertex each vertex of `mesh` is (after welding: the first of those
    /// merged into it).
    pub source_vertices: Vec<u32>,
    /// Its topology.
    pub topology: MeshTopology,
    /// Per-vertex angle defects and curvature.
    pub vertices: VertexDevelopability,
    /// Rendered outputs `(file name, bytes)`.
    pub files: Vec<(String, Vec<u8>)>,
    /// The report.
    pub report: Report,
    /// How the run ended (the report's `status` says the same).
    pub outcome: Outcome,
}

/// Welds vertices closer than `weld` (model units), if asked; returns how many merged and
/// the input vertex each vertex now is (all of them when nothing is welded).
pub(crate) fn weld_input(
    mesh: &mut TriangleMesh,
    weld: Option<f64>,
) -> Result<(Option<usize>, Vec<u32>), PipelineError> {
    if let Some(w) = weld {
        if !(w.is_finite() && w >= 0.0) {
            return Err(PipelineError::Option {
                option: "--weld",
                message: format!(
                    "must be a non-negative distance, got {}",
                    sheetform_geometry::short_number(w)
                ),
            });
        }
    }
    let faces = mesh.triangles.len();
    let before = mesh.positions.len();
    let origins = match weld {
        Some(tolerance) => mesh.weld_keeping_origins(tolerance),
        None => (0..before as u32).collect(),
    };
    let merged = weld.map(|_| before - mesh.positions.len());
    if let Some(w) = weld {
        if mesh.triangles.is_empty() && faces > 0 {
            return Err(PipelineError::Option {
                option: "--weld",
                message: format!(
                    "welding at {} merged the mesh into {} vertices and left none of its {faces} faces; give a distance below its edge lengths",
                    sheetform_geometry::short_number(w),
                    mesh.positions.len()
                ),
            });
        }
    }
    Ok((merged, origins))
}

/// The name of a mesh for its outputs: the one given, else the input file's stem, else
/// `mesh`.
pub(crate) fn mesh_name(name: Option<&str>, input: Option<&str>) -> String {
    if let Some(name) = name {
        return name.to_string();
    }
    input
        .and_then(|i| Path::new(i).file_stem())
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "mesh".into())
}

/// Measures the developability of any triangle mesh (read from OBJ, PLY, STL, OFF by the
/// caller, or built in memory): topology
/// (non-manifold edges and vertices, degenerate faces, orientability, boundary loops),
/// angle defects, Gaussian curvature, `D[M]` and `G[X]` (Wang & Tang 2004), and the
/// isometry error of the flattening stored in the file's `vt`; renders a colour map of
/// |angle defect| (PLY with vertex colours and GLB).
///
/// # Errors
/// [`PipelineError::Option`] for a bad weld distance; [`PipelineError::Cancelled`].
pub fn run_check(mesh: TriangleMesh, options: &CheckOptions, context: &RunContext) -> Result<CheckRun, PipelineError> {
    let start = Instant::now();
    if !(options.tolerance.is_finite() && options.tolerance >= 0.0) {
        return Err(PipelineError::Option {
            option: "--tolerance",
            message: format!(
                "must be a non-negative angle in radians, got {}",
                sheetform_geometry::short_number(options.tolerance)
            ),
        });
    }
    let mut mesh = mesh;
    let (welded, source_vertices) = weld_input(&mut mesh, options.weld)?;
    let parsed = Instant::now();
    context.progress("measuring", 0.1);
    let mm = options.unit.millimetres();
    let topology = mesh_topology(&mesh);
    let (defects, vertices) = angle_defects(&mesh, &topology, options.tolerance, mm);
    let stored = mesh.corner_uvs.as_ref().map(|uv| stored_flattening_error(&mesh, uv));
    let solved = Instant::now();
    context.check_cancelled()?;
    let colours = defect_colours(&vertices.angle_defect, options.tolerance, defects.angle_defect_max_rad);
    let name = mesh_name(options.name.as_deref(), options.input.as_deref());
    let mut files = Vec::new();
    if context.renders_all() {
        files.push((
            "developability.ply".to_string(),
            ply_vertex_colours(&mesh, &colours, &vertices.angle_defect, "angle_defect").into_bytes(),
        ));
    }
    files.push((
        "developability.glb".to_string(),
        glb_vertex_colours(&mesh, &colours, mm / 1000.0, &name, UpAxis::Y),
    ));
    let exported = Instant::now();
    let mut report = Report::new(Command::Check, options.input.clone());
    report.model_unit = options.unit;
    report.status = if topology.is_clean() && defects.vertices_over_tolerance == 0 {
        Status::Developable
    } else {
        Status::NotDevelopable
    };
    report.vertex_count = mesh.positions.len();
    report.face_count = mesh.triangles.len();
    report.isometry_error_max_relative = stored.map(|s| s.0);
    report.isometry_error_mean_relative = stored.map(|s| s.1);
    report.flat_area_mm2 = stored.map(|s| s.2 * mm * mm);
    report.area_mm2 = (0..mesh.triangles.len()).map(|f| mesh.face_area(f)).sum::<f64>() * mm * mm;
    report.angle_defects = Some(defects);
    report.topology = Some(topology.clone());
    report.welded_vertex_count = welded;
    report.outputs = output_names(&files);
    report.timings = Timings::from_stages(start, parsed, solved, exported);
    Ok(CheckRun {
        mesh,
        source_vertices,
        topology,
        vertices,
        files,
        report,
        outcome: Outcome::Ok,
    })
}

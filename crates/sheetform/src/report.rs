//! `report.json`: one vocabulary for every command. The same key means the same measure
//! everywhere, and every key with a unit says it (`_mm`, `_mm2`, `_rad`, `_ms`). Lengths
//! are always reported in millimetres, whatever the model's unit.

use serde::Serialize;

/// Version of the report format.
pub const REPORT_FORMAT: &str = "sheetform-report/1";

/// Wall-clock times of the pipeline stages.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Timings {
    /// Reading and validating the input.
    pub parse_ms: f64,
    /// The method itself (sampling, solving, meshing).
    pub solve_ms: f64,
    /// Rendering and writing the outputs.
    pub export_ms: f64,
    /// Everything.
    pub total_ms: f64,
}

/// Where a shape stops being admissible, in millimetres.
#[derive(Debug, Clone, Serialize)]
pub struct RegressionEntry {
    /// What fails.
    pub message: String,
    /// Region index.
    pub region: usize,
    /// Arc-length range of the failing rulings along the control curve.
    pub arc_length_range_mm: [f64; 2],
    /// Where on the flat sheet.
    pub flat_point_mm: [f64; 2],
    /// Where on the bent sheet, if known.
    pub point_mm: Option<[f64; 3]>,
}

/// Per curved region.
#[derive(Debug, Clone, Serialize)]
pub struct RegionReport {
    /// Region name.
    pub name: String,
    /// Sampled rulings.
    pub ruling_count: usize,
    /// Arc length of the control curve.
    pub curve_length_mm: f64,
    /// Total bending `Σ|φ|`.
    pub total_fold_rad: f64,
    /// Largest angle between neighbouring strips.
    pub max_fold_rad: f64,
    /// Eq. 6 holds on every ruling.
    pub admissible: bool,
    /// Smallest distance by which the curve of regression stays off the sheet (negative:
    /// inside); `null` when all rulings are parallel.
    pub regression_margin_mm: Option<f64>,
    /// Largest distance between the mesh's geodesic and the control curve.
    pub curve_deviation_mm: f64,
    /// Closed regions: largest gap between the glued end rulings.
    pub closure_gap_mm: Option<f64>,
}

/// The report every command writes.
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    /// [`REPORT_FORMAT`].
    pub format: &'static str,
    /// `bend`, …
    pub command: String,
    /// sheetform version.
    pub sheetform_version: &'static str,
    /// Input file, if any.
    pub input: Option<String>,
    /// `ok` or `inadmissible`.
    pub status: String,
    /// The model's length unit.
    pub model_unit: String,
    /// Whether the shape is admissible (no singular point on the sheet).
    pub admissible: bool,
    /// Where it is not.
    pub regression_entry: Option<RegressionEntry>,
    /// Mesh vertices.
    pub vertex_count: usize,
    /// Mesh triangles.
    pub face_count: usize,
    /// Curved + planar pieces.
    pub piece_count: usize,
    /// Rulings over all curved regions.
    pub ruling_count: usize,
    /// `max | |e_3D| − |e_flat| | / |e_flat|` over the mesh edges.
    pub isometry_error_max_relative: f64,
    /// Mean of the same.
    pub isometry_error_mean_relative: f64,
    /// Largest angle between the surface normals at the two ends of a ruling.
    pub developability_error_max_rad: f64,
    /// Area of the flat pattern.
    pub flat_area_mm2: f64,
    /// Area of the 3D surface.
    pub area_mm2: f64,
    /// Per curved region.
    pub regions: Vec<RegionReport>,
    /// Files written (relative to the output directory).
    pub outputs: Vec<String>,
    /// Stage times.
    pub timings: Timings,
}

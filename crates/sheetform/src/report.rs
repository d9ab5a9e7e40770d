//! `report.json`: one vocabulary for every command. The same key means the same measure
//! everywhere, and every key with a unit says it (`_mm`, `_mm2`, `_rad`, `_ms`). Lengths
//! are always reported in millimetres, whatever the model's unit.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use sheetform_photo::{AngleSummary, StageTimes};

/// Version of the report format.
pub const REPORT_FORMAT: &str = "sheetform-report/1";

/// The command that wrote a report.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Command {
    /// System A: a sheet bent by control curves.
    Bend,
    /// System B: a slit sheet.
    Slit,
    /// System C: developability-preserving FFD.
    Ffd,
    /// System D: patterns from a photograph.
    Photo,
    /// Developability of any mesh.
    Check,
    /// Any mesh laid out in the plane.
    Flatten,
    /// A target shape made of exactly developable pieces (inverse design).
    Develop,
    /// The printable pattern of a mesh that already has its flat layout (the bindings'
    /// `pattern`).
    Pattern,
}

/// How a run ended, in one word per case (the process exit code follows from it).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
pub enum Status {
    /// Every bound the report states holds.
    #[serde(rename = "ok")]
    Ok,
    /// `bend`: the shape cannot be made; `regression_entry` says where.
    #[serde(rename = "inadmissible")]
    Inadmissible,
    /// `check`: clean topology and every angle defect within the tolerance.
    #[serde(rename = "developable")]
    Developable,
    /// `check`: not so; `photo`: a ruled patch misses the refinement's bound.
    #[serde(rename = "not developable")]
    NotDevelopable,
    /// `flatten`: the pattern overlaps itself.
    #[serde(rename = "overlapping")]
    Overlapping,
    /// `ffd`, `slit`: a solve stopped before its bound.
    #[serde(rename = "not converged")]
    NotConverged,
    /// `photo`: the drawing leaves some curve's depth free.
    #[serde(rename = "depth undetermined")]
    DepthUndetermined,
    /// `flatten`: the pattern stretches an edge by more than the distortion bound;
    /// `ffd`: a restoration ended above its defect tolerance.
    #[serde(rename = "out of tolerance")]
    OutOfTolerance,
}

impl Status {
    /// The word written in report.json.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Ok => "ok",
            Self::Inadmissible => "inadmissible",
            Self::Developable => "developable",
            Self::NotDevelopable => "not developable",
            Self::Overlapping => "overlapping",
            Self::NotConverged => "not converged",
            Self::DepthUndetermined => "depth undetermined",
            Self::OutOfTolerance => "out of tolerance",
        }
    }
}

impl std::fmt::Display for Status {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// How a chart of a pattern was laid out in the plane.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum ChartMethod {
    /// Exact unfolding from the edge lengths.
    Exact,
    /// Least-squares conformal maps.
    Lscm,
    /// As-rigid-as-possible.
    Arap,
}

/// Wall-clock times of the pipeline stages.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize, JsonSchema)]
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

impl Timings {
    /// Stage times from the instants a pipeline passed: start, input read, solved,
    /// outputs rendered.
    pub fn from_stages(
        start: std::time::Instant,
        parsed: std::time::Instant,
        solved: std::time::Instant,
        exported: std::time::Instant,
    ) -> Self {
        let ms = |d: std::time::Duration| d.as_secs_f64() * 1e3;
        Self {
            parse_ms: ms(parsed - start),
            solve_ms: ms(solved - parsed),
            export_ms: ms(exported - solved),
            total_ms: ms(exported - start),
        }
    }
}

/// Where a shape stops being admissible, in millimetres.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
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
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
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

/// One strip of a slit sheet (`slit`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct StripReport {
    /// Strip index (0 at `z = 0`).
    pub strip: usize,
    /// Quads per half strip (after subdivision).
    pub quad_count: usize,
    /// Levenberg–Marquardt iterations (all subdivision levels).
    pub iterations: usize,
    /// The paper's penalty `F` (Eq. 1) before solving.
    pub initial_penalty: f64,
    /// `F` at the end.
    pub penalty: f64,
    /// `F`'s terms at the end, each with its weight.
    pub penalty_terms: sheetform_slit::strip_penalty::PenaltyTerms,
    /// Largest distance of the strip's end from the symmetry plane.
    pub gap_mm: f64,
    /// `gap_mm / (L2 + L3)`.
    pub normalised_error: f64,
    /// Converged (see `StripSolveInfo::converged`).
    pub converged: bool,
    /// Solver time.
    pub time_ms: f64,
}

/// The developability-preserving FFD (`ffd`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct FfdReport {
    /// The restoration method.
    pub solver: sheetform_ffd::SolverMethod,
    /// The constrained solver's bending weight (`solver.bending_weight`; default 3e-3;
    /// 0: the springs alone, as in the paper).
    pub bending_weight: f64,
    /// The constrained solver's line-search memory (`solver.line_search_memory`; 1:
    /// monotone, default 12).
    pub line_search_memory: usize,
    /// The constrained solver's step unknowns (`solver.step_unknowns`).
    pub step_unknowns: sheetform_ffd::StepUnknowns,
    /// Panels (mesh patches).
    pub panel_count: usize,
    /// Nodes (linked vertex sets): one parameter triple each.
    pub node_count: usize,
    /// Nodes shared by several vertices (seams between panels).
    pub linked_node_count: usize,
    /// Largest distance between linked copies after restoration (0: no crack).
    pub linked_vertex_gap_max_mm: f64,
    /// Whether the embedding was linear (box lattice) rather than Newton's method.
    pub linear_embedding: bool,
    /// Time to embed the vertices (0 when the run resumed an earlier design: it kept
    /// that design's embedding).
    pub embedding_time_ms: f64,
    /// Deformations taken unchanged from an earlier run's design (the editor's warm
    /// start, `FfdRunOptions::warm_start`): their `steps` entries, times included, are
    /// that run's. 0 for a run from scratch (the CLI).
    pub resumed_deformations: usize,
    /// Control points per direction.
    pub lattice_counts: [usize; 3],
    /// Degrees per direction.
    pub lattice_degrees: [usize; 3],
    /// Angle defects of the plain FFD (last step), `D[M]` and `G[X]` included.
    pub angle_defects_before: AngleDefects,
    /// Angle defects after restoration.
    pub angle_defects_after: AngleDefects,
    /// Largest edge-length error of the plain FFD's panels laid flat by least squares
    /// (what cutting the undeveloped shape would cost).
    pub deformed_pattern_edge_length_max_relative: f64,
    /// Every deformation step.
    pub steps: Vec<FfdStepReport>,
}

/// One deformation and its restoration (`ffd`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct FfdStepReport {
    /// Name from the scene.
    pub name: String,
    /// Solver used.
    pub solver: sheetform_ffd::SolverMethod,
    /// Iterations (constrained: factorised steps) or penalty updates (paper).
    pub iterations: usize,
    /// Chord steps of the constrained solver: projections that reused the last
    /// factorisation (not counted in `iterations`).
    #[serde(default)]
    pub chord_steps: usize,
    /// Whether the solver met its stopping rule.
    pub converged: bool,
    /// The constrained solver's bending weight at the end of the step (the scene's
    /// `solver.bending_weight`, or `solver.stall_bending_weight` after a fallback).
    pub bending_weight: f64,
    /// The iteration after which the bending term was switched on because the
    /// restoration stalled (`null`: it did not).
    pub bending_fallback_iteration: Option<usize>,
    /// Restorations along the deformation's path (1: the whole deformation at once;
    /// more with `solver.continuation`; 0: method `none`).
    pub sub_steps: usize,
    /// Nodes optimised (the selective set).
    pub variable_node_count: usize,
    /// Constrained interior vertices.
    pub constraint_count: usize,
    /// `G[X₀]` over the constrained vertices (Eq. 2-5).
    pub developability_g_before_rad2: f64,
    /// `G[X*]`.
    pub developability_g_after_rad2: f64,
    /// Largest angle defect before.
    pub angle_defect_max_before_rad: f64,
    /// Largest angle defect after.
    pub angle_defect_max_after_rad: f64,
    /// Spring energy `E(X*)` (Eq. 2-2).
    pub spring_energy_mm2: f64,
    /// Largest vertex displacement from the plain FFD.
    pub deviation_max_mm: f64,
    /// Largest relative edge-length change from the plain FFD.
    pub edge_length_change_max_relative: f64,
    /// Mean relative edge-length change.
    pub edge_length_change_mean_relative: f64,
    /// Largest angle between the normals of two triangles sharing an edge, inside a panel
    /// or across a seam between two panels, in the plain FFD.
    pub fold_angle_max_before_rad: f64,
    /// The same after restoration: far above `fold_angle_max_before_rad` when the
    /// restoration folded the panels into node-scale zig-zags (crinkles) or creased a
    /// seam.
    pub fold_angle_max_after_rad: f64,
    /// Largest change of one edge's signed fold angle from the plain FFD to the
    /// restored shape (panels and seams): the crease the restoration added, also where
    /// the largest fold is one the design has on purpose (a crotch, a pleat).
    pub fold_angle_change_max_rad: f64,
    /// Solver time.
    pub time_ms: f64,
}

/// The slit-sheet design (`slit`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct SlitReport {
    /// Strips one by one or all together.
    pub solve_mode: sheetform_slit::SolveMode,
    /// How the no-gap condition is enforced.
    pub gap_handling: sheetform_slit::GapHandling,
    /// Subdivisions applied.
    pub subdivision_count: usize,
    /// `E = G / (L2 + L3)` (§4), `G` the largest gap over all strips.
    pub normalised_error: f64,
    /// `G`.
    pub gap_max_mm: f64,
    /// Every strip converged.
    pub converged: bool,
    /// Per strip.
    pub strips: Vec<StripReport>,
    /// The mould (`null` when disabled).
    pub mould: Option<MouldReport>,
    /// Fit to the scanned points (`null` without a scan).
    pub scan_fit: Option<ScanFitReport>,
}

/// How close the strips are to the scanned points (`slit` with a scan, §4.1): distance
/// from every ridge-line end point to its nearest scanned point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ScanFitReport {
    /// Points in the scan.
    pub scanned_point_count: usize,
    /// Ridge-line end points measured (half model).
    pub fitted_point_count: usize,
    /// Mean distance.
    pub distance_mean_mm: f64,
    /// Root-mean-square distance.
    pub distance_rms_mm: f64,
    /// Largest distance.
    pub distance_max_mm: f64,
}

/// The printable mould (`slit`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct MouldReport {
    /// Triangles in `mould.stl`.
    pub face_count: usize,
    /// Enclosed volume.
    pub volume_mm3: f64,
    /// Every edge is shared by exactly two faces in opposite directions.
    pub watertight: bool,
}

/// Angle-defect figures of a mesh (Wang & Tang 2004): the same keys in every command.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct AngleDefects {
    /// Interior vertices measured.
    pub interior_vertex_count: usize,
    /// Largest |2π − Σθ| over interior vertices.
    pub angle_defect_max_rad: f64,
    /// Mean |angle defect|.
    pub angle_defect_mean_rad: f64,
    /// Root mean square angle defect.
    pub angle_defect_rms_rad: f64,
    /// Interior vertices with |angle defect| above `tolerance_rad`.
    pub vertices_over_tolerance: usize,
    /// The tolerance.
    pub tolerance_rad: f64,
    /// Largest |discrete Gaussian curvature| (Eq. 2-1).
    pub gaussian_curvature_max_per_mm2: f64,
    /// `D[M]` (Definition 2-1): area fraction of developable vertices (1 = developable).
    pub developability_d: f64,
    /// `G[X]` = Σ g² (Eq. 2-5).
    pub developability_g_rad2: f64,
}

/// One chart of a flattening (`flatten`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ChartReport {
    /// Chart name.
    pub name: String,
    /// Layout method.
    pub method: ChartMethod,
    /// Faces in the chart.
    pub face_count: usize,
    /// Largest relative edge-length error.
    pub edge_length_max_relative: f64,
    /// Mean relative edge-length error.
    pub edge_length_mean_relative: f64,
    /// Largest relative area error.
    pub area_max_relative: f64,
    /// Mean relative area error.
    pub area_mean_relative: f64,
    /// Faces flipped on the pattern.
    pub flipped_face_count: usize,
    /// Crossings of the pattern's boundary with itself.
    pub boundary_crossing_count: usize,
}

/// The cut into charts (`flatten` of a closed or high-genus mesh).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct SegmentationReport {
    /// Charts in the end.
    pub chart_count: usize,
    /// Charts separated by sharp creases and user seams alone.
    pub initial_chart_count: usize,
    /// Charts split in two because they were not disks or flattened with too much
    /// distortion or with overlaps.
    pub split_count: usize,
    /// Charts cut open along straight seams (from cone points to the boundary, between
    /// boundary loops) to become flat disks.
    #[serde(default)]
    pub opened_chart_count: usize,
    /// Small charts (slivers) joined to a neighbour.
    #[serde(default)]
    pub merged_chart_count: usize,
    /// Borders between split charts moved onto the shortest edge path between their ends.
    #[serde(default)]
    pub straightened_border_count: usize,
    /// Mesh edges cut open (each appears on two charts).
    pub seam_edge_count: usize,
    /// User-given seam edges (OBJ `l`).
    pub user_seam_edge_count: usize,
    /// Crease angle used (degrees).
    pub crease_angle_degrees: f64,
    /// Distortion bound each chart had to meet.
    pub max_edge_distortion_relative: f64,
}

/// The net of a faceted mesh (`flatten` with the net layout).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct NetReport {
    /// Pieces of the net.
    pub piece_count: usize,
    /// Edges kept whole across which the surface bends (folds to make).
    pub fold_edge_count: usize,
    /// Edges cut (glued back together, with a seam ID and a glue tab).
    pub cut_edge_count: usize,
    /// Total length of the cut edges in 3D.
    pub cut_length_mm: f64,
    /// User-given seam edges (OBJ `l`), always cut.
    pub user_seam_edge_count: usize,
    /// Starting faces tried (the net with the fewest pieces kept).
    pub attempt_count: usize,
    /// Pieces joined to a neighbour after the growth.
    pub merged_piece_count: usize,
    /// Edges cut because the budget of overlap tests ran out (0 on ordinary meshes; more
    /// pieces than the budget-free growth would give, never an overlap).
    #[serde(default)]
    pub budget_cut_count: usize,
}

/// The printable pattern (`bend`, `flatten`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct PatternReport {
    /// Scale factor applied (1 = true size).
    pub scale: f64,
    /// Width of the pattern as printed.
    pub width_mm: f64,
    /// Height of the pattern as printed.
    pub height_mm: f64,
    /// Paper of the tiled PDF.
    pub page: sheetform_pattern::PageSize,
    /// PDF tile rows.
    pub tile_rows: usize,
    /// PDF tile columns.
    pub tile_columns: usize,
    /// Pages of the tiled PDF: the tiles that show part of the pattern.
    pub page_count: usize,
    /// Whether the PDF prints the pieces packed onto its pages (one page each, fewer
    /// pages than tiling the layout) rather than tiles of the layout.
    #[serde(default)]
    pub pieces_packed_on_pages: bool,
    /// Pieces to cut (connected parts of the pattern).
    pub piece_count: usize,
    /// Sheets the pieces are packed on (0 when not packed).
    pub sheet_count: usize,
    /// Seams (runs of edges glued to a run elsewhere), each with an ID to print on both
    /// copies.
    pub seam_count: usize,
    /// Seams whose ID is not printed on both copies (no room off every line on one of
    /// them, or seam labels turned off), counted from the labels drawn.
    #[serde(default)]
    pub seam_id_missing_count: usize,
    /// Mountain folds drawn.
    pub mountain_fold_count: usize,
    /// Valley folds drawn.
    pub valley_fold_count: usize,
    /// Glue tabs placed, narrowed, dropped (when asked for).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tabs: Option<sheetform_pattern::TabReport>,
    /// Seam allowance added outside every piece (0: none).
    #[serde(default)]
    pub seam_allowance_mm: f64,
    /// Laser kerf compensated on the cut lines (0: none).
    #[serde(default)]
    pub kerf_mm: f64,
    /// The bend allowance given to every mountain and valley fold for the sheet's
    /// thickness (when asked for).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bend_allowance: Option<BendAllowanceReport>,
    /// Notches cut into the seam allowance.
    #[serde(default)]
    pub notch_count: usize,
    /// Pieces with a grain line.
    #[serde(default)]
    pub grain_line_count: usize,
    /// Labels printed (piece names and seam IDs), each upright, inside its piece, over no
    /// line and no other label.
    #[serde(default)]
    pub label_count: usize,
    /// Labels printed smaller than asked to fit.
    #[serde(default)]
    pub label_shrunk_count: usize,
    /// Labels left out: no room in their piece off every line (tiny faces).
    #[serde(default)]
    pub label_dropped_count: usize,
}

/// The sheet's thickness and how its bends changed the pattern.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct BendAllowanceReport {
    /// Sheet thickness.
    pub thickness_mm: f64,
    /// Inner bend radius.
    pub inner_radius_mm: f64,
    /// K-factor (ANSI convention).
    pub k_factor: f64,
    /// Where the thickness lies relative to the model's surface.
    pub material_side: sheetform_pattern::MaterialSide,
    /// Folds given a bend zone.
    pub bend_count: usize,
    /// Square corner reliefs cut where two bend zones meet at their ends.
    #[serde(default)]
    pub corner_relief_count: usize,
    /// Smallest change of flat length across a bend against the zero-thickness pattern
    /// (negative: a bend deduction; 0 without bends).
    pub flat_change_min_mm: f64,
    /// Largest change of flat length across a bend.
    pub flat_change_max_mm: f64,
}

/// The report every command writes. Keys that do not apply to a command are left out.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct Report {
    /// [`REPORT_FORMAT`].
    pub format: String,
    /// Which command wrote it.
    pub command: Command,
    /// sheetform version.
    pub sheetform_version: String,
    /// Input file, if any.
    pub input: Option<String>,
    /// How the run ended.
    pub status: Status,
    /// The model's length unit.
    pub model_unit: sheetform_mesh::LengthUnit,
    /// Mesh vertices.
    pub vertex_count: usize,
    /// Mesh triangles.
    pub face_count: usize,
    /// `max | |e_3D| − |e_flat| | / |e_flat|` over the mesh edges (for `check`: of the
    /// flattening stored in the file's `vt`; absent when there is none).
    pub isometry_error_max_relative: Option<f64>,
    /// Mean of the same.
    pub isometry_error_mean_relative: Option<f64>,
    /// Angle defects.
    pub angle_defects: Option<AngleDefects>,
    /// Area of the flat pattern (when there is one).
    pub flat_area_mm2: Option<f64>,
    /// Area of the 3D surface.
    pub area_mm2: f64,
    /// Mesh topology (`check`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub topology: Option<sheetform_mesh::MeshTopology>,
    /// Vertices merged by `--weld` (`check`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub welded_vertex_count: Option<usize>,
    /// Whether the shape is admissible (`bend`: no singular point on the sheet).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub admissible: Option<bool>,
    /// Where it is not (`bend`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub regression_entry: Option<RegressionEntry>,
    /// Curved + planar pieces (`bend`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub piece_count: Option<usize>,
    /// Rulings over all curved regions (`bend`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ruling_count: Option<usize>,
    /// Largest angle between the surface normals at the two ends of a ruling (`bend`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub developability_error_max_rad: Option<f64>,
    /// Per curved region (`bend`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub regions: Vec<RegionReport>,
    /// The printable pattern (`bend`, `flatten`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pattern: Option<PatternReport>,
    /// Charts of the pattern (`flatten`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub charts: Vec<ChartReport>,
    /// How the mesh was laid out (`flatten`): whole, charts or net.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub layout: Option<sheetform_flatten::Layout>,
    /// Why that layout (`flatten`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub layout_reason: Option<String>,
    /// How a closed or high-genus mesh was cut into charts (`flatten`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub segmentation: Option<SegmentationReport>,
    /// The net (`flatten` with the net layout).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub net: Option<NetReport>,
    /// The solver's report (`flatten`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub solver: Option<sheetform_solve::SolverInfo>,
    /// `slit`: the strips, the gap and the mould.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slit: Option<SlitReport>,
    /// `ffd`: the deformation steps and their restoration.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ffd: Option<FfdReport>,
    /// `photo`: the reconstruction from an annotated photograph.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub photo: Option<PhotoReport>,
    /// `develop`: how far the pieces moved from the target to become developable.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub develop: Option<DevelopReport>,
    /// What the user should know of the result that no bound states (a model printed
    /// too small to fold, ...): each a sentence saying what to do.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// Files written (relative to the output directory).
    pub outputs: Vec<String>,
    /// Stage times.
    pub timings: Timings,
}

impl Report {
    /// The JSON Schema of report.json.
    pub fn json_schema() -> serde_json::Value {
        serde_json::to_value(schemars::schema_for!(Report)).expect("schema serialises")
    }

    /// An empty report of `command` (fields filled by the pipeline).
    pub fn new(command: Command, input: Option<String>) -> Self {
        Self {
            format: REPORT_FORMAT.into(),
            command,
            sheetform_version: env!("CARGO_PKG_VERSION").into(),
            input,
            status: Status::Ok,
            model_unit: sheetform_mesh::LengthUnit::Mm,
            vertex_count: 0,
            face_count: 0,
            isometry_error_max_relative: None,
            isometry_error_mean_relative: None,
            angle_defects: None,
            flat_area_mm2: None,
            area_mm2: 0.0,
            topology: None,
            welded_vertex_count: None,
            admissible: None,
            regression_entry: None,
            piece_count: None,
            ruling_count: None,
            developability_error_max_rad: None,
            regions: vec![],
            pattern: None,
            charts: vec![],
            layout: None,
            layout_reason: None,
            segmentation: None,
            net: None,
            solver: None,
            slit: None,
            ffd: None,
            photo: None,
            develop: None,
            warnings: vec![],
            outputs: vec![],
            timings: Timings::default(),
        }
    }
}

/// What `develop` did to the target (lengths in millimetres, angles in radians).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct DevelopReport {
    /// Where the target was cut: `automatic` (found, with the drawn seams among them) or
    /// `drawn` (the OBJ `l` polylines only).
    pub seams: crate::pipeline::SeamSource,
    /// Pieces in the pattern: the `seam_piece_count` pieces the seams cut, and
    /// `overlap_split_count` more where a developed piece would overlap itself in the
    /// plane (a band that unrolls into more than a full turn) and its unfolding was cut
    /// in two.
    pub piece_count: usize,
    /// Pieces the target was cut into along its seams.
    pub seam_piece_count: usize,
    /// Pieces added by the unfolding, which cuts a developed piece that would overlap
    /// itself in the plane.
    pub overlap_split_count: usize,
    /// Edges cut in the printed pattern: the seams, the slits, and the cuts the
    /// unfolding added (a piece that would overlap itself cut in two, a ring opened).
    /// Read from the pattern: a cut edge borders two pattern pieces (or one piece twice).
    pub seam_edge_count: usize,
    /// Total length of the cut edges (`seam_edge_count`), on the developed model.
    pub seam_length_mm: f64,
    /// `seam_length_mm` over the target's bounding-box diagonal.
    pub seam_length_relative: f64,
    /// Automatic seams: the area-weighted RMS angle between the target's face normals and
    /// the cone fitted to their piece, for the worst piece (how far from developable the
    /// pieces were before they were made exact).
    pub normal_deviation_rms_deg: Option<f64>,
    /// Automatic seams: slits cut from cone points inside a piece (a box's corner) to
    /// its border, so they need not be flattened (counted in `seam_edge_count`).
    pub slit_count: usize,
    /// Automatic seams: seam vertices slid onto smooth curves over the developed surface
    /// before the pieces were developed again (0: the seams run along the mesh's edges
    /// as found: smoothing off, nothing to smooth, or its result not developable or
    /// farther than allowed).
    #[serde(default)]
    pub seam_smoothed_vertex_count: usize,
    /// Vertices inside a piece, made flat (angle sum 2π).
    pub constrained_vertex_count: usize,
    /// Largest angle defect inside a piece, in the target.
    pub angle_defect_max_before_rad: f64,
    /// Largest angle defect inside a piece, in the result (the bound is
    /// `angle_defect_tolerance_rad`).
    pub angle_defect_max_rad: f64,
    /// The bound on `angle_defect_max_rad`.
    pub angle_defect_tolerance_rad: f64,
    /// Gauss–Newton steps (over every solve: a solve that left cone points unflattened is
    /// run again after slits from them, counted in `slit_count`).
    pub iterations: usize,
    /// Two-sided Hausdorff distance between the result and the target.
    pub hausdorff_mm: f64,
    /// `hausdorff_mm` over the target's bounding-box diagonal.
    pub hausdorff_relative: f64,
    /// Mean distance between the surfaces (both ways).
    pub distance_mean_mm: f64,
    /// `distance_mean_mm` over the target's bounding-box diagonal.
    pub distance_mean_relative: f64,
    /// The target's bounding-box diagonal.
    pub bounding_box_diagonal_mm: f64,
    /// Largest vertex displacement.
    pub displacement_max_mm: f64,
    /// The bound on `hausdorff_mm` asked for (`--max-distance`), if any: above it the
    /// status is `out of tolerance`.
    pub max_distance_mm: Option<f64>,
    /// Segmentations tried (more pieces each time, while a distance bound was not met or
    /// a piece did not fit the sheet).
    pub attempt_count: usize,
    /// Vertices kept where they are (`--fixed` groups): they do not move at all.
    pub fixed_vertex_count: usize,
    /// Faces of the target as read.
    pub target_face_count: usize,
    /// Faces develop worked on and wrote: the target's, or fewer when a target of more
    /// than `--work-faces` was remeshed first (its boundary, seams and fixed regions
    /// kept); the distances are to the target as read.
    pub work_face_count: usize,
    /// With a sheet (`--sheet`): whether every piece fits on it. `false`: no piece budget
    /// made them fit; the pattern is written without the sheets and the status is `out of
    /// tolerance`.
    pub pieces_fit_sheet: Option<bool>,
    /// The mirror plane kept (`--mirror`), e.g. `x = 0` (the mesh's units): the half on
    /// one side was developed and joined with its mirror image.
    pub mirror_plane: Option<String>,
    /// With a mirror plane: whether the whole is cut along it (a centre seam; `false`:
    /// pieces run across the plane, flat on it).
    pub mirror_seam: Option<bool>,
    /// How far the target is from symmetric in that plane: the two-sided Hausdorff
    /// distance between it and its mirror image over its bounding-box diagonal (0 for a
    /// symmetric target; the developed half's image is this far from the other half).
    pub mirror_asymmetry_relative: Option<f64>,
}

/// `photo`: what the reconstruction from an annotated photograph made (system D,
/// Fondevilla et al.; the counts of their Table 1 and the developability error of §8.2).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct PhotoReport {
    /// 3D control points solved for (after splitting the curves at their crossings).
    pub control_point_count: usize,
    /// Control points in the annotation.
    pub annotated_control_point_count: usize,
    /// Traced curves.
    pub curve_count: usize,
    /// Cubic segments after splitting.
    pub segment_count: usize,
    /// Points where curves are joined.
    pub junction_count: usize,
    /// Crossings left unjoined (`occlusions`).
    pub occluded_crossing_count: usize,
    /// Material patches (minimal cycles not marked as openings).
    pub patch_count: usize,
    /// Cycles marked as openings.
    pub opening_count: usize,
    /// Patches swept by rulings.
    pub ruled_patch_count: usize,
    /// Patches filled by a minimal surface.
    pub filled_patch_count: usize,
    /// Rulings kept.
    pub ruling_count: usize,
    /// Rulings taken from the warping paths.
    pub ruling_candidate_count: usize,
    /// Rulings rejected for leaving their patch.
    pub ruling_rejected_count: usize,
    /// Ruling ends moved from their matched sample onto the point of parallel tangents.
    pub ruling_aligned_count: usize,
    /// Mirror pairs of points.
    pub symmetric_pair_count: usize,
    /// The camera the photo was reconstructed through: `orthographic` or `perspective`.
    pub camera_projection: String,
    /// Its focal length in pixels of the image (perspective only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub camera_focal_length_px: Option<f64>,
    /// Whether that focal length was read from the photo's EXIF
    /// (`FocalLengthIn35mmFilm`) rather than given in the annotation.
    #[serde(default)]
    pub camera_focal_length_from_exif: bool,
    /// Whether that focal length was estimated from the drawing (neither the annotation
    /// nor the photo's EXIF gives one): the one whose linear solve leaves the rulings most
    /// nearly developable (`sheetform_photo::estimate_focal_length`).
    #[serde(default)]
    pub camera_focal_length_estimated: bool,
    /// Unit normal of the symmetry plane (model frame: x right, y up, z towards the camera).
    pub symmetry_plane_normal: [f64; 3],
    /// Angle between the surface normals at the two ends of each ruling after the
    /// paper's linear solve (degrees).
    pub developability_error_linear: AngleSummary,
    /// The same after the refinement (absent when it is switched off).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub developability_error_refined: Option<AngleSummary>,
    /// Refinement iterations.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refinement_iterations: Option<usize>,
    /// Whether the refinement met its bound (sine of the error ≤ 1e-12).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refinement_converged: Option<bool>,
    /// The refinement stopped at its work budget (`refinement_converged` says whether
    /// the bound was met all the same).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refinement_work_bound_reached: Option<bool>,
    /// Largest move of a control point by the refinement (pixels).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refinement_displacement_max_px: Option<f64>,
    /// Largest slide of a ruling's end along its curve by the refinement (pixels).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refinement_slide_max_px: Option<f64>,
    /// The refinement's bound on the sine of the largest developability error.
    pub refinement_bound: f64,
    /// The developability error of the final model, after the symmetrisation (absent
    /// when it is switched off). The status checks this one against `refinement_bound`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub developability_error_symmetrized: Option<AngleSummary>,
    /// What the symmetrisation (§7) did (absent when it is switched off).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub symmetrization: Option<sheetform_photo::SymmetrizationInfo>,
    /// The bands closed around their axis (`back_side: revolve`; absent otherwise): the
    /// model and the pattern are then the whole object.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub revolution: Option<sheetform_photo::Revolution>,
    /// Largest depth sensitivity of a curve: how much of an arbitrary shift of the depth
    /// prior it follows (0: the drawing fixes its depth; 1: free).
    pub depth_sensitivity_max: f64,
    /// The bound on it for a depth to count as fixed.
    pub depth_sensitivity_bound: f64,
    /// Curves whose depth the drawing does not fix (mark their mirror relations).
    pub depth_undetermined_curves: Vec<String>,
    /// Mean distance between the solved curves' projections and the traced curves (px).
    pub reprojection_error_mean_px: f64,
    /// Largest such distance (px).
    pub reprojection_error_max_px: f64,
    /// Scale set by the true size.
    pub millimetres_per_pixel: f64,
    /// Time per stage of the method (ms).
    pub stage_times: StageTimes,
}

//! Report parts shared by the commands: angle defects, colour maps, the fields of every
//! sheet mesh, charts.

use crate::report::{AngleDefects, ChartMethod, ChartReport, Command, Report};
use sheetform_flatten::Distortion;
use sheetform_io::colour_ramp;
use sheetform_mesh::{
    developability_summary, isometry_error, mesh_topology, vertex_developability, MeshTopology, SheetMesh,
    TriangleMesh, VertexDevelopability,
};

/// Developability colour map (the paper's Fig. 4): a logarithmic scale from `tolerance`
/// (blue: developable) to `top` (red; at least 10 × the tolerance), so that typical
/// defects show next to a few large ones (cone points).
pub(crate) fn defect_colours(defects: &[f64], tolerance: f64, top: f64) -> Vec<[f32; 3]> {
    let span = (top.max(10.0 * tolerance) / tolerance).ln();
    defects
        .iter()
        .map(|g| colour_ramp((g.abs().max(tolerance) / tolerance).ln() / span))
        .collect()
}

/// Angle-defect figures of a mesh, lengths converted to millimetres by `mm` per unit.
pub(crate) fn angle_defects(
    mesh: &TriangleMesh,
    topology: &MeshTopology,
    tolerance: f64,
    mm: f64,
) -> (AngleDefects, VertexDevelopability) {
    let vertices = vertex_developability(mesh, topology);
    let s = developability_summary(mesh, topology, &vertices, tolerance);
    (
        AngleDefects {
            interior_vertex_count: s.interior_vertex_count,
            angle_defect_max_rad: s.angle_defect_max_rad,
            angle_defect_mean_rad: s.angle_defect_mean_rad,
            angle_defect_rms_rad: s.angle_defect_rms_rad,
            vertices_over_tolerance: s.vertices_over_tolerance,
            tolerance_rad: s.tolerance_rad,
            gaussian_curvature_max_per_mm2: s.gaussian_curvature_max_per_length2 / (mm * mm),
            developability_d: s.developability_d,
            developability_g_rad2: s.developability_g,
        },
        vertices,
    )
}

/// The report fields every command that makes a [`SheetMesh`] shares: unit, counts, the
/// isometry error of its flat pattern, angle defects, areas (mm, mm²), pieces.
pub(crate) fn sheet_mesh_report(command: Command, input: Option<String>, mesh: &SheetMesh) -> Report {
    sheet_mesh_report_and_defects(command, input, mesh).0
}

/// [`sheet_mesh_report`] and the angle defect at each vertex of `mesh` (radians; 0 on
/// the boundary), the colour map of a live preview.
pub(crate) fn sheet_mesh_report_and_defects(
    command: Command,
    input: Option<String>,
    mesh: &SheetMesh,
) -> (Report, Vec<f64>) {
    let mm = mesh.unit.millimetres();
    let iso = isometry_error(mesh);
    let triangle_mesh = mesh.to_triangle_mesh();
    let topology = mesh_topology(&triangle_mesh);
    let mut report = Report::new(command, input);
    report.model_unit = mesh.unit;
    report.vertex_count = mesh.vertex_count();
    report.face_count = mesh.triangles.len();
    report.isometry_error_max_relative = Some(iso.max_relative);
    report.isometry_error_mean_relative = Some(iso.mean_relative);
    let (figures, vertices) = angle_defects(&triangle_mesh, &topology, DEFAULT_ANGLE_TOLERANCE, mm);
    report.angle_defects = Some(figures);
    report.flat_area_mm2 = Some(mesh.flat_area() * mm * mm);
    report.area_mm2 = mesh.area() * mm * mm;
    report.piece_count = Some(mesh.pieces.len());
    (report, vertices.angle_defect)
}

/// Default tolerance (radians) under which an angle defect counts as zero: 1e-4 rad
/// (0.006°) is far below anything a sheet material can show, and above the rounding of
/// mesh files written with 6–7 significant digits (whose exactly developable meshes show
/// defects of ~1e-5). `--tolerance` sets another.
pub const DEFAULT_ANGLE_TOLERANCE: f64 = 1e-4;

pub(crate) fn chart_report(name: &str, method: ChartMethod, face_count: usize, d: &Distortion) -> ChartReport {
    ChartReport {
        name: name.to_string(),
        method,
        face_count,
        edge_length_max_relative: d.edge_length_max_relative,
        edge_length_mean_relative: d.edge_length_mean_relative,
        area_max_relative: d.area_max_relative,
        area_mean_relative: d.area_mean_relative,
        flipped_face_count: d.flipped_faces.len(),
        boundary_crossing_count: d.boundary_crossings,
    }
}

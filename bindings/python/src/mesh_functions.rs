//! Functions on any mesh given as numpy arrays (from trimesh, libigl, Open3D, …), without
//! files: `check`, `flatten` (whole, in smooth charts or as a net), `develop` (a target
//! made of exactly developable pieces) and `pattern`.

use crate::convert::{float_rows, index_list, index_rows};
use crate::errors::{invalid_argument, python_error, refuse_renamed_keywords};
use crate::pattern_options::pattern_argument;
use crate::run::{output_set, run_interruptibly, Run, RunParts};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sheetform::flatten::ChartOptions;
use sheetform::mesh::LengthUnit;
use sheetform::pipeline::{
    mesh_from_arrays, run_check, run_develop, run_flatten, run_pattern, seam_edges_from_array, sheet_mesh_from_arrays,
    ChartMode, CheckOptions, DevelopOptions, DevelopRunOptions, DistanceBound, FlattenMethod, FlattenOptions,
    SeamSmoothingOptions, SeamSource, SegmentationOptions, DEFAULT_ANGLE_TOLERANCE,
};

/// The mesh of `vertices` and `faces` with its `drawn_seams` (`(k, 2)` vertex pairs), read
/// with the interpreter's lock held, as in `check` (the arrays are the caller's).
fn mesh_with_seams(
    py: Python<'_>,
    vertices: &numpy::PyReadonlyArray2<'_, f64>,
    faces: &numpy::PyReadonlyArray2<'_, i64>,
    drawn_seams: Option<&Bound<'_, PyAny>>,
    name: &str,
) -> PyResult<sheetform::mesh::TriangleMesh> {
    let (v, f) = (vertices.as_slice()?, faces.as_slice()?);
    let seams = drawn_seams.map(|s| index_rows("drawn_seams", s, 2)).transpose()?;
    let seams = seams.as_ref().map(|s| s.as_slice()).transpose()?;
    mesh_from_arrays(v, f, name)
        .and_then(|mut mesh| {
            if let Some(seams) = seams {
                mesh.seam_edges = seam_edges_from_array(&mesh, seams)?;
            }
            Ok(mesh)
        })
        .map_err(|e| python_error(py, e))
}

/// The keywords the mesh functions took before they took the CLI's names (issue 39).
const RENAMED_KEYWORDS: [(&str, &str, &str); 1] = [("unit", "units", "")];

/// `flatten`'s, which also took the drawn seam edges as `seams`.
const FLATTEN_RENAMED_KEYWORDS: [(&str, &str, &str); 2] = [
    ("unit", "units", ""),
    ("seams", "drawn_seams", "the seam edges an OBJ draws as `l` lines"),
];

/// `develop`'s, which took its `--seams` choice as a flag `automatic_seams` and the drawn
/// seam edges as `seams`.
const DEVELOP_RENAMED_KEYWORDS: [(&str, &str, &str); 2] = [
    ("unit", "units", ""),
    (
        "automatic_seams",
        "seams",
        "`\"automatic\"` or `\"drawn\"` as the CLI's --seams",
    ),
];

fn length_unit(units: &str) -> PyResult<LengthUnit> {
    match units {
        "mm" => Ok(LengthUnit::Mm),
        "cm" => Ok(LengthUnit::Cm),
        "m" => Ok(LengthUnit::M),
        "in" => Ok(LengthUnit::In),
        other => Err(invalid_argument(
            "units",
            format!("`{other}`: one of \"mm\", \"cm\", \"m\", \"in\""),
        )),
    }
}

/// Measures the developability of a triangle mesh, as `sheetform check`: topology
/// (non-manifold edges and vertices, degenerate faces, boundary loops), the angle defect
/// `2π − Σθ` at every vertex, `D[M]` and `G[X]` (Wang & Tang 2004).
///
/// `vertices`: `(n, 3)` numbers; `faces`: `(m, 3)` integer indices (any integer dtype).
/// `weld`: merge vertices closer than this first (model units). `tolerance`: defects up
/// to this (radians, default 1e-4) count as developable. `units`: the mesh's length unit (the CLI's `--units`).
///
/// Returns a `Run` with `uv = None`, `angle_defects_rad` per vertex and
/// `source_vertices` (the input vertex each vertex is; after `weld`, the first of those
/// merged); the report's `status` is `"developable"` or `"not developable"`.
#[pyfunction]
#[pyo3(signature = (vertices, faces, *, weld=None, tolerance=None, units="mm", name="mesh", outputs="all", progress=None, **renamed))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn check(
    py: Python<'_>,
    vertices: &Bound<'_, PyAny>,
    faces: &Bound<'_, PyAny>,
    weld: Option<f64>,
    tolerance: Option<f64>,
    units: &str,
    name: &str,
    outputs: &str,
    progress: Option<Py<PyAny>>,
    renamed: Option<&Bound<'_, PyDict>>,
) -> PyResult<Run> {
    refuse_renamed_keywords("check()", renamed, &RENAMED_KEYWORDS)?;
    let v = float_rows("vertices", vertices, 3)?;
    let f = index_rows("faces", faces, 3)?;
    let outputs = output_set(outputs)?;
    let options = CheckOptions {
        weld,
        tolerance: tolerance.unwrap_or(DEFAULT_ANGLE_TOLERANCE),
        unit: length_unit(units)?,
        input: None,
        name: Some(name.to_string()),
    };
    let (v, f) = (v.as_slice()?, f.as_slice()?);
    // (Read with the interpreter's lock held: the arrays are the caller's, which another
    // Python thread could write to; this is their one copy.)
    let mesh = mesh_from_arrays(v, f, name).map_err(|e| python_error(py, e))?;
    let (run, seconds) = run_interruptibly(py, progress, |controls| {
        run_check(mesh, &options, &controls.context(".", outputs))
    })?;
    let defects: Vec<f64> = run.vertices.angle_defect.clone();
    Run::new(
        py,
        RunParts {
            positions: &run.mesh.positions,
            triangles: &run.mesh.triangles,
            flat: None,
            face_pieces: Some(&run.mesh.face_groups),
            pieces: run.mesh.groups.clone(),
            angle_defects_rad: Some(defects),
            source_vertices: Some(&run.source_vertices),
            files: run.files,
            report: run.report,
            outcome: run.outcome,
            pipeline_seconds: seconds,
            meshes: Vec::new(),
            ffd_design: None,
        },
    )
}

/// Lays a mesh out flat, as `sheetform flatten`: the exact unfolding of a developable
/// mesh, or cut into charts (or a net) when it cannot be flattened whole.
///
/// `drawn_seams`: `(k, 2)` vertex pairs, edges the mesh is cut open along first (as an
/// OBJ's `l` lines; chart borders when it is cut into charts).
/// `method`: `"exact"` (from the edge lengths), `"lscm"` or `"arap"` for a mesh flattened
/// whole. `charts`: `"auto"` (what a maker would expect: a developable disk whole, a
/// faceted model as a net, a curved surface in smooth charts), `"smooth"`, `"net"` or
/// `"never"`. `crease_angle` (degrees) and `max_distortion` (relative edge-length change
/// allowed in a chart) steer the cut. A net gets glue tabs on one side of every seam
/// unless `pattern` says otherwise (`tabs="none"`, or other tabs).
///
/// Returns a `Run`: `uv` is the pattern at 1:1, `face_pieces` the chart of each face,
/// `source_vertices` the input vertex each output vertex copies (a vertex on a seam has
/// one copy per chart; after `weld`, the first of the input vertices merged into it). `outcome` is `"overlapping"` when the pattern overlaps itself and
/// `"out_of_tolerance"` when an edge stretches more than `max_distortion`.
#[pyfunction]
#[pyo3(signature = (vertices, faces, *, drawn_seams=None, method="exact", charts="auto", crease_angle=None, max_distortion=None, weld=None, units="mm", size=None, name="mesh", outputs="all", progress=None, pattern=None, **renamed))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn flatten(
    py: Python<'_>,
    vertices: &Bound<'_, PyAny>,
    faces: &Bound<'_, PyAny>,
    drawn_seams: Option<&Bound<'_, PyAny>>,
    method: &str,
    charts: &str,
    crease_angle: Option<f64>,
    max_distortion: Option<f64>,
    weld: Option<f64>,
    units: &str,
    size: Option<f64>,
    name: &str,
    outputs: &str,
    progress: Option<Py<PyAny>>,
    pattern: Option<&Bound<'_, PyAny>>,
    renamed: Option<&Bound<'_, PyDict>>,
) -> PyResult<Run> {
    refuse_renamed_keywords("flatten()", renamed, &FLATTEN_RENAMED_KEYWORDS)?;
    let v = float_rows("vertices", vertices, 3)?;
    let f = index_rows("faces", faces, 3)?;
    let outputs = output_set(outputs)?;
    let pattern = pattern_argument(py, pattern)?;
    let defaults = ChartOptions::default();
    let options = FlattenOptions {
        method: match method {
            "exact" => FlattenMethod::Exact,
            "lscm" => FlattenMethod::Lscm,
            "arap" => FlattenMethod::Arap,
            other => {
                return Err(invalid_argument(
                    "method",
                    format!("`{other}`: one of \"exact\", \"lscm\", \"arap\""),
                ))
            }
        },
        charts: match charts {
            "auto" => ChartMode::Auto,
            "smooth" => ChartMode::Smooth,
            "net" => ChartMode::Net,
            "never" => ChartMode::Never,
            other => {
                return Err(invalid_argument(
                    "charts",
                    format!("`{other}`: one of \"auto\", \"smooth\", \"net\", \"never\""),
                ))
            }
        },
        chart_options: ChartOptions {
            crease_angle_degrees: crease_angle.unwrap_or(defaults.crease_angle_degrees),
            max_edge_distortion: max_distortion.unwrap_or(defaults.max_edge_distortion),
            ..defaults
        },
        net_options: Default::default(),
        net_tabs: pattern.net_tabs,
        pattern: pattern.options,
        weld,
        unit: length_unit(units)?,
        input: None,
        name: Some(name.to_string()),
        size_mm: size,
    };
    let mesh = mesh_with_seams(py, &v, &f, drawn_seams, name)?;
    let (run, seconds) = run_interruptibly(py, progress, |controls| {
        run_flatten(mesh, &options, &controls.context(".", outputs))
    })?;
    let mut parts = RunParts::of_sheet(&run.sheet, run.files, run.report, run.outcome, seconds);
    parts.source_vertices = Some(&run.source_vertices);
    Run::new(py, parts)
}

/// Develops a target shape, as `sheetform develop`: the nearest surface made of exactly
/// developable pieces, unfolded exactly, with the patterns.
///
/// `drawn_seams`: `(k, 2)` vertex pairs drawn as seams (an OBJ's `l` lines). `seams`, as
/// the CLI's `--seams`: `"automatic"` (the default, also `None`) adds seams of its own to the drawn
/// ones, up to `max_pieces` pieces each within `normal_tolerance` degrees (RMS) of a cone,
/// cylinder or plane, with a slit from every vertex inside a piece whose angle defect
/// exceeds `cone_angle` degrees; `"drawn"` cuts along the drawn seams only. `fixed`:
/// indices of vertices that keep their place (the CLI's `--fixed` names the OBJ groups
/// holding them). `max_distance`: the farthest the result may be from
/// the target, a length in `units` (`2.0`) or a percentage of the bounding-box diagonal
/// (`"0.5%"`); pieces are added until it holds. `work_faces` (default 10 000): a target of more
/// faces (a scan) is remeshed first into about this many even triangles, its boundary, seams
/// and fixed vertices kept. `mirror`: a mirror plane the result keeps, `"x"`, `"y"` or
/// `"z"` (through the middle of the mesh) or placed, `"x=0"`: the half with more area is
/// developed and joined with its mirror image. `seam_smoothing` (default 6): sweeps that
/// slide the automatic seams onto smooth curves instead of the staircase of mesh edges (0:
/// along the edges as found). `smoothness`, `tolerance` (radians) and `max_iterations`
/// steer the developability solve.
///
/// Returns a `Run` (`uv` the pattern at 1:1, `face_pieces` the piece of each face,
/// `source_vertices` the target vertex each output vertex copies, -1 for a vertex the
/// remeshing made or a mirror plane imaged); its report's
/// `develop` section has the figures. `outcome` is `"out_of_tolerance"` when a piece
/// keeps a defect above `tolerance` or the distance bound is not met (the closest
/// result is returned).
#[pyfunction]
#[pyo3(signature = (vertices, faces, *, drawn_seams=None, seams=None, max_pieces=12, normal_tolerance=2.0, cone_angle=60.0, fixed=None, max_distance=None, work_faces=None, mirror=None, seam_smoothing=6, smoothness=0.1, tolerance=1e-10, max_iterations=100, units="mm", size=None, name="mesh", outputs="all", progress=None, pattern=None, **renamed))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn develop(
    py: Python<'_>,
    vertices: &Bound<'_, PyAny>,
    faces: &Bound<'_, PyAny>,
    drawn_seams: Option<&Bound<'_, PyAny>>,
    seams: Option<&Bound<'_, PyAny>>,
    max_pieces: usize,
    normal_tolerance: f64,
    cone_angle: f64,
    fixed: Option<&Bound<'_, PyAny>>,
    max_distance: Option<&Bound<'_, PyAny>>,
    work_faces: Option<usize>,
    mirror: Option<&str>,
    seam_smoothing: usize,
    smoothness: f64,
    tolerance: f64,
    max_iterations: usize,
    units: &str,
    size: Option<f64>,
    name: &str,
    outputs: &str,
    progress: Option<Py<PyAny>>,
    pattern: Option<&Bound<'_, PyAny>>,
    renamed: Option<&Bound<'_, PyDict>>,
) -> PyResult<Run> {
    refuse_renamed_keywords("develop()", renamed, &DEVELOP_RENAMED_KEYWORDS)?;
    let v = float_rows("vertices", vertices, 3)?;
    let f = index_rows("faces", faces, 3)?;
    let outputs = output_set(outputs)?;
    let pattern = pattern_argument(py, pattern)?;
    let max_distance = max_distance.map(distance_bound).transpose()?;
    let mirror = mirror
        .map(|text| {
            text.parse()
                .map_err(|message: String| invalid_argument("mirror", message))
        })
        .transpose()?;
    let fixed_vertices = match fixed {
        None => Vec::new(),
        Some(array) => index_list("fixed", array)?
            .into_iter()
            .map(|v| u32::try_from(v).map_err(|_| invalid_argument("fixed", format!("vertex {v} is out of range"))))
            .collect::<PyResult<_>>()?,
    };
    let options = DevelopRunOptions {
        fixed_vertices,
        seams: seam_source(seams)?,
        max_distance,
        work_faces,
        mirror,
        seam_smoothing: SeamSmoothingOptions {
            iterations: seam_smoothing,
            ..Default::default()
        },
        segmentation: SegmentationOptions {
            max_pieces,
            normal_tolerance_degrees: normal_tolerance,
            cone_point_radians: cone_angle.to_radians(),
            ..Default::default()
        },
        develop: DevelopOptions {
            smoothness,
            defect_tolerance: tolerance,
            max_iterations,
            ..Default::default()
        },
        flatten: FlattenOptions {
            pattern: pattern.options,
            net_tabs: pattern.net_tabs,
            unit: length_unit(units)?,
            input: None,
            name: Some(name.to_string()),
            size_mm: size,
            ..Default::default()
        },
        ..Default::default()
    };
    let mesh = mesh_with_seams(py, &v, &f, drawn_seams, name)?;
    let (developed, seconds) = run_interruptibly(py, progress, |controls| {
        run_develop(mesh, &options, &controls.context(".", outputs))
    })?;
    let run = developed.run;
    let mut parts = RunParts::of_sheet(&run.sheet, run.files, run.report, run.outcome, seconds);
    parts.source_vertices = Some(&run.source_vertices);
    Run::new(py, parts)
}

/// `max_distance`: a length (a number) or a percentage of the size (`"0.5%"`), parsed as
/// the CLI parses `--max-distance`.
fn distance_bound(value: &Bound<'_, PyAny>) -> PyResult<DistanceBound> {
    if let Ok(length) = value.extract::<f64>() {
        return Ok(DistanceBound::Absolute(length));
    }
    let text: String = value
        .extract()
        .map_err(|_| invalid_argument("max_distance", "a length (2.0) or a percentage of the size (\"0.5%\")"))?;
    text.parse()
        .map_err(|message: String| invalid_argument("max_distance", message))
}

/// The printable pattern of a mesh that already has its flat layout (`uv`, `(n, 2)` at
/// 1:1 in `units`): `pattern.svg` (cut, mountain, valley and guide layers), and with
/// `outputs="all"` `pattern.dxf` and the tiled true-scale `pattern.pdf`, as every command
/// renders them. `face_pieces` (`(m,)`, from 0) and `piece_names` split it into pieces.
///
/// Returns a `Run` whose `files` are the pattern files and whose report has the
/// pattern's figures.
#[pyfunction]
#[pyo3(signature = (vertices, faces, uv, *, face_pieces=None, piece_names=None, units="mm", name="pattern", outputs="all", progress=None, pattern=None, **renamed))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn pattern(
    py: Python<'_>,
    vertices: &Bound<'_, PyAny>,
    faces: &Bound<'_, PyAny>,
    uv: &Bound<'_, PyAny>,
    face_pieces: Option<&Bound<'_, PyAny>>,
    piece_names: Option<Vec<String>>,
    units: &str,
    name: &str,
    outputs: &str,
    progress: Option<Py<PyAny>>,
    pattern: Option<&Bound<'_, PyAny>>,
    renamed: Option<&Bound<'_, PyDict>>,
) -> PyResult<Run> {
    refuse_renamed_keywords("pattern()", renamed, &RENAMED_KEYWORDS)?;
    let v = float_rows("vertices", vertices, 3)?;
    let f = index_rows("faces", faces, 3)?;
    let flat = float_rows("uv", uv, 2)?;
    let labels = face_pieces.map(|l| index_list("face_pieces", l)).transpose()?;
    let outputs = output_set(outputs)?;
    let unit = length_unit(units)?;
    let options = pattern_argument(py, pattern)?.options;
    let (v, f, flat) = (v.as_slice()?, f.as_slice()?, flat.as_slice()?);
    // (Read with the interpreter's lock held, as in `check`.)
    let sheet = sheet_mesh_from_arrays(v, f, flat, labels.as_deref(), piece_names.as_deref(), name, unit)
        .map_err(|e| python_error(py, e))?;
    let ((files, report, outcome), seconds) = run_interruptibly(py, progress, |controls| {
        run_pattern(&sheet, name, &options, &controls.context(".", outputs))
    })?;
    Run::new(py, RunParts::of_sheet(&sheet, files, report, outcome, seconds))
}

/// `seams`: where develop cuts, as the CLI's `--seams`: `"automatic"` (or `None`, the
/// default) or `"drawn"`.
fn seam_source(value: Option<&Bound<'_, PyAny>>) -> PyResult<SeamSource> {
    let Some(value) = value else {
        return Ok(SeamSource::Automatic);
    };
    const CHOICES: &str = "\"automatic\" (seams found, the drawn ones among them) or \"drawn\" (the drawn seams only)";
    match value.extract::<String>().as_deref() {
        Ok("automatic") => Ok(SeamSource::Automatic),
        Ok("drawn") => Ok(SeamSource::Drawn),
        Ok(other) => Err(invalid_argument("seams", format!("`{other}`: {CHOICES}"))),
        // The keyword took the drawn seam edges before it took the CLI's choice.
        Err(_) => Err(invalid_argument(
            "seams",
            format!("{CHOICES}; the drawn seam edges themselves are `drawn_seams`"),
        )),
    }
}

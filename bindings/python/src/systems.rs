//! The four systems, each a function taking a scene (a dict or a path) and returning a
//! [`Run`]: the same library pipelines the CLI runs, with the same scene parsing.

use crate::convert::{scene_argument, SceneArgument};
use crate::errors::{invalid_argument, python_error, refuse_renamed_keywords};
use crate::pattern_options::pattern_argument;
use crate::run::{output_set, run_interruptibly, Run, RunParts};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sheetform::bend::BendScene;
use sheetform::ffd::{FfdScene, SolverMethod};
use sheetform::photo::BackSide;
use sheetform::pipeline::{
    run_bend, run_ffd, run_photo, run_slit, BendRunOptions, FfdRunOptions, PhotoInput, PhotoRunOptions, SlitRunOptions,
};
use sheetform::slit::SlitScene;
use std::path::PathBuf;

fn parsed<T>(py: Python<'_>, parse: Result<T, impl Into<sheetform::pipeline::PipelineError>>) -> PyResult<T> {
    parse.map_err(|e| python_error(py, e.into()))
}

/// Bends a sheet along 3D control curves (system A, Bo & Wang 2007), as `sheetform bend`.
///
/// `scene` is a bend scene as a dict (the JSON of `sheetform schema bend`) or the path of
/// its file. Files the scene names (a texture) are read relative to `root`: by default the
/// scene file's directory, or the current directory for a dict.
///
/// `animate`: also write this many frames of the isometric deformation from flat to bent
/// (`frames/frame-0000.obj` …), as the CLI's `--animate`.
///
/// Returns a `Run` whose `uv` is the flat sheet at 1:1 and `angle_defects_rad` the
/// developability colour map (zero to rounding).
///
/// Raises `InvalidInputError` for an invalid scene (the message names the field),
/// `InadmissibleError` for a shape that cannot be made (its `.report` says where).
#[pyfunction]
#[pyo3(signature = (scene, *, root=None, outputs="all", progress=None, animate=0, pattern=None, **renamed))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn bend(
    py: Python<'_>,
    scene: &Bound<'_, PyAny>,
    root: Option<PathBuf>,
    outputs: &str,
    progress: Option<Py<PyAny>>,
    animate: usize,
    pattern: Option<&Bound<'_, PyAny>>,
    renamed: Option<&Bound<'_, PyDict>>,
) -> PyResult<Run> {
    refuse_renamed_keywords("bend()", renamed, &[("animate_frames", "animate", "")])?;
    let SceneArgument { text, root, input } = scene_argument(py, scene, root)?;
    let outputs = output_set(outputs)?;
    let options = BendRunOptions {
        pattern: pattern_argument(py, pattern)?.options,
        animate_frames: animate,
        input,
    };
    let scene = parsed(py, BendScene::from_json(&text))?;
    let (run, seconds) = run_interruptibly(py, progress, |controls| {
        run_bend(&scene, &options, &controls.context(root, outputs))
    })?;
    let mut parts = RunParts::of_sheet(&run.sheet.mesh, run.files, run.report, run.outcome, seconds);
    parts.angle_defects_rad = Some(run.angle_defects_rad);
    Run::new(py, parts)
}

/// Solves a slit sheet (system B, Tsuruta et al.), as `sheetform slit`: the strips of a
/// sheet with parallel slits bent over a chair's or a bench's curves.
///
/// `scene`: a slit scene as a dict or the path of its file; a scan it names is read
/// relative to `root` (default: the file's directory, or the current directory).
#[pyfunction]
#[pyo3(signature = (scene, *, root=None, outputs="all", progress=None, pattern=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn slit(
    py: Python<'_>,
    scene: &Bound<'_, PyAny>,
    root: Option<PathBuf>,
    outputs: &str,
    progress: Option<Py<PyAny>>,
    pattern: Option<&Bound<'_, PyAny>>,
) -> PyResult<Run> {
    let SceneArgument { text, root, input } = scene_argument(py, scene, root)?;
    let outputs = output_set(outputs)?;
    let options = SlitRunOptions {
        pattern: pattern_argument(py, pattern)?.options,
        input,
    };
    let scene = parsed(py, SlitScene::from_json(&text))?;
    let (run, seconds) = run_interruptibly(py, progress, |controls| {
        run_slit(&scene, &options, &controls.context(root, outputs))
    })?;
    Run::new(
        py,
        RunParts::of_sheet(&run.mesh, run.files, run.report, run.outcome, seconds),
    )
}

/// Deforms sheet-metal or cloth panels in a lattice and restores their developability
/// (system C, Wang & Tang 2004), as `sheetform ffd`.
///
/// `scene`: an FFD scene as a dict or the path of its file; a mesh it names is read
/// relative to `root`. `solver` overrides the scene's (`"constrained"`, `"paper"` or
/// `"none"`, as the CLI's `--solver`).
///
/// `warm_start`: an earlier `ffd` run whose scene shares its first deformations with
/// this one (an interactive drag adds one): those are taken over and only the rest is
/// restored, with the same result as a run from scratch (the report's
/// `ffd.resumed_deformations` says how many).
///
/// Returns a `Run` with the restored panels, each with its exact flat pattern (pieces =
/// panels), and `meshes["plain"]` / `meshes["restored"]`: the welded panels before and
/// after the last restoration with their angle defects. Raises `InvalidInputError` for invalid scenes and `NotConvergedError` when
/// the restoration fails.
#[pyfunction]
#[pyo3(signature = (scene, *, root=None, outputs="all", progress=None, solver=None, warm_start=None, pattern=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn ffd(
    py: Python<'_>,
    scene: &Bound<'_, PyAny>,
    root: Option<PathBuf>,
    outputs: &str,
    progress: Option<Py<PyAny>>,
    solver: Option<&str>,
    warm_start: Option<PyRef<'_, Run>>,
    pattern: Option<&Bound<'_, PyAny>>,
) -> PyResult<Run> {
    let SceneArgument { text, root, input } = scene_argument(py, scene, root)?;
    let outputs = output_set(outputs)?;
    let solver = match solver {
        None => None,
        Some("constrained") => Some(SolverMethod::Constrained),
        Some("paper") => Some(SolverMethod::Paper),
        Some("none") => Some(SolverMethod::None),
        Some(other) => {
            return Err(invalid_argument(
                "solver",
                format!("`{other}`: one of \"constrained\", \"paper\", \"none\""),
            ))
        }
    };
    let options = FfdRunOptions {
        pattern: pattern_argument(py, pattern)?.options,
        input,
        solver,
        warm_start: match &warm_start {
            None => None,
            Some(run) => Some(
                run.ffd_design
                    .clone()
                    .ok_or_else(|| invalid_argument("warm_start", "not the result of an ffd run"))?,
            ),
        },
    };
    drop(warm_start);
    let scene = parsed(py, FfdScene::from_json(&text))?;
    let (run, seconds) = run_interruptibly(py, progress, |controls| {
        run_ffd(&scene, &options, &controls.context(root, outputs))
    })?;
    let mut parts = RunParts::of_sheet(&run.sheet, run.files, run.report, run.outcome, seconds);
    parts.meshes = vec![
        ("plain", &run.plain, run.angle_defects_before_rad),
        ("restored", &run.restored, run.angle_defects_after_rad),
    ];
    parts.ffd_design = Some(std::sync::Arc::new(run.design));
    Run::new(py, parts)
}

/// Reconstructs a developable model and its pattern from an annotated photograph
/// (system D, Fondevilla et al.), as `sheetform photo`.
///
/// `annotation`: a photo annotation as a dict, or the path of its JSON file or of an SVG
/// drawing made over the photo. The photo it names is read relative to `root`.
///
/// `back_side`: `"visible"` (only what the drawing shows) or `"revolve"` (every band
/// closed round one axis, cut open along a seam at the back: the whole cup or lamp
/// shade); default: the annotation's `back_side`.
///
/// Returns a `Run` (pieces = patches); `outcome` is `"out_of_tolerance"` when the model is
/// not developable to the refinement's bound or a depth is not fixed by the drawing.
#[pyfunction]
#[pyo3(signature = (annotation, *, root=None, outputs="all", progress=None, pattern=None, back_side=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn photo(
    py: Python<'_>,
    annotation: &Bound<'_, PyAny>,
    root: Option<PathBuf>,
    outputs: &str,
    progress: Option<Py<PyAny>>,
    pattern: Option<&Bound<'_, PyAny>>,
    back_side: Option<&str>,
) -> PyResult<Run> {
    let SceneArgument { text, root, input } = scene_argument(py, annotation, root)?;
    let outputs = output_set(outputs)?;
    let back_side = match back_side {
        None => None,
        Some("visible") => Some(BackSide::Visible),
        Some("revolve") => Some(BackSide::Revolve),
        Some(other) => {
            return Err(invalid_argument(
                "back_side",
                format!("`{other}`: one of \"visible\", \"revolve\""),
            ))
        }
    };
    let pattern = pattern_argument(py, pattern)?;
    let options = PhotoRunOptions {
        pattern: pattern.options,
        input,
        back_side,
        whole_object_tabs: pattern.net_tabs,
    };
    let input = parsed(py, PhotoInput::from_text(&text))?;
    let (run, seconds) = run_interruptibly(py, progress, |controls| {
        run_photo(&input, &options, &controls.context(root, outputs))
    })?;
    Run::new(
        py,
        RunParts::of_sheet(&run.sheet, run.files, run.report, run.outcome, seconds),
    )
}

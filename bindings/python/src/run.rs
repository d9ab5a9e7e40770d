//! [`Run`], what every system and mesh function returns, and running a library pipeline
//! off the interpreter's lock so that Ctrl-C (a notebook's interrupt) cancels it.

use crate::convert::{labels, points2, points3, to_python, triangles};
use crate::errors::{internal_error, python_error};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use sheetform::mesh::SheetMesh;
use sheetform::pipeline::{write_outputs, Outcome, OutputSet, PipelineError, RenderedFiles, RunContext};
use sheetform::report::Report;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::Instant;

/// What a running pipeline is given besides its scene: the cancellation flag and the
/// progress callback that looks for Ctrl-C (and calls the user's `progress`).
pub(crate) struct Controls<'a> {
    cancel: &'a AtomicBool,
    progress: &'a (dyn Fn(&str, f64) + Sync),
}

impl<'a> Controls<'a> {
    /// The library's run context: assets under `root`, these controls, `outputs`.
    pub(crate) fn context(&self, root: impl Into<PathBuf>, outputs: OutputSet) -> RunContext<'a> {
        RunContext::new(root)
            .with_cancel(self.cancel)
            .with_progress(self.progress)
            .with_outputs(outputs)
    }
}

/// Runs `job` without the interpreter's lock (other Python threads go on). At every
/// progress report of the pipeline (each stage; each iteration of an FFD restoration) it
/// takes the lock back for a moment to look for Ctrl-C (a notebook's interrupt) and to
/// call `progress(stage, fraction)` when given: an interrupt, or an exception raised by
/// `progress`, cancels the run at its next stage and is raised once it has stopped. A
/// panic in the run is raised as a `RuntimeError`, never a crash of the interpreter.
/// Returns the job's value and the seconds it took.
///
/// The job runs on the calling thread: a thread of its own cost 0.15–0.19 ms per call
/// (measured, `docs/benchmarks-history.md`), more than the rest of the binding on a small mesh.
pub(crate) fn run_interruptibly<T: Send>(
    py: Python<'_>,
    progress: Option<Py<PyAny>>,
    job: impl FnOnce(&Controls<'_>) -> Result<T, PipelineError> + Send,
) -> PyResult<(T, f64)> {
    let cancel = AtomicBool::new(false);
    let stopped_by: Mutex<Option<PyErr>> = Mutex::new(None);
    let report = |stage: &str, fraction: f64| {
        if cancel.load(Ordering::SeqCst) {
            return;
        }
        Python::attach(|py| {
            let checked = py.check_signals().and_then(|()| match &progress {
                Some(callback) => callback.call1(py, (stage, fraction)).map(drop),
                None => Ok(()),
            });
            if let Err(error) = checked {
                *stopped_by.lock().expect("not poisoned") = Some(error);
                cancel.store(true, Ordering::SeqCst);
            }
        });
    };
    let controls = Controls {
        cancel: &cancel,
        progress: &report,
    };
    let (result, seconds) = py.detach(|| {
        let start = Instant::now();
        let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| job(&controls)));
        (result, start.elapsed().as_secs_f64())
    });
    if let Some(error) = stopped_by.into_inner().expect("not poisoned") {
        return Err(error);
    }
    match result {
        Ok(Ok(value)) => Ok((value, seconds)),
        Ok(Err(error)) => Err(python_error(py, error)),
        Err(payload) => Err(internal_error(payload)),
    }
}

/// A mesh beside a run's model, as numpy arrays (an FFD run's panels welded at their
/// seams before and after the restoration).
#[pyclass(module = "sheetform", frozen)]
pub struct Mesh {
    /// `(n, 3)` float64: vertex positions (model units).
    #[pyo3(get)]
    vertices: Py<PyArray2<f64>>,
    /// `(m, 3)` int64: triangles.
    #[pyo3(get)]
    faces: Py<PyArray2<i64>>,
    /// `(n,)` float64: the angle defect `2π − Σθ` at each vertex (radians; 0 on the
    /// boundary).
    #[pyo3(get)]
    angle_defects_rad: Py<PyArray1<f64>>,
}

#[pymethods]
impl Mesh {
    /// Pickling: rebuilt from its three arrays by `sheetform._native._restore_mesh`.
    fn __reduce__(&self, py: Python<'_>) -> PyResult<(Py<PyAny>, Py<PyAny>)> {
        let restore = py.import("sheetform._native")?.getattr("_restore_mesh")?;
        let arguments = (
            self.vertices.clone_ref(py),
            self.faces.clone_ref(py),
            self.angle_defects_rad.clone_ref(py),
        )
            .into_pyobject(py)?;
        Ok((restore.unbind(), arguments.into_any().unbind()))
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        use numpy::PyUntypedArrayMethods;
        format!(
            "<sheetform.Mesh: {} vertices, {} faces>",
            self.vertices.bind(py).shape()[0],
            self.faces.bind(py).shape()[0]
        )
    }
}

/// The result of a system (`bend`, `slit`, `ffd`, `photo`) or a mesh function
/// (`check`, `flatten`, `pattern`): the mesh with its flat pattern as numpy arrays, the
/// report as a dict, and the files the CLI would write, in memory.
///
/// Every array is made once, when the run ends (one copy of the library's data), and
/// returned as it is on every access: changing one changes it for every later access,
/// but not the rendered `files` nor what `write` writes.
#[pyclass(module = "sheetform", frozen)]
pub struct Run {
    /// `(n, 3)` float64: vertex positions (model units). Vertices on a seam between
    /// pieces have one copy per piece, with the same position.
    #[pyo3(get)]
    vertices: Py<PyArray2<f64>>,
    /// `(m, 3)` int64: triangles, indices into `vertices`.
    #[pyo3(get)]
    faces: Py<PyArray2<i64>>,
    /// `(n, 2)` float64: each vertex's position on the flat pattern at 1:1 (model units),
    /// or `None` when the run makes no pattern (`check`).
    #[pyo3(get)]
    uv: Option<Py<PyArray2<f64>>>,
    /// `(m,)` int64: the piece (index into `pieces`) of each face.
    #[pyo3(get)]
    face_pieces: Option<Py<PyArray1<i64>>>,
    /// The pieces' names, as in the OBJ groups and on the pattern.
    #[pyo3(get)]
    pieces: Vec<String>,
    /// `(n,)` float64: the angle defect `2π − Σθ` at each vertex (radians; 0 on the
    /// boundary), when the run measures it (`bend`, `check`).
    #[pyo3(get)]
    angle_defects_rad: Option<Py<PyArray1<f64>>>,
    /// `(n,)` int64: the input vertex each vertex is a copy of (`flatten`), else `None`.
    #[pyo3(get)]
    source_vertices: Option<Py<PyArray1<i64>>>,
    /// The report: the `report.json` the CLI writes, as a dict.
    #[pyo3(get)]
    report: Py<PyAny>,
    /// How the run ended: `"ok"`, `"overlapping"` (the pattern overlaps itself) or
    /// `"out_of_tolerance"` (a bound the report states is missed).
    #[pyo3(get)]
    outcome: &'static str,
    /// Meshes beside the model, by name: for `ffd`, `"plain"` (the panels after the last
    /// plain FFD) and `"restored"` (after the last restoration), welded at the seams, each
    /// with its angle defects; empty for the other functions.
    #[pyo3(get)]
    meshes: Py<PyDict>,
    /// Seconds the library's pipeline call took (`run_bend`, `run_flatten`, …): without
    /// the checks and copies of the arrays going in, the arrays and the report coming out.
    #[pyo3(get)]
    pipeline_seconds: f64,
    files: RenderedFiles,
    report_value: Report,
    files_dict: std::sync::OnceLock<Py<PyDict>>,
    /// An FFD run's design, to resume the next run from (`ffd(..., warm_start=run)`).
    pub(crate) ffd_design: Option<std::sync::Arc<sheetform::ffd::FfdDesign>>,
}

/// What a [`Run`] is made of, before the conversion.
pub(crate) struct RunParts<'a> {
    pub(crate) positions: &'a [sheetform::geometry::Vec3],
    pub(crate) triangles: &'a [[u32; 3]],
    pub(crate) flat: Option<&'a [sheetform::geometry::Vec2]>,
    pub(crate) face_pieces: Option<&'a [u32]>,
    pub(crate) pieces: Vec<String>,
    pub(crate) angle_defects_rad: Option<Vec<f64>>,
    pub(crate) source_vertices: Option<&'a [u32]>,
    pub(crate) files: RenderedFiles,
    pub(crate) report: Report,
    pub(crate) outcome: Outcome,
    pub(crate) pipeline_seconds: f64,
    pub(crate) meshes: Vec<(&'static str, &'a sheetform::mesh::TriangleMesh, Vec<f64>)>,
    pub(crate) ffd_design: Option<std::sync::Arc<sheetform::ffd::FfdDesign>>,
}

impl<'a> RunParts<'a> {
    /// The parts of a run whose model is a [`SheetMesh`].
    pub(crate) fn of_sheet(
        sheet: &'a SheetMesh,
        files: RenderedFiles,
        report: Report,
        outcome: Outcome,
        pipeline_seconds: f64,
    ) -> Self {
        Self {
            positions: &sheet.positions,
            triangles: &sheet.triangles,
            flat: Some(&sheet.flat),
            face_pieces: Some(&sheet.face_pieces),
            pieces: sheet.pieces.iter().map(|p| p.name.clone()).collect(),
            angle_defects_rad: None,
            source_vertices: None,
            files,
            report,
            outcome,
            pipeline_seconds,
            meshes: Vec::new(),
            ffd_design: None,
        }
    }
}

impl Run {
    pub(crate) fn new(py: Python<'_>, parts: RunParts<'_>) -> PyResult<Self> {
        let meshes = PyDict::new(py);
        for (name, mesh, defects) in parts.meshes {
            let mesh = Mesh {
                vertices: points3(py, &mesh.positions)?.unbind(),
                faces: triangles(py, &mesh.triangles)?.unbind(),
                angle_defects_rad: PyArray1::from_vec(py, defects).unbind(),
            };
            meshes.set_item(name, Py::new(py, mesh)?)?;
        }
        Ok(Self {
            meshes: meshes.unbind(),
            ffd_design: parts.ffd_design,
            vertices: points3(py, parts.positions)?.unbind(),
            faces: triangles(py, parts.triangles)?.unbind(),
            uv: parts.flat.map(|f| points2(py, f)).transpose()?.map(Bound::unbind),
            face_pieces: parts.face_pieces.map(|l| labels(py, l).unbind()),
            pieces: parts.pieces,
            angle_defects_rad: parts.angle_defects_rad.map(|d| PyArray1::from_vec(py, d).unbind()),
            source_vertices: parts.source_vertices.map(|l| labels(py, l).unbind()),
            report: to_python(py, &parts.report)?.unbind(),
            outcome: match parts.outcome {
                Outcome::Ok => "ok",
                Outcome::Overlapping => "overlapping",
                Outcome::OutOfTolerance => "out_of_tolerance",
            },
            pipeline_seconds: parts.pipeline_seconds,
            files: parts.files,
            report_value: parts.report,
            files_dict: std::sync::OnceLock::new(),
        })
    }
}

#[pymethods]
impl Run {
    /// The rendered files the CLI would write, `{name: bytes}` (`model.obj`, `model.glb`,
    /// `pattern.svg`, `pattern.dxf`, `pattern.pdf`, …; without `report.json`, which is
    /// `report`). Made on first access.
    #[getter]
    fn files(&self, py: Python<'_>) -> PyResult<Py<PyDict>> {
        if let Some(dict) = self.files_dict.get() {
            return Ok(dict.clone_ref(py));
        }
        let dict = PyDict::new(py);
        for (name, bytes) in &self.files {
            dict.set_item(name, PyBytes::new(py, bytes))?;
        }
        let dict = dict.unbind();
        let _ = self.files_dict.set(dict.clone_ref(py));
        Ok(dict)
    }

    /// Writes the files and `report.json` into `directory` (created if missing) as one
    /// set, exactly as the CLI does: the previous run's files there are replaced as a
    /// unit, and nothing is left half-written.
    ///
    /// Raises `OutputError` when the directory cannot be used or a write fails.
    fn write(&self, py: Python<'_>, directory: PathBuf) -> PyResult<()> {
        let (files, report) = (&self.files, &self.report_value);
        crate::errors::detached(py, || write_outputs(&directory, files, report))?.map_err(|e| python_error(py, e))
    }

    /// Pickling (for worker processes: multiprocessing, Dask): the arrays, the report, the
    /// outcome, the meshes and the rendered files, rebuilt by
    /// `sheetform._native._restore_run`. An FFD run's design (`warm_start`) stays behind:
    /// an unpickled run resumes nothing.
    fn __reduce__(&self, py: Python<'_>) -> PyResult<(Py<PyAny>, Py<PyAny>)> {
        let restore = py.import("sheetform._native")?.getattr("_restore_run")?;
        let state = PyDict::new(py);
        state.set_item("vertices", self.vertices.clone_ref(py))?;
        state.set_item("faces", self.faces.clone_ref(py))?;
        state.set_item("uv", self.uv.as_ref().map(|a| a.clone_ref(py)))?;
        state.set_item("face_pieces", self.face_pieces.as_ref().map(|a| a.clone_ref(py)))?;
        state.set_item("pieces", self.pieces.clone())?;
        state.set_item(
            "angle_defects_rad",
            self.angle_defects_rad.as_ref().map(|a| a.clone_ref(py)),
        )?;
        state.set_item(
            "source_vertices",
            self.source_vertices.as_ref().map(|a| a.clone_ref(py)),
        )?;
        state.set_item("outcome", self.outcome)?;
        state.set_item("meshes", self.meshes.clone_ref(py))?;
        state.set_item("pipeline_seconds", self.pipeline_seconds)?;
        let report = serde_json::to_string(&self.report_value)
            .map_err(|e| crate::errors::internal_error(Box::new(e.to_string())))?;
        state.set_item("report_json", report)?;
        let files = PyDict::new(py);
        for (name, bytes) in &self.files {
            files.set_item(name, PyBytes::new(py, bytes))?;
        }
        state.set_item("files", files)?;
        Ok((restore.unbind(), (state,).into_pyobject(py)?.into_any().unbind()))
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        use numpy::PyUntypedArrayMethods;
        let n = self.vertices.bind(py).shape()[0];
        let m = self.faces.bind(py).shape()[0];
        format!(
            "<sheetform.Run {}: {n} vertices, {m} faces, {} pieces>",
            self.outcome,
            self.pieces.len()
        )
    }
}

/// `"all"` (every file the CLI writes) or `"preview"` (GLB, SVG and the report only).
pub(crate) fn output_set(outputs: &str) -> PyResult<OutputSet> {
    match outputs {
        "all" => Ok(OutputSet::All),
        "preview" => Ok(OutputSet::Preview),
        other => Err(crate::errors::invalid_argument(
            "outputs",
            format!("`{other}`: one of \"all\", \"preview\""),
        )),
    }
}

/// Rebuilds a pickled [`Mesh`] (its `__reduce__`).
#[pyfunction]
pub(crate) fn _restore_mesh(
    vertices: Py<PyArray2<f64>>,
    faces: Py<PyArray2<i64>>,
    angle_defects_rad: Py<PyArray1<f64>>,
) -> Mesh {
    Mesh {
        vertices,
        faces,
        angle_defects_rad,
    }
}

/// Rebuilds a pickled [`Run`] (its `__reduce__`): the report from its JSON, so that
/// `write` writes the same `report.json`.
#[pyfunction]
pub(crate) fn _restore_run(py: Python<'_>, state: &Bound<'_, PyDict>) -> PyResult<Run> {
    let item = |key: &str| -> PyResult<Bound<'_, PyAny>> {
        state
            .get_item(key)?
            .ok_or_else(|| crate::errors::invalid_argument("state", format!("no `{key}` in a pickled Run")))
    };
    let optional =
        |key: &str| -> PyResult<Option<Bound<'_, PyAny>>> { Ok(state.get_item(key)?.filter(|v| !v.is_none())) };
    let report_json: String = item("report_json")?.extract()?;
    let report_value: Report = serde_json::from_str(&report_json)
        .map_err(|e| crate::errors::invalid_argument("state", format!("the pickled report: {e}")))?;
    let outcome: String = item("outcome")?.extract()?;
    let outcome = match outcome.as_str() {
        "ok" => "ok",
        "overlapping" => "overlapping",
        "out_of_tolerance" => "out_of_tolerance",
        other => return Err(crate::errors::invalid_argument("state", format!("outcome `{other}`"))),
    };
    let files_dict = item("files")?;
    let files_dict = files_dict.cast::<PyDict>()?;
    let mut files: RenderedFiles = Vec::with_capacity(files_dict.len());
    for (name, bytes) in files_dict.iter() {
        files.push((name.extract()?, bytes.extract()?));
    }
    Ok(Run {
        vertices: item("vertices")?.extract()?,
        faces: item("faces")?.extract()?,
        uv: optional("uv")?.map(|v| v.extract().map_err(PyErr::from)).transpose()?,
        face_pieces: optional("face_pieces")?
            .map(|v| v.extract().map_err(PyErr::from))
            .transpose()?,
        pieces: item("pieces")?.extract()?,
        angle_defects_rad: optional("angle_defects_rad")?
            .map(|v| v.extract().map_err(PyErr::from))
            .transpose()?,
        source_vertices: optional("source_vertices")?
            .map(|v| v.extract().map_err(PyErr::from))
            .transpose()?,
        report: to_python(py, &report_value)?.unbind(),
        outcome,
        meshes: item("meshes")?.cast::<PyDict>()?.clone().unbind(),
        pipeline_seconds: item("pipeline_seconds")?.extract()?,
        files,
        report_value,
        files_dict: std::sync::OnceLock::new(),
        ffd_design: None,
    })
}

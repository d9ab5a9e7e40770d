//! The bend editor as a Python class, for interactive use in a notebook: the edits of the
//! web editor (Bo & Wang 2007, §4.1) through the library's
//! [`sheetform::pipeline::edit_bend_scene`], refused (with the reason) when the shape
//! would not be admissible, the last admissible scene kept.

use crate::convert::{scene_argument, to_python, SceneArgument};
use crate::errors::{invalid_argument, python_error};
use crate::run::{output_set, run_interruptibly, Run, RunParts};
use numpy::PyArray2;
use pyo3::prelude::*;
use sheetform::bend::{BendModel, BendScene, CurveSpec};
use sheetform::pipeline::{
    edit_bend_scene_with, run_bend, BendEdit, BendEditOptions, BendRunOptions, EndHandleSpec, LengthMethod,
};
use std::path::PathBuf;

/// Most edits kept for `undo`.
const MAX_UNDO: usize = 1_000;

/// An editable bend scene: move a control point, drag keeping the curve's length, drag
/// the end handles; each edit returns what it did (a dict: `applied`,
/// `rejected_because`, `curve_length_before`, `curve_length_after`, `solver`,
/// `moved_fraction`, `stopped_because`). An edit that would make the shape inadmissible
/// is refused and the scene kept, or, with `stop_at_boundary=True`, goes as far as the
/// shape stays admissible, as the web editor's drags do.
///
/// `BendEditor(scene, root=None)`: `scene` as a dict or the path of its file. Regions and
/// control points are numbered from 0; negative numbers count from the end, as Python
/// indexes.
#[pyclass(module = "sheetform")]
pub struct BendEditor {
    scene: BendScene,
    root: PathBuf,
    history: std::collections::VecDeque<BendScene>,
}

/// `index` in `0..count`, or counted from the end when negative.
fn from_end(index: i64, count: usize) -> Option<usize> {
    let index = if index < 0 { index + count as i64 } else { index };
    (0..count as i64).contains(&index).then_some(index as usize)
}

fn point(argument: &str, p: Vec<f64>) -> PyResult<[f64; 3]> {
    match p.as_slice() {
        [x, y, z] if p.iter().all(|c| c.is_finite()) => Ok([*x, *y, *z]),
        _ => Err(invalid_argument(
            argument,
            format!("three finite numbers expected, got {p:?}"),
        )),
    }
}

fn flat_point(argument: &str, p: Vec<f64>) -> PyResult<[f64; 2]> {
    match p.as_slice() {
        [x, y] if p.iter().all(|c| c.is_finite()) => Ok([*x, *y]),
        _ => Err(invalid_argument(
            argument,
            format!("two finite numbers expected, got {p:?}"),
        )),
    }
}

impl BendEditor {
    /// A vertex of the outline (`hole` None) or of a hole, negative numbers counted from
    /// the end; `insert` allows none (an index checked by the library).
    fn loop_vertex(&self, hole: Option<i64>, index: i64) -> PyResult<(Option<usize>, usize)> {
        let (hole, vertices) = match hole {
            None => (None, &self.scene.outline),
            Some(h) => {
                let count = self.scene.holes.len();
                let h = from_end(h, count)
                    .ok_or_else(|| invalid_argument("hole", format!("no hole {h} (the sheet has {count})")))?;
                (Some(h), &self.scene.holes[h])
            }
        };
        let count = vertices.len();
        let index = from_end(index, count)
            .ok_or_else(|| invalid_argument("index", format!("no vertex {index} (the loop has {count})")))?;
        Ok((hole, index))
    }

    /// A region number, negative ones counted from the end as Python indexes.
    fn region(&self, region: i64) -> PyResult<usize> {
        let count = self.scene.regions.len();
        from_end(region, count)
            .ok_or_else(|| invalid_argument("region", format!("no region {region} (the scene has {count})")))
    }

    /// A control point of `region`'s curve, negative numbers counted from the end.
    /// `bezier_only`: the length-preserving drag edits Bézier curves only.
    fn control_point_index(&self, region: usize, index: i64, bezier_only: bool) -> PyResult<usize> {
        let count = match &self.scene.regions[region].curve {
            CurveSpec::Bezier { control_points } => control_points.len(),
            CurveSpec::Bspline { control_points, .. } if !bezier_only => control_points.len(),
            _ => {
                return Err(invalid_argument(
                    "region",
                    format!(
                        "region {region}: not a {} control curve",
                        if bezier_only { "Bézier" } else { "Bézier or B-spline" }
                    ),
                ))
            }
        };
        from_end(index, count).ok_or_else(|| {
            invalid_argument(
                "index",
                format!("no control point {index} (region {region}'s curve has {count})"),
            )
        })
    }

    fn apply(&mut self, py: Python<'_>, edit: BendEdit, stop_at_boundary: bool) -> PyResult<Py<PyAny>> {
        let scene = &self.scene;
        let options = BendEditOptions {
            stop_at_boundary,
            ..BendEditOptions::default()
        };
        let result = crate::errors::detached(py, || edit_bend_scene_with(scene, &edit, &options))?
            .map_err(|e| python_error(py, e))?;
        let info = to_python(py, &result.info)?;
        info.set_item("moved_fraction", result.moved_fraction)?;
        info.set_item("stopped_because", result.stopped_because)?;
        if result.info.applied {
            self.history.push_back(std::mem::replace(&mut self.scene, result.scene));
            if self.history.len() > MAX_UNDO {
                self.history.pop_front();
            }
        }
        Ok(info.unbind())
    }
}

#[pymethods]
impl BendEditor {
    #[new]
    #[pyo3(signature = (scene, *, root=None))]
    fn new(py: Python<'_>, scene: &Bound<'_, PyAny>, root: Option<PathBuf>) -> PyResult<Self> {
        let SceneArgument { text, root, .. } = scene_argument(py, scene, root)?;
        let scene = BendScene::from_json(&text).map_err(|e| python_error(py, e.into()))?;
        BendModel::from_scene(&scene).map_err(|e| python_error(py, e.into()))?;
        // (Made absolute now: a later change of the working directory does not change
        // which files the scene reads.)
        let root =
            std::path::absolute(&root).map_err(|e| invalid_argument("root", format!("{}: {e}", root.display())))?;
        Ok(Self {
            scene,
            root,
            history: std::collections::VecDeque::new(),
        })
    }

    /// The current scene as a dict (the JSON `sheetform bend` reads).
    #[getter]
    fn scene(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        Ok(to_python(py, &self.scene)?.unbind())
    }

    /// The control points of `region`'s curve (Bézier or B-spline), `(k, 3)`.
    fn control_points<'py>(&self, py: Python<'py>, region: i64) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let region = self.region(region)?;
        let spec = &self.scene.regions[region];
        match &spec.curve {
            CurveSpec::Bezier { control_points } | CurveSpec::Bspline { control_points, .. } => {
                let points: Vec<_> = control_points
                    .iter()
                    .map(|p| sheetform::geometry::Vec3::new(p[0], p[1], p[2]))
                    .collect();
                crate::convert::points3(py, &points)
            }
            CurveSpec::Helix { .. } => Err(invalid_argument(
                "region",
                format!("region {region}: a helix has no control points"),
            )),
        }
    }

    /// Moves one control point of `region`'s curve (Bézier or B-spline) to `position`
    /// (§4.1.1); the curve's length changes with it.
    #[pyo3(signature = (region, index, position, *, stop_at_boundary=false))]
    fn move_control_point(
        &mut self,
        py: Python<'_>,
        region: i64,
        index: i64,
        position: Vec<f64>,
        stop_at_boundary: bool,
    ) -> PyResult<Py<PyAny>> {
        let region = self.region(region)?;
        let index = self.control_point_index(region, index, false)?;
        let position = point("position", position)?;
        self.apply(
            py,
            BendEdit::MoveControlPoint {
                region,
                index,
                position,
            },
            stop_at_boundary,
        )
    }

    /// Moves one control point and restores the curve's length (§4.1.3): `method="trim"`
    /// cuts or extends the curve at its old arc length (the paper's), `"scale"` scales it
    /// about the dragged point.
    #[pyo3(signature = (region, index, position, method="trim", *, stop_at_boundary=false))]
    fn drag_preserving_length(
        &mut self,
        py: Python<'_>,
        region: i64,
        index: i64,
        position: Vec<f64>,
        method: &str,
        stop_at_boundary: bool,
    ) -> PyResult<Py<PyAny>> {
        let region = self.region(region)?;
        let index = self.control_point_index(region, index, true)?;
        let position = point("position", position)?;
        let method = match method {
            "trim" => LengthMethod::Trim,
            "scale" => LengthMethod::Scale,
            other => {
                return Err(invalid_argument(
                    "method",
                    format!("`{other}`: one of \"trim\", \"scale\""),
                ))
            }
        };
        self.apply(
            py,
            BendEdit::DragPreservingLength {
                region,
                index,
                position,
                method,
            },
            stop_at_boundary,
        )
    }

    /// Drags the end handles (§4.1.2): the curve's end points and the surface normals
    /// wanted there (each optional); the interior control points follow.
    #[pyo3(signature = (region, *, start_position=None, start_normal=None, end_position=None, end_normal=None, stop_at_boundary=false))]
    #[allow(clippy::too_many_arguments)]
    fn drag_end_handles(
        &mut self,
        py: Python<'_>,
        region: i64,
        start_position: Option<Vec<f64>>,
        start_normal: Option<Vec<f64>>,
        end_position: Option<Vec<f64>>,
        end_normal: Option<Vec<f64>>,
        stop_at_boundary: bool,
    ) -> PyResult<Py<PyAny>> {
        let region = self.region(region)?;
        let start = EndHandleSpec {
            position: start_position.map(|p| point("start_position", p)).transpose()?,
            normal: start_normal.map(|p| point("start_normal", p)).transpose()?,
        };
        let end = EndHandleSpec {
            position: end_position.map(|p| point("end_position", p)).transpose()?,
            normal: end_normal.map(|p| point("end_normal", p)).transpose()?,
        };
        self.apply(py, BendEdit::DragEndHandles { region, start, end }, stop_at_boundary)
    }

    /// Moves a vertex of the sheet's outline (or of hole `hole`) to `position` `[x, y]` on
    /// the flat sheet.
    #[pyo3(signature = (index, position, *, hole=None, stop_at_boundary=false))]
    fn move_outline_vertex(
        &mut self,
        py: Python<'_>,
        index: i64,
        position: Vec<f64>,
        hole: Option<i64>,
        stop_at_boundary: bool,
    ) -> PyResult<Py<PyAny>> {
        let (hole, index) = self.loop_vertex(hole, index)?;
        let position = flat_point("position", position)?;
        self.apply(
            py,
            BendEdit::MoveOutlineVertex { hole, index, position },
            stop_at_boundary,
        )
    }

    /// Inserts a vertex at `position` after vertex `after` of the outline (or of hole
    /// `hole`).
    #[pyo3(signature = (after, position, *, hole=None))]
    fn insert_outline_vertex(
        &mut self,
        py: Python<'_>,
        after: i64,
        position: Vec<f64>,
        hole: Option<i64>,
    ) -> PyResult<Py<PyAny>> {
        let (hole, after) = self.loop_vertex(hole, after)?;
        let position = flat_point("position", position)?;
        self.apply(py, BendEdit::InsertOutlineVertex { hole, after, position }, false)
    }

    /// Deletes a vertex of the outline (or of hole `hole`); three must remain.
    #[pyo3(signature = (index, *, hole=None))]
    fn delete_outline_vertex(&mut self, py: Python<'_>, index: i64, hole: Option<i64>) -> PyResult<Py<PyAny>> {
        let (hole, index) = self.loop_vertex(hole, index)?;
        self.apply(py, BendEdit::DeleteOutlineVertex { hole, index }, false)
    }

    /// Moves `region`'s flat segment: its `start` `[x, y]`, its `direction`, or both.
    #[pyo3(signature = (region, *, start=None, direction=None, stop_at_boundary=false))]
    fn move_flat_segment(
        &mut self,
        py: Python<'_>,
        region: i64,
        start: Option<Vec<f64>>,
        direction: Option<Vec<f64>>,
        stop_at_boundary: bool,
    ) -> PyResult<Py<PyAny>> {
        let region = self.region(region)?;
        let start = start.map(|p| flat_point("start", p)).transpose()?;
        let direction = direction.map(|p| flat_point("direction", p)).transpose()?;
        self.apply(
            py,
            BendEdit::MoveFlatSegment {
                region,
                start,
                direction,
            },
            stop_at_boundary,
        )
    }

    /// Changes `region`'s helix: `radius`, `rise_per_radian` (the pitch over 2π),
    /// `start_angle`, `end_angle` (radians); each one left out is kept.
    #[pyo3(signature = (region, *, radius=None, rise_per_radian=None, start_angle=None, end_angle=None, stop_at_boundary=false))]
    #[allow(clippy::too_many_arguments)]
    fn set_helix(
        &mut self,
        py: Python<'_>,
        region: i64,
        radius: Option<f64>,
        rise_per_radian: Option<f64>,
        start_angle: Option<f64>,
        end_angle: Option<f64>,
        stop_at_boundary: bool,
    ) -> PyResult<Py<PyAny>> {
        let region = self.region(region)?;
        self.apply(
            py,
            BendEdit::SetHelix {
                region,
                radius,
                rise_per_radian,
                start_angle,
                end_angle,
            },
            stop_at_boundary,
        )
    }

    /// Changes the radius of `region`'s flat arc (a non-geodesic control curve).
    #[pyo3(signature = (region, radius, *, stop_at_boundary=false))]
    fn set_flat_arc(
        &mut self,
        py: Python<'_>,
        region: i64,
        radius: f64,
        stop_at_boundary: bool,
    ) -> PyResult<Py<PyAny>> {
        let region = self.region(region)?;
        self.apply(py, BendEdit::SetFlatArc { region, radius }, stop_at_boundary)
    }

    /// Takes the last applied edit back; `False` when there is none.
    fn undo(&mut self) -> bool {
        match self.history.pop_back() {
            Some(scene) => {
                self.scene = scene;
                true
            }
            None => false,
        }
    }

    /// Bends the current scene, as `sheetform.bend` (by default only the preview files:
    /// GLB, SVG and the report).
    #[pyo3(signature = (*, outputs="preview"))]
    fn bend(&self, py: Python<'_>, outputs: &str) -> PyResult<Run> {
        let outputs = output_set(outputs)?;
        let (scene, root) = (&self.scene, self.root.clone());
        let (run, seconds) = run_interruptibly(py, None, |controls| {
            run_bend(scene, &BendRunOptions::default(), &controls.context(root, outputs))
        })?;
        let mut parts = RunParts::of_sheet(&run.sheet.mesh, run.files, run.report, run.outcome, seconds);
        parts.angle_defects_rad = Some(run.angle_defects_rad);
        Run::new(py, parts)
    }
}

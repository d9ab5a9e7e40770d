//! Editing a bend scene's control curve (Bo & Wang 2007, §4.1) for every front end: the
//! web editor's drags and the bindings' editor class send a [`BendEdit`]; the library's
//! [`BendEditor`] applies it (or refuses it, keeping the last admissible state) and the
//! result comes back as a new scene, the same file the CLI reads.

use super::error::PipelineError;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use sheetform_bend::{
    BendEditor, BendError, BendModel, BendScene, CurveSpec, EditInfo, EndHandle, EndHandleOptions, LengthPreservation,
};
use sheetform_geometry::Vec3;

/// How a length-preserving drag restores the curve's length (§4.1.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum LengthMethod {
    /// Cut or extend the Bézier curve exactly at its original arc length, then translate
    /// it so the dragged point stays where it was dropped (the paper's method).
    #[default]
    Trim,
    /// Scale the curve about the dragged point by the ratio of the lengths.
    Scale,
}

/// An end handle: where the curve's end goes and the surface normal wanted there.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct EndHandleSpec {
    /// New position of the end point (absent: kept).
    #[serde(default)]
    pub position: Option<[f64; 3]>,
    /// Surface normal wanted at the end (absent: free).
    #[serde(default)]
    pub normal: Option<[f64; 3]>,
}

/// One edit of a region's Bézier control curve (§4.1).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum BendEdit {
    /// Move one control point (§4.1.1); the curve's length changes with it.
    MoveControlPoint {
        /// Region index.
        region: usize,
        /// Control point index.
        index: usize,
        /// New position.
        position: [f64; 3],
    },
    /// Move one control point and restore the curve's length (§4.1.3).
    DragPreservingLength {
        /// Region index.
        region: usize,
        /// Control point index.
        index: usize,
        /// Where the point is dropped.
        position: [f64; 3],
        /// How the length is restored.
        #[serde(default)]
        method: LengthMethod,
    },
    /// Drag the end handles (§4.1.2): end positions and the surface normals there; the
    /// interior control points follow by a regularised least-squares solve.
    DragEndHandles {
        /// Region index.
        region: usize,
        /// The start handle.
        #[serde(default)]
        start: EndHandleSpec,
        /// The end handle.
        #[serde(default)]
        end: EndHandleSpec,
    },
}

/// What an edit gave.
#[derive(Debug, Clone)]
pub struct BendEditResult {
    /// The scene after the edit (the input scene when the edit was refused).
    pub scene: BendScene,
    /// What the edit did: applied, or why not (the shape would not be admissible).
    pub info: EditInfo,
}

/// Applies `edit` to `scene` through [`BendEditor`]: the region's control points in the
/// returned scene are the edited curve's. An edit that would make the shape
/// inadmissible is not an error: `info.applied` is false and the scene is unchanged.
///
/// # Errors
/// [`PipelineError::Bend`] for an invalid or inadmissible starting scene, a region or
/// point that does not exist, a curve that is not Bézier, bad handles.
pub fn edit_bend_scene(scene: &BendScene, edit: &BendEdit) -> Result<BendEditResult, PipelineError> {
    let region = match edit {
        BendEdit::MoveControlPoint { region, .. }
        | BendEdit::DragPreservingLength { region, .. }
        | BendEdit::DragEndHandles { region, .. } => *region,
    };
    let edit_error = |message: String| PipelineError::Bend(BendError::Edit { message });
    let Some(spec) = scene.regions.get(region) else {
        return Err(edit_error(format!(
            "no region {region} (the scene has {})",
            scene.regions.len()
        )));
    };
    if !matches!(spec.curve, CurveSpec::Bezier { .. }) {
        return Err(edit_error(format!(
            "region {region}: the editor edits Bézier control curves"
        )));
    }
    let vector = |p: [f64; 3]| Vec3::new(p[0], p[1], p[2]);
    let handle = |h: &EndHandleSpec| EndHandle {
        position: h.position.map(vector),
        normal: h.normal.map(vector),
    };
    let mut editor = BendEditor::new(BendModel::from_scene(scene)?)?;
    let info = match edit {
        BendEdit::MoveControlPoint { index, position, .. } => {
            editor.move_control_point(region, *index, vector(*position))?
        }
        BendEdit::DragPreservingLength {
            index,
            position,
            method,
            ..
        } => {
            let method = match method {
                LengthMethod::Trim => LengthPreservation::Trim,
                LengthMethod::Scale => LengthPreservation::Scale,
            };
            editor.drag_preserving_length(region, *index, vector(*position), method)?
        }
        BendEdit::DragEndHandles { start, end, .. } => {
            editor.drag_end_handles(region, handle(start), handle(end), &EndHandleOptions::default())?
        }
    };
    let mut edited = scene.clone();
    if info.applied {
        let points = editor.model().regions[region]
            .curve
            .shape()
            .control_points()
            .iter()
            .map(|p| [p.x, p.y, p.z])
            .collect();
        edited.regions[region].curve = CurveSpec::Bezier { control_points: points };
    }
    Ok(BendEditResult { scene: edited, info })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipeline::{run_bend, BendRunOptions, OutputSet, RunContext};

    fn rectangle() -> BendScene {
        BendScene::from_json(include_str!("../../../../examples/bent-rectangle.json")).unwrap()
    }

    /// A length-preserving drag keeps the curve's length exactly, and the scene it returns
    /// bends (through the same pipeline as the CLI) to that length.
    #[test]
    fn a_length_preserving_drag_returns_a_scene_of_the_same_length() {
        let scene = rectangle();
        let before = run_bend(
            &scene,
            &BendRunOptions::default(),
            &RunContext::new(".").with_outputs(OutputSet::Preview),
        )
        .unwrap();
        let edit = BendEdit::DragPreservingLength {
            region: 0,
            index: 2,
            position: [150.0, 20.0, 70.0],
            method: LengthMethod::Trim,
        };
        let result = edit_bend_scene(&scene, &edit).unwrap();
        assert!(result.info.applied, "{:?}", result.info.rejected_because);
        assert!((result.info.curve_length_after - result.info.curve_length_before).abs() < 1e-9);
        let CurveSpec::Bezier { control_points } = &result.scene.regions[0].curve else {
            panic!("a Bézier curve")
        };
        assert_eq!(control_points[2], [150.0, 20.0, 70.0]);
        let after = run_bend(
            &result.scene,
            &BendRunOptions::default(),
            &RunContext::new(".").with_outputs(OutputSet::Preview),
        )
        .unwrap();
        let length = |r: &crate::report::Report| r.regions[0].curve_length_mm;
        assert!((length(&after.report) - length(&before.report)).abs() < 1e-6);
    }

    /// An edit that would make the shape inadmissible is refused, the scene unchanged.
    #[test]
    fn an_inadmissible_edit_is_refused_and_the_scene_kept() {
        let scene = rectangle();
        let torsion = edit_bend_scene(
            &BendScene::from_json(
                r#"{"outline": [[0, -60], [240, -60], [240, 60], [0, 60]], "regions": [{"flat_start": [0, 0],
                "flat_direction": [1, 0], "curve": {"type": "bezier",
                "control_points": [[0, 0, 0], [80, 10, 0], [150, -10, 60], [170, 10, 120]]}}]}"#,
            )
            .unwrap(),
            &BendEdit::MoveControlPoint {
                region: 0,
                index: 2,
                position: [150.0, -20.0, 60.0],
            },
        )
        .unwrap();
        assert!(!torsion.info.applied);
        assert!(torsion
            .info
            .rejected_because
            .as_deref()
            .unwrap_or("")
            .contains("regression"));
        let CurveSpec::Bezier { control_points } = &torsion.scene.regions[0].curve else {
            panic!()
        };
        assert_eq!(control_points[2], [150.0, -10.0, 60.0], "the scene was kept");
        // A small move of the same point is admissible.
        let small = BendEdit::MoveControlPoint {
            region: 0,
            index: 2,
            position: [142.0, 9.0, 62.0],
        };
        assert!(edit_bend_scene(&scene, &small).unwrap().info.applied);
    }

    /// End handles: the wanted normals are reached at both ends.
    #[test]
    fn end_handles_turn_the_end_normals() {
        let scene = rectangle();
        let edit = BendEdit::DragEndHandles {
            region: 0,
            start: EndHandleSpec {
                position: None,
                normal: Some([0.0, 0.2, 1.0]),
            },
            end: EndHandleSpec::default(),
        };
        let result = edit_bend_scene(&scene, &edit).unwrap();
        assert!(result.info.applied, "{:?}", result.info.rejected_because);
        let CurveSpec::Bezier { control_points: p } = &result.scene.regions[0].curve else {
            panic!()
        };
        let v = |a: [f64; 3]| Vec3::new(a[0], a[1], a[2]);
        let (p0, p1, p2) = (v(p[0]), v(p[1]), v(p[2]));
        let d = p1 - p0;
        let normal = d.cross(&(p2 - 2.0 * p1 + p0)).cross(&d).normalize();
        let wanted = Vec3::new(0.0, 0.2, 1.0).normalize();
        assert!(normal.dot(&wanted) > 0.99, "start normal {normal:?}");
    }

    /// Issue 35: a drag (or a trim) to a coordinate ≥ 1e200 panicked in the edit (the
    /// server answered 500 quoting the panic; the Python editor shares the code). Every
    /// edit to such a place is refused naming it, the scene unchanged.
    #[test]
    fn edits_to_absurd_places_are_refused_not_panics() {
        let scene = rectangle();
        for method in [LengthMethod::Trim, LengthMethod::Scale] {
            for position in [
                [1e200, 0.0, 0.0],
                [1e300, 1e300, 1e300],
                [150.0, 1e250, 70.0],
                [2e9, 0.0, 0.0],
            ] {
                let edit = BendEdit::DragPreservingLength {
                    region: 0,
                    index: 2,
                    position,
                    method,
                };
                let e = edit_bend_scene(&scene, &edit).unwrap_err().to_string();
                assert!(e.contains("within 1e9"), "{position:?}: {e}");
            }
        }
        let e = edit_bend_scene(
            &scene,
            &BendEdit::MoveControlPoint {
                region: 0,
                index: 1,
                position: [0.0, -1e200, 0.0],
            },
        )
        .unwrap_err();
        assert!(e.to_string().contains("within 1e9"), "{e}");
    }
}

//! Editing a bend scene's control curve (Bo & Wang 2007, §4.1) for every front end: the
//! web editor's drags and the bindings' editor class send a [`BendEdit`]; the library's
//! [`BendEditor`] applies it (or refuses it, keeping the last admissible state) and the
//! result comes back as a new scene, the same file the CLI reads.

use super::error::PipelineError;
use nalgebra::SVector;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use sheetform_bend::{
    bend, check_control_point_index, check_edit_coordinates, check_edit_number, BendEditor, BendError, BendModel,
    BendScene, CurveSpec, EditInfo, EndHandle, EndHandleOptions, FlatCurveSpec, LengthPreservation,
};
use sheetform_geometry::{Vec2, Vec3};

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
    /// Move a vertex of the sheet's outline (or of a hole) on the flat sheet.
    MoveOutlineVertex {
        /// The hole whose vertex moves (absent: the outline).
        #[serde(default)]
        hole: Option<usize>,
        /// Vertex index.
        index: usize,
        /// New position `[x, y]` on the flat sheet.
        position: [f64; 2],
    },
    /// Insert a vertex into the outline (or a hole) after vertex `after`.
    InsertOutlineVertex {
        /// The hole (absent: the outline).
        #[serde(default)]
        hole: Option<usize>,
        /// The new vertex follows this one.
        after: usize,
        /// Its position `[x, y]` on the flat sheet.
        position: [f64; 2],
    },
    /// Delete a vertex of the outline (or of a hole); three must remain.
    DeleteOutlineVertex {
        /// The hole (absent: the outline).
        #[serde(default)]
        hole: Option<usize>,
        /// Vertex index.
        index: usize,
    },
    /// Move a region's flat geodesic segment on the sheet: its start, its direction, or
    /// both (its length stays the curve's). `flat_end` gives way to `flat_direction`.
    MoveFlatSegment {
        /// Region index.
        region: usize,
        /// New start `[x, y]` (absent: kept).
        #[serde(default)]
        start: Option<[f64; 2]>,
        /// New direction `[x, y]`, any length but zero (absent: kept).
        #[serde(default)]
        direction: Option<[f64; 2]>,
    },
    /// Change a helix (or circle) control curve's parameters; each one absent is kept.
    SetHelix {
        /// Region index.
        region: usize,
        /// Radius (model units, positive).
        #[serde(default)]
        radius: Option<f64>,
        /// Rise along the axis per radian (the pitch is `2π` times it; 0: a circle).
        #[serde(default)]
        rise_per_radian: Option<f64>,
        /// Start angle (radians).
        #[serde(default)]
        start_angle: Option<f64>,
        /// End angle (radians).
        #[serde(default)]
        end_angle: Option<f64>,
    },
    /// Change the radius of a region's flat arc (a non-geodesic control curve, §5).
    SetFlatArc {
        /// Region index.
        region: usize,
        /// The arc's radius on the flat sheet (model units, positive).
        radius: f64,
    },
}

impl BendEdit {
    /// The region whose curve the edit changes or follows (none for the outline's edits,
    /// whose [`EditInfo`] curve lengths are 0).
    pub fn region(&self) -> Option<usize> {
        match self {
            BendEdit::MoveControlPoint { region, .. }
            | BendEdit::DragPreservingLength { region, .. }
            | BendEdit::DragEndHandles { region, .. }
            | BendEdit::MoveFlatSegment { region, .. }
            | BendEdit::SetHelix { region, .. }
            | BendEdit::SetFlatArc { region, .. } => Some(*region),
            BendEdit::MoveOutlineVertex { .. }
            | BendEdit::InsertOutlineVertex { .. }
            | BendEdit::DeleteOutlineVertex { .. } => None,
        }
    }

    /// The edit can be made part of the way (a move, a turn, a change of number); an
    /// insertion or a deletion cannot, and is made whole or refused.
    pub fn is_continuous(&self) -> bool {
        !matches!(
            self,
            BendEdit::InsertOutlineVertex { .. } | BendEdit::DeleteOutlineVertex { .. }
        )
    }
}

/// What an edit gave.
#[derive(Debug, Clone)]
pub struct BendEditResult {
    /// The scene after the edit (the input scene when the edit was refused).
    pub scene: BendScene,
    /// What the edit did: applied, or why not (the shape would not be admissible).
    pub info: EditInfo,
    /// How much of the asked move was made: 1 for the whole edit, less when it stopped at
    /// the boundary of the admissible shapes ([`BendEditOptions::stop_at_boundary`]), 0
    /// when it was refused.
    pub moved_fraction: f64,
    /// Why the edit stopped short of what was asked (the refusal of the whole move), when
    /// it did.
    pub stopped_because: Option<String>,
    /// The edited scene's model and bent sheet, when checking the edit bent it as
    /// [`super::run_bend`] does (the scene's own edits): [`super::run_bend_bent`] exports
    /// them without bending again. `None` for a refused edit and the editor's drags.
    pub bent: Option<Box<super::BentScene>>,
}

/// How an edit meets the boundary of the admissible shapes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BendEditOptions {
    /// An edit that would make the shape inadmissible stops at the boundary instead of
    /// being refused: the moved points (and turned normals) go the largest fraction of
    /// the way that stays admissible, found by bisection. Off by default: the edit is
    /// then refused whole.
    pub stop_at_boundary: bool,
    /// Bisection steps: the stop is within `2^-steps` of the asked move from the
    /// boundary (one bend per step). At most [`MAX_BOUNDARY_STEPS`].
    pub boundary_steps: u32,
}

impl Default for BendEditOptions {
    fn default() -> Self {
        Self {
            stop_at_boundary: false,
            boundary_steps: 8,
        }
    }
}

/// The most bisection steps an edit may take to find the boundary (each one bends the
/// sheet; 30 steps place the stop within 1e-9 of the move).
pub const MAX_BOUNDARY_STEPS: u32 = 30;

/// Applies `edit` to `scene`, refused whole when the shape would not be admissible
/// ([`edit_bend_scene_with`] with the default options).
///
/// # Errors
/// As [`edit_bend_scene_with`].
pub fn edit_bend_scene(scene: &BendScene, edit: &BendEdit) -> Result<BendEditResult, PipelineError> {
    edit_bend_scene_with(scene, edit, &BendEditOptions::default())
}

/// Applies `edit` to `scene` through [`BendEditor`]: the region's control points in the
/// returned scene are the edited curve's. An edit that would make the shape
/// inadmissible is not an error: `info.applied` is false and the scene is unchanged, or,
/// with [`BendEditOptions::stop_at_boundary`], the edit goes as far as the shape stays
/// admissible (`moved_fraction` says how far).
///
/// A stopped edit is the asked one scaled along its way: the moved point (or end) at
/// `p0 + t (p1 − p0)`, an end normal turned to `normalize((1 − t) n0 + t n1)`, with `t`
/// the largest admissible fraction found by bisection from the admissible start (`t =
/// 0`). The admissible set need not be convex along the way: the stop is a boundary
/// point, the first one bisection meets.
///
/// Moving a control point works on Bézier and B-spline curves (a periodic B-spline's
/// wrapped copies follow); the length-preserving drag and the end handles need a Bézier
/// curve.
///
/// # Errors
/// [`PipelineError::Bend`] for an invalid or inadmissible starting scene, a region or
/// point that does not exist, a curve without control points, bad handles, more than
/// [`MAX_BOUNDARY_STEPS`] steps.
pub fn edit_bend_scene_with(
    scene: &BendScene,
    edit: &BendEdit,
    options: &BendEditOptions,
) -> Result<BendEditResult, PipelineError> {
    if options.boundary_steps > MAX_BOUNDARY_STEPS {
        return Err(edit_error(format!(
            "boundary_steps is {}, at most {MAX_BOUNDARY_STEPS}",
            options.boundary_steps
        )));
    }
    let mut editor = None;
    let whole = apply_edit(scene, edit, &mut editor)?;
    if whole.info.applied || !options.stop_at_boundary || !edit.is_continuous() {
        return Ok(whole);
    }
    // The start must be admissible for the bisection to mean anything.
    if editor.is_none() {
        BendEditor::new(BendModel::from_scene(scene)?)?;
    }
    let mut best: Option<BendEditResult> = None;
    let (mut low, mut high) = (0.0_f64, 1.0_f64);
    for _ in 0..options.boundary_steps {
        let t = 0.5 * (low + high);
        let attempt = apply_edit(scene, &edit_part(scene, edit, t)?, &mut editor)?;
        if attempt.info.applied {
            low = t;
            best = Some(attempt);
        } else {
            high = t;
        }
    }
    let stopped_because = whole.info.rejected_because.clone();
    Ok(match best {
        Some(result) => BendEditResult {
            moved_fraction: low,
            stopped_because,
            ..result
        },
        None => BendEditResult {
            stopped_because,
            ..whole
        },
    })
}

fn edit_error(message: String) -> PipelineError {
    PipelineError::Bend(BendError::Edit { message })
}

/// The control points of `region`'s curve in the scene (Bézier or B-spline; a periodic
/// B-spline's without its wrapped copies).
fn scene_control_points(scene: &BendScene, region: usize) -> Result<&Vec<[f64; 3]>, PipelineError> {
    let Some(spec) = scene.regions.get(region) else {
        return Err(edit_error(format!(
            "no region {region} (the scene has {})",
            scene.regions.len()
        )));
    };
    match &spec.curve {
        CurveSpec::Bezier { control_points } | CurveSpec::Bspline { control_points, .. } => Ok(control_points),
        CurveSpec::Helix { .. } => Err(edit_error(format!(
            "region {region}'s curve is a helix: it has no control points (change its radius, rise or angles)"
        ))),
    }
}

fn vector(p: [f64; 3]) -> Vec3 {
    Vec3::new(p[0], p[1], p[2])
}

/// The principal normal of a Bézier curve at its start (`at_end` false) or end, up to a
/// positive factor: `d × (P2 − 2P1 + P0) × d` with `d = P1 − P0` (§4.1.2).
fn end_normal(points: &[[f64; 3]], at_end: bool) -> Vec3 {
    let n = points.len() - 1;
    let (p0, p1, p2) = if at_end {
        (vector(points[n]), vector(points[n - 1]), vector(points[n - 2]))
    } else {
        (vector(points[0]), vector(points[1]), vector(points[2]))
    };
    let d = p1 - p0;
    d.cross(&(p2 - 2.0 * p1 + p0)).cross(&d)
}

/// The fraction `t` of the turn from the direction `now` to `wanted`: normalised linear
/// interpolation, each first scaled by its largest component (a tiny vector has a norm).
/// A zero `now` or `wanted` gives `wanted` (the edit refuses a zero one); opposite
/// directions give `wanted` where the interpolation passes through zero.
fn turned_part<const D: usize>(now: SVector<f64, D>, wanted: SVector<f64, D>, t: f64) -> SVector<f64, D> {
    if now.amax() == 0.0 || wanted.amax() == 0.0 {
        return wanted;
    }
    let unit = |v: SVector<f64, D>| {
        let v = v / v.amax();
        v / v.norm()
    };
    let (now, wanted) = (unit(now), unit(wanted));
    let turned = now * (1.0 - t) + wanted * t;
    if turned.norm() < 1e-9 {
        wanted
    } else {
        turned
    }
}

/// `edit` made the fraction `t` of the way from `scene`'s state.
fn edit_part(scene: &BendScene, edit: &BendEdit, t: f64) -> Result<BendEdit, PipelineError> {
    let lerp = |from: [f64; 3], to: [f64; 3]| std::array::from_fn(|a| from[a] + t * (to[a] - from[a]));
    let lerp2 = |from: [f64; 2], to: [f64; 2]| std::array::from_fn(|a| from[a] + t * (to[a] - from[a]));
    let number = |from: f64, to: Option<f64>| to.map(|to| from + t * (to - from));
    match edit {
        BendEdit::MoveOutlineVertex { hole, index, position } => {
            let vertex = outline_loop(scene, *hole)?
                .get(*index)
                .copied()
                .ok_or_else(|| edit_error(no_vertex(*hole, *index, outline_loop(scene, *hole).map_or(0, Vec::len))))?;
            return Ok(BendEdit::MoveOutlineVertex {
                hole: *hole,
                index: *index,
                position: lerp2(vertex, *position),
            });
        }
        BendEdit::InsertOutlineVertex { .. } | BendEdit::DeleteOutlineVertex { .. } => return Ok(edit.clone()),
        BendEdit::MoveFlatSegment {
            region,
            start,
            direction,
        } => {
            let (here, heading) = flat_segment(scene, *region)?;
            let direction = direction.map(|wanted| turned_part(Vec2::from(heading), Vec2::from(wanted), t).into());
            return Ok(BendEdit::MoveFlatSegment {
                region: *region,
                start: start.map(|p| lerp2(here, p)),
                direction,
            });
        }
        BendEdit::SetHelix {
            region,
            radius,
            rise_per_radian,
            start_angle,
            end_angle,
        } => {
            let Some(CurveSpec::Helix {
                radius: r,
                rise_per_radian: c,
                start_angle: a,
                end_angle: b,
                ..
            }) = scene.regions.get(*region).map(|spec| &spec.curve)
            else {
                return Err(edit_error(format!("region {region} has no helix")));
            };
            return Ok(BendEdit::SetHelix {
                region: *region,
                radius: number(*r, *radius),
                rise_per_radian: number(*c, *rise_per_radian),
                start_angle: number(*a, *start_angle),
                end_angle: number(*b, *end_angle),
            });
        }
        BendEdit::SetFlatArc { region, radius } => {
            let Some(Some(FlatCurveSpec::Arc { radius: r, .. })) =
                scene.regions.get(*region).map(|spec| spec.flat_curve.as_ref())
            else {
                return Err(edit_error(format!("region {region} has no flat arc")));
            };
            return Ok(BendEdit::SetFlatArc {
                region: *region,
                radius: r + t * (radius - r),
            });
        }
        _ => {}
    }
    let points = scene_control_points(scene, edit.region().unwrap_or(0))?;
    let at = |index: usize| {
        points.get(index).copied().ok_or_else(|| {
            edit_error(format!(
                "control point {index} does not exist (the curve has {})",
                points.len()
            ))
        })
    };
    Ok(match edit {
        BendEdit::MoveControlPoint {
            region,
            index,
            position,
        } => BendEdit::MoveControlPoint {
            region: *region,
            index: *index,
            position: lerp(at(*index)?, *position),
        },
        BendEdit::DragPreservingLength {
            region,
            index,
            position,
            method,
        } => BendEdit::DragPreservingLength {
            region: *region,
            index: *index,
            position: lerp(at(*index)?, *position),
            method: *method,
        },
        BendEdit::DragEndHandles { region, start, end } => {
            if points.len() < 3 {
                return Err(edit_error(format!(
                    "end handles need degree ≥ 3, the curve has degree {}",
                    points.len() - 1
                )));
            }
            let part = |handle: &EndHandleSpec, at_end: bool| {
                let here = points[if at_end { points.len() - 1 } else { 0 }];
                let normal = handle
                    .normal
                    .map(|wanted| turned_part(end_normal(points, at_end), vector(wanted), t).into());
                EndHandleSpec {
                    position: handle.position.map(|p| lerp(here, p)),
                    normal,
                }
            };
            BendEdit::DragEndHandles {
                region: *region,
                start: part(start, false),
                end: part(end, true),
            }
        }
        _ => unreachable!("the scene's own edits are made part of the way above"),
    })
}

/// The outline (`hole` absent) or a hole of the scene.
fn outline_loop(scene: &BendScene, hole: Option<usize>) -> Result<&Vec<[f64; 2]>, PipelineError> {
    match hole {
        None => Ok(&scene.outline),
        Some(h) => scene
            .holes
            .get(h)
            .ok_or_else(|| edit_error(format!("no hole {h} (the sheet has {})", scene.holes.len()))),
    }
}

fn no_vertex(hole: Option<usize>, index: usize, count: usize) -> String {
    match hole {
        None => format!("the outline has no vertex {index} (it has {count})"),
        Some(h) => format!("hole {h} has no vertex {index} (it has {count})"),
    }
}

/// A region's flat segment: its start and direction on the sheet.
fn flat_segment(scene: &BendScene, region: usize) -> Result<([f64; 2], [f64; 2]), PipelineError> {
    let spec = scene
        .regions
        .get(region)
        .ok_or_else(|| edit_error(format!("no region {region} (the scene has {})", scene.regions.len())))?;
    let Some(start) = spec.flat_start else {
        return Err(edit_error(format!(
            "region {region} has no flat segment to move (its flat curve sets where it lies)"
        )));
    };
    let direction = match (spec.flat_direction, spec.flat_end) {
        (Some(d), _) => d,
        (None, Some(end)) => [end[0] - start[0], end[1] - start[1]],
        (None, None) => [1.0, 0.0],
    };
    Ok((start, direction))
}

/// The scene with one of its own edits made (the outline's, a flat segment's, a helix's):
/// not yet checked for admissibility.
fn edited_scene(scene: &BendScene, edit: &BendEdit) -> Result<BendScene, PipelineError> {
    let mut edited = scene.clone();
    match edit {
        BendEdit::MoveOutlineVertex { hole, index, position } => {
            check_edit_coordinates(position)?;
            let vertices = loop_mut(&mut edited, scene, *hole)?;
            let count = vertices.len();
            *vertices
                .get_mut(*index)
                .ok_or_else(|| edit_error(no_vertex(*hole, *index, count)))? = *position;
        }
        BendEdit::InsertOutlineVertex { hole, after, position } => {
            check_edit_coordinates(position)?;
            let vertices = loop_mut(&mut edited, scene, *hole)?;
            if *after >= vertices.len() {
                return Err(edit_error(no_vertex(*hole, *after, vertices.len())));
            }
            if vertices.len() >= MAX_OUTLINE_VERTICES {
                return Err(edit_error(format!(
                    "a loop of the sheet has at most {MAX_OUTLINE_VERTICES} vertices"
                )));
            }
            vertices.insert(after + 1, *position);
        }
        BendEdit::DeleteOutlineVertex { hole, index } => {
            let vertices = loop_mut(&mut edited, scene, *hole)?;
            if *index >= vertices.len() {
                return Err(edit_error(no_vertex(*hole, *index, vertices.len())));
            }
            if vertices.len() <= 3 {
                return Err(edit_error(
                    "a loop of the sheet keeps at least 3 vertices (delete the hole instead)".into(),
                ));
            }
            vertices.remove(*index);
        }
        BendEdit::MoveFlatSegment {
            region,
            start,
            direction,
        } => {
            let (here, heading) = flat_segment(scene, *region)?;
            let start = start.unwrap_or(here);
            check_edit_coordinates(&start)?;
            let direction = direction.unwrap_or(heading);
            check_edit_coordinates(&direction)?;
            if direction == [0.0, 0.0] {
                return Err(edit_error(format!(
                    "region {region}: a flat direction cannot be the zero vector"
                )));
            }
            let spec = &mut edited.regions[*region];
            spec.flat_start = Some(start);
            spec.flat_direction = Some(direction);
            spec.flat_end = None;
        }
        BendEdit::SetHelix {
            region,
            radius,
            rise_per_radian,
            start_angle,
            end_angle,
        } => {
            for (name, value) in [
                ("radius", radius),
                ("rise_per_radian", rise_per_radian),
                ("start_angle", start_angle),
                ("end_angle", end_angle),
            ] {
                if let Some(v) = value {
                    check_edit_number(name, *v)?;
                }
            }
            let Some(CurveSpec::Helix {
                radius: r,
                rise_per_radian: c,
                start_angle: a,
                end_angle: b,
                ..
            }) = edited.regions.get_mut(*region).map(|spec| &mut spec.curve)
            else {
                return Err(edit_error(format!("region {region} has no helix")));
            };
            for (field, value) in [(r, radius), (c, rise_per_radian), (a, start_angle), (b, end_angle)] {
                if let Some(v) = value {
                    *field = *v;
                }
            }
            // The flat segment's length follows the curve's.
            free_flat_length(&mut edited.regions[*region]);
        }
        BendEdit::SetFlatArc { region, radius } => {
            check_edit_number("radius", *radius)?;
            let Some(Some(FlatCurveSpec::Arc { radius: r, .. })) =
                edited.regions.get_mut(*region).map(|spec| spec.flat_curve.as_mut())
            else {
                return Err(edit_error(format!("region {region} has no flat arc")));
            };
            *r = *radius;
        }
        BendEdit::MoveControlPoint {
            region,
            index,
            position,
        } => {
            check_edit_coordinates(position)?;
            let count = scene_control_points(scene, *region)?.len();
            check_control_point_index(*index, count)?;
            if let CurveSpec::Bezier { control_points } | CurveSpec::Bspline { control_points, .. } =
                &mut edited.regions[*region].curve
            {
                control_points[*index] = *position;
            }
            free_flat_length(&mut edited.regions[*region]);
        }
        BendEdit::DragPreservingLength { .. } | BendEdit::DragEndHandles { .. } => {
            unreachable!("solved by the library's editor")
        }
    }
    Ok(edited)
}

/// A region's flat segment given by its end becomes one given by its direction, so that
/// its length follows the curve's when the curve changes.
fn free_flat_length(spec: &mut sheetform_bend::CurvedRegionSpec) {
    if let (Some(start), Some(end), None) = (spec.flat_start, spec.flat_end, spec.flat_direction) {
        spec.flat_direction = Some([end[0] - start[0], end[1] - start[1]]);
        spec.flat_end = None;
    }
}

/// The most vertices a loop of the sheet may reach by insertions in the editor.
pub const MAX_OUTLINE_VERTICES: usize = 10_000;

fn loop_mut<'a>(
    edited: &'a mut BendScene,
    scene: &BendScene,
    hole: Option<usize>,
) -> Result<&'a mut Vec<[f64; 2]>, PipelineError> {
    outline_loop(scene, hole)?;
    Ok(match hole {
        None => &mut edited.outline,
        Some(h) => &mut edited.holes[h],
    })
}

/// One edit, applied whole or refused. `editor` caches the library's editor of the
/// starting scene (one bend) across the bisection's attempts.
fn apply_edit(
    scene: &BendScene,
    edit: &BendEdit,
    editor: &mut Option<BendEditor>,
) -> Result<BendEditResult, PipelineError> {
    if !matches!(
        edit,
        BendEdit::DragPreservingLength { .. } | BendEdit::DragEndHandles { .. }
    ) {
        // The scene's own edits: the scene changed, bent as the CLI bends it (a periodic
        // B-spline's wrapped copies follow in the model).
        let edited = edited_scene(scene, edit)?;
        let length = |model: &BendModel| edit.region().map_or(0.0, |r| model.regions[r].curve.length());
        let before = length(&BendModel::from_scene(scene)?);
        let attempt = BendModel::from_scene(&edited).and_then(|model| bend(&model).map(|sheet| (model, sheet)));
        return Ok(match attempt {
            Ok((model, sheet)) => BendEditResult {
                scene: edited,
                info: EditInfo {
                    applied: true,
                    rejected_because: None,
                    solver: None,
                    curve_length_before: before,
                    curve_length_after: length(&model),
                },
                moved_fraction: 1.0,
                stopped_because: None,
                bent: Some(Box::new(super::BentScene { model, sheet })),
            },
            Err(e) => BendEditResult {
                scene: scene.clone(),
                info: EditInfo {
                    applied: false,
                    rejected_because: Some(e.to_string()),
                    solver: None,
                    curve_length_before: before,
                    curve_length_after: before,
                },
                moved_fraction: 0.0,
                stopped_because: None,
                bent: None,
            },
        });
    }
    let region = edit.region().unwrap_or(0);
    scene_control_points(scene, region)?;
    if !matches!(scene.regions[region].curve, CurveSpec::Bezier { .. }) {
        return Err(edit_error(format!(
            "region {region}: the length-preserving drag and the end handles edit Bézier control curves (move its control points instead)"
        )));
    }
    let handle = |h: &EndHandleSpec| EndHandle {
        position: h.position.map(vector),
        normal: h.normal.map(vector),
    };
    let mut editor = match editor {
        Some(editor) => editor.clone(),
        None => editor.insert(BendEditor::new(BendModel::from_scene(scene)?)?).clone(),
    };
    let info = match edit {
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
        _ => unreachable!("the scene's own edits are made above"),
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
        free_flat_length(&mut edited.regions[region]);
    }
    let moved_fraction = if info.applied { 1.0 } else { 0.0 };
    Ok(BendEditResult {
        scene: edited,
        info,
        moved_fraction,
        stopped_because: None,
        bent: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipeline::{run_bend, run_bend_bent, BendRunOptions, OutputSet, RunContext};

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

    /// A scene edit hands over the sheet its check bent, and exporting that sheet gives
    /// what bending the edited scene again gives: the same mesh, files and report; a
    /// refused edit and an editor drag hand over none.
    #[test]
    fn an_edit_s_bent_sheet_exports_as_the_edited_scene_bends() {
        let scene = rectangle();
        let context = RunContext::new(".").with_outputs(OutputSet::Preview);
        let options = BendEditOptions {
            stop_at_boundary: true,
            ..Default::default()
        };
        for edit in [
            BendEdit::MoveControlPoint {
                region: 0,
                index: 2,
                position: [150.0, 20.0, 70.0],
            },
            // Far past what can bend: stopped at the boundary, the best attempt's sheet.
            BendEdit::MoveControlPoint {
                region: 0,
                index: 3,
                position: [400.0, 0.0, 0.0],
            },
        ] {
            let result = edit_bend_scene_with(&scene, &edit, &options).unwrap();
            assert!(result.info.applied);
            let bent = result.bent.clone().expect("the check's sheet");
            let again = run_bend(&result.scene, &BendRunOptions::default(), &context).unwrap();
            let shared = run_bend_bent(&result.scene, Some(bent), &BendRunOptions::default(), &context).unwrap();
            assert_eq!(shared.sheet.mesh.positions, again.sheet.mesh.positions);
            assert_eq!(shared.sheet.mesh.flat, again.sheet.mesh.flat);
            assert_eq!(shared.sheet.mesh.triangles, again.sheet.mesh.triangles);
            assert_eq!(shared.files, again.files);
            assert_eq!(shared.angle_defects_rad, again.angle_defects_rad);
            let without_timings = |r: &crate::report::Report| {
                let mut v = serde_json::to_value(r).unwrap();
                v.as_object_mut().unwrap().remove("timings");
                v
            };
            assert_eq!(without_timings(&shared.report), without_timings(&again.report));
        }
        let drag = BendEdit::DragPreservingLength {
            region: 0,
            index: 2,
            position: [150.0, 20.0, 70.0],
            method: LengthMethod::Trim,
        };
        assert!(edit_bend_scene(&scene, &drag).unwrap().bent.is_none());
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
        assert!(torsion.bent.is_none(), "a refused edit hands over no sheet");
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

    fn torsion_scene() -> BendScene {
        BendScene::from_json(
            r#"{"outline": [[0, -60], [240, -60], [240, 60], [0, 60]], "regions": [{"flat_start": [0, 0],
            "flat_direction": [1, 0], "curve": {"type": "bezier",
            "control_points": [[0, 0, 0], [80, 10, 0], [150, -10, 60], [170, 10, 120]]}}]}"#,
        )
        .unwrap()
    }

    fn stopping() -> BendEditOptions {
        BendEditOptions {
            stop_at_boundary: true,
            ..BendEditOptions::default()
        }
    }

    /// A move past the admissible set stops at its boundary: the point goes part of the
    /// way, the shape bends, and a step of the bisection's resolution further is refused.
    #[test]
    fn a_move_past_the_boundary_stops_there() {
        let scene = torsion_scene();
        let edit = BendEdit::MoveControlPoint {
            region: 0,
            index: 2,
            position: [150.0, -20.0, 60.0],
        };
        let result = edit_bend_scene_with(&scene, &edit, &stopping()).unwrap();
        assert!(result.info.applied);
        let t = result.moved_fraction;
        assert!(t > 0.0 && t < 1.0, "moved {t}");
        assert!(result.stopped_because.as_deref().unwrap_or("").contains("regression"));
        let CurveSpec::Bezier { control_points } = &result.scene.regions[0].curve else {
            panic!()
        };
        assert!(
            (control_points[2][1] - (-10.0 - 10.0 * t)).abs() < 1e-12,
            "{control_points:?}"
        );
        assert_eq!(control_points[2][0], 150.0);
        // Admissible where it stopped, refused one bisection step further.
        run_bend(
            &result.scene,
            &BendRunOptions::default(),
            &RunContext::new(".").with_outputs(OutputSet::Preview),
        )
        .unwrap();
        let further = edit_part(&scene, &edit, t + 1.0 / 256.0).unwrap();
        assert!(!edit_bend_scene(&scene, &further).unwrap().info.applied);
        // Without the option the same edit is refused whole.
        let refused = edit_bend_scene(&scene, &edit).unwrap();
        assert!(!refused.info.applied);
        assert_eq!(refused.moved_fraction, 0.0);
        // An admissible edit is made whole, stop or not.
        let small = BendEdit::MoveControlPoint {
            region: 0,
            index: 2,
            position: [142.0, 9.0, 62.0],
        };
        assert_eq!(
            edit_bend_scene_with(&scene, &small, &stopping())
                .unwrap()
                .moved_fraction,
            1.0
        );
    }

    /// The desk's legs are B-splines: their control points move (the editor's drags), in
    /// the curve's plane; a leg pulled far outward stops where its flat segment would
    /// leave the sheet.
    #[test]
    fn b_spline_control_points_move_and_stop_at_the_sheet() {
        let scene = BendScene::from_json(include_str!("../../../../examples/desk.json")).unwrap();
        let small = BendEdit::MoveControlPoint {
            region: 1,
            index: 3,
            position: [100.0, 0.0, -110.0],
        };
        let result = edit_bend_scene_with(&scene, &small, &stopping()).unwrap();
        assert!(result.info.applied, "{:?}", result.info.rejected_because);
        assert_eq!(result.moved_fraction, 1.0);
        let CurveSpec::Bspline {
            control_points, degree, ..
        } = &result.scene.regions[1].curve
        else {
            panic!("still a B-spline")
        };
        assert_eq!(*degree, 3);
        assert_eq!(control_points[3], [100.0, 0.0, -110.0]);
        assert!(result.info.curve_length_after > result.info.curve_length_before);
        // The last point pulled 2 m outward: the leg would be longer than the sheet.
        let far = BendEdit::MoveControlPoint {
            region: 0,
            index: 5,
            position: [2130.0, 0.0, -280.0],
        };
        assert!(!edit_bend_scene(&scene, &far).unwrap().info.applied);
        let stopped = edit_bend_scene_with(&scene, &far, &stopping()).unwrap();
        assert!(stopped.info.applied);
        assert!(
            stopped.moved_fraction > 0.0 && stopped.moved_fraction < 0.5,
            "{}",
            stopped.moved_fraction
        );
        assert!(stopped.stopped_because.is_some());
    }

    /// A periodic B-spline's first points are wrapped round: moving one moves the closed
    /// curve, which stays closed.
    #[test]
    fn a_closed_curves_point_moves_with_its_wrapped_copy() {
        let scene = BendScene::from_json(include_str!("../../../../examples/closed-strip.json")).unwrap();
        let CurveSpec::Bspline { control_points, .. } = &scene.regions[0].curve else {
            panic!()
        };
        let p = control_points[0];
        let edit = BendEdit::MoveControlPoint {
            region: 0,
            index: 0,
            position: [p[0] * 1.03, p[1] * 1.03, p[2]],
        };
        let result = edit_bend_scene_with(&scene, &edit, &stopping()).unwrap();
        assert!(result.info.applied, "{:?}", result.info.rejected_because);
        assert!(result.moved_fraction > 0.0);
        run_bend(
            &result.scene,
            &BendRunOptions::default(),
            &RunContext::new(".").with_outputs(OutputSet::Preview),
        )
        .unwrap();
    }

    /// A stopped end-handle drag turns the normal part of the way, between the present
    /// normal and the wanted one.
    #[test]
    fn an_end_handle_turned_too_far_stops_part_of_the_way() {
        let scene = rectangle();
        let CurveSpec::Bezier { control_points } = &scene.regions[0].curve else {
            panic!()
        };
        let now = end_normal(control_points, false).normalize();
        let wanted = Vec3::new(0.0, 1.0, -0.3).normalize();
        let edit = BendEdit::DragEndHandles {
            region: 0,
            start: EndHandleSpec {
                position: None,
                normal: Some([wanted.x, wanted.y, wanted.z]),
            },
            end: EndHandleSpec::default(),
        };
        let half = edit_part(&scene, &edit, 0.5).unwrap();
        let BendEdit::DragEndHandles { start, .. } = half else {
            panic!()
        };
        let turned = vector(start.normal.unwrap()).normalize();
        assert!((turned - (now + wanted).normalize()).norm() < 1e-12);
        // Turned that far the sheet would fold onto itself: refused whole, stopped part
        // of the way, with the normal turned toward the wanted one.
        assert!(!edit_bend_scene(&scene, &edit).unwrap().info.applied);
        let result = edit_bend_scene_with(&scene, &edit, &stopping()).unwrap();
        assert!(result.info.applied);
        assert!(
            result.moved_fraction > 0.0 && result.moved_fraction < 1.0,
            "{}",
            result.moved_fraction
        );
        assert!(result.stopped_because.is_some());
        let CurveSpec::Bezier { control_points: after } = &result.scene.regions[0].curve else {
            panic!()
        };
        let reached = end_normal(after, false).normalize();
        assert!(
            reached.dot(&wanted) > now.dot(&wanted),
            "turned toward the wanted normal"
        );
        assert!(edit_bend_scene_with(
            &scene,
            &edit,
            &BendEditOptions {
                boundary_steps: 31,
                ..stopping()
            }
        )
        .is_err());
    }

    fn curve_length(scene: &BendScene, region: usize) -> f64 {
        BendModel::from_scene(scene).unwrap().regions[region].curve.length()
    }

    /// An outline vertex dragged inward stops where the sheet's edge meets the end of the
    /// flat segment: the right edge from (240, −60) to (X, 60) crosses y = 0 at
    /// `(240 + X)/2`, which must stay past the segment's end at `L` (the curve's length),
    /// so the stop is at `X = 2L − 240`.
    #[test]
    fn an_outline_vertex_stops_where_the_edge_meets_the_flat_segment() {
        let scene = rectangle();
        let length = curve_length(&scene, 0);
        let edit = BendEdit::MoveOutlineVertex {
            hole: None,
            index: 2,
            position: [100.0, 60.0],
        };
        assert!(!edit_bend_scene(&scene, &edit).unwrap().info.applied);
        let stopped = edit_bend_scene_with(&scene, &edit, &stopping()).unwrap();
        assert!(stopped.info.applied);
        let x = stopped.scene.outline[2][0];
        let expected = 2.0 * length - 240.0;
        assert!(
            x >= expected - 1e-9 && x - expected < 140.0 / 256.0,
            "stopped at {x}, boundary {expected}"
        );
        assert_eq!(stopped.scene.outline[2][1], 60.0);
        // Outward it is made whole.
        let outward = BendEdit::MoveOutlineVertex {
            hole: None,
            index: 2,
            position: [300.0, 80.0],
        };
        let result = edit_bend_scene_with(&scene, &outward, &stopping()).unwrap();
        assert_eq!(result.moved_fraction, 1.0);
        assert_eq!(result.scene.outline[2], [300.0, 80.0]);
        assert_eq!(result.info.curve_length_before, 0.0, "an outline edit changes no curve");
    }

    /// A vertex inserted on an edge changes nothing of the shape; deleted, the scene is
    /// the one before; a loop keeps three vertices; holes are edited as the outline.
    #[test]
    fn outline_vertices_are_inserted_and_deleted() {
        let scene = rectangle();
        let insert = BendEdit::InsertOutlineVertex {
            hole: None,
            after: 1,
            position: [240.0, 0.0],
        };
        let inserted = edit_bend_scene_with(&scene, &insert, &stopping()).unwrap();
        assert!(inserted.info.applied);
        assert_eq!(inserted.scene.outline.len(), 5);
        assert_eq!(inserted.scene.outline[2], [240.0, 0.0]);
        let deleted =
            edit_bend_scene(&inserted.scene, &BendEdit::DeleteOutlineVertex { hole: None, index: 2 }).unwrap();
        assert_eq!(deleted.scene, scene);
        let mut triangle = scene.clone();
        triangle.outline.pop();
        let e = edit_bend_scene(&triangle, &BendEdit::DeleteOutlineVertex { hole: None, index: 0 }).unwrap_err();
        assert!(e.to_string().contains("at least 3"), "{e}");
        let e = edit_bend_scene(&scene, &BendEdit::DeleteOutlineVertex { hole: None, index: 9 }).unwrap_err();
        assert!(e.to_string().contains("no vertex 9"), "{e}");
        let holed = BendScene::from_json(include_str!("../../../../examples/sheet-with-hole.json")).unwrap();
        let hole = &holed.holes[0];
        let c = [0, 1].map(|a| hole.iter().map(|p| p[a]).sum::<f64>() / hole.len() as f64);
        let p = hole[0];
        let smaller = BendEdit::MoveOutlineVertex {
            hole: Some(0),
            index: 0,
            position: [c[0] + 0.9 * (p[0] - c[0]), c[1] + 0.9 * (p[1] - c[1])],
        };
        let result = edit_bend_scene_with(&holed, &smaller, &stopping()).unwrap();
        assert!(result.info.applied, "{:?}", result.info.rejected_because);
        let e = edit_bend_scene(
            &holed,
            &BendEdit::MoveOutlineVertex {
                hole: Some(3),
                index: 0,
                position: [0.0, 0.0],
            },
        )
        .unwrap_err();
        assert!(e.to_string().contains("no hole 3"), "{e}");
    }

    /// The flat segment turned toward the sheet's long edge stops where its end reaches
    /// that edge: the direction at angle `asin(60 / L)` (the edge at y = 60).
    #[test]
    fn a_flat_segment_turned_too_far_stops_at_the_edge() {
        let scene = rectangle();
        let length = curve_length(&scene, 0);
        let moved = edit_bend_scene_with(
            &scene,
            &BendEdit::MoveFlatSegment {
                region: 0,
                start: Some([10.0, 5.0]),
                direction: None,
            },
            &stopping(),
        )
        .unwrap();
        assert_eq!(moved.moved_fraction, 1.0);
        assert_eq!(moved.scene.regions[0].flat_start, Some([10.0, 5.0]));
        let turn = BendEdit::MoveFlatSegment {
            region: 0,
            start: None,
            direction: Some([0.0, 1.0]),
        };
        let stopped = edit_bend_scene_with(&scene, &turn, &stopping()).unwrap();
        assert!(stopped.info.applied && stopped.moved_fraction < 1.0);
        let d = stopped.scene.regions[0].flat_direction.unwrap();
        let angle = d[1].atan2(d[0]);
        let boundary = (60.0 / length).asin();
        // Bisection on the nlerp fraction t: the angle is atan(t / (1 − t)).
        let t = stopped.moved_fraction;
        let resolution = ((t + 1.0 / 256.0) / (1.0 - t - 1.0 / 256.0)).atan() - (t / (1.0 - t)).atan();
        assert!(
            angle <= boundary + 1e-9 && boundary - angle < resolution,
            "{angle} vs {boundary}"
        );
    }

    /// A helix's radius and rise, and a flat arc's radius, change; the arc band's flat arc
    /// follows the helix's length.
    #[test]
    fn helix_and_flat_arc_parameters_change() {
        let scene = BendScene::from_json(include_str!("../../../../examples/arc-band.json")).unwrap();
        let before = curve_length(&scene, 0);
        let edit = BendEdit::SetHelix {
            region: 0,
            radius: Some(42.0),
            rise_per_radian: Some(11.0),
            start_angle: None,
            end_angle: None,
        };
        let result = edit_bend_scene_with(&scene, &edit, &stopping()).unwrap();
        assert!(result.info.applied, "{:?}", result.info.rejected_because);
        let (r, c) = (42.0_f64, 11.0_f64);
        let expected = (r * r + c * c).sqrt() * std::f64::consts::FRAC_PI_2;
        assert!(
            (result.info.curve_length_after - expected).abs() < 1e-9 * expected,
            "{}",
            result.info.curve_length_after
        );
        assert!((result.info.curve_length_before - before).abs() < 1e-12);
        let arc = BendEdit::SetFlatArc {
            region: 0,
            radius: 64.0,
        };
        let result = edit_bend_scene_with(&scene, &arc, &stopping()).unwrap();
        assert!(result.info.applied, "{:?}", result.info.rejected_because);
        let Some(FlatCurveSpec::Arc { radius, .. }) = &result.scene.regions[0].flat_curve else {
            panic!()
        };
        assert_eq!(*radius, 64.0);
        let e = edit_bend_scene(
            &scene,
            &BendEdit::SetHelix {
                region: 0,
                radius: Some(f64::NAN),
                rise_per_radian: None,
                start_angle: None,
                end_angle: None,
            },
        )
        .unwrap_err();
        assert!(e.to_string().contains("radius must be finite"), "{e}");
        let rectangle = rectangle();
        let e = edit_bend_scene(&rectangle, &arc).unwrap_err();
        assert!(e.to_string().contains("no flat arc"), "{e}");
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

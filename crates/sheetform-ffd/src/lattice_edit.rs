//! Edits of the control lattice: move, re-weight or transform control points.

use crate::{FfdError, NurbsVolume};
use nalgebra::{Matrix3, Rotation3, Unit, Vector3};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

type Vec3 = Vector3<f64>;

/// Which control points an edit applies to.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(
    untagged,
    expecting = "a list of [i, j, k] control-point indices, or index ranges {\"i\": [first, last], \"j\": [first, last], \"k\": [first, last]} (no other keys; a missing one means all)"
)]
pub enum ControlPointSelection {
    /// Explicit `[i, j, k]` indices.
    List(Vec<[usize; 3]>),
    /// Inclusive index ranges per direction; a missing direction means all of it, so
    /// `{"k": [3, 3]}` is the top layer of a lattice with four layers.
    Ranges(IndexRanges),
}

/// Inclusive index ranges per lattice direction (a missing direction means all of it).
/// Unknown keys are refused: a misspelt `"kk"` must not select the whole lattice.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct IndexRanges {
    /// `[first, last]` in u.
    #[serde(default)]
    pub i: Option<[usize; 2]>,
    /// `[first, last]` in v.
    #[serde(default)]
    pub j: Option<[usize; 2]>,
    /// `[first, last]` in w.
    #[serde(default)]
    pub k: Option<[usize; 2]>,
}

/// One change to the lattice (JSON: `{"move": {...}}`, `{"weight": {...}}` or
/// `{"transform": {...}}`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum LatticeEdit {
    /// Translate the selected control points by `by` (model units).
    Move {
        /// The control points.
        points: ControlPointSelection,
        /// Displacement (model units).
        by: [f64; 3],
    },
    /// Set the weights of the selected control points (positive, at most
    /// [`crate::MAX_WEIGHT`]): a weight above 1 pulls the volume towards the point.
    Weight {
        /// The control points.
        points: ControlPointSelection,
        /// The new weight.
        value: f64,
    },
    /// `p' = c + M R S (p − c) + t` for each selected point: scale `S` (per axis), then
    /// rotation `R` (`rotate_degrees` about `axis`), then a general matrix `M`, about the
    /// centre `c` (default: the selected points' centroid), then translation `t`.
    Transform {
        /// The control points.
        points: ControlPointSelection,
        /// Per-axis scale factors.
        #[serde(default)]
        scale: Option<[f64; 3]>,
        /// Rotation angle (degrees, right-handed about `axis`).
        #[serde(default)]
        rotate_degrees: Option<f64>,
        /// Rotation axis (default z).
        #[serde(default)]
        axis: Option<[f64; 3]>,
        /// A general 3×3 matrix (rows).
        #[serde(default)]
        matrix: Option<[[f64; 3]; 3]>,
        /// Translation (model units).
        #[serde(default)]
        translate: Option<[f64; 3]>,
        /// Centre of scaling and rotation (model units).
        #[serde(default)]
        centre: Option<[f64; 3]>,
    },
}

impl ControlPointSelection {
    /// Indices of the selected control points, checked against the lattice size.
    ///
    /// # Errors
    /// An index or range outside the lattice, or an empty selection, named by `field`.
    pub fn indices(&self, volume: &NurbsVolume, field: &str) -> Result<Vec<usize>, FfdError> {
        let counts = volume.counts();
        let mut out = Vec::new();
        match self {
            Self::List(list) => {
                for (n, ijk) in list.iter().enumerate() {
                    for d in 0..3 {
                        if ijk[d] >= counts[d] {
                            return Err(FfdError::field(
                                format!("{field}[{n}]"),
                                format!(
                                    "control point [{}, {}, {}] does not exist: the lattice has {} × {} × {} points (indices from 0)",
                                    ijk[0], ijk[1], ijk[2], counts[0], counts[1], counts[2]
                                ),
                            ));
                        }
                    }
                    out.push(volume.index(ijk[0], ijk[1], ijk[2]));
                }
            }
            Self::Ranges(IndexRanges { i, j, k }) => {
                let mut ranges = [[0usize; 2]; 3];
                for (d, (name, r)) in [("i", i), ("j", j), ("k", k)].into_iter().enumerate() {
                    ranges[d] = r.unwrap_or([0, counts[d] - 1]);
                    if ranges[d][0] > ranges[d][1] || ranges[d][1] >= counts[d] {
                        return Err(FfdError::field(
                            format!("{field}.{name}"),
                            format!(
                                "range [{}, {}] is not within 0..={}",
                                ranges[d][0],
                                ranges[d][1],
                                counts[d] - 1
                            ),
                        ));
                    }
                }
                for kk in ranges[2][0]..=ranges[2][1] {
                    for jj in ranges[1][0]..=ranges[1][1] {
                        for ii in ranges[0][0]..=ranges[0][1] {
                            out.push(volume.index(ii, jj, kk));
                        }
                    }
                }
            }
        }
        if out.is_empty() {
            return Err(FfdError::field(field, "selects no control point"));
        }
        Ok(out)
    }
}

fn finite(values: &[f64], field: &str) -> Result<(), FfdError> {
    if values.iter().any(|v| !v.is_finite()) {
        return Err(FfdError::field(field, "must be finite"));
    }
    Ok(())
}

/// The error for an edit that moves a control point to a non-finite place (finite
/// numbers whose sum or product overflows), naming the edit's field: the lattice's own
/// `lattice.control_points` may not be in the scene at all.
fn check_moved(volume: &NurbsVolume, points: &[Vec3], chosen: &[usize], field: &str) -> Result<(), FfdError> {
    let Some(&n) = chosen.iter().find(|&&n| !points[n].iter().all(|c| c.is_finite())) else {
        return Ok(());
    };
    let [nu, nv, _] = volume.counts();
    let (i, j, k) = (n % nu, (n / nu) % nv, n / (nu * nv));
    Err(FfdError::field(
        field,
        format!("moves control point [{i}, {j}, {k}] beyond the largest numbers (its coordinates overflow): give a smaller edit"),
    ))
}

/// Applies `edits` in order to a copy of the lattice; `field` is the JSON path of the
/// edit list (for messages such as `deformations[0].edits[2].move.points[1]`).
///
/// # Errors
/// Selections outside the lattice, non-finite numbers, weights that are not positive or
/// exceed [`crate::MAX_WEIGHT`], non-positive scale factors, a zero rotation axis, a
/// singular matrix, an edit that moves a control point to a non-finite place: each named
/// by the edit's field.
pub fn apply_edits(volume: &NurbsVolume, edits: &[LatticeEdit], field: &str) -> Result<NurbsVolume, FfdError> {
    let mut points = volume.control_points().to_vec();
    let mut weights = volume.weights().to_vec();
    for (e, edit) in edits.iter().enumerate() {
        match edit {
            LatticeEdit::Move { points: selection, by } => {
                let f = format!("{field}[{e}].move");
                finite(by, &format!("{f}.by"))?;
                let chosen = selection.indices(volume, &format!("{f}.points"))?;
                for &n in &chosen {
                    points[n] += Vec3::from(*by);
                }
                check_moved(volume, &points, &chosen, &format!("{f}.by"))?;
            }
            LatticeEdit::Weight {
                points: selection,
                value,
            } => {
                let f = format!("{field}[{e}].weight");
                crate::scene::check_weight(&format!("{f}.value"), *value, crate::scene::WeightSign::Positive)?;
                for n in selection.indices(volume, &format!("{f}.points"))? {
                    weights[n] = *value;
                }
            }
            LatticeEdit::Transform {
                points: selection,
                scale,
                rotate_degrees,
                axis,
                matrix,
                translate,
                centre,
            } => {
                let f = format!("{field}[{e}].transform");
                let chosen = selection.indices(volume, &format!("{f}.points"))?;
                let s = scale.unwrap_or([1.0; 3]);
                finite(&s, &format!("{f}.scale"))?;
                if s.iter().any(|&v| v <= 0.0) {
                    return Err(FfdError::field(format!("{f}.scale"), "scale factors must be positive"));
                }
                let mut linear = Matrix3::from_diagonal(&Vec3::from(s));
                if let Some(angle) = rotate_degrees {
                    let a = Vec3::from(axis.unwrap_or([0.0, 0.0, 1.0]));
                    finite(&[*angle, a.x, a.y, a.z], &format!("{f}.rotate_degrees"))?;
                    if a.norm() == 0.0 {
                        return Err(FfdError::field(format!("{f}.axis"), "rotation axis is zero"));
                    }
                    let r = Rotation3::from_axis_angle(&Unit::new_normalize(a), angle.to_radians());
                    linear = r.matrix() * linear;
                }
                if let Some(m) = matrix {
                    let m = Matrix3::from_row_slice(&m.concat());
                    finite(m.as_slice(), &format!("{f}.matrix"))?;
                    if m.determinant().abs() < 1e-12 {
                        return Err(FfdError::field(format!("{f}.matrix"), "matrix is singular"));
                    }
                    linear = m * linear;
                }
                let t = Vec3::from(translate.unwrap_or([0.0; 3]));
                finite(t.as_slice(), &format!("{f}.translate"))?;
                let c = match centre {
                    Some(c) => {
                        finite(c, &format!("{f}.centre"))?;
                        Vec3::from(*c)
                    }
                    None => chosen.iter().map(|&n| points[n]).sum::<Vec3>() / chosen.len() as f64,
                };
                for &n in &chosen {
                    points[n] = c + linear * (points[n] - c) + t;
                }
                check_moved(volume, &points, &chosen, &f)?;
            }
        }
    }
    volume.with_control_net(points, weights)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edits_move_weight_and_transform() {
        let v = NurbsVolume::parallelepiped(
            Vec3::zeros(),
            [Vec3::x(), Vec3::y(), Vec3::z()],
            [2, 2, 2],
            [3, 3, 3],
            None,
        )
        .unwrap();
        let edits: Vec<LatticeEdit> = serde_json::from_str(
            r#"[{"move": {"points": [[1, 1, 1]], "by": [0, 0, 0.5]}},
                {"weight": {"points": {"k": [2, 2]}, "value": 2.0}},
                {"transform": {"points": {"k": [0, 0]}, "scale": [2, 2, 1]}}]"#,
        )
        .unwrap();
        let out = apply_edits(&v, &edits, "edits").unwrap();
        assert!((out.control_points()[v.index(1, 1, 1)] - Vec3::new(0.5, 0.5, 1.0)).norm() < 1e-12);
        assert_eq!(out.weights()[v.index(0, 2, 2)], 2.0);
        // Bottom layer scaled about its centroid (0.5, 0.5, 0).
        assert!((out.control_points()[v.index(0, 0, 0)] - Vec3::new(-0.5, -0.5, 0.0)).norm() < 1e-12);
        let bad: Vec<LatticeEdit> =
            serde_json::from_str(r#"[{"move": {"points": [[3, 0, 0]], "by": [0, 0, 1]}}]"#).unwrap();
        let e = apply_edits(&v, &bad, "deformations[0].edits").unwrap_err();
        assert!(e.to_string().contains("deformations[0].edits[0].move.points[0]"), "{e}");
    }

    /// Issue 35: edits of finite numbers that together send a control point beyond the
    /// largest numbers were reported at `lattice.control_points[16]`, a field the scene
    /// does not have (its lattice is made from a box): the edit is named, and the point.
    #[test]
    fn an_overflowing_edit_is_named_not_the_lattice() {
        let v = NurbsVolume::parallelepiped(
            Vec3::zeros(),
            [Vec3::x(), Vec3::y(), Vec3::z()],
            [2, 2, 2],
            [3, 3, 3],
            None,
        )
        .unwrap();
        for (edits, field, point) in [
            (
                r#"[{"move": {"points": [[1, 1, 1]], "by": [1.5e308, 0, 0]}},
                    {"move": {"points": {"i": [1, 1]}, "by": [1.5e308, 0, 0]}}]"#,
                "deformations[0].edits[1].move.by",
                "[1, 1, 1]",
            ),
            (
                r#"[{"transform": {"points": [[2, 2, 2], [0, 0, 0]], "scale": [1e300, 1, 1]}},
                    {"transform": {"points": [[2, 2, 2], [0, 0, 0]], "scale": [1e300, 1, 1]}}]"#,
                "deformations[0].edits[1].transform",
                "[2, 2, 2]",
            ),
        ] {
            let edits: Vec<LatticeEdit> = serde_json::from_str(edits).unwrap();
            let e = apply_edits(&v, &edits, "deformations[0].edits")
                .unwrap_err()
                .to_string();
            assert!(e.contains(&format!("`{field}`")) && e.contains(point), "{e}");
            assert!(!e.contains("lattice"), "{e}");
        }
    }

    /// Issue 35: a weight edit had no upper bound (1e300 left the panels collapsed and
    /// was reported as that): it is refused at the edit's own field with its value and
    /// the bounds, never at `lattice.weights`, which the scene may not have.
    #[test]
    fn a_weight_edit_past_the_bound_names_the_edit() {
        let v = NurbsVolume::parallelepiped(
            Vec3::zeros(),
            [Vec3::x(), Vec3::y(), Vec3::z()],
            [2, 2, 2],
            [3, 3, 3],
            None,
        )
        .unwrap();
        let edit = |value: f64| -> Vec<LatticeEdit> {
            serde_json::from_value(serde_json::json!([
                {"move": {"points": [[1, 1, 1]], "by": [0, 0, 0.1]}},
                {"weight": {"points": [[1, 1, 1]], "value": value}}
            ]))
            .unwrap()
        };
        let out = apply_edits(&v, &edit(crate::MAX_WEIGHT), "deformations[0].edits").unwrap();
        assert_eq!(out.weights()[v.index(1, 1, 1)], crate::MAX_WEIGHT);
        for (value, shown) in [(1e300, "1e300"), (1_000_001.0, "1.000001e6"), (0.0, "0")] {
            let e = apply_edits(&v, &edit(value), "deformations[0].edits")
                .unwrap_err()
                .to_string();
            assert_eq!(
                e,
                format!(
                    "scene field `deformations[0].edits[1].weight.value`: must be a positive number up to 1e6, got \
                     {shown}"
                )
            );
        }
    }
}

//! The exactly isometric discretisation of a rectifying developable: a folded strip.

use crate::RulingSample;
use nalgebra::Matrix3;
use sheetform_geometry::{rotation_about_axis, RigidMotion, Vec2, Vec3};

/// Lifts a flat point to 3D (`z = 0`).
pub fn lift(p: Vec2) -> Vec3 {
    Vec3::new(p.x, p.y, 0.0)
}

/// The rigid motions that carry the flat sheet onto the bent sheet, strip by strip.
///
/// The flat sheet is cut along the sampled rulings `0..=n`. `motions[m]` places the part
/// between ruling `m − 1` and ruling `m` (`motions[0]`: before the first ruling,
/// `motions[n + 1]`: after the last). Crossing ruling `j` turns the sheet about that
/// ruling by the fold angle
///
/// `φ_j = ∫_{s_{j−½}}^{s_{j+½}} ρ ds ≈ ρ_j (s_{j+1} − s_{j−1}) / 2`
///
/// (`ρ` the fold rate of [`RulingSample`]; half intervals at the two ends), so
/// `motions[j + 1] = motions[j] ∘ Rot(flat ruling j, φ_j)`. `motions[0]` maps the flat
/// frame `(e, n̄, +z)` at the first geodesic point onto `(T, b, n)` at `p(0)`: a planar
/// piece beyond an end ruling lies in the tangent plane along that ruling (§3.4).
///
/// Every strip is moved rigidly, so the mesh is an exact isometry of the flat pattern
/// (edge lengths equal to rounding) and exactly developable. Its distance to the smooth
/// rectifying developable is `O(h²)` in the ruling spacing; the integration is the
/// midpoint rule of the frame equation `Q' = Q [w]×`, whose body angular velocity
/// `w = ρ r̄` always lies along the flat ruling.
#[derive(Debug, Clone)]
pub struct FoldedStrip {
    /// One motion per part, `n + 2` for `n + 1` rulings.
    pub motions: Vec<RigidMotion>,
    /// Fold angle at each ruling (radians).
    pub fold_angles: Vec<f64>,
}

impl FoldedStrip {
    /// Builds the motions from the ruling samples.
    pub fn new(samples: &[RulingSample]) -> Self {
        let n = samples.len();
        let e = samples[0].flat_tangent;
        let side = Vec2::new(-e.y, e.x);
        let flat_frame = Matrix3::new(e.x, side.x, 0.0, e.y, side.y, 0.0, 0.0, 0.0, 1.0);
        let first = &samples[0];
        let frame = Matrix3::from_columns(&[first.tangent, first.side, first.normal]);
        let rotation = frame * flat_frame.transpose();
        let start = RigidMotion::new(rotation, first.point - rotation * lift(first.flat_point));
        let mut fold_angles = Vec::with_capacity(n);
        for j in 0..n {
            let before = if j > 0 {
                samples[j - 1].arc_length
            } else {
                samples[j].arc_length
            };
            let after = if j + 1 < n {
                samples[j + 1].arc_length
            } else {
                samples[j].arc_length
            };
            fold_angles.push(samples[j].fold_rate * 0.5 * (after - before));
        }
        let mut motions = Vec::with_capacity(n + 1);
        motions.push(start);
        for j in 0..n {
            let fold = rotation_about_axis(
                &lift(samples[j].flat_point),
                &lift(samples[j].flat_ruling),
                fold_angles[j],
            );
            let next = motions[j].compose(&fold);
            motions.push(next);
        }
        Self { motions, fold_angles }
    }

    /// The same strip with every fold angle scaled by `t ∈ [0, 1]`: a continuous
    /// isometric deformation from the flat sheet (`t = 0`, placed in the tangent plane at
    /// the first ruling) to the bent sheet (`t = 1`).
    pub fn scaled(&self, samples: &[RulingSample], t: f64) -> Self {
        let mut motions = Vec::with_capacity(self.motions.len());
        motions.push(self.motions[0]);
        let fold_angles: Vec<f64> = self.fold_angles.iter().map(|a| a * t).collect();
        for (j, s) in samples.iter().enumerate() {
            let fold = rotation_about_axis(&lift(s.flat_point), &lift(s.flat_ruling), fold_angles[j]);
            let next = motions[j].compose(&fold);
            motions.push(next);
        }
        Self { motions, fold_angles }
    }
}

//! The mirror-symmetry plane from the user's annotation (§6.1) and the 3D relation of a
//! pair of mirror points (Cordier et al.'s formulas, §6.1).
//!
//! Model frame: `X` right, `Y` up, `Z` towards the viewer, orthographic (pixels). The
//! frame segments project vectors `u`, `v` lying in the plane and the pair of symmetric
//! points projects `s`, along the plane's normal. `u·v = u·s = v·s = 0` with
//! `u = (ū, u_z)` etc. give `u_z = −ū·s̄/s_z`, `v_z = −v̄·s̄/s_z` and
//!
//! `s_z² = −(ū·s̄)(v̄·s̄)/(ū·v̄)`,
//!
//! so the annotation is degenerate unless the right side is positive (and finite: `ū·v̄`
//! must not vanish). The sign of `s_z` is the depth-reversal ambiguity of a single
//! orthographic view: by convention `s_z > 0` (the second point of the pair is nearer the
//! camera), `flip_depth` takes the other. `n = s/|s|`; the plane passes through the
//! midpoint of the annotated pair at depth 0.
//!
//! For image points `p̄`, `p̄′` of a mirror pair, `t = p − p′ = λ n` and the midpoint
//! `m = (p + p′)/2` lies on the plane. Departures from the printed formulas (see
//! `shared/papers/README.md`): `λ` is the least-squares fit `λ = (p̄ − p̄′)·n̄ / |n̄|²` over
//! both image axes instead of the `y` component alone (the printed one divides by `n_y`,
//! which vanishes for a vertical plane), which also removes the printed sign error of
//! `t_z`; `m_z` follows from `n·(m − c) = 0` with the plane's point `c`.

use crate::annotation::{image_to_model, SymmetrySpec};
use crate::PhotoError;
use nalgebra::{Vector2, Vector3};

type Vec2 = Vector2<f64>;
type Vec3 = Vector3<f64>;

/// The symmetry plane `n · (x − c) = 0` in the model frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SymmetryPlane {
    /// Unit normal.
    pub normal: Vec3,
    /// A point of the plane (the annotated pair's midpoint, depth 0).
    pub point: Vec3,
}

impl SymmetryPlane {
    /// The plane of an annotation.
    ///
    /// # Errors
    /// [`PhotoError::Field`] on `symmetry` when the frame gives no real plane normal
    /// (`s_z² ≤ 0`, parallel or perpendicular frame images, zero-length segments) or the
    /// plane is seen edge-on.
    pub fn from_annotation(spec: &SymmetrySpec) -> Result<Self, PhotoError> {
        let vector = |seg: [[f64; 2]; 2]| image_to_model(seg[1]) - image_to_model(seg[0]);
        let (u, v) = (vector(spec.frame[0]), vector(spec.frame[1]));
        let (p0, p1) = (image_to_model(spec.points[0]), image_to_model(spec.points[1]));
        let s = p1 - p0;
        for (name, w) in [
            ("symmetry.frame[0]", u),
            ("symmetry.frame[1]", v),
            ("symmetry.points", s),
        ] {
            if w.norm() < 1.0 {
                return Err(PhotoError::field(name, "its two points are less than a pixel apart"));
            }
        }
        let uv = u.dot(&v);
        let (us, vs) = (u.dot(&s), v.dot(&s));
        if uv.abs() < 1e-3 * u.norm() * v.norm() {
            return Err(PhotoError::field(
                "symmetry.frame",
                "the two frame segments are perpendicular in the image: the plane's tilt cannot be recovered (draw segments whose images make another angle)",
            ));
        }
        let sz2 = -us * vs / uv;
        if !(sz2.is_finite() && sz2 > 1e-6 * s.norm_squared()) {
            return Err(PhotoError::field(
                "symmetry",
                format!(
                    "the frame and the symmetric pair give no real plane normal (s_z² = {sz2:.3e} px² ≤ 0): the pair must \
                     be mirror images across the plane the frame spans, and the frame's two segments perpendicular in 3D"
                ),
            ));
        }
        let sz = if spec.flip_depth { -sz2.sqrt() } else { sz2.sqrt() };
        let normal = Vec3::new(s.x, s.y, sz).normalize();
        if normal.z.abs() < 1e-3 {
            return Err(PhotoError::field(
                "symmetry",
                "the plane is seen edge-on: no depth can be recovered",
            ));
        }
        let mid = 0.5 * (p0 + p1);
        Ok(Self {
            normal,
            point: Vec3::new(mid.x, mid.y, 0.0),
        })
    }

    /// The image direction of the normal (unit): mirror pairs are joined along it
    /// (§5.3).
    pub fn image_direction(&self) -> Vec2 {
        Vec2::new(self.normal.x, self.normal.y).normalize()
    }

    /// Signed distance of a point from the plane.
    pub fn signed_distance(&self, p: Vec3) -> f64 {
        self.normal.dot(&(p - self.point))
    }

    /// The mirror image of a point.
    pub fn mirror(&self, p: Vec3) -> Vec3 {
        p - 2.0 * self.signed_distance(p) * self.normal
    }

    /// The 3D difference `t = p − p′` and midpoint `m` of a mirror pair seen at image
    /// points `a`, `b` (model frame).
    pub fn pair_relation(&self, a: Vec2, b: Vec2) -> (Vec3, Vec3) {
        let n2 = Vec2::new(self.normal.x, self.normal.y);
        let lambda = (a - b).dot(&n2) / n2.norm_squared();
        let t = self.normal * lambda;
        let m2 = 0.5 * (a + b);
        let mz = self.point.z
            - (self.normal.x * (m2.x - self.point.x) + self.normal.y * (m2.y - self.point.y)) / self.normal.z;
        (t, Vec3::new(m2.x, m2.y, mz))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A plane with a known normal, its frame and pair projected orthographically: the
    /// normal comes back exactly (up to the depth sign convention).
    #[test]
    fn recovers_a_known_plane() {
        let n = Vec3::new(0.6, -0.3, 0.74).normalize();
        // Two perpendicular vectors in the plane.
        let u = n.cross(&Vec3::new(0.2, 1.0, 0.1)).normalize() * 120.0;
        let v = n.cross(&u).normalize() * 80.0;
        let origin = Vec3::new(300.0, -200.0, 0.0);
        let to_image = |p: Vec3| [p.x, -p.y];
        let q = origin + u * 0.3 + v * 0.2;
        let spec = SymmetrySpec {
            frame: [
                [to_image(origin), to_image(origin + u)],
                [to_image(origin), to_image(origin + v)],
            ],
            points: [to_image(q - n * 50.0), to_image(q + n * 50.0)],
            flip_depth: false,
        };
        let plane = SymmetryPlane::from_annotation(&spec).unwrap();
        assert!((plane.normal - n).norm() < 1e-12, "{:?}", plane.normal);
        // Mirror pair relation reproduces the true difference and the midpoint depth up to
        // the plane's offset (the annotation cannot fix the absolute depth).
        let p = origin + u * -0.4 + v * 0.7 + n * 33.0;
        let p2 = p - n * 66.0;
        let (t, m) = plane.pair_relation(Vec2::new(p.x, p.y), Vec2::new(p2.x, p2.y));
        assert!((t - (p - p2)).norm() < 1e-9);
        let true_mid = 0.5 * (p + p2);
        assert!((m.x - true_mid.x).abs() < 1e-9 && (m.y - true_mid.y).abs() < 1e-9);
        assert!(plane.signed_distance(m).abs() < 1e-9);
        let flipped = SymmetryPlane::from_annotation(&SymmetrySpec {
            flip_depth: true,
            ..spec
        })
        .unwrap();
        assert!((flipped.normal.z + n.z).abs() < 1e-12);
    }

    #[test]
    fn perpendicular_frame_images_are_refused() {
        let spec = SymmetrySpec {
            frame: [[[0.0, 0.0], [0.0, 100.0]], [[0.0, 0.0], [100.0, 0.0]]],
            points: [[10.0, 10.0], [20.0, 40.0]],
            flip_depth: false,
        };
        let e = SymmetryPlane::from_annotation(&spec).unwrap_err();
        assert!(e.to_string().contains("symmetry.frame"), "{e}");
    }

    #[test]
    fn a_frame_without_real_normal_is_refused() {
        // ū·s̄ and v̄·s̄ of the same sign with ū·v̄ > 0: s_z² < 0.
        let spec = SymmetrySpec {
            frame: [[[0.0, 0.0], [100.0, 0.0]], [[0.0, 0.0], [100.0, -30.0]]],
            points: [[0.0, 0.0], [50.0, 0.0]],
            flip_depth: false,
        };
        let e = SymmetryPlane::from_annotation(&spec).unwrap_err();
        assert!(e.to_string().contains("no real plane normal"), "{e}");
    }
}

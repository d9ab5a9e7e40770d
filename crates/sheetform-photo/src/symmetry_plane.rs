//! The mirror-symmetry plane from the user's annotation (§6.1) and the 3D relation of a
//! pair of mirror points (Cordier et al.'s formulas, §6.1).
//!
//! **Orthographic camera.** Model frame: `X` right, `Y` up, `Z` towards the viewer
//! (pixels). The frame segments project vectors `u`, `v` lying in the plane and the pair
//! of symmetric points projects `s`, along the plane's normal. `u·v = u·s = v·s = 0` with
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
//!
//! **Perspective camera** (beyond the paper, which names it as its limit): each marked
//! point lies on its ray, `P_k = P_k(Z_k)` ([`Camera::point_at_depth`]), and the same
//! conditions hold in 3D: `u·v = u·s = v·s = 0`, the pair's midpoint on the plane
//! (`s·(½(S₀ + S₁) − A) = 0` for the frame's first point `A`), a second frame segment
//! that does not start on the first also on it, and the gauge `Z_{S₀} + Z_{S₁} = 0` (the
//! whole scene may be scaled about the centre of projection; the true size fixes it). The
//! five or six equations in as many depths are solved by Gauss–Newton from the
//! orthographic solution (`flip_depth` picks its sign). A mirror pair seen at `a`, `b`
//! has `p = C + α r_a`, `p′ = C + β r_b` on the rays `r = (x̄ − c, −f)` from the centre
//! `C`; `α r_a − β r_b = λ n` and `n·(½(p + p′) − c) = 0` are four linear equations in
//! `(α, β, λ)`, solved in the least-squares sense (exact when `a`, `b` and the normal's
//! vanishing point are collinear); `t = λ n`, `m = ½(p + p′)`. Mirror points are joined
//! in the image along the line through the vanishing point of `n`.

use crate::annotation::{image_to_model, SymmetrySpec};
use crate::camera::Camera;
use crate::PhotoError;
use nalgebra::{DMatrix, DVector, Matrix4x3, Vector2, Vector3, Vector4};

type Vec2 = Vector2<f64>;
type Vec3 = Vector3<f64>;

/// The symmetry plane `n · (x − c) = 0` in the model frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SymmetryPlane {
    /// Unit normal.
    pub normal: Vec3,
    /// A point of the plane (the annotated pair's midpoint, depth 0).
    pub point: Vec3,
    /// The camera the plane is seen through.
    pub camera: Camera,
}

impl SymmetryPlane {
    /// The plane of an annotation seen through `camera`.
    ///
    /// # Errors
    /// [`PhotoError::Field`] on `symmetry` when the frame gives no real plane normal
    /// (`s_z² ≤ 0`, parallel or perpendicular frame images, zero-length segments), the
    /// plane is seen edge-on, or (perspective) no plane through the marked rays meets the
    /// conditions.
    pub fn from_annotation(spec: &SymmetrySpec, camera: &Camera) -> Result<Self, PhotoError> {
        let orthographic = Self::orthographic(spec)?;
        if camera.is_orthographic() {
            return Ok(orthographic);
        }
        Self::perspective(spec, camera, &orthographic)
    }

    /// The orthographic plane of the annotation.
    fn orthographic(spec: &SymmetrySpec) -> Result<Self, PhotoError> {
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
            camera: Camera::orthographic(),
        })
    }

    /// The plane seen through a perspective camera: Gauss–Newton on the depths of the
    /// marked points from the orthographic plane `start` (see the module's comment).
    fn perspective(spec: &SymmetrySpec, camera: &Camera, start: &Self) -> Result<Self, PhotoError> {
        // The marked points, one unknown depth per distinct image point.
        let marked: [Vec2; 6] = [
            spec.frame[0][0],
            spec.frame[0][1],
            spec.frame[1][0],
            spec.frame[1][1],
            spec.points[0],
            spec.points[1],
        ]
        .map(image_to_model);
        let mut distinct: Vec<Vec2> = Vec::new();
        let index: Vec<usize> = marked
            .iter()
            .map(|p| match distinct.iter().position(|q| (q - p).norm() < 1e-6) {
                Some(k) => k,
                None => {
                    distinct.push(*p);
                    distinct.len() - 1
                }
            })
            .collect();
        let [a, b, c, d, s0, s1] = [0, 1, 2, 3, 4, 5].map(|k| index[k]);
        // A second segment starting off the first adds the condition that it lies on the plane.
        let second_apart = c != a && c != b;
        // Orthographic start: every frame point on the plane, the pair's midpoint at depth 0.
        let mid = 0.5 * (marked[4] + marked[5]);
        let n = start.normal;
        let z0: Vec<f64> = distinct
            .iter()
            .enumerate()
            .map(|(k, p)| {
                if k == s0 || k == s1 {
                    let half = 0.5 * n.z / n.xy().norm() * (marked[5] - marked[4]).norm();
                    if k == s1 {
                        half
                    } else {
                        -half
                    }
                } else {
                    -(n.x * (p.x - mid.x) + n.y * (p.y - mid.y)) / n.z
                }
            })
            .collect();
        let scale = |v: Vec2| v.norm().max(1.0);
        let (u_len, v_len, s_len) = (
            scale(marked[1] - marked[0]),
            scale(marked[3] - marked[2]),
            scale(marked[5] - marked[4]),
        );
        let residuals = |z: &DVector<f64>| -> DVector<f64> {
            let p = |k: usize| camera.point_at_depth(distinct[k], z[k]);
            let (u, v, s) = (p(b) - p(a), p(d) - p(c), p(s1) - p(s0));
            let mut r = vec![
                0.5 * (z[s0] + z[s1]) / s_len,
                u.dot(&v) / (u_len * v_len),
                u.dot(&s) / (u_len * s_len),
                v.dot(&s) / (v_len * s_len),
                s.dot(&(0.5 * (p(s0) + p(s1)) - p(a))) / (s_len * u_len),
            ];
            if second_apart {
                r.push(s.dot(&(p(c) - p(a))) / (s_len * u_len));
            }
            DVector::from_vec(r)
        };
        let mut z = DVector::from_vec(z0);
        let mut r = residuals(&z);
        for _ in 0..100 {
            if r.amax() < 1e-13 {
                break;
            }
            let step_size = 1e-5 * s_len.max(u_len);
            let mut jacobian = DMatrix::zeros(r.len(), z.len());
            for k in 0..z.len() {
                let mut ahead = z.clone();
                ahead[k] += step_size;
                let mut behind = z.clone();
                behind[k] -= step_size;
                jacobian.set_column(k, &((residuals(&ahead) - residuals(&behind)) / (2.0 * step_size)));
            }
            let Ok(step) = jacobian.svd(true, true).solve(&(-&r), 1e-14) else {
                break;
            };
            let mut length = 1.0;
            let mut improved = false;
            for _ in 0..30 {
                let trial = &z + &step * length;
                let rt = residuals(&trial);
                if rt.norm() < r.norm() {
                    z = trial;
                    r = rt;
                    improved = true;
                    break;
                }
                length *= 0.5;
            }
            if !improved {
                break;
            }
        }
        let points: Vec<Vec3> = (0..distinct.len())
            .map(|k| camera.point_at_depth(distinct[k], z[k]))
            .collect();
        let s = points[s1] - points[s0];
        let in_front = points.iter().all(|p| camera.divisor(p.z) > 0.05);
        if r.amax() > 1e-9 || !in_front || s.norm() < 1e-9 {
            return Err(PhotoError::field(
                "symmetry",
                format!(
                    "seen through the perspective camera, the frame and the symmetric pair give no plane (the \
                     conditions stay {:.1e} off): the pair must be mirror images across the plane the frame \
                     spans, the frame's two segments perpendicular in 3D, and the focal length right",
                    r.amax()
                ),
            ));
        }
        let normal = s.normalize();
        if normal.z.abs() < 1e-3 {
            return Err(PhotoError::field(
                "symmetry",
                "the plane is seen edge-on: no depth can be recovered",
            ));
        }
        Ok(Self {
            normal,
            point: 0.5 * (points[s0] + points[s1]),
            camera: *camera,
        })
    }

    /// The unit image direction along which the mirror partner of the image point `at`
    /// is seen (§5.3): the image of the normal, through its vanishing point under
    /// perspective.
    pub fn image_direction_at(&self, at: Vec2) -> Vec2 {
        self.camera
            .image_direction(self.normal, at)
            .unwrap_or_else(|| Vec2::new(self.normal.x, self.normal.y).normalize())
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
        if let Some(f) = self.camera.focal_length_px {
            let centre = self.camera.principal_point;
            let eye = Vec3::new(centre.x, centre.y, f);
            let ray = |p: Vec2| Vec3::new(p.x - centre.x, p.y - centre.y, -f);
            let (ra, rb, n) = (ray(a), ray(b), self.normal);
            #[rustfmt::skip]
            let m = Matrix4x3::new(
                ra.x, -rb.x, -n.x * f,
                ra.y, -rb.y, -n.y * f,
                ra.z, -rb.z, -n.z * f,
                0.5 * n.dot(&ra), 0.5 * n.dot(&rb), 0.0,
            );
            let rhs = Vector4::new(0.0, 0.0, 0.0, n.dot(&(self.point - eye)));
            if let Ok(x) = m.svd(true, true).solve(&rhs, 1e-12) {
                let (p, q) = (eye + ra * x[0], eye + rb * x[1]);
                return (n * (x[2] * f), 0.5 * (p + q));
            }
        }
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
        let plane = SymmetryPlane::from_annotation(&spec, &Camera::orthographic()).unwrap();
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
        let flipped = SymmetryPlane::from_annotation(
            &SymmetrySpec {
                flip_depth: true,
                ..spec
            },
            &Camera::orthographic(),
        )
        .unwrap();
        assert!((flipped.normal.z + n.z).abs() < 1e-12);
    }

    /// The same seen through a perspective camera (a phone's 26 mm lens, the object at
    /// two of its sizes from the camera): the normal comes back exactly, and a mirror
    /// pair's relation gives its two 3D points up to the scale about the camera centre
    /// that one view cannot fix.
    #[test]
    fn recovers_a_known_plane_in_perspective() {
        let camera = Camera::perspective(480.0, [320.0, 240.0]);
        let n = Vec3::new(0.6, -0.3, 0.74).normalize();
        let u = n.cross(&Vec3::new(0.2, 1.0, 0.1)).normalize() * 120.0;
        let v = n.cross(&u).normalize() * 80.0;
        let origin = Vec3::new(300.0, -200.0, -40.0);
        let to_image = |p: Vec3| {
            let q = camera.project(p);
            [q.x, -q.y]
        };
        let q = origin + u * 0.3 + v * 0.2;
        for (frame, name) in [
            ([[origin, origin + u], [origin, origin + v]], "shared corner"),
            (
                [[origin, origin + u], [origin + u * 0.5, origin + u * 0.5 + v]],
                "second segment apart",
            ),
        ] {
            let spec = SymmetrySpec {
                frame: frame.map(|seg| seg.map(to_image)),
                points: [to_image(q - n * 50.0), to_image(q + n * 50.0)],
                flip_depth: false,
            };
            let plane = SymmetryPlane::from_annotation(&spec, &camera).unwrap();
            assert!((plane.normal - n).norm() < 1e-9, "{name}: {:?}", plane.normal);
            // A pair far from the marked one, across the plane.
            let p = origin + u * -0.4 + v * 0.7 + n * 33.0;
            let p2 = p - n * 66.0;
            let (t, m) = plane.pair_relation(camera.project(p), camera.project(p2));
            // Up to one scale about the centre of projection.
            let eye = Vec3::new(320.0, -240.0, 480.0);
            let ratio = (m - eye).norm() / (0.5 * (p + p2) - eye).norm();
            assert!((t - (p - p2) * ratio).norm() < 1e-7, "{name}: {t} {}", p - p2);
            assert!((m - eye - (0.5 * (p + p2) - eye) * ratio).norm() < 1e-7, "{name}");
            assert!(plane.signed_distance(m).abs() < 1e-7);
            // The partner is seen along the line through the normal's vanishing point.
            let direction = plane.image_direction_at(camera.project(p));
            let seen = (camera.project(p2) - camera.project(p)).normalize();
            assert!((direction.dot(&seen).abs() - 1.0).abs() < 1e-12, "{name}");
        }
    }

    #[test]
    fn perpendicular_frame_images_are_refused() {
        let spec = SymmetrySpec {
            frame: [[[0.0, 0.0], [0.0, 100.0]], [[0.0, 0.0], [100.0, 0.0]]],
            points: [[10.0, 10.0], [20.0, 40.0]],
            flip_depth: false,
        };
        let e = SymmetryPlane::from_annotation(&spec, &Camera::orthographic()).unwrap_err();
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
        let e = SymmetryPlane::from_annotation(&spec, &Camera::orthographic()).unwrap_err();
        assert!(e.to_string().contains("no real plane normal"), "{e}");
    }
}

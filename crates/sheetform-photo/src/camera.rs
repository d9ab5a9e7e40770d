//! The camera that took the photograph: orthographic (the paper's assumption, §6) or a
//! pinhole perspective camera (the paper's stated limit and future work, §9 and Fig. 14).
//!
//! Model frame (pixels): `X` = image x, `Y` = −(image y), `Z` towards the viewer. A
//! perspective camera with focal length `f` (pixels) and principal point `c` (model
//! frame) has its centre of projection at `(c, f)` and looks down `−Z`; the plane `Z = 0`
//! is seen at scale 1, so a point `P = (X, Y, Z)` is seen at
//!
//! `x = c + (P_xy − c) / w`, `w = (f − Z) / f` (the perspective divisor).
//!
//! The image point `x̄` is therefore the image of every point of its ray, which is
//! linear in the point:
//!
//! `P_xy + a Z = x̄`, `a = (x̄ − c) / f`,
//!
//! so the paper's projection term `|P_xy − x̄|²` becomes `|P_xy + a Z − x̄|²` and stays a
//! linear least-squares residual. The orthographic camera is the limit `f → ∞` (`a = 0`,
//! `w = 1`).
//!
//! A direction `n` has its vanishing point at `c − f n_xy / n_z`; the image line through
//! `x̄` along which the points `P + t n` are seen has the direction
//! `f n_xy + n_z (x̄ − c)` (towards or away from the vanishing point), the image direction
//! of `n` itself under orthography.

use crate::annotation::{image_to_model, CameraSpec, Projection};
use crate::PhotoError;
use nalgebra::{Vector2, Vector3};

type Vec2 = Vector2<f64>;
type Vec3 = Vector3<f64>;

/// The diagonal of a 35 mm film frame (36 × 24 mm), in mm: a focal length "35 mm
/// equivalent" `F` is `F / 43.27` image diagonals (the diagonal field of view of CIPA
/// DC-004, which EXIF's `FocalLengthIn35mmFilm` uses).
pub const FILM_35MM_DIAGONAL_MM: f64 = 43.266_615_305_567_87;

/// An orthographic or pinhole camera in the model frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Focal length (pixels); `None` for an orthographic camera.
    pub focal_length_px: Option<f64>,
    /// Principal point (model frame).
    pub principal_point: Vec2,
}

impl Camera {
    /// The orthographic camera.
    pub fn orthographic() -> Self {
        Self {
            focal_length_px: None,
            principal_point: Vec2::zeros(),
        }
    }

    /// A perspective camera of focal length `focal_length_px` and principal point
    /// `principal_point` (image pixels).
    pub fn perspective(focal_length_px: f64, principal_point: [f64; 2]) -> Self {
        Self {
            focal_length_px: Some(focal_length_px),
            principal_point: image_to_model(principal_point),
        }
    }

    /// The camera of an annotation's `camera` (validated) for an image of
    /// `width × height` pixels.
    ///
    /// # Errors
    /// [`PhotoError::Field`] on `camera` for a perspective camera without a focal length
    /// (none given, and none found in the photo's EXIF by the caller; [`crate::reconstruct`]
    /// estimates one from the drawing instead of calling this).
    pub fn from_spec(spec: &CameraSpec, width: u32, height: u32) -> Result<Self, PhotoError> {
        match spec.projection {
            Projection::Orthographic => Ok(Self::orthographic()),
            Projection::Perspective => {
                let centre = spec.principal_point_or_centre(width, height);
                let f = spec.focal_length(width, height).ok_or_else(|| {
                    PhotoError::field(
                        "camera",
                        "a perspective camera needs its focal length, and the photo's EXIF has none \
                         (FocalLengthIn35mmFilm): give focal_length_35mm (about 26 mm for a phone's main \
                         camera; `exiftool -FocalLengthIn35mmFormat photo.jpg` on the original shows it) or \
                         focal_length_px",
                    )
                })?;
                Ok(Self::perspective(f, centre))
            }
        }
    }

    /// Whether the camera is orthographic.
    pub fn is_orthographic(&self) -> bool {
        self.focal_length_px.is_none()
    }

    /// The slope `a = (x̄ − c)/f` of the ray through the model-frame image point `x̄`:
    /// the points `P` seen at `x̄` are those with `P_xy + a Z = x̄` (zero for an
    /// orthographic camera).
    pub fn ray_slope(&self, image: Vec2) -> Vec2 {
        match self.focal_length_px {
            Some(f) => (image - self.principal_point) / f,
            None => Vec2::zeros(),
        }
    }

    /// The point seen at model-frame image point `image` at depth `z`.
    pub fn point_at_depth(&self, image: Vec2, z: f64) -> Vec3 {
        let p = image - self.ray_slope(image) * z;
        Vec3::new(p.x, p.y, z)
    }

    /// The perspective divisor `w = (f − Z)/f` of a depth (1 for an orthographic
    /// camera): the image magnifies the neighbourhood of the point by `1/w`.
    pub fn divisor(&self, z: f64) -> f64 {
        match self.focal_length_px {
            Some(f) => (f - z) / f,
            None => 1.0,
        }
    }

    /// Where a model-frame point is seen (model-frame image point). A point at or behind
    /// the centre of projection has no image; it is returned at the divisor's floor
    /// (`w = 1e-9`) so that the result stays finite.
    pub fn project(&self, p: Vec3) -> Vec2 {
        match self.focal_length_px {
            Some(_) => {
                let c = self.principal_point;
                let w = self.divisor(p.z).max(1e-9);
                c + (Vec2::new(p.x, p.y) - c) / w
            }
            None => Vec2::new(p.x, p.y),
        }
    }

    /// The unit image direction along which points moving along the 3D direction
    /// `direction` are seen near the model-frame image point `at` (the line through `at`
    /// and the direction's vanishing point). `None` when the direction is seen end-on
    /// at `at` (the point is its vanishing point).
    pub fn image_direction(&self, direction: Vec3, at: Vec2) -> Option<Vec2> {
        let d = match self.focal_length_px {
            Some(f) => Vec2::new(direction.x, direction.y) * f + (at - self.principal_point) * direction.z,
            None => Vec2::new(direction.x, direction.y),
        };
        let norm = d.norm();
        (norm > 1e-12 * direction.norm().max(1e-300) * self.focal_length_px.unwrap_or(1.0)).then(|| d / norm)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A point anywhere on the ray through an image point is seen there (the ray
    /// residual of the projection term is exact), and `1/w` is the local magnification.
    #[test]
    fn points_on_a_ray_project_to_its_image_point() {
        let camera = Camera::perspective(514.7, [240.0, 240.0]);
        let image = image_to_model([123.0, 401.5]);
        for z in [-150.0, -3.0, 0.0, 42.0, 300.0] {
            let p = camera.point_at_depth(image, z);
            let a = camera.ray_slope(image);
            assert!((Vec2::new(p.x, p.y) + a * z - image).norm() < 1e-12);
            assert!((camera.project(p) - image).norm() < 1e-9, "{z}");
            // Magnification: a small step dx at depth z is seen 1/w larger.
            let step = 1e-3;
            let q = camera.project(p + Vec3::new(step, 0.0, 0.0));
            let seen = (q - camera.project(p)).norm() / step;
            assert!((seen - 1.0 / camera.divisor(z)).abs() < 1e-6, "{seen}");
        }
    }

    /// The image direction of a 3D direction is the tangent of the image of a line along
    /// it (finite differences), and the orthographic camera sees it as its `xy` part.
    #[test]
    fn image_directions_follow_projected_lines() {
        let camera = Camera::perspective(400.0, [200.0, 150.0]);
        let n = Vec3::new(0.6, -0.3, -0.74).normalize();
        for p in [
            Vec3::new(10.0, -40.0, 20.0),
            Vec3::new(320.0, -260.0, -90.0),
            Vec3::new(200.0, -150.0, 0.0),
        ] {
            let at = camera.project(p);
            let ahead = camera.project(p + n * 1e-4);
            let expected = (ahead - at).normalize();
            let got = camera.image_direction(n, at).unwrap();
            assert!((got.dot(&expected).abs() - 1.0).abs() < 1e-8, "{got} {expected}");
        }
        let ortho = Camera::orthographic();
        let d = ortho.image_direction(n, Vec2::new(5.0, 5.0)).unwrap();
        assert!((d - Vec2::new(n.x, n.y).normalize()).norm() < 1e-15);
        assert!(ortho.image_direction(Vec3::z(), Vec2::zeros()).is_none());
    }
}

use crate::Vec3;
use nalgebra::{Matrix3, Rotation3, Unit};

/// A rigid motion `x ↦ R x + t` of 3D space (`R` a rotation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidMotion {
    /// The rotation `R`.
    pub rotation: Matrix3<f64>,
    /// The translation `t`.
    pub translation: Vec3,
}

impl Default for RigidMotion {
    fn default() -> Self {
        Self::identity()
    }
}

impl RigidMotion {
    /// The identity.
    pub fn identity() -> Self {
        Self {
            rotation: Matrix3::identity(),
            translation: Vec3::zeros(),
        }
    }

    /// Builds `x ↦ R x + t`.
    pub fn new(rotation: Matrix3<f64>, translation: Vec3) -> Self {
        Self { rotation, translation }
    }

    /// Applies the motion to a point.
    pub fn apply(&self, x: &Vec3) -> Vec3 {
        self.rotation * x + self.translation
    }

    /// Applies the rotation only (to a direction).
    pub fn apply_vector(&self, v: &Vec3) -> Vec3 {
        self.rotation * v
    }

    /// `self ∘ other`: first `other`, then `self`.
    pub fn compose(&self, other: &RigidMotion) -> RigidMotion {
        RigidMotion {
            rotation: self.rotation * other.rotation,
            translation: self.rotation * other.translation + self.translation,
        }
    }

    /// The inverse motion `x ↦ Rᵀ (x − t)`.
    pub fn inverse(&self) -> RigidMotion {
        let rt = self.rotation.transpose();
        RigidMotion {
            rotation: rt,
            translation: -(rt * self.translation),
        }
    }

    /// Largest displacement between the images of `points` under `self` and `other`.
    pub fn max_difference(&self, other: &RigidMotion, points: &[Vec3]) -> f64 {
        points
            .iter()
            .map(|p| (self.apply(p) - other.apply(p)).norm())
            .fold(0.0, f64::max)
    }
}

/// The rotation by `angle` (radians, right-hand rule) about the line through `point` with
/// direction `axis` (need not be unit), as a rigid motion. Rodrigues' formula.
pub fn rotation_about_axis(point: &Vec3, axis: &Vec3, angle: f64) -> RigidMotion {
    let r = Rotation3::from_axis_angle(&Unit::new_normalize(*axis), angle).into_inner();
    RigidMotion {
        rotation: r,
        translation: point - r * point,
    }
}

use crate::{curve::ParametricCurve, GeometryError};
use nalgebra::SVector;

/// A circular helix about the z axis (a circle when `rise_per_radian = 0`):
///
/// `h(θ) = (r cos θ, r sin θ, c θ)`, `θ ∈ [θ0, θ1]`,
///
/// with curvature `κ = r / (r² + c²)` and torsion `τ = c / (r² + c²)`. Derivatives of any
/// order are exact: `h⁽ᵏ⁾(θ) = (r cos(θ + kπ/2), r sin(θ + kπ/2), 0)` for `k ≥ 2`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Helix {
    /// Radius `r > 0`.
    pub radius: f64,
    /// Rise along z per radian, `c` (0 for a circle).
    pub rise_per_radian: f64,
    /// Start angle `θ0` (radians).
    pub start_angle: f64,
    /// End angle `θ1 > θ0` (radians).
    pub end_angle: f64,
}

impl Helix {
    /// Builds a helix.
    ///
    /// # Errors
    /// Non-positive or non-finite radius, empty angle range.
    pub fn new(radius: f64, rise_per_radian: f64, start_angle: f64, end_angle: f64) -> Result<Self, GeometryError> {
        if !(radius.is_finite() && radius > 0.0) {
            return Err(GeometryError::DegenerateCurve {
                reason: format!("helix radius must be positive, got {}", crate::short_number(radius)),
            });
        }
        if !(rise_per_radian.is_finite() && start_angle.is_finite() && end_angle.is_finite() && end_angle > start_angle)
        {
            return Err(GeometryError::DegenerateCurve {
                reason: "helix needs finite numbers and end_angle > start_angle".into(),
            });
        }
        Ok(Self {
            radius,
            rise_per_radian,
            start_angle,
            end_angle,
        })
    }
}

impl ParametricCurve<3> for Helix {
    fn domain(&self) -> (f64, f64) {
        (self.start_angle, self.end_angle)
    }

    fn derivatives_into(&self, u: f64, out: &mut [SVector<f64, 3>]) {
        let theta = u.clamp(self.start_angle, self.end_angle);
        for (k, slot) in out.iter_mut().enumerate() {
            let phase = theta + k as f64 * std::f64::consts::FRAC_PI_2;
            let (s, c) = phase.sin_cos();
            let z = match k {
                0 => self.rise_per_radian * theta,
                1 => self.rise_per_radian,
                _ => 0.0,
            };
            *slot = SVector::<f64, 3>::new(self.radius * c, self.radius * s, z);
        }
    }
}

//! The curve of regression of a rectifying developable (Bo & Wang 2007, §3.2).

/// Signed distance `l(s)` from the geodesic point to the curve of regression along the
/// ruling (Bo & Wang 2007, Eq. 4):
///
/// `l(s) = sin α(s) / α'(s)`,
///
/// where `α` is the angle from the tangent to the ruling (preserved by the isometry to the
/// flat sheet) and `α' = dα/ds`. Positive values lie on the ruling's positive side (the
/// flat sheet's left of the geodesic). Returns `±∞` where `α' = 0` (the neighbouring
/// rulings are parallel, as on a cylinder).
///
/// `α'` is computed exactly from curvature and torsion and their arc-length derivatives:
/// with the signed normal curvature `k` and torsion `τ`, `α = atan2(|k|, −sign(k) τ)`, so
/// `α' = (k τ' − k' τ) / (k² + τ²)`.
///
/// Units: lengths in the model unit, `k, τ` in 1/length, `k', τ'` in 1/length².
pub fn regression_distance(k: f64, tau: f64, dk: f64, dtau: f64, sin_alpha: f64) -> f64 {
    let w2 = k * k + tau * tau;
    if w2 == 0.0 {
        return f64::INFINITY;
    }
    let dalpha = (k * dtau - dk * tau) / w2;
    if dalpha == 0.0 {
        return f64::INFINITY;
    }
    let l = sin_alpha / dalpha;
    if l.is_finite() {
        l
    } else {
        f64::INFINITY.copysign(l)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cylinder_has_no_regression_point() {
        // Planar curve: τ = 0, α = π/2 everywhere, α' = 0.
        assert!(regression_distance(0.5, 0.0, 0.1, 0.0, 1.0).is_infinite());
    }

    #[test]
    fn sign_follows_alpha_derivative() {
        let l = regression_distance(1.0, 0.5, 0.0, 0.2, 0.8);
        assert!((l - 0.8 / (0.2 / 1.25)).abs() < 1e-12);
    }
}

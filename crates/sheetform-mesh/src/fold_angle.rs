//! The signed dihedral (fold) angle across an edge shared by two triangles, and its exact
//! gradient with respect to the four points.

use nalgebra::Vector3;

type Vec3 = Vector3<f64>;

/// Signed dihedral fold angle (radians) across the edge `a → b` shared by triangles
/// `(a, b, c)` and `(b, a, d)`: positive when the surface bends away from the side the
/// normals point to (a mountain seen from that side), negative for a valley, 0 when flat
/// or when a triangle is degenerate.
///
/// `θ = atan2((n₁ × n₂)·ê, n₁·n₂)` with `n₁ = (b − a) × (c − a)`, `n₂ = (a − b) × (d − b)`,
/// `ê = (b − a)/|b − a|`: the angle from the first normal to the second about the edge.
pub fn signed_fold_angle([a, b, c, d]: [Vec3; 4]) -> f64 {
    let n1 = (b - a).cross(&(c - a));
    let n2 = (a - b).cross(&(d - b));
    let (l1, l2) = (n1.norm(), n2.norm());
    if l1 == 0.0 || l2 == 0.0 {
        return 0.0;
    }
    let (n1, n2) = (n1 / l1, n2 / l2);
    let e = (b - a).normalize();
    n1.cross(&n2).dot(&e).atan2(n1.dot(&n2))
}

/// The gradients of [`signed_fold_angle`] with respect to `[a, b, c, d]` (radians per
/// length unit); zero for a degenerate triangle. They sum to zero (a translation does not
/// fold).
///
/// Bridson, Marino & Fedkiw, "Simulation of clothing with folds and wrinkles" (SCA 2003,
/// §4), written with the normals above (`n₁ = (c − a) × (c − b)`, `n₂ = (d − b) × (d − a)`,
/// the same vectors), `e = b − a`, `ê = e/|e|`:
///
/// `∇_cθ = −|e| n₁/|n₁|²`, `∇_dθ = −|e| n₂/|n₂|²`,
/// `∇_aθ = −((c − b)·ê) n₁/|n₁|² − ((d − b)·ê) n₂/|n₂|²`,
/// `∇_bθ = ((c − a)·ê) n₁/|n₁|² + ((d − a)·ê) n₂/|n₂|²`
///
/// (the paper's formulas are for the unsigned angle; the common sign here is the one of
/// [`signed_fold_angle`], checked against finite differences in the tests).
pub fn signed_fold_angle_gradients([a, b, c, d]: [Vec3; 4]) -> [Vec3; 4] {
    let edge = b - a;
    let length = edge.norm();
    let n1 = (c - a).cross(&(c - b));
    let n2 = (d - b).cross(&(d - a));
    let (s1, s2) = (n1.norm_squared(), n2.norm_squared());
    if length == 0.0 || s1 == 0.0 || s2 == 0.0 {
        return [Vec3::zeros(); 4];
    }
    let (m1, m2) = (n1 / s1, n2 / s2);
    let unit = edge / length;
    [
        -(m1 * (c - b).dot(&unit) + m2 * (d - b).dot(&unit)),
        m1 * (c - a).dot(&unit) + m2 * (d - a).dot(&unit),
        -m1 * length,
        -m2 * length,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Mountain and valley signs, and 0 when flat.
    #[test]
    fn sign_follows_the_fold() {
        let (a, b, c) = (Vec3::zeros(), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.5, 1.0, 0.0));
        // Normals point to +z; d below the plane bends away from them: a mountain.
        let mountain = signed_fold_angle([a, b, c, Vec3::new(0.5, -1.0, -1.0)]);
        let valley = signed_fold_angle([a, b, c, Vec3::new(0.5, -1.0, 1.0)]);
        assert!((mountain - std::f64::consts::FRAC_PI_4).abs() < 1e-12, "{mountain}");
        assert!((valley + std::f64::consts::FRAC_PI_4).abs() < 1e-12, "{valley}");
        assert_eq!(signed_fold_angle([a, b, c, Vec3::new(0.5, -1.0, 0.0)]), 0.0);
    }

    /// The gradients are those of the angle itself (central differences), flat and
    /// folded either way, and sum to zero.
    #[test]
    fn gradients_match_finite_differences() {
        for (fold, skew) in [(0.0, 0.0), (0.4, 0.3), (-1.1, -0.2), (2.0, 0.7)] {
            let points = [
                Vec3::new(0.1, -0.2, 0.05),
                Vec3::new(1.3, 0.1, -0.1),
                Vec3::new(0.5 + skew, 1.0, 0.2),
                Vec3::new(0.7, -f64::cos(fold), f64::sin(fold)),
            ];
            let gradients = signed_fold_angle_gradients(points);
            let sum: Vec3 = gradients.iter().sum();
            assert!(sum.norm() < 1e-12, "{sum}");
            for k in 0..6 {
                let delta: [Vec3; 4] = std::array::from_fn(|i| {
                    let x = (k * 4 + i) as f64;
                    Vec3::new((0.7 * x).sin(), (1.3 * x + 0.5).cos(), (2.1 * x).sin())
                });
                let linear: f64 = gradients.iter().zip(&delta).map(|(g, d)| g.dot(d)).sum();
                let t = 1e-6;
                let moved = |s: f64| signed_fold_angle(std::array::from_fn(|i| points[i] + s * delta[i]));
                let difference = (moved(t) - moved(-t)) / (2.0 * t);
                assert!(
                    (linear - difference).abs() < 1e-7 * (1.0 + difference.abs()),
                    "fold {fold}: {linear} vs {difference}"
                );
            }
        }
    }
}

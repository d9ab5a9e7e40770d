//! A triangle's corner angle and its exact gradient.

use nalgebra::Vector3;

type Vec3 = Vector3<f64>;

/// The angle `θ = atan2(|u × v|, u · v)` at corner `a` of triangle `(a, b, c)`, with
/// `u = b − a`, `v = c − a` (radians; accurate for every angle).
pub fn corner_angle(a: Vec3, b: Vec3, c: Vec3) -> f64 {
    let (u, v) = (b - a, c - a);
    u.cross(&v).norm().atan2(u.dot(&v))
}

/// The angle `θ` at corner `a` of triangle `(a, b, c)` (radians) and its gradient with
/// respect to `a`, `b` and `c` (radians per length unit).
///
/// With `u = b − a`, `v = c − a` and the unit normal `n = u × v / |u × v|`:
/// `θ = atan2(|u × v|, u · v)`, `∂θ/∂b = −(n × u) / |u|²`, `∂θ/∂c = (n × v) / |v|²` and
/// `∂θ/∂a = −(∂θ/∂b + ∂θ/∂c)` (moving `b` within the plane towards `c` closes the angle;
/// motion along `n` does not change it to first order). These give the exact gradient of
/// the vertex developability `g(q_i) = 2π − Σ_j θ_j` (Wang & Tang 2004, Eq. 2-4) that the
/// paper takes by central differences. A degenerate corner (`|u × v| = 0`) has no
/// gradient; zero is returned there.
pub fn corner_angle_gradient(a: Vec3, b: Vec3, c: Vec3) -> (f64, [Vec3; 3]) {
    let (u, v) = (b - a, c - a);
    let cross = u.cross(&v);
    let s = cross.norm();
    let angle = s.atan2(u.dot(&v));
    if s == 0.0 {
        return (angle, [Vec3::zeros(); 3]);
    }
    let n = cross / s;
    let db = -n.cross(&u) / u.norm_squared();
    let dc = n.cross(&v) / v.norm_squared();
    (angle, [-(db + dc), db, dc])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gradient_matches_finite_differences() {
        let p = [
            Vec3::new(0.1, 0.2, 0.3),
            Vec3::new(1.3, -0.2, 0.4),
            Vec3::new(0.4, 0.9, -0.5),
        ];
        let (_, g) = corner_angle_gradient(p[0], p[1], p[2]);
        let h = 1e-6;
        for corner in 0..3 {
            for d in 0..3 {
                let (mut plus, mut minus) = (p, p);
                plus[corner][d] += h;
                minus[corner][d] -= h;
                let fd = (corner_angle_gradient(plus[0], plus[1], plus[2]).0
                    - corner_angle_gradient(minus[0], minus[1], minus[2]).0)
                    / (2.0 * h);
                assert!(
                    (fd - g[corner][d]).abs() < 1e-8,
                    "{corner} {d}: {fd} vs {}",
                    g[corner][d]
                );
            }
        }
    }
}

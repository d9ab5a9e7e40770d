//! A triangle's corner angle and its exact gradient.

use nalgebra::{Matrix3, Vector3};

type Vec3 = Vector3<f64>;

/// The angle `θ = atan2(|u × v|, u · v)` at corner `a` of triangle `(a, b, c)`, with
/// `u = b − a`, `v = c − a` (radians; accurate for every angle).
pub fn corner_angle(a: Vec3, b: Vec3, c: Vec3) -> f64 {
    let (u, v) = (b - a, c - a);
    u.cross(&v).norm().atan2(u.dot(&v))
}

/// Each vertex's angle sum `Σ θ` over the corners of `triangles` at it (radians; 0 for a
/// vertex no triangle uses): `2π` minus it is the vertex's angle defect.
pub fn vertex_angle_sums(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<f64> {
    let mut sums = vec![0.0; positions.len()];
    for t in triangles {
        let p = t.map(|v| positions[v as usize]);
        for k in 0..3 {
            sums[t[k] as usize] += corner_angle(p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
        }
    }
    sums
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

/// The angle `θ` at corner `a` of triangle `(a, b, c)` (radians), its gradient (radians
/// per length unit) and its Hessian (radians per length unit²) with respect to `a`, `b`,
/// `c`: `hessian[i][j] = ∂²θ / ∂p_i ∂p_j` (3×3 blocks).
///
/// Through the squared side lengths `x = |c − b|²` (opposite), `y = |c − a|²`,
/// `z = |b − a|²`. With `s = 4·area = 2|u × v|` and `D = y + z − x = 2 u·v`,
/// `E = x + z − y`, `F = x + y − z` (so `s² + D² = 4yz`, `s² + E² = 4xz`,
/// `s² + F² = 4xy`), `θ = atan2(s, D)` and
///
/// - `θ_x = 1/s`, `θ_y = −F/(2ys)`, `θ_z = −E/(2zs)`;
/// - `θ_xx = −D/s³`, `θ_xy = −E/s³`, `θ_xz = −F/s³`, `θ_yz = 2x/s³`,
///   `θ_yy = −1/(2ys) + F/(2y²s) + EF/(2ys³)`, `θ_zz = −1/(2zs) + E/(2z²s) + EF/(2zs³)`.
///
/// The chain rule to positions is exact and simple because squared lengths are
/// quadratic: `∇²θ = Σ θ_pq ∇p ∇qᵀ + Σ θ_p ∇²p` with `∇²|c − b|² = 2[I −I; −I I]` on
/// `(b, c)`. This gives the constraints' curvature `Σ λ ∇²g` of a Newton (SQP) step on
/// the Lagrangian; the paper uses no second derivatives. A degenerate corner (`s = 0`)
/// has none: zeros are returned.
pub fn corner_angle_hessian(a: Vec3, b: Vec3, c: Vec3) -> (f64, [Vec3; 3], [[Matrix3<f64>; 3]; 3]) {
    let (u, v, w) = (b - a, c - a, c - b);
    let (x, y, z) = (w.norm_squared(), v.norm_squared(), u.norm_squared());
    let s = 2.0 * u.cross(&v).norm();
    let d = 2.0 * u.dot(&v);
    let angle = s.atan2(d);
    let zero = [[Matrix3::zeros(); 3]; 3];
    if s == 0.0 || y == 0.0 || z == 0.0 {
        return (angle, [Vec3::zeros(); 3], zero);
    }
    let (e, f) = (x + z - y, x + y - z);
    let s3 = s * s * s;
    let first = [1.0 / s, -f / (2.0 * y * s), -e / (2.0 * z * s)];
    let second = [
        [-d / s3, -e / s3, -f / s3],
        [
            -e / s3,
            -1.0 / (2.0 * y * s) + f / (2.0 * y * y * s) + e * f / (2.0 * y * s3),
            2.0 * x / s3,
        ],
        [
            -f / s3,
            2.0 * x / s3,
            -1.0 / (2.0 * z * s) + e / (2.0 * z * z * s) + e * f / (2.0 * z * s3),
        ],
    ];
    // Gradients of x, y, z with respect to a, b, c.
    let zero3 = Vec3::zeros();
    let grads = [
        [zero3, -2.0 * w, 2.0 * w],
        [-2.0 * v, zero3, 2.0 * v],
        [-2.0 * u, 2.0 * u, zero3],
    ];
    // The corner pairs each squared length joins ((b, c), (a, c), (a, b)).
    let ends = [[1, 2], [0, 2], [0, 1]];
    let mut gradient = [Vec3::zeros(); 3];
    let mut hessian = zero;
    for p in 0..3 {
        for i in 0..3 {
            gradient[i] += first[p] * grads[p][i];
        }
    }
    for i in 0..3 {
        for j in 0..3 {
            let mut block = Matrix3::zeros();
            for p in 0..3 {
                for q in 0..3 {
                    block += second[p][q] * grads[p][i] * grads[q][j].transpose();
                }
            }
            hessian[i][j] = block;
        }
    }
    for (p, [i, j]) in ends.into_iter().enumerate() {
        let diagonal = Matrix3::identity() * (2.0 * first[p]);
        hessian[i][i] += diagonal;
        hessian[j][j] += diagonal;
        hessian[i][j] -= diagonal;
        hessian[j][i] -= diagonal;
    }
    (angle, gradient, hessian)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hessian_matches_finite_differences_of_the_gradient() {
        for p in [
            [
                Vec3::new(0.1, 0.2, 0.3),
                Vec3::new(1.3, -0.2, 0.4),
                Vec3::new(0.4, 0.9, -0.5),
            ],
            // An obtuse corner.
            [
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.1, 0.0),
                Vec3::new(-0.8, 0.3, 0.2),
            ],
        ] {
            let (angle, gradient, hessian) = corner_angle_hessian(p[0], p[1], p[2]);
            let (expected_angle, expected_gradient) = corner_angle_gradient(p[0], p[1], p[2]);
            assert!((angle - expected_angle).abs() < 1e-14);
            for i in 0..3 {
                assert!((gradient[i] - expected_gradient[i]).norm() < 1e-12, "gradient {i}");
            }
            let h = 1e-6;
            for j in 0..3 {
                for l in 0..3 {
                    let (mut plus, mut minus) = (p, p);
                    plus[j][l] += h;
                    minus[j][l] -= h;
                    let gp = corner_angle_gradient(plus[0], plus[1], plus[2]).1;
                    let gm = corner_angle_gradient(minus[0], minus[1], minus[2]).1;
                    for i in 0..3 {
                        let fd = (gp[i] - gm[i]) / (2.0 * h);
                        let exact = hessian[i][j].column(l);
                        assert!((fd - exact).norm() < 1e-7, "block {i} {j} column {l}: {fd} vs {exact}");
                    }
                }
            }
        }
    }

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

//! Cubic Bézier segments on fixed-size arrays: the Bernstein weights every step uses to
//! write a point on a curve as a linear combination of its four control points (§6.1:
//! sample points are "affine combinations of the Bézier control points"), and the
//! evaluations of the hot loops. Splitting and arc length: `sheetform_geometry::Bezier`.

use nalgebra::{SVector, Vector2};

type Vec2 = Vector2<f64>;

/// Bernstein weights `B_i(t) = C(3,i) tⁱ (1−t)³⁻ⁱ`, `i = 0 … 3`.
pub fn bernstein(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    [s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t]
}

/// Derivative weights `dB_i/dt`.
pub fn bernstein_derivative(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    [
        -3.0 * s * s,
        3.0 * s * s - 6.0 * s * t,
        6.0 * s * t - 3.0 * t * t,
        3.0 * t * t,
    ]
}

/// Second-derivative weights `d²B_i/dt²`.
pub fn bernstein_second_derivative(t: f64) -> [f64; 4] {
    [6.0 * (1.0 - t), 6.0 * (3.0 * t - 2.0), 6.0 * (1.0 - 3.0 * t), 6.0 * t]
}

/// Point of a cubic at `t`.
pub fn point<const D: usize>(b: &[SVector<f64, D>; 4], t: f64) -> SVector<f64, D> {
    let w = bernstein(t);
    b[0] * w[0] + b[1] * w[1] + b[2] * w[2] + b[3] * w[3]
}

/// Derivative of a cubic at `t`.
pub fn derivative<const D: usize>(b: &[SVector<f64, D>; 4], t: f64) -> SVector<f64, D> {
    let w = bernstein_derivative(t);
    b[0] * w[0] + b[1] * w[1] + b[2] * w[2] + b[3] * w[3]
}

/// A polyline of `pieces + 1` points at uniform parameters.
pub fn polyline(b: &[Vec2; 4], pieces: usize) -> Vec<Vec2> {
    (0..=pieces).map(|i| point(b, i as f64 / pieces as f64)).collect()
}

/// Length of the control polygon (an upper bound of the arc length).
pub fn hull_length(b: &[Vec2; 4]) -> f64 {
    (b[1] - b[0]).norm() + (b[2] - b[1]).norm() + (b[3] - b[2]).norm()
}

/// Parameter at which a cubic is nearest to `p`: the best of a coarse scan, refined by
/// Newton's method on `(B(t) − p)·B'(t) = 0`, clamped to `[0, 1]`. Returns `(t, distance)`.
pub fn nearest_parameter(b: &[Vec2; 4], p: Vec2) -> (f64, f64) {
    let mut best = (0.0, f64::INFINITY);
    for i in 0..=32 {
        let t = i as f64 / 32.0;
        let d = (point(b, t) - p).norm();
        if d < best.1 {
            best = (t, d);
        }
    }
    let mut t = best.0;
    for _ in 0..20 {
        let q = point(b, t) - p;
        let d1 = derivative(b, t);
        let w = bernstein_second_derivative(t);
        let t2 = b[0] * w[0] + b[1] * w[1] + b[2] * w[2] + b[3] * w[3];
        let g = q.dot(&d1);
        let h = d1.dot(&d1) + q.dot(&t2);
        if h <= 0.0 {
            break;
        }
        let next = (t - g / h).clamp(0.0, 1.0);
        if (next - t).abs() < 1e-15 {
            t = next;
            break;
        }
        t = next;
    }
    let d = (point(b, t) - p).norm();
    if d < best.1 {
        (t, d)
    } else {
        best
    }
}

/// A root of `f` in `[lo, hi]` by bisection (60 halvings: to the last bit of a unit
/// interval), or `None` when `f` has the same sign at both ends.
pub fn bisect(f: impl Fn(f64) -> f64, lo: f64, hi: f64) -> Option<f64> {
    let (mut lo, mut hi) = (lo, hi);
    let (mut flo, fhi) = (f(lo), f(hi));
    if flo * fhi > 0.0 || (flo == fhi && flo != 0.0) {
        return None;
    }
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        let fm = f(mid);
        if fm * flo <= 0.0 {
            hi = mid;
        } else {
            lo = mid;
            flo = fm;
        }
    }
    Some(0.5 * (lo + hi))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> [Vec2; 4] {
        [
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 2.0),
            Vec2::new(3.0, 2.5),
            Vec2::new(4.0, -1.0),
        ]
    }

    #[test]
    fn bernstein_weights_form_a_partition_of_unity_and_differentiate() {
        for i in 0..=10 {
            let t = i as f64 / 10.0;
            let w = bernstein(t);
            assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-15);
            let d = bernstein_derivative(t);
            let h = 1e-6;
            let (a, b) = (bernstein(t - h), bernstein(t + h));
            let (da, db) = (bernstein_derivative(t - h), bernstein_derivative(t + h));
            let d2 = bernstein_second_derivative(t);
            for k in 0..4 {
                assert!((d[k] - (b[k] - a[k]) / (2.0 * h)).abs() < 1e-8);
                assert!((d2[k] - (db[k] - da[k]) / (2.0 * h)).abs() < 1e-7);
            }
        }
    }

    #[test]
    fn nearest_parameter_finds_a_point_on_the_curve() {
        let b = sample();
        let p = point(&b, 0.62);
        let normal = {
            let d = derivative(&b, 0.62);
            Vec2::new(-d.y, d.x).normalize()
        };
        let (t, d) = nearest_parameter(&b, p + normal * 0.05);
        assert!((t - 0.62).abs() < 1e-6, "{t}");
        assert!((d - 0.05).abs() < 1e-9);
    }
}

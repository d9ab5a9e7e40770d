//! Cubic Bézier segments: the Bernstein weights every step uses to write a point on a
//! curve as a linear combination of its four control points (§6.1: sample points are
//! "affine combinations of the Bézier control points"), and de Casteljau subdivision
//! (§5.1: curves are split at their intersections without changing their shape).

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

/// De Casteljau subdivision at `t`: the two cubics covering `[0, t]` and `[t, 1]`.
pub fn split<const D: usize>(b: &[SVector<f64, D>; 4], t: f64) -> ([SVector<f64, D>; 4], [SVector<f64, D>; 4]) {
    let lerp = |p: SVector<f64, D>, q: SVector<f64, D>| p + (q - p) * t;
    let (p01, p12, p23) = (lerp(b[0], b[1]), lerp(b[1], b[2]), lerp(b[2], b[3]));
    let (p012, p123) = (lerp(p01, p12), lerp(p12, p23));
    let m = lerp(p012, p123);
    ([b[0], p01, p012, m], [m, p123, p23, b[3]])
}

/// A polyline of `pieces + 1` points at uniform parameters.
pub fn polyline(b: &[Vec2; 4], pieces: usize) -> Vec<Vec2> {
    (0..=pieces).map(|i| point(b, i as f64 / pieces as f64)).collect()
}

/// Length of the control polygon (an upper bound of the arc length).
pub fn hull_length(b: &[Vec2; 4]) -> f64 {
    (b[1] - b[0]).norm() + (b[2] - b[1]).norm() + (b[3] - b[2]).norm()
}

/// Arc length by 16-point composite Simpson rule on `|B'(t)|` (ample for the smooth
/// segments of a tracing; used for sampling, not for geometry that must be exact).
pub fn arc_length(b: &[Vec2; 4], t0: f64, t1: f64) -> f64 {
    let n = 16;
    let h = (t1 - t0) / n as f64;
    let f = |t: f64| derivative(b, t).norm();
    let mut sum = f(t0) + f(t1);
    for i in 1..n {
        sum += f(t0 + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    sum * h / 3.0
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
    fn splitting_keeps_the_curve() {
        let b = sample();
        let (l, r) = split(&b, 0.3);
        for i in 0..=10 {
            let s = i as f64 / 10.0;
            assert!((point(&l, s) - point(&b, 0.3 * s)).norm() < 1e-13);
            assert!((point(&r, s) - point(&b, 0.3 + 0.7 * s)).norm() < 1e-13);
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

    #[test]
    fn arc_length_of_a_straight_cubic() {
        let b = [
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(2.0, 0.0),
            Vec2::new(3.0, 0.0),
        ];
        assert!((arc_length(&b, 0.0, 1.0) - 3.0).abs() < 1e-12);
    }
}

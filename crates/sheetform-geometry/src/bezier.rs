use crate::{curve::ParametricCurve, GeometryError};
use nalgebra::SVector;

/// A Bézier curve of any degree `n ≥ 1` in `D` dimensions, on `t ∈ [0, 1]`.
///
/// `P(t) = Σ_{i=0}^{n} P_i B_{i,n}(t)`, `B_{i,n}(t) = C(n,i) tⁱ (1−t)^{n−i}`.
/// The k-th derivative is the Bézier curve of degree `n−k` whose control points are
/// `n!/(n−k)! · Δ^k P_i` (the hodograph, Farin 2002, §5.3); those nets are computed once
/// at construction, so every derivative is exact and evaluation does not allocate.
#[derive(Debug, Clone, PartialEq)]
pub struct Bezier<const D: usize> {
    /// `nets[k]` = control points of the k-th derivative (`nets[0]` = the curve).
    nets: Vec<Vec<SVector<f64, D>>>,
}

/// Highest degree of a [`Bezier`] curve: its derivative nets hold about `n²/2` points
/// and each evaluation costs about `n²` (8 000 control points took 88 s and 860 MB).
pub const MAX_BEZIER_DEGREE: usize = 64;

/// A planar Bézier curve.
pub type Bezier2 = Bezier<2>;
/// A space Bézier curve.
pub type Bezier3 = Bezier<3>;

impl<const D: usize> Bezier<D> {
    /// Builds the curve from its `n + 1` control points.
    ///
    /// # Errors
    /// Fewer than two points, more than `MAX_BEZIER_DEGREE + 1`, or a non-finite
    /// coordinate.
    pub fn new(control_points: Vec<SVector<f64, D>>) -> Result<Self, GeometryError> {
        if control_points.len() < 2 {
            return Err(GeometryError::TooFewControlPoints {
                degree: control_points.len().saturating_sub(1),
                needed: 2,
                got: control_points.len(),
            });
        }
        if control_points.len() - 1 > MAX_BEZIER_DEGREE {
            return Err(GeometryError::BadDegree {
                degree: control_points.len() - 1,
                reason: format!(
                    "a Bézier curve has at most {} control points (degree {MAX_BEZIER_DEGREE}; its derivatives cost the \
                     square of the count); use a B-spline (`bspline`) for more",
                    MAX_BEZIER_DEGREE + 1
                ),
            });
        }
        for (index, p) in control_points.iter().enumerate() {
            if p.iter().any(|c| !c.is_finite()) {
                return Err(GeometryError::NonFinite {
                    what: "Bézier control point".into(),
                    index,
                });
            }
        }
        let mut nets = vec![control_points];
        loop {
            let last = nets.last().expect("non-empty");
            if last.len() < 2 {
                break;
            }
            let m = (last.len() - 1) as f64;
            let next: Vec<_> = last.windows(2).map(|w| (w[1] - w[0]) * m).collect();
            nets.push(next);
        }
        Ok(Self { nets })
    }

    /// The degree `n`.
    pub fn degree(&self) -> usize {
        self.nets[0].len() - 1
    }

    /// The control points `P_0 … P_n`.
    pub fn control_points(&self) -> &[SVector<f64, D>] {
        &self.nets[0]
    }

    /// Splits at `t` by de Casteljau's algorithm into the pieces on `[0, t]` and `[t, 1]`,
    /// each reparametrised to `[0, 1]`. Exact (no approximation).
    pub fn split(&self, t: f64) -> (Self, Self) {
        let p = self.control_points();
        let n = p.len();
        let mut work = p.to_vec();
        let mut left = Vec::with_capacity(n);
        let mut right = Vec::with_capacity(n);
        left.push(work[0]);
        right.push(work[n - 1]);
        for level in 1..n {
            for i in 0..n - level {
                work[i] = work[i] * (1.0 - t) + work[i + 1] * t;
            }
            left.push(work[0]);
            right.push(work[n - 1 - level]);
        }
        right.reverse();
        (
            Self::new(left).expect("split of a valid curve is valid"),
            Self::new(right).expect("split of a valid curve is valid"),
        )
    }

    /// The piece on `[t0, t1]` reparametrised to `[0, 1]` (exact).
    pub fn segment(&self, t0: f64, t1: f64) -> Self {
        let (_, tail) = self.split(t0);
        if (1.0 - t0).abs() < f64::EPSILON {
            return tail;
        }
        let (head, _) = tail.split(((t1 - t0) / (1.0 - t0)).clamp(0.0, 1.0));
        head
    }

    /// The same curve with control point `index` moved to `point`.
    ///
    /// # Panics
    /// `index` out of range.
    pub fn with_point(&self, index: usize, point: SVector<f64, D>) -> Self {
        let mut pts = self.control_points().to_vec();
        pts[index] = point;
        Self::new(pts).expect("a finite point keeps the curve valid")
    }

    /// Moves every control point by `offset`.
    pub fn translated(&self, offset: SVector<f64, D>) -> Self {
        Self::new(self.control_points().iter().map(|p| p + offset).collect())
            .expect("translation keeps a valid curve valid")
    }
}

impl<const D: usize> ParametricCurve<D> for Bezier<D> {
    fn domain(&self) -> (f64, f64) {
        (0.0, 1.0)
    }

    /// One pass of the Bernstein triangle `B_{i,m}(t)`, `m = 0 … n`: the k-th derivative is
    /// `Σ_i Q^k_i B_{i,n−k}(t)` with `Q^k` the k-th hodograph net, so all requested
    /// derivatives come from rows `n, n−1, …` of the same triangle (no allocation for
    /// degree ≤ 15, the usual range; higher degrees allocate one row).
    fn derivatives_into(&self, u: f64, out: &mut [SVector<f64, D>]) {
        let t = u.clamp(0.0, 1.0);
        let n = self.degree();
        for slot in out.iter_mut() {
            *slot = SVector::zeros();
        }
        let mut stack = [0.0f64; 17];
        let mut heap = Vec::new();
        let row: &mut [f64] = if n < 17 {
            &mut stack[..=n]
        } else {
            heap.resize(n + 1, 0.0);
            &mut heap
        };
        row[0] = 1.0;
        for m in 0..=n {
            if m > 0 {
                // B_{i,m} = (1−t) B_{i,m−1} + t B_{i−1,m−1}, updated in place from the end.
                row[m] = t * row[m - 1];
                for i in (1..m).rev() {
                    row[i] = (1.0 - t) * row[i] + t * row[i - 1];
                }
                row[0] *= 1.0 - t;
            }
            let k = n - m;
            if k < out.len() {
                let net = &self.nets[k];
                let mut acc = SVector::<f64, D>::zeros();
                for (p, b) in net.iter().zip(row.iter()) {
                    acc += p * *b;
                }
                out[k] = acc;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    fn sample() -> Bezier3 {
        Bezier3::new(vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 2.0, 0.0),
            Vector3::new(3.0, 2.0, 1.0),
            Vector3::new(4.0, 0.0, 2.0),
            Vector3::new(5.0, -1.0, 0.5),
        ])
        .unwrap()
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let c = sample();
        let h = 1e-5;
        for &t in &[0.1, 0.37, 0.5, 0.93] {
            let d = c.derivatives4(t);
            for k in 0..4 {
                let fd = (c.derivatives4(t + h)[k] - c.derivatives4(t - h)[k]) / (2.0 * h);
                assert!(
                    (fd - d[k + 1]).norm() < 1e-5 * (1.0 + d[k + 1].norm()),
                    "order {}",
                    k + 1
                );
            }
        }
    }

    #[test]
    fn split_reproduces_the_curve() {
        let c = sample();
        let (a, b) = c.split(0.3);
        for i in 0..=10 {
            let s = i as f64 / 10.0;
            assert!((a.point(s) - c.point(0.3 * s)).norm() < 1e-13);
            assert!((b.point(s) - c.point(0.3 + 0.7 * s)).norm() < 1e-13);
        }
        let seg = c.segment(0.2, 0.7);
        assert!((seg.point(0.5) - c.point(0.45)).norm() < 1e-13);
    }

    #[test]
    fn rejects_bad_input() {
        assert!(Bezier3::new(vec![Vector3::zeros()]).is_err());
        assert!(Bezier3::new(vec![Vector3::zeros(), Vector3::new(f64::NAN, 0.0, 0.0)]).is_err());
    }
}

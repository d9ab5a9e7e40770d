use crate::{curve::ParametricCurve, BSplineBasis, GeometryError};
use nalgebra::SVector;

/// A non-rational B-spline curve of degree `p` (cubic by default) in `D` dimensions.
///
/// `C(u) = Σ_i N_{i,p}(u) P_i` on `u ∈ [u_p, u_{m−p}]` for a non-decreasing knot vector
/// `u_0 … u_m`, `m = n + p + 1` for `n + 1` control points. Basis functions and their
/// derivatives are evaluated exactly by the Cox–de Boor recurrences (Piegl & Tiller,
/// *The NURBS Book*, 1997, Algorithms A2.1 and A2.3), without allocation.
#[derive(Debug, Clone, PartialEq)]
pub struct BSpline<const D: usize> {
    basis: BSplineBasis,
    control_points: Vec<SVector<f64, D>>,
}

/// A planar B-spline curve.
pub type BSpline2 = BSpline<2>;
/// A space B-spline curve.
pub type BSpline3 = BSpline<3>;

impl<const D: usize> BSpline<D> {
    /// Builds a B-spline from its degree, control points and full knot vector
    /// (`control_points.len() + degree + 1` knots, non-decreasing, interior multiplicity
    /// at most `degree`).
    ///
    /// # Errors
    /// Degree 0 or above [`crate::MAX_BSPLINE_DEGREE`], too few control points, wrong knot count,
    /// decreasing or non-finite knots, an empty parameter domain, non-finite points.
    pub fn new(degree: usize, control_points: Vec<SVector<f64, D>>, knots: Vec<f64>) -> Result<Self, GeometryError> {
        for (index, p) in control_points.iter().enumerate() {
            if p.iter().any(|c| !c.is_finite()) {
                return Err(GeometryError::NonFinite {
                    what: "B-spline control point".into(),
                    index,
                });
            }
        }
        let basis = BSplineBasis::new(degree, knots, control_points.len())?;
        Ok(Self { basis, control_points })
    }

    /// A clamped B-spline with uniformly spaced interior knots on `[0, 1]` (the curve
    /// interpolates its first and last control points).
    ///
    /// # Errors
    /// As [`BSpline::new`].
    pub fn clamped_uniform(degree: usize, control_points: Vec<SVector<f64, D>>) -> Result<Self, GeometryError> {
        let basis = BSplineBasis::clamped_uniform(degree, control_points.len())?;
        Self::new(degree, control_points, basis.knots().to_vec())
    }

    /// The degree `p`.
    pub fn degree(&self) -> usize {
        self.basis.degree()
    }

    /// The control points.
    pub fn control_points(&self) -> &[SVector<f64, D>] {
        &self.control_points
    }

    /// The full knot vector.
    pub fn knots(&self) -> &[f64] {
        self.basis.knots()
    }

    /// A copy with different control points (same degree and knots).
    ///
    /// # Errors
    /// As [`BSpline::new`].
    pub fn with_control_points(&self, points: Vec<SVector<f64, D>>) -> Result<Self, GeometryError> {
        Self::new(self.degree(), points, self.knots().to_vec())
    }

    /// The distinct knot values inside the domain (span boundaries), including both ends.
    pub fn breakpoints(&self) -> Vec<f64> {
        let (a, b) = self.domain();
        let mut out: Vec<f64> = vec![a];
        for &k in self.knots() {
            if k > a && k < b && k > *out.last().expect("non-empty") {
                out.push(k);
            }
        }
        out.push(b);
        out
    }
}

impl<const D: usize> ParametricCurve<D> for BSpline<D> {
    fn domain(&self) -> (f64, f64) {
        self.basis.domain()
    }

    fn derivatives_into(&self, u: f64, out: &mut [SVector<f64, D>]) {
        let p = self.basis.degree();
        let (span, ders) = self.basis.derivatives(u, out.len().saturating_sub(1));
        for (k, slot) in out.iter_mut().enumerate() {
            *slot = SVector::zeros();
            if k <= p {
                for (j, &n) in ders[k][..=p].iter().enumerate() {
                    *slot += self.control_points[span - p + j] * n;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Bezier3;
    use nalgebra::Vector3;

    #[test]
    fn single_span_equals_bezier() {
        let pts = vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 2.0, 0.5),
            Vector3::new(3.0, 2.0, 1.0),
            Vector3::new(4.0, 0.0, 2.0),
        ];
        let b = BSpline3::clamped_uniform(3, pts.clone()).unwrap();
        let z = Bezier3::new(pts).unwrap();
        for i in 0..=20 {
            let t = i as f64 / 20.0;
            let (db, dz) = (b.derivatives4(t), z.derivatives4(t));
            for k in 0..5 {
                assert!((db[k] - dz[k]).norm() < 1e-11, "t={t} order {k}");
            }
        }
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let pts: Vec<_> = (0..7)
            .map(|i| {
                let x = i as f64;
                Vector3::new(x, (x * 1.3).sin(), (x * 0.7).cos())
            })
            .collect();
        let b = BSpline3::clamped_uniform(3, pts).unwrap();
        let h = 1e-6;
        for &t in &[0.05, 0.33, 0.61, 0.9] {
            let d = b.derivatives4(t);
            for k in 0..3 {
                let fd = (b.derivatives4(t + h)[k] - b.derivatives4(t - h)[k]) / (2.0 * h);
                assert!(
                    (fd - d[k + 1]).norm() < 1e-4 * (1.0 + d[k + 1].norm()),
                    "order {}",
                    k + 1
                );
            }
        }
    }

    #[test]
    fn rejects_bad_knots() {
        let pts = vec![Vector3::zeros(), Vector3::x(), Vector3::y(), Vector3::z()];
        assert!(BSpline3::new(3, pts.clone(), vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.5, 1.0]).is_err());
        assert!(BSpline3::new(3, pts.clone(), vec![0.0; 7]).is_err());
        assert!(BSpline3::new(0, pts, vec![0.0; 5]).is_err());
    }
}

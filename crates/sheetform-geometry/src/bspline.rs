use crate::{curve::ParametricCurve, GeometryError};
use nalgebra::SVector;

/// Largest B-spline degree supported (evaluation uses fixed-size stack tables).
pub const MAX_BSPLINE_DEGREE: usize = 8;
const W: usize = MAX_BSPLINE_DEGREE + 1;

/// A non-rational B-spline curve of degree `p` (cubic by default) in `D` dimensions.
///
/// `C(u) = Σ_i N_{i,p}(u) P_i` on `u ∈ [u_p, u_{m−p}]` for a non-decreasing knot vector
/// `u_0 … u_m`, `m = n + p + 1` for `n + 1` control points. Basis functions and their
/// derivatives are evaluated exactly by the Cox–de Boor recurrences (Piegl & Tiller,
/// *The NURBS Book*, 1997, Algorithms A2.1 and A2.3), without allocation.
#[derive(Debug, Clone, PartialEq)]
pub struct BSpline<const D: usize> {
    degree: usize,
    control_points: Vec<SVector<f64, D>>,
    knots: Vec<f64>,
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
    /// Degree 0 or above [`MAX_BSPLINE_DEGREE`], too few control points, wrong knot count,
    /// decreasing or non-finite knots, an empty parameter domain, non-finite points.
    pub fn new(degree: usize, control_points: Vec<SVector<f64, D>>, knots: Vec<f64>) -> Result<Self, GeometryError> {
        if degree == 0 || degree > MAX_BSPLINE_DEGREE {
            return Err(GeometryError::BadDegree {
                degree,
                reason: format!("B-spline degree must be between 1 and {MAX_BSPLINE_DEGREE}"),
            });
        }
        if control_points.len() < degree + 1 {
            return Err(GeometryError::TooFewControlPoints {
                degree,
                needed: degree + 1,
                got: control_points.len(),
            });
        }
        for (index, p) in control_points.iter().enumerate() {
            if p.iter().any(|c| !c.is_finite()) {
                return Err(GeometryError::NonFinite {
                    what: "B-spline control point".into(),
                    index,
                });
            }
        }
        let expected = control_points.len() + degree + 1;
        if knots.len() != expected {
            return Err(GeometryError::BadKnots {
                reason: format!(
                    "{} control points of degree {degree} need {expected} knots, got {}",
                    control_points.len(),
                    knots.len()
                ),
            });
        }
        if let Some(i) = knots.iter().position(|k| !k.is_finite()) {
            return Err(GeometryError::BadKnots {
                reason: format!("knot {i} is not finite"),
            });
        }
        if let Some(i) = knots.windows(2).position(|w| w[1] < w[0]) {
            return Err(GeometryError::BadKnots {
                reason: format!("knots decrease at index {} ({} > {})", i + 1, knots[i], knots[i + 1]),
            });
        }
        let n = control_points.len();
        if knots[n] <= knots[degree] {
            return Err(GeometryError::BadKnots {
                reason: "the parameter domain [u_p, u_{n+1}] is empty".into(),
            });
        }
        Ok(Self {
            degree,
            control_points,
            knots,
        })
    }

    /// A clamped B-spline with uniformly spaced interior knots on `[0, 1]` (the curve
    /// interpolates its first and last control points).
    ///
    /// # Errors
    /// As [`BSpline::new`].
    pub fn clamped_uniform(degree: usize, control_points: Vec<SVector<f64, D>>) -> Result<Self, GeometryError> {
        let n = control_points.len();
        if n < degree + 1 {
            return Err(GeometryError::TooFewControlPoints {
                degree,
                needed: degree + 1,
                got: n,
            });
        }
        let spans = n - degree;
        let mut knots = vec![0.0; degree + 1];
        for i in 1..spans {
            knots.push(i as f64 / spans as f64);
        }
        knots.extend(std::iter::repeat_n(1.0, degree + 1));
        Self::new(degree, control_points, knots)
    }

    /// The degree `p`.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The control points.
    pub fn control_points(&self) -> &[SVector<f64, D>] {
        &self.control_points
    }

    /// The full knot vector.
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// A copy with different control points (same degree and knots).
    ///
    /// # Errors
    /// As [`BSpline::new`].
    pub fn with_control_points(&self, points: Vec<SVector<f64, D>>) -> Result<Self, GeometryError> {
        Self::new(self.degree, points, self.knots.clone())
    }

    /// The distinct knot values inside the domain (span boundaries), including both ends.
    pub fn breakpoints(&self) -> Vec<f64> {
        let (a, b) = self.domain();
        let mut out: Vec<f64> = vec![a];
        for &k in &self.knots {
            if k > a && k < b && k > *out.last().expect("non-empty") {
                out.push(k);
            }
        }
        out.push(b);
        out
    }

    /// Knot span index `i` with `u_i ≤ u < u_{i+1}` (A2.1), clamped to the domain.
    fn span(&self, u: f64) -> usize {
        let n = self.control_points.len() - 1;
        let p = self.degree;
        if u >= self.knots[n + 1] {
            // last non-empty span
            let mut i = n;
            while i > p && self.knots[i] >= self.knots[n + 1] {
                i -= 1;
            }
            return i;
        }
        if u <= self.knots[p] {
            let mut i = p;
            while self.knots[i + 1] <= self.knots[p] {
                i += 1;
            }
            return i;
        }
        let (mut low, mut high) = (p, n + 1);
        let mut mid = (low + high) / 2;
        while u < self.knots[mid] || u >= self.knots[mid + 1] {
            if u < self.knots[mid] {
                high = mid;
            } else {
                low = mid;
            }
            mid = (low + high) / 2;
        }
        mid
    }
}

impl<const D: usize> ParametricCurve<D> for BSpline<D> {
    fn domain(&self) -> (f64, f64) {
        (self.knots[self.degree], self.knots[self.control_points.len()])
    }

    // The index loops mirror Piegl & Tiller's Algorithm A2.3 line by line, so that the
    // kernel can be checked against the book.
    #[allow(clippy::needless_range_loop)]
    fn derivatives_into(&self, u: f64, out: &mut [SVector<f64, D>]) {
        let (a, b) = self.domain();
        let u = u.clamp(a, b);
        let p = self.degree;
        let span = self.span(u);
        let knots = &self.knots;
        let nder = (out.len().saturating_sub(1)).min(p);
        // A2.3: ndu holds basis functions (upper triangle) and knot differences (lower).
        let mut ndu = [[0.0f64; W]; W];
        let mut left = [0.0f64; W];
        let mut right = [0.0f64; W];
        ndu[0][0] = 1.0;
        for j in 1..=p {
            left[j] = u - knots[span + 1 - j];
            right[j] = knots[span + j] - u;
            let mut saved = 0.0;
            for r in 0..j {
                ndu[j][r] = right[r + 1] + left[j - r];
                let temp = ndu[r][j - 1] / ndu[j][r];
                ndu[r][j] = saved + right[r + 1] * temp;
                saved = left[j - r] * temp;
            }
            ndu[j][j] = saved;
        }
        let mut ders = [[0.0f64; W]; W];
        for j in 0..=p {
            ders[0][j] = ndu[j][p];
        }
        let mut a_tab = [[0.0f64; W]; 2];
        for r in 0..=p {
            let (mut s1, mut s2) = (0usize, 1usize);
            a_tab[0][0] = 1.0;
            for k in 1..=nder {
                let mut d = 0.0;
                let rk = r as isize - k as isize;
                let pk = p - k;
                if r >= k {
                    a_tab[s2][0] = a_tab[s1][0] / ndu[pk + 1][rk as usize];
                    d = a_tab[s2][0] * ndu[rk as usize][pk];
                }
                let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
                let j2 = if (r as isize - 1) <= pk as isize { k - 1 } else { p - r };
                for j in j1..=j2 {
                    let idx = (rk + j as isize) as usize;
                    a_tab[s2][j] = (a_tab[s1][j] - a_tab[s1][j - 1]) / ndu[pk + 1][idx];
                    d += a_tab[s2][j] * ndu[idx][pk];
                }
                if r <= pk {
                    a_tab[s2][k] = -a_tab[s1][k - 1] / ndu[pk + 1][r];
                    d += a_tab[s2][k] * ndu[r][pk];
                }
                ders[k][r] = d;
                std::mem::swap(&mut s1, &mut s2);
            }
        }
        let mut factor = p as f64;
        for k in 1..=nder {
            for j in 0..=p {
                ders[k][j] *= factor;
            }
            factor *= (p - k) as f64;
        }
        for (k, slot) in out.iter_mut().enumerate() {
            *slot = SVector::zeros();
            if k <= nder {
                for j in 0..=p {
                    *slot += self.control_points[span - p + j] * ders[k][j];
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

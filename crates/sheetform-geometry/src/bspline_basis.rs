use crate::GeometryError;

/// Largest B-spline degree supported (evaluation uses fixed-size stack tables).
pub const MAX_BSPLINE_DEGREE: usize = 8;
const W: usize = MAX_BSPLINE_DEGREE + 1;

/// Values and derivatives of the `p + 1` non-zero basis functions at one parameter:
/// `values[k][j]` is the `k`-th derivative of `N_{span−p+j, p}(u)`.
pub type BasisTable = [[f64; MAX_BSPLINE_DEGREE + 1]; MAX_BSPLINE_DEGREE + 1];

/// The B-spline basis of degree `p` over a knot vector `u_0 … u_m` for `n + 1` control
/// points (`m = n + p + 1`): knot spans and basis-function derivatives.
///
/// Shared by the B-spline curves and by the trivariate NURBS volume of the FFD (Wang &
/// Tang 2004 §2.1), so both evaluate their basis by the same checked code: Piegl &
/// Tiller, *The NURBS Book*, 1997, Algorithm A2.1 (span) and A2.3 (derivatives). The
/// parameter is unitless; a `k`-th derivative is per parameter unit to the power `k`.
#[derive(Debug, Clone, PartialEq)]
pub struct BSplineBasis {
    degree: usize,
    knots: Vec<f64>,
    count: usize,
}

impl BSplineBasis {
    /// Checks and stores a basis for `count` control points: degree between 1 and
    /// [`MAX_BSPLINE_DEGREE`], at least `degree + 1` control points, `count + degree + 1`
    /// finite non-decreasing knots and a non-empty domain `[u_p, u_{n+1}]`.
    ///
    /// # Errors
    /// [`GeometryError::BadDegree`], [`GeometryError::TooFewControlPoints`] or
    /// [`GeometryError::BadKnots`] saying what is wrong (and at which knot).
    pub fn new(degree: usize, knots: Vec<f64>, count: usize) -> Result<Self, GeometryError> {
        if degree == 0 || degree > MAX_BSPLINE_DEGREE {
            return Err(GeometryError::BadDegree {
                degree,
                reason: format!("B-spline degree must be between 1 and {MAX_BSPLINE_DEGREE}"),
            });
        }
        if count < degree + 1 {
            return Err(GeometryError::TooFewControlPoints {
                degree,
                needed: degree + 1,
                got: count,
            });
        }
        let expected = count + degree + 1;
        if knots.len() != expected {
            return Err(GeometryError::BadKnots {
                reason: format!(
                    "{count} control points of degree {degree} need {expected} knots, got {}",
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
        if knots[count] <= knots[degree] {
            return Err(GeometryError::BadKnots {
                reason: "the parameter domain [u_p, u_{n+1}] is empty".into(),
            });
        }
        Ok(Self { degree, knots, count })
    }

    /// Clamped knots with uniformly spaced interior knots on `[0, 1]` for `count` control
    /// points (the first and last control points are interpolated).
    ///
    /// # Errors
    /// As [`BSplineBasis::new`].
    pub fn clamped_uniform(degree: usize, count: usize) -> Result<Self, GeometryError> {
        if count < degree + 1 {
            return Err(GeometryError::TooFewControlPoints {
                degree,
                needed: degree + 1,
                got: count,
            });
        }
        let spans = count - degree;
        let mut knots = vec![0.0; degree + 1];
        for i in 1..spans {
            knots.push(i as f64 / spans as f64);
        }
        knots.extend(std::iter::repeat_n(1.0, degree + 1));
        Self::new(degree, knots, count)
    }

    /// The degree `p`.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The full knot vector.
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// Number of control points (basis functions).
    pub fn count(&self) -> usize {
        self.count
    }

    /// The parameter domain `[u_p, u_{n+1}]`.
    pub fn domain(&self) -> (f64, f64) {
        (self.knots[self.degree], self.knots[self.count])
    }

    /// Greville abscissa of control point `i`: `(u_{i+1} + … + u_{i+p}) / p`, the
    /// parameter a control point "belongs" to (a B-spline with control points
    /// `P_i = a + b ξ_i` is the straight line `a + b u`).
    pub fn greville(&self, i: usize) -> f64 {
        self.knots[i + 1..=i + self.degree].iter().sum::<f64>() / self.degree as f64
    }

    /// Knot span index `i` with `u_i ≤ u < u_{i+1}` (A2.1), clamped to the domain; the
    /// basis functions non-zero at `u` are `N_{i−p} … N_i`.
    pub fn span(&self, u: f64) -> usize {
        let n = self.count - 1;
        let p = self.degree;
        let knots = &self.knots;
        if u >= knots[n + 1] {
            let mut i = n;
            while i > p && knots[i] >= knots[n + 1] {
                i -= 1;
            }
            return i;
        }
        if u <= knots[p] {
            let mut i = p;
            while knots[i + 1] <= knots[p] {
                i += 1;
            }
            return i;
        }
        let (mut low, mut high) = (p, n + 1);
        let mut mid = (low + high) / 2;
        while u < knots[mid] || u >= knots[mid + 1] {
            if u < knots[mid] {
                high = mid;
            } else {
                low = mid;
            }
            mid = (low + high) / 2;
        }
        mid
    }

    /// Basis functions and their derivatives up to order `derivatives` (at most `p`;
    /// higher orders are zero) at `u` clamped to the domain (A2.3). Returns the span and
    /// the table `ders[k][j] = d^k N_{span−p+j,p} / du^k`.
    // The index loops mirror Piegl & Tiller's Algorithm A2.3 line by line, so that the
    // kernel can be checked against the book.
    #[allow(clippy::needless_range_loop)]
    pub fn derivatives(&self, u: f64, derivatives: usize) -> (usize, BasisTable) {
        let (a, b) = self.domain();
        let u = u.clamp(a, b);
        let p = self.degree;
        let span = self.span(u);
        let knots = &self.knots;
        let nder = derivatives.min(p);
        // ndu holds basis functions (upper triangle) and knot differences (lower).
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
        (span, ders)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn partition_of_unity_and_derivatives_sum_to_zero() {
        let basis = BSplineBasis::new(3, vec![0.0, 0.0, 0.0, 0.0, 0.3, 0.3, 0.7, 1.0, 1.0, 1.0, 1.0], 7).unwrap();
        for s in 0..=50 {
            let u = s as f64 / 50.0;
            let (span, d) = basis.derivatives(u, 2);
            assert!((d[0][..4].iter().sum::<f64>() - 1.0).abs() < 1e-14);
            assert!(d[1][..4].iter().sum::<f64>().abs() < 1e-11);
            assert!((3..=6).contains(&span));
        }
        // Greville abscissae of a clamped basis start at 0 and end at 1.
        let clamped = BSplineBasis::clamped_uniform(2, 5).unwrap();
        assert_eq!(clamped.greville(0), 0.0);
        assert_eq!(clamped.greville(4), 1.0);
    }
}

//! The trivariate NURBS volume `Q(u, v, w)` that carries the free-form deformation.

use crate::FfdError;
use nalgebra::{Matrix3, Vector3};
use sheetform_geometry::{BSplineBasis, GeometryError};

type Vec3 = Vector3<f64>;

/// A trivariate NURBS volume (Wang & Tang 2004 §2.1):
///
/// `Q(u,v,w) = Σ_ijk N_i(u) N_j(v) N_k(w) w_ijk P_ijk / Σ_ijk N_i(u) N_j(v) N_k(w) w_ijk`
///
/// with B-spline bases of any degrees over any knot vectors (evaluated by
/// [`BSplineBasis`], Piegl & Tiller A2.3), control points `P_ijk` (model length units)
/// and positive weights `w_ijk`. Control point `(i, j, k)` is stored at index
/// `i + n_u (j + n_v k)`.
///
/// The parameter Jacobian comes from the quotient rule: with `A = Σ N w P` and
/// `W = Σ N w`, `∂Q/∂u = (A_u − W_u Q) / W` (the same for `v`, `w`), in length units per
/// parameter unit.
#[derive(Debug, Clone, PartialEq)]
pub struct NurbsVolume {
    bases: [BSplineBasis; 3],
    control_points: Vec<Vec3>,
    weights: Vec<f64>,
}

/// The three parameter directions' names (for messages).
pub const DIRECTION_NAMES: [&str; 3] = ["u", "v", "w"];

/// The scene field named when a [`NurbsVolume::parallelepiped`] box has no volume (the
/// box's far corner; a scene without a box names its model instead).
pub(crate) const NO_VOLUME_FIELD: &str = "lattice.box_max";

impl NurbsVolume {
    /// Builds a volume from its degrees, full knot vectors, control-point counts, control
    /// points (in `i + n_u (j + n_v k)` order) and weights.
    ///
    /// # Errors
    /// A field error naming `lattice.degrees`, `lattice.knots[d]`, `lattice.counts`,
    /// `lattice.control_points[n]` or `lattice.weights[n]`: too few control points for
    /// the degree, wrong knot counts, decreasing knots, non-finite points, weights that are
    /// not positive or exceed [`crate::MAX_WEIGHT`].
    pub fn new(
        degrees: [usize; 3],
        knots: [Vec<f64>; 3],
        counts: [usize; 3],
        control_points: Vec<Vec3>,
        weights: Vec<f64>,
    ) -> Result<Self, FfdError> {
        let mut bases = Vec::with_capacity(3);
        for (d, knot_vector) in knots.into_iter().enumerate() {
            let basis = BSplineBasis::new(degrees[d], knot_vector, counts[d]).map_err(|e| {
                let field = match e {
                    GeometryError::BadKnots { .. } => format!("lattice.knots[{d}]"),
                    GeometryError::TooFewControlPoints { .. } => format!("lattice.counts[{d}]"),
                    _ => format!("lattice.degrees[{d}]"),
                };
                FfdError::field(field, format!("direction {}: {e}", DIRECTION_NAMES[d]))
            })?;
            bases.push(basis);
        }
        let total = counts[0] * counts[1] * counts[2];
        if control_points.len() != total {
            return Err(FfdError::field(
                "lattice.control_points",
                format!(
                    "{} × {} × {} lattice needs {total} control points, got {}",
                    counts[0],
                    counts[1],
                    counts[2],
                    control_points.len()
                ),
            ));
        }
        if let Some(n) = control_points.iter().position(|p| p.iter().any(|c| !c.is_finite())) {
            return Err(FfdError::field(format!("lattice.control_points[{n}]"), "not finite"));
        }
        if weights.len() != total {
            return Err(FfdError::field(
                "lattice.weights",
                format!("need one weight per control point ({total}), got {}", weights.len()),
            ));
        }
        check_weights(&weights)?;
        let bases: [BSplineBasis; 3] = bases.try_into().expect("three bases");
        Ok(Self {
            bases,
            control_points,
            weights,
        })
    }

    /// A parallelepiped lattice: the given knots (default: clamped uniform), unit weights and control points at
    /// `origin + Σ_d ξ_d axes[d]` with `ξ` the Greville abscissae, so that `Q` is the affine
    /// map `origin + [axes] (u, v, w)` on `[0, 1]³` until a control point is moved.
    ///
    /// # Errors
    /// As [`NurbsVolume::new`]; also degenerate (coplanar) axes.
    pub fn parallelepiped(
        origin: Vec3,
        axes: [Vec3; 3],
        degrees: [usize; 3],
        counts: [usize; 3],
        knots: Option<[Vec<f64>; 3]>,
    ) -> Result<Self, FfdError> {
        if Matrix3::from_columns(&axes).determinant().abs() <= 1e-12 * axes.iter().map(|a| a.norm()).product::<f64>() {
            return Err(FfdError::field(NO_VOLUME_FIELD, "the lattice box has no volume"));
        }
        let bases = match knots {
            Some(knots) => Self::new(
                degrees,
                knots,
                counts,
                vec![Vec3::zeros(); counts.iter().product()],
                vec![1.0; counts.iter().product()],
            )?
            .bases
            .to_vec(),
            None => {
                let mut bases = Vec::with_capacity(3);
                for d in 0..3 {
                    bases.push(BSplineBasis::clamped_uniform(degrees[d], counts[d]).map_err(|e| {
                        FfdError::field(
                            format!("lattice.counts[{d}]"),
                            format!("direction {}: {e}", DIRECTION_NAMES[d]),
                        )
                    })?);
                }
                bases
            }
        };
        let mut points = Vec::with_capacity(counts.iter().product());
        for k in 0..counts[2] {
            for j in 0..counts[1] {
                for i in 0..counts[0] {
                    let xi = [bases[0].greville(i), bases[1].greville(j), bases[2].greville(k)];
                    points.push(origin + axes[0] * xi[0] + axes[1] * xi[1] + axes[2] * xi[2]);
                }
            }
        }
        let knots = [0, 1, 2].map(|d| bases[d].knots().to_vec());
        let total = points.len();
        Self::new(degrees, knots, counts, points, vec![1.0; total])
    }

    /// Control points per direction `(n_u, n_v, n_w)`.
    pub fn counts(&self) -> [usize; 3] {
        [0, 1, 2].map(|d| self.bases[d].count())
    }

    /// Degrees per direction.
    pub fn degrees(&self) -> [usize; 3] {
        [0, 1, 2].map(|d| self.bases[d].degree())
    }

    /// The basis of direction `d` (0 = u, 1 = v, 2 = w).
    pub fn basis(&self, d: usize) -> &BSplineBasis {
        &self.bases[d]
    }

    /// Parameter domain per direction.
    pub fn domain(&self) -> [(f64, f64); 3] {
        [0, 1, 2].map(|d| self.bases[d].domain())
    }

    /// Clamps a parameter triple into the domain.
    pub fn clamp(&self, uvw: Vec3) -> Vec3 {
        let dom = self.domain();
        Vec3::new(
            uvw.x.clamp(dom[0].0, dom[0].1),
            uvw.y.clamp(dom[1].0, dom[1].1),
            uvw.z.clamp(dom[2].0, dom[2].1),
        )
    }

    /// Index of control point `(i, j, k)`.
    pub fn index(&self, i: usize, j: usize, k: usize) -> usize {
        let [nu, nv, _] = self.counts();
        i + nu * (j + nv * k)
    }

    /// The control points.
    pub fn control_points(&self) -> &[Vec3] {
        &self.control_points
    }

    /// The weights.
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// Replaces control points and weights (same lattice size), e.g. after edits.
    ///
    /// # Errors
    /// Wrong sizes, non-finite points, weights that are not positive or exceed
    /// [`crate::MAX_WEIGHT`].
    pub fn with_control_net(&self, control_points: Vec<Vec3>, weights: Vec<f64>) -> Result<Self, FfdError> {
        Self::new(
            self.degrees(),
            [0, 1, 2].map(|d| self.bases[d].knots().to_vec()),
            self.counts(),
            control_points,
            weights,
        )
    }

    /// The volume a fraction `t` of the way from `self` to `other` (same degrees, knots
    /// and counts): control points and weights interpolated linearly, `(1 − t)·a + t·b`.
    /// The path of a deformation for [`crate::restore_along_path`]; `t = 0` is `self`,
    /// `t = 1` is `other`.
    ///
    /// # Panics
    /// If the two lattices differ in size (an edit never changes it).
    pub fn interpolated(&self, other: &Self, t: f64) -> Self {
        assert_eq!(self.control_points.len(), other.control_points.len(), "same lattice");
        let mut volume = self.clone();
        for (p, q) in volume.control_points.iter_mut().zip(&other.control_points) {
            *p += t * (q - *p);
        }
        for (w, v) in volume.weights.iter_mut().zip(&other.weights) {
            *w += t * (v - *w);
        }
        volume
    }

    /// `Q(u, v, w)`.
    pub fn point(&self, uvw: Vec3) -> Vec3 {
        self.contract(uvw, false).0
    }

    /// `Q(u, v, w)` and its Jacobian `[∂Q/∂u ∂Q/∂v ∂Q/∂w]` (columns).
    pub fn point_and_jacobian(&self, uvw: Vec3) -> (Vec3, Matrix3<f64>) {
        self.contract(uvw, true)
    }

    /// `Q` and (when `jacobian`) its first derivatives, the homogeneous sums
    /// `A = Σ N_i N_j N_k w_ijk P_ijk`, `W = Σ N_i N_j N_k w_ijk` contracted one direction
    /// at a time (over `u` for each `(j, k)`, then `v`, then `w`): `(p+1)³` homogeneous
    /// points read once, about a third of the products of summing every term of the
    /// triple sum (as [`NurbsVolume::evaluate`] does for the second derivatives). Then
    /// `Q = A / W`, `∂Q/∂x = (∂A/∂x − Q ∂W/∂x) / W`.
    #[allow(clippy::needless_range_loop)]
    fn contract(&self, uvw: Vec3, jacobian: bool) -> (Vec3, Matrix3<f64>) {
        let order = usize::from(jacobian);
        let (su, nu) = self.bases[0].derivatives(uvw.x, order);
        let (sv, nv) = self.bases[1].derivatives(uvw.y, order);
        let (sw, nw) = self.bases[2].derivatives(uvw.z, order);
        let [pu, pv, pw] = self.degrees();
        type H = [f64; 4];
        let add = |sum: &mut H, h: &H, n: f64| {
            for t in 0..4 {
                sum[t] += h[t] * n;
            }
        };
        // Over w: value, ∂u, ∂v, ∂w.
        let mut total: [H; 4] = [[0.0; 4]; 4];
        for c in 0..=pw {
            let k = sw - pw + c;
            // Over v: value, ∂u, ∂v.
            let mut plane: [H; 3] = [[0.0; 4]; 3];
            for b in 0..=pv {
                let j = sv - pv + b;
                // Over u: value, ∂u.
                let mut line: [H; 2] = [[0.0; 4]; 2];
                let row = self.index(su - pu, j, k);
                for a in 0..=pu {
                    let weight = self.weights[row + a];
                    let p = self.control_points[row + a] * weight;
                    let h = [p.x, p.y, p.z, weight];
                    add(&mut line[0], &h, nu[0][a]);
                    if jacobian {
                        add(&mut line[1], &h, nu[1][a]);
                    }
                }
                add(&mut plane[0], &line[0], nv[0][b]);
                if jacobian {
                    add(&mut plane[1], &line[1], nv[0][b]);
                    add(&mut plane[2], &line[0], nv[1][b]);
                }
            }
            add(&mut total[0], &plane[0], nw[0][c]);
            if jacobian {
                add(&mut total[1], &plane[1], nw[0][c]);
                add(&mut total[2], &plane[2], nw[0][c]);
                add(&mut total[3], &plane[0], nw[1][c]);
            }
        }
        let [ax, ay, az, w] = total[0];
        let q = Vec3::new(ax, ay, az) / w;
        let mut out = Matrix3::zeros();
        if jacobian {
            for d in 0..3 {
                let [x, y, z, wd] = total[d + 1];
                out.set_column(d, &((Vec3::new(x, y, z) - q * wd) / w));
            }
        }
        (q, out)
    }

    /// `Q`, its Jacobian and its second derivatives `second[i][j] = ∂²Q/∂x_i∂x_j`
    /// (`x = (u, v, w)`, length units per parameter unit²), by the quotient rule on
    /// `Q = A / W`: `Q_ij = (A_ij − W_ij Q − W_i Q_j − W_j Q_i) / W` (for the chain rule
    /// of second derivatives with respect to the embedded parameters).
    pub fn point_jacobian_and_second_derivatives(&self, uvw: Vec3) -> (Vec3, Matrix3<f64>, [[Vec3; 3]; 3]) {
        self.evaluate(uvw, 2)
    }

    /// `Q`, its Jacobian (`order` ≥ 1) and second derivatives (`order` 2), summing every
    /// term of the triple sum.
    // Index loops over the three bases' tables read best side by side.
    #[allow(clippy::needless_range_loop)]
    fn evaluate(&self, uvw: Vec3, order: usize) -> (Vec3, Matrix3<f64>, [[Vec3; 3]; 3]) {
        let (su, nu) = self.bases[0].derivatives(uvw.x, order);
        let (sv, nv) = self.bases[1].derivatives(uvw.y, order);
        let (sw, nw) = self.bases[2].derivatives(uvw.z, order);
        let [pu, pv, pw] = self.degrees();
        let (mut a, mut w) = (Vec3::zeros(), 0.0);
        let (mut a_d, mut w_d) = ([Vec3::zeros(); 3], [0.0; 3]);
        let (mut a_dd, mut w_dd) = ([[Vec3::zeros(); 3]; 3], [[0.0; 3]; 3]);
        for c in 0..=pw {
            let k = sw - pw + c;
            for b in 0..=pv {
                let j = sv - pv + b;
                for a_i in 0..=pu {
                    let i = su - pu + a_i;
                    let index = self.index(i, j, k);
                    let weight = self.weights[index];
                    let wp = self.control_points[index] * weight;
                    let n = nu[0][a_i] * nv[0][b] * nw[0][c];
                    a += wp * n;
                    w += weight * n;
                    if order >= 1 {
                        let dn = [
                            nu[1][a_i] * nv[0][b] * nw[0][c],
                            nu[0][a_i] * nv[1][b] * nw[0][c],
                            nu[0][a_i] * nv[0][b] * nw[1][c],
                        ];
                        for d in 0..3 {
                            a_d[d] += wp * dn[d];
                            w_d[d] += weight * dn[d];
                        }
                    }
                    if order >= 2 {
                        // Orders of the u, v, w factors for each (d, e) with d <= e.
                        let table = [&nu, &nv, &nw];
                        let index_of = [a_i, b, c];
                        for d in 0..3 {
                            for e in d..3 {
                                let mut orders = [0usize; 3];
                                orders[d] += 1;
                                orders[e] += 1;
                                let dn = (0..3).map(|t| table[t][orders[t]][index_of[t]]).product::<f64>();
                                a_dd[d][e] += wp * dn;
                                w_dd[d][e] += weight * dn;
                            }
                        }
                    }
                }
            }
        }
        let q = a / w;
        let mut jacobian = Matrix3::zeros();
        let mut second = [[Vec3::zeros(); 3]; 3];
        if order >= 1 {
            for d in 0..3 {
                jacobian.set_column(d, &((a_d[d] - q * w_d[d]) / w));
            }
        }
        if order >= 2 {
            for d in 0..3 {
                for e in d..3 {
                    let value =
                        (a_dd[d][e] - q * w_dd[d][e] - jacobian.column(e) * w_d[d] - jacobian.column(d) * w_d[e]) / w;
                    second[d][e] = value;
                    second[e][d] = value;
                }
            }
        }
        (q, jacobian, second)
    }

    /// The affine map `Q(x) = o + M x` when the volume is one: all weights equal and
    /// every control point equal to `o + M ξ_ijk` (Greville abscissae) to rounding
    /// (`1e-12` of the lattice size). Then embedding is one linear solve per vertex.
    pub fn affine_map(&self) -> Option<(Vec3, Matrix3<f64>)> {
        let w0 = self.weights[0];
        if self.weights.iter().any(|&w| (w - w0).abs() > 1e-14 * w0) {
            return None;
        }
        let [nu, nv, nw] = self.counts();
        let origin = self.control_points[0];
        let greville = |d: usize, i: usize| self.bases[d].greville(i);
        let column = |d: usize| {
            let (last, index) = match d {
                0 => (nu - 1, self.index(nu - 1, 0, 0)),
                1 => (nv - 1, self.index(0, nv - 1, 0)),
                _ => (nw - 1, self.index(0, 0, nw - 1)),
            };
            (self.control_points[index] - origin) / (greville(d, last) - greville(d, 0))
        };
        let m = Matrix3::from_columns(&[column(0), column(1), column(2)]);
        let offset = origin - m * Vec3::new(greville(0, 0), greville(1, 0), greville(2, 0));
        let size = m.column_iter().map(|c| c.norm()).fold(0.0, f64::max);
        for k in 0..nw {
            for j in 0..nv {
                for i in 0..nu {
                    let expected = offset + m * Vec3::new(greville(0, i), greville(1, j), greville(2, k));
                    if (self.control_points[self.index(i, j, k)] - expected).norm() > 1e-12 * size {
                        return None;
                    }
                }
            }
        }
        if m.determinant().abs() <= 1e-14 * size.powi(3) {
            return None;
        }
        Some((offset, m))
    }
}

/// Every weight positive and at most [`crate::MAX_WEIGHT`], or a field error naming the
/// first bad one.
pub(crate) fn check_weights(weights: &[f64]) -> Result<(), FfdError> {
    for (n, &w) in weights.iter().enumerate() {
        crate::scene::check_weight(&format!("lattice.weights[{n}]"), w, crate::scene::WeightSign::Positive)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bent_volume() -> NurbsVolume {
        let mut v = NurbsVolume::parallelepiped(
            Vec3::new(-1.0, -2.0, 0.5),
            [
                Vec3::new(3.0, 0.0, 0.0),
                Vec3::new(0.5, 2.0, 0.0),
                Vec3::new(0.0, 0.3, 4.0),
            ],
            [3, 2, 3],
            [5, 4, 6],
            None,
        )
        .unwrap();
        let mut points = v.control_points().to_vec();
        let mut weights = v.weights().to_vec();
        for (n, p) in points.iter_mut().enumerate() {
            p.x += 0.2 * ((n as f64) * 0.7).sin();
            p.z += 0.1 * ((n as f64) * 1.3).cos();
            weights[n] = 1.0 + 0.5 * ((n as f64) * 0.37).sin().abs();
        }
        v = v.with_control_net(points, weights).unwrap();
        v
    }

    #[test]
    fn parallelepiped_is_its_affine_map() {
        let axes = [
            Vec3::new(3.0, 0.0, 0.0),
            Vec3::new(0.5, 2.0, 0.0),
            Vec3::new(0.0, 0.3, 4.0),
        ];
        let origin = Vec3::new(-1.0, -2.0, 0.5);
        let v = NurbsVolume::parallelepiped(origin, axes, [3, 2, 1], [5, 4, 2], None).unwrap();
        let (o, m) = v.affine_map().expect("affine");
        assert!((o - origin).norm() < 1e-12);
        for x in [
            Vec3::new(0.1, 0.2, 0.3),
            Vec3::new(0.9, 0.5, 0.05),
            Vec3::new(1.0, 1.0, 1.0),
        ] {
            let expected = origin + axes[0] * x.x + axes[1] * x.y + axes[2] * x.z;
            assert!((v.point(x) - expected).norm() < 1e-12);
            assert!((m * x + o - expected).norm() < 1e-12);
        }
        assert!(bent_volume().affine_map().is_none());
    }

    #[test]
    fn interpolation_runs_from_one_lattice_to_the_other() {
        let bent = bent_volume();
        let straight = NurbsVolume::parallelepiped(
            Vec3::new(-1.0, -2.0, 0.5),
            [
                Vec3::new(3.0, 0.0, 0.0),
                Vec3::new(0.5, 2.0, 0.0),
                Vec3::new(0.0, 0.3, 4.0),
            ],
            [3, 2, 3],
            [5, 4, 6],
            None,
        )
        .unwrap();
        let x = Vec3::new(0.3, 0.6, 0.45);
        assert_eq!(straight.interpolated(&bent, 0.0).point(x), straight.point(x));
        assert!((straight.interpolated(&bent, 1.0).point(x) - bent.point(x)).norm() < 1e-14);
        // Halfway: control points and weights are the means.
        let half = straight.interpolated(&bent, 0.5);
        for n in 0..bent.control_points().len() {
            let mean = 0.5 * (straight.control_points()[n] + bent.control_points()[n]);
            assert!((half.control_points()[n] - mean).norm() < 1e-14);
            assert!((half.weights()[n] - 0.5 * (1.0 + bent.weights()[n])).abs() < 1e-14);
        }
    }

    #[test]
    fn jacobian_matches_finite_differences() {
        let v = bent_volume();
        let h = 1e-6;
        for x in [
            Vec3::new(0.13, 0.42, 0.77),
            Vec3::new(0.61, 0.08, 0.35),
            // Off the knots at 0.5 (central differences lose an order across a knot).
            Vec3::new(0.47, 0.53, 0.49),
        ] {
            let (_, j) = v.point_and_jacobian(x);
            for d in 0..3 {
                let mut e = Vec3::zeros();
                e[d] = h;
                let fd = (v.point(x + e) - v.point(x - e)) / (2.0 * h);
                assert!(
                    (fd - j.column(d)).norm() < 1e-7 * (1.0 + fd.norm()),
                    "{d}: {fd} vs {}",
                    j.column(d)
                );
            }
        }
    }

    #[test]
    fn second_derivatives_match_finite_differences_of_the_jacobian() {
        let volume = bent_volume();
        let x = Vec3::new(0.37, 0.52, 0.61);
        let (q, jacobian, second) = volume.point_jacobian_and_second_derivatives(x);
        let (expected_q, expected_jacobian) = volume.point_and_jacobian(x);
        assert!((q - expected_q).norm() < 1e-14 * (1.0 + q.norm()));
        assert!((jacobian - expected_jacobian).norm() < 1e-12 * (1.0 + jacobian.norm()));
        // The term-by-term sum and the one-direction-at-a-time contraction agree, also on
        // the lattice's faces and corners.
        for y in [
            x,
            Vec3::zeros(),
            Vec3::new(1.0, 1.0, 1.0),
            Vec3::new(0.5, 0.0, 0.93),
            Vec3::new(0.21, 0.5, 1.0),
        ] {
            let (q, jacobian, _) = volume.evaluate(y, 1);
            let (expected_q, expected_jacobian) = volume.point_and_jacobian(y);
            assert!((q - expected_q).norm() < 1e-14 * (1.0 + q.norm()), "{y}");
            assert!(
                (jacobian - expected_jacobian).norm() < 1e-12 * (1.0 + jacobian.norm()),
                "{y}"
            );
            assert!((volume.point(y) - q).norm() < 1e-14 * (1.0 + q.norm()), "{y}");
        }
        let h = 1e-6;
        for e in 0..3 {
            let mut step = Vec3::zeros();
            step[e] = h;
            let difference =
                (volume.point_and_jacobian(x + step).1 - volume.point_and_jacobian(x - step).1) / (2.0 * h);
            for (d, row) in second.iter().enumerate() {
                let fd = difference.column(d);
                assert!(
                    (fd - row[e]).norm() < 1e-6 * (1.0 + fd.norm()),
                    "∂²Q/∂{d}∂{e}: {fd} vs {}",
                    row[e]
                );
            }
        }
    }

    #[test]
    fn rejects_bad_lattices() {
        let p = vec![Vec3::zeros(); 8];
        let knots = || {
            [
                vec![0.0, 0.0, 1.0, 1.0],
                vec![0.0, 0.0, 1.0, 1.0],
                vec![0.0, 0.0, 1.0, 1.0],
            ]
        };
        assert!(NurbsVolume::new([1, 1, 1], knots(), [2, 2, 2], p.clone(), vec![1.0; 8]).is_ok());
        let e = NurbsVolume::new([3, 1, 1], knots(), [2, 2, 2], p.clone(), vec![1.0; 8]).unwrap_err();
        assert!(e.to_string().contains("lattice.counts[0]"), "{e}");
        let mut k = knots();
        k[1] = vec![0.0, 0.5, 0.2, 1.0];
        let e = NurbsVolume::new([1, 1, 1], k, [2, 2, 2], p.clone(), vec![1.0; 8]).unwrap_err();
        assert!(
            e.to_string().contains("lattice.knots[1]") && e.to_string().contains("decrease"),
            "{e}"
        );
        let mut w = vec![1.0; 8];
        w[5] = 0.0;
        let e = NurbsVolume::new([1, 1, 1], knots(), [2, 2, 2], p, w).unwrap_err();
        assert!(e.to_string().contains("lattice.weights[5]"), "{e}");
    }
}

//! Lifting the curve network to 3D (§6): the six quadratic energy terms on the 3D
//! control points, assembled sparse and minimised by one linear least-squares solve.
//!
//! Unknowns: every network control point `q = (X, Y, Z)` (model frame, pixels). With
//! `q̄` the traced 2D point, each term is a sum of squared linear residuals:
//!
//! - `E_proj = |q_xy + a Z − q̄|²` per control point, `a = (q̄ − c)/f` the slope of its
//!   ray through a perspective camera ([`crate::Camera`]), `a = 0` under the paper's
//!   orthographic one (`E_proj = |q|_{z=0} − q̄|²`);
//! - `E_minvar = |φ0 q0 + φ1 q1 + φ2 q2 − q3|²` for the four points of every segment and
//!   the four handles `b1ᵏ, b2ᵏ, b1ᵏ⁺¹, b2ᵏ⁺¹` around every join, `φ` the barycentric
//!   coordinates of `q̄3` in the triangle `q̄0 q̄1 q̄2` (skipped when that is degenerate);
//! - `E_col = |(1 − δ) r0 + δ r2 − r1|²` for the triplet `b2ᵏ, b3ᵏ, b1ᵏ⁺¹` of every join
//!   (C¹) and every triplet of successive control points that is straight in 2D, `δ` the
//!   parameter of `r̄1` on `r̄0 r̄2`;
//! - `E_foreshort = (Z_i − Z_{i+1})²` for successive control points of a segment;
//! - `E_sym = |p − p′ − t|² + |½(p + p′) − m|²` per mirror pair (Eq. 3), `p = Σ Bᵢ(t) qᵢ`
//!   on its segment, `t` and `m` from [`SymmetryPlane::pair_relation`];
//! - `E_develop = |φ0 pᵢ + φ1 pᵢ₊₁ + φ2 p′ⱼ − p′ⱼ₊₁|²` for consecutive rulings `pᵢp′ⱼ`,
//!   `pᵢ₊₁p′ⱼ₊₁` (Eq. 4): the quad they span is planar.
//!
//! `E = ω1 E_proj + ω2 E_minvar + ω3 E_col + ω4 E_foreshort + ω5 E_sym + ω6 E_develop` with
//! the paper's `ω = (1, 0.1, 1, 1e-8, 1, 1)` by default (§6.2).
//!
//! **Perspective** (beyond the paper): the barycentric coordinates `φ` of the image are
//! not those of the 3D points. If `P₃ = Σ φᵢ Pᵢ` in 3D, its image has the coordinates
//! `μᵢ = φᵢ wᵢ / w₃` with `w` the perspective divisors, so the 3D coordinates are
//! `φᵢ = μᵢ w₃ / wᵢ` (normalised to sum 1). `E_minvar`, `E_col` and `E_develop` take them
//! with the divisors of a previous solution (`depths`; all 1 for the first solve and for
//! an orthographic camera); [`crate::reconstruct`] solves again until the depths settle.
//!
//! Departures from the paper: (1) the normal equations `AᵀA q = Aᵀb` are solved by a
//! sparse Cholesky factorisation (faer) instead of a dense SVD; rank deficiency (a curve
//! that no symmetric pair or ruling reaches has a free depth) is resolved by a Tikhonov
//! term `ε |q − (q̄, 0)|²`, `ε = 1e-9` of the largest diagonal entry, which selects the
//! solution nearest the image plane among the minimisers, as the SVD's minimum-norm
//! solution does up to the choice of origin. (2) Each `E_develop` residual is divided by
//! `√(1 + |φ|²)`: the barycentric coordinates of a point outside a thin triangle are
//! large, and unscaled they would weigh long, densely spaced rulings far more than the
//! rest (the residual then measures a distance to the plane, in pixels).

use crate::curve_network::CurveNetwork;
use crate::curve_samples::CurvePoint;
use crate::ruling_propagation::RuledStrip;
use crate::symmetric_correspondences::SymmetricPair;
use crate::symmetry_plane::SymmetryPlane;
use crate::{cubic, EnergyWeights, PhotoError};
use faer::sparse::Triplet;
use nalgebra::{Vector2, Vector3};
use sheetform_solve::SparseCholesky;

type Vec2 = Vector2<f64>;
type Vec3 = Vector3<f64>;

/// Which energy term a residual row belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EnergyTerm {
    /// `E_proj`.
    Projection,
    /// `E_minvar`.
    MinimalVariation,
    /// `E_col`.
    Collinearity,
    /// `E_foreshort`.
    Foreshortening,
    /// `E_sym`.
    Symmetry,
    /// `E_develop`.
    Developability,
}

/// One weighted linear residual `Σ coefficient · x[column] − rhs` (columns index the
/// unknown vector, `3 × point + axis`).
#[derive(Debug, Clone, PartialEq)]
pub struct EnergyRow {
    /// The term.
    pub term: EnergyTerm,
    /// Sparse coefficients (weight included).
    pub coefficients: Vec<(u32, f64)>,
    /// Right-hand side (weight included).
    pub rhs: f64,
}

/// The assembled energy: its rows and the counts of each term.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Energy {
    /// All residual rows.
    pub rows: Vec<EnergyRow>,
    /// Number of unknowns (`3 ×` points).
    pub unknown_count: usize,
}

/// Linear combination `Σ wᵢ qᵢ` of control points for a place on the network, per
/// point index.
fn place_weights(network: &CurveNetwork, place: CurvePoint) -> [(u32, f64); 4] {
    let seg = network.segments[place.segment as usize].points;
    let w = cubic::bernstein(place.t);
    [(seg[0], w[0]), (seg[1], w[1]), (seg[2], w[2]), (seg[3], w[3])]
}

/// `Σ wᵢ qᵢ` over the four 3D control points of `segment` in the unknown vector `x`
/// (`3 × point + axis`): a point (Bernstein weights) or a derivative of the lifted curve.
pub fn combine3(network: &CurveNetwork, x: &[f64], segment: u32, weights: [f64; 4]) -> Vec3 {
    network.segments[segment as usize]
        .points
        .iter()
        .zip(weights)
        .map(|(&i, w)| Vec3::new(x[3 * i as usize], x[3 * i as usize + 1], x[3 * i as usize + 2]) * w)
        .sum()
}

/// 2D image position of a place.
pub fn place_image(network: &CurveNetwork, place: CurvePoint) -> Vec2 {
    cubic::point(&network.control_points(place.segment as usize), place.t)
}

/// The 3D affine coordinates with image coordinates `mu` (summing to 1) of points with
/// perspective divisors `divisors` (the last one the combined point's): `μᵢ w / wᵢ`,
/// normalised (the image coordinates themselves for equal divisors).
fn corrected<const N: usize>(mu: [f64; N], divisors: [f64; N], combined: f64) -> [f64; N] {
    let mut phi: [f64; N] = std::array::from_fn(|i| mu[i] * combined / divisors[i]);
    let sum: f64 = phi.iter().sum();
    if sum.abs() > 1e-9 {
        for v in &mut phi {
            *v /= sum;
        }
        phi
    } else {
        mu
    }
}

/// Barycentric coordinates of `p` in triangle `a b c` (`None` if degenerate).
fn barycentric(a: Vec2, b: Vec2, c: Vec2, p: Vec2) -> Option<[f64; 3]> {
    let cross = |u: Vec2, v: Vec2| u.x * v.y - u.y * v.x;
    let area = cross(b - a, c - a);
    let scale = (b - a).norm_squared().max((c - a).norm_squared());
    if area.abs() <= 1e-9 * scale || scale == 0.0 {
        return None;
    }
    let l1 = cross(p - a, c - a) / area;
    let l2 = cross(b - a, p - a) / area;
    Some([1.0 - l1 - l2, l1, l2])
}

/// Adds three rows (X, Y, Z) `Σ cᵢ q[pointᵢ] − rhs` with weight `sqrt(ω)`.
fn push_vector_rows(rows: &mut Vec<EnergyRow>, term: EnergyTerm, weight: f64, combo: &[(u32, f64)], rhs: Vec3) {
    let w = weight.sqrt();
    for axis in 0..3 {
        let mut coefficients: Vec<(u32, f64)> = Vec::with_capacity(combo.len());
        for &(point, c) in combo {
            let col = 3 * point + axis as u32;
            match coefficients.iter_mut().find(|(k, _)| *k == col) {
                Some((_, v)) => *v += w * c,
                None => coefficients.push((col, w * c)),
            }
        }
        rows.push(EnergyRow {
            term,
            coefficients,
            rhs: w * rhs[axis],
        });
    }
}

/// Assembles the energy of §6.1 for the camera of `plane`. `depths` are the depths `Z`
/// of a previous solution at the network's points (empty: all 0), for the perspective
/// correction of the barycentric coordinates.
pub fn assemble_energy(
    network: &CurveNetwork,
    strips: &[RuledStrip],
    pairs: &[SymmetricPair],
    plane: &SymmetryPlane,
    weights: &EnergyWeights,
    depths: &[f64],
) -> Energy {
    let mut rows: Vec<EnergyRow> = Vec::new();
    let q = &network.points;
    let camera = &plane.camera;
    let depth = |i: u32| depths.get(i as usize).copied().unwrap_or(0.0);
    let divisor = |i: u32| camera.divisor(depth(i));
    let place_divisor =
        |place: CurvePoint| camera.divisor(place_weights(network, place).iter().map(|&(i, b)| b * depth(i)).sum());
    // E_proj.
    let w1 = weights.projection.sqrt();
    for (i, p) in q.iter().enumerate() {
        let slope = camera.ray_slope(*p);
        for axis in 0..2 {
            let mut coefficients = vec![(3 * i as u32 + axis, w1)];
            if slope[axis as usize] != 0.0 {
                coefficients.push((3 * i as u32 + 2, w1 * slope[axis as usize]));
            }
            rows.push(EnergyRow {
                term: EnergyTerm::Projection,
                coefficients,
                rhs: w1 * p[axis as usize],
            });
        }
    }
    // Quadruples and triplets along every curve.
    let minvar = |rows: &mut Vec<EnergyRow>, ids: [u32; 4]| {
        let [a, b, c, d] = ids.map(|i| q[i as usize]);
        if let Some(mu) = barycentric(a, b, c, d) {
            let phi = corrected(mu, [divisor(ids[0]), divisor(ids[1]), divisor(ids[2])], divisor(ids[3]));
            let combo = [(ids[0], phi[0]), (ids[1], phi[1]), (ids[2], phi[2]), (ids[3], -1.0)];
            push_vector_rows(
                rows,
                EnergyTerm::MinimalVariation,
                weights.minimal_variation,
                &combo,
                Vec3::zeros(),
            );
        }
    };
    let collinear = |rows: &mut Vec<EnergyRow>, ids: [u32; 3], require_straight: bool| {
        let [r0, r1, r2] = ids.map(|i| q[i as usize]);
        let span = r2 - r0;
        let l2 = span.norm_squared();
        if l2 < 1e-12 {
            return;
        }
        let off = (span.x * (r1 - r0).y - span.y * (r1 - r0).x).abs() / l2.sqrt();
        if require_straight && off > 1e-3 * l2.sqrt() {
            return;
        }
        let delta = (r1 - r0).dot(&span) / l2;
        let [phi0, phi2] = corrected(
            [1.0 - delta, delta],
            [divisor(ids[0]), divisor(ids[2])],
            divisor(ids[1]),
        );
        let combo = [(ids[0], phi0), (ids[2], phi2), (ids[1], -1.0)];
        push_vector_rows(
            rows,
            EnergyTerm::Collinearity,
            weights.collinearity,
            &combo,
            Vec3::zeros(),
        );
    };
    for curve in &network.curves {
        let segs = &curve.segments;
        for &s in segs {
            let ids = network.segments[s as usize].points;
            minvar(&mut rows, ids);
            collinear(&mut rows, [ids[0], ids[1], ids[2]], true);
            collinear(&mut rows, [ids[1], ids[2], ids[3]], true);
            let wz = weights.foreshortening.sqrt();
            for k in 0..3 {
                rows.push(EnergyRow {
                    term: EnergyTerm::Foreshortening,
                    coefficients: vec![(3 * ids[k] + 2, wz), (3 * ids[k + 1] + 2, -wz)],
                    rhs: 0.0,
                });
            }
        }
        let joins = if curve.closed {
            segs.len()
        } else {
            segs.len().saturating_sub(1)
        };
        for k in 0..joins {
            let a = network.segments[segs[k] as usize].points;
            let b = network.segments[segs[(k + 1) % segs.len()] as usize].points;
            minvar(&mut rows, [a[1], a[2], b[1], b[2]]);
            collinear(&mut rows, [a[2], a[3], b[1]], false);
        }
    }
    // E_sym.
    for pair in pairs {
        let (a, b) = (
            place_image(network, pair.places[0]),
            place_image(network, pair.places[1]),
        );
        let (t, m) = plane.pair_relation(a, b);
        let (pa, pb) = (
            place_weights(network, pair.places[0]),
            place_weights(network, pair.places[1]),
        );
        let difference: Vec<(u32, f64)> = pa.iter().copied().chain(pb.iter().map(|&(i, w)| (i, -w))).collect();
        push_vector_rows(&mut rows, EnergyTerm::Symmetry, weights.symmetry, &difference, t);
        let mean: Vec<(u32, f64)> = pa.iter().chain(pb.iter()).map(|&(i, w)| (i, 0.5 * w)).collect();
        push_vector_rows(&mut rows, EnergyTerm::Symmetry, weights.symmetry, &mean, m);
    }
    // E_develop.
    for strip in strips {
        for i in 0..strip.rulings.len() - 1 {
            let [pi, pj] = strip.ends(i);
            let [pi1, pj1] = strip.ends(i + 1);
            let img = |p| place_image(network, p);
            let Some(mu) = barycentric(img(pi), img(pi1), img(pj), img(pj1)) else {
                continue;
            };
            let phi = corrected(
                mu,
                [place_divisor(pi), place_divisor(pi1), place_divisor(pj)],
                place_divisor(pj1),
            );
            let scale = 1.0 / (1.0 + phi.iter().map(|v| v * v).sum::<f64>()).sqrt();
            let mut combo: Vec<(u32, f64)> = Vec::with_capacity(16);
            for (place, c) in [(pi, phi[0]), (pi1, phi[1]), (pj, phi[2]), (pj1, -1.0)] {
                combo.extend(place_weights(network, place).iter().map(|&(k, w)| (k, scale * c * w)));
            }
            push_vector_rows(
                &mut rows,
                EnergyTerm::Developability,
                weights.developability,
                &combo,
                Vec3::zeros(),
            );
        }
    }
    Energy {
        rows,
        unknown_count: 3 * q.len(),
    }
}

/// Minimises the energy plus the Tikhonov term `ε |q − prior|²` for each prior, with one
/// factorisation (the priors change only the right-hand side); one solution per prior.
///
/// # Errors
/// [`PhotoError::Solver`] if the factorisation fails or a solution is not finite.
pub fn solve_energy(energy: &Energy, priors: &[&[f64]]) -> Result<Vec<Vec<f64>>, PhotoError> {
    let n = energy.unknown_count;
    let mut diagonal = vec![0.0; n];
    let mut atb = vec![0.0; n];
    let mut triplets: Vec<Triplet<usize, usize, f64>> = Vec::new();
    for row in &energy.rows {
        for &(ci, ai) in &row.coefficients {
            atb[ci as usize] += ai * row.rhs;
            for &(cj, aj) in &row.coefficients {
                if cj <= ci {
                    triplets.push(Triplet::new(ci as usize, cj as usize, ai * aj));
                }
                if cj == ci {
                    diagonal[ci as usize] += ai * aj;
                }
            }
        }
    }
    let epsilon = 1e-9 * diagonal.iter().copied().fold(0.0, f64::max).max(1e-300);
    for k in 0..n {
        triplets.push(Triplet::new(k, k, epsilon));
    }
    let llt = SparseCholesky::new(n, &triplets).map_err(|e| {
        tracing::debug!("photo: the 3D curves' system: {e:?}");
        PhotoError::Solver(
            "the 3D curves cannot be found from the drawing: their system has no solution in finite numbers \
             (control points or weights far out of scale?)"
                .into(),
        )
    })?;
    priors
        .iter()
        .map(|prior| {
            let rhs: Vec<f64> = (0..n).map(|k| atb[k] + epsilon * prior[k]).collect();
            let out = llt.solve(&rhs);
            if out.iter().any(|v| !v.is_finite()) {
                return Err(PhotoError::Solver(
                    "the 3D curves found from the drawing are not finite (control points or weights far out of \
                     scale?)"
                        .into(),
                ));
            }
            Ok(out)
        })
        .collect()
}

/// The prior of the Tikhonov term: the traced points at depth `depth` on their rays
/// through `camera` (0: the points as traced).
pub fn image_prior(network: &CurveNetwork, camera: &crate::Camera, depth: f64) -> Vec<f64> {
    network
        .points
        .iter()
        .flat_map(|&p| {
            let q = camera.point_at_depth(p, depth);
            [q.x, q.y, q.z]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 35: the factorisation's "pivot 96084 is not positive" reached the user; a
    /// system that cannot be solved is told in the drawing's terms.
    #[test]
    fn an_unsolvable_system_is_told_in_the_drawings_terms() {
        let energy = Energy {
            rows: vec![EnergyRow {
                term: EnergyTerm::Projection,
                coefficients: vec![(0, f64::NAN), (1, 1.0)],
                rhs: 1.0,
            }],
            unknown_count: 3,
        };
        let prior = [0.0; 3];
        let text = solve_energy(&energy, &[&prior]).unwrap_err().to_string();
        assert!(
            text.contains("3D curves") && !text.contains("pivot") && !text.contains("matrix"),
            "{text}"
        );
    }
}

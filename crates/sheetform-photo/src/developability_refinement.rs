//! The developability error of §8.2 and a refinement, beyond the paper, that removes it.
//!
//! **Metric** (§8.2, Table 1): for a ruling from `p_a` (on one curve, tangent `T_a`) to
//! `p_b` (tangent `T_b`), `d = p_b − p_a`, the surface normals at its ends are
//! `n_a = T_a × d` and `n_b = T_b × d`; the error is the angle between them (as lines,
//! radians). The surface is developable along the ruling iff it vanishes, i.e. iff
//! `det(T_a, T_b, d) = 0` (Eq. 1: `A, B, A + Ȧ, B + Ḃ` coplanar), because
//! `n_a × n_b = det(T_a, T_b, d) d`.
//!
//! **Refinement**: the linear energy only *encourages* planar quads between rulings, and
//! leaves 6–16° of error on real drawings (Table 1). Here the 3D control points `q` solve
//!
//! `min ½|A q − b|² + ½ μ |q − q_lin|²` subject to `g_r(q) = 0` for every ruling `r`,
//!
//! with `A q − b` the weighted rows of the linear energy (so the annotations, symmetry and
//! C¹ joins still pull as before), `q_lin` its solution, `μ = 1e-3` (relative to the
//! projection weight) and `g_r = det(T_a, T_b, d) |d| / (|T_a × d| |T_b × d|)` with the
//! denominator frozen at `q_lin` (then `g_r ≈ sin` of the error angle). The objective is
//! quadratic with a constant sparse Hessian `H = AᵀA + μI`, factorised once (faer); each
//! iteration is a Gauss–Newton SQP step `[H Cᵀ; C 0][δ; λ] = [−∇f; −g]` solved through the
//! Schur complement `C H⁻¹ Cᵀ` (dense, one row per ruling), with a backtracking search on
//! `max |g|`. It stops at `max |g| ≤ 1e-12`, when no step reduces `max |g|`, or after 50
//! iterations, and reports convergence when `max |g| ≤` [`REFINEMENT_BOUND`]. Rulings whose
//! tangent is parallel to the ruling (a cone's apex) carry no constraint.

use crate::curve_lifting::Energy;
use crate::curve_network::CurveNetwork;
use crate::curve_samples::CurvePoint;
use crate::ruling_propagation::RuledStrip;
use crate::{cubic, PhotoError};
use faer::prelude::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Col, Mat, Side};
use nalgebra::Vector3;

type Vec3 = Vector3<f64>;

/// The refinement's bound on `max |g|` (≈ the sine of the largest error angle): 1e-7 rad,
/// 6e-6°, far below any fabrication tolerance (a 1 m ruling then bends 0.1 µm). The
/// iteration goes on towards 1e-12 while it makes progress.
pub const REFINEMENT_BOUND: f64 = 1e-7;

/// Point of the 3D network (unknown vector `x`) at a place.
fn point3(network: &CurveNetwork, x: &[f64], place: CurvePoint) -> Vec3 {
    let w = cubic::bernstein(place.t);
    let ids = network.segments[place.segment as usize].points;
    (0..4)
        .map(|k| {
            Vec3::new(
                x[3 * ids[k] as usize],
                x[3 * ids[k] as usize + 1],
                x[3 * ids[k] as usize + 2],
            ) * w[k]
        })
        .sum()
}

fn tangent3(network: &CurveNetwork, x: &[f64], place: CurvePoint) -> Vec3 {
    let w = cubic::bernstein_derivative(place.t);
    let ids = network.segments[place.segment as usize].points;
    (0..4)
        .map(|k| {
            Vec3::new(
                x[3 * ids[k] as usize],
                x[3 * ids[k] as usize + 1],
                x[3 * ids[k] as usize + 2],
            ) * w[k]
        })
        .sum()
}

/// The paper's developability error of every ruling (radians), strip by strip.
pub fn ruling_errors(network: &CurveNetwork, x: &[f64], strips: &[RuledStrip]) -> Vec<f64> {
    let mut out = Vec::new();
    for strip in strips {
        for i in 0..strip.rulings.len() {
            let [a, b] = strip.ends(i);
            let d = point3(network, x, b) - point3(network, x, a);
            let na = tangent3(network, x, a).cross(&d);
            let nb = tangent3(network, x, b).cross(&d);
            let denominator = na.norm() * nb.norm();
            if denominator < 1e-300 {
                continue;
            }
            out.push((na.dot(&nb).abs() / denominator).min(1.0).acos());
        }
    }
    out
}

/// What the refinement did.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RefinementInfo {
    /// SQP iterations.
    pub iterations: usize,
    /// Constraints (rulings) enforced.
    pub constraint_count: usize,
    /// `max |g|` at the end (≈ sine of the largest error angle).
    pub constraint_violation: f64,
    /// Whether `max |g| ≤ REFINEMENT_BOUND` was reached.
    pub converged: bool,
    /// Largest change of a control point (pixels).
    pub displacement_max: f64,
}

struct Constraint {
    a: CurvePoint,
    b: CurvePoint,
    scale: f64,
}

/// Values and sparse gradients of the constraints.
fn evaluate(network: &CurveNetwork, x: &[f64], constraints: &[Constraint]) -> (Vec<f64>, Vec<Vec<(usize, f64)>>) {
    let mut values = Vec::with_capacity(constraints.len());
    let mut gradients = Vec::with_capacity(constraints.len());
    for c in constraints {
        let (ta, tb) = (tangent3(network, x, c.a), tangent3(network, x, c.b));
        let d = point3(network, x, c.b) - point3(network, x, c.a);
        values.push(ta.cross(&tb).dot(&d) * c.scale);
        let (g_ta, g_tb, g_d) = (tb.cross(&d) * c.scale, d.cross(&ta) * c.scale, ta.cross(&tb) * c.scale);
        let mut grad: Vec<(usize, f64)> = Vec::with_capacity(24);
        for (place, sign) in [(c.a, -1.0), (c.b, 1.0)] {
            let ids = network.segments[place.segment as usize].points;
            let (w, dw) = (cubic::bernstein(place.t), cubic::bernstein_derivative(place.t));
            let g_t = if sign < 0.0 { g_ta } else { g_tb };
            for k in 0..4 {
                for axis in 0..3 {
                    let v = dw[k] * g_t[axis] + sign * w[k] * g_d[axis];
                    grad.push((3 * ids[k] as usize + axis, v));
                }
            }
        }
        gradients.push(grad);
    }
    (values, gradients)
}

/// Makes every ruling's tangent plane constant (see the module documentation).
///
/// # Errors
/// [`PhotoError::Solver`] if the factorisation fails.
pub fn refine_developability(
    network: &CurveNetwork,
    energy: &Energy,
    strips: &[RuledStrip],
    x_linear: &[f64],
    proximity: f64,
) -> Result<(Vec<f64>, RefinementInfo), PhotoError> {
    let n = x_linear.len();
    let mut constraints = Vec::new();
    for strip in strips {
        for i in 0..strip.rulings.len() {
            let [a, b] = strip.ends(i);
            let d = point3(network, x_linear, b) - point3(network, x_linear, a);
            let (ta, tb) = (tangent3(network, x_linear, a), tangent3(network, x_linear, b));
            let (sa, sb) = (ta.cross(&d).norm(), tb.cross(&d).norm());
            if sa < 1e-6 * ta.norm() * d.norm() || sb < 1e-6 * tb.norm() * d.norm() {
                continue;
            }
            constraints.push(Constraint {
                a,
                b,
                scale: d.norm() / (sa * sb),
            });
        }
    }
    let mut info = RefinementInfo {
        constraint_count: constraints.len(),
        ..Default::default()
    };
    if constraints.is_empty() {
        info.converged = true;
        return Ok((x_linear.to_vec(), info));
    }
    // H = AᵀA + μ I and the constant part of the gradient.
    let mut triplets: Vec<Triplet<usize, usize, f64>> = Vec::new();
    let mut atb = vec![0.0; n];
    for row in &energy.rows {
        for &(ci, ai) in &row.coefficients {
            atb[ci as usize] += ai * row.rhs;
            for &(cj, aj) in &row.coefficients {
                if cj <= ci {
                    triplets.push(Triplet::new(ci as usize, cj as usize, ai * aj));
                }
            }
        }
    }
    for k in 0..n {
        triplets.push(Triplet::new(k, k, proximity));
    }
    let h = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &triplets)
        .map_err(|e| PhotoError::Solver(format!("{e:?}")))?;
    let symbolic = SymbolicLlt::try_new(h.symbolic(), Side::Lower).map_err(|e| PhotoError::Solver(format!("{e:?}")))?;
    let llt = Llt::try_new_with_symbolic(symbolic, h.as_ref(), Side::Lower)
        .map_err(|e| PhotoError::Solver(format!("factorisation failed: {e:?}")))?;
    let h_times = |x: &[f64]| -> Vec<f64> {
        let mut out = vec![0.0; n];
        for row in &energy.rows {
            let r: f64 = row.coefficients.iter().map(|&(c, a)| a * x[c as usize]).sum();
            for &(c, a) in &row.coefficients {
                out[c as usize] += a * r;
            }
        }
        for k in 0..n {
            out[k] += proximity * x[k];
        }
        out
    };
    let mut x = x_linear.to_vec();
    let m = constraints.len();
    let (mut g, mut grads) = evaluate(network, &x, &constraints);
    let max_abs = |v: &[f64]| v.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    for iteration in 0..50 {
        info.iterations = iteration;
        let violation = max_abs(&g);
        if violation <= 1e-12 {
            info.converged = true;
            break;
        }
        // ∇f = H x − Aᵀb − μ x_lin.
        let hx = h_times(&x);
        let grad_f: Vec<f64> = (0..n).map(|k| hx[k] - atb[k] - proximity * x_linear[k]).collect();
        let z = llt.solve(Col::from_fn(n, |k| grad_f[k]));
        // Y = H⁻¹ Cᵀ, one column per constraint.
        let mut ct = Mat::<f64>::zeros(n, m);
        for (r, grad) in grads.iter().enumerate() {
            for &(c, v) in grad {
                ct[(c, r)] += v;
            }
        }
        let y = llt.solve(&ct);
        // S = C Y (symmetric positive semi-definite), rhs = g − C z.
        let mut s = Mat::<f64>::zeros(m, m);
        let mut rhs = Col::<f64>::zeros(m);
        for (r, grad) in grads.iter().enumerate() {
            let mut cz = 0.0;
            for &(c, v) in grad {
                cz += v * z[c];
                for j in 0..m {
                    s[(r, j)] += v * y[(c, j)];
                }
            }
            rhs[r] = g[r] - cz;
        }
        // Redundant constraints make S singular: a tiny ridge keeps the solve defined.
        let ridge = 1e-12 * (0..m).map(|i| s[(i, i)]).fold(0.0, f64::max).max(1e-300);
        for i in 0..m {
            s[(i, i)] += ridge;
        }
        let lambda = s.partial_piv_lu().solve(&rhs);
        let step: Vec<f64> = (0..n)
            .map(|k| {
                let mut v = -z[k];
                for j in 0..m {
                    v -= y[(k, j)] * lambda[j];
                }
                v
            })
            .collect();
        let mut alpha = 1.0;
        let mut accepted = false;
        for _ in 0..20 {
            let trial: Vec<f64> = x.iter().zip(&step).map(|(a, b)| a + alpha * b).collect();
            let (g_trial, grads_trial) = evaluate(network, &trial, &constraints);
            let v = max_abs(&g_trial);
            if v.is_finite() && (v < (1.0 - 1e-4 * alpha) * violation || v <= 1e-12) {
                x = trial;
                g = g_trial;
                grads = grads_trial;
                accepted = true;
                break;
            }
            alpha *= 0.5;
        }
        if !accepted {
            break;
        }
        info.iterations = iteration + 1;
    }
    info.constraint_violation = max_abs(&g);
    info.converged = info.constraint_violation <= REFINEMENT_BOUND;
    info.displacement_max = (0..n / 3)
        .map(|i| {
            Vec3::new(
                x[3 * i] - x_linear[3 * i],
                x[3 * i + 1] - x_linear[3 * i + 1],
                x[3 * i + 2] - x_linear[3 * i + 2],
            )
            .norm()
        })
        .fold(0.0, f64::max);
    Ok((x, info))
}

use crate::{LeastSquaresProblem, LevenbergMarquardtOptions, SolverInfo};
use nalgebra::{DMatrix, DVector};
use std::ops::AddAssign;

/// `min_x ½ |r(x)|²` subject to equality constraints `c(x) = 0`, with exact Jacobians.
pub trait ConstrainedLeastSquaresProblem: LeastSquaresProblem {
    /// Constraint values `c(x)`.
    fn constraints(&self, x: &DVector<f64>) -> DVector<f64>;
    /// Constraint Jacobian `∂c/∂x`.
    fn constraint_jacobian(&self, x: &DVector<f64>) -> DMatrix<f64>;
    /// The constraints' curvature weighted by the multipliers, `Σ_i λ_i ∇²c_i(x)`, if
    /// known. Without it the step converges only linearly on curved constraints.
    fn constraint_curvature(&self, x: &DVector<f64>, multipliers: &DVector<f64>) -> Option<DMatrix<f64>> {
        let _ = (x, multipliers);
        None
    }
    /// The residuals' own curvature, `Σ_i r_i ∇²r_i(x)`, for the residuals where it is
    /// known and matters (large residuals on curved functions), if any. The Gauss–Newton
    /// Hessian `JᵀJ` leaves it out; when `F` is dominated by such residuals the steps are
    /// systematically too long and the damping stalls the solver.
    fn residual_curvature(&self, x: &DVector<f64>) -> Option<DMatrix<f64>> {
        let _ = x;
        None
    }
}

/// Knobs of [`constrained_levenberg_marquardt`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConstrainedOptions {
    /// The unconstrained knobs (iterations, tolerances, initial damping).
    pub base: LevenbergMarquardtOptions,
    /// Converged only when `max |c| ≤ constraint_tolerance`.
    pub constraint_tolerance: f64,
}

impl Default for ConstrainedOptions {
    fn default() -> Self {
        Self {
            base: LevenbergMarquardtOptions::default(),
            constraint_tolerance: 1e-10,
        }
    }
}

/// What [`constrained_levenberg_marquardt`] did: the usual [`SolverInfo`] and the largest
/// constraint violation at the end.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ConstrainedInfo {
    /// Iterations, cost, projected gradient norm, converged.
    pub solver: SolverInfo,
    /// `max |c(x)|` at the end.
    pub constraint_violation: f64,
}

/// The matrices `Zᵀ M Z` for an orthonormal basis `Z` of the null space of the
/// constraint Jacobian `C` (`m × n`), the constraints' tangent space.
///
/// `Z` is never formed: Householder reflections `P_1 … P_r` that bring `Cᵀ` to upper
/// triangular form (`Q = P_1 ⋯ P_r`, whose first `r` columns span the range of `Cᵀ`) are
/// applied to `M` from both sides, and `Zᵀ M Z` is the trailing `(n − r)` block of
/// `Qᵀ M Q`: `O(m n²)` instead of the `O(n³)` of forming `Z`. Columns of `Cᵀ` that are
/// numerically dependent on the previous ones (redundant constraints) are skipped, so
/// `r = rank C`; their indices are returned with the blocks.
fn tangent_blocks(cj: &DMatrix<f64>, matrices: &[&DMatrix<f64>]) -> (Vec<DMatrix<f64>>, Vec<usize>) {
    let (m, n) = cj.shape();
    let mut columns = cj.transpose();
    let mut out: Vec<DMatrix<f64>> = matrices.iter().map(|&a| a.clone()).collect();
    let scale = columns.norm().max(1e-300);
    let mut rank = 0;
    let mut independent = Vec::with_capacity(m);
    for k in 0..m {
        if rank == n {
            break;
        }
        let mut v = columns.view((rank, k), (n - rank, 1)).into_owned();
        let norm = v.norm();
        if norm <= 1e-12 * scale {
            continue;
        }
        // v = x + sign(x_0) |x| e_0, reflection P = I − 2 v vᵀ / vᵀv.
        v[0] += norm.copysign(v[0]);
        let beta = 2.0 / v.norm_squared();
        let reflect_rows = |a: &mut DMatrix<f64>, rows_from: usize| {
            let mut block = a.rows_mut(rows_from, n - rows_from);
            let w = block.tr_mul(&v) * beta;
            block -= &v * w.transpose();
        };
        reflect_rows(&mut columns, rank);
        for a in &mut out {
            reflect_rows(a, rank);
            let mut block = a.columns_mut(rank, n - rank);
            let w = &block * &v * beta;
            block -= w * v.transpose();
        }
        rank += 1;
        independent.push(k);
    }
    let blocks = out
        .into_iter()
        .map(|a| a.view((rank, rank), (n - rank, n - rank)).into_owned())
        .collect();
    (blocks, independent)
}

/// Most sweeps of the SVD that gives a singular KKT system its minimum-norm step (a few
/// dozen suffice for the systems here; the bound keeps a pathological one from running
/// on).
const MAX_SVD_SWEEPS: usize = 10_000;

/// Levenberg–Marquardt with linearised equality constraints (an SQP-type step).
///
/// Each step solves the damped KKT system
/// `[H + μ diag(JᵀJ), Cᵀ; C, 0] [δ; λ] = [−Jᵀr; −τ c]`,
/// `H = JᵀJ + Σ_k r_k ∇²r_k + Σ_i λ_i ∇²c_i` (the Hessian of the Lagrangian with the
/// least-squares multipliers `λ = −(CCᵀ)⁻¹ C Jᵀr` of the current point; each curvature
/// term only when the problem provides it, otherwise the Gauss–Newton part alone). With
/// curvature terms `H` can be indefinite on the constraints' tangent space (near a saddle
/// or a maximum); then `μ` is raised until `Zᵀ(H + μD)Z` is positive definite (`Z` a
/// basis of the tangent space: inertia control, N&W §16.2), and a stalled cost does not
/// count as convergence there,
/// (by LU, or by SVD when redundant constraints make it singular),
/// so the step moves onto the linearised constraint (`τ = 1`; halved after a rejected
/// step, reset after an accepted one) while the damping shortens only the part along it.
/// Steps are accepted by the gain ratio on the exact ℓ1 merit function
/// `φ = ½|r|² + ν |c|₁` with `ν ≥ 2 |λ|∞`, and large enough that the step predicts a decrease (N&W Eq. 18.36; never lowered) (Nocedal & Wright 2006, §15.4, §18.3), and `μ`
/// follows Nielsen's update as in [`crate::levenberg_marquardt`]. Converged when
/// `max |c| ≤ constraint_tolerance` and the gradient projected onto the constraints'
/// tangent space is small relative to its start, or an accepted step no longer changes
/// the cost or the unknowns.
///
/// Unlike a quadratic penalty, the constraint is met to the tolerance without driving a
/// weight to infinity, so the problem's conditioning does not degrade.
pub fn constrained_levenberg_marquardt(
    problem: &impl ConstrainedLeastSquaresProblem,
    x0: DVector<f64>,
    options: &ConstrainedOptions,
) -> (DVector<f64>, ConstrainedInfo) {
    let base = &options.base;
    let n = x0.len();
    let mut x = x0;
    let mut r = problem.residuals(&x);
    let mut c = problem.constraints(&x);
    let m = c.len();
    let mut j = problem.jacobian(&x);
    let mut cj = problem.constraint_jacobian(&x);
    let mut a = j.transpose() * &j;
    let mut g = j.transpose() * &r;
    let mut cost = 0.5 * r.norm_squared();
    let max_diag = (0..n).map(|i| a[(i, i)]).fold(0.0, f64::max).max(1e-300);
    let mut mu = base.initial_damping * max_diag;
    let mut growth = 2.0;
    let mut tau = 1.0;
    let mut info = ConstrainedInfo {
        solver: SolverInfo {
            initial_cost: cost,
            ..Default::default()
        },
        ..Default::default()
    };
    // Least-squares multipliers λ = −(CCᵀ)⁻¹ C g and the projected gradient g + Cᵀλ.
    let projected = |g: &DVector<f64>, cj: &DMatrix<f64>| -> (f64, DVector<f64>) {
        if m == 0 {
            return (g.norm(), DVector::zeros(0));
        }
        let cct = cj * cj.transpose();
        match cct.cholesky() {
            Some(ch) => {
                let lambda = -ch.solve(&(cj * g));
                ((g + cj.transpose() * &lambda).norm(), lambda)
            }
            None => (g.norm(), DVector::zeros(m)),
        }
    };
    let (mut gradient, mut multipliers) = projected(&g, &cj);
    let mut merit_weight: f64 = 2.0 * multipliers.amax() + 1e-12;
    let gradient_limit = base.gradient_tolerance * gradient.max(1e-300);
    let violation = |c: &DVector<f64>| c.iter().fold(0.0f64, |v, e| v.max(e.abs()));
    // One `tracing` debug line per iteration (`SHEETFORM_TRACE=1` shows them in the CLI).
    for it in 0..base.max_iterations {
        info.solver.iterations = it;
        if problem.stop_requested() {
            break;
        }
        let feasible = violation(&c) <= options.constraint_tolerance;
        if feasible && gradient <= gradient_limit {
            info.solver.converged = true;
            break;
        }
        let mut hessian = a.clone();
        if let Some(curvature) = problem.residual_curvature(&x) {
            hessian.add_assign(&curvature);
        }
        if let Some(curvature) = problem.constraint_curvature(&x, &multipliers) {
            hessian.add_assign(&curvature);
        }
        // Inertia control (N&W §16.2, §18.3): the step is a minimiser of the model only
        // if the damped Hessian is positive definite on the constraints' tangent space;
        // the exact Hessian of the Lagrangian need not be (near a saddle, e.g. a
        // symmetric start), and Newton steps would then converge to the saddle. Raise μ
        // until `Zᵀ(H + μD)Z` has a Cholesky factor.
        let damping = DVector::from_iterator(n, (0..n).map(|i| a[(i, i)].max(1e-12 * max_diag)));
        let (blocks, independent) = tangent_blocks(&cj, &[&hessian, &DMatrix::from_diagonal(&damping)]);
        let [reduced, reduced_damping]: [DMatrix<f64>; 2] = blocks.try_into().expect("two blocks");
        let convex = (&reduced + &reduced_damping * (1e-12)).cholesky().is_some();
        let mut raised = 0;
        while (&reduced + &reduced_damping * mu).cholesky().is_none() && raised < 100 {
            mu = (mu * 4.0).max(1e-12);
            raised += 1;
        }
        // Only the linearly independent constraints enter the KKT system: redundant ones
        // (e.g. two that coincide at a symmetric start) would make it singular.
        let k = independent.len();
        let mut kkt = DMatrix::zeros(n + k, n + k);
        kkt.view_mut((0, 0), (n, n)).copy_from(&hessian);
        for i in 0..n {
            kkt[(i, i)] += mu * damping[i];
        }
        let mut rhs = DVector::zeros(n + k);
        rhs.rows_mut(0, n).copy_from(&(-&g));
        for (row, &e) in independent.iter().enumerate() {
            for col in 0..n {
                kkt[(n + row, col)] = cj[(e, col)];
                kkt[(col, n + row)] = cj[(e, col)];
            }
            rhs[n + row] = -c[e] * tau;
        }
        // Should the system still be singular: the minimum-norm least-squares solution.
        let solution = kkt
            .clone()
            .lu()
            .solve(&rhs)
            .filter(|x| x.iter().all(|v| v.is_finite()))
            .or_else(|| {
                tracing::debug!("constrained LM: singular KKT system, minimum-norm step by SVD");
                // (nalgebra's SVD iterates until it converges, which a matrix with a
                // non-finite entry never does: such a system has no step, and the SVD's
                // sweeps are bounded.)
                if !kkt.iter().all(|v| v.is_finite()) {
                    return None;
                }
                let svd = kkt.try_svd(true, true, f64::EPSILON, MAX_SVD_SWEEPS)?;
                let tolerance = 1e-13 * svd.singular_values.max();
                svd.solve(&rhs, tolerance).ok()
            });
        let Some(solution) = solution else {
            mu *= growth;
            growth *= 2.0;
            continue;
        };
        let step = solution.rows(0, n).into_owned();
        let c1 = c.iter().map(|e| e.abs()).sum::<f64>();
        let model_increase = step.dot(&g) + 0.5 * step.dot(&(&hessian * &step));
        if c1 > 0.0 {
            // ν large enough that the step predicts a merit decrease (N&W Eq. 18.36).
            merit_weight = merit_weight.max(model_increase / (0.5 * tau * c1));
        }
        let predicted = -model_increase + merit_weight * tau * c1;
        let merit = cost + merit_weight * c1;
        let evaluate = |candidate: DVector<f64>| {
            let r_new = problem.residuals(&candidate);
            let c_new = problem.constraints(&candidate);
            let cost_new = 0.5 * r_new.norm_squared();
            let merit_new = cost_new + merit_weight * c_new.iter().map(|e| e.abs()).sum::<f64>();
            (candidate, r_new, c_new, cost_new, merit_new)
        };
        let mut trial = evaluate(&x + &step);
        // Second-order correction (N&W §15.6): the step's own constraint error, of second
        // order, is projected out along Cᵀ (in the diag(JᵀJ) metric) so the merit test sees
        // the tangential progress instead of the constraint's curvature. Repeated (up to
        // three times, with the same C) while it lowers the merit: on strongly curved
        // constraints one projection leaves an error comparable to the progress.
        if m > 0 && trial.2.iter().all(|v| v.is_finite()) {
            let scaled = DMatrix::from_fn(n, m, |i, k| cj[(k, i)] / damping[i]);
            if let Some(ch) = (&cj * &scaled).cholesky() {
                for _ in 0..3 {
                    let correction = -(&scaled * ch.solve(&trial.2));
                    let corrected = evaluate(&trial.0 + correction);
                    if corrected.4 < trial.4 {
                        trial = corrected;
                    } else {
                        break;
                    }
                }
            }
        }
        let (candidate, r_new, c_new, cost_new, merit_new) = trial;
        let rho = if predicted > 0.0 {
            (merit - merit_new) / predicted
        } else {
            -1.0
        };
        info.solver.iterations = it + 1;
        tracing::debug!(
            "constrained LM {it}: cost {cost:.6e} -> {cost_new:.6e}, max |c| {:.2e} -> {:.2e}, rho {rho:.3}, mu {mu:.2e}, tau {tau}, |step| {:.2e}, projected gradient {gradient:.2e}",
            violation(&c),
            violation(&c_new),
            step.norm()
        );
        if rho > 1e-4 && merit_new.is_finite() {
            let change = (cost - cost_new).abs() / cost.max(1e-300);
            let small_step = step.norm() <= base.step_tolerance * (x.norm() + base.step_tolerance);
            x = candidate;
            r = r_new;
            c = c_new;
            cost = cost_new;
            j = problem.jacobian(&x);
            cj = problem.constraint_jacobian(&x);
            a = j.transpose() * &j;
            g = j.transpose() * &r;
            (gradient, multipliers) = projected(&g, &cj);
            merit_weight = merit_weight.max(2.0 * multipliers.amax() + 1e-12);
            mu *= (1.0f64 / 3.0).max(1.0 - (2.0 * rho - 1.0).powi(3));
            growth = 2.0;
            tau = 1.0;
            // A stalled cost or step counts as converged only where the model was convex
            // (not at a saddle, where the steps are short because the curvature is).
            if violation(&c) <= options.constraint_tolerance
                && (gradient <= gradient_limit || (convex && (change < base.cost_tolerance || small_step)))
            {
                info.solver.converged = true;
                break;
            }
        } else {
            mu *= growth;
            growth *= 2.0;
            tau = (tau * 0.5).max(1.0 / 64.0);
            if !mu.is_finite() || mu > 1e30 * max_diag {
                break;
            }
        }
    }
    info.solver.cost = cost;
    info.solver.gradient_norm = gradient;
    info.constraint_violation = violation(&c);
    (x, info)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `min ½ |W (v − t)|²` on the unit circle, `W = diag(weights)`.
    struct OnCircle {
        weights: [f64; 2],
        target: [f64; 2],
    }
    impl LeastSquaresProblem for OnCircle {
        fn residuals(&self, v: &DVector<f64>) -> DVector<f64> {
            DVector::from_fn(2, |i, _| self.weights[i] * (v[i] - self.target[i]))
        }
        fn jacobian(&self, _: &DVector<f64>) -> DMatrix<f64> {
            DMatrix::from_diagonal(&DVector::from_row_slice(&self.weights))
        }
    }
    impl ConstrainedLeastSquaresProblem for OnCircle {
        fn constraints(&self, v: &DVector<f64>) -> DVector<f64> {
            DVector::from_vec(vec![v[0] * v[0] + v[1] * v[1] - 1.0])
        }
        fn constraint_jacobian(&self, v: &DVector<f64>) -> DMatrix<f64> {
            DMatrix::from_row_slice(1, 2, &[2.0 * v[0], 2.0 * v[1]])
        }
        fn constraint_curvature(&self, _: &DVector<f64>, l: &DVector<f64>) -> Option<DMatrix<f64>> {
            Some(DMatrix::identity(2, 2) * (2.0 * l[0]))
        }
    }

    /// The nearest point to (2, 1) on the unit circle: (2, 1)/√5.
    const NEAREST_POINT: OnCircle = OnCircle {
        weights: [1.0, 1.0],
        target: [2.0, 1.0],
    };

    /// `min ½(x² + ¼y²)` on the unit circle: the minima are `(0, ±1)`; `(±1, 0)` are
    /// maxima on the circle, where the exact Hessian of the Lagrangian is negative along
    /// the circle.
    const ELLIPSE: OnCircle = OnCircle {
        weights: [1.0, 0.5],
        target: [0.0, 0.0],
    };

    #[test]
    fn leaves_a_maximum_on_the_constraint_for_a_minimum() {
        // Started next to the maximum (1, 0): plain Newton steps on the KKT system would
        // converge to it; inertia control turns them downhill.
        let (x, info) = constrained_levenberg_marquardt(
            &ELLIPSE,
            DVector::from_vec(vec![1.0, 1e-3]),
            &ConstrainedOptions::default(),
        );
        assert!(info.solver.converged, "{info:?}");
        assert!(x[0].abs() < 1e-6 && (x[1].abs() - 1.0).abs() < 1e-9, "{x:?}");
        assert!((info.solver.cost - 0.125).abs() < 1e-12, "{info:?}");
    }

    #[test]
    fn tangent_blocks_are_the_reduced_matrices() {
        // C of rank 2 (the third row is twice the first); M symmetric positive definite.
        // The eigenvalues of Zᵀ M Z are the non-zero eigenvalues of P M P, P the
        // orthogonal projector onto the null space of C (built from an SVD).
        let c = DMatrix::from_row_slice(3, 4, &[1.0, 2.0, 0.0, -1.0, 0.0, 1.0, 1.0, 0.0, 2.0, 4.0, 0.0, -2.0]);
        let m = DMatrix::from_fn(4, 4, |i, j| {
            1.0 / (1.0 + i as f64 + j as f64) + if i == j { 1.0 } else { 0.0 }
        });
        let (mut blocks, independent) = tangent_blocks(&c, &[&m]);
        assert_eq!(independent, vec![0, 1]);
        let reduced = blocks.remove(0);
        assert_eq!(reduced.shape(), (2, 2));
        let range = c.transpose().svd(true, false).u.unwrap().columns(0, 2).into_owned();
        let projector = DMatrix::<f64>::identity(4, 4) - &range * range.transpose();
        let projected = &projector * &m * &projector;
        let sorted = |v: Vec<f64>| {
            let mut v = v;
            v.sort_by(f64::total_cmp);
            v
        };
        let e1 = sorted(reduced.symmetric_eigenvalues().iter().copied().collect());
        let e2 = sorted(
            projected
                .symmetric_eigenvalues()
                .iter()
                .copied()
                .filter(|v| v.abs() > 1e-12)
                .collect(),
        );
        assert_eq!(e1.len(), e2.len());
        for (a, b) in e1.iter().zip(&e2) {
            assert!((a - b).abs() < 1e-12, "{e1:?} vs {e2:?}");
        }
    }

    #[test]
    fn finds_the_nearest_point_on_a_circle() {
        let (x, info) = constrained_levenberg_marquardt(
            &NEAREST_POINT,
            DVector::from_vec(vec![-0.3, 2.0]),
            &ConstrainedOptions {
                base: LevenbergMarquardtOptions {
                    cost_tolerance: 0.0,
                    ..Default::default()
                },
                ..Default::default()
            },
        );
        assert!(info.solver.converged, "{info:?}");
        let s = 5f64.sqrt();
        assert!((x[0] - 2.0 / s).abs() < 1e-9 && (x[1] - 1.0 / s).abs() < 1e-9, "{x:?}");
        assert!(info.constraint_violation < 1e-10);
    }

    /// Issue 35: weights whose squares overflow (a slit scene's weight of 1e200) made the
    /// KKT system infinite, and the SVD taken for its step never converged: the solve hung.
    /// It now ends within its iterations, not converged, with finite unknowns.
    #[test]
    fn an_overflowing_problem_ends_within_its_iterations() {
        let huge = OnCircle {
            weights: [1e200, 1e200],
            target: [2.0, 1.0],
        };
        let options = ConstrainedOptions {
            base: LevenbergMarquardtOptions {
                max_iterations: 50,
                ..Default::default()
            },
            constraint_tolerance: 1e-10,
        };
        let (x, info) = constrained_levenberg_marquardt(&huge, DVector::from_vec(vec![1.0, 0.0]), &options);
        assert!(!info.solver.converged);
        assert!(info.solver.iterations < 50);
        assert!(x.iter().all(|v| v.is_finite()));
    }

    /// A problem that asks to stop is left at once, not converged.
    #[test]
    fn a_stop_request_ends_the_solve() {
        struct Stopping(OnCircle);
        impl LeastSquaresProblem for Stopping {
            fn residuals(&self, v: &DVector<f64>) -> DVector<f64> {
                self.0.residuals(v)
            }
            fn jacobian(&self, v: &DVector<f64>) -> DMatrix<f64> {
                self.0.jacobian(v)
            }
            fn stop_requested(&self) -> bool {
                true
            }
        }
        impl ConstrainedLeastSquaresProblem for Stopping {
            fn constraints(&self, v: &DVector<f64>) -> DVector<f64> {
                self.0.constraints(v)
            }
            fn constraint_jacobian(&self, v: &DVector<f64>) -> DMatrix<f64> {
                self.0.constraint_jacobian(v)
            }
        }
        let problem = Stopping(NEAREST_POINT);
        let (x, info) = constrained_levenberg_marquardt(
            &problem,
            DVector::from_vec(vec![1.0, 0.0]),
            &ConstrainedOptions::default(),
        );
        assert_eq!((info.solver.iterations, info.solver.converged), (0, false));
        assert_eq!(x.as_slice(), &[1.0, 0.0]);
        let (_, info) = crate::levenberg_marquardt(&problem, DVector::from_vec(vec![1.0, 0.0]), &Default::default());
        assert_eq!((info.iterations, info.converged), (0, false));
    }
}

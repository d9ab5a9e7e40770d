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

/// Levenberg–Marquardt with linearised equality constraints (an SQP-type step).
///
/// Each step solves the damped KKT system
/// `[H + μ diag(JᵀJ), Cᵀ; C, 0] [δ; λ] = [−Jᵀr; −τ c]`, `H = JᵀJ + Σ λ_i ∇²c_i` (the
/// Gauss–Newton Hessian of the Lagrangian with the least-squares multipliers
/// `λ = −(CCᵀ)⁻¹ C Jᵀr` of the current point; the curvature term only when the problem
/// provides it),
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
    for it in 0..base.max_iterations {
        info.solver.iterations = it;
        let feasible = violation(&c) <= options.constraint_tolerance;
        if feasible && gradient <= gradient_limit {
            info.solver.converged = true;
            break;
        }
        let mut kkt = DMatrix::zeros(n + m, n + m);
        kkt.view_mut((0, 0), (n, n)).copy_from(&a);
        if let Some(curvature) = problem.constraint_curvature(&x, &multipliers) {
            kkt.view_mut((0, 0), (n, n)).add_assign(&curvature);
        }
        for i in 0..n {
            kkt[(i, i)] += mu * a[(i, i)].max(1e-12 * max_diag);
        }
        kkt.view_mut((n, 0), (m, n)).copy_from(&cj);
        kkt.view_mut((0, n), (n, m)).copy_from(&cj.transpose());
        let mut rhs = DVector::zeros(n + m);
        rhs.rows_mut(0, n).copy_from(&(-&g));
        rhs.rows_mut(n, m).copy_from(&(-&c * tau));
        // Redundant constraints (e.g. two that coincide at a symmetric start) make the
        // KKT matrix singular: then the minimum-norm least-squares solution by SVD.
        let solution = kkt
            .clone()
            .lu()
            .solve(&rhs)
            .filter(|x| x.iter().all(|v| v.is_finite()))
            .or_else(|| {
                let svd = kkt.svd(true, true);
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
        let model_increase = step.dot(&g) + 0.5 * step.dot(&(&a * &step));
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
        // the tangential progress instead of the constraint's curvature.
        if m > 0 && trial.2.iter().all(|v| v.is_finite()) {
            let weights = DVector::from_iterator(n, (0..n).map(|i| 1.0 / a[(i, i)].max(1e-12 * max_diag)));
            let scaled = DMatrix::from_fn(n, m, |i, k| weights[i] * cj[(k, i)]);
            if let Some(ch) = (&cj * &scaled).cholesky() {
                let correction = -(&scaled * ch.solve(&trial.2));
                let corrected = evaluate(&trial.0 + correction);
                if corrected.4 < trial.4 {
                    trial = corrected;
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
            if violation(&c) <= options.constraint_tolerance
                && (gradient <= gradient_limit || change < base.cost_tolerance || small_step)
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

    /// Nearest point to (2, 1) on the unit circle: (2, 1)/√5.
    struct CirclePoint;
    impl LeastSquaresProblem for CirclePoint {
        fn residuals(&self, v: &DVector<f64>) -> DVector<f64> {
            DVector::from_vec(vec![v[0] - 2.0, v[1] - 1.0])
        }
        fn jacobian(&self, _: &DVector<f64>) -> DMatrix<f64> {
            DMatrix::identity(2, 2)
        }
    }
    impl ConstrainedLeastSquaresProblem for CirclePoint {
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

    #[test]
    fn finds_the_nearest_point_on_a_circle() {
        let (x, info) = constrained_levenberg_marquardt(
            &CirclePoint,
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
}

use crate::SolverInfo;
use nalgebra::{DMatrix, DVector};

/// A nonlinear least-squares problem `min_x ½ |r(x)|²` with an exact Jacobian.
pub trait LeastSquaresProblem {
    /// Residuals `r(x)`.
    fn residuals(&self, x: &DVector<f64>) -> DVector<f64>;
    /// Jacobian `∂r/∂x` (rows: residuals, columns: unknowns).
    fn jacobian(&self, x: &DVector<f64>) -> DMatrix<f64>;
    /// Whether the solve should stop now (a cancelled run: Ctrl-C, an abandoned editor
    /// request). Asked once an iteration; the solvers then return where they are, not
    /// converged. Default: never.
    fn stop_requested(&self) -> bool {
        false
    }
}

/// Knobs of [`levenberg_marquardt`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LevenbergMarquardtOptions {
    /// Most iterations.
    pub max_iterations: usize,
    /// Stop when `|Jᵀr| ≤ gradient_tolerance · |Jᵀr|₀` (relative to the start).
    pub gradient_tolerance: f64,
    /// Stop when a step is shorter than `step_tolerance · (|x| + step_tolerance)`.
    pub step_tolerance: f64,
    /// Stop when a step changes the cost by less than this fraction.
    pub cost_tolerance: f64,
    /// Initial damping `μ` (relative to the largest diagonal entry of `JᵀJ`).
    pub initial_damping: f64,
}

impl Default for LevenbergMarquardtOptions {
    fn default() -> Self {
        Self {
            max_iterations: 100,
            gradient_tolerance: 1e-10,
            step_tolerance: 1e-12,
            cost_tolerance: 1e-12,
            initial_damping: 1e-3,
        }
    }
}

/// Levenberg–Marquardt (Nielsen's damping update) for small dense problems:
/// solve `(JᵀJ + μ diag(JᵀJ)) δ = −Jᵀr`, accept the step if the cost drops, and update
/// `μ` from the gain ratio. Converged when the gradient is small relative to its initial
/// size, the step is negligible, or an accepted step no longer lowers the cost. Returns
/// the solution and a [`SolverInfo`].
pub fn levenberg_marquardt(
    problem: &impl LeastSquaresProblem,
    x0: DVector<f64>,
    options: &LevenbergMarquardtOptions,
) -> (DVector<f64>, SolverInfo) {
    let mut x = x0;
    let mut r = problem.residuals(&x);
    let mut cost = 0.5 * r.norm_squared();
    let initial_cost = cost;
    let mut j = problem.jacobian(&x);
    let mut g = j.transpose() * &r;
    let mut a = j.transpose() * &j;
    let max_diag = (0..a.nrows()).map(|i| a[(i, i)]).fold(0.0, f64::max).max(1e-300);
    let mut mu = options.initial_damping * max_diag;
    let mut nu = 2.0;
    let mut info = SolverInfo {
        initial_cost,
        ..Default::default()
    };
    let gradient_limit = options.gradient_tolerance * g.norm();
    for it in 0..options.max_iterations {
        info.iterations = it;
        if problem.stop_requested() {
            break;
        }
        if g.norm() <= gradient_limit {
            info.converged = true;
            break;
        }
        let mut damped = a.clone();
        for i in 0..damped.nrows() {
            damped[(i, i)] += mu * a[(i, i)].max(1e-12 * max_diag);
        }
        let Some(chol) = damped.cholesky() else {
            mu *= nu;
            nu *= 2.0;
            continue;
        };
        let step = chol.solve(&(-&g));
        if step.norm() <= options.step_tolerance * (x.norm() + options.step_tolerance) {
            info.converged = true;
            info.iterations = it;
            break;
        }
        let candidate = &x + &step;
        let r_new = problem.residuals(&candidate);
        let cost_new = 0.5 * r_new.norm_squared();
        let predicted = -(step.dot(&g) + 0.5 * step.dot(&(&a * &step)));
        let rho = if predicted > 0.0 {
            (cost - cost_new) / predicted
        } else {
            -1.0
        };
        if rho > 0.0 && cost_new.is_finite() {
            let change = (cost - cost_new) / cost.max(1e-300);
            x = candidate;
            r = r_new;
            cost = cost_new;
            j = problem.jacobian(&x);
            g = j.transpose() * &r;
            a = j.transpose() * &j;
            mu *= (1.0f64 / 3.0).max(1.0 - (2.0 * rho - 1.0).powi(3));
            nu = 2.0;
            if change < options.cost_tolerance {
                info.converged = true;
                info.iterations = it + 1;
                break;
            }
        } else {
            mu *= nu;
            nu *= 2.0;
        }
        info.iterations = it + 1;
    }
    info.cost = cost;
    info.gradient_norm = g.norm();
    if info.gradient_norm <= gradient_limit {
        info.converged = true;
    }
    (x, info)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rosenbrock as least squares: r = (10 (y − x²), 1 − x).
    struct Rosenbrock;
    impl LeastSquaresProblem for Rosenbrock {
        fn residuals(&self, v: &DVector<f64>) -> DVector<f64> {
            DVector::from_vec(vec![10.0 * (v[1] - v[0] * v[0]), 1.0 - v[0]])
        }
        fn jacobian(&self, v: &DVector<f64>) -> DMatrix<f64> {
            DMatrix::from_row_slice(2, 2, &[-20.0 * v[0], 10.0, -1.0, 0.0])
        }
    }

    #[test]
    fn solves_rosenbrock() {
        let (x, info) = levenberg_marquardt(&Rosenbrock, DVector::from_vec(vec![-1.2, 1.0]), &Default::default());
        assert!(info.converged, "{info:?}");
        assert!((x[0] - 1.0).abs() < 1e-8 && (x[1] - 1.0).abs() < 1e-8);
        assert!(info.cost < 1e-16 && info.initial_cost > 1.0);
    }
}

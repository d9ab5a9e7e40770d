//! The paper's solver: a penalty function minimised by a few conjugate-gradient steps
//! per penalty weight (Wang & Tang 2004 §3).

use crate::{DevelopabilityProblem, Evaluation, RestorationInfo};
use nalgebra::Vector3;
use std::time::Instant;

/// Knobs of [`restore_paper`]; the defaults are the paper's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PaperOptions {
    /// Conjugate-gradient steps per penalty weight (the paper: 5).
    pub conjugate_gradient_steps: usize,
    /// `N_max`, most penalty updates (the paper: 200).
    pub max_steps: usize,
    /// `ε`: stop when `|G[X_i] − G[X_{i−1}]| / G[X₀] < ε` (the paper: 0.01 %).
    pub relative_change: f64,
}

impl Default for PaperOptions {
    fn default() -> Self {
        Self {
            conjugate_gradient_steps: 5,
            max_steps: 200,
            relative_change: 1e-4,
        }
    }
}

/// The paper's numerical scheme (§3, Eq. 3-1):
///
/// `J(X) = E(X) + (ρ_k / 2) G(X)²`, `ρ_k = (1/n_e) Σ_j (l⁰_j)² / G[X_k]²`,
///
/// minimised for each `ρ_k` by `conjugate_gradient_steps` Polak–Ribière (PR+)
/// conjugate-gradient steps from `X_k`, giving `X_{k+1}`; stop when the relative change
/// of `G` is below `ε` or after `N_max` updates. Linked vertices share their parameters
/// (the paper's "modified gradients" make them move alike; sharing is the same thing).
///
/// Departures, all in the paper's favour and none changing the scheme: exact gradients
/// (the paper takes the gradient of `G` by central differences), an Armijo backtracking
/// line search (the paper does not say which it used), and `n_e` and the sums over the
/// springs of the selected nodes only (edges between fixed nodes never change).
pub fn restore_paper(
    problem: &DevelopabilityProblem<'_>,
    options: &PaperOptions,
) -> (Vec<Vector3<f64>>, RestorationInfo) {
    restore_paper_with_progress(problem, options, &mut |_, _| {})
}

/// [`restore_paper`], calling `progress(step, largest |defect|)` at the start (step 0)
/// and after each penalty update.
pub fn restore_paper_with_progress(
    problem: &DevelopabilityProblem<'_>,
    options: &PaperOptions,
    progress: &mut dyn FnMut(usize, f64),
) -> (Vec<Vector3<f64>>, RestorationInfo) {
    let start = Instant::now();
    let mut y = problem.gather(&problem.start);
    let mut e = problem.evaluate(&y);
    let mut info = RestorationInfo::begin(crate::SolverMethod::Paper, problem, &e);
    progress(0, info.angle_defect_max_before_rad);
    let g0 = problem.developability_g(&e);
    if problem.variables.is_empty() || g0 == 0.0 {
        info.finish(problem, &e, 0, true, start);
        return (e.parameters, info);
    }
    let mean_rest_square = problem
        .springs
        .iter()
        .map(|s| s.rest_length * s.rest_length)
        .sum::<f64>()
        / problem.springs.len().max(1) as f64;
    let mut g_previous = g0;
    let mut steps = 0;
    let mut converged = false;
    let mut alpha = f64::NAN;
    while steps < options.max_steps {
        if problem.check_cancelled().is_err() {
            break;
        }
        steps += 1;
        let rho = mean_rest_square / (g_previous * g_previous);
        let mut gradient = penalty_gradient(problem, &e, rho);
        let mut direction: Vec<f64> = gradient.iter().map(|g| -g).collect();
        let mut value = penalty(problem, &e, rho);
        if alpha.is_nan() {
            // First step: move the parameters by at most 1e-3 of the domain.
            alpha = 0.5e-3 / gradient.iter().fold(f64::MIN_POSITIVE, |m, g| m.max(g.abs()));
        }
        for _ in 0..options.conjugate_gradient_steps {
            let mut slope: f64 = gradient.iter().zip(&direction).map(|(g, d)| g * d).sum();
            if slope >= 0.0 {
                direction = gradient.iter().map(|g| -g).collect();
                slope = -gradient.iter().map(|g| g * g).sum::<f64>();
            }
            if slope == 0.0 {
                break;
            }
            // Armijo backtracking from twice the last accepted step.
            let mut step = alpha * 2.0;
            let mut accepted = None;
            for _ in 0..40 {
                let trial_y: Vec<f64> = y.iter().zip(&direction).map(|(a, d)| a + step * d).collect();
                let trial = problem.evaluate(&trial_y);
                let trial_value = penalty(problem, &trial, rho);
                if trial_value <= value + 1e-4 * step * slope {
                    accepted = Some((trial_y, trial, trial_value));
                    break;
                }
                step *= 0.5;
            }
            let Some((new_y, new_e, new_value)) = accepted else {
                break;
            };
            alpha = step;
            y = new_y;
            e = new_e;
            value = new_value;
            let new_gradient = penalty_gradient(problem, &e, rho);
            // Polak–Ribière with restart (PR+).
            let numerator: f64 = new_gradient.iter().zip(&gradient).map(|(n, o)| n * (n - o)).sum();
            let denominator: f64 = gradient.iter().map(|g| g * g).sum();
            let b = if denominator > 0.0 {
                (numerator / denominator).max(0.0)
            } else {
                0.0
            };
            direction = direction.iter().zip(&new_gradient).map(|(d, g)| -g + b * d).collect();
            gradient = new_gradient;
        }
        let g = problem.developability_g(&e);
        let change = (g - g_previous).abs() / g0;
        g_previous = g;
        progress(steps, e.defects.iter().fold(0.0, |m: f64, d| m.max(d.abs())));
        if change < options.relative_change || g == 0.0 {
            converged = true;
            break;
        }
    }
    info.finish(problem, &e, steps, converged, start);
    (e.parameters, info)
}

/// `J = E + (ρ/2) G²`.
fn penalty(problem: &DevelopabilityProblem<'_>, e: &Evaluation, rho: f64) -> f64 {
    let g = problem.developability_g(e);
    problem.spring_energy(e) + 0.5 * rho * g * g
}

/// `∇J = ∇E + ρ G ∇G`, `∇E = Σ 2 r_j ∇r_j`, `∇G = Σ 2 g_i ∇g_i`.
fn penalty_gradient(problem: &DevelopabilityProblem<'_>, e: &Evaluation, rho: f64) -> Vec<f64> {
    let mut out = vec![0.0; problem.unknown_count()];
    for (s, r) in e.spring_residuals.iter().enumerate() {
        for (v, d) in problem.spring_gradient(e, s) {
            if v != u32::MAX {
                for k in 0..3 {
                    out[3 * v as usize + k] += 2.0 * r * d[k];
                }
            }
        }
    }
    let g = problem.developability_g(e);
    let mut row = Vec::new();
    for (c, defect) in e.defects.iter().enumerate() {
        problem.defect_gradient(e, c, &mut row);
        for (v, d) in &row {
            for k in 0..3 {
                out[3 * *v as usize + k] += rho * g * 2.0 * defect * d[k];
            }
        }
    }
    out
}

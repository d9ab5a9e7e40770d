//! Solving the strips: Levenberg–Marquardt on the penalty of [`crate::strip_penalty`]
//! with its exact Jacobian, and the no-gap condition either as the paper's fixed penalty
//! or as an equality constraint.
//!
//! **Gap as a constraint (default).** The gap rows `g_e = (v_·,M)_x / (L2 + L3)` are taken
//! out of the penalty and imposed as equality constraints `g = 0`: each
//! Levenberg–Marquardt step solves the damped KKT system of
//! [`constrained_levenberg_marquardt`] (an SQP-type step). At the solution the other terms
//! are minimised *on* the set where the strips close, to `gap_tolerance`. A quadratic
//! penalty (or the method of multipliers around it) was tried first: it needed 200–500
//! iterations per strip because the Gauss–Newton model misses the constraint's curvature
//! and the steps crawl along the curved valley.
//!
//! **The step's Hessian is the exact Hessian of the Lagrangian**:
//! `JᵀJ + Σ r_i ∇²r_i + Σ λ_e ∇²g_e`, all analytic (second derivatives of the folded
//! vertices in [`crate::strip_folding::FoldedStrip::add_weighted_hessian`]). The
//! Gauss–Newton `JᵀJ` alone is a poor model here: `F` is dominated by the fairness rows
//! `√w3 Δ^(−1/2)`, which are never small and whose own curvature is three times their
//! Gauss–Newton part, so the steps were about four times too long, the damping settled
//! near `μ ≈ 4` and the solver crept (45–316 iterations per strip on the chair, 30–45 ms
//! for the chair). With the exact Hessian: 14–35 iterations, about 6 ms
//! (`docs/benchmarks-history.md`).
//!
//! **Penalty** (`gap: penalty`): the paper's method, plain Levenberg–Marquardt on `F`
//! with the fixed weight `w1`; some gap remains (the paper reports `E ≤ 1.5e-3`).
//!
//! **Joint solve** (the paper's future work): all strips' unknowns in one problem, with
//! rows `√w_n (θ_j^k − θ_j^{k+1})` that keep neighbouring strips' ridge angles close.

use crate::strip_folding::StripState;
use crate::strip_penalty::{PenaltyTerms, StripTerms};
use crate::GapHandling;
use nalgebra::{DMatrix, DVector};
use sheetform_solve::{
    constrained_levenberg_marquardt, levenberg_marquardt, ConstrainedLeastSquaresProblem, ConstrainedOptions,
    LeastSquaresProblem, LevenbergMarquardtOptions, SolverInfo,
};
use std::sync::atomic::{AtomicBool, Ordering};

/// Knobs of the strip solver.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StripSolveOptions {
    /// Constraint or penalty.
    pub gap: GapHandling,
    /// Target normalised error `E` (constraint mode).
    pub gap_tolerance: f64,
    /// Most Levenberg–Marquardt iterations over all rounds.
    pub max_iterations: usize,
}

impl Default for StripSolveOptions {
    fn default() -> Self {
        Self {
            gap: GapHandling::Exact,
            gap_tolerance: 1e-8,
            max_iterations: 500,
        }
    }
}

/// What the solver did for one strip (or, jointly, for all).
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct StripSolveInfo {
    /// Strip index (joint solve: the first strip).
    pub strip: usize,
    /// Quads in the strip.
    pub quads: usize,
    /// Levenberg–Marquardt iterations over all rounds.
    pub iterations: usize,
    /// The paper's penalty `F` before solving.
    pub initial_penalty: f64,
    /// The paper's penalty `F` at the end, term by term.
    pub penalty: PenaltyTerms,
    /// `G`: the largest distance of the strip's end points from the symmetry plane, in the
    /// model's unit.
    pub gap: f64,
    /// `E = G / (L2 + L3)`.
    pub normalised_error: f64,
    /// Final gradient norm of the last round.
    pub gradient_norm: f64,
    /// Constraint mode: `E` reached the tolerance and the last round converged; penalty
    /// mode: Levenberg–Marquardt converged.
    pub converged: bool,
    /// Wall-clock time.
    pub time_ms: f64,
}

/// A least-squares problem whose gap rows can be switched off and handed to the solver
/// as constraints.
pub trait GapConstrained: ConstrainedLeastSquaresProblem {
    /// Sets the weight of the gap rows in the residuals (0: constraint mode).
    fn set_gap_weight(&mut self, weight: f64);
    /// The nominal gap weight `w1`.
    fn nominal_gap_weight(&self) -> f64;
}

/// One strip as a [`LeastSquaresProblem`].
#[derive(Debug, Clone)]
pub struct StripProblem<'a> {
    /// The strip's terms.
    pub terms: StripTerms<'a>,
    /// Set from another thread to stop the solve (a cancelled run).
    pub stop: Option<&'a AtomicBool>,
}

impl LeastSquaresProblem for StripProblem<'_> {
    fn residuals(&self, x: &DVector<f64>) -> DVector<f64> {
        let mut r = DVector::zeros(self.terms.residual_count());
        self.terms.residuals_into(x.as_slice(), r.as_mut_slice());
        r
    }

    fn jacobian(&self, x: &DVector<f64>) -> DMatrix<f64> {
        let mut j = DMatrix::zeros(self.terms.residual_count(), x.len());
        self.terms.jacobian_into(x.as_slice(), &mut j, 0, 0);
        j
    }

    fn stop_requested(&self) -> bool {
        self.stop.is_some_and(|s| s.load(Ordering::Relaxed))
    }
}

impl ConstrainedLeastSquaresProblem for StripProblem<'_> {
    fn constraints(&self, x: &DVector<f64>) -> DVector<f64> {
        DVector::from_vec(self.terms.gaps(x.as_slice()).to_vec())
    }
    fn constraint_jacobian(&self, x: &DVector<f64>) -> DMatrix<f64> {
        let mut c = DMatrix::zeros(2, x.len());
        self.terms.gap_jacobian_into(x.as_slice(), &mut c, 0, 0);
        c
    }
    fn constraint_curvature(&self, x: &DVector<f64>, multipliers: &DVector<f64>) -> Option<DMatrix<f64>> {
        let mut out = DMatrix::zeros(x.len(), x.len());
        self.terms
            .gap_curvature_into(x.as_slice(), [multipliers[0], multipliers[1]], &mut out, 0);
        Some(out)
    }
    fn residual_curvature(&self, x: &DVector<f64>) -> Option<DMatrix<f64>> {
        let mut out = DMatrix::zeros(x.len(), x.len());
        self.terms.residual_curvature_into(x.as_slice(), &mut out, 0);
        Some(out)
    }
}

impl GapConstrained for StripProblem<'_> {
    fn set_gap_weight(&mut self, weight: f64) {
        self.terms.gap_weight = weight;
    }
    fn nominal_gap_weight(&self) -> f64 {
        self.terms.weights.no_gap
    }
}

/// All strips in one problem, with the neighbour rows.
#[derive(Debug, Clone)]
pub struct JointProblem<'a> {
    /// Each strip's terms.
    pub strips: Vec<StripTerms<'a>>,
    /// Weight of the neighbour rows.
    pub neighbour_weight: f64,
    /// Set from another thread to stop the solve (a cancelled run).
    pub stop: Option<&'a AtomicBool>,
}

impl JointProblem<'_> {
    fn columns(&self) -> Vec<usize> {
        let mut at = 0;
        self.strips
            .iter()
            .map(|s| {
                let c = at;
                at += 3 * s.quads - 2;
                c
            })
            .collect()
    }

    fn neighbour_pairs(&self) -> Vec<(usize, usize, usize)> {
        let mut pairs = Vec::new();
        for k in 1..self.strips.len() {
            let m = self.strips[k].quads.min(self.strips[k - 1].quads);
            for j in 0..m {
                pairs.push((k - 1, k, j));
            }
        }
        pairs
    }

    fn rows(&self) -> usize {
        self.strips.iter().map(StripTerms::residual_count).sum::<usize>() + self.neighbour_pairs().len()
    }
}

impl LeastSquaresProblem for JointProblem<'_> {
    fn residuals(&self, x: &DVector<f64>) -> DVector<f64> {
        let mut r = DVector::zeros(self.rows());
        let cols = self.columns();
        let mut row = 0;
        for (s, &c) in self.strips.iter().zip(&cols) {
            let n = s.residual_count();
            s.residuals_into(
                &x.as_slice()[c..c + 3 * s.quads - 2],
                &mut r.as_mut_slice()[row..row + n],
            );
            row += n;
        }
        let w = self.neighbour_weight.sqrt();
        for (a, b, j) in self.neighbour_pairs() {
            r[row] = w * (x[cols[a] + j] - x[cols[b] + j]);
            row += 1;
        }
        r
    }

    fn jacobian(&self, x: &DVector<f64>) -> DMatrix<f64> {
        let mut jac = DMatrix::zeros(self.rows(), x.len());
        let cols = self.columns();
        let mut row = 0;
        for (s, &c) in self.strips.iter().zip(&cols) {
            s.jacobian_into(&x.as_slice()[c..c + 3 * s.quads - 2], &mut jac, row, c);
            row += s.residual_count();
        }
        let w = self.neighbour_weight.sqrt();
        for (a, b, j) in self.neighbour_pairs() {
            jac[(row, cols[a] + j)] = w;
            jac[(row, cols[b] + j)] = -w;
            row += 1;
        }
        jac
    }

    fn stop_requested(&self) -> bool {
        self.stop.is_some_and(|s| s.load(Ordering::Relaxed))
    }
}

impl ConstrainedLeastSquaresProblem for JointProblem<'_> {
    fn constraints(&self, x: &DVector<f64>) -> DVector<f64> {
        let cols = self.columns();
        DVector::from_iterator(
            2 * self.strips.len(),
            self.strips
                .iter()
                .zip(&cols)
                .flat_map(|(s, &c)| s.gaps(&x.as_slice()[c..c + 3 * s.quads - 2])),
        )
    }
    fn constraint_jacobian(&self, x: &DVector<f64>) -> DMatrix<f64> {
        let cols = self.columns();
        let mut out = DMatrix::zeros(2 * self.strips.len(), x.len());
        for (k, (s, &c)) in self.strips.iter().zip(&cols).enumerate() {
            s.gap_jacobian_into(&x.as_slice()[c..c + 3 * s.quads - 2], &mut out, 2 * k, c);
        }
        out
    }
    fn constraint_curvature(&self, x: &DVector<f64>, multipliers: &DVector<f64>) -> Option<DMatrix<f64>> {
        // Block diagonal: each strip's gaps depend on its own unknowns only.
        let cols = self.columns();
        let mut out = DMatrix::zeros(x.len(), x.len());
        for (k, (s, &c)) in self.strips.iter().zip(&cols).enumerate() {
            s.gap_curvature_into(
                &x.as_slice()[c..c + 3 * s.quads - 2],
                [multipliers[2 * k], multipliers[2 * k + 1]],
                &mut out,
                c,
            );
        }
        Some(out)
    }
    fn residual_curvature(&self, x: &DVector<f64>) -> Option<DMatrix<f64>> {
        // The neighbour rows are linear: only the strips' own rows are curved.
        let cols = self.columns();
        let mut out = DMatrix::zeros(x.len(), x.len());
        for (s, &c) in self.strips.iter().zip(&cols) {
            s.residual_curvature_into(&x.as_slice()[c..c + 3 * s.quads - 2], &mut out, c);
        }
        Some(out)
    }
}

impl GapConstrained for JointProblem<'_> {
    fn set_gap_weight(&mut self, weight: f64) {
        for s in &mut self.strips {
            s.gap_weight = weight;
        }
    }
    fn nominal_gap_weight(&self) -> f64 {
        self.strips.first().map_or(0.1, |s| s.weights.no_gap)
    }
}

/// Minimises a gap-constrained problem from `x0`; returns the unknowns, the solver info
/// and the largest gap `max |g|` at the end.
///
/// Constraint mode: the gap rows are switched off and `g = 0` is handed to
/// [`constrained_levenberg_marquardt`] as an equality constraint. Penalty mode: the
/// paper's plain Levenberg–Marquardt on `F` with weight `w1`.
pub fn solve_gap_constrained<P: GapConstrained>(
    problem: &mut P,
    x0: DVector<f64>,
    options: &StripSolveOptions,
) -> (DVector<f64>, SolverInfo, f64) {
    let base = LevenbergMarquardtOptions {
        max_iterations: options.max_iterations,
        // Once the strip is closed (E ≤ tolerance), stop when an accepted step lowers the
        // penalty by less than 1e-8 of itself: F is dominated by the fairness term's
        // constant part and is very flat, and the shape no longer changes visibly.
        gradient_tolerance: 1e-6,
        step_tolerance: 1e-12,
        cost_tolerance: 1e-8,
        ..Default::default()
    };
    let largest = |p: &P, x: &DVector<f64>| p.constraints(x).amax();
    match options.gap {
        GapHandling::Penalty => {
            let weight = problem.nominal_gap_weight();
            problem.set_gap_weight(weight);
            let (x, info) = levenberg_marquardt(problem, x0, &base);
            let gap = largest(problem, &x);
            (x, info, gap)
        }
        GapHandling::Exact => {
            problem.set_gap_weight(0.0);
            let (x, info) = constrained_levenberg_marquardt(
                problem,
                x0,
                &ConstrainedOptions {
                    base,
                    constraint_tolerance: options.gap_tolerance,
                },
            );
            (x, info.solver, info.constraint_violation)
        }
    }
}

/// Solves one strip from `state` (updated in place).
pub fn solve_strip(
    terms: StripTerms<'_>,
    strip: usize,
    state: &mut StripState,
    options: &StripSolveOptions,
) -> StripSolveInfo {
    solve_strip_until(terms, strip, state, options, None)
}

/// [`solve_strip`] that stops where it is once `stop` is set (from another thread).
pub fn solve_strip_until(
    terms: StripTerms<'_>,
    strip: usize,
    state: &mut StripState,
    options: &StripSolveOptions,
    stop: Option<&AtomicBool>,
) -> StripSolveInfo {
    let started = std::time::Instant::now();
    let x0 = state.to_vector();
    let initial_penalty = terms.penalty(&x0).total;
    let mut problem = StripProblem { terms, stop };
    let (x, info, _) = solve_gap_constrained(&mut problem, DVector::from_vec(x0), options);
    state.set_vector(x.as_slice());
    let terms = &problem.terms;
    let gaps = terms.gaps(x.as_slice());
    let normalised_error = gaps[0].abs().max(gaps[1].abs());
    StripSolveInfo {
        strip,
        quads: state.quads(),
        iterations: info.iterations,
        initial_penalty,
        penalty: terms.penalty(x.as_slice()),
        gap: normalised_error * terms.length_scale,
        normalised_error,
        gradient_norm: info.gradient_norm,
        converged: info.converged,
        time_ms: started.elapsed().as_secs_f64() * 1e3,
    }
}

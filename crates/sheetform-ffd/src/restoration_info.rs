//! What a developability restoration did.

use crate::{DevelopabilityProblem, Evaluation};
use serde::Serialize;
use std::time::Instant;

/// Report of one restoration (either solver).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RestorationInfo {
    /// The method that ran.
    pub solver: crate::SolverMethod,
    /// Iterations (constrained: SQP iterations; paper: penalty updates, each with its
    /// conjugate-gradient steps).
    pub iterations: usize,
    /// Whether the stopping rule was met (constrained: every defect within tolerance;
    /// paper: the relative change of G below ε before Nmax).
    pub converged: bool,
    /// Nodes whose parameters were optimised (the selective set of §3).
    pub variable_node_count: usize,
    /// Constrained interior vertices.
    pub constraint_count: usize,
    /// `G[X₀]` (Eq. 2-5) over the constrained vertices (radians²).
    pub developability_g_before: f64,
    /// `G[X*]` (radians²).
    pub developability_g_after: f64,
    /// Largest |angle defect| before (radians).
    pub angle_defect_max_before_rad: f64,
    /// Largest |angle defect| after (radians).
    pub angle_defect_max_after_rad: f64,
    /// `E(X*)` (Eq. 2-2, model units²).
    pub spring_energy_after: f64,
    /// Wall-clock time of the solve (milliseconds).
    pub time_ms: f64,
    /// The constrained solver's bending weight at the end (0: springs alone; the paper's
    /// solver: 0).
    pub bending_weight: f64,
    /// The iteration after which the constrained solver switched the bending term on
    /// because the restoration stalled (`ConstrainedOptions::stall_bending_weight`), if
    /// it did.
    pub bending_fallback_iteration: Option<usize>,
    /// Restorations run along the deformation's path (1: the whole deformation at once;
    /// more with `solver.continuation`, see [`crate::restore_along_path`]; 0: none).
    pub sub_steps: usize,
    /// Chord steps of the constrained solver: projections that reused the last
    /// factorisation instead of a new one (not counted in `iterations`, which are the
    /// factorised steps).
    pub chord_steps: usize,
}

/// Where a restoration is, reported after each iteration (constrained: each Gauss–Newton
/// step; paper: each penalty update) to a progress callback
/// ([`crate::run_design_with_progress`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RestorationProgress {
    /// The deformation being restored (0-based).
    pub deformation: usize,
    /// Deformations in the scene.
    pub deformation_count: usize,
    /// Iterations done in this restoration.
    pub iteration: usize,
    /// Largest |angle defect| before this restoration (radians).
    pub angle_defect_max_start_rad: f64,
    /// Largest |angle defect| now (radians).
    pub angle_defect_max_rad: f64,
    /// The restoration's target for the largest defect (radians; the constrained
    /// solver's tolerance, the paper's solver: 0).
    pub tolerance_rad: f64,
}

impl RestorationProgress {
    /// How far this restoration is, in `[0, 1]`: the defect's fall on a log scale,
    /// `ln(d₀/d) / ln(d₀/tolerance)` (a Newton iteration's natural measure; for the
    /// paper's solver, which has no tolerance, against `1e-10·d₀`). Not monotone when
    /// the defect rises between iterations.
    pub fn fraction(&self) -> f64 {
        let start = self.angle_defect_max_start_rad;
        let target = if self.tolerance_rad > 0.0 {
            self.tolerance_rad
        } else {
            1e-10 * start
        };
        if start <= target || self.angle_defect_max_rad <= target {
            return 1.0;
        }
        ((start / self.angle_defect_max_rad.max(f64::MIN_POSITIVE)).ln() / (start / target).ln()).clamp(0.0, 1.0)
    }
}

impl RestorationInfo {
    pub(crate) fn begin(solver: crate::SolverMethod, problem: &DevelopabilityProblem<'_>, e: &Evaluation) -> Self {
        Self {
            solver,
            iterations: 0,
            converged: false,
            variable_node_count: problem.variables.len(),
            constraint_count: problem.constraint_count(),
            developability_g_before: problem.developability_g(e),
            developability_g_after: 0.0,
            angle_defect_max_before_rad: e.defects.iter().fold(0.0, |m, g| m.max(g.abs())),
            angle_defect_max_after_rad: 0.0,
            spring_energy_after: 0.0,
            time_ms: 0.0,
            bending_weight: 0.0,
            bending_fallback_iteration: None,
            sub_steps: 1,
            chord_steps: 0,
        }
    }

    pub(crate) fn finish(
        &mut self,
        problem: &DevelopabilityProblem<'_>,
        e: &Evaluation,
        iterations: usize,
        converged: bool,
        start: Instant,
    ) {
        self.iterations = iterations;
        self.converged = converged;
        self.developability_g_after = problem.developability_g(e);
        self.angle_defect_max_after_rad = e.defects.iter().fold(0.0, |m, g| m.max(g.abs()));
        self.spring_energy_after = problem.spring_energy(e);
        self.time_ms = start.elapsed().as_secs_f64() * 1e3;
    }
}

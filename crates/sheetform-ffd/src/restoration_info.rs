//! What a developability restoration did.

use crate::{DevelopabilityProblem, Evaluation};
use serde::Serialize;
use std::time::Instant;

/// Report of one restoration (either solver).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RestorationInfo {
    /// `constrained` (default) or `paper`.
    pub solver: String,
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
}

impl RestorationInfo {
    pub(crate) fn begin(solver: &str, problem: &DevelopabilityProblem<'_>, e: &Evaluation) -> Self {
        Self {
            solver: solver.into(),
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

/// What a solver did.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct SolverInfo {
    /// Iterations taken.
    pub iterations: usize,
    /// Final cost (the objective's value, e.g. `½|r|²`).
    pub cost: f64,
    /// Cost at the start.
    pub initial_cost: f64,
    /// Final gradient norm (first-order optimality).
    pub gradient_norm: f64,
    /// Whether a convergence test was met (not just the iteration limit).
    pub converged: bool,
}

//! Solvers shared by the sheetform methods. Every solver returns a [`SolverInfo`]
//! (iterations, residual, converged), never a bare bool; sparse symmetric positive-definite
//! systems go through [`SparseCholesky`], symmetric indefinite KKT systems of a
//! constrained Gauss–Newton step through [`KktSystem`] (ordered by AMD or by
//! [`nested_dissection`]).

mod constrained_levenberg_marquardt;
mod diagonal_kkt_system;
mod kkt_system;
mod levenberg_marquardt;
pub mod nested_dissection;
mod solver_info;
mod sparse_cholesky;

pub use constrained_levenberg_marquardt::{
    constrained_levenberg_marquardt, ConstrainedInfo, ConstrainedLeastSquaresProblem, ConstrainedOptions,
};
pub use diagonal_kkt_system::DiagonalKktSystem;
pub use kkt_system::{
    FactorisationFailure, KktError, KktSystem, SolveAccuracy, MAX_FACTOR_BYTES, MAX_REFINEMENT_STEPS,
    PROJECTION_METRIC_BACKWARD_ERROR, REFINED_BACKWARD_ERROR,
};
pub use levenberg_marquardt::{levenberg_marquardt, LeastSquaresProblem, LevenbergMarquardtOptions};
pub use solver_info::SolverInfo;
pub use sparse_cholesky::{CholeskyError, SparseCholesky};

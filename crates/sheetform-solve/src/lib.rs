//! Solvers shared by the sheetform methods. Every solver returns a [`SolverInfo`]
//! (iterations, residual, converged), never a bare bool; sparse symmetric positive-definite
//! systems go through [`SparseCholesky`].

mod constrained_levenberg_marquardt;
mod levenberg_marquardt;
mod solver_info;
mod sparse_cholesky;

pub use constrained_levenberg_marquardt::{
    constrained_levenberg_marquardt, ConstrainedInfo, ConstrainedLeastSquaresProblem, ConstrainedOptions,
};
pub use levenberg_marquardt::{levenberg_marquardt, LeastSquaresProblem, LevenbergMarquardtOptions};
pub use solver_info::SolverInfo;
pub use sparse_cholesky::{CholeskyError, SparseCholesky};

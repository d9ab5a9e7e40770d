//! Solvers shared by the sheetform methods. Every solver returns a [`SolverInfo`]
//! (iterations, residual, converged), never a bare bool.

mod levenberg_marquardt;
mod solver_info;

pub use levenberg_marquardt::{levenberg_marquardt, LeastSquaresProblem, LevenbergMarquardtOptions};
pub use solver_info::SolverInfo;

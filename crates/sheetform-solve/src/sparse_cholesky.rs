//! Sparse symmetric positive-definite systems `A x = b`, factorised once and solved for
//! as many right-hand sides as needed: faer's sparse LLᵀ (Cholesky) with its fill-reducing
//! ordering. One place for the assembly from triplets, the symbolic analysis (reusable
//! while the pattern stays) and the numeric factorisation that every method's normal
//! equations, Laplace fills and SQP steps go through.

use faer::prelude::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Col, Mat, MatRef, Side};
use thiserror::Error;

/// Why a sparse Cholesky factorisation failed.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum CholeskyError {
    /// The triplets do not make an `n × n` matrix (an index out of range).
    #[error("cannot assemble the matrix: {0}")]
    Assembly(String),
    /// The symbolic analysis failed (the pattern is too large).
    #[error("cannot analyse the matrix: {0}")]
    Symbolic(String),
    /// A pivot was not positive: the matrix is singular or indefinite. The message says
    /// so in words for people; the solver's detail (which pivot) is kept for logs, and a
    /// `tracing` debug line gives it where it happens.
    #[error("the linear system has no unique solution (singular, or not positive definite)")]
    NotPositiveDefinite(String),
}

/// `A = L Lᵀ` of a sparse symmetric positive-definite `n × n` matrix.
#[derive(Debug)]
pub struct SparseCholesky {
    symbolic: SymbolicLlt<usize>,
    llt: Llt<usize, f64>,
    n: usize,
}

fn assemble(n: usize, triplets: &[Triplet<usize, usize, f64>]) -> Result<SparseColMat<usize, f64>, CholeskyError> {
    SparseColMat::<usize, f64>::try_new_from_triplets(n, n, triplets).map_err(|e| {
        CholeskyError::Assembly(match e {
            faer::sparse::CreationError::OutOfBounds { row, col } => {
                format!("entry ({row}, {col}) is outside the {n} × {n} matrix")
            }
            faer::sparse::CreationError::Generic(_) => format!("a {n} × {n} matrix is too large for this machine"),
        })
    })
}

fn not_positive_definite(e: faer::sparse::linalg::LltError, n: usize) -> CholeskyError {
    match e {
        faer::sparse::linalg::LltError::Numeric(faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot {
            index,
        }) => {
            let detail = format!("pivot {index} of {n} is not positive");
            tracing::debug!("sparse Cholesky: {detail}");
            CholeskyError::NotPositiveDefinite(detail)
        }
        faer::sparse::linalg::LltError::Generic(_) => {
            CholeskyError::Symbolic(format!("a {n} × {n} factor is too large for this machine"))
        }
    }
}

impl SparseCholesky {
    /// Factorises the matrix whose lower triangle `triplets` give (entries above the
    /// diagonal are ignored, repeated entries are summed).
    ///
    /// # Errors
    /// [`CholeskyError`] when the triplets leave the matrix or it is not positive definite.
    pub fn new(n: usize, triplets: &[Triplet<usize, usize, f64>]) -> Result<Self, CholeskyError> {
        let matrix = assemble(n, triplets)?;
        let symbolic = SymbolicLlt::try_new(matrix.symbolic(), Side::Lower)
            .map_err(|_| CholeskyError::Symbolic(format!("a {n} × {n} factor is too large for this machine")))?;
        let llt = Llt::try_new_with_symbolic(symbolic.clone(), matrix.as_ref(), Side::Lower)
            .map_err(|e| not_positive_definite(e, n))?;
        Ok(Self { symbolic, llt, n })
    }

    /// Factorises a new matrix with the same pattern, reusing the symbolic analysis
    /// (Gauss–Newton iterations).
    ///
    /// # Errors
    /// As [`Self::new`].
    pub fn refactor(&mut self, triplets: &[Triplet<usize, usize, f64>]) -> Result<(), CholeskyError> {
        let matrix = assemble(self.n, triplets)?;
        self.llt = Llt::try_new_with_symbolic(self.symbolic.clone(), matrix.as_ref(), Side::Lower)
            .map_err(|e| not_positive_definite(e, self.n))?;
        Ok(())
    }

    /// The order `n`.
    pub fn dimension(&self) -> usize {
        self.n
    }

    /// `A⁻¹ b`.
    pub fn solve(&self, b: &[f64]) -> Vec<f64> {
        let x = self.llt.solve(Col::from_fn(self.n, |k| b[k]));
        (0..self.n).map(|k| x[k]).collect()
    }

    /// `A⁻¹ B` for a matrix of right-hand sides (one per column).
    pub fn solve_columns(&self, b: MatRef<'_, f64>) -> Mat<f64> {
        self.llt.solve(b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 1D Laplacian with a mass term against a dense solve; a refactorisation with
    /// the same pattern; an indefinite matrix refused.
    #[test]
    fn solves_a_tridiagonal_system_and_refuses_an_indefinite_one() {
        let n = 50;
        let lower = |shift: f64| -> Vec<Triplet<usize, usize, f64>> {
            let mut t = Vec::new();
            for i in 0..n {
                t.push(Triplet::new(i, i, 2.0 + shift));
                if i > 0 {
                    t.push(Triplet::new(i, i - 1, -1.0));
                }
            }
            t
        };
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.3).sin()).collect();
        let mut cholesky = SparseCholesky::new(n, &lower(0.1)).unwrap();
        let check = |x: &[f64], shift: f64| {
            for i in 0..n {
                let mut ax = (2.0 + shift) * x[i];
                if i > 0 {
                    ax -= x[i - 1];
                }
                if i + 1 < n {
                    ax -= x[i + 1];
                }
                assert!((ax - b[i]).abs() < 1e-10, "row {i}: {ax} vs {}", b[i]);
            }
        };
        check(&cholesky.solve(&b), 0.1);
        cholesky.refactor(&lower(1.0)).unwrap();
        check(&cholesky.solve(&b), 1.0);
        let columns =
            cholesky.solve_columns(Mat::from_fn(n, 2, |i, j| if j == 0 { b[i] } else { 2.0 * b[i] }).as_ref());
        assert!((columns[(7, 1)] - 2.0 * columns[(7, 0)]).abs() < 1e-12);
        // Issue 35: the message is for people ("pivot 96084 is not positive" was shown);
        // the pivot stays in the detail, for logs.
        let refused = SparseCholesky::new(n, &lower(-3.0)).unwrap_err();
        assert!(!refused.to_string().contains("pivot"), "{refused}");
        assert!(matches!(&refused, CholeskyError::NotPositiveDefinite(detail) if detail.starts_with("pivot ")));
        assert!(matches!(
            SparseCholesky::new(3, &[Triplet::new(5, 0, 1.0)]),
            Err(CholeskyError::Assembly(_))
        ));
    }
}

//! The KKT system of a constrained Gauss–Newton step whose metric is diagonal,
//! `[D Aᵀ; A −δI]`, solved through its constraints' Schur complement
//! `S = A D⁻¹ Aᵀ + δI`: with `D` diagonal the unknowns eliminate without fill, so only
//! `S` (one row per constraint, the pattern of constraints sharing an unknown) is
//! factorised. `develop` uses it: on the koala (7 116 faces, 2 962 angle-defect
//! constraints) the full KKT system's factor holds 1.64 M values, `S`'s 0.14 M.

use crate::{FactorisationFailure, KktError, KktSystem, SolveAccuracy, MAX_REFINEMENT_STEPS};
use crate::{PROJECTION_METRIC_BACKWARD_ERROR, REFINED_BACKWARD_ERROR};
use faer::sparse::Pair;
use nalgebra::Vector3;
use std::collections::HashMap;

/// `[D Aᵀ; A −δI] [x; λ] = [b; c]` for a diagonal `D` given by its inverse (an unknown
/// whose inverse metric is 0 is held: its step is 0 and its row is dropped), solved as
///
/// `(A D⁻¹ Aᵀ + δI) λ = A D⁻¹ b − c`, then `x = D⁻¹ (b − Aᵀ λ)`
///
/// (block elimination of the unknowns; Nocedal & Wright, *Numerical Optimization*, 2nd
/// ed., §16.2, "Schur-complement method", Eq. 16.16), with iterative refinement against
/// the system without its `−δ` block, as [`KktSystem::solve_to`] does. `S` is factorised
/// by a [`KktSystem`] of `nc` unknowns and no constraints (AMD, LDLᵀ with dynamic
/// regularisation: a constraint that depends on others gets the pivot `δ`), always
/// supernodal: faer's flop-ratio rule picked its simplicial factorisation for these
/// 2-ring patterns, whose numeric step was the largest part of a develop run (24 % of the
/// wing nut's under `perf`); forced supernodal, whole develop runs took 1.10–1.11 s
/// instead of 1.19–1.40 (koala) and 1.25–1.31 instead of 1.66–1.67 (wing nut), the same
/// results (docs/benchmarks-history.md, session 34).
///
/// Units: those of the caller's `D` and `A`; `δ` is in the units of `S`.
pub struct DiagonalKktSystem {
    /// Unknowns.
    pub n: usize,
    /// Constraints.
    pub nc: usize,
    /// `A`'s values, row by row in the order of the columns given to
    /// [`DiagonalKktSystem::new`].
    pub constraint_values: Vec<f64>,
    /// `D⁻¹`, one value per unknown (0 holds the unknown).
    pub inverse_metric: Vec<f64>,
    /// Start of each row's values in [`DiagonalKktSystem::constraint_values`].
    row_starts: Vec<usize>,
    /// Each row's columns.
    columns: Vec<usize>,
    /// For each unknown, the values of `A` in its column: `(row, value index)`.
    column_entries: Vec<Vec<(usize, usize)>>,
    /// For each unknown, the index into `S`'s values of each pair `(a, b)`, `a ≤ b`, of
    /// its column's entries, in the order the pairs are visited.
    pair_targets: Vec<Vec<usize>>,
    /// Where `δ` is added (the diagonal's value indices).
    diagonal: Vec<usize>,
    /// The factorisation of `S`.
    schur: KktSystem,
    /// Solves through `S` of the last solve (the first and one per refinement step; each
    /// solves `S` refined to rounding) and its componentwise backward error (infinite
    /// when a residual is not finite).
    pub last_solve: (usize, f64),
}

impl DiagonalKktSystem {
    /// The pattern of `S` from `A`'s (`rows[r]`: the columns of row `r`, without
    /// duplicates), its ordering and symbolic analysis. `row_coordinates[r]` places each
    /// constraint (for the ordering when `S` is large).
    ///
    /// # Errors
    /// [`KktError`] when `S`'s factor does not fit.
    pub fn new(n: usize, rows: &[Vec<usize>], row_coordinates: &[Vector3<f64>]) -> Result<Self, KktError> {
        let nc = rows.len();
        let mut row_starts = Vec::with_capacity(nc + 1);
        let mut columns = Vec::new();
        let mut column_entries: Vec<Vec<(usize, usize)>> = vec![Vec::new(); n];
        for (r, row) in rows.iter().enumerate() {
            debug_assert!(
                row.iter().enumerate().all(|(i, j)| !row[..i].contains(j)),
                "row {r} lists a column twice"
            );
            row_starts.push(columns.len());
            for &j in row {
                column_entries[j].push((r, columns.len()));
                columns.push(j);
            }
        }
        row_starts.push(columns.len());
        let mut index: HashMap<(usize, usize), usize> = HashMap::new();
        let mut pairs = Vec::new();
        let mut slot = |a: usize, b: usize, pairs: &mut Vec<Pair<usize, usize>>| {
            let key = (a.min(b), a.max(b));
            *index.entry(key).or_insert_with(|| {
                pairs.push(Pair { row: key.0, col: key.1 });
                pairs.len() - 1
            })
        };
        let diagonal: Vec<usize> = (0..nc).map(|r| slot(r, r, &mut pairs)).collect();
        let pair_targets: Vec<Vec<usize>> = column_entries
            .iter()
            .map(|entries| {
                let mut targets = Vec::with_capacity(entries.len() * (entries.len() + 1) / 2);
                for (i, &(a, _)) in entries.iter().enumerate() {
                    for &(b, _) in &entries[i..] {
                        targets.push(slot(a, b, &mut pairs));
                    }
                }
                targets
            })
            .collect();
        let blocks: Vec<usize> = (0..nc).collect();
        let mut schur = KktSystem::new_supernodal(nc, 0, pairs, &blocks, row_coordinates, true)?;
        schur.values.fill(0.0);
        Ok(Self {
            n,
            nc,
            constraint_values: vec![0.0; columns.len()],
            inverse_metric: vec![0.0; n],
            row_starts,
            columns,
            column_entries,
            pair_targets,
            diagonal,
            schur,
            last_solve: (0, 0.0),
        })
    }

    /// Values in the factor of `S`.
    pub fn factor_size(&self) -> usize {
        self.schur.factor_size()
    }

    /// Forms `S = A D⁻¹ Aᵀ + δI` from the current values and factorises it.
    ///
    /// # Errors
    /// [`FactorisationFailure::Singular`] (a non-finite value).
    pub fn factorise(&mut self, delta: f64) -> Result<(), FactorisationFailure> {
        let values = &mut self.schur.values;
        values.fill(0.0);
        for (j, (entries, targets)) in self.column_entries.iter().zip(&self.pair_targets).enumerate() {
            let weight = self.inverse_metric[j];
            if weight == 0.0 {
                continue;
            }
            let mut t = targets.iter();
            for (i, &(_, va)) in entries.iter().enumerate() {
                let scaled = self.constraint_values[va] * weight;
                for &(_, vb) in &entries[i..] {
                    let target = *t.next().expect("one target per pair");
                    values[target] += scaled * self.constraint_values[vb];
                }
            }
        }
        for &d in &self.diagonal {
            values[d] += delta;
        }
        self.schur.factorise(delta)
    }

    /// `A x` (the held unknowns left out).
    fn constraint_product(&self, x: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let mut product = vec![0.0; self.nc];
        let mut magnitude = vec![0.0; self.nc];
        for r in 0..self.nc {
            for k in self.row_starts[r]..self.row_starts[r + 1] {
                let j = self.columns[k];
                if self.inverse_metric[j] != 0.0 {
                    let term = self.constraint_values[k] * x[j];
                    product[r] += term;
                    magnitude[r] += term.abs();
                }
            }
        }
        (product, magnitude)
    }

    /// `Aᵀ λ` and, for the backward error, `|A|ᵀ |λ|`.
    fn transposed_product(&self, lambda: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let mut product = vec![0.0; self.n];
        let mut magnitude = vec![0.0; self.n];
        for (r, &l) in lambda.iter().enumerate() {
            for k in self.row_starts[r]..self.row_starts[r + 1] {
                let term = self.constraint_values[k] * l;
                product[self.columns[k]] += term;
                magnitude[self.columns[k]] += term.abs();
            }
        }
        (product, magnitude)
    }

    /// One solve of the system through `S` (no refinement): `[x; λ]`.
    fn solve_once(&mut self, b: &[f64], c: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let scaled: Vec<f64> = b.iter().zip(&self.inverse_metric).map(|(b, w)| b * w).collect();
        let (a_scaled, _) = self.constraint_product(&scaled);
        let mut lambda: Vec<f64> = a_scaled.iter().zip(c).map(|(a, c)| a - c).collect();
        self.schur.solve_to(&mut lambda, SolveAccuracy::Rounding);
        let (transposed, _) = self.transposed_product(&lambda);
        let x = (0..self.n)
            .map(|j| self.inverse_metric[j] * (b[j] - transposed[j]))
            .collect();
        (x, lambda)
    }

    /// Solves `[D Aᵀ; A −δI] [x; λ] = rhs` in place (`rhs = [b; c]`, `n + nc` values),
    /// refined against the system without `−δ` as far as `accuracy` asks (as
    /// [`KktSystem::solve_to`]: each refinement step must at least halve the
    /// componentwise backward error, at most [`MAX_REFINEMENT_STEPS`]). A held unknown's
    /// value is 0.
    pub fn solve_to(&mut self, rhs: &mut [f64], accuracy: SolveAccuracy) {
        let n = self.n;
        let held = |j: usize, w: &[f64]| w[j] == 0.0;
        let b: Vec<f64> = (0..n)
            .map(|j| if held(j, &self.inverse_metric) { 0.0 } else { rhs[j] })
            .collect();
        let c = rhs[n..].to_vec();
        let (mut x, mut lambda) = self.solve_once(&b, &c);
        let mut last = f64::INFINITY;
        for solves in 1..=MAX_REFINEMENT_STEPS + 1 {
            // Residuals of both block rows and the sizes of their terms.
            let (ax, ax_magnitude) = self.constraint_product(&x);
            let (transposed, transposed_magnitude) = self.transposed_product(&lambda);
            let mut metric_residual = vec![0.0; n];
            let mut metric_backward = 0.0f64;
            for j in 0..n {
                if held(j, &self.inverse_metric) {
                    continue;
                }
                let metric = x[j] / self.inverse_metric[j];
                metric_residual[j] = b[j] - metric - transposed[j];
                let size = metric.abs() + transposed_magnitude[j] + b[j].abs();
                if size > 0.0 {
                    metric_backward = metric_backward.max(metric_residual[j].abs() / size);
                }
            }
            let constraint_residual: Vec<f64> = c.iter().zip(&ax).map(|(c, a)| c - a).collect();
            let mut backward = metric_backward;
            for ((residual, magnitude), c) in constraint_residual.iter().zip(&ax_magnitude).zip(&c) {
                let size = magnitude + c.abs();
                if size > 0.0 {
                    backward = backward.max(residual.abs() / size);
                }
            }
            // A residual that is not finite (a NaN from the data) is never accurate.
            if !(backward.is_finite()
                && metric_residual
                    .iter()
                    .chain(&constraint_residual)
                    .all(|r| r.is_finite()))
            {
                backward = f64::INFINITY;
            }
            self.last_solve = (solves, backward);
            let accurate = match accuracy {
                SolveAccuracy::Rounding => backward <= REFINED_BACKWARD_ERROR,
                SolveAccuracy::ConstraintResidual(bound) => {
                    metric_backward <= PROJECTION_METRIC_BACKWARD_ERROR
                        && constraint_residual.iter().all(|r| r.abs() <= bound)
                }
            };
            if accurate || backward > 0.5 * last || solves > MAX_REFINEMENT_STEPS {
                break;
            }
            last = backward;
            let (dx, dlambda) = self.solve_once(&metric_residual, &constraint_residual);
            for (x, d) in x.iter_mut().zip(&dx) {
                *x += d;
            }
            for (l, d) in lambda.iter_mut().zip(&dlambda) {
                *l += d;
            }
        }
        rhs[..n].copy_from_slice(&x);
        rhs[n..].copy_from_slice(&lambda);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The reduced solve equals the full KKT system's on a random constrained problem
    /// (fixed seed), with a held unknown staying at 0.
    #[test]
    fn the_reduced_solve_equals_the_full_system() {
        let n = 12;
        let nc = 4;
        let mut seed = 7u64;
        let mut random = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        let rows: Vec<Vec<usize>> = (0..nc).map(|r| (0..6).map(|k| (3 * r + k) % n).collect()).collect();
        let coordinates: Vec<Vector3<f64>> = (0..nc).map(|r| Vector3::new(r as f64, 0.0, 0.0)).collect();
        let mut reduced = DiagonalKktSystem::new(n, &rows, &coordinates).unwrap();
        let held = 5;
        for (j, w) in reduced.inverse_metric.iter_mut().enumerate() {
            *w = if j == held { 0.0 } else { 1.0 / (1.0 + j as f64 * 0.3) };
        }
        for v in &mut reduced.constraint_values {
            *v = random();
        }
        let delta = 1e-12;
        reduced.factorise(delta).unwrap();
        let rhs: Vec<f64> = (0..n + nc).map(|_| random()).collect();
        let mut solved = rhs.clone();
        reduced.solve_to(&mut solved, SolveAccuracy::Rounding);
        assert!(
            reduced.last_solve.1 <= REFINED_BACKWARD_ERROR,
            "{:?}",
            reduced.last_solve
        );
        assert_eq!(solved[held], 0.0);
        // The full system: D x + Aᵀ λ = b on the free rows, x_held = 0, A x = c.
        let (x, lambda) = solved.split_at(n);
        for j in (0..n).filter(|&j| j != held) {
            let mut row = x[j] / reduced.inverse_metric[j];
            for (r, list) in rows.iter().enumerate() {
                for (k, &col) in list.iter().enumerate() {
                    if col == j {
                        row += reduced.constraint_values[6 * r + k] * lambda[r];
                    }
                }
            }
            assert!((row - rhs[j]).abs() < 1e-12, "row {j}: {row} against {}", rhs[j]);
        }
        for (r, list) in rows.iter().enumerate() {
            let row: f64 = list
                .iter()
                .enumerate()
                .map(|(k, &col)| reduced.constraint_values[6 * r + k] * x[col])
                .sum();
            assert!(
                (row - rhs[n + r]).abs() < 1e-12,
                "constraint {r}: {row} against {}",
                rhs[n + r]
            );
        }
    }
}

//! The sparse symmetric KKT system `[H Aᵀ; A −δI]` that a constrained Gauss–Newton
//! solver factorises: pattern, ordering, symbolic analysis and workspace once per
//! problem, then numeric LDLᵀ factorisations and solves with iterative refinement. The
//! FFD restoration (Wang & Tang 2004) and `develop` share it.

use crate::nested_dissection::nested_dissection;

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::ldlt::factor::LdltRegularization;
use faer::sparse::linalg::amd;
use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, LdltRef, SymbolicCholesky, SymmetricOrdering};
use faer::sparse::{Pair, SparseColMat, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par, Side};
use nalgebra::Vector3;

/// Most iterative refinement steps of [`KktSystem::solve`].
pub const MAX_REFINEMENT_STEPS: usize = 10;
/// [`KktSystem::solve`] stops refining once the componentwise backward error
/// `max_i |r_i| / (|K| |x| + |b|)_i` is at most this.
pub const REFINED_BACKWARD_ERROR: f64 = 1e-13;

/// A projection step's refinement ([`KktSystem::projection`]) stops once the rows of
/// `H` have at most this componentwise backward error (and the constraint rows are
/// within their bound): the step is then the exact least-norm step of a metric within
/// `1e-6` of `H` entry by entry, which changes its shape by as little.
pub const PROJECTION_METRIC_BACKWARD_ERROR: f64 = 1e-6;

/// When [`KktSystem::solve`] stops refining.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SolveAccuracy {
    /// The whole system to rounding: componentwise backward error at most
    /// [`REFINED_BACKWARD_ERROR`].
    Rounding,
    /// An inexact Newton step: the constraint rows' residual `|A p − b_c|` at most this
    /// (absolute, the units of the defects) and the rows of `H` within
    /// [`PROJECTION_METRIC_BACKWARD_ERROR`].
    ConstraintResidual(f64),
}

/// The error when faer cannot index or allocate the system's pattern, its ordering or
/// its factor (its only failures there: an index overflow or out of memory).
/// Most memory the restoration's factorisation may take (bytes): its factor's values and
/// the numeric factorisation's workspace, counted from the symbolic analysis before either
/// is allocated. (A 300-byte scene of 1 000 gores asked for 6.8 GB, with more gores 115 GB,
/// which killed the process; the 100 000-vertex duct takes about 0.9 GB in all.)
pub const MAX_FACTOR_BYTES: usize = 8 << 30;

/// Bytes a value of the factor takes at most with its structure (the value, and a row
/// index where the factor is stored column by column).
const FACTOR_BYTES_PER_VALUE: usize = 16;

/// Why a KKT system cannot be set up.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum KktError {
    /// faer cannot index or allocate the pattern, its ordering or its factor (an index
    /// overflow or out of memory).
    #[error("the linear system ({rows} rows) is too large to factorise on this machine")]
    TooLarge {
        /// Rows of the system.
        rows: usize,
    },
    /// The factorisation would take more than [`MAX_FACTOR_BYTES`].
    #[error("the linear system ({rows} rows) needs {:.1} GB to factorise, more than the {} GB it may take", *bytes as f64 / 1e9, MAX_FACTOR_BYTES >> 30)]
    OverMemory {
        /// Rows of the system.
        rows: usize,
        /// Bytes the factor and its workspace would take.
        bytes: usize,
    },
}

/// The error of a factorisation over [`MAX_FACTOR_BYTES`].
fn over_the_memory_bound(size: usize, bytes: usize) -> KktError {
    KktError::OverMemory { rows: size, bytes }
}

/// The number of values in the Cholesky factor of the symmetric matrix whose upper
/// triangle is `pattern`, ordered by `inverse` (new index of each row): the column counts
/// of the permuted pattern (faer's elimination tree and column counts), in time and
/// memory linear in the pattern. `None` when the count overflows.
fn factor_values(pattern: &SymbolicSparseColMat<usize>, inverse: &[usize]) -> Option<usize> {
    let n = pattern.nrows();
    let mut entries = Vec::with_capacity(pattern.compute_nnz());
    for col in 0..n {
        for row in pattern.row_idx_of_col(col) {
            let (a, b) = (inverse[row], inverse[col]);
            entries.push(Pair::new(a.min(b), a.max(b)));
        }
    }
    let (permuted, _) = SymbolicSparseColMat::try_new_from_indices(n, n, &entries).ok()?;
    let mut etree = vec![0isize; n];
    let mut counts = vec![0usize; n];
    let mut memory = MemBuffer::new(
        faer::sparse::linalg::cholesky::simplicial::prefactorize_symbolic_cholesky_scratch::<usize>(
            n,
            permuted.compute_nnz(),
        ),
    );
    faer::sparse::linalg::cholesky::simplicial::prefactorize_symbolic_cholesky::<usize>(
        &mut etree,
        &mut counts,
        permuted.as_ref(),
        MemStack::new(&mut memory),
    );
    counts.iter().try_fold(0usize, |sum, &c| sum.checked_add(c))
}

fn too_large(size: usize) -> KktError {
    KktError::TooLarge { rows: size }
}

/// Why a numeric factorisation failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FactorisationFailure {
    /// A zero pivot (with the dynamic regularisation on, a pivot that is NaN: a
    /// non-finite value in the matrix, or exactly 0 with `δ = 0`).
    Singular,
}

/// A KKT matrix of `n` unknowns and `nc` constraints, stored as its upper triangle: a fixed
/// sequence of `(row, column)` pairs (duplicates are summed) whose values are refilled
/// before each factorisation.
pub struct KktSystem {
    /// Unknowns.
    pub n: usize,
    /// Constraints.
    pub nc: usize,
    /// The values, in the order of the pairs given to [`KktSystem::new`].
    pub values: Vec<f64>,
    /// `"amd"` or `"nested dissection"`: the ordering kept.
    pub ordering: &'static str,
    /// Values in `L` with AMD and with nested dissection, when both were analysed.
    pub compared_factor_sizes: Option<(usize, usize)>,
    symbolic: SymbolicSparseColMat<usize>,
    /// The matrix last factorised (duplicates summed), for the residuals of the
    /// refinement.
    matrix: Option<SparseColMat<usize, f64>>,
    argsort: faer::sparse::Argsort<usize>,
    cholesky: SymbolicCholesky<usize>,
    l_values: Vec<f64>,
    signs: Vec<i8>,
    memory: MemBuffer,
    /// Triangular solves and the final componentwise backward error of the last
    /// [`KktSystem::solve`] (for the trace and the tests).
    pub last_solve: (usize, f64),
}

/// Which fill-reducing ordering [`KktSystem::with_ordering_choice`] uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum OrderingChoice {
    /// Approximate minimum degree (faer's).
    Amd,
    /// [`nested_dissection`].
    NestedDissection,
    /// Both analysed; the one with fewer values in `L` kept.
    Smaller,
}

/// The graph of blocks coupled by an entry of the upper-triangular pattern `symbolic`
/// (block `b`'s unknowns are `members[start[b]..start[b + 1]]`): each block's
/// neighbours, sorted, without itself.
fn block_graph(
    symbolic: &SymbolicSparseColMat<usize>,
    blocks: &[usize],
    start: &[usize],
    members: &[usize],
) -> Vec<Vec<usize>> {
    let block_count = start.len() - 1;
    // One direction (the blocks of the rows in a block's columns), each neighbour once
    // thanks to the marker, then both directions.
    let mut marker = vec![usize::MAX; block_count];
    let mut upper: Vec<(usize, usize)> = Vec::new();
    for b in 0..block_count {
        marker[b] = b;
        for &col in &members[start[b]..start[b + 1]] {
            for row in symbolic.row_idx_of_col(col) {
                let a = blocks[row];
                if marker[a] != b {
                    marker[a] = b;
                    upper.push((b, a));
                }
            }
        }
    }
    let mut degree = vec![0usize; block_count];
    for &(b, a) in &upper {
        degree[a] += 1;
        degree[b] += 1;
    }
    let mut graph: Vec<Vec<usize>> = degree.iter().map(|&d| Vec::with_capacity(d)).collect();
    for &(b, a) in &upper {
        graph[a].push(b);
        graph[b].push(a);
    }
    for list in &mut graph {
        list.sort_unstable();
        list.dedup();
    }
    graph
}

impl KktSystem {
    /// Below this many rows both orderings are analysed (a few milliseconds each).
    pub const BOTH_ORDERINGS_BELOW: usize = 20_000;

    /// The pattern's ordering, symbolic analysis and workspace.
    ///
    /// **Blocks.** `blocks[i]` is the block of unknown `i` (for the FFD: a node's three
    /// parameters and the defect constraint at that node form one block) and
    /// `block_coordinates[b]` where block `b` lives, for the nested-dissection ordering.
    /// The orderings below order the blocks (on the graph of blocks coupled by an entry),
    /// and each block's unknowns follow in increasing index, so that a constraint
    /// (indices from `n` on) is eliminated right after its own node's parameters. Why:
    /// a fill-reducing ordering of the unknowns eliminates the constraints first (their
    /// rows are the sparsest); the pivot is then the tiny `−δ` and the update `aᵀa/δ`
    /// swamps `H`. The factorisation stays quasi-definite in exact arithmetic but not in
    /// floating point: the first solve's componentwise backward error on a 16k-vertex
    /// duct was 2e-6 and the refinement needed 4–6 triangular solves per step; in
    /// block order it is 4e-10 to 2e-7 and 2–3 solves suffice (on the examples 2, the
    /// trousers' second deformation 3).
    /// The price is 17–25 % more values in `L` (trousers 814k against 662k, skirt 476k
    /// against 380k, 16k duct 28.3M against 24.2M), yet whole designs run faster: in one
    /// criterion run with this session's other changes, duct 13.5 ms against 22, skirt
    /// 50 against 62.5, trousers 104 against 112, the springs alone on the trousers
    /// 303 against 461 (docs/benchmarks-history.md, eleventh session).
    ///
    /// **Ordering**: below [`KktSystem::BOTH_ORDERINGS_BELOW`] unknowns, AMD alone when
    /// `amd_when_small` (the caller knows AMD fills less: with the hinge bending term it
    /// did on every example, skirt 476k values against 903k, trousers 814k against 1.38M,
    /// and skipping the other analysis saves set-up time); otherwise AMD and nested
    /// dissection ([`nested_dissection`]) are both analysed and the one with fewer values
    /// in `L` is kept. Above the threshold, nested dissection alone (on the 100k duct
    /// in node order, with the default metric: 226 M values in `L` against AMD's 254 M;
    /// with the springs alone and single-unknown orderings it halved `L`).
    pub fn new(
        n: usize,
        nc: usize,
        pairs: Vec<Pair<usize, usize>>,
        blocks: &[usize],
        block_coordinates: &[Vector3<f64>],
        amd_when_small: bool,
    ) -> Result<Self, KktError> {
        let choice = Self::ordering_choice(n + nc, amd_when_small);
        Self::with_ordering_choice(n, nc, pairs, blocks, block_coordinates, choice, false)
    }

    /// The ordering [`KktSystem::new`] documents for a system of `size` rows.
    fn ordering_choice(size: usize, amd_when_small: bool) -> OrderingChoice {
        match (size < Self::BOTH_ORDERINGS_BELOW, amd_when_small) {
            (false, _) => OrderingChoice::NestedDissection,
            (true, true) => OrderingChoice::Amd,
            (true, false) => OrderingChoice::Smaller,
        }
    }

    /// As [`KktSystem::new`], the factorisation always supernodal (faer otherwise picks
    /// simplicial below a flop-ratio threshold: for the develop Schur complements of a
    /// few thousand rows, whose supernodal factorisation is faster; see
    /// [`crate::DiagonalKktSystem`]).
    pub(crate) fn new_supernodal(
        n: usize,
        nc: usize,
        pairs: Vec<Pair<usize, usize>>,
        blocks: &[usize],
        block_coordinates: &[Vector3<f64>],
        amd_when_small: bool,
    ) -> Result<Self, KktError> {
        let choice = Self::ordering_choice(n + nc, amd_when_small);
        Self::with_ordering_choice(n, nc, pairs, blocks, block_coordinates, choice, true)
    }

    /// As [`KktSystem::new`], with the ordering chosen by `choice`.
    fn with_ordering_choice(
        n: usize,
        nc: usize,
        pairs: Vec<Pair<usize, usize>>,
        blocks: &[usize],
        block_coordinates: &[Vector3<f64>],
        choice: OrderingChoice,
        supernodal: bool,
    ) -> Result<Self, KktError> {
        let size = n + nc;
        let (symbolic, argsort) =
            SymbolicSparseColMat::try_new_from_indices(size, size, &pairs).map_err(|_| too_large(size))?;
        let mut params = faer::sparse::linalg::cholesky::CholeskySymbolicParams::default();
        if supernodal {
            params.supernodal_flop_ratio_threshold = faer::sparse::linalg::SupernodalThreshold::FORCE_SUPERNODAL;
        }
        let analyse = |ordering: SymmetricOrdering<'_, usize>| {
            factorize_symbolic_cholesky(symbolic.as_ref(), Side::Upper, ordering, params).map_err(|_| too_large(size))
        };
        // Each block's unknowns, `members[start[b]..start[b + 1]]`, in increasing index.
        let block_count = block_coordinates.len();
        let mut start = vec![0usize; block_count + 1];
        for &b in blocks {
            start[b + 1] += 1;
        }
        for b in 0..block_count {
            start[b + 1] += start[b];
        }
        let mut members = vec![0usize; size];
        let mut next = start.clone();
        for (i, &b) in blocks.iter().enumerate() {
            members[next[b]] = i;
            next[b] += 1;
        }
        let block_graph = block_graph(&symbolic, blocks, &start, &members);
        // A block order expanded to unknowns, each block's in increasing index (its
        // variables before its constraint), analysed.
        let expand_and_analyse = |block_order: &[usize]| {
            let forward: Vec<usize> = block_order
                .iter()
                .flat_map(|&b| members[start[b]..start[b + 1]].iter().copied())
                .collect();
            let mut inverse = vec![0; size];
            for (k, &i) in forward.iter().enumerate() {
                inverse[i] = k;
            }
            // The factor's size first, from the column counts alone (linear in the
            // matrix; a lower bound of what the supernodal factor stores, checked exactly
            // after the analysis): a factor over the memory bound is refused before its
            // structure is built (the structure of a 115 GB factor is itself gigabytes).
            let values = factor_values(&symbolic, &inverse).ok_or_else(|| too_large(size))?;
            let bytes = values.saturating_mul(FACTOR_BYTES_PER_VALUE);
            if bytes > MAX_FACTOR_BYTES {
                return Err(over_the_memory_bound(size, bytes));
            }
            analyse(SymmetricOrdering::Custom(faer::perm::PermRef::new_checked(
                &forward, &inverse, size,
            )))
        };
        let dissect = || expand_and_analyse(&nested_dissection(&block_graph, block_coordinates));
        let amd = || {
            // faer's AMD on the block graph's upper triangle.
            let mut col_ptr = vec![0usize];
            let mut row_idx = Vec::new();
            for (col, list) in block_graph.iter().enumerate() {
                row_idx.extend(list.iter().copied().filter(|&r| r < col));
                col_ptr.push(row_idx.len());
            }
            let pattern = SymbolicSparseColMat::new_checked(block_count, block_count, col_ptr, None, row_idx);
            let (mut forward, mut inverse) = (vec![0usize; block_count], vec![0usize; block_count]);
            let mut memory = MemBuffer::new(amd::order_scratch::<usize>(block_count, pattern.compute_nnz()));
            amd::order(
                &mut forward,
                &mut inverse,
                pattern.as_ref(),
                Default::default(),
                MemStack::new(&mut memory),
            )
            .map_err(|_| too_large(size))?;
            expand_and_analyse(&forward)
        };
        let (cholesky, ordering, compared_factor_sizes) = match choice {
            OrderingChoice::Amd => (amd()?, "amd", None),
            OrderingChoice::NestedDissection => (dissect()?, "nested dissection", None),
            OrderingChoice::Smaller => {
                let (amd, dissected) = (amd()?, dissect()?);
                let sizes = Some((amd.len_val(), dissected.len_val()));
                if amd.len_val() <= dissected.len_val() {
                    (amd, "amd", sizes)
                } else {
                    (dissected, "nested dissection", sizes)
                }
            }
        };
        let scratch = StackReq::any_of(&[
            cholesky.factorize_numeric_ldlt_scratch::<f64>(Par::Seq, Default::default()),
            cholesky.solve_in_place_scratch::<f64>(1, Par::Seq),
        ]);
        // What the factorisation will allocate, known before anything is: refused over
        // the bound rather than killed by the allocator.
        let bytes = cholesky
            .len_val()
            .saturating_mul(std::mem::size_of::<f64>())
            .saturating_add(scratch.size_bytes());
        if bytes > MAX_FACTOR_BYTES {
            return Err(over_the_memory_bound(size, bytes));
        }
        let memory = MemBuffer::new(scratch);
        Ok(Self {
            n,
            nc,
            values: vec![0.0; pairs.len()],
            l_values: vec![0.0; cholesky.len_val()],
            signs: (0..n + nc).map(|i| if i < n { 1 } else { -1 }).collect(),
            ordering,
            compared_factor_sizes,
            symbolic,
            matrix: None,
            argsort,
            cholesky,
            memory,
            last_solve: (0, 0.0),
        })
    }

    /// Factorises the matrix with the current [`KktSystem::values`]. The matrix is used as
    /// quasi-definite (`H` positive definite): pivots of the wrong sign or smaller than
    /// `δ·1e-3` become `±δ` (faer's dynamic regularisation).
    ///
    /// # Errors
    /// [`FactorisationFailure::Singular`].
    pub fn factorise(&mut self, delta: f64) -> Result<(), FactorisationFailure> {
        let matrix = SparseColMat::new_from_argsort(self.symbolic.clone(), &self.argsort, &self.values)
            .expect("the values match the pattern analysed in KktSystem::new");
        let regularization = LdltRegularization {
            dynamic_regularization_signs: Some(&self.signs),
            dynamic_regularization_delta: delta,
            dynamic_regularization_epsilon: delta * 1e-3,
        };
        let result = self
            .cholesky
            .factorize_numeric_ldlt(
                &mut self.l_values,
                matrix.as_ref(),
                Side::Upper,
                regularization,
                Par::Seq,
                MemStack::new(&mut self.memory),
                Default::default(),
            )
            .map_err(|e| match e {
                // faer's index counts in an order of its own (measured: not the one its
                // `perm()` gives), so the caller diagnoses the place.
                faer::linalg::cholesky::ldlt::factor::LdltError::ZeroPivot { .. } => FactorisationFailure::Singular,
            });
        self.matrix = Some(matrix);
        result.map(|_| ())
    }

    /// Values in the factor `L`.
    pub fn factor_size(&self) -> usize {
        self.l_values.len()
    }

    /// Solves `K x = rhs` in place with the current factorisation and iterative
    /// refinement against the matrix without its `−δ` block: steps while the
    /// componentwise backward error `ω = max_i |r_i| / (|K| |x| + |b|)_i` (Oettli &
    /// Prager 1964; LAPACK's `BERR`) is above [`REFINED_BACKWARD_ERROR`] and each step at
    /// least halves it, at most [`MAX_REFINEMENT_STEPS`]. The factor is that of the
    /// matrix with `−δ`, so each step shrinks the error by about `δ ‖A H⁻¹ Aᵀ‖`.
    ///
    /// Why this measure: the tenth session stopped at a residual of `1e-10` relative to
    /// the largest right-hand side entry. The rows of `H` carry the term `Aᵀλ`, far
    /// larger than the defects `g` that form the right-hand side, so their rounding floor
    /// (about `1e-11` absolute) sits above that bound on fine meshes (a 16k-vertex duct:
    /// `3e-7` relative); every solve then refined until the residual stopped halving. The
    /// backward error compares each row's residual with the size of the terms summed in
    /// that row, so it reaches rounding (`1e-16`–`1e-14`) when the solution is as good
    /// as the data allow. In block order (see [`KktSystem::new`]) the first solve's `ω`
    /// is `4e-10`–`2e-7` on a 16k-vertex duct and one or two refinement steps end it.
    ///
    /// [`KktSystem::last_solve`] records the triangular solves and the final `ω`.
    pub fn solve(&mut self, rhs: &mut [f64]) {
        self.solve_to(rhs, SolveAccuracy::Rounding);
    }

    /// [`KktSystem::solve`], refined only as far as `accuracy` asks (still at most
    /// [`MAX_REFINEMENT_STEPS`] steps, each at least halving `ω`).
    pub fn solve_to(&mut self, rhs: &mut [f64], accuracy: SolveAccuracy) {
        let size = self.n + self.nc;
        let ldlt = LdltRef::new(&self.cholesky, &self.l_values);
        let original = rhs.to_vec();
        ldlt.solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, size, 1),
            Par::Seq,
            MemStack::new(&mut self.memory),
        );
        let mut last = f64::INFINITY;
        // `solves`: triangular solves so far (the first, then one per refinement step).
        for solves in 1..=MAX_REFINEMENT_STEPS + 1 {
            let (product, magnitude) = self.product_and_magnitude(rhs);
            let mut residual: Vec<f64> = original.iter().zip(&product).map(|(b, a)| b - a).collect();
            // Componentwise backward error max_i |r_i| / (|K||x| + |b|)_i.
            let backward = residual
                .iter()
                .zip(&magnitude)
                .zip(&original)
                .map(|((r, m), b)| {
                    let d = m + b.abs();
                    if d > 0.0 {
                        r.abs() / d
                    } else {
                        0.0
                    }
                })
                .fold(0.0f64, f64::max);
            self.last_solve = (solves, backward);
            let accurate = match accuracy {
                SolveAccuracy::Rounding => backward <= REFINED_BACKWARD_ERROR,
                SolveAccuracy::ConstraintResidual(bound) => {
                    let metric_rows = residual[..self.n]
                        .iter()
                        .zip(&magnitude[..self.n])
                        .zip(&original[..self.n])
                        .all(|((r, m), b)| r.abs() <= PROJECTION_METRIC_BACKWARD_ERROR * (m + b.abs()));
                    metric_rows && residual[self.n..].iter().all(|r| r.abs() <= bound)
                }
            };
            if accurate || backward > 0.5 * last || solves > MAX_REFINEMENT_STEPS {
                break;
            }
            last = backward;
            ldlt.solve_in_place_with_conj(
                Conj::No,
                MatMut::from_column_major_slice_mut(&mut residual, size, 1),
                Par::Seq,
                MemStack::new(&mut self.memory),
            );
            for (x, d) in rhs.iter_mut().zip(&residual) {
                *x += d;
            }
        }
    }

    /// The step of least `H`-norm with `A p = −g`: `K [p; λ] = [0; −g]`, solved as an
    /// inexact Newton step (Dembo, Eisenstat & Steihaug, SIAM J. Numer. Anal. 19(2),
    /// 1982): refined until `|A p + g| ≤ min(10⁻³ max|g|, tolerance / 10)` in every
    /// constraint row, not to rounding. The forcing term `10⁻³` is far below the
    /// contraction the steps reach (the largest defect falls by 2–20× per step), and
    /// `tolerance / 10` keeps the last step from stopping short of the bound. The first
    /// solve usually meets it: on the 100k-vertex duct its constraint residual is
    /// `10⁻⁵`–`10⁻⁸` of `max|g|`, where refining to rounding took 2–5 triangular solves
    /// per step (docs/benchmarks-history.md, session 19).
    pub fn projection(&mut self, defects: &[f64], tolerance: f64) -> Vec<f64> {
        let largest = defects.iter().fold(0.0f64, |m, g| m.max(g.abs()));
        let bound = (1e-3 * largest).min(0.1 * tolerance);
        let mut rhs: Vec<f64> = vec![0.0; self.n]
            .into_iter()
            .chain(defects.iter().map(|g| -g))
            .collect();
        self.solve_to(&mut rhs, SolveAccuracy::ConstraintResidual(bound));
        rhs.truncate(self.n);
        rhs
    }

    /// `K x` for the matrix last factorised (its upper triangle, duplicates summed),
    /// leaving out the `−δ` diagonal of the constraint block (the last `nc` entries).
    ///
    /// # Panics
    /// Before the first [`KktSystem::factorise`].
    #[cfg(test)]
    pub fn product(&self, x: &[f64]) -> Vec<f64> {
        self.product_and_magnitude(x).0
    }

    /// `K x` (its upper triangle, duplicates summed, without the `−δ` diagonal of the
    /// constraint block) and `|K| |x|` (entrywise absolute values).
    fn product_and_magnitude(&self, x: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let matrix = self.matrix.as_ref().expect("product after a factorisation").as_ref();
        let mut out = vec![0.0; x.len()];
        let mut magnitude = vec![0.0; x.len()];
        for col in 0..self.n + self.nc {
            let (mut sum, mut sum_abs) = (0.0, 0.0);
            for (row, &v) in matrix.row_idx_of_col(col).zip(matrix.val_of_col(col)) {
                if row == col {
                    if row < self.n {
                        sum += v * x[col];
                        sum_abs += (v * x[col]).abs();
                    }
                } else {
                    sum += v * x[row];
                    sum_abs += (v * x[row]).abs();
                    out[row] += v * x[col];
                    magnitude[row] += (v * x[col]).abs();
                }
            }
            out[col] += sum;
            magnitude[col] += sum_abs;
        }
        (out, magnitude)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 35: the factor's size is known from the column counts before its structure is
    /// built: an arrow matrix (every unknown coupled to one, as every gore to the waist)
    /// fills nothing when that unknown comes last (`2n − 1` values: the diagonal and the
    /// last row) and everything when it comes first (`n(n + 1)/2`); faer's symbolic factor
    /// stores at least that many (its supernodes pad). Over the memory bound the error
    /// names the model and the sizes.
    #[test]
    fn the_factor_size_is_known_before_the_factor_is_built() {
        let n = 200;
        let mut pairs: Vec<Pair<usize, usize>> = (0..n).map(|k| Pair::new(k, k)).collect();
        pairs.extend((0..n - 1).map(|k| Pair::new(k, n - 1)));
        let (pattern, _) = SymbolicSparseColMat::try_new_from_indices(n, n, &pairs).unwrap();
        let last: Vec<usize> = (0..n).collect();
        let first: Vec<usize> = std::iter::once(n - 1).chain(0..n - 1).collect();
        for (forward, expected) in [(last, 2 * n - 1), (first, n * (n + 1) / 2)] {
            let mut inverse = vec![0; n];
            for (k, &i) in forward.iter().enumerate() {
                inverse[i] = k;
            }
            assert_eq!(factor_values(&pattern, &inverse), Some(expected));
            let symbolic = factorize_symbolic_cholesky(
                pattern.as_ref(),
                Side::Upper,
                SymmetricOrdering::Custom(faer::perm::PermRef::new_checked(&forward, &inverse, n)),
                Default::default(),
            )
            .unwrap();
            assert!(symbolic.len_val() >= expected);
        }
        let e = over_the_memory_bound(425_000, 10_100_000_000).to_string();
        assert!(
            e.contains("425000 rows") && e.contains("10.1 GB") && e.contains("8 GB"),
            "{e}"
        );
    }

    /// A small KKT system `[H Aᵀ; A −δI]` (4 unknowns, one constraint `x0 + x1`), stored
    /// with a duplicate entry, is solved to rounding.
    #[test]
    fn a_zero_pivot_is_reported_not_a_panic() {
        // diag(1, 0, 2) without regularisation: singular.
        let pairs: Vec<Pair<usize, usize>> = (0..3).map(|i| Pair { row: i, col: i }).collect();
        let coordinates: Vec<Vector3<f64>> = (0..3).map(|x| Vector3::new(x as f64, 0.0, 0.0)).collect();
        let mut kkt = KktSystem::new(3, 0, pairs, &[0, 1, 2], &coordinates, true).unwrap();
        kkt.values = vec![1.0, 0.0, 2.0];
        assert_eq!(kkt.factorise(0.0), Err(FactorisationFailure::Singular));
        kkt.values = vec![1.0, 3.0, 2.0];
        assert_eq!(kkt.factorise(0.0), Ok(()));
    }

    #[test]
    fn solves_a_small_kkt_system() {
        let mut pairs = Vec::new();
        let mut values = Vec::new();
        for (i, d) in [2.0, 1.0, 3.0, 1.5].into_iter().enumerate() {
            pairs.push(Pair { row: i, col: i });
            values.push(d);
            if i + 1 < 4 {
                pairs.push(Pair { row: i, col: i + 1 });
                values.push(0.1);
            }
        }
        // The (0, 0) entry again: duplicates are summed.
        pairs.push(Pair { row: 0, col: 0 });
        values.push(0.5);
        for i in 0..2 {
            pairs.push(Pair { row: i, col: 4 });
            values.push(1.0);
        }
        pairs.push(Pair { row: 4, col: 4 });
        values.push(-1e-12);
        // The constraint shares unknown 0's block.
        let blocks = [0, 1, 2, 3, 0];
        let coordinates = [0.0, 1.0, 2.0, 3.0].map(|x| Vector3::new(x, 0.0, 0.0));
        let mut kkt = KktSystem::new(4, 1, pairs, &blocks, &coordinates, false).unwrap();
        kkt.values = values;
        kkt.factorise(1e-12).unwrap();
        let mut rhs = vec![1.0, -2.0, 0.5, 0.25, 0.3];
        let original = rhs.clone();
        kkt.solve(&mut rhs);
        let product = kkt.product(&rhs);
        // Refined to the backward-error bound; the residual is at rounding level.
        assert!(kkt.last_solve.1 <= REFINED_BACKWARD_ERROR, "{:?}", kkt.last_solve);
        for (a, b) in product.iter().zip(&original) {
            assert!((a - b).abs() <= 1e-12, "{product:?} vs {original:?}");
        }
        // The constraint holds: x0 + x1 = 0.3.
        assert!((rhs[0] + rhs[1] - 0.3).abs() <= 1e-12);
        // The projection satisfies A p = −g.
        let p = kkt.projection(&[0.7], 1e-12);
        assert!((p[0] + p[1] + 0.7).abs() <= 1e-13);
    }

    /// A larger system (a 30 × 30 grid: `H` = graph Laplacian + I on three unknowns per
    /// node, one constraint per ten nodes coupling a node's first unknown to its right
    /// neighbour's) is solved to rounding with either ordering, in block order with one
    /// refinement step (two triangular solves; with every unknown a block of its own,
    /// four); when both are compared, the one kept fills no more than nested dissection
    /// (on this small grid AMD: 32.4k values in `L` against 47.6k).
    #[test]
    fn solves_a_grid_system_in_nested_dissection_order() {
        let side = 30;
        let nodes = side * side;
        let (n, nc) = (3 * nodes, nodes / 10);
        let mut pairs = Vec::new();
        let mut values = Vec::new();
        let mut coordinates = Vec::new();
        let mut blocks = Vec::new();
        for node in 0..nodes {
            let (i, j) = (node % side, node / side);
            let neighbours: Vec<usize> = [(i + 1 < side, node + 1), (j + 1 < side, node + side)]
                .into_iter()
                .filter_map(|(ok, m)| ok.then_some(m))
                .collect();
            let degree = [i > 0, i + 1 < side, j > 0, j + 1 < side]
                .iter()
                .filter(|&&b| b)
                .count();
            for k in 0..3 {
                pairs.push(Pair {
                    row: 3 * node + k,
                    col: 3 * node + k,
                });
                values.push(1.0 + degree as f64);
                for &m in &neighbours {
                    pairs.push(Pair {
                        row: 3 * node + k,
                        col: 3 * m + k,
                    });
                    values.push(-1.0);
                }
            }
            coordinates.push(Vector3::new(i as f64, j as f64, 0.0));
            blocks.extend([node; 3]);
        }
        for c in 0..nc {
            let node = 10 * c + 3;
            pairs.push(Pair {
                row: 3 * node,
                col: n + c,
            });
            values.push(1.0);
            pairs.push(Pair {
                row: 3 * (node + 1),
                col: n + c,
            });
            values.push(-2.0);
            pairs.push(Pair { row: n + c, col: n + c });
            values.push(-1e-12);
            blocks.push(node);
        }
        let dissected_size = KktSystem::with_ordering_choice(
            n,
            nc,
            pairs.clone(),
            &blocks,
            &coordinates,
            OrderingChoice::NestedDissection,
            false,
        )
        .unwrap()
        .factor_size();
        for choice in [
            OrderingChoice::Smaller,
            OrderingChoice::NestedDissection,
            OrderingChoice::Amd,
        ] {
            let mut kkt =
                KktSystem::with_ordering_choice(n, nc, pairs.clone(), &blocks, &coordinates, choice, false).unwrap();
            match choice {
                OrderingChoice::Smaller => {
                    let (amd, dissected) = kkt.compared_factor_sizes.expect("both analysed");
                    assert_eq!(dissected, dissected_size);
                    assert_eq!(kkt.factor_size(), amd.min(dissected));
                }
                OrderingChoice::NestedDissection => assert_eq!(kkt.ordering, "nested dissection"),
                OrderingChoice::Amd => {
                    assert_eq!(kkt.ordering, "amd");
                    assert!(kkt.compared_factor_sizes.is_none());
                }
            }
            kkt.values = values.clone();
            kkt.factorise(1e-12).unwrap();
            let mut rhs: Vec<f64> = (0..n + nc).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
            let original = rhs.clone();
            kkt.solve(&mut rhs);
            let product = kkt.product(&rhs);
            let error = product
                .iter()
                .zip(&original)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            assert!(error < 1e-9, "{}: residual {error}", kkt.ordering);
            // In block order one refinement step reaches the backward-error bound.
            assert!(
                kkt.last_solve.0 <= 2 && kkt.last_solve.1 <= REFINED_BACKWARD_ERROR,
                "{}: {:?}",
                kkt.ordering,
                kkt.last_solve
            );
        }
        // Every unknown a block of its own: AMD eliminates constraints before their
        // unknowns (pivot −δ), and the first solve is far less accurate.
        let unknown_blocks: Vec<usize> = (0..n + nc).collect();
        let unknown_coordinates: Vec<Vector3<f64>> = (0..n)
            .map(|i| coordinates[i / 3])
            .chain((0..nc).map(|c| coordinates[10 * c + 3]))
            .collect();
        let mut kkt = KktSystem::with_ordering_choice(
            n,
            nc,
            pairs,
            &unknown_blocks,
            &unknown_coordinates,
            OrderingChoice::Amd,
            false,
        )
        .unwrap();
        kkt.values = values;
        kkt.factorise(1e-12).unwrap();
        let mut rhs: Vec<f64> = (0..n + nc).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        kkt.solve(&mut rhs);
        let to_rounding = kkt.last_solve.0;
        assert!(to_rounding > 2, "unit blocks: {:?}", kkt.last_solve);
        // A projection is an inexact Newton step: it stops refining once the constraint
        // rows are within min(1e-3 max|g|, tolerance / 10) and the metric rows within
        // their backward error, in fewer solves than to rounding, and the bound holds.
        let defects: Vec<f64> = (0..nc).map(|c| 1e-4 * (((c * 31) % 7) as f64 - 3.0)).collect();
        for (tolerance, bound) in [(1e-2, 3e-7), (1e-9, 1e-10)] {
            let step = kkt.projection(&defects, tolerance);
            let solves = kkt.last_solve.0;
            let mut x = step.clone();
            x.extend(std::iter::repeat_n(0.0, nc));
            // A p from the constraint columns of K x (λ set to 0 leaves A p in those rows).
            let product = kkt.product(&x);
            let worst = product[n..]
                .iter()
                .zip(&defects)
                .map(|(ap, g)| (ap + g).abs())
                .fold(0.0, f64::max);
            assert!(worst <= bound, "tolerance {tolerance}: |A p + g| = {worst:e}");
            if tolerance > 1e-3 {
                assert!(solves < to_rounding, "{solves} solves, {to_rounding} to rounding");
            }
        }
    }
}

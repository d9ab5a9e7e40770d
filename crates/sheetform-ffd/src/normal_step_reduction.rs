//! The constrained solver's KKT system reduced to one unknown per node: a step along
//! each node's surface normal (`solver.step_unknowns: "normal"`).
//!
//! Each variable node `v` moves in parameter space along `d_v = J_v⁻¹ n̂_v` only
//! (`J_v = ∂Q/∂(u,v,w)` the deformed lattice's Jacobian at the node, `n̂_v` the unit
//! area-weighted normal of its triangles): the node's position moves by `t_v n̂_v` to
//! first order, `t_v` in model units. With the basis `B = diag(d_v)` (3 × 1 per node),
//! the projection step of the full system,
//!
//! `[H  Aᵀ; A  −δI] [p; λ] = [0; −g]`, `p` the 3n parameter changes,
//!
//! becomes `[BᵀHB  (AB)ᵀ; AB  −δI] [t; λ] = [0; −g]` with `p = B t`: a step of least
//! `H`-norm among the steps along the normals. The reduced matrix has two unknowns per
//! node instead of four (the node's unknowns and the defect at that node), so its
//! factor holds about a quarter of the values (16k-vertex duct: 6.3 M against 28.3 M;
//! 100k: 52 M against 226 M) and its factorisation costs about an eighth.
//!
//! Why normals: a tangential move of a node on a flat or developable patch leaves the
//! angle sums unchanged to first order, so the defects are removed mainly by normal
//! moves; the tangential freedom of the full system lets the mesh slide to keep its
//! edge lengths. Without it, a normal offset `t` of a surface of curvature `κ` stretches
//! its edges by about `κ t`: on the small examples the largest edge-length change grows
//! (duct 14.9 % → 20 %, trousers 22 % → 29 %), at 100k vertices it stays within 10 % of
//! the full system's (15.4 % against 14.3 %; docs/benchmarks-history.md). A departure from the
//! paper, whose unknowns are the three parameters of every node; off by default.

use crate::{DevelopabilityProblem, Evaluation, FfdError};
use faer::sparse::Pair;
use nalgebra::Vector3;

/// The reduction `B` of the full KKT system's unknowns to one per variable node.
pub(crate) struct NormalStepReduction {
    /// Unknowns of the full system (three per variable node).
    full_unknowns: usize,
    /// For each entry of the full system, in the order it is assembled: the index of the
    /// reduced value it adds to.
    slots: Vec<u32>,
    /// `B`'s entry for each full unknown `3v + k`: `d_v[k]`.
    coefficients: Vec<f64>,
}

impl NormalStepReduction {
    /// The reduction of a full system of `full_unknowns` unknowns (then its constraints)
    /// whose upper-triangle entries, in the order they are assembled, fall on the
    /// reduced entries `reduced_entries` ([`NormalStepReduction::reduced_entry`] of each
    /// full `(row, column)`; duplicates allowed), and the reduced system's pairs, each
    /// once (column by column, rows ascending). The reduced values are then summed
    /// straight into their slots ([`NormalStepReduction::reducer`]): the full system is
    /// never stored (100k-vertex duct: 1.5 M reduced values against 10.8 M full ones).
    ///
    /// # Errors
    /// [`FfdError::Solver`] if the system has more than `u32::MAX` entries (the model
    /// size bounds keep it far below: 27 M at 250k vertices).
    pub fn new(
        full_unknowns: usize,
        reduced_entries: &[(u32, u32)],
    ) -> Result<(Self, Vec<Pair<usize, usize>>), FfdError> {
        if reduced_entries.len() > u32::MAX as usize {
            return Err(FfdError::Solver(format!(
                "the restoration's system has {} entries, more than this solver indexes",
                reduced_entries.len()
            )));
        }
        let size = reduced_entries.iter().map(|&(_, c)| c as usize + 1).max().unwrap_or(0);
        // Bucket the entries by reduced column (a counting sort) as `row << 32 | entry`,
        // then sort each column's few entries and give each distinct row one slot.
        let mut column_start = vec![0usize; size + 1];
        for &(_, c) in reduced_entries {
            column_start[c as usize + 1] += 1;
        }
        for c in 0..size {
            column_start[c + 1] += column_start[c];
        }
        let mut next = column_start.clone();
        let mut by_column = vec![0u64; reduced_entries.len()];
        for (i, &(r, c)) in reduced_entries.iter().enumerate() {
            by_column[next[c as usize]] = (u64::from(r) << 32) | i as u64;
            next[c as usize] += 1;
        }
        let mut slots = vec![0u32; reduced_entries.len()];
        let mut reduced_pairs = Vec::new();
        for col in 0..size {
            let members = &mut by_column[column_start[col]..column_start[col + 1]];
            members.sort_unstable();
            let mut last_row = u64::MAX;
            for &member in members.iter() {
                let row = member >> 32;
                if row != last_row {
                    reduced_pairs.push(Pair { row: row as usize, col });
                    last_row = row;
                }
                // At most `u32::MAX` reduced pairs: no more than the entries.
                slots[(member & u64::from(u32::MAX)) as usize] = (reduced_pairs.len() - 1) as u32;
            }
        }
        let reduction = Self {
            full_unknowns,
            slots,
            coefficients: vec![0.0; full_unknowns],
        };
        Ok((reduction, reduced_pairs))
    }

    /// The reduced system's entry `(row, column)`, upper triangle, of the full system's
    /// entry `(row, col)`: a node's three parameters become its one unknown, the
    /// constraints follow. (Indices below `u32::MAX`: models have at most 250k vertices.)
    pub fn reduced_entry(full_unknowns: usize, row: usize, col: usize) -> (u32, u32) {
        let nodes = full_unknowns / 3;
        let reduced = |i: usize| {
            let r = if i < full_unknowns {
                i / 3
            } else {
                i - full_unknowns + nodes
            };
            r as u32
        };
        let (a, b) = (reduced(row), reduced(col));
        (a.min(b), a.max(b))
    }

    /// Unknowns of the reduced system.
    pub fn unknowns(&self) -> usize {
        self.full_unknowns / 3
    }

    /// Sets `B` at evaluation `e` ([`normal_directions`]).
    pub fn update(&mut self, problem: &DevelopabilityProblem<'_>, e: &Evaluation) {
        for (v, d) in normal_directions(problem, e).iter().enumerate() {
            self.coefficients[3 * v..3 * v + 3].copy_from_slice(d.as_slice());
        }
    }

    /// A receiver of the full system's entries, in their assembly order, that sums
    /// `BᵀKB` into `reduced_values` (one per reduced pair, zeroed by the caller): entry
    /// `(i, j)` adds `B_i K_ij B_j` to its slot, where `B_i` is `d_v[k]` for a parameter
    /// `i = 3v + k` and 1 for a constraint. An entry `(3v + k, 3v + l)`, `k < l`, of the
    /// full upper triangle stands for both `K_kl` and `K_lk` of the node's block, which
    /// fall on the same reduced entry: it counts twice.
    pub fn reducer<'a>(&'a self, reduced_values: &'a mut [f64]) -> Reducer<'a> {
        Reducer {
            reduction: self,
            reduced_values,
            next: 0,
        }
    }

    /// `Bᵀ x` of a full unknown vector `x`.
    pub fn reduce_vector(&self, x: &[f64]) -> Vec<f64> {
        x.chunks_exact(3)
            .zip(self.coefficients.chunks_exact(3))
            .map(|(x, d)| x[0] * d[0] + x[1] * d[1] + x[2] * d[2])
            .collect()
    }

    /// `B t`: the full parameter step of a reduced step `t`.
    pub fn expand(&self, t: &[f64]) -> Vec<f64> {
        t.iter()
            .zip(self.coefficients.chunks_exact(3))
            .flat_map(|(t, d)| [t * d[0], t * d[1], t * d[2]])
            .collect()
    }
}

/// See [`NormalStepReduction::reducer`].
pub(crate) struct Reducer<'a> {
    reduction: &'a NormalStepReduction,
    reduced_values: &'a mut [f64],
    /// Entries received so far.
    next: usize,
}

impl Reducer<'_> {
    /// Adds the full system's next entry `(row, col, value)`, `row ≤ col`.
    pub fn add(&mut self, row: usize, col: usize, value: f64) {
        let n = self.reduction.full_unknowns;
        let coefficient = |i: usize| if i < n { self.reduction.coefficients[i] } else { 1.0 };
        let multiplicity = if row != col && col < n && row / 3 == col / 3 {
            2.0
        } else {
            1.0
        };
        let slot = self.reduction.slots[self.next] as usize;
        self.next += 1;
        self.reduced_values[slot] += value * coefficient(row) * coefficient(col) * multiplicity;
    }
}

/// Per variable node, the parameter direction `d = J⁻¹ n̂` that the deformed lattice maps
/// to the unit normal `n̂` of the node's triangles (area-weighted, at the evaluation's
/// positions). A node whose triangles' normals cancel (panels wound against each other
/// at a seam) takes its first triangle's; a singular `J` gives `d = 0`, which makes the
/// system singular and the restoration name the place
/// (`constrained_gauss_newton::degenerate`).
pub(crate) fn normal_directions(problem: &DevelopabilityProblem<'_>, e: &Evaluation) -> Vec<Vector3<f64>> {
    let node_count = e.positions.len();
    let mut summed = vec![Vector3::zeros(); node_count];
    let mut first: Vec<Option<Vector3<f64>>> = vec![None; node_count];
    let mut magnitude = vec![0.0; node_count];
    for t in &problem.assembly.node_triangles {
        let [a, b, c] = t.map(|m| e.positions[m as usize]);
        let normal = (b - a).cross(&(c - a));
        for &m in t {
            let m = m as usize;
            summed[m] += normal;
            magnitude[m] += normal.norm();
            first[m].get_or_insert(normal);
        }
    }
    problem
        .variables
        .iter()
        .zip(&e.jacobians)
        .map(|(&m, jacobian)| {
            let m = m as usize;
            let normal = if summed[m].norm() > 1e-6 * magnitude[m] {
                summed[m]
            } else {
                first[m].unwrap_or_else(Vector3::zeros)
            };
            let unit = normal.try_normalize(0.0).unwrap_or_else(Vector3::zeros);
            jacobian
                .try_inverse()
                .map_or_else(Vector3::zeros, |inverse| inverse * unit)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The reduced values are `BᵀKB` of the full symmetric matrix, with the full
    /// matrix given as an upper triangle with duplicates and the reduced one summed by
    /// pair: a dense oracle on a random system of three nodes and two constraints.
    #[test]
    #[allow(clippy::needless_range_loop)] // dense matrix products read clearest indexed
    fn the_reduced_system_is_the_projection_of_the_full_one() {
        let (nodes, constraints) = (3, 2);
        let n = 3 * nodes;
        let size = n + constraints;
        // A fixed pseudo-random sequence (no seed-dependent crate needed).
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut random = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        // Every upper entry, some twice (duplicates are summed), in a shuffled order.
        let mut pairs = Vec::new();
        for col in 0..size {
            for row in 0..=col {
                pairs.push((row, col));
                if (row + col) % 4 == 0 {
                    pairs.push((row, col));
                }
            }
        }
        pairs.reverse();
        pairs.rotate_left(7);
        let values: Vec<f64> = pairs.iter().map(|_| random()).collect();
        let entries: Vec<(u32, u32)> = pairs
            .iter()
            .map(|&(row, col)| NormalStepReduction::reduced_entry(n, row, col))
            .collect();
        let (mut reduction, reduced_pairs) = NormalStepReduction::new(n, &entries).unwrap();
        for c in &mut reduction.coefficients {
            *c = random();
        }
        let mut dense = vec![vec![0.0; size]; size];
        for (&(row, col), v) in pairs.iter().zip(&values) {
            dense[row][col] += v;
            if row != col {
                dense[col][row] += v;
            }
        }
        // B: 3 × 1 per node, identity on the constraints.
        let reduced_size = nodes + constraints;
        let b = |i: usize, j: usize| -> f64 {
            match (i < n, j < nodes) {
                (true, true) if i / 3 == j => reduction.coefficients[i],
                (false, false) => f64::from(u8::from(i - n == j - nodes)),
                _ => 0.0,
            }
        };
        let mut reduced_values = vec![0.0; reduced_pairs.len()];
        let mut reducer = reduction.reducer(&mut reduced_values);
        for (&(row, col), &v) in pairs.iter().zip(&values) {
            reducer.add(row, col, v);
        }
        let mut reduced = vec![vec![0.0; reduced_size]; reduced_size];
        // Each reduced entry once, column by column with rows ascending.
        assert!(reduced_pairs
            .windows(2)
            .all(|w| (w[0].col, w[0].row) < (w[1].col, w[1].row)));
        for (p, v) in reduced_pairs.iter().zip(&reduced_values) {
            assert!(p.row <= p.col);
            reduced[p.row][p.col] += v;
        }
        for col in 0..reduced_size {
            for row in 0..=col {
                let mut expected = 0.0;
                for i in 0..size {
                    for j in 0..size {
                        expected += b(i, row) * dense[i][j] * b(j, col);
                    }
                }
                assert!(
                    (reduced[row][col] - expected).abs() <= 1e-12,
                    "({row}, {col}): {} against {expected}",
                    reduced[row][col]
                );
            }
        }
        // Bᵀx and Bt agree with the dense B.
        let x: Vec<f64> = (0..n).map(|_| random()).collect();
        for (j, value) in reduction.reduce_vector(&x).iter().enumerate() {
            let expected: f64 = (0..n).map(|i| b(i, j) * x[i]).sum();
            assert!((value - expected).abs() <= 1e-15);
        }
        let t: Vec<f64> = (0..nodes).map(|_| random()).collect();
        for (i, value) in reduction.expand(&t).iter().enumerate() {
            let expected: f64 = (0..nodes).map(|j| b(i, j) * t[j]).sum();
            assert!((value - expected).abs() <= 1e-15);
        }
    }
}

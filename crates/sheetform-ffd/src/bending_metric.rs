//! An optional term of the constrained solver's step metric that penalises uneven normal
//! motion: `½ γ Σ_v (n_vᵀ Σ_{u∈N(v)} (δq_u − δq_v))² / l̄²`.

use crate::{DevelopabilityProblem, Evaluation};
use nalgebra::Vector3;
use sheetform_mesh::area_weighted_normals;

type Vec3 = Vector3<f64>;

/// The rows of the uniform graph Laplacian of the variable nodes, in variable indices.
///
/// For every variable node `v` with neighbours `N(v)` (the ends of its springs), the row is
/// `Σ_{u∈N(v)} δq_u − |N(v)| δq_v`; fixed neighbours do not move (`δq_u = 0`), so their
/// terms are left out of the row while still counting in `|N(v)|`.
///
/// The constrained solver adds, when its `bending_weight` `γ > 0`, the Gauss–Newton
/// matrix of
///
/// `B(δX) = ½ γ Σ_v (n_vᵀ Σ_u c_vu J_u δX_u)² / l̄²`
///
/// to the metric `H` of its steps (`n_v`: the area-weighted unit normal at node `v`,
/// `J_u = ∂Q/∂(u,v,w)` at node `u`, `c_vu` the row's coefficients, `l̄` the mean edge
/// length; `γ` is dimensionless). `B` measures how unevenly the step moves neighbouring
/// nodes along the normal, a discrete `|Δw|²` of the normal displacement `w`.
///
/// Why: with springs alone, moving a node along the normal changes edge lengths only to
/// second order, so the least-`H`-norm projection uses large single-node normal moves.
/// Those moves change the defects to second order as well, so the linearisation is poor
/// and the line search cuts the steps to `1/16`–`1/32` for tens of iterations (skirt: 38
/// iterations). With `γ = 0.1` the same example takes 7 full steps; the rows of boundary
/// and seam nodes alone (which no defect constrains) give 21, those of interior nodes
/// alone 31, so every variable node has a row. The normals are those of the current
/// iterate. The term is part of the metric only, not of the objective the solver
/// reports; it changes which developable shape the projection reaches: the edge lengths
/// change more (docs/benchmarks.md has the figures). Not in the paper (§3 has no step
/// metric).
#[derive(Debug, Clone)]
pub(crate) struct BendingMetric {
    /// `(node, [(variable, coefficient)])` per variable node.
    rows: Vec<(u32, Vec<(u32, f64)>)>,
    /// The distinct 3×3 blocks `(a, b)`, `a ≤ b`, that the rows touch.
    blocks: Vec<(u32, u32)>,
    /// Per row, the block of each pair `(i, j)`, `i ≤ j`, of its entries, in the order
    /// `(0,0), (0,1), …, (1,1), …`.
    row_blocks: Vec<Vec<u32>>,
    /// The panels' triangles in node indices (for the nodes' normals).
    node_triangles: Vec<[u32; 3]>,
}

impl BendingMetric {
    /// The Laplacian rows of `problem`'s variable nodes.
    pub fn new(problem: &DevelopabilityProblem<'_>) -> Self {
        let nodes = problem.variable_of_node.len();
        let mut neighbours: Vec<Vec<u32>> = vec![Vec::new(); nodes];
        for s in &problem.springs {
            neighbours[s.a as usize].push(s.b);
            neighbours[s.b as usize].push(s.a);
        }
        let rows = problem
            .variables
            .iter()
            .enumerate()
            .map(|(v, &node)| {
                let around = &neighbours[node as usize];
                let mut row: Vec<(u32, f64)> = around
                    .iter()
                    .map(|&u| problem.variable_of_node[u as usize])
                    .filter(|&u| u != u32::MAX)
                    .map(|u| (u, 1.0))
                    .collect();
                row.push((v as u32, -(around.len() as f64)));
                (node, row)
            })
            .collect::<Vec<(u32, Vec<(u32, f64)>)>>();
        let mut index = std::collections::HashMap::new();
        let mut blocks = Vec::new();
        let row_blocks = rows
            .iter()
            .map(|(_, row)| {
                let mut ids = Vec::with_capacity(row.len() * (row.len() + 1) / 2);
                for (i, &(a, _)) in row.iter().enumerate() {
                    for &(b, _) in &row[i..] {
                        let key = (a.min(b), a.max(b));
                        let id = *index.entry(key).or_insert_with(|| {
                            blocks.push(key);
                            blocks.len() as u32 - 1
                        });
                        ids.push(id);
                    }
                }
                ids
            })
            .collect();
        let assembly = problem.assembly;
        let node_triangles = assembly
            .mesh
            .triangles
            .iter()
            .map(|t| t.map(|v| assembly.vertex_node[v as usize]))
            .collect();
        Self {
            rows,
            blocks,
            row_blocks,
            node_triangles,
        }
    }

    /// Calls `push(row, column, value)` for the upper triangle of `γ/l̄² · Σ_v r_vᵀ r_v`,
    /// `r_v = Σ_u c_vu n_vᵀ J_u` (3 columns per variable), at evaluation `e`, one entry
    /// per distinct position. The sequence of `(row, column)` pairs depends only on the
    /// problem, not on `e`.
    pub fn push_upper(&self, e: &Evaluation, weight: f64, mut push: impl FnMut(usize, usize, f64)) {
        let normals = area_weighted_normals(&e.positions, &self.node_triangles);
        let mut sums = vec![nalgebra::Matrix3::<f64>::zeros(); self.blocks.len()];
        let mut parts: Vec<(u32, Vec3)> = Vec::new();
        for ((node, row), ids) in self.rows.iter().zip(&self.row_blocks) {
            let normal = normals[*node as usize];
            parts.clear();
            parts.extend(
                row.iter()
                    .map(|&(u, c)| (u, e.jacobians[u as usize].tr_mul(&normal) * c)),
            );
            let mut id = ids.iter();
            for (i, &(a, ra)) in parts.iter().enumerate() {
                for &(b, rb) in &parts[i..] {
                    let block = &mut sums[*id.next().expect("one block per pair") as usize];
                    // The block (min, max) of r_vᵀ r_v: ra rbᵀ, or its transpose.
                    *block += if a <= b {
                        ra * rb.transpose()
                    } else {
                        rb * ra.transpose()
                    };
                }
            }
        }
        for (&(a, b), block) in self.blocks.iter().zip(&sums) {
            let (a, b) = (a as usize, b as usize);
            for k in 0..3 {
                for l in 0..3 {
                    if a == b && l < k {
                        continue;
                    }
                    // Diagonal blocks are symmetric: their upper triangle only.
                    push(3 * a + k, 3 * b + l, weight * block[(k, l)]);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::procedural_panels::ProceduralModel;
    use crate::{apply_edits, embed_points, FfdScene, PanelAssembly, ProblemOptions};

    /// The pushed entries are the upper triangle of `γ Σ_v r_vᵀ r_v`: the quadratic form
    /// they define equals `γ Σ_v (n_vᵀ Σ_{u∈N(v)} (δq_u − δq_v))²` computed directly from
    /// the node displacements `δq = J δX` of a step (fixed nodes do not move).
    #[test]
    fn quadratic_form_is_the_normal_laplacian_of_the_step() {
        let mesh = ProceduralModel::TwoPanels { columns: 5, rows: 4 }.build();
        let assembly = PanelAssembly::from_mesh(&mesh).unwrap();
        let scene = FfdScene::from_json(
            r#"{"model": {"procedural": {"kind": "two_panels"}}, "lattice": {"counts": [4, 4, 4]},
                "deformations": [{"edits": [
                   {"move": {"points": [[1, 2, 1], [2, 1, 2]], "by": [30, -20, 15]}}]}]}"#,
        )
        .unwrap();
        let nodes = assembly.node_positions();
        let lattice = scene.lattice(&nodes).unwrap();
        let x = embed_points(&lattice, &nodes).unwrap();
        let volume = apply_edits(&lattice, &scene.deformations[0].edits, "edits").unwrap();
        let problem = DevelopabilityProblem::new(&volume, &assembly, x, &ProblemOptions::default());
        // Some nodes stay fixed, so rows with dropped neighbours are exercised.
        assert!(problem.variables.len() > 10 && problem.variables.len() < assembly.node_count);
        let e = problem.evaluate(&problem.gather(&problem.start));
        let step: Vec<f64> = (0..problem.unknown_count()).map(|i| (i as f64 * 0.61).sin()).collect();
        let gamma = 0.37;
        let mut form = 0.0;
        let metric = BendingMetric::new(&problem);
        metric.push_upper(&e, gamma, |r, c, v| {
            form += if r == c {
                v * step[r] * step[r]
            } else {
                2.0 * v * step[r] * step[c]
            };
        });
        // Directly: node displacements, then the normal component of their Laplacian.
        let mut moved = vec![Vec3::zeros(); assembly.node_count];
        for (v, &node) in problem.variables.iter().enumerate() {
            moved[node as usize] = e.jacobians[v] * Vec3::new(step[3 * v], step[3 * v + 1], step[3 * v + 2]);
        }
        let normals = area_weighted_normals(&e.positions, &metric.node_triangles);
        let mut laplacian = vec![Vec3::zeros(); assembly.node_count];
        for s in &problem.springs {
            let (a, b) = (s.a as usize, s.b as usize);
            laplacian[a] += moved[b] - moved[a];
            laplacian[b] += moved[a] - moved[b];
        }
        let direct: f64 = problem
            .variables
            .iter()
            .map(|&node| gamma * normals[node as usize].dot(&laplacian[node as usize]).powi(2))
            .sum();
        assert!(direct > 1e-3);
        assert!((form - direct).abs() <= 1e-10 * direct, "{form} vs {direct}");
        // Normals are unit vectors.
        for &node in &problem.variables {
            assert!((normals[node as usize].norm() - 1.0).abs() < 1e-12);
        }
    }
}

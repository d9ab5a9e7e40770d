//! An optional term of the constrained solver's step metric that penalises bending
//! steps: `½ γ (A/l̄²) Σ_e w_e (δθ_e)²`, `δθ_e` the step's change of the dihedral angle at
//! each interior edge.

use crate::{DevelopabilityProblem, Evaluation};
use nalgebra::Vector3;
use sheetform_mesh::signed_fold_angle_gradients;

type Vec3 = Vector3<f64>;

/// The hinges of the welded panels: every edge shared by two triangles, inside a panel
/// or across a seam between two panels, with the linearised change of its dihedral
/// angle as a row over the variables.
///
/// The constrained solver adds, when its `bending_weight` `γ > 0` (default 3e-3), the
/// Gauss–Newton matrix of
///
/// `B(δX) = ½ γ (A/l̄²) Σ_e w_e (Σ_{i∈{a,b,c,d}} ∇_iθ_eᵀ J_i δX_i)²`
///
/// to the metric `H` of its steps: `θ_e` the dihedral angle at edge `e = (a, b)` between
/// triangles `(a, b, c)` and `(b, a, d)`, `∇_iθ_e` its gradient with respect to node `i`
/// at the current iterate, `J_i = ∂Q/∂(u,v,w)` at node `i` (fixed nodes do not move),
/// `w_e = |e|² / (A₁ + A₂)` the edge's weight in the plain FFD (dimensionless), `A` the
/// panels' area and `l̄` the mean edge length there; `γ` is dimensionless. This is the
/// Gauss–Newton matrix of the discrete-shells bending energy `Σ_e w_e (θ_e − θ⁰_e)²`
/// (Grinspun, Hirani, Desbrun & Schröder, "Discrete shells", SCA 2003, Eq. 2 with
/// `3|e|²/A_e`) at `θ = θ⁰`. The gradients are `sheetform_mesh::signed_fold_angle_gradients`
/// (Bridson, Marino & Fedkiw, SCA 2003, §4; shared with `develop`'s bending term).
///
/// Why: with springs alone, moving a node along the normal changes edge lengths only to
/// second order, so the least-`H`-norm projection uses large single-node normal moves.
/// Those moves change the defects to second order as well, so the linearisation is poor
/// and the line search cuts the steps to `1/16`–`1/32` for tens of iterations (skirt: 27
/// iterations), and the developable shape it reaches is crinkled: node-scale zig-zag
/// folds (largest fold angle 0.56 rad against the deformed mesh's 0.09 on the skirt).
/// The term makes the steps smooth, so they are taken in full: skirt 4 steps, ending
/// at 0.088 rad.
///
/// Scaling: for a strain `ε` on edges of length `h` the springs' sum `Σ (δl)²/l̄²` is
/// about `(A/h²) ε²`, while `Σ_e w_e (δθ_e)²` is about `∫ |∇²w|²` (`w` the normal
/// displacement), independent of `h`; without the factor `A/l̄²` the term would fade
/// like `h²` as a mesh is refined. The term is part of the metric only, not of the
/// objective the solver reports; it changes which developable shape the projection
/// reaches: fair, with larger edge-length changes (docs/benchmarks-history.md has the figures).
/// Not in the paper (§3 has no step metric).
///
/// Until the tenth session the term was an umbrella Laplacian of the normal
/// displacement at every node, `Σ_v (n_vᵀ Σ_{u∈N(v)} (δq_u − δq_v))² / l̄²` (`γ` 3e-4).
/// Its rows couple a node's whole 2-ring, which the KKT factor had to hold (skirt: 562k
/// values in `L` against 423k with the springs alone; with hinges 380k); a hinge
/// couples the four nodes of two triangles, which the defects' rows already couple. The
/// umbrella also coupled the panels across seams, where a garment may fold, and left
/// the results less fair (fold angles skirt 0.09 → 0.13 rad, duct 0.21 → 0.42; with
/// hinges 0.088 and 0.201) in more steps (skirt 7, trousers 8, duct 11; with hinges
/// 4, 4, 5).
///
/// Seams (fifteenth session): until then the hinges were the edges inside a panel only,
/// and the restoration put creases along the seams that the plain FFD did not have (the
/// largest dihedral angle across a seam: duct 8.1° → 24.9°, skirt 5.1° → 11.1°, two
/// panels 8.5° → 12.8°). With the seams' hinges it stays near the deformed shape's
/// (9.3°, 5.3°, 9.3°) in as many steps, the largest edge-length change within 8 % of
/// what it was (docs/benchmarks-history.md). The term penalises a step's change of the dihedral
/// angle, not the angle, so a seam folded in the design keeps its fold.
#[derive(Debug, Clone)]
pub(crate) struct BendingMetric {
    /// Per hinge: its nodes `[a, b, c, d]` (edge `a → b`, `c` and `d` opposite).
    hinges: Vec<[u32; 4]>,
    /// Per hinge: the variables of its nodes (`u32::MAX`: a fixed node).
    hinge_variables: Vec<[u32; 4]>,
    /// Per hinge: `w_e = |e|² / (A₁ + A₂)` in the plain FFD.
    hinge_weights: Vec<f64>,
    /// The distinct 3×3 blocks `(a, b)`, `a ≤ b`, in variable indices, that the hinges
    /// touch.
    blocks: Vec<(u32, u32)>,
    /// Per hinge `h`, `hinge_blocks[hinge_block_start[h]..hinge_block_start[h + 1]]`:
    /// the block of each pair `(i, j)`, `i ≤ j`, of its variable nodes (fixed nodes left
    /// out), in the order `(0,0), (0,1), …, (1,1), …`.
    hinge_blocks: Vec<u32>,
    /// Where each hinge's blocks start in `hinge_blocks` (one entry more than hinges).
    hinge_block_start: Vec<usize>,
    /// `A / l̄²`: the panels' area (plain FFD) over the squared mean edge length.
    pub resolution: f64,
}

impl BendingMetric {
    /// The hinges of `problem`'s panels that move at least one variable node.
    pub fn new(problem: &DevelopabilityProblem<'_>) -> Self {
        let assembly = problem.assembly;
        let at = |n: u32| problem.target[n as usize];
        // Hinges over the welded assembly (triangles in node indices): the edges inside a
        // panel and the seams where two panels' linked vertices meet.
        let (node_triangles, edges) = (&assembly.node_triangles, &assembly.node_edges);
        let mut hinges = Vec::new();
        let mut hinge_weights = Vec::new();
        for e in 0..edges.len() {
            let [s, t] = edges.sides(e) else { continue };
            let [a, b] = edges.edges[e];
            let opposite = |f: u32| node_triangles[f as usize].into_iter().find(|&v| v != a && v != b);
            let (Some(c), Some(d)) = (opposite(s.face), opposite(t.face)) else {
                continue;
            };
            // Orient the edge as the first triangle traverses it.
            let (a, b) = if s.forward { (a, b) } else { (b, a) };
            let hinge = [a, b, c, d];
            let distinct = (0..4).all(|i| (i + 1..4).all(|j| hinge[i] != hinge[j]));
            let moves = hinge.iter().any(|&n| problem.variable_of_node[n as usize] != u32::MAX);
            let [pa, pb, pc, pd] = hinge.map(at);
            let areas = 0.5 * ((pb - pa).cross(&(pc - pa)).norm() + (pa - pb).cross(&(pd - pb)).norm());
            if distinct && moves && areas > 0.0 {
                hinges.push(hinge);
                hinge_weights.push((pb - pa).norm_squared() / areas);
            }
        }
        let hinge_variables: Vec<[u32; 4]> = hinges
            .iter()
            .map(|hinge| hinge.map(|n| problem.variable_of_node[n as usize]))
            .collect();
        // Every hinge's pairs of variable nodes, then the distinct ones (sorted) as blocks.
        let mut pairs = Vec::with_capacity(10 * hinges.len());
        let mut hinge_block_start = Vec::with_capacity(hinges.len() + 1);
        hinge_block_start.push(0);
        for variables in &hinge_variables {
            let moving = variables.iter().copied().filter(|&v| v != u32::MAX);
            for (i, p) in moving.clone().enumerate() {
                for q in moving.clone().skip(i) {
                    pairs.push((p.min(q), p.max(q)));
                }
            }
            hinge_block_start.push(pairs.len());
        }
        let mut blocks = pairs.clone();
        blocks.sort_unstable();
        blocks.dedup();
        let hinge_blocks = pairs
            .iter()
            .map(|key| blocks.binary_search(key).expect("a listed pair") as u32)
            .collect();
        Self {
            hinges,
            hinge_variables,
            hinge_weights,
            blocks,
            hinge_blocks,
            hinge_block_start,
            resolution: problem.resolution(),
        }
    }

    /// Calls `push(row, column, value)` for the upper triangle of
    /// `weight · Σ_e w_e r_eᵀ r_e`, `r_e = [∇_iθ_eᵀ J_i]_i` (3 columns per variable), at
    /// evaluation `e`, one entry per distinct position. The sequence of `(row, column)`
    /// pairs depends only on the problem, not on `e`.
    pub fn push_upper(&self, e: &Evaluation, weight: f64, mut push: impl FnMut(usize, usize, f64)) {
        let mut sums = vec![nalgebra::Matrix3::<f64>::zeros(); self.blocks.len()];
        let mut parts: Vec<(u32, Vec3)> = Vec::with_capacity(4);
        for (h, hinge) in self.hinges.iter().enumerate() {
            let ids = &self.hinge_blocks[self.hinge_block_start[h]..self.hinge_block_start[h + 1]];
            let w = self.hinge_weights[h];
            let gradients = signed_fold_angle_gradients(hinge.map(|n| e.positions[n as usize]));
            parts.clear();
            for (&v, g) in self.hinge_variables[h].iter().zip(&gradients) {
                if v != u32::MAX {
                    parts.push((v, e.jacobians[v as usize].tr_mul(g)));
                }
            }
            let mut id = ids.iter();
            for (i, &(a, ra)) in parts.iter().enumerate() {
                for &(b, rb) in &parts[i..] {
                    let block = &mut sums[*id.next().expect("one block per pair") as usize];
                    // The block (min, max) of r_eᵀ r_e: ra rbᵀ, or its transpose.
                    *block += w * if a <= b {
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
    use sheetform_mesh::signed_fold_angle;

    /// The change of the dihedral angle at edge `a → b` between triangles `(a, b, c)` and
    /// `(b, a, d)` along a displacement `δ` of the four points, by central differences of
    /// the pattern crate's signed fold angle (the same convention).
    fn angle_change(points: [Vec3; 4], delta: [Vec3; 4]) -> f64 {
        let t = 1e-6;
        let moved = |s: f64| signed_fold_angle(std::array::from_fn(|i| points[i] + s * delta[i]));
        (moved(t) - moved(-t)) / (2.0 * t)
    }

    /// The pushed entries are the upper triangle of `γ Σ_e w_e r_eᵀ r_e`: the quadratic
    /// form they define equals `γ Σ_e w_e (δθ_e)²`, each hinge's change of dihedral angle
    /// computed by finite differences from the node displacements `δq = J δX` of a step
    /// (fixed nodes do not move).
    #[test]
    fn quadratic_form_is_the_weighted_sum_of_squared_angle_changes() {
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
        // Some nodes stay fixed, so hinges with fixed nodes are exercised.
        assert!(problem.variables.len() > 10 && problem.variables.len() < assembly.node_count);
        let e = problem.evaluate(&problem.gather(&problem.start));
        let step: Vec<f64> = (0..problem.unknown_count()).map(|i| (i as f64 * 0.61).sin()).collect();
        let gamma = 0.37;
        let mut form = 0.0;
        let metric = BendingMetric::new(&problem);
        // At most both panels' interior edges (a 5 × 4 grid of split quads: 3·20 + 5 + 4
        // edges, 18 of them on the boundary, so 51 per panel) and the 4 edges of the seam
        // between them; hinges whose four nodes are all fixed are left out.
        assert!(
            metric.hinges.len() > 50 && metric.hinges.len() <= 106,
            "{}",
            metric.hinges.len()
        );
        metric.push_upper(&e, gamma, |r, c, v| {
            form += if r == c {
                v * step[r] * step[r]
            } else {
                2.0 * v * step[r] * step[c]
            };
        });
        let mut moved = vec![Vec3::zeros(); assembly.node_count];
        for (v, &node) in problem.variables.iter().enumerate() {
            moved[node as usize] = e.jacobians[v] * Vec3::new(step[3 * v], step[3 * v + 1], step[3 * v + 2]);
        }
        let direct: f64 = metric
            .hinges
            .iter()
            .zip(&metric.hinge_weights)
            .map(|(hinge, w)| {
                let change = angle_change(hinge.map(|n| e.positions[n as usize]), hinge.map(|n| moved[n as usize]));
                gamma * w * change * change
            })
            .sum();
        assert!(direct > 1e-3);
        assert!((form - direct).abs() <= 1e-6 * direct, "{form} vs {direct}");
    }
}

//! The constrained problem of Wang & Tang §2.3 on the embedded parameters.

use crate::{corner_angle, corner_angle_gradient, NurbsVolume, PanelAssembly};
use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;
use std::f64::consts::TAU;

type Vec3 = Vector3<f64>;

/// Knobs of the problem set-up, shared by both solvers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProblemOptions {
    /// `λ` of §3: a node's parameters are variables only if one of its vertices has
    /// `|g| > λ` or a neighbour has (radians; the paper: 1e-8). Keep it at most the
    /// solver's tolerance (`SolverSpec::problem_options` does): defects between the two
    /// are never optimised, and the restoration cannot meet its tolerance.
    pub selection_threshold: f64,
}

impl Default for ProblemOptions {
    fn default() -> Self {
        Self {
            selection_threshold: 1e-8,
        }
    }
}

/// One spring of Eq. 2-2: the edge between nodes `a` and `b`, rest length = its length
/// on the deformed mesh `M′` (model units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spring {
    /// First node.
    pub a: u32,
    /// Second node.
    pub b: u32,
    /// `l⁰_j` (model units).
    pub rest_length: f64,
}

/// The problem `min E(X) subject to g(q_i(X)) = 0` (Eq. 2-2 to 2-6) for one deformation
/// step: the lattice `Q′` is fixed, the unknowns are the parameters `X` of the selected
/// nodes (linked vertex sets, so linked vertices share their parameters).
///
/// - **Variables**: nodes with a vertex whose `|g| > λ`, and their neighbours (§3).
/// - **Springs**: every edge (between nodes, counted once) with a variable end; the
///   others cannot change length.
/// - **Constraints**: every interior vertex (of its panel) whose one-ring has a variable
///   node, so vertices that are developable now stay so. Boundary and seam vertices have
///   `g = 0` by definition (Eq. 2-4).
#[derive(Debug, Clone)]
pub struct DevelopabilityProblem<'a> {
    /// The deformed lattice `Q′`.
    pub volume: &'a NurbsVolume,
    /// The panels.
    pub assembly: &'a PanelAssembly,
    /// Node positions of `M′` (the shape the designer asked for).
    pub target: Vec<Vec3>,
    /// Parameters at the start (`X₀`: the embedding, or the previous step's optimum).
    pub start: Vec<Vec3>,
    /// The variable nodes.
    pub variables: Vec<u32>,
    /// Variable index of each node (`u32::MAX` when fixed).
    pub variable_of_node: Vec<u32>,
    /// Springs with at least one variable end.
    pub springs: Vec<Spring>,
    /// Node of each constrained vertex.
    pub constraint_nodes: Vec<u32>,
    /// Corners around each constrained vertex: `(centre, next, previous)` nodes, in
    /// `corner_start[c]..corner_start[c + 1]`.
    pub corners: Vec<[u32; 3]>,
    /// Offsets into `corners`.
    pub corner_start: Vec<usize>,
    /// Mean rest length of all edges (model units), the length scale of the residuals.
    pub length_scale: f64,
    /// Set from another thread to stop the restoration at its next iteration
    /// ([`FfdError::Cancelled`](crate::FfdError::Cancelled)); `None` from
    /// [`DevelopabilityProblem::new`].
    pub cancel: Option<&'a std::sync::atomic::AtomicBool>,
}

/// Positions, parameter Jacobians, spring residuals and angle defects at one `X`.
#[derive(Debug, Clone)]
pub struct Evaluation {
    /// Parameters of every node.
    pub parameters: Vec<Vec3>,
    /// Position of every node.
    pub positions: Vec<Vec3>,
    /// `∂Q/∂(u,v,w)` at every variable node.
    pub jacobians: Vec<Matrix3<f64>>,
    /// `|q_s − q_e| − l⁰` per spring (model units).
    pub spring_residuals: Vec<f64>,
    /// `g` per constrained vertex (radians).
    pub defects: Vec<f64>,
}

impl<'a> DevelopabilityProblem<'a> {
    /// Sets the problem up at parameters `start` (one triple per node) in the deformed
    /// lattice `volume`.
    pub fn new(
        volume: &'a NurbsVolume,
        assembly: &'a PanelAssembly,
        start: Vec<Vec3>,
        options: &ProblemOptions,
    ) -> Self {
        let target: Vec<Vec3> = start.par_iter().map(|&x| volume.point(x)).collect();
        let mesh = &assembly.mesh;
        let node = |v: u32| assembly.vertex_node[v as usize];
        // Angle sums per mesh vertex (panel-local, so seams are boundaries).
        let mut angle_sum = vec![0.0; mesh.positions.len()];
        let mut vertex_faces: Vec<Vec<u32>> = vec![Vec::new(); mesh.positions.len()];
        for (f, t) in mesh.triangles.iter().enumerate() {
            for k in 0..3 {
                let p = [t[k], t[(k + 1) % 3], t[(k + 2) % 3]].map(|v| target[node(v) as usize]);
                angle_sum[t[k] as usize] += corner_angle(p[0], p[1], p[2]);
                vertex_faces[t[k] as usize].push(f as u32);
            }
        }
        let interior = |v: usize| !assembly.boundary[v] && !vertex_faces[v].is_empty();
        // Node adjacency by edges.
        let mut edges: Vec<[u32; 2]> = Vec::with_capacity(mesh.triangles.len() * 3);
        for t in &mesh.triangles {
            for k in 0..3 {
                let (a, b) = (node(t[k]), node(t[(k + 1) % 3]));
                edges.push([a.min(b), a.max(b)]);
            }
        }
        edges.par_sort_unstable();
        edges.dedup();
        let n = assembly.node_count;
        let mut hot = vec![false; n];
        for v in 0..mesh.positions.len() {
            if interior(v) && (TAU - angle_sum[v]).abs() > options.selection_threshold {
                hot[node(v as u32) as usize] = true;
            }
        }
        let mut variable = hot.clone();
        for e in &edges {
            if hot[e[0] as usize] || hot[e[1] as usize] {
                variable[e[0] as usize] = true;
                variable[e[1] as usize] = true;
            }
        }
        let mut variable_of_node = vec![u32::MAX; n];
        let mut variables = Vec::new();
        for (i, &is) in variable.iter().enumerate() {
            if is {
                variable_of_node[i] = variables.len() as u32;
                variables.push(i as u32);
            }
        }
        let length_scale = if edges.is_empty() {
            1.0
        } else {
            edges
                .iter()
                .map(|e| (target[e[0] as usize] - target[e[1] as usize]).norm())
                .sum::<f64>()
                / edges.len() as f64
        };
        let springs = edges
            .iter()
            .filter(|e| variable[e[0] as usize] || variable[e[1] as usize])
            .map(|e| Spring {
                a: e[0],
                b: e[1],
                rest_length: (target[e[0] as usize] - target[e[1] as usize]).norm(),
            })
            .collect();
        let mut constraint_nodes = Vec::new();
        let mut corners = Vec::new();
        let mut corner_start = vec![0];
        for (v, faces) in vertex_faces.iter().enumerate() {
            if !interior(v) {
                continue;
            }
            let ring: Vec<[u32; 3]> = faces
                .iter()
                .map(|&f| {
                    let t = mesh.triangles[f as usize];
                    let k = t.iter().position(|&w| w as usize == v).expect("vertex of its face");
                    [t[k], t[(k + 1) % 3], t[(k + 2) % 3]].map(node)
                })
                .collect();
            if ring.iter().flatten().any(|&m| variable[m as usize]) {
                constraint_nodes.push(node(v as u32));
                corners.extend(ring);
                corner_start.push(corners.len());
            }
        }
        Self {
            volume,
            assembly,
            target,
            start,
            variables,
            variable_of_node,
            springs,
            constraint_nodes,
            corners,
            corner_start,
            length_scale,
            cancel: None,
        }
    }

    /// `A / l̄²`: the panels' area on the plain FFD `M′` over the squared mean edge
    /// length (about 0.87 × the node count for near-equilateral triangles); the factor
    /// that makes per-vertex quantities mean the same at every resolution (the bending
    /// weight, the continuation's sub-step curvature).
    pub fn resolution(&self) -> f64 {
        let mesh = &self.assembly.mesh;
        let at = |v: u32| self.target[self.assembly.vertex_node[v as usize] as usize];
        let area: f64 = mesh
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(at);
                0.5 * (b - a).cross(&(c - a)).norm()
            })
            .sum();
        let l = self.length_scale;
        if l > 0.0 {
            area / (l * l)
        } else {
            0.0
        }
    }

    /// [`FfdError::Cancelled`](crate::FfdError::Cancelled) once the cancel flag is set.
    ///
    /// # Errors
    /// When cancelled.
    pub fn check_cancelled(&self) -> Result<(), crate::FfdError> {
        match self.cancel {
            Some(flag) if flag.load(std::sync::atomic::Ordering::Relaxed) => Err(crate::FfdError::Cancelled),
            _ => Ok(()),
        }
    }

    /// Number of scalar unknowns (three per variable node).
    pub fn unknown_count(&self) -> usize {
        3 * self.variables.len()
    }

    /// Number of constraints.
    pub fn constraint_count(&self) -> usize {
        self.constraint_nodes.len()
    }

    /// The variable vector (parameters of the variable nodes) of a full parameter list.
    pub fn gather(&self, parameters: &[Vec3]) -> Vec<f64> {
        self.variables
            .iter()
            .flat_map(|&n| {
                let x = parameters[n as usize];
                [x.x, x.y, x.z]
            })
            .collect()
    }

    /// A full parameter list from the start with the variables replaced by `y` (clamped to
    /// the lattice domain).
    pub fn scatter(&self, y: &[f64]) -> Vec<Vec3> {
        let mut x = self.start.clone();
        for (i, &n) in self.variables.iter().enumerate() {
            x[n as usize] = self.volume.clamp(Vec3::new(y[3 * i], y[3 * i + 1], y[3 * i + 2]));
        }
        x
    }

    /// Evaluates positions, Jacobians, springs and defects at variables `y`.
    pub fn evaluate(&self, y: &[f64]) -> Evaluation {
        let parameters = self.scatter(y);
        let mut positions = self.target.clone();
        let evaluated: Vec<(Vec3, Matrix3<f64>)> = self
            .variables
            .par_iter()
            .map(|&n| self.volume.point_and_jacobian(parameters[n as usize]))
            .collect();
        let mut jacobians = Vec::with_capacity(evaluated.len());
        for (&n, (q, j)) in self.variables.iter().zip(evaluated) {
            positions[n as usize] = q;
            jacobians.push(j);
        }
        let spring_residuals = self
            .springs
            .par_iter()
            .map(|s| (positions[s.a as usize] - positions[s.b as usize]).norm() - s.rest_length)
            .collect();
        let defects = self.defects_at(&positions);
        Evaluation {
            parameters,
            positions,
            jacobians,
            spring_residuals,
            defects,
        }
    }

    /// The defects `g` alone at the gathered unknowns `y`: node positions without their
    /// Jacobians and no spring residuals, for line searches that only compare defects
    /// (the accepted point is then evaluated in full once).
    pub fn evaluate_defects(&self, y: &[f64]) -> Vec<f64> {
        self.defects_at(&self.positions_at(y))
    }

    /// Every node's position at the gathered unknowns `y` (no Jacobians).
    fn positions_at(&self, y: &[f64]) -> Vec<Vec3> {
        let parameters = self.scatter(y);
        let mut positions = self.target.clone();
        let evaluated: Vec<Vec3> = self
            .variables
            .par_iter()
            .map(|&n| self.volume.point(parameters[n as usize]))
            .collect();
        for (&n, q) in self.variables.iter().zip(evaluated) {
            positions[n as usize] = q;
        }
        positions
    }

    /// The objective of [`crate::restore_constrained`]'s refinement, at an evaluation:
    /// `f = ½ Σ_j (|q_s − q_e| − l⁰_j)² / l̄² + ½ β Σ_n |q_n − q′_n|² / l̄²` over the
    /// springs and the variable nodes (`β` = `position_weight`; dimensionless).
    pub fn restoration_objective(&self, e: &Evaluation, position_weight: f64) -> f64 {
        let springs: f64 = e.spring_residuals.iter().map(|r| r * r).sum();
        let proximity: f64 = self
            .variables
            .iter()
            .map(|&m| (e.positions[m as usize] - self.target[m as usize]).norm_squared())
            .sum();
        0.5 * (springs + position_weight * proximity) / (self.length_scale * self.length_scale)
    }

    /// `g = 2π − Σ θ` at every constrained vertex, from node positions.
    fn defects_at(&self, positions: &[Vec3]) -> Vec<f64> {
        (0..self.constraint_nodes.len())
            .into_par_iter()
            .map(|c| {
                let mut sum = 0.0;
                for corner in &self.corners[self.corner_start[c]..self.corner_start[c + 1]] {
                    let p = corner.map(|m| positions[m as usize]);
                    sum += corner_angle(p[0], p[1], p[2]);
                }
                TAU - sum
            })
            .collect()
    }

    /// The spring energy `E(X) = Σ_j (|q_s − q_e| − l⁰_j)²` (Eq. 2-2, model units²).
    pub fn spring_energy(&self, e: &Evaluation) -> f64 {
        e.spring_residuals.iter().map(|r| r * r).sum()
    }

    /// `G[X] = Σ g²` over the constrained vertices (Eq. 2-5, radians²). Vertices outside
    /// the problem have `|g| ≤ λ` and do not change.
    pub fn developability_g(&self, e: &Evaluation) -> f64 {
        e.defects.iter().map(|g| g * g).sum()
    }

    /// Gradient rows of one spring with respect to the variables: up to two
    /// `(variable, ∂r/∂X_node)` pairs (model units per parameter unit).
    pub fn spring_gradient(&self, e: &Evaluation, s: usize) -> [(u32, Vec3); 2] {
        let spring = &self.springs[s];
        let d = e.positions[spring.a as usize] - e.positions[spring.b as usize];
        let norm = d.norm();
        let dir = if norm > 0.0 { d / norm } else { Vec3::zeros() };
        let part = |node: u32, sign: f64| {
            let v = self.variable_of_node[node as usize];
            if v == u32::MAX {
                (u32::MAX, Vec3::zeros())
            } else {
                (v, e.jacobians[v as usize].tr_mul(&dir) * sign)
            }
        };
        [part(spring.a, 1.0), part(spring.b, -1.0)]
    }

    /// Gradient of constraint `c` (the defect `g` of one vertex) with respect to the
    /// variables: `∂g/∂X_n = −Σ_corners (∂θ/∂q_n)ᵀ J_Q(X_n)`, accumulated per variable
    /// node into `out` (cleared first; radians per parameter unit).
    pub fn defect_gradient(&self, e: &Evaluation, c: usize, out: &mut Vec<(u32, Vec3)>) {
        out.clear();
        for corner in &self.corners[self.corner_start[c]..self.corner_start[c + 1]] {
            let p = corner.map(|m| e.positions[m as usize]);
            let (_, g) = corner_angle_gradient(p[0], p[1], p[2]);
            for k in 0..3 {
                let v = self.variable_of_node[corner[k] as usize];
                if v == u32::MAX {
                    continue;
                }
                let d = -e.jacobians[v as usize].tr_mul(&g[k]);
                match out.iter_mut().find(|(w, _)| *w == v) {
                    Some((_, acc)) => *acc += d,
                    None => out.push((v, d)),
                }
            }
        }
    }
}

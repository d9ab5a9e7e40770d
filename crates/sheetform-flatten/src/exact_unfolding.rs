//! Exact unfolding of a developable triangle mesh from its intrinsic edge lengths.

use crate::{FlattenError, Vec2};
use faer::sparse::Triplet;
use sheetform_mesh::{mesh_topology_with_edges, TriangleMesh};
use sheetform_solve::SolverInfo;
use sheetform_solve::SparseCholesky;
use std::collections::VecDeque;

/// Knobs of [`exact_unfold`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UnfoldOptions {
    /// Most Gauss–Newton iterations of the global refinement.
    pub max_iterations: usize,
    /// Stop when the largest relative edge-length residual is below this (1e-11: 10× below
    /// the 1e-10 the tests require; an exactly developable mesh needs no iteration, so it
    /// unfolds in linear time). Not 1e-12: the breadth-first layout of a developable mesh
    /// accumulates rounding to ~1e-12 along paths of a thousand faces, and a Gauss–Newton
    /// step to remove that costs seconds at 1M faces and buys nothing.
    pub tolerance: f64,
}

impl Default for UnfoldOptions {
    fn default() -> Self {
        Self {
            max_iterations: 30,
            tolerance: 1e-11,
        }
    }
}

/// A flattening: one 2D point per vertex (same length unit as the mesh), counter-clockwise
/// faces, and the refinement's solver report.
#[derive(Debug, Clone, PartialEq)]
pub struct Unfolding {
    /// Flat position of every vertex.
    pub flat: Vec<Vec2>,
    /// Gauss–Newton report (cost = `½ Σ r_e²`, relative residuals).
    pub solver: SolverInfo,
    /// Largest relative edge-length residual after refinement.
    pub max_relative_residual: f64,
}

/// Unfolds a disk-like triangle mesh into the plane from its 3D edge lengths.
///
/// 1. **Layout**: faces are laid out breadth-first from the most central face (the one
///    minimising the largest face distance, so error chains are as short as possible),
///    each new vertex placed from its two already placed neighbours by the law of
///    cosines, `x = (l_ik² − l_jk² + d²) / 2d`, `h = √(l_ik² − x²)`, on the side that
///    keeps the face counter-clockwise.
/// 2. **Global refinement** over all edges at once: Gauss–Newton on the relative
///    residuals `r_e = (|u_i − u_j| − l_e) / l_e`, normal equations `JᵀJ δ = −Jᵀr` solved
///    by faer's sparse Cholesky (symbolic factorisation computed once, numeric each
///    iteration), with one vertex and one direction pinned (the rigid-motion gauge).
///
/// On an exactly developable mesh the result reproduces the edge lengths to rounding; on
/// a nearly developable one it is the least-squares layout of its edge lengths.
///
/// # Errors
/// Non-manifold, degenerate or non-orientable meshes; meshes that are not a single disk
/// (closed surfaces and annuli must be cut first); a failing factorisation.
pub fn exact_unfold(mesh: &TriangleMesh, options: &UnfoldOptions) -> Result<Unfolding, FlattenError> {
    let (topology, table) = mesh_topology_with_edges(mesh);
    let problems = topology_problems(&topology);
    if !problems.is_empty() {
        return Err(FlattenError::Topology {
            problem: problems.join("; "),
        });
    }
    if topology.component_count != 1 || topology.boundary_loop_count != 1 || topology.euler_characteristic != 1 {
        return Err(FlattenError::NotADisk {
            components: topology.component_count,
            boundary_loops: topology.boundary_loop_count,
            euler: topology.euler_characteristic,
        });
    }
    let nf = mesh.triangles.len();
    let nv = mesh.positions.len();
    // Face adjacency across edges (the topology check's edge table).
    let neighbours: Vec<[u32; 3]> = (0..nf)
        .map(|f| [0, 1, 2].map(|k| table.opposite(f, k).unwrap_or(u32::MAX)))
        .collect();
    let bfs = |start: usize| {
        let mut dist = vec![usize::MAX; nf];
        let mut queue = VecDeque::from([start]);
        dist[start] = 0;
        let mut order = Vec::with_capacity(nf);
        while let Some(f) = queue.pop_front() {
            order.push(f);
            for &g in &neighbours[f] {
                if g != u32::MAX && dist[g as usize] == usize::MAX {
                    dist[g as usize] = dist[f] + 1;
                    queue.push_back(g as usize);
                }
            }
        }
        (dist, order)
    };
    // Most central face: minimise the larger distance to two far-apart faces.
    let (_, o0) = bfs(0);
    let far1 = *o0.last().expect("non-empty");
    let (d1, o1) = bfs(far1);
    let far2 = *o1.last().expect("non-empty");
    let (d2, _) = bfs(far2);
    let seed = (0..nf).min_by_key(|&f| d1[f].max(d2[f])).expect("non-empty");
    let length = |a: u32, b: u32| (mesh.positions[a as usize] - mesh.positions[b as usize]).norm();

    // 1. Breadth-first layout.
    let mut flat = vec![Vec2::zeros(); nv];
    let mut placed = vec![false; nv];
    let t = mesh.triangles[seed];
    let (a, b, c) = (t[0], t[1], t[2]);
    flat[a as usize] = Vec2::zeros();
    flat[b as usize] = Vec2::new(length(a, b), 0.0);
    flat[c as usize] = third_point(flat[a as usize], flat[b as usize], length(a, c), length(b, c));
    for v in [a, b, c] {
        placed[v as usize] = true;
    }
    let (_, order) = bfs(seed);
    for &f in &order {
        let t = mesh.triangles[f];
        let missing: Vec<usize> = (0..3).filter(|&k| !placed[t[k] as usize]).collect();
        if let [k] = missing[..] {
            let (i, j) = (t[(k + 1) % 3], t[(k + 2) % 3]);
            // Counter-clockwise (i, j, k): k lies to the left of i → j.
            flat[t[k] as usize] = third_point(flat[i as usize], flat[j as usize], length(i, t[k]), length(j, t[k]));
            placed[t[k] as usize] = true;
        }
    }

    // 2. Global Gauss–Newton over all edges.
    // The table's edges are already sorted by vertex pair.
    let edges: Vec<([u32; 2], f64)> = table.edges.iter().map(|&[i, j]| ([i, j], length(i, j))).collect();
    // Unknowns: all coordinates except a.x, a.y, b.y (gauge).
    let mut column = vec![[usize::MAX; 2]; nv];
    let mut unknowns = 0;
    for (v, cols) in column.iter_mut().enumerate() {
        for (d, col) in cols.iter_mut().enumerate() {
            let pinned = (v == a as usize) || (v == b as usize && d == 1);
            if !pinned {
                *col = unknowns;
                unknowns += 1;
            }
        }
    }
    let residuals = |u: &[Vec2]| -> Vec<f64> {
        edges
            .iter()
            .map(|&([i, j], l)| ((u[i as usize] - u[j as usize]).norm() - l) / l)
            .collect()
    };
    let mut r = residuals(&flat);
    let max_abs = |r: &[f64]| r.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let cost = |r: &[f64]| 0.5 * r.iter().map(|x| x * x).sum::<f64>();
    let mut info = SolverInfo {
        initial_cost: cost(&r),
        cost: cost(&r),
        ..Default::default()
    };
    let mut cholesky: Option<SparseCholesky> = None;
    for it in 0..options.max_iterations {
        if max_abs(&r) <= options.tolerance {
            info.converged = true;
            break;
        }
        // Normal equations JᵀJ and Jᵀr.
        let mut triplets: Vec<Triplet<usize, usize, f64>> = Vec::with_capacity(edges.len() * 16);
        let mut rhs = vec![0.0; unknowns];
        for (e, &([i, j], l)) in edges.iter().enumerate() {
            let d = flat[i as usize] - flat[j as usize];
            let n = d.norm().max(f64::MIN_POSITIVE);
            let g = [d.x / (n * l), d.y / (n * l)];
            // J row: +g at i, −g at j.
            let entries = [(i as usize, 1.0), (j as usize, -1.0)];
            for &(v, s) in &entries {
                for dv in 0..2 {
                    let cv = column[v][dv];
                    if cv == usize::MAX {
                        continue;
                    }
                    rhs[cv] -= s * g[dv] * r[e];
                    for &(w, t) in &entries {
                        for dw in 0..2 {
                            let cw = column[w][dw];
                            if cw != usize::MAX && cw <= cv {
                                triplets.push(Triplet::new(cv, cw, s * t * g[dv] * g[dw]));
                            }
                        }
                    }
                }
            }
        }
        // The pattern is the same every iteration: the symbolic analysis is reused.
        let factorised = match cholesky.as_mut() {
            Some(c) => c.refactor(&triplets).map(|()| c),
            None => SparseCholesky::new(unknowns, &triplets).map(|c| cholesky.insert(c)),
        };
        let llt = factorised.map_err(|e| {
            tracing::debug!(error = %e, "exact unfolding: the layout's normal equations did not factorise");
            FlattenError::Solver {
                message: layout_not_fixed(mesh),
            }
        })?;
        let delta = llt.solve(&rhs);
        // Damped step: halve until the cost does not grow.
        let mut step = 1.0;
        loop {
            let mut trial = flat.clone();
            for (v, cols) in column.iter().enumerate() {
                for d in 0..2 {
                    if cols[d] != usize::MAX {
                        trial[v][d] += step * delta[cols[d]];
                    }
                }
            }
            let r_trial = residuals(&trial);
            if cost(&r_trial) <= cost(&r) || step < 1e-6 {
                // Converged once an iteration gains less than 10 % (the least-squares
                // optimum of a mesh that is not exactly developable).
                let improved = cost(&r_trial) < 0.9 * cost(&r);
                if cost(&r_trial) < cost(&r) {
                    flat = trial;
                    r = r_trial;
                }
                info.iterations = it + 1;
                if !improved {
                    info.converged = true;
                }
                break;
            }
            step *= 0.5;
        }
        if info.converged {
            break;
        }
    }
    info.cost = cost(&r);
    let max_relative_residual = max_abs(&r);
    if max_relative_residual <= options.tolerance {
        info.converged = true;
    }
    Ok(Unfolding {
        flat,
        solver: info,
        max_relative_residual,
    })
}

/// A triangle whose width (its height over its longest edge) is below this fraction of its
/// length is needle-thin: the refinement's normal equations of a mesh holding one
/// (measured: a 25 mm edge with its third corner 2.5e-8 mm off it, 1e-9) do not factorise.
const NEEDLE_WIDTH: f64 = 1e-6;

/// Why the edge lengths of `mesh` leave its flat layout free (the refinement's normal
/// equations are singular), in the mesh's terms and with what to do: its thinnest
/// triangle when that one is needle-thin, its corners almost in a line.
fn layout_not_fixed(mesh: &TriangleMesh) -> String {
    layout_not_fixed_numbered(mesh, |f| f)
}

/// [`layout_not_fixed`] of a part of a mesh, its faces named by `number` (the part's
/// face → the whole mesh's).
pub(crate) fn layout_not_fixed_numbered(mesh: &TriangleMesh, number: impl Fn(usize) -> usize) -> String {
    let short = sheetform_geometry::short_number;
    let thinnest = (0..mesh.triangles.len())
        .filter_map(|f| {
            let [a, b, c] = mesh.triangles[f].map(|v| mesh.positions[v as usize]);
            let longest = (b - a).norm().max((c - b).norm()).max((a - c).norm());
            let width = 2.0 * mesh.face_area(f) / longest;
            (longest > 0.0 && width.is_finite()).then_some((f, width, longest, (a + b + c) / 3.0))
        })
        .min_by(|x, y| (x.1 / x.2).total_cmp(&(y.1 / y.2)));
    match thinnest {
        Some((face, width, longest, centre)) if width < NEEDLE_WIDTH * longest => {
            let face = number(face);
            format!(
                "the mesh cannot be laid flat as it is: it has needle-thin triangles, their three corners almost \
             in a line, whose edge lengths do not hold the pattern in shape (the thinnest, face {face} near \
             ({}, {}, {}), is {} wide across its longest edge of {}); remove such triangles (collapse their \
             shortest edge, as a mesh editor's clean-up of degenerate faces does, or remesh) and try again",
                short(centre.x),
                short(centre.y),
                short(centre.z),
                short(width),
                short(longest)
            )
        }
        _ => "the mesh cannot be laid flat as it is: its edge lengths do not hold the pattern in shape (laid \
              flat, some of its triangles are squashed into lines, as happens to a surface far from \
              developable); repair or remesh it, or cut it into pieces that are each nearly developable, and \
              try again"
            .to_string(),
    }
}

/// The point at distances `li` from `pi` and `lj` from `pj`, to the left of `pi → pj`.
fn third_point(pi: Vec2, pj: Vec2, li: f64, lj: f64) -> Vec2 {
    let e = pj - pi;
    let d = e.norm().max(f64::MIN_POSITIVE);
    let ex = e / d;
    let ey = Vec2::new(-ex.y, ex.x);
    let x = (li * li - lj * lj + d * d) / (2.0 * d);
    let h = (li * li - x * x).max(0.0).sqrt();
    pi + ex * x + ey * h
}

/// What keeps a mesh from being flattened as it is: non-manifold edges and vertices,
/// degenerate faces, a non-orientable surface (empty when it is clean).
pub(crate) fn topology_problems(topology: &sheetform_mesh::MeshTopology) -> Vec<String> {
    topology.problems()
}

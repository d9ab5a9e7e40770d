//! The nearest surface (in a smooth metric) whose pieces are exactly developable: a
//! constrained Gauss–Newton (SQP) projection of the target's vertex positions onto the
//! set where every vertex inside a piece has angle sum 2π.

use crate::{mirror_interior, DevelopError, SeamPieces};
use faer::sparse::Pair;
use nalgebra::Vector3;
use rayon::prelude::*;
use sheetform_mesh::{corner_angle_gradient, vertex_angle_sums, EdgeTable, TriangleMesh};
use sheetform_solve::{DiagonalKktSystem, FactorisationFailure, KktError, KktSystem, SolveAccuracy};
use std::f64::consts::TAU;
use std::sync::atomic::{AtomicBool, Ordering};

type Vec3 = Vector3<f64>;

/// Knobs of [`develop_pieces`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DevelopOptions {
    /// Weight of the smoothness term against closeness (dimensionless): 0 moves each
    /// vertex as little as possible, larger values spread the change over its
    /// neighbours (fewer crinkles, farther from the target). Default 0.1.
    pub smoothness: f64,
    /// Most Gauss–Newton steps. Default 100.
    pub max_iterations: usize,
    /// The largest angle defect accepted inside a piece (radians). Default 1e-10.
    pub defect_tolerance: f64,
    /// End the solve early, without its feasibility polish, once some vertex is a
    /// hopeless cone point ([`HOPELESS_DEFECT`]); [`Developed::hopeless`] lists them for
    /// the caller to cut free and solve again. Default false.
    pub end_at_hopeless_cone_points: bool,
}

impl Default for DevelopOptions {
    fn default() -> Self {
        Self {
            smoothness: 0.1,
            max_iterations: 100,
            defect_tolerance: 1e-10,
            end_at_hopeless_cone_points: false,
        }
    }
}

/// The solve ends once every defect is within the tolerance and a step moves no vertex
/// coordinate by more than this fraction of the mean edge length (a micrometre on a
/// metre-long edge).
pub const STEP_TOLERANCE: f64 = 1e-6;

/// A step moves no vertex farther than this many mean edge lengths (a trust region: the
/// angle defects are linearised, and a longer move makes new ones). Measured on automatic
/// pieces of a torus, the wing nut and a sphere (benchmarks-history.md, session 24): without it
/// the torus and the wing nut stayed out of tolerance after 100 steps; with 0.5 both
/// converge and the distance to the target is unchanged (±5 %); 0.25 and 0.1 left the
/// wing nut out again.
pub const STEP_REACH: f64 = 0.5;

/// The Gauss–Newton steps end once the objective changes by less than this fraction of
/// itself for [`STALL_STEPS`] steps in a row with every defect below [`STALL_DEFECT`]
/// radians; the feasibility polish then brings the defects to the tolerance. Measured
/// (benchmarks-history.md, session 24): the steps converge linearly (line-search steps of 1/8 on
/// automatic sphere pieces), so the last 40–80 steps of 100 bought ≤ 4 % of distance;
/// with the rule, the UV sphere takes 60 steps instead of 103, the icosphere 22 instead
/// of 101, the torus 32 instead of 92, the capsule 20 instead of 102, distances within 5 %.
pub const STALL_TOLERANCE: f64 = 1e-3;
/// See [`STALL_TOLERANCE`].
pub const STALL_STEPS: usize = 3;
/// See [`STALL_TOLERANCE`] (radians).
pub const STALL_DEFECT: f64 = 0.05;
/// The steps also end after [`STALL_STEPS`] in a row that move no vertex coordinate by
/// more than this fraction of the mean edge length (the line search cutting each step
/// to a sliver; the feasibility polish then takes over). Measured (benchmarks-history.md,
/// session 25): the koala's solve spent 20 of its 38 steps at `α` below 0.03 with its
/// largest defect stuck at 1.64 rad, and the polish finished from there.
pub const STALL_MOVE: f64 = 1e-3;
/// Most steps of the feasibility polish (least-norm corrections `J Δx = −g`, each
/// damped by halving until `Σ |g|` decreases, from at most [`STEP_REACH`]` ℓ`). Measured:
/// undamped, the polish stopped at its first non-improving step and the wing nut stayed
/// at 1.7e-3 rad; damped, 20 steps reach 7.8e-10 rad on it and 40 reach 1.3e-14.
pub const POLISH_STEPS: usize = 40;

/// A full correction of the feasibility polish that brought `Σ |g|` below this fraction
/// of itself is followed by a chord step: the same factor (the Jacobian at the earlier
/// point) with the new defects, a triangular solve instead of a factorisation, at most
/// [`MAX_CHORD_STEPS`] in a row (Shamanskii's modification of Newton's method, Kelley
/// 2003, *Solving Nonlinear Equations with Newton's Method*, §2.3.3: superlinear while
/// the contraction is strong). A chord step that does not decrease `Σ |g|` is taken
/// again with a fresh factor.
pub const CHORD_CONTRACTION: f64 = 0.5;
/// See [`CHORD_CONTRACTION`].
pub const MAX_CHORD_STEPS: usize = 4;

/// Up to this [`DevelopOptions::smoothness`], the steps' metric is `H`'s diagonal
/// `(M + s·deg) ⊗ I₃` instead of `H = (M + s L) ⊗ I₃` (see [`develop_pieces`]).
pub const DIAGONAL_METRIC_SMOOTHNESS: f64 = 0.5;

/// A vertex whose angle defect stays above this (radians) for [`HOPELESS_STEPS`] steps
/// in a row is a cone point the solve cannot flatten (with
/// [`DevelopOptions::end_at_hopeless_cone_points`] the solve ends there, and every vertex
/// above it for the last [`HOPELESS_COMPANION_STEPS`] steps is reported with it).
/// Measured (benchmarks-history.md, session 34): of the 8 targets of the develop table,
/// only the koala's first solve has a vertex above 0.5 rad after 8 steps (1109, above it
/// from the first step; the solve then took 70 steps with its largest defect at
/// 1.2–3.4 rad, and the slit rounds cut 8 cone points from its end); ended at step 8,
/// its two hopeless vertices are cut free and the next solve converges in 39 steps.
pub const HOPELESS_DEFECT: f64 = 0.5;
/// See [`HOPELESS_DEFECT`].
pub const HOPELESS_STEPS: usize = 8;
/// See [`HOPELESS_DEFECT`]: a vertex above it for this many steps in a row when the
/// solve ends is reported hopeless too (the defects of the vertices round a stuck one
/// come and go as the steps push between them; measured on the koala: 1156 above 0.5
/// rad at steps 3–5 and 7–8, below at 6).
pub const HOPELESS_COMPANION_STEPS: usize = 3;

/// Largest [`DevelopOptions::smoothness`] accepted.
pub const MAX_SMOOTHNESS: f64 = 1e6;
/// Largest [`DevelopOptions::max_iterations`] accepted.
pub const MAX_ITERATIONS: usize = 10_000;

impl DevelopOptions {
    /// Checks the ranges.
    ///
    /// # Errors
    /// The option named with its value and bounds.
    pub fn validate(&self) -> Result<(), DevelopError> {
        if !(self.smoothness.is_finite() && (0.0..=MAX_SMOOTHNESS).contains(&self.smoothness)) {
            return Err(DevelopError::Option {
                option: "smoothness",
                message: format!(
                    "must be between 0 and {MAX_SMOOTHNESS}, got {}",
                    sheetform_geometry::short_number(self.smoothness)
                ),
            });
        }
        if self.max_iterations == 0 || self.max_iterations > MAX_ITERATIONS {
            return Err(DevelopError::Option {
                option: "max_iterations",
                message: format!("must be between 1 and {MAX_ITERATIONS}, got {}", self.max_iterations),
            });
        }
        if !(self.defect_tolerance.is_finite() && self.defect_tolerance >= 1e-14 && self.defect_tolerance <= 0.1) {
            return Err(DevelopError::Option {
                option: "defect_tolerance",
                message: format!(
                    "must be between 1e-14 and 0.1 radians, got {}",
                    sheetform_geometry::short_number(self.defect_tolerance)
                ),
            });
        }
        Ok(())
    }
}

/// The mirror plane of a half target (`develop --mirror`): the half is developed so that
/// it and its mirror image, joined along the plane, are exactly developable.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MirrorBoundary<'a> {
    /// The plane's normal axis (0 = x, 1 = y, 2 = z): a vertex on the plane keeps its
    /// coordinate on this axis and moves in the plane only.
    pub axis: usize,
    /// Whether each vertex of the half lies on the plane.
    pub on_plane: &'a [bool],
}

/// The developed surface.
#[derive(Debug, Clone, PartialEq)]
pub struct Developed {
    /// New vertex positions (model units; the mesh's triangles and pieces unchanged).
    pub positions: Vec<Vec3>,
    /// Vertices inside a piece, whose angle sum was made 2π.
    pub constrained_vertex_count: usize,
    /// Largest angle defect inside a piece before (radians).
    pub max_defect_before: f64,
    /// Largest angle defect inside a piece after (radians).
    pub max_defect: f64,
    /// Gauss–Newton steps taken.
    pub iterations: usize,
    /// Whether every defect inside a piece is within the tolerance.
    pub converged: bool,
    /// Largest and mean vertex displacement (model units).
    pub displacement_max: f64,
    /// Mean vertex displacement (model units).
    pub displacement_mean: f64,
    /// Cone points found hopeless: vertices whose defect stayed above
    /// [`HOPELESS_DEFECT`] for [`HOPELESS_STEPS`] steps in a row, which ended the solve
    /// early (without its feasibility polish). Empty when the solve ran its course.
    pub hopeless: Vec<u32>,
}

/// Moves the vertices of `target` as little as possible (in the metric below) so that
/// every vertex inside a piece of `pieces` has angle sum 2π: each piece then unfolds
/// into the plane without stretching, and pieces still meet along their seams (they
/// share the seam vertices, which are free).
///
/// **Problem.** With `x` the positions (scaled by the mean edge length `ℓ`, so every
/// figure below is dimensionless) and `t` the target's,
///
/// `min ½ (x − t)ᵀ H (x − t)` subject to `g_v(x) = 2π − Σ_{corners at v} θ = 0` for every
/// vertex `v` inside a piece,
///
/// `H = (M + s L) ⊗ I₃`: `M` the lumped vertex areas over their mean, `L` the graph
/// Laplacian of the mesh's edges, `s` [`DevelopOptions::smoothness`]. `g_v` is Wang &
/// Tang's vertex developability (2004, Eq. 2-4), the angle defect whose vanishing at every
/// interior vertex makes a triangle mesh intrinsically flat; its exact gradient is
/// [`corner_angle_gradient`]'s (the FFD restoration's). Seams as free boundaries of
/// exactly developable pieces follow Stein, Grinspun & Crane (2018, §3: a piecewise
/// developable mesh is one whose pieces' interior vertices are flat); their hinge energy
/// flow is replaced here by the constraint itself, so the result is exact rather than
/// near.
///
/// **Step** (Gauss–Newton SQP, the constraints' curvature left out):
/// `[B Jᵀ; J −δI] [Δx; λ] = [−H(x − t); −g]`, `J = ∂g/∂x`. The step's metric `B` is
/// `H`'s diagonal `D = (M + s·deg) ⊗ I₃` while `s ≤` [`DIAGONAL_METRIC_SMOOTHNESS`]:
/// the unknowns then eliminate without fill and only the constraints' Schur complement
/// `J D⁻¹ Jᵀ + δI` is factorised ([`DiagonalKktSystem`]; Nocedal & Wright 2006, Eq.
/// 16.16). Its factor holds a tenth of the full system's values (koala: 0.14 M against
/// 1.64 M), and whole runs take 1.1–4× less CPU time (docs/benchmarks-history.md, session
/// 29). This is a departure from Newton's step in `H` only: the objective and its
/// gradient `H(x − t)` are `H`'s, so the problem and its solutions are the same;
/// `D⁻¹H = I − s D⁻¹A` (`A` the adjacency) has its eigenvalues in `[1 − ρ, 1 + ρ]`,
/// `ρ = s·deg/(M + s·deg)`: `[0.63, 1.38]` at the default `s` = 0.1, `[0.25, 1.75]` at
/// 0.5 (valence 6, `M` ≈ 1). Heavier smoothness spreads each step over the
/// neighbours, which `D` does not: above the bound `B = H` and the full system is
/// factorised by the shared [`KktSystem`] (ordering, symbolic analysis and workspace
/// once; LDLᵀ each step, iterative refinement). A backtracking line search (from at
/// most [`STEP_REACH`]` ℓ`) on the ℓ₁ merit
/// `½ (x − t)ᵀ H (x − t) + μ ‖g‖₁`, `μ = 2 ‖λ‖∞ + 1`, keeps the steps safe far from the
/// constraint set. It stops when every defect is within the tolerance and the step is
/// below [`STEP_TOLERANCE`]` ℓ` (or would take a defect out of it), or once the objective
/// has stalled ([`STALL_TOLERANCE`]); steps after the last with the objective's row zeroed
/// (the least-`B`-norm correction `J Δx = −g`, damped; at most [`POLISH_STEPS`]
/// factorisations, with chord steps between them, [`CHORD_CONTRACTION`]) then bring the
/// defects to the tolerance (Newton on `g`, quadratic near the solution).
///
/// **Mirror plane** (`mirror`: `target` is one half of a symmetric target, its cut on
/// the plane). A vertex on the plane keeps its coordinate along the plane's normal (its
/// row and column of that coordinate are treated as a fixed vertex's), and a plane
/// vertex inside a piece of the whole ([`mirror_interior`]) has the constraint
/// `g_v = 2π − 2 Σ θ = 0`: joined with its mirror image it has angle sum 2π, and its
/// defect is the whole's (the same tolerance holds for the whole). The half and its
/// image are then exactly developable together, with no seam along the plane.
///
/// **Fixed vertices** (`fixed`, one flag per vertex, or empty for none: a region the
/// designer keeps where it is) do not move: their rows of the step's system are the
/// identity with a zero right-hand side, their columns of `H` and `J` zero, so every step
/// leaves them exactly in place. A vertex inside a piece whose whole star is fixed cannot
/// be flattened: it is not constrained, but its defect counts in
/// [`Developed::max_defect`] (a fixed region that is not developable is out of
/// tolerance, and the pipeline cuts it a slit).
///
/// # Errors
/// [`DevelopError::Option`] (the options out of range, `fixed` of the wrong length),
/// [`DevelopError::Solver`] (the system too large or singular),
/// [`DevelopError::Cancelled`] once `stop` is set.
pub fn develop_pieces(
    target: &TriangleMesh,
    table: &EdgeTable,
    pieces: &SeamPieces,
    fixed: &[bool],
    mirror: Option<&MirrorBoundary>,
    options: &DevelopOptions,
    stop: Option<&AtomicBool>,
) -> Result<Developed, DevelopError> {
    options.validate()?;
    let nv = target.positions.len();
    if !fixed.is_empty() && fixed.len() != nv {
        return Err(DevelopError::Option {
            option: "fixed",
            message: format!("must have one flag per vertex ({nv}), got {}", fixed.len()),
        });
    }
    let fixed: Vec<bool> = if fixed.is_empty() {
        vec![false; nv]
    } else {
        fixed.to_vec()
    };
    if let Some(mirror) = mirror {
        if mirror.on_plane.len() != nv || mirror.axis > 2 {
            return Err(DevelopError::Option {
                option: "mirror",
                message: format!(
                    "must flag each of the {nv} vertices on an axis 0–2, got {} flags on axis {}",
                    mirror.on_plane.len(),
                    mirror.axis
                ),
            });
        }
    }
    let n = 3 * nv;
    // Each coordinate that does not move: a fixed vertex's three, a plane vertex's normal
    // one.
    let mut fixed_coordinate: Vec<bool> = fixed.iter().flat_map(|&f| [f; 3]).collect();
    // How many times each vertex's angle sum counts towards 2π (0: unconstrained): once
    // inside a piece, twice on the mirror plane inside a piece of the whole.
    let mut angle_goal: Vec<f64> = pieces.interior.iter().map(|&i| if i { 1.0 } else { 0.0 }).collect();
    if let Some(mirror) = mirror {
        for (v, &on) in mirror.on_plane.iter().enumerate() {
            if on {
                fixed_coordinate[3 * v + mirror.axis] = true;
            }
        }
        for (goal, half) in angle_goal
            .iter_mut()
            .zip(mirror_interior(table, pieces, mirror.on_plane))
        {
            if half {
                *goal = 2.0;
            }
        }
    }
    // A vertex inside a piece with its whole star fixed cannot move towards flatness.
    let mut star_moves = vec![false; nv];
    for t in &target.triangles {
        if t.iter().any(|&v| !fixed[v as usize]) {
            for &v in t {
                star_moves[v as usize] = true;
            }
        }
    }
    let pinned: Vec<u32> = (0..nv as u32)
        .filter(|&v| angle_goal[v as usize] > 0.0 && !star_moves[v as usize])
        .collect();
    let constrained: Vec<u32> = (0..nv as u32)
        .filter(|&v| angle_goal[v as usize] > 0.0 && star_moves[v as usize])
        .collect();
    let nc = constrained.len();
    let scale = {
        let total: f64 = table
            .edges
            .iter()
            .map(|&[a, b]| (target.positions[a as usize] - target.positions[b as usize]).norm())
            .sum();
        if table.is_empty() || total.is_nan() || total <= 0.0 {
            return Err(DevelopError::Topology {
                problem: "the mesh has no edge of positive length".into(),
            });
        }
        total / table.len() as f64
    };
    let goal: Vec<Vec3> = target.positions.iter().map(|p| p / scale).collect();
    // Lumped areas over their mean (vertices no face uses weigh 1 and stay put).
    let mut mass = vec![0.0; nv];
    for t in &target.triangles {
        let [a, b, c] = t.map(|v| goal[v as usize]);
        let third = (b - a).cross(&(c - a)).norm() / 6.0;
        for &v in t {
            mass[v as usize] += third;
        }
    }
    let mean_mass = mass.iter().sum::<f64>() / nv.max(1) as f64;
    for m in &mut mass {
        *m = if *m > 0.0 { *m / mean_mass } else { 1.0 };
    }
    let mut degree = vec![0usize; nv];
    for &[a, b] in &table.edges {
        degree[a as usize] += 1;
        degree[b as usize] += 1;
    }
    // Corners around each constrained vertex: (face, position of v in it).
    let mut corners: Vec<Vec<(u32, u8)>> = vec![Vec::new(); nv];
    for (f, t) in target.triangles.iter().enumerate() {
        for (k, &v) in t.iter().enumerate() {
            if angle_goal[v as usize] > 0.0 {
                corners[v as usize].push((f as u32, k as u8));
            }
        }
    }
    // The Jacobian row of each constraint: its star's vertices, sorted.
    let stars: Vec<Vec<u32>> = constrained
        .iter()
        .map(|&v| {
            let mut star: Vec<u32> = corners[v as usize]
                .iter()
                .flat_map(|&(f, _)| target.triangles[f as usize])
                .collect();
            star.sort_unstable();
            star.dedup();
            star
        })
        .collect();
    // The pattern (upper triangle), in a fixed order: H's diagonal, H's edges, the
    // Jacobian's columns, the −δ block.
    let s = options.smoothness;
    let mut pairs = Vec::new();
    let mut h_values = Vec::new();
    for v in 0..nv {
        for k in 0..3 {
            pairs.push(Pair {
                row: 3 * v + k,
                col: 3 * v + k,
            });
            h_values.push(mass[v] + s * degree[v] as f64);
        }
    }
    if s > 0.0 {
        for &[a, b] in &table.edges {
            let (a, b) = (a.min(b) as usize, a.max(b) as usize);
            for k in 0..3 {
                // A fixed coordinate's row is diagonal: no coupling to its neighbours.
                let coupling = if fixed_coordinate[3 * a + k] || fixed_coordinate[3 * b + k] {
                    0.0
                } else {
                    -s
                };
                pairs.push(Pair {
                    row: 3 * a + k,
                    col: 3 * b + k,
                });
                h_values.push(coupling);
            }
        }
    }
    let delta = 1e-12;
    // The step's system: H's diagonal as its metric, solved through the constraints'
    // Schur complement, while the smoothness term is light; H itself otherwise.
    let (mut kkt, jacobian_start) = if s <= DIAGONAL_METRIC_SMOOTHNESS {
        let rows: Vec<Vec<usize>> = stars
            .iter()
            .map(|star| {
                star.iter()
                    .flat_map(|&w| (0..3).map(move |k| 3 * w as usize + k))
                    .collect()
            })
            .collect();
        let row_coordinates: Vec<Vec3> = constrained.iter().map(|&v| goal[v as usize]).collect();
        let mut system = DiagonalKktSystem::new(n, &rows, &row_coordinates).map_err(too_large)?;
        for (i, w) in system.inverse_metric.iter_mut().enumerate() {
            *w = if fixed_coordinate[i] { 0.0 } else { 1.0 / h_values[i] };
        }
        (StepSystem::Diagonal(system), 0)
    } else {
        let jacobian_start = pairs.len();
        for (c, star) in stars.iter().enumerate() {
            for &w in star {
                for k in 0..3 {
                    pairs.push(Pair {
                        row: 3 * w as usize + k,
                        col: n + c,
                    });
                }
            }
        }
        let delta_start = pairs.len();
        for c in 0..nc {
            pairs.push(Pair { row: n + c, col: n + c });
        }
        let mut blocks: Vec<usize> = (0..n).map(|i| i / 3).collect();
        blocks.extend(constrained.iter().map(|&v| v as usize));
        let mut system = KktSystem::new(n, nc, pairs, &blocks, &goal, true).map_err(too_large)?;
        system.values = vec![0.0; delta_start + nc];
        system.values[..h_values.len()].copy_from_slice(&h_values);
        for value in &mut system.values[delta_start..] {
            *value = -delta;
        }
        (StepSystem::Full(system), jacobian_start)
    };
    let geometry = Geometry {
        triangles: &target.triangles,
        constrained: &constrained,
        corners: &corners,
        stars: &stars,
        fixed: &fixed_coordinate,
        multiplicity: constrained.iter().map(|&v| angle_goal[v as usize]).collect(),
    };
    let row_starts: Vec<usize> = stars
        .iter()
        .scan(jacobian_start, |start, star| {
            let here = *start;
            *start += 3 * star.len();
            Some(here)
        })
        .collect();
    let objective = |x: &[Vec3], h: &[f64]| -> (f64, Vec<f64>) {
        // ½ dᵀ H d and H d with d = x − t (H from its values: diagonal, then edges).
        let d: Vec<f64> = x
            .iter()
            .zip(&goal)
            .flat_map(|(p, q)| (p - q).iter().copied().collect::<Vec<_>>())
            .collect();
        let mut hd: Vec<f64> = (0..n).map(|i| h[i] * d[i]).collect();
        if s > 0.0 {
            for (e, &[a, b]) in table.edges.iter().enumerate() {
                let (a, b) = (a.min(b) as usize, a.max(b) as usize);
                for k in 0..3 {
                    let value = h[n + 3 * e + k];
                    hd[3 * a + k] += value * d[3 * b + k];
                    hd[3 * b + k] += value * d[3 * a + k];
                }
            }
        }
        let energy = 0.5 * d.iter().zip(&hd).map(|(a, b)| a * b).sum::<f64>();
        (energy, hd)
    };
    let mut x = goal.clone();
    let mut defects = geometry.defects(&x, None);
    // The vertices inside a piece that a fixed region pins (unconstrained) count too.
    let pinned_defect = |x: &[Vec3]| {
        if pinned.is_empty() {
            return 0.0;
        }
        let sums = vertex_angle_sums(x, &target.triangles);
        pinned
            .iter()
            .map(|&v| (TAU - angle_goal[v as usize] * sums[v as usize]).abs())
            .fold(0.0, f64::max)
    };
    let max_defect_before = max_abs(&defects).max(pinned_defect(&x));
    let mut iterations = 0;
    let mut settled = false;
    let tolerance = options.defect_tolerance;
    let factorise = |kkt: &mut StepSystem| {
        kkt.factorise(delta)
            .map_err(|FactorisationFailure::Singular| DevelopError::Solver {
                message: "the step's linear system is singular (a degenerate or flat-folded triangle)".into(),
            })
    };
    // The polish's corrections are inexact Newton steps (Dembo, Eisenstat & Steihaug
    // 1982): refined until their constraint rows are within 10⁻³ of the largest defect,
    // or a tenth of the tolerance once the defects are that small (`max`: far from the
    // solution only the forcing term counts; `KktSystem::projection` takes the smaller
    // of the two, the FFD's choice), so that the last steps land within the tolerance.
    // The first solve usually meets it far from the solution (measured on the koala:
    // constraint residuals of 1e-10 where the defects are about 1 rad; refined to
    // rounding, every step took two solves). The closeness steps above are solved to
    // rounding: inexact, they changed the path (benchmarks-history.md, session 29).
    let forcing = |defects: &[f64]| SolveAccuracy::ConstraintResidual((1e-3 * max_abs(defects)).max(0.1 * tolerance));
    let mut stalled = 0;
    // Steps in a row each constrained vertex's defect has stayed above HOPELESS_DEFECT.
    let mut stuck = vec![0usize; nc];
    let mut hopeless = Vec::new();
    while iterations < options.max_iterations {
        if stop.is_some_and(|flag| flag.load(Ordering::Relaxed)) {
            return Err(DevelopError::Cancelled);
        }
        iterations += 1;
        defects = geometry.defects(&x, Some((kkt.jacobian(), &row_starts)));
        factorise(&mut kkt)?;
        let (energy, hd) = objective(&x, &h_values);
        let mut rhs: Vec<f64> = hd.iter().map(|v| -v).chain(defects.iter().map(|g| -g)).collect();
        for (value, _) in rhs.iter_mut().zip(&fixed_coordinate).filter(|(_, &f)| f) {
            *value = 0.0;
        }
        kkt.solve_to(&mut rhs, SolveAccuracy::Rounding);
        let step: Vec<Vec3> = (0..nv)
            .map(|v| Vec3::new(rhs[3 * v], rhs[3 * v + 1], rhs[3 * v + 2]))
            .collect();
        let multipliers = &rhs[n..];
        let mu = 2.0 * max_abs(multipliers) + 1.0;
        let violation: f64 = defects.iter().map(|g| g.abs()).sum();
        let merit = energy + mu * violation;
        let slope = hd.iter().zip(rhs[..n].iter()).map(|(a, b)| a * b).sum::<f64>() - mu * violation;
        let longest = step.iter().map(|d| d.norm()).fold(0.0, f64::max);
        let mut alpha = (STEP_REACH / longest.max(f64::MIN_POSITIVE)).min(1.0);
        let mut accepted = None;
        for _ in 0..30 {
            let trial: Vec<Vec3> = x.iter().zip(&step).map(|(p, d)| p + d * alpha).collect();
            let trial_defects = geometry.defects(&trial, None);
            let trial_merit = objective(&trial, &h_values).0 + mu * trial_defects.iter().map(|g| g.abs()).sum::<f64>();
            if trial_merit.is_finite() && trial_merit <= merit + 1e-4 * alpha * slope.min(0.0) {
                accepted = Some((trial, trial_defects));
                break;
            }
            alpha *= 0.5;
        }
        let Some((trial, trial_defects)) = accepted else {
            tracing::debug!(iterations, "develop: the line search found no decrease");
            break;
        };
        // Once every defect is within the tolerance, a step that takes one out of it is
        // not taken: the ℓ₁ merit's weight only estimates the multipliers, and far along
        // such steps the solve traded developability for closeness (measured: from
        // 1.5e-14 rad at step 6 back to 5e-4 rad by step 100 on the globe).
        if max_abs(&defects) <= tolerance && max_abs(&trial_defects) > tolerance {
            settled = true;
            break;
        }
        let moved = step.iter().map(|d| d.amax()).fold(0.0, f64::max) * alpha;
        x = trial;
        defects = trial_defects;
        tracing::debug!(
            iterations,
            alpha,
            energy,
            max_defect = max_abs(&defects),
            violation = defects.iter().map(|g| g.abs()).sum::<f64>(),
            moved,
            "develop step"
        );
        for (count, g) in stuck.iter_mut().zip(&defects) {
            *count = if g.abs() > HOPELESS_DEFECT { *count + 1 } else { 0 };
        }
        if options.end_at_hopeless_cone_points && stuck.iter().any(|&c| c >= HOPELESS_STEPS) {
            hopeless = constrained
                .iter()
                .zip(&stuck)
                .filter(|(_, &c)| c >= HOPELESS_COMPANION_STEPS)
                .map(|(&v, _)| v)
                .collect();
            tracing::debug!(
                iterations,
                count = hopeless.len(),
                "develop: cone points found hopeless"
            );
            break;
        }
        if max_abs(&defects) <= tolerance && moved <= STEP_TOLERANCE {
            settled = true;
            break;
        }
        // Closeness has stopped improving: the feasibility polish below finishes faster
        // than more of these linearly converging steps. So it does when the line search
        // keeps only slivers of the steps (see `STALL_MOVE`).
        let now = objective(&x, &h_values).0;
        if moved <= STALL_MOVE || (now - energy).abs() <= STALL_TOLERANCE * now && max_abs(&defects) < STALL_DEFECT {
            stalled += 1;
            if stalled >= STALL_STEPS {
                break;
            }
        } else {
            stalled = 0;
        }
    }
    // Feasibility: corrections J Δx = −g of least norm in the step's metric (Newton on g)
    // while needed; a correction that contracted the defects well is followed by one
    // with the same factor (a chord step, see `CHORD_CONTRACTION`).
    let mut corrections = 0;
    let mut factorisations = 0;
    // Whether the factor is of the Jacobian at `x`, and whether the next correction may
    // use the factor of an earlier point.
    let mut factor_at_x = false;
    let mut reuse_factor = false;
    let mut chord_steps = 0;
    while hopeless.is_empty() && max_abs(&defects) > tolerance {
        if stop.is_some_and(|flag| flag.load(Ordering::Relaxed)) {
            return Err(DevelopError::Cancelled);
        }
        if !reuse_factor {
            if factorisations == POLISH_STEPS {
                break;
            }
            defects = geometry.defects(&x, Some((kkt.jacobian(), &row_starts)));
            factorise(&mut kkt)?;
            factorisations += 1;
            factor_at_x = true;
            chord_steps = 0;
        }
        let mut step: Vec<f64> = vec![0.0; n].into_iter().chain(defects.iter().map(|g| -g)).collect();
        kkt.solve_to(&mut step, forcing(&defects));
        let before: f64 = defects.iter().map(|g| g.abs()).sum();
        let longest = (0..nv)
            .map(|v| Vec3::new(step[3 * v], step[3 * v + 1], step[3 * v + 2]).norm())
            .fold(0.0, f64::max);
        let mut alpha = (STEP_REACH / longest.max(f64::MIN_POSITIVE)).min(1.0);
        let mut accepted = None;
        for _ in 0..12 {
            let trial: Vec<Vec3> = (0..nv)
                .map(|v| x[v] + alpha * Vec3::new(step[3 * v], step[3 * v + 1], step[3 * v + 2]))
                .collect();
            let trial_defects = geometry.defects(&trial, None);
            if trial_defects.iter().map(|g| g.abs()).sum::<f64>() < before {
                accepted = Some((trial, trial_defects));
                break;
            }
            alpha *= 0.5;
        }
        let Some((trial, trial_defects)) = accepted else {
            if factor_at_x {
                break;
            }
            // The chord step did not help: a fresh factor at `x`.
            reuse_factor = false;
            continue;
        };
        x = trial;
        defects = trial_defects;
        corrections += 1;
        let after: f64 = defects.iter().map(|g| g.abs()).sum();
        tracing::debug!(
            corrections,
            chord = !factor_at_x,
            alpha,
            before,
            after,
            max_defect = max_abs(&defects),
            "develop polish step"
        );
        chord_steps += usize::from(!factor_at_x);
        reuse_factor = alpha == 1.0 && after <= CHORD_CONTRACTION * before && chord_steps < MAX_CHORD_STEPS;
        factor_at_x = false;
    }
    let max_defect = max_abs(&defects).max(pinned_defect(&x));
    // Fixed coordinates stay exactly where they were (not rescaled).
    let positions: Vec<Vec3> = x
        .iter()
        .zip(&target.positions)
        .zip(fixed_coordinate.chunks(3))
        .map(|((p, q), f)| Vec3::from_fn(|k, _| if f[k] { q[k] } else { p[k] * scale }))
        .collect();
    let displacements: Vec<f64> = positions
        .iter()
        .zip(&target.positions)
        .map(|(p, q)| (p - q).norm())
        .collect();
    Ok(Developed {
        positions,
        constrained_vertex_count: nc,
        max_defect_before,
        max_defect,
        iterations: iterations + corrections,
        converged: max_defect <= tolerance,
        displacement_max: displacements.iter().copied().fold(0.0, f64::max),
        displacement_mean: displacements.iter().sum::<f64>() / nv.max(1) as f64,
        hopeless,
    })
    .inspect(|developed| {
        tracing::info!(
            settled,
            iterations = developed.iterations,
            max_defect = developed.max_defect,
            "develop: pieces made developable"
        );
    })
}

/// The step's linear system `[H Jᵀ; J −δI]`, or the same with `H`'s diagonal.
enum StepSystem {
    /// `H`'s diagonal as the step's metric ([`DiagonalKktSystem`]: the constraints'
    /// Schur complement factorised).
    Diagonal(DiagonalKktSystem),
    /// `H` itself ([`KktSystem`]).
    Full(KktSystem),
}

impl StepSystem {
    /// The values the Jacobian's rows are written into.
    fn jacobian(&mut self) -> &mut Vec<f64> {
        match self {
            Self::Diagonal(system) => &mut system.constraint_values,
            Self::Full(system) => &mut system.values,
        }
    }

    fn factorise(&mut self, delta: f64) -> Result<(), FactorisationFailure> {
        match self {
            Self::Diagonal(system) => system.factorise(delta),
            Self::Full(system) => system.factorise(delta),
        }
    }

    fn solve_to(&mut self, rhs: &mut [f64], accuracy: SolveAccuracy) {
        match self {
            Self::Diagonal(system) => system.solve_to(rhs, accuracy),
            Self::Full(system) => system.solve_to(rhs, accuracy),
        }
    }
}

/// A system too large to factorise, as the develop error.
fn too_large(error: KktError) -> DevelopError {
    DevelopError::Solver {
        message: format!("{error}: use a coarser mesh"),
    }
}

/// Largest absolute value (0 for none).
fn max_abs(values: &[f64]) -> f64 {
    values.iter().fold(0.0, |m, v| m.max(v.abs()))
}

/// What the defects are computed from.
struct Geometry<'a> {
    triangles: &'a [[u32; 3]],
    constrained: &'a [u32],
    corners: &'a [Vec<(u32, u8)>],
    stars: &'a [Vec<u32>],
    /// Fixed coordinates (three per vertex): their Jacobian columns are zero.
    fixed: &'a [bool],
    /// How many times each constraint's angle sum counts (1, or 2 on a mirror plane).
    multiplicity: Vec<f64>,
}

impl Geometry<'_> {
    /// The defects `g_v = 2π − m Σ θ` (`m` = 2 on a mirror plane, else 1) at `x`; with
    /// `jacobian`, also writes `∂g/∂x` into the values (each constraint's row from its
    /// start, its star's vertices in order; the rows follow each other). The constraints
    /// are shared out over rayon's threads.
    fn defects(&self, x: &[Vec3], jacobian: Option<(&mut Vec<f64>, &Vec<usize>)>) -> Vec<f64> {
        // Constraints per rayon task: a few microseconds of work each.
        const CHUNK: usize = 64;
        match jacobian {
            None => (0..self.constrained.len())
                .into_par_iter()
                .with_min_len(CHUNK)
                .map(|c| self.defect(c, x, None))
                .collect(),
            Some((values, starts)) => {
                let mut rows: Vec<&mut [f64]> = Vec::with_capacity(self.constrained.len());
                let mut rest = &mut values[starts.first().copied().unwrap_or(0)..];
                for (c, star) in self.stars.iter().enumerate() {
                    debug_assert!(c + 1 == starts.len() || starts[c + 1] == starts[c] + 3 * star.len());
                    let (row, tail) = std::mem::take(&mut rest).split_at_mut(3 * star.len());
                    rows.push(row);
                    rest = tail;
                }
                rows.into_par_iter()
                    .with_min_len(CHUNK)
                    .enumerate()
                    .map(|(c, row)| self.defect(c, x, Some(row)))
                    .collect()
            }
        }
    }

    /// Constraint `c`'s defect at `x`; with `row`, its Jacobian row.
    fn defect(&self, c: usize, x: &[Vec3], row: Option<&mut [f64]>) -> f64 {
        let v = self.constrained[c];
        let star = &self.stars[c];
        let mut defect = TAU;
        let mut gradient = row.as_ref().map(|_| vec![Vec3::zeros(); star.len()]);
        for &(f, k) in &self.corners[v as usize] {
            let t = self.triangles[f as usize];
            let k = k as usize;
            let corner = [t[k], t[(k + 1) % 3], t[(k + 2) % 3]];
            let (angle, grads) =
                corner_angle_gradient(x[corner[0] as usize], x[corner[1] as usize], x[corner[2] as usize]);
            defect -= self.multiplicity[c] * angle;
            if let Some(gradient) = gradient.as_mut() {
                for (w, g) in corner.iter().zip(grads) {
                    let i = star.binary_search(w).expect("a corner's vertices are in its star");
                    gradient[i] -= g * self.multiplicity[c];
                }
            }
        }
        if let (Some(row), Some(gradient)) = (row, gradient) {
            for (i, (g, &w)) in gradient.iter().zip(star).enumerate() {
                for k in 0..3 {
                    let fixed = self.fixed[3 * w as usize + k];
                    row[3 * i + k] = if fixed { 0.0 } else { g[k] };
                }
            }
        }
        defect
    }
}

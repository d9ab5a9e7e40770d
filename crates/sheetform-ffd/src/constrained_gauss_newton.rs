//! The default solver: constrained Gauss–Newton (SQP) on the embedded parameters.

use crate::bending_metric::BendingMetric;
use crate::normal_step_reduction::NormalStepReduction;
use crate::{DevelopabilityProblem, Evaluation, FfdError, RestorationInfo};
use faer::sparse::Pair;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use sheetform_geometry::short_number;
use sheetform_solve::{FactorisationFailure, KktError, KktSystem};
use std::time::Instant;

/// The shared KKT system's refusals in the FFD's terms: the model is what the user can
/// change (fewer gores, segments or panels).
impl From<KktError> for FfdError {
    fn from(error: KktError) -> Self {
        match error {
            KktError::TooLarge { rows } => FfdError::Solver(format!(
                "the restoration's linear system ({rows} rows) is too large to factorise on this machine; use fewer vertices"
            )),
            KktError::OverMemory { .. } => FfdError::field(
                "model",
                format!("the restoration's {error}: use fewer vertices (fewer gores, segments or panels)"),
            ),
        }
    }
}

/// Knobs of [`restore_constrained`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConstrainedOptions {
    /// Stop when every angle defect is at most this (radians).
    pub tolerance: f64,
    /// Weight `β` of the proximity term `½ β Σ |q_n − q′_n|² / l̄²` next to the springs
    /// `½ Σ (|q_s − q_e| − l⁰)² / l̄²`. A departure from the paper (whose objective is the
    /// springs alone): springs do not see motions that keep every edge length (rigid
    /// motions, flexing of the mesh), and without this term the result could drift along
    /// them. 0.01: small enough that edge lengths dominate.
    pub position_weight: f64,
    /// Most iterations (default 100: with the default bending term the examples need at
    /// most 11 and a 40k-vertex duct 15; with the springs alone the paper's sizes need up
    /// to 27 and a 6 300-node duct 67 with the stall fallback).
    pub max_iterations: usize,
    /// Memory `M` of the restoration's non-monotone line search: a trial step is accepted
    /// when its largest defect is below the largest of the last `M` iterates' (1: below
    /// the current one, a monotone search). 12 (default): skirt 27 iterations instead
    /// of 38 and trousers 25 instead of 32, with the same edge-length change and
    /// deviation within 4 %; docs/benchmarks-history.md has the figures.
    pub line_search_memory: usize,
    /// Most refinement iterations after the defects are within tolerance (0: restore
    /// only).
    pub refine_iterations: usize,
    /// Refinement stops when the objective falls by less than this fraction in one step.
    pub objective_tolerance: f64,
    /// Weight `γ` of the bending term `½ γ (A/l̄²) Σ_e w_e (δθ_e)²` added to the metric of
    /// the steps (not to the objective; `δθ_e` a step's change of the dihedral angle at
    /// interior edge `e`, `w_e = |e|²/(A₁ + A₂)`, `A` the panels' area, `l̄` their mean
    /// edge length; see `BendingMetric`). Default 3e-3. With the springs alone (`γ = 0`,
    /// the paper's energy) the least-norm steps move single nodes along the normal; the
    /// line search cuts them for tens of iterations (skirt 27, trousers 25) and the
    /// restoration reaches zero defect by folding the panels into node-scale zig-zags:
    /// the largest fold angle goes from 0.09 to 0.56 rad on the skirt and from 0.19 to
    /// 0.79 rad on the trousers, crinkles that the edge-length change and the deviation
    /// do not see (the springs alone change edge lengths less: skirt 3.8 % against
    /// 13 %). With the default the skirt takes 4 full steps and ends at 0.088 rad, the
    /// trousers 4 and 0.187 rad. The factor `A/l̄²` (about the number of triangles)
    /// keeps the ratio of bending to springs fixed when a mesh is refined (the springs'
    /// sum over edges grows like `1/h²` for the same strain, the bending sum does not):
    /// ducts of 2.5k to 40k vertices take 5 to 9 steps. Larger `γ`: fewer steps, lower
    /// deviation, larger edge-length changes (docs/benchmarks-history.md has the sweep).
    pub bending_weight: f64,
    /// The bending weight switched on when the restoration stalls with `bending_weight`
    /// 0: after five steps in a row cut to `α ≤ 1/64` (0: never; default 3e-3). On fine
    /// meshes the springs' least-norm steps are dominated by node-scale normal
    /// oscillations, and with springs alone the restoration crawls without converging
    /// (a 16k-vertex duct, before this fallback existed: max defect 2.1e-4 → 2.3e-4 in
    /// 60 iterations); the term damps them.
    /// [`RestorationInfo::bending_fallback_iteration`] says when it happened. A
    /// restoration that stalls with nothing left to switch on (the term already on, or
    /// this weight 0) stops there, not converged, instead of crawling on to
    /// `max_iterations`.
    pub stall_bending_weight: f64,
    /// Which unknowns the steps move: every node's three lattice parameters (default) or
    /// one per node along the surface normal (`NormalStepReduction`): about a quarter of
    /// the factor's values, for large meshes, at the price of larger edge-length changes
    /// on small ones.
    pub step_unknowns: StepUnknowns,
    /// Most chord steps after a full step (see [`restore_constrained`]; 0: none).
    /// Default 8. [`crate::restore_along_path`] sets 0: along the path of a large
    /// deformation the chords' steps, each of least norm for the metric of an earlier
    /// iterate, add up to larger edge-length changes (the duct deformed five times
    /// over: 49 % against 42 %).
    pub chord_steps: usize,
}

/// The unknowns of the constrained solver's steps (`solver.step_unknowns`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum StepUnknowns {
    /// Each node's three lattice parameters (the paper's unknowns).
    #[default]
    Parameters,
    /// One per node: a move along the surface normal. The factor holds about a quarter
    /// of the values and takes about a third of the time on the 100k-vertex duct (15.4 %
    /// largest edge-length change against 14.3 %); on small meshes the edges change more
    /// (duct 20 % against 14.9 %, trousers 29 % against 22 %), since only tangential moves
    /// let the mesh slide to keep its lengths.
    Normal,
}

impl Default for ConstrainedOptions {
    fn default() -> Self {
        Self {
            tolerance: 1e-10,
            position_weight: 0.01,
            max_iterations: 100,
            line_search_memory: 12,
            objective_tolerance: 1e-3,
            refine_iterations: 0,
            bending_weight: 3e-3,
            stall_bending_weight: 3e-3,
            step_unknowns: StepUnknowns::Parameters,
            chord_steps: 8,
        }
    }
}

/// A step cut to at most this fraction counts as stalled. 1/64: with the springs alone
/// the examples at the paper's sizes never take five such steps in a row; a 6 300-node
/// duct does after 29 iterations (it crawls at 1/64–1/128 without converging).
const STALL_STEP: f64 = 1.0 / 64.0;
/// Stalled steps in a row before the bending term is switched on.
const STALL_ITERATIONS: usize = 5;
/// A chord step is kept when the largest defect falls to at most this fraction.
const CHORD_CONTRACTION: f64 = 0.5;

/// The factorised system of the steps: the KKT system of every parameter, or its
/// reduction to the normals.
struct StepSystem {
    kkt: KktSystem,
    reduction: Option<NormalStepReduction>,
}

impl StepSystem {
    /// The projection step `p` (full parameters) with `A p = −g` of least `H`-norm.
    fn projection(&mut self, defects: &[f64], tolerance: f64) -> Vec<f64> {
        let step = self.kkt.projection(defects, tolerance);
        match &self.reduction {
            Some(reduction) => reduction.expand(&step),
            None => step,
        }
    }

    /// The refinement step: `[H Aᵀ; A −δI] [p; λ] = [−∇f; 0]` (full parameters).
    fn descent(&mut self, gradient: &[f64]) -> Vec<f64> {
        let reduced;
        let gradient = match &self.reduction {
            Some(reduction) => {
                reduced = reduction.reduce_vector(gradient);
                &reduced
            }
            None => gradient,
        };
        let mut rhs: Vec<f64> = gradient
            .iter()
            .map(|g| -g)
            .chain(std::iter::repeat_n(0.0, self.kkt.nc))
            .collect();
        self.kkt.solve(&mut rhs);
        rhs.truncate(self.kkt.n);
        match &self.reduction {
            Some(reduction) => reduction.expand(&rhs),
            None => rhs,
        }
    }
}

/// The step system's pattern at `e` for `metric`, ordered and analysed.
fn kkt_system_at(
    problem: &DevelopabilityProblem<'_>,
    e: &Evaluation,
    metric: &Metric<'_>,
    unknowns: StepUnknowns,
) -> Result<StepSystem, FfdError> {
    // Blocks (see `KktSystem::new`): a variable node's parameter triple and the defect at
    // that node; a defect whose node is fixed forms a block of its own.
    let mut block_coordinates: Vec<nalgebra::Vector3<f64>> =
        problem.variables.iter().map(|&m| e.positions[m as usize]).collect();
    let mut blocks: Vec<usize> = (0..problem.unknown_count()).map(|i| i / 3).collect();
    for &m in &problem.constraint_nodes {
        let v = problem.variable_of_node[m as usize];
        blocks.push(if v == u32::MAX {
            block_coordinates.push(e.positions[m as usize]);
            block_coordinates.len() - 1
        } else {
            v as usize
        });
    }
    // With the bending term AMD fills less at every size compared (see `KktSystem::new`).
    let amd_when_small = metric.bending.is_some();
    let n = problem.unknown_count();
    match unknowns {
        StepUnknowns::Parameters => {
            let mut pairs = Vec::new();
            assemble(problem, e, metric, |row, col, _| pairs.push(Pair { row, col }));
            Ok(StepSystem {
                kkt: KktSystem::new(
                    n,
                    problem.constraint_count(),
                    pairs,
                    &blocks,
                    &block_coordinates,
                    amd_when_small,
                )?,
                reduction: None,
            })
        }
        StepUnknowns::Normal => {
            let mut entries = Vec::new();
            assemble(problem, e, metric, |row, col, _| {
                entries.push(NormalStepReduction::reduced_entry(n, row, col));
            });
            let (reduction, reduced_pairs) = NormalStepReduction::new(n, &entries)?;
            drop(entries);
            // A node's one unknown is its block, as its three were.
            let reduced_blocks: Vec<usize> = (0..reduction.unknowns()).chain(blocks[n..].iter().copied()).collect();
            Ok(StepSystem {
                kkt: KktSystem::new(
                    reduction.unknowns(),
                    problem.constraint_count(),
                    reduced_pairs,
                    &reduced_blocks,
                    &block_coordinates,
                    amd_when_small,
                )?,
                reduction: Some(reduction),
            })
        }
    }
}

/// Assembles `[H Aᵀ; A −δI]` at `e` into `kkt` and factorises it; returns the
/// objective's gradient and the assembly's share of the time.
fn factorise(
    system: &mut StepSystem,
    problem: &DevelopabilityProblem<'_>,
    e: &Evaluation,
    metric: &Metric<'_>,
) -> Result<(Vec<f64>, std::time::Duration), FfdError> {
    let clock = Instant::now();
    let kkt = &mut system.kkt;
    let (delta, gradient) = match system.reduction.as_mut() {
        Some(reduction) => {
            // `BᵀKB` directly: each full entry scaled by `B` into its reduced slot.
            reduction.update(problem, e);
            kkt.values.fill(0.0);
            let mut reduced = reduction.reducer(&mut kkt.values);
            assemble(problem, e, metric, |row, col, value| reduced.add(row, col, value))
        }
        None => {
            kkt.values.clear();
            assemble(problem, e, metric, |_, _, value| kkt.values.push(value))
        }
    };
    let assembled = clock.elapsed();
    if kkt.values.iter().any(|v| !v.is_finite()) {
        return Err(degenerate(problem, e));
    }
    kkt.factorise(delta)
        .map_err(|FactorisationFailure::Singular| degenerate(problem, e))?;
    Ok((gradient, assembled))
}

/// The error for a restoration whose linear system is singular or not finite, naming
/// the first place found: a node the lattice maps to a non-finite point or with a
/// singular Jacobian, or a triangle collapsed to a zero-length edge.
pub(crate) fn degenerate(problem: &DevelopabilityProblem<'_>, e: &Evaluation) -> FfdError {
    let vertex_of = |node: u32| {
        problem
            .assembly
            .vertex_node
            .iter()
            .position(|&m| m == node)
            .unwrap_or(node as usize)
    };
    let at = |node: u32| {
        let p = problem.target[node as usize];
        format!(
            "vertex {} ({}, {}, {})",
            vertex_of(node),
            short_number(p.x),
            short_number(p.y),
            short_number(p.z)
        )
    };
    for (v, &node) in problem.variables.iter().enumerate() {
        let (p, jacobian) = (e.positions[node as usize], e.jacobians[v]);
        if !(p.iter().all(|x| x.is_finite()) && jacobian.iter().all(|x| x.is_finite())) {
            return FfdError::Solver(format!(
                "the restoration cannot continue at {}: the lattice maps it to a non-finite point",
                at(node)
            ));
        }
        if jacobian.determinant().abs() <= 1e-12 * jacobian.norm().powi(3) {
            return FfdError::Solver(format!(
                "the restoration cannot move {}: the deformed lattice is flat or folded there (its Jacobian is singular); undo the edit that squashes it",
                at(node)
            ));
        }
    }
    let shortest = 1e-9 * problem.length_scale;
    for t in &problem.assembly.node_triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if (e.positions[a as usize] - e.positions[b as usize]).norm() <= shortest {
                return FfdError::Solver(format!(
                    "the restoration collapsed an edge at {}; try a smaller deformation or solver.continuation",
                    at(a)
                ));
            }
        }
    }
    FfdError::Solver(
        "the restoration's linear system is singular: no motion the lattice allows changes some angle defect (the lattice may be flat or folded where the panels are, or vertices sit on its boundary: a larger lattice.margin helps)".to_string(),
    )
}

/// Restores developability in two phases, both with the step metric `H + B`: `H = JᵀJ + μI`
/// the Gauss–Newton model of
///
/// `f(X) = ½ Σ_j (|q_s − q_e| − l⁰_j)² / l̄² + ½ β Σ_n |q_n − q′_n|² / l̄²`
///
/// (`q_n = Q′(X_n)`, springs of Eq. 2-2 plus a small proximity term), `B` the
/// Gauss–Newton matrix of a bending term on the step's normal displacements
/// (`bending_weight`, see `BendingMetric` in `bending_metric.rs`; `B = 0` when the
/// weight is 0), with the exact Jacobian `A` of the defects `g(q_i(X))` (chain rule
/// through `∂Q/∂(u,v,w)`, [`DevelopabilityProblem::defect_gradient`]):
///
/// 1. **Restoration** (Gauss–Newton projection onto `g = 0`): `p` of least `(H + B)`-norm
///    with `A p = −g`, i.e. `[H + B  Aᵀ; A −δI] [p; λ] = [0; −g]`, halved until the largest defect
///    falls below the largest of the last `line_search_memory` iterates' (a non-monotone
///    test in the manner of Grippo, Lampariello & Lucidi, SIAM J. Numer. Anal. 23(4),
///    1986; the reference value never increases, so the largest defect still falls
///    over every `M` iterations). A sum-of-defects test accepted longer steps and
///    converged in fewer iterations, but left edges changed by up to 37 % on the
///    trousers instead of 10 %; the largest defect keeps the path close to the
///    continuous Newton flow. Converges quadratically once close; ends when every
///    `|g| ≤ tolerance`. Each projection is solved as an inexact Newton step (see
///    `KktSystem::projection`). After a full step (`α = 1`), **chord steps** reuse its
///    factorisation: `p′` with `A p′ = −g(X + p)` for the same `A` and metric (a
///    simplified Newton step, Kantorovich's chord method), kept while each is at most
///    half as long as the step before it and at least halves the largest defect, at
///    most `chord_steps` in a row. A chord step costs one triangular solve and an
///    evaluation of the defects, about a tenth of a factorisation on the 100k-vertex
///    duct; there they replace 2 of 7 factorisations (docs/benchmarks-history.md, session 19).
///    The length test keeps them inside the region where the old Jacobian still holds
///    (without it, a duct deformed five times over and restored along its path
///    wandered off and stopped unconverged).
/// 2. **Refinement** (optional, `refine_iterations`, default 0; SQP with a Gauss–Newton
///    Hessian): `[H Aᵀ; A −δI] [p; λ] =
///    [−∇f; 0]` moves along the constraint surface to lower `f`, followed by projection
///    steps back onto `g = 0`; a step is kept only if `f` decreased and every defect is
///    still within tolerance. Stops when `f` changes by less than `objective_tolerance`.
///
/// **Bending term** (default on): with the springs alone (`bending_weight` 0) the
/// least-norm steps move single nodes along the normal, the line search cuts them for
/// tens of iterations, and the shape reached is crinkled (node-scale zig-zag folds, see
/// [`crate::fold_angle_max`]); the term makes the steps smooth, so they are taken in
/// full (skirt: 4 instead of 27) and the result is fair, with larger edge-length changes
/// (skirt 13 % instead of 3.8 %) but the same deviation (20.4 mm).
///
/// **Stall fallback**: when steps with the springs alone are cut to `α ≤ 1/64` five
/// times in a row (fine meshes), the bending term is switched on with
/// `stall_bending_weight` and the KKT pattern rebuilt. A second stall, or a stall with
/// the term already on, ends the restoration unconverged.
///
/// The linear systems are solved by a sparse LDLᵀ factorisation (faer; ordering, AMD
/// or nested dissection on the graph of nodes, each node's parameters eliminated just
/// before the defect at that node (see `KktSystem::new`), and symbolic analysis once
/// per problem, numeric factorisation per iteration). The tiny
/// `μ = 1e-9·mean diag (H + B)` and `δ` make the matrix quasi-definite; iterative
/// refinement against the system without `δ` removes its effect (see `KktSystem::solve`).
///
/// Departures and why: the paper minimises `E + (ρ/2) G²` by conjugate gradients with
/// finite-difference gradients (§3) and never reaches `G = 0` (Table 1). A full SQP
/// iteration from the start was tried first: its Gauss–Newton Hessian lacks the
/// constraints' curvature `Σ λ ∇²g`, which dominates in the direction normal to the
/// surface (edge lengths change only to second order there), so its steps were cut
/// by the line search and it crawled (60 iterations, defect 5e-5 on the duct).
/// Projecting first reaches `1e-12` in about ten iterations (duct: 10 iterations,
/// 20 ms); ten refinement iterations then lower the duct's deviation from 9.6 to 6.5 mm
/// and its largest edge-length change from 4.9 % to 2.0 % but take 8× the time, so they
/// are off by default.
///
/// # Errors
/// [`FfdError::Solver`] if the factorisation fails.
pub fn restore_constrained(
    problem: &DevelopabilityProblem<'_>,
    options: &ConstrainedOptions,
) -> Result<(Vec<nalgebra::Vector3<f64>>, RestorationInfo), FfdError> {
    restore_constrained_with_progress(problem, options, &mut |_, _| {})
}

/// [`restore_constrained`], calling `progress(iteration, largest |defect|)` at the start
/// (iteration 0) and after each iteration (both phases).
///
/// # Errors
/// As [`restore_constrained`].
pub fn restore_constrained_with_progress(
    problem: &DevelopabilityProblem<'_>,
    options: &ConstrainedOptions,
    progress: &mut dyn FnMut(usize, f64),
) -> Result<(Vec<nalgebra::Vector3<f64>>, RestorationInfo), FfdError> {
    let start = Instant::now();
    let mut y = problem.gather(&problem.start);
    let mut e = problem.evaluate(&y);
    let mut info = RestorationInfo::begin(crate::SolverMethod::Constrained, problem, &e);
    progress(0, max_abs(&e.defects));
    if problem.variables.is_empty() || max_abs(&e.defects) <= options.tolerance {
        info.finish(problem, &e, 0, true, start);
        return Ok((e.parameters, info));
    }
    // The bending term of the metric and its weight γ, when on.
    let mut bending = (options.bending_weight > 0.0).then(|| (BendingMetric::new(problem), options.bending_weight));
    let mut system = kkt_system_at(
        problem,
        &e,
        &Metric::new(problem, options, bending.as_ref()),
        options.step_unknowns,
    )?;
    let kkt = &system.kkt;
    tracing::debug!(
        "set-up {:.2} ms (evaluation, pattern, ordering, symbolic analysis): KKT {} + {} rows, {} entries assembled, {} values in L ({})",
        start.elapsed().as_secs_f64() * 1e3,
        kkt.n,
        kkt.nc,
        kkt.values.len(),
        kkt.factor_size(),
        match kkt.compared_factor_sizes {
            Some((amd, dissected)) => format!("{}; AMD {amd}, nested dissection {dissected}", kkt.ordering),
            None => kkt.ordering.to_string(),
        }
    );
    // Consecutive steps cut to `α ≤ STALL_STEP` (see `ConstrainedOptions::stall_bending_weight`).
    let mut stalled = 0;
    let mut iterations = 0;
    // The largest defect of every iterate so far, for the non-monotone test.
    let mut largest_defects = vec![max_abs(&e.defects)];
    let memory = options.line_search_memory.max(1);
    // Phase 1: restoration.
    while iterations < options.max_iterations && max_abs(&e.defects) > options.tolerance {
        problem.check_cancelled()?;
        if stalled >= STALL_ITERATIONS {
            if bending.is_some() || options.stall_bending_weight <= 0.0 {
                // Nothing left to switch on: stop instead of crawling to `max_iterations`.
                tracing::debug!("stalled: stopping after {iterations} iterations");
                break;
            }
            bending = Some((BendingMetric::new(problem), options.stall_bending_weight));
            system = kkt_system_at(
                problem,
                &e,
                &Metric::new(problem, options, bending.as_ref()),
                options.step_unknowns,
            )?;
            info.bending_fallback_iteration = Some(iterations);
            stalled = 0;
            tracing::debug!(
                "stalled: bending term switched on (weight {})",
                options.stall_bending_weight
            );
        }
        iterations += 1;
        let clock = Instant::now();
        let (_, assembled) = factorise(
            &mut system,
            problem,
            &e,
            &Metric::new(problem, options, bending.as_ref()),
        )?;
        let factorised = clock.elapsed();
        let step = system.projection(&e.defects, options.tolerance);
        let solved = clock.elapsed();
        let reference = largest_defects
            .iter()
            .rev()
            .take(memory)
            .fold(0.0, |m: f64, d| m.max(*d));
        let mut alpha = 1.0;
        let mut accepted = None;
        // The full step is evaluated in full (with the default metric it is nearly always
        // taken); shorter trials compare defects only, and the accepted one is then
        // evaluated in full once.
        for trial_index in 0..30 {
            let trial_y: Vec<f64> = y.iter().zip(&step).map(|(a, p)| a + alpha * p).collect();
            let full = (trial_index == 0).then(|| problem.evaluate(&trial_y));
            let defects = match &full {
                Some(trial) => max_abs(&trial.defects),
                None => max_abs(&problem.evaluate_defects(&trial_y)),
            };
            if defects < reference {
                let trial = full.unwrap_or_else(|| problem.evaluate(&trial_y));
                accepted = Some((trial_y, trial));
                break;
            }
            alpha *= 0.5;
        }
        let Some((new_y, new_e)) = accepted else {
            break;
        };
        stalled = if alpha <= STALL_STEP { stalled + 1 } else { 0 };
        {
            let ms = |d: std::time::Duration| d.as_secs_f64() * 1e3;
            tracing::debug!(
                "restore {iterations}: alpha {alpha} max defect {:.3e} (assemble {:.2} ms, factorise {:.2} ms; solve {:.2} ms, {} triangular solves, backward error {:.1e}; line search {:.2} ms)",
                max_abs(&new_e.defects),
                ms(assembled),
                ms(factorised - assembled),
                ms(solved - factorised),
                system.kkt.last_solve.0,
                system.kkt.last_solve.1,
                ms(clock.elapsed() - solved)
            );
        }
        y = new_y;
        e = new_e;
        // Chord steps (see `restore_constrained`): projections with this factorisation
        // at the new defects, after a full step, while each is at most half as long as
        // the step before it and at least halves the largest defect.
        let mut defects = e.defects.clone();
        let mut chords = 0;
        let mut last_length = alpha * norm(&step);
        while alpha == 1.0 && chords < options.chord_steps && max_abs(&defects) > options.tolerance {
            let clock = Instant::now();
            let chord = system.projection(&defects, options.tolerance);
            let length = norm(&chord);
            if !contracts(length, last_length) {
                break;
            }
            let trial_y: Vec<f64> = y.iter().zip(&chord).map(|(a, p)| a + p).collect();
            let trial = problem.evaluate_defects(&trial_y);
            tracing::debug!(
                "chord: max defect {:.3e} -> {:.3e} ({:.2} ms)",
                max_abs(&defects),
                max_abs(&trial),
                clock.elapsed().as_secs_f64() * 1e3
            );
            if !contracts(max_abs(&trial), max_abs(&defects)) {
                break;
            }
            last_length = length;
            y = trial_y;
            defects = trial;
            chords += 1;
        }
        if chords > 0 {
            e = problem.evaluate(&y);
            info.chord_steps += chords;
        }
        largest_defects.push(max_abs(&e.defects));
        progress(iterations, max_abs(&e.defects));
    }
    let converged = max_abs(&e.defects) <= options.tolerance;
    info.bending_weight = bending.as_ref().map_or(0.0, |(_, weight)| *weight);
    let metric = Metric::new(problem, options, bending.as_ref());
    // Phase 2: refinement of the objective on the constraint surface.
    let mut f = problem.restoration_objective(&e, options.position_weight);
    let mut last_alpha: f64 = 1.0;
    let mut refinements = 0;
    while converged && iterations < options.max_iterations && refinements < options.refine_iterations {
        problem.check_cancelled()?;
        refinements += 1;
        iterations += 1;
        let (gradient, _) = factorise(&mut system, problem, &e, &metric)?;
        let step = system.descent(&gradient);
        let mut alpha = (2.0 * last_alpha).min(1.0);
        let mut accepted = None;
        'halving: for _ in 0..12 {
            let mut trial_y: Vec<f64> = y.iter().zip(&step).map(|(a, p)| a + alpha * p).collect();
            let mut trial = problem.evaluate(&trial_y);
            // Back onto g = 0 with the same factorisation.
            for _ in 0..10 {
                if max_abs(&trial.defects) <= options.tolerance || max_abs(&trial.defects) > 1e-2 {
                    break;
                }
                let correction = system.projection(&trial.defects, options.tolerance);
                for (a, c) in trial_y.iter_mut().zip(&correction) {
                    *a += c;
                }
                trial = problem.evaluate(&trial_y);
            }
            let trial_f = problem.restoration_objective(&trial, options.position_weight);
            if max_abs(&trial.defects) <= options.tolerance && trial_f < f {
                accepted = Some((trial_y, trial, trial_f));
                break 'halving;
            }
            alpha *= 0.5;
        }
        let Some((new_y, new_e, new_f)) = accepted else {
            break;
        };
        last_alpha = alpha;
        let change = (f - new_f) / f.max(1e-300);
        tracing::debug!(
            "refine {iterations}: alpha {alpha} f {new_f:.4e} max defect {:.3e}",
            max_abs(&new_e.defects)
        );
        y = new_y;
        e = new_e;
        f = new_f;
        progress(iterations, max_abs(&e.defects));
        if change < options.objective_tolerance {
            break;
        }
    }
    info.finish(problem, &e, iterations, converged, start);
    Ok((e.parameters, info))
}

/// Whether `after` is at most [`CHORD_CONTRACTION`] of `before` (false for NaN).
fn contracts(after: f64, before: f64) -> bool {
    after <= CHORD_CONTRACTION * before
}

fn norm(values: &[f64]) -> f64 {
    values.iter().map(|v| v * v).sum::<f64>().sqrt()
}

fn max_abs(values: &[f64]) -> f64 {
    values.iter().fold(0.0, |m, v| m.max(v.abs()))
}

/// The weights of the metric `H`: springs and proximity (the objective's Gauss–Newton
/// matrix), and the optional bending term with its weight `γ A/l̄²`.
struct Metric<'a> {
    springs: f64,
    proximity: f64,
    bending: Option<(&'a BendingMetric, f64)>,
}

impl<'a> Metric<'a> {
    /// Springs `1/l̄²`, proximity `β/l̄²` and, when given (with its `γ`), the bending term
    /// with weight `γ A/l̄²` (`A/l̄²`: [`BendingMetric::resolution`]; the term's sum of
    /// squared angle changes is dimensionless).
    fn new(
        problem: &DevelopabilityProblem<'_>,
        options: &ConstrainedOptions,
        bending: Option<&'a (BendingMetric, f64)>,
    ) -> Self {
        let w = 1.0 / (problem.length_scale * problem.length_scale);
        Self {
            springs: w,
            proximity: options.position_weight * w,
            bending: bending.map(|(b, weight)| (b, weight * b.resolution)),
        }
    }
}

/// Where entry `(k, l)`, `k ≤ l`, of a symmetric 3×3 block is kept in six numbers.
const DIAGONAL_SLOT: [[usize; 3]; 3] = [[0, 1, 2], [1, 3, 4], [2, 4, 5]];

/// Produces the upper triangle of the KKT matrix, entry by entry, as
/// `entry(row, column, value)` with `row ≤ column`, always in the same order for the same
/// problem and metric (duplicates are summed by the receiver), and returns `δ` and the
/// objective's gradient.
fn assemble(
    problem: &DevelopabilityProblem<'_>,
    e: &Evaluation,
    metric: &Metric<'_>,
    mut entry: impl FnMut(usize, usize, f64),
) -> (f64, Vec<f64>) {
    let (w, beta) = (metric.springs, metric.proximity);
    let n = problem.unknown_count();
    let nc = problem.constraint_count();
    let mut gradient = vec![0.0; n];
    // Each variable's 3×3 diagonal block of the metric (upper triangle, `(k, l)` at
    // `DIAGONAL_SLOT[k][l]`), summed over springs, proximity and bending before it is
    // pushed once with `μ`: every node's block gets contributions from each of its
    // springs and hinges, and pushing them one by one doubled the entries the pattern
    // and every factorisation had to sum.
    let mut diagonal = vec![[0.0f64; 6]; n / 3];
    let mut push_entry = |row: usize, col: usize, value: f64| {
        let (r, c) = if row <= col { (row, col) } else { (col, row) };
        entry(r, c, value);
    };
    let mut push = |row: usize, col: usize, value: f64| {
        if row < n && col < n && row / 3 == col / 3 {
            let (k, l) = (row % 3, col % 3);
            diagonal[row / 3][DIAGONAL_SLOT[k.min(l)][k.max(l)]] += value;
        } else {
            push_entry(row, col, value);
        }
    };
    // Springs: JᵀJ blocks and Jᵀr.
    for s in 0..problem.springs.len() {
        let parts = problem.spring_gradient(e, s);
        let r = e.spring_residuals[s];
        for (a, (va, ga)) in parts.iter().enumerate() {
            if *va == u32::MAX {
                continue;
            }
            for k in 0..3 {
                gradient[3 * *va as usize + k] += w * r * ga[k];
            }
            for (vb, gb) in parts.iter().skip(a) {
                if *vb == u32::MAX {
                    continue;
                }
                for k in 0..3 {
                    for l in 0..3 {
                        let (row, col) = (3 * *va as usize + k, 3 * *vb as usize + l);
                        if va == vb && l < k {
                            continue;
                        }
                        push(row, col, w * ga[k] * gb[l]);
                    }
                }
            }
        }
    }
    // Proximity term and damping: β JᵀJ per node, μ on the diagonal.
    for (v, &m) in problem.variables.iter().enumerate() {
        let j = &e.jacobians[v];
        let jtj = j.tr_mul(j) * beta;
        let d = e.positions[m as usize] - problem.target[m as usize];
        let g = j.tr_mul(&d) * beta;
        for k in 0..3 {
            gradient[3 * v + k] += g[k];
            for l in k..3 {
                push(3 * v + k, 3 * v + l, jtj[(k, l)]);
            }
        }
    }
    if let Some((bending, weight)) = metric.bending {
        bending.push_upper(e, weight, &mut push);
    }
    let diagonal_sum: f64 = diagonal.iter().map(|b| b[0] + b[3] + b[5]).sum();
    let mean_diagonal = (diagonal_sum / n.max(1) as f64).max(1e-300);
    let mu = 1e-9 * mean_diagonal;
    for (v, block) in diagonal.iter().enumerate() {
        for k in 0..3 {
            for l in k..3 {
                let value = block[DIAGONAL_SLOT[k][l]] + if k == l { mu } else { 0.0 };
                push_entry(3 * v + k, 3 * v + l, value);
            }
        }
    }
    // Constraint rows A (as the upper-right block Aᵀ) and the −δ block.
    let mut row = Vec::new();
    let mut a_norm = 0.0;
    for c in 0..nc {
        problem.defect_gradient(e, c, &mut row);
        for (v, d) in &row {
            for k in 0..3 {
                a_norm += d[k] * d[k];
                push_entry(3 * *v as usize + k, n + c, d[k]);
            }
        }
    }
    let delta = 1e-10 * (a_norm / nc.max(1) as f64) / mean_diagonal;
    for c in 0..nc {
        push_entry(n + c, n + c, -delta);
    }
    (delta.max(1e-300), gradient)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::procedural_panels::ProceduralModel;
    use crate::{apply_edits, embed_points, FfdScene, PanelAssembly, ProblemOptions};

    /// A singular restoration names the vertex and the cause in words: a lattice squashed
    /// flat where the panels are, a node mapped to NaN, a collapsed edge.
    #[test]
    fn a_degenerate_restoration_names_the_vertex_and_the_cause() {
        let mesh = ProceduralModel::TwoPanels { columns: 5, rows: 4 }.build();
        let assembly = PanelAssembly::from_mesh(&mesh).unwrap();
        let scene = FfdScene::from_json(
            r#"{"model": {"procedural": {"kind": "two_panels"}}, "lattice": {"counts": [4, 4, 4]},
                "deformations": [{"edits": [
                   {"move": {"points": [[1, 2, 1], [2, 1, 2]], "by": [30, -20, 15]}},
                   {"transform": {"points": {}, "scale": [1e-20, 1, 1]}}]}]}"#,
        )
        .unwrap();
        let nodes = assembly.node_positions();
        let lattice = scene.lattice(&nodes).unwrap();
        let x = embed_points(&lattice, &nodes).unwrap();
        let volume = apply_edits(&lattice, &scene.deformations[0].edits, "edits").unwrap();
        let problem = DevelopabilityProblem::new(&volume, &assembly, x, &ProblemOptions::default());
        let mut e = problem.evaluate(&problem.gather(&problem.start));
        let message = degenerate(&problem, &e).to_string();
        assert!(
            message.contains("flat or folded") && message.contains("vertex "),
            "{message}"
        );
        assert!(!message.contains("{") && !message.contains("Pivot"), "{message}");
        e.jacobians[0][(0, 0)] = f64::NAN;
        assert!(degenerate(&problem, &e).to_string().contains("non-finite"));
    }
}

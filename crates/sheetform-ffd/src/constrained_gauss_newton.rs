//! The default solver: constrained Gauss–Newton (SQP) on the embedded parameters.

use crate::bending_metric::BendingMetric;
use crate::kkt_system::KktSystem;
use crate::{DevelopabilityProblem, Evaluation, FfdError, RestorationInfo};
use faer::sparse::Pair;
use std::time::Instant;

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
    /// Most iterations.
    pub max_iterations: usize,
    /// Memory `M` of the restoration's non-monotone line search: a trial step is accepted
    /// when its largest defect is below the largest of the last `M` iterates' (1: below
    /// the current one, a monotone search). 12 (default): skirt 27 iterations instead
    /// of 38 and trousers 25 instead of 32, with the same edge-length change and
    /// deviation within 4 %; docs/benchmarks.md has the figures.
    pub line_search_memory: usize,
    /// Most refinement iterations after the defects are within tolerance (0: restore
    /// only).
    pub refine_iterations: usize,
    /// Refinement stops when the objective falls by less than this fraction in one step.
    pub objective_tolerance: f64,
    /// Weight `γ` of the bending term `½ γ Σ_v (n_vᵀ Σ_{u∈N(v)} (δq_u − δq_v))² / l̄²`
    /// added to the metric of the steps (not to the objective); 0 (default): off. With
    /// `γ = 0.1` the skirt and the trousers are restored in 7 and 9 full steps instead
    /// of 38 and 32 mostly cut ones (several times faster; the duct and the two panels,
    /// which already took full steps, get slower), but the projection then reaches
    /// shapes whose edge lengths change about twice as much (skirt: 9.1 % instead of
    /// 3.6 %); docs/benchmarks.md has the tables. A quick preview while editing, not the
    /// final pattern.
    pub bending_weight: f64,
}

impl Default for ConstrainedOptions {
    fn default() -> Self {
        Self {
            tolerance: 1e-10,
            position_weight: 0.01,
            max_iterations: 60,
            line_search_memory: 12,
            objective_tolerance: 1e-3,
            refine_iterations: 0,
            bending_weight: 0.0,
        }
    }
}

/// Assembles `[H Aᵀ; A −δI]` at `e` into `kkt` and factorises it; returns the
/// objective's gradient.
fn factorise(
    kkt: &mut KktSystem,
    problem: &DevelopabilityProblem<'_>,
    e: &Evaluation,
    metric: &Metric<'_>,
) -> Result<Vec<f64>, FfdError> {
    let (delta, gradient) = assemble(problem, e, metric, None, &mut kkt.values);
    kkt.factorise(delta)?;
    Ok(gradient)
}

/// Restores developability in two phases, both on the Gauss–Newton model
/// `H = JᵀJ + μI` of
///
/// `f(X) = ½ Σ_j (|q_s − q_e| − l⁰_j)² / l̄² + ½ β Σ_n |q_n − q′_n|² / l̄²`
///
/// (`q_n = Q′(X_n)`, springs of Eq. 2-2 plus a small proximity term) with the exact
/// Jacobian `A` of the defects `g(q_i(X))` (chain rule through `∂Q/∂(u,v,w)`,
/// [`DevelopabilityProblem::defect_gradient`]):
///
/// 1. **Restoration** (Gauss–Newton projection onto `g = 0`): `p` of least `H`-norm with
///    `A p = −g`, i.e. `[H Aᵀ; A −δI] [p; λ] = [0; −g]`, halved until the largest defect
///    falls below the largest of the last `line_search_memory` iterates' (a non-monotone
///    test in the manner of Grippo, Lampariello & Lucidi, SIAM J. Numer. Anal. 23(4),
///    1986; the reference value never increases, so the largest defect still falls
///    over every `M` iterations). A sum-of-defects test accepted longer steps and
///    converged in fewer iterations, but left edges changed by up to 37 % on the
///    trousers instead of 10 %; the largest defect keeps the path close to the
///    continuous Newton flow. Converges quadratically once close; ends when every
///    `|g| ≤ tolerance`.
/// 2. **Refinement** (optional, `refine_iterations`, default 0; SQP with a Gauss–Newton
///    Hessian): `[H Aᵀ; A −δI] [p; λ] =
///    [−∇f; 0]` moves along the constraint surface to lower `f`, followed by projection
///    steps back onto `g = 0`; a step is kept only if `f` decreased and every defect is
///    still within tolerance. Stops when `f` changes by less than `objective_tolerance`.
///
/// With `bending_weight` `γ > 0` the metric of both phases is `H + B`, `B` the
/// Gauss–Newton matrix of a bending term on the step's normal displacements (see
/// `BendingMetric` in `bending_metric.rs`): the objective and the constraints are
/// unchanged, the steps are not cut and far fewer are needed, but they reach a
/// developable shape with larger edge-length changes.
///
/// The linear systems are solved by a sparse LDLᵀ factorisation (faer; ordering, AMD
/// or nested dissection, whichever fills less (see `KktSystem::new`), and symbolic
/// analysis once per problem, numeric factorisation per iteration). The tiny
/// `μ = 1e-9·mean diag H` and `δ` make the matrix quasi-definite; two steps of iterative
/// refinement against the system without `δ` remove its effect.
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
    let start = Instant::now();
    let mut y = problem.gather(&problem.start);
    let mut e = problem.evaluate(&y);
    let mut info = RestorationInfo::begin("constrained", problem, &e);
    if problem.variables.is_empty() || max_abs(&e.defects) <= options.tolerance {
        info.finish(problem, &e, 0, true, start);
        return Ok((e.parameters, info));
    }
    let w = 1.0 / (problem.length_scale * problem.length_scale);
    let bending = (options.bending_weight > 0.0).then(|| BendingMetric::new(problem));
    let metric = Metric {
        springs: w,
        proximity: options.position_weight * w,
        bending: bending.as_ref().map(|b| (b, options.bending_weight * w)),
    };
    let mut pairs = Vec::new();
    let mut values = Vec::new();
    assemble(problem, &e, &metric, Some(&mut pairs), &mut values);
    // Where each unknown lives, for the nested-dissection ordering: a parameter triple at
    // its node, a defect at its vertex's node.
    let coordinates: Vec<nalgebra::Vector3<f64>> = problem
        .variables
        .iter()
        .flat_map(|&m| [e.positions[m as usize]; 3])
        .chain(problem.constraint_nodes.iter().map(|&m| e.positions[m as usize]))
        .collect();
    let mut kkt = KktSystem::new(problem.unknown_count(), problem.constraint_count(), pairs, &coordinates)?;
    let trace = std::env::var_os("SHEETFORM_TRACE").is_some();
    if trace {
        eprintln!(
            "set-up {:.2} ms (evaluation, pattern, ordering, symbolic analysis): KKT {} + {} rows, {} values in L ({})",
            start.elapsed().as_secs_f64() * 1e3,
            kkt.n,
            kkt.nc,
            kkt.factor_size(),
            kkt.ordering
        );
    }
    let mut iterations = 0;
    // The largest defect of every iterate so far, for the non-monotone test.
    let mut largest_defects = vec![max_abs(&e.defects)];
    let memory = options.line_search_memory.max(1);
    // Phase 1: restoration.
    while iterations < options.max_iterations && max_abs(&e.defects) > options.tolerance {
        iterations += 1;
        let clock = Instant::now();
        factorise(&mut kkt, problem, &e, &metric)?;
        let factorised = clock.elapsed();
        let step = kkt.projection(&e.defects);
        let solved = clock.elapsed();
        let reference = largest_defects
            .iter()
            .rev()
            .take(memory)
            .fold(0.0, |m: f64, d| m.max(*d));
        let mut alpha = 1.0;
        let mut accepted = None;
        // Trials compare defects only; the accepted point is evaluated in full once.
        for _ in 0..30 {
            let trial_y: Vec<f64> = y.iter().zip(&step).map(|(a, p)| a + alpha * p).collect();
            if max_abs(&problem.evaluate_defects(&trial_y)) < reference {
                let trial = problem.evaluate(&trial_y);
                accepted = Some((trial_y, trial));
                break;
            }
            alpha *= 0.5;
        }
        let Some((new_y, new_e)) = accepted else {
            break;
        };
        if trace {
            let ms = |d: std::time::Duration| d.as_secs_f64() * 1e3;
            eprintln!(
                "restore {iterations}: alpha {alpha} max defect {:.3e} (assemble + factorise {:.2} ms, solve {:.2} ms, line search {:.2} ms)",
                max_abs(&new_e.defects),
                ms(factorised),
                ms(solved - factorised),
                ms(clock.elapsed() - solved)
            );
        }
        y = new_y;
        e = new_e;
        largest_defects.push(max_abs(&e.defects));
    }
    let converged = max_abs(&e.defects) <= options.tolerance;
    // Phase 2: refinement of the objective on the constraint surface.
    let mut f = problem.restoration_objective(&e, options.position_weight);
    let mut last_alpha: f64 = 1.0;
    let mut refinements = 0;
    while converged && iterations < options.max_iterations && refinements < options.refine_iterations {
        refinements += 1;
        iterations += 1;
        let gradient = factorise(&mut kkt, problem, &e, &metric)?;
        let mut rhs: Vec<f64> = gradient
            .iter()
            .map(|g| -g)
            .chain(std::iter::repeat_n(0.0, kkt.nc))
            .collect();
        kkt.solve(&mut rhs);
        let step = rhs[..kkt.n].to_vec();
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
                let correction = kkt.projection(&trial.defects);
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
        if trace {
            eprintln!(
                "refine {iterations}: alpha {alpha} f {new_f:.4e} max defect {:.3e}",
                max_abs(&new_e.defects)
            );
        }
        y = new_y;
        e = new_e;
        f = new_f;
        if change < options.objective_tolerance {
            break;
        }
    }
    info.finish(problem, &e, iterations, converged, start);
    Ok((e.parameters, info))
}

fn max_abs(values: &[f64]) -> f64 {
    values.iter().fold(0.0, |m, v| m.max(v.abs()))
}

/// The weights of the metric `H`: springs and proximity (the objective's Gauss–Newton
/// matrix), and the optional bending term with its weight `γ/l̄²`.
struct Metric<'a> {
    springs: f64,
    proximity: f64,
    bending: Option<(&'a BendingMetric, f64)>,
}

/// Fills the upper triangle of the KKT matrix (values in a fixed order; the index pairs
/// too when `pairs` is given) and returns `δ` and the objective's gradient.
fn assemble(
    problem: &DevelopabilityProblem<'_>,
    e: &Evaluation,
    metric: &Metric<'_>,
    mut pairs: Option<&mut Vec<Pair<usize, usize>>>,
    values: &mut Vec<f64>,
) -> (f64, Vec<f64>) {
    let (w, beta) = (metric.springs, metric.proximity);
    let n = problem.unknown_count();
    let nc = problem.constraint_count();
    values.clear();
    let mut gradient = vec![0.0; n];
    let mut push = |row: usize, col: usize, value: f64, values: &mut Vec<f64>| {
        let (r, c) = if row <= col { (row, col) } else { (col, row) };
        if let Some(p) = pairs.as_deref_mut() {
            p.push(Pair { row: r, col: c });
        }
        values.push(value);
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
                        push(row, col, w * ga[k] * gb[l], values);
                    }
                }
            }
        }
    }
    // Proximity term and damping: β JᵀJ per node, μ on the diagonal.
    let mut diagonal_sum = 0.0;
    for (v, &m) in problem.variables.iter().enumerate() {
        let j = &e.jacobians[v];
        let jtj = j.tr_mul(j) * beta;
        let d = e.positions[m as usize] - problem.target[m as usize];
        let g = j.tr_mul(&d) * beta;
        for k in 0..3 {
            gradient[3 * v + k] += g[k];
            diagonal_sum += jtj[(k, k)];
            for l in k..3 {
                push(3 * v + k, 3 * v + l, jtj[(k, l)], values);
            }
        }
    }
    if let Some((bending, weight)) = metric.bending {
        bending.push_upper(e, weight, |row, col, value| push(row, col, value, values));
    }
    let mean_diagonal = (diagonal_sum / n.max(1) as f64).max(1e-300);
    let mu = 1e-9 * mean_diagonal;
    for i in 0..n {
        push(i, i, mu, values);
    }
    // Constraint rows A (as the upper-right block Aᵀ) and the −δ block.
    let mut row = Vec::new();
    let mut a_norm = 0.0;
    for c in 0..nc {
        problem.defect_gradient(e, c, &mut row);
        for (v, d) in &row {
            for k in 0..3 {
                a_norm += d[k] * d[k];
                push(3 * *v as usize + k, n + c, d[k], values);
            }
        }
    }
    let delta = 1e-10 * (a_norm / nc.max(1) as f64) / mean_diagonal;
    for c in 0..nc {
        push(n + c, n + c, -delta, values);
    }
    (delta.max(1e-300), gradient)
}

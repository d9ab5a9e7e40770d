//! The developability error of §8.2 and a refinement, beyond the paper, that removes it.
//!
//! **Metric** (§8.2, Table 1): for a ruling from `p_a` (on one curve, tangent `T_a`) to
//! `p_b` (tangent `T_b`), `d = p_b − p_a`, the surface normals at its ends are
//! `n_a = T_a × d` and `n_b = T_b × d`; the error is the angle between them (as lines,
//! radians). The surface is developable along the ruling iff it vanishes, i.e. iff
//! `det(T_a, T_b, d) = 0` (Eq. 1: `A, B, A + Ȧ, B + Ḃ` coplanar), because
//! `n_a × n_b = det(T_a, T_b, d) d`.
//!
//! **Refinement**: the linear energy only *encourages* planar quads between rulings, and
//! leaves 6–16° of error on real drawings (Table 1). Here the 3D control points `q` and
//! the parameters `t_r` of the rulings' far (`b`) ends solve
//!
//! `min ½|A q − b|² + ½ μ |q − q_lin|² + ½ w Σ_r |B'(t_r⁰)|² (t_r − t_r⁰)²`
//! subject to `g_r(q, t_r) = 0` for every ruling `r`,
//!
//! with `A q − b` the weighted rows of the linear energy (so the annotations, symmetry and
//! C¹ joins still pull as before), `q_lin` its solution, `μ` = the projection weight (1)
//! and `g_r = det(T_a, T̂_b, d) |d| / (|T_a × d| |T̂_b × d|)` with the denominator frozen
//! at the start (then `g_r ≈ sin` of the error angle). Letting each ruling's end slide
//! along its curve (`w = 0.1` per square pixel of slide, so sliding is ten times
//! cheaper than moving the curves) is what makes the problem well posed: with the ends
//! pinned at the samples the warping chose, the hand-traced cup needed 60-pixel moves of
//! the curves to make its 35 rulings exact, and never got there. An end slides along its
//! whole chain (perspective drawings need slides across several segments), within one
//! half-edge per step and on to the next between steps; the tangent is normalised
//! (`T̂_b`) so that `g` stays continuous where the curve is C¹, and the C¹ rows weigh
//! `C1_EMPHASIS`² more than in the linear energy so that it nearly is. The silhouettes
//! (ends at the chain's ends) do not slide. `∂g/∂u_r = det(T_a, (I − T̂T̂ᵀ)B''/|B'|, d)`
//! (the end moves along `T_b`, which leaves `det` unchanged). The objective is quadratic with
//! a constant sparse Hessian `H = AᵀA + μI`, factorised once (faer); each iteration is a
//! Gauss–Newton SQP step `[H Cᵀ; C 0][δ; λ] = [−∇f; −g]` solved through the Schur
//! complement `C H⁻¹ Cᵀ + diag(c_t²/w)` (dense, one row per ruling and companion), with a backtracking
//! search on `max |g|` and the parameters clamped to their segment. Gauss–Newton leaves
//! out the constraints' curvature (`Σ λ_r ∇²g_r`), so near a curved `g` it crawls (a noisy
//! drawing: `max |g|` falling by a quarter per step, 1e-4 after 50 steps); once `max |g|`
//! is below [`PROJECTION_START`], after the first step that does not halve it, every step
//! is a projection, the same system with `∇f` and the slides' pull `w (t − t0)` left out
//! (the least change in the metric `H` that the linearised constraints ask for: Newton
//! on `g = 0`, quadratic; 1e-13 in four steps there). An end that hops back to the
//! half-edge it left has its root in the tangent's turn at their join: it stays at the
//! join (its slide is fixed), and a companion constraint (the same ruling, the tangent
//! on the join's other side) makes the curves turn both tangents into the ruling's
//! plane. It stops at `max |g| ≤ 1e-12`, when no step reduces `max |g|`, after 50
//! iterations, or before an iteration would pass [`MAX_REFINEMENT_WORK`] (an iteration is
//! cubic in the rulings), and reports convergence when `max |g| ≤` [`REFINEMENT_BOUND`]
//! and the sine of every enforced ruling's error angle is within it too (so that what
//! the report then measures on the rulings holds; a companion's tangent counts). Rulings
//! whose tangent is parallel to the ruling (a cone's apex) carry no constraint. The moved ends become
//! curve samples ([`crate::move_ruling_ends`]), so the mesh's rulings are the refined
//! ones.
//!
//! **Symmetry**: after the symmetrisation (§7) the model is `q = P z + o` with `P` the
//! [`MirrorMap`] (mirrored points follow their sources). The SQP then works in `z`:
//! `H_z = Pᵀ H P` (+ `μ` on columns nothing depends on), gradient `Pᵀ ∇f`, constraint
//! rows `C P`, and the step `δq = P δz` keeps the model exactly symmetric. Without
//! symmetrisation `P` is the identity.

use crate::curve_lifting::Energy;
use crate::curve_network::CurveNetwork;
use crate::curve_samples::CurvePoint;
use crate::patch_cycles::HalfEdge;
use crate::ruling_propagation::RuledStrip;
use crate::symmetrization::MirrorMap;
use crate::{cubic, PhotoError};
use faer::prelude::Solve;
use faer::sparse::Triplet;
use faer::{Col, Mat};
use nalgebra::Vector3;
use sheetform_solve::SparseCholesky;

type Vec3 = Vector3<f64>;

/// The refinement's bound on `max |g|` (≈ the sine of the largest error angle): 1e-7 rad,
/// 6e-6°, far below any fabrication tolerance (a 1 m ruling then bends 0.1 µm). The
/// iteration goes on towards 1e-12 while it makes progress.
pub const REFINEMENT_BOUND: f64 = 1e-7;

/// Most values of the refinement's dense matrices (`n m + m²` for `n` unknowns and `m`
/// constraints: rulings and their companions).
pub const MAX_DENSE_VALUES: usize = 50_000_000;

/// The violation `max |g|` (≈ radians) below which a step that does not halve it turns
/// the iterations into projections. Farther out a projection, blind to the objective, can
/// reach the constraints by turning a curve's tangent along its rulings (`det = 0` with
/// the planes undefined): 39-pixel moves on the noisy composite at 3-pixel rulings.
const PROJECTION_START: f64 = 1e-2;

/// Most SQP iterations of one refinement.
const ITERATIONS: usize = 50;

/// Fewest iterations the work bound must allow before the refinement starts (it
/// usually converges in one to five).
const BUDGETED_ITERATIONS: usize = 5;

/// Most work of one refinement, in units of its dense linear algebra: an iteration with
/// `m` rulings and `n` unknowns costs [`refinement_iteration_work`]`(n, m) =
/// m³ + 2 000 m² + 1 500 n m` (the LU of the `m × m` Schur complement, forming it, and
/// the `m` solves through the sparse factor; about 0.02 ns a unit on the development
/// machine, measured: 0.5 s an iteration at 2 100 rulings on 1 920 control points, 10 s
/// estimated at the 7 000 that [`MAX_DENSE_VALUES`] lets through, 17 minutes for 50
/// iterations twice). 7.5e11 is about 15 s; the reconstruction refines at most twice
/// (with and without the mirror constraint). The iterations stop before one would pass
/// the bound ([`RefinementInfo::work_bound_reached`]; the report says whether the model
/// met [`REFINEMENT_BOUND`]), and a refinement the bound does not allow 5 iterations is
/// refused: about 4 700 rulings on 100 control points, 4 200 on 2 000. A traced photo
/// has tens to hundreds.
pub const MAX_REFINEMENT_WORK: f64 = 7.5e11;

/// The work of one refinement iteration with `n` unknowns and `m` rulings, in the units
/// of [`MAX_REFINEMENT_WORK`].
pub fn refinement_iteration_work(n: usize, m: usize) -> f64 {
    let (n, m) = (n as f64, m as f64);
    m * m * m + 2_000.0 * m * m + 1_500.0 * n * m
}

/// Point of the 3D network (unknown vector `x`) at a place.
fn point3(network: &CurveNetwork, x: &[f64], place: CurvePoint) -> Vec3 {
    crate::curve_lifting::combine3(network, x, place.segment, cubic::bernstein(place.t))
}

/// Tangent `dB/dt` of the 3D network at a place.
fn tangent3(network: &CurveNetwork, x: &[f64], place: CurvePoint) -> Vec3 {
    crate::curve_lifting::combine3(network, x, place.segment, cubic::bernstein_derivative(place.t))
}

/// The paper's developability error of every ruling (radians), strip by strip.
pub fn ruling_errors(network: &CurveNetwork, x: &[f64], strips: &[RuledStrip]) -> Vec<f64> {
    let mut out = Vec::new();
    for strip in strips {
        for i in 0..strip.rulings.len() {
            let [a, b] = strip.ends(i);
            let d = point3(network, x, b) - point3(network, x, a);
            let na = tangent3(network, x, a).cross(&d);
            let nb = tangent3(network, x, b).cross(&d);
            let denominator = na.norm() * nb.norm();
            if denominator < 1e-300 {
                continue;
            }
            out.push((na.dot(&nb).abs() / denominator).min(1.0).acos());
        }
    }
    out
}

/// What the refinement did.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RefinementInfo {
    /// SQP iterations.
    pub iterations: usize,
    /// Constraints (rulings) enforced.
    pub constraint_count: usize,
    /// `max |g|` at the end (≈ sine of the largest error angle).
    pub constraint_violation: f64,
    /// Whether `max |g| ≤ REFINEMENT_BOUND` was reached, and the sine of every enforced
    /// ruling's error angle is within it too.
    pub converged: bool,
    /// Largest change of a control point (pixels).
    pub displacement_max: f64,
    /// Largest slide of a ruling's end along its curve, in the image (pixels).
    pub slide_max_px: f64,
    /// The iterations stopped at [`MAX_REFINEMENT_WORK`] (`converged` still says whether
    /// the bound was met).
    pub work_bound_reached: bool,
}

struct Constraint {
    a: CurvePoint,
    /// The chain of half-edges the `b` end slides along (its strip's side b).
    chain: Vec<HalfEdge>,
    scale: f64,
    /// Where it came from: strip and ruling.
    origin: (usize, usize),
    /// The `b` end may slide (not at the chain's ends: silhouettes stay).
    slides: bool,
    /// Image speed `|dB/du|` at the start (pixels per unit of chain coordinate).
    speed: f64,
}

/// The place at chain coordinate `u` on half-edge `half` (traversal parameter
/// `u − half`, clamped to it) and `dt/du` (±1).
fn chain_place(chain: &[HalfEdge], u: f64, half: usize) -> (CurvePoint, f64) {
    let k = half.min(chain.len() - 1);
    let s = (u - k as f64).clamp(0.0, 1.0);
    let h = chain[k];
    (
        CurvePoint {
            segment: h.segment,
            t: h.segment_parameter(s),
        },
        if h.reversed { -1.0 } else { 1.0 },
    )
}

/// The chain coordinate of a place on the chain.
fn chain_coordinate(chain: &[HalfEdge], place: CurvePoint) -> Option<f64> {
    chain
        .iter()
        .position(|h| h.segment == place.segment)
        .map(|k| k as f64 + if chain[k].reversed { 1.0 - place.t } else { place.t })
}

/// Constraint values, their sparse gradients in `x` and their derivatives in `t_b`.
type ConstraintValues = (Vec<f64>, Vec<Vec<(usize, f64)>>, Vec<f64>);

/// Values, sparse gradients in `x` and derivatives in the `b` ends' parameters `tb` of
/// the constraints.
fn evaluate(
    network: &CurveNetwork,
    x: &[f64],
    constraints: &[Constraint],
    ub: &[f64],
    halves: &[usize],
) -> ConstraintValues {
    let mut values = Vec::with_capacity(constraints.len());
    let mut gradients = Vec::with_capacity(constraints.len());
    let mut slopes = Vec::with_capacity(constraints.len());
    for ((c, &u), &half) in constraints.iter().zip(ub).zip(halves) {
        let (b_place, sign) = chain_place(&c.chain, u, half);
        let (ta, tb) = (tangent3(network, x, c.a), tangent3(network, x, b_place));
        let tb_norm = tb.norm().max(1e-300);
        let unit = tb / tb_norm;
        let d = point3(network, x, b_place) - point3(network, x, c.a);
        // g = det(T_a, T̂_b, d) · scale: the unit tangent keeps g continuous where the end
        // crosses from one segment to the next.
        values.push(ta.cross(&unit).dot(&d) * c.scale);
        let project = |v: Vec3| v - unit * unit.dot(&v);
        let d_cross_ta = d.cross(&ta);
        // ∂/∂u: T̂_b turns by (I − T̂T̂ᵀ) B'' (dt/du) / |B'|; d moves along T̂_b (no change).
        let turn = project(second3(network, x, b_place)) * (sign / tb_norm);
        slopes.push(turn.dot(&d_cross_ta) * c.scale);
        let (g_ta, g_tb, g_d) = (
            unit.cross(&d) * c.scale,
            project(d_cross_ta) * (c.scale / tb_norm),
            ta.cross(&unit) * c.scale,
        );
        let mut grad: Vec<(usize, f64)> = Vec::with_capacity(24);
        for (place, side) in [(c.a, -1.0), (b_place, 1.0)] {
            let ids = network.segments[place.segment as usize].points;
            let (w, dw) = (cubic::bernstein(place.t), cubic::bernstein_derivative(place.t));
            let g_t = if side < 0.0 { g_ta } else { g_tb };
            for k in 0..4 {
                for axis in 0..3 {
                    let v = dw[k] * g_t[axis] + side * w[k] * g_d[axis];
                    grad.push((3 * ids[k] as usize + axis, v));
                }
            }
        }
        gradients.push(grad);
    }
    (values, gradients, slopes)
}

/// Second derivative of the 3D curve at a place.
fn second3(network: &CurveNetwork, x: &[f64], place: CurvePoint) -> Vec3 {
    crate::curve_lifting::combine3(network, x, place.segment, cubic::bernstein_second_derivative(place.t))
}

/// The refined 3D control points, the new places of the rulings' `b` ends
/// (`[strip][ruling]`, `None` where unchanged) and the report.
pub type Refinement = (Vec<f64>, Vec<Vec<Option<CurvePoint>>>, RefinementInfo);

/// Makes every ruling's tangent plane constant (see the module documentation).
///
/// # Errors
/// [`PhotoError::Solver`] if the factorisation fails; [`PhotoError::Field`] on
/// `analysis.ruling_spacing_px` when the dense Schur complement would exceed
/// [`MAX_DENSE_VALUES`], or [`MAX_REFINEMENT_WORK`] would not allow 5 iterations.
pub fn refine_developability(
    network: &CurveNetwork,
    energy: &Energy,
    strips: &[RuledStrip],
    x_linear: &[f64],
    proximity: f64,
    map: &MirrorMap,
) -> Result<Refinement, PhotoError> {
    let n = x_linear.len();
    let mut constraints = Vec::new();
    for (si, strip) in strips.iter().enumerate() {
        for i in 0..strip.rulings.len() {
            let [a, b] = strip.ends(i);
            let d = point3(network, x_linear, b) - point3(network, x_linear, a);
            let (ta, tb) = (tangent3(network, x_linear, a), tangent3(network, x_linear, b));
            let (sa, sb) = (ta.cross(&d).norm(), tb.cross(&d).norm());
            if sa < 1e-6 * ta.norm() * d.norm() || sb < 1e-6 * tb.norm() * d.norm() {
                continue;
            }
            let speed = cubic::derivative(&network.control_points(b.segment as usize), b.t).norm();
            let Some(u0) = chain_coordinate(&strip.chain_b, b) else {
                continue;
            };
            let n_chain = strip.chain_b.len() as f64;
            constraints.push(Constraint {
                a,
                chain: strip.chain_b.clone(),
                scale: d.norm() * tb.norm() / (sa * sb),
                origin: (si, i),
                slides: u0 > 0.0 && u0 < n_chain && speed > 0.0,
                speed,
            });
        }
    }
    let mut ends: Vec<Vec<Option<CurvePoint>>> = strips.iter().map(|s| vec![None; s.rulings.len()]).collect();
    let mut info = RefinementInfo {
        constraint_count: constraints.len(),
        ..Default::default()
    };
    if constraints.is_empty() {
        info.converged = true;
        return Ok((x_linear.to_vec(), ends, info));
    }
    // H = AᵀA + μ I and the constant part of the gradient; in the free coordinates of
    // the symmetry map, H_z = Pᵀ H P (+ μ on columns nothing depends on).
    let mut full: Vec<(usize, usize, f64)> = Vec::new();
    let mut atb = vec![0.0; n];
    let emphasis = |row: &crate::curve_lifting::EnergyRow| {
        if row.term == crate::curve_lifting::EnergyTerm::Collinearity {
            C1_EMPHASIS
        } else {
            1.0
        }
    };
    for row in &energy.rows {
        let e = emphasis(row);
        for &(ci, ai) in &row.coefficients {
            let ai = ai * e;
            atb[ci as usize] += ai * row.rhs * e;
            for &(cj, aj) in &row.coefficients {
                full.push((ci as usize, cj as usize, ai * aj * e));
            }
        }
    }
    for k in 0..n {
        full.push((k, k, proximity));
    }
    let mut triplets: Vec<Triplet<usize, usize, f64>> = Vec::with_capacity(full.len());
    for &(i, j, v) in &full {
        for &(a, pa) in &map.rows[i] {
            for &(b, pb) in &map.rows[j] {
                if b <= a {
                    triplets.push(Triplet::new(a, b, pa * v * pb));
                }
            }
        }
    }
    for (k, used) in map.used_columns().into_iter().enumerate() {
        if !used {
            triplets.push(Triplet::new(k, k, proximity));
        }
    }
    // Constraint gradients in the free coordinates: C_z = C_x P.
    let reduce = |grads: &[Vec<(usize, f64)>]| -> Vec<Vec<(usize, f64)>> {
        grads
            .iter()
            .map(|g| {
                g.iter()
                    .flat_map(|&(c, v)| map.rows[c].iter().map(move |&(col, a)| (col, v * a)))
                    .collect()
            })
            .collect()
    };
    let llt = SparseCholesky::new(n, &triplets).map_err(|e| {
        tracing::debug!("photo: the developability refinement's system: {e:?}");
        PhotoError::Solver(
            "the developability refinement cannot start: its system has no solution in finite numbers (the \
             3D curves found from the drawing are degenerate)"
                .into(),
        )
    })?;
    let h_times = |x: &[f64]| -> Vec<f64> {
        let mut out = vec![0.0; n];
        for row in &energy.rows {
            let e = emphasis(row);
            let r: f64 = row.coefficients.iter().map(|&(c, a)| a * x[c as usize]).sum();
            for &(c, a) in &row.coefficients {
                out[c as usize] += a * r * e * e;
            }
        }
        for (o, v) in out.iter_mut().zip(x) {
            *o += proximity * v;
        }
        out
    };
    let mut m = constraints.len();
    // The Schur complement is dense: H⁻¹Cᵀ (n × m) and C H⁻¹ Cᵀ (m × m), bounded (~400 MB).
    if n * m + m * m > MAX_DENSE_VALUES {
        return Err(PhotoError::field(
            "analysis.ruling_spacing_px",
            format!(
                "{m} rulings on {} control points are too many to refine (at most {MAX_DENSE_VALUES} dense values): \
                 space the rulings wider or set analysis.refine to false",
                n / 3
            ),
        ));
    }
    // The iterations' work (~15 s): refused when it would not allow a few.
    let mut iteration_work = refinement_iteration_work(n, m);
    if BUDGETED_ITERATIONS as f64 * iteration_work > MAX_REFINEMENT_WORK {
        let fits = |k: usize| BUDGETED_ITERATIONS as f64 * refinement_iteration_work(n, k) <= MAX_REFINEMENT_WORK;
        let (mut most, mut over) = (0, m);
        while over - most > 1 {
            let mid = most + (over - most) / 2;
            if fits(mid) {
                most = mid;
            } else {
                over = mid;
            }
        }
        return Err(PhotoError::field(
            "analysis.ruling_spacing_px",
            format!(
                "{m} rulings on {} control points are too many to refine in bounded time (at most {most} \
                 with this many control points): space the rulings wider or set analysis.refine to false",
                n / 3
            ),
        ));
    }
    let mut work = 0.0;
    // Sliding an end by one pixel costs `SLIDE_WEIGHT` (moving a control point by one
    // pixel costs at least `proximity`).
    let mut slide_weight: Vec<f64> = constraints
        .iter()
        .map(|c| {
            if c.slides {
                SLIDE_WEIGHT * c.speed * c.speed
            } else {
                0.0
            }
        })
        .collect();
    let mut t0: Vec<f64> = constraints
        .iter()
        .map(|c| chain_coordinate(&c.chain, strips[c.origin.0].ends(c.origin.1)[1]).expect("on its chain"))
        .collect();
    let mut x = x_linear.to_vec();
    let mut tb = t0.clone();
    // Each end slides within one half-edge per step and moves on to the next one between
    // steps: the 3D curves are C¹ only to the collinearity energy, so the tangent may
    // turn a little at a join, and a step across it would see a jump.
    let mut halves: Vec<usize> = t0
        .iter()
        .zip(&constraints)
        .map(|(u, c)| (u.floor() as usize).min(c.chain.len() - 1))
        .collect();
    let (mut g, mut grads, mut slopes) = evaluate(network, &x, &constraints, &tb, &halves);
    // The direction of each end's last hop to a neighbouring half-edge (0: none yet).
    let mut last_hop = vec![0i8; m];
    let mut companions: Vec<(usize, usize)> = Vec::new();
    let mut project = false;
    let max_abs = |v: &[f64]| v.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    for iteration in 0..ITERATIONS {
        info.iterations = iteration;
        let violation = max_abs(&g);
        if violation <= 1e-12 {
            break;
        }
        work += iteration_work;
        if work > MAX_REFINEMENT_WORK {
            info.work_bound_reached = true;
            break;
        }
        // ∇f = H x − Aᵀb − μ x_lin, and in t: w (t − t0).
        let hx = h_times(&x);
        // A projection leaves the objective out: the step is the least change, in the
        // metric `H`, that the linearised constraints ask for.
        let grad_f: Vec<f64> = if project {
            vec![0.0; n]
        } else {
            (0..n).map(|k| hx[k] - atb[k] - proximity * x_linear[k]).collect()
        };
        let grad_z = map.apply_transpose(&grad_f);
        let z = llt.solve(&grad_z);
        let grads_z = reduce(&grads);
        // Y = H⁻¹ Cᵀ, one column per constraint.
        let mut ct = Mat::<f64>::zeros(n, m);
        for (r, grad) in grads_z.iter().enumerate() {
            for &(c, v) in grad {
                ct[(c, r)] += v;
            }
        }
        let y = llt.solve_columns(ct.as_ref());
        // S = C_x Y + diag(c_t² / w) (symmetric positive semi-definite),
        // rhs = g − C_x z − c_t ∇_t f / w.
        // Column by column: `y` and `s` are column-major (the same sums, in the same
        // order, as row by row).
        let mut s = Mat::<f64>::zeros(m, m);
        for j in 0..m {
            let (y_j, s_j) = (y.col(j), s.col_mut(j));
            for (s_rj, grad) in s_j.iter_mut().zip(&grads_z) {
                for &(c, v) in grad {
                    *s_rj += v * y_j[c];
                }
            }
        }
        let mut rhs = Col::<f64>::zeros(m);
        for (r, grad) in grads_z.iter().enumerate() {
            let mut cz = 0.0;
            for &(c, v) in grad {
                cz += v * z[c];
            }
            if slide_weight[r] > 0.0 {
                s[(r, r)] += slopes[r] * slopes[r] / slide_weight[r];
                if !project {
                    cz += slopes[r] * (tb[r] - t0[r]);
                }
            }
            rhs[r] = g[r] - cz;
        }
        // Redundant constraints make S singular: a tiny ridge keeps the solve defined.
        let ridge = 1e-12 * (0..m).map(|i| s[(i, i)]).fold(0.0, f64::max).max(1e-300);
        for i in 0..m {
            s[(i, i)] += ridge;
        }
        let lambda = s.partial_piv_lu().solve(&rhs);
        // −z − Y λ, column by column (each entry's terms in the same order as row by row).
        let mut step_z: Vec<f64> = (0..n).map(|k| -z[k]).collect();
        for j in 0..m {
            for (v, &y_kj) in step_z.iter_mut().zip(y.col(j).iter()) {
                *v -= y_kj * lambda[j];
            }
        }
        let step = map.apply(&step_z);
        let step_t: Vec<f64> = (0..m)
            .map(|r| {
                if slide_weight[r] > 0.0 {
                    -(if project { 0.0 } else { tb[r] - t0[r] }) - slopes[r] * lambda[r] / slide_weight[r]
                } else {
                    0.0
                }
            })
            .collect();
        let mut alpha = 1.0;
        let mut accepted = false;
        for _ in 0..30 {
            let trial: Vec<f64> = x.iter().zip(&step).map(|(a, b)| a + alpha * b).collect();
            let trial_t: Vec<f64> = tb
                .iter()
                .zip(&step_t)
                .zip(&halves)
                .map(|((t, d), &h)| (t + alpha * d).clamp(h as f64, h as f64 + 1.0))
                .collect();
            let (g_trial, grads_trial, slopes_trial) = evaluate(network, &trial, &constraints, &trial_t, &halves);
            let v = max_abs(&g_trial);
            if v.is_finite() && (v < (1.0 - 1e-4 * alpha) * violation || v <= 1e-12) {
                x = trial;
                tb = trial_t;
                g = g_trial;
                grads = grads_trial;
                slopes = slopes_trial;
                accepted = true;
                break;
            }
            alpha *= 0.5;
        }
        // What the step made of the violation (before hops re-evaluate `g` on other
        // half-edges): a step that does not halve it starts the projections.
        let after_step = max_abs(&g);
        // Ends stopped at a join that the step would carry further move on to the next
        // half-edge.
        let (mut hopped, mut pinned) = (false, false);
        for r in 0..m {
            if slide_weight[r] <= 0.0 {
                continue;
            }
            let wanted = tb[r] + step_t[r];
            let (h, n_chain) = (halves[r], constraints[r].chain.len());
            let direction = if tb[r] >= (h + 1) as f64 && wanted > tb[r] && h + 1 < n_chain {
                1
            } else if tb[r] <= h as f64 && wanted < tb[r] && h > 0 {
                -1
            } else {
                0
            };
            if direction == 0 {
                continue;
            }
            if last_hop[r] == -direction {
                // Back to the half-edge it left: its root lies in the tangent's turn at
                // the join. The end stays at the join, and a companion constraint asks
                // the tangent on the other side to lie in the ruling's plane too: the
                // curves turn both into it (the join stays C¹ across the ruling).
                slide_weight[r] = 0.0;
                let grown = m + companions.len() + 1;
                if n * grown + grown * grown <= MAX_DENSE_VALUES {
                    companions.push((r, if direction > 0 { h + 1 } else { h - 1 }));
                } else {
                    tracing::debug!(
                        ruling = r,
                        "refinement: an end held at a join without its companion (dense bound)"
                    );
                }
                pinned = true;
                continue;
            }
            last_hop[r] = direction;
            halves[r] = if direction > 0 { h + 1 } else { h - 1 };
            hopped = true;
        }
        for (r, other) in companions.drain(..) {
            let c = &constraints[r];
            constraints.push(Constraint {
                a: c.a,
                chain: c.chain.clone(),
                scale: c.scale,
                origin: c.origin,
                slides: false,
                speed: c.speed,
            });
            t0.push(tb[r]);
            tb.push(tb[r]);
            halves.push(other);
            slide_weight.push(0.0);
            last_hop.push(0);
        }
        if hopped || pinned {
            m = constraints.len();
            iteration_work = refinement_iteration_work(n, m);
            (g, grads, slopes) = evaluate(network, &x, &constraints, &tb, &halves);
        }
        // A step that did not halve the violation: Gauss–Newton on the objective crawls
        // (it leaves out the constraints' curvature); project from here on.
        let switched = !project && after_step > 0.5 * violation && after_step < PROJECTION_START;
        project |= switched;
        tracing::trace!(
            iteration,
            violation = max_abs(&g),
            accepted,
            hopped,
            project,
            "refinement step"
        );
        if !accepted && !hopped && !pinned && !switched {
            break;
        }
        info.iterations = iteration + 1;
    }
    info.constraint_violation = max_abs(&g);
    // Met when `max |g|` is, and every ruling's error angle (§8.2) with it: `g` is the
    // angle's sine only while the frozen denominators hold, so a ruling whose tangent
    // turned along it could meet `g` and not the angle.
    let angle_max = constraints
        .iter()
        .zip(&tb)
        .zip(&halves)
        .map(|((c, &u), &half)| {
            let b = chain_place(&c.chain, u, half).0;
            let d = point3(network, &x, b) - point3(network, &x, c.a);
            let (na, nb) = (tangent3(network, &x, c.a).cross(&d), tangent3(network, &x, b).cross(&d));
            let denominator = na.norm() * nb.norm();
            if denominator < 1e-300 {
                std::f64::consts::FRAC_PI_2
            } else {
                (na.dot(&nb).abs() / denominator).min(1.0).acos()
            }
        })
        .fold(0.0, f64::max);
    info.converged = info.constraint_violation <= REFINEMENT_BOUND && angle_max.sin() <= REFINEMENT_BOUND;
    info.displacement_max = (0..n / 3)
        .map(|i| {
            Vec3::new(
                x[3 * i] - x_linear[3 * i],
                x[3 * i + 1] - x_linear[3 * i + 1],
                x[3 * i + 2] - x_linear[3 * i + 2],
            )
            .norm()
        })
        .fold(0.0, f64::max);
    for (((c, &u), &u0), &half) in constraints.iter().zip(&tb).zip(&t0).zip(&halves) {
        if u != u0 {
            info.slide_max_px = info.slide_max_px.max((u - u0).abs() * c.speed);
            ends[c.origin.0][c.origin.1] = Some(chain_place(&c.chain, u, half).0);
        }
    }
    Ok((x, ends, info))
}

/// Weight of an end's slide along its curve, per square pixel (control points weigh
/// the proximity, 1 per square pixel by default): rulings move along the curves far
/// more readily than the curves move.
const SLIDE_WEIGHT: f64 = 1e-1;

/// Factor on the C¹ (collinearity) residuals in the refinement's objective (their
/// weight is its square): a ruling end crossing a join sees the tangent jump by as much
/// as the curve misses C¹ there, and a root inside that jump cannot be reached by
/// sliding. With the linear energy's weight the hand-traced cup stalled at a join
/// (max |g| 1e-3); with 1e2 it converges in 2 iterations (1e3 and 3e1 behave alike).
const C1_EMPHASIS: f64 = 1e2;

#[cfg(test)]
mod tests {
    use super::*;

    /// The constraint gradients against central differences, on the espresso cup.
    #[test]
    fn constraint_gradients_match_finite_differences() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/photo/coffee-cup.json");
        let annotation = crate::PhotoAnnotation::from_json(&std::fs::read_to_string(path).unwrap()).unwrap();
        let r = crate::reconstruct(&annotation).unwrap();
        let mut constraints = Vec::new();
        let mut us = Vec::new();
        for strip in &r.strips {
            for i in 0..strip.rulings.len() {
                let [a, b] = strip.ends(i);
                constraints.push(Constraint {
                    a,
                    chain: strip.chain_b.clone(),
                    scale: 1e-4,
                    origin: (0, i),
                    slides: true,
                    speed: 1.0,
                });
                us.push(chain_coordinate(&strip.chain_b, b).unwrap());
            }
        }
        let x = r.linear.clone();
        // Away from the segment joins, where the second derivative jumps, and inside the
        // chain (its ends clamp).
        let tb: Vec<f64> = us
            .iter()
            .zip(&constraints)
            .map(|(u, c): (&f64, &Constraint)| {
                (u.floor() + u.fract().clamp(0.01, 0.99)).min(c.chain.len() as f64 - 0.01)
            })
            .collect();
        let halves: Vec<usize> = tb.iter().map(|u| u.floor() as usize).collect();
        let (_, grads, slopes) = evaluate(&r.network, &x, &constraints, &tb, &halves);
        let h = 1e-4;
        let mut worst = 0.0f64;
        for (c, grad) in grads.iter().enumerate() {
            let mut dense = vec![0.0; x.len()];
            for &(k, v) in grad {
                dense[k] += v;
            }
            for (k, &analytic) in dense.iter().enumerate() {
                let (mut xp, mut xm) = (x.clone(), x.clone());
                xp[k] += h;
                xm[k] -= h;
                let numeric = (evaluate(&r.network, &xp, &constraints[c..=c], &tb[c..=c], &halves[c..=c]).0[0]
                    - evaluate(&r.network, &xm, &constraints[c..=c], &tb[c..=c], &halves[c..=c]).0[0])
                    / (2.0 * h);
                worst = worst.max((numeric - analytic).abs() / (1.0 + analytic.abs()));
            }
            let ht = 1e-6;
            let (tp, tm) = ([tb[c] + ht], [tb[c] - ht]);
            let numeric = (evaluate(&r.network, &x, &constraints[c..=c], &tp, &halves[c..=c]).0[0]
                - evaluate(&r.network, &x, &constraints[c..=c], &tm, &halves[c..=c]).0[0])
                / (2.0 * ht);
            worst = worst.max((numeric - slopes[c]).abs() / (1.0 + slopes[c].abs()));
        }
        assert!(worst < 1e-6, "{worst}");
    }
}

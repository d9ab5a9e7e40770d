//! Symmetrising the curves and rulings (§7, "Symmetrizing the contours and rulings").
//!
//! The lifted network satisfies the mirror pairs only in the least-squares sense, so
//! symmetric curves are not exact mirror images. As in the paper, the half of the model on
//! the positive side of the plane (`n·(x − c) > 0`: by the depth convention of
//! [`crate::SymmetryPlane`], the side of the annotated pair's point nearer the camera, the
//! better seen one in a 3/4 view) is kept and the other half is replaced by its mirror
//! image `M x = x − 2 (n·(x − c)) n`:
//!
//! - **Curves.** First the curves are split where a partner's node mirrors
//!   ([`split_at_mirror_nodes`]; exact, so nothing changes shape), so that nodes can
//!   correspond. The segments of a symmetric pair of curves (or of a self-symmetric
//!   curve with itself) are then matched one to one: the map is the order-preserving or
//!   order-reversing (for closed curves: cyclically shifted) one whose mirrored 3D control
//!   points are nearest, accepted when their RMS distance is under a quarter of the mean
//!   chord. An unmarked open curve whose two ends are matched with each other (a
//!   silhouette running along the direction of symmetry, where §5.3 finds no
//!   correspondences) is taken as self-symmetric. For each matched pair the segment on the
//!   negative side gets the mirror of the other's control points, so `B′(t) = M B(t)` (or
//!   `M B(1 − t)`) holds exactly; a segment matched with itself keeps its positive half
//!   (`q₃ = M q₀`, `q₂ = M q₁`), a node matched with itself is projected onto the plane.
//!   Segments of unmatched curves whose end nodes moved follow them with the affine blend
//!   `Δq_k = (1 − k/3) Δq₀ + (k/3) Δq₃` (a straight segment stays straight).
//! - **Samples.** A mirrored segment takes its partner's sample parameters, so mirrored
//!   places are samples and the mesh on both sides is the same.
//! - **Rulings.** A ruled strip whose rulings mirror into another strip is replaced by
//!   the mirror of the positive one. In a self-symmetric strip the rulings on the positive
//!   side are kept and mirrored; those on the negative side are dropped; a ruling
//!   crossing the plane is replaced, as in the paper, by the ruling that joins its
//!   positive end to that end's mirror point (when that lies on the strip's other side).
//! - **The map.** The result is `x = P z + o` with `P` a [`MirrorMap`]: the refinement
//!   takes its steps in `z`, so the refined model stays exactly symmetric, and the
//!   rulings are mirrored once more from the refined positive half.
//!
//! Departures, each listed in the report: a curve pair whose splits do not correspond
//! (a crossing on one side only) is left as solved; so is every curve bounding a ruled
//! strip that is only partly mirrored in the drawing (the visible front arc of a body of
//! revolution: its mirror image is partly hidden) and every segment joined to one —
//! symmetrising one side of such a strip alone fights its own rulings, which do not
//! mirror (measured: the noisy cone's scale error went from 3.7 % to 11 %, see
//! `docs/benchmarks-history.md`). Unmatched curves in the negative half are kept (the paper
//! removes them; they have no mirror image to take their place). The caller
//! ([`crate::reconstruct`]) keeps the unsymmetrised model when nothing mirrors, or when the
//! symmetric model cannot be made developable and the plain one can.

use crate::cubic;
use crate::curve_network::CurveNetwork;
use crate::curve_samples::{CurvePoint, CurveSamples, SampledChain};
use crate::ruling_propagation::RuledStrip;
use crate::symmetry_plane::SymmetryPlane;
use crate::PhotoError;
use nalgebra::{Vector2, Vector3};
use sheetform_geometry::{quoted_token, short_number};

type Vec3 = Vector3<f64>;

/// Most segment comparisons of one call of [`symmetrize`] or [`split_at_mirror_nodes`]
/// (which checks its splits with the same matching). Matching two curves of `n` segments
/// scores every order-preserving and order-reversing map: one map each for open curves,
/// `n` cyclic shifts each for closed ones, so `2n²` comparisons (four control points
/// mirrored) for two closed curves and `n²` for a closed self-symmetric one. About 1 s
/// at the measured 6 ns a comparison (3.6e7 in 0.23 s); a closed self-symmetric curve of
/// 10 000 segments (all the annotation's control points) makes 1e8, a traced photo
/// hundreds. The maps are scored one at a time, so the memory is linear in `n` (keeping
/// every candidate map took 1.6 GB at 10 000 segments).
pub const MAX_SEGMENT_COMPARISONS: usize = 150_000_000;

/// Most curve evaluations of one call of [`split_at_mirror_nodes`]: every end node of
/// one curve of a pair looks for the crossings of its mirror line with every segment of
/// the other curve. A segment whose control polygon lies on one side of the line is
/// rejected by one test (counted as one evaluation); another takes 64 evaluations of
/// sign tests and 60 per bisection. About 2 s at the measured 4 ns an evaluation (a
/// closed curve of 1 000 segments with itself: 2 million searches took 0.5 s before the
/// polygon test, 0.07 s with it); a closed curve of 3 000 segments with itself makes
/// 2e7, a comb whose every segment straddles every line 2e9 (a closed curve of 9 000
/// segments took 2 minutes and 1.6 GB before the bound).
pub const MAX_MIRROR_SEARCH_EVALUATIONS: usize = 400_000_000;

/// Most chain entries examined by one call of [`symmetrize`] to place the strips'
/// rulings: which strip's chains hold a mirrored ruling's ends (a segment's entries in
/// the chain index, one or two per patch whose cycle runs along it) and which sample of
/// a chain is nearest a ruling end (the samples of the same segment nearest in
/// parameter, or those within a grid cell of its position). Both are indexed once per
/// strip, so a ruling costs a few entries: the drawing's at most
/// [`crate::MAX_STRIP_SAMPLES`] strip samples make some tens of millions. Only coincident
/// samples (a chain traversing many zero-length segments at one place) could come near;
/// about 1 s at a few nanoseconds an entry. (Before the index, every ruling scanned its
/// strip's chains and every other strip's: rulings × strips × chain length.)
pub const MAX_RULING_LOOKUP_WORK: usize = 300_000_000;

/// Evaluations of one [`cubic::bisect`] that finds a root.
const BISECTION_EVALUATIONS: usize = 60;

/// Quoted name of network curve `c`.
fn curve_name(network: &CurveNetwork, c: usize) -> String {
    format!("`{}`", quoted_token(&network.curves[c].name))
}

/// Adds `cost` to `spent`, or the error when that passes `limit`: `step` says what was to
/// be done, `unit` what is counted.
fn charge(
    spent: &mut usize,
    cost: usize,
    limit: usize,
    unit: &str,
    step: impl Fn() -> String,
) -> Result<(), PhotoError> {
    charge_field(
        spent,
        cost,
        limit,
        unit,
        (
            "analysis.symmetrize",
            "trace the curves with fewer control points or set analysis.symmetrize to false",
        ),
        step,
    )
}

/// [`charge`] with the error on another field: `refusal` is the field and the advice.
fn charge_field(
    spent: &mut usize,
    cost: usize,
    limit: usize,
    unit: &str,
    refusal: (&str, &str),
    step: impl Fn() -> String,
) -> Result<(), PhotoError> {
    let total = spent.saturating_add(cost);
    if total > limit {
        let (field, advice) = refusal;
        return Err(PhotoError::field(
            field,
            format!(
                "{} would bring the symmetrisation to {} {unit} (at most {}): {advice}",
                step(),
                short_number(total as f64),
                short_number(limit as f64)
            ),
        ));
    }
    *spent = total;
    Ok(())
}

/// What the symmetrisation did (the `photo.symmetrization` section of report.json).
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct SymmetrizationInfo {
    /// Segments split so that nodes mirror onto nodes ([`split_at_mirror_nodes`]).
    pub split_segment_count: usize,
    /// Segments replaced by the mirror image of their partner (a self-symmetric segment
    /// counts once).
    pub mirrored_segment_count: usize,
    /// Ruled strips whose rulings were rebuilt by mirroring.
    pub mirrored_strip_count: usize,
    /// Rulings crossing the plane replaced by one joining mirror points.
    pub crossing_ruling_count: usize,
    /// Curves (by name) whose mirror partner is split differently, left as solved.
    pub unmatched_curves: Vec<String>,
    /// Curves (by name) that bound a ruled strip only partly mirrored in the drawing,
    /// left as solved.
    pub partly_mirrored_curves: Vec<String>,
    /// Largest move of a control point (pixels).
    pub displacement_max_px: f64,
    /// The symmetric model could not be made developable (the refinement did not
    /// converge with the mirror constraint, but did without): the model is left
    /// unsymmetrised.
    pub abandoned: bool,
}

/// The linear part of the symmetrised control points as functions of free ones: after
/// [`symmetrize`], `x = P z + o` with `P` these rows (one per coordinate of `x`, each a
/// short list of `(column, coefficient)` over the same index space) — the identity for a
/// free coordinate, the mirror `I − 2nnᵀ` of a source point for a mirrored one, the
/// projection `I − nnᵀ` for a node held on the plane. A step `δx = P δz` keeps the model
/// symmetric; the developability refinement takes its steps in `z`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MirrorMap {
    /// Per coordinate of `x`, its dependence on the free coordinates.
    pub rows: Vec<Vec<(usize, f64)>>,
}

impl MirrorMap {
    /// The identity on `n` coordinates.
    pub fn identity(n: usize) -> Self {
        Self {
            rows: (0..n).map(|k| vec![(k, 1.0)]).collect(),
        }
    }

    /// `P v`.
    pub fn apply(&self, v: &[f64]) -> Vec<f64> {
        self.rows
            .iter()
            .map(|r| r.iter().map(|&(c, a)| a * v[c]).sum())
            .collect()
    }

    /// `Pᵀ v`.
    pub fn apply_transpose(&self, v: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; v.len()];
        for (r, &vr) in self.rows.iter().zip(v) {
            for &(c, a) in r {
                out[c] += a * vr;
            }
        }
        out
    }

    /// Columns that some coordinate depends on.
    pub fn used_columns(&self) -> Vec<bool> {
        let mut used = vec![false; self.rows.len()];
        for r in &self.rows {
            for &(c, _) in r {
                used[c] = true;
            }
        }
        used
    }
}

/// One segment matched with its mirror partner.
#[derive(Debug, Clone, Copy, PartialEq)]
struct SegmentMatch {
    source: u32,
    partner: u32,
    /// `partner(t) = M source(1 − t)` instead of `M source(t)`.
    reversed: bool,
}

fn point(x: &[f64], i: u32) -> Vec3 {
    Vec3::new(x[3 * i as usize], x[3 * i as usize + 1], x[3 * i as usize + 2])
}

/// The segment map between curves `a` and `b` (equal for a self-symmetric curve), or
/// `None` when no map fits. The comparisons made go to `spent`.
///
/// # Errors
/// [`PhotoError::Field`] on `analysis.symmetrize` when `spent` would pass
/// [`MAX_SEGMENT_COMPARISONS`] (checked before the work).
fn match_curves(
    network: &CurveNetwork,
    x: &[f64],
    plane: &SymmetryPlane,
    a: usize,
    b: usize,
    spent: &mut usize,
) -> Result<Option<Vec<SegmentMatch>>, PhotoError> {
    let (ca, cb) = (&network.curves[a], &network.curves[b]);
    let n = ca.segments.len();
    if n != cb.segments.len() || ca.closed != cb.closed || n == 0 {
        return Ok(None);
    }
    // Candidate maps i → (j, reversed): per shift c, the forward map i → i + c (two
    // different curves only) and the backward one, scored one at a time in that order
    // (the first of equal scores wins).
    let shifts = if ca.closed { n } else { 1 };
    let per_shift = if a != b { 2 } else { 1 };
    charge(
        spent,
        shifts.saturating_mul(per_shift).saturating_mul(n),
        MAX_SEGMENT_COMPARISONS,
        "segment comparisons",
        || {
            if a == b {
                format!(
                    "matching curve {}'s {n} segments with their mirror images",
                    curve_name(network, a)
                )
            } else {
                format!(
                    "matching curves {} and {} ({n} segments each)",
                    curve_name(network, a),
                    curve_name(network, b)
                )
            }
        },
    )?;
    let control = |s: u32| network.segments[s as usize].points.map(|p| point(x, p));
    let map_of = |c: usize, reversed: bool| {
        let back = if ca.closed { c } else { n - 1 };
        move |i: usize| {
            if reversed {
                ((back + n - i) % n, true)
            } else {
                ((i + c) % n, false)
            }
        }
    };
    // Mirrored control points of `a` and control points of `b`, once.
    let mirrored: Vec<[Vec3; 4]> = ca
        .segments
        .iter()
        .map(|&s| control(s).map(|q| plane.mirror(q)))
        .collect();
    let partner: Vec<[Vec3; 4]> = cb.segments.iter().map(|&s| control(s)).collect();
    let mismatch = |map: &dyn Fn(usize) -> (usize, bool)| -> f64 {
        let mut sum = 0.0;
        for (i, qa) in mirrored.iter().enumerate() {
            let (j, reversed) = map(i);
            let qb = &partner[j];
            for (k, &q) in qa.iter().enumerate() {
                let kb = if reversed { 3 - k } else { k };
                sum += (q - qb[kb]).norm_squared();
            }
        }
        (sum / (4 * n) as f64).sqrt()
    };
    let mut best: Option<((usize, bool), f64)> = None;
    for c in 0..shifts {
        for reversed in [false, true] {
            if !reversed && a == b {
                continue;
            }
            let error = mismatch(&map_of(c, reversed));
            if best.is_none_or(|(_, e)| error.total_cmp(&e) == std::cmp::Ordering::Less) {
                best = Some(((c, reversed), error));
            }
        }
    }
    let Some(((c, reversed), error)) = best else {
        return Ok(None);
    };
    let chord: f64 = ca
        .segments
        .iter()
        .map(|&s| {
            let q = control(s);
            (q[3] - q[0]).norm()
        })
        .sum::<f64>()
        / n as f64;
    // (A NaN mismatch fails too.)
    if error.is_nan() || error > 0.25 * chord {
        return Ok(None);
    }
    let map = map_of(c, reversed);
    Ok(Some(
        (0..n)
            .map(|i| {
                let (j, reversed) = map(i);
                SegmentMatch {
                    source: ca.segments[i],
                    partner: cb.segments[j],
                    reversed,
                }
            })
            .collect(),
    ))
}

/// Symmetrises the control points `x` (pixels), the samples and the strips' rulings.
/// `curve_pairs` are the annotation's symmetric curve pairs and self-symmetric curves
/// (`[c, c]`), as network curve indices.
///
/// # Errors
/// [`PhotoError::Field`] on `analysis.symmetrize` when matching the curves would take
/// more than [`MAX_SEGMENT_COMPARISONS`].
pub fn symmetrize(
    network: &CurveNetwork,
    samples: &mut CurveSamples,
    strips: &mut [RuledStrip],
    plane: &SymmetryPlane,
    curve_pairs: &[[usize; 2]],
    x: &[f64],
) -> Result<(Vec<f64>, SymmetrizationInfo, MirrorMap), PhotoError> {
    let mut info = SymmetrizationInfo::default();
    let mut spent = 0;
    // Segment maps, both ways: mirror_of[s] = (partner, reversed).
    let mut mirror_of: Vec<Option<(u32, bool)>> = vec![None; network.segments.len()];
    let mut matches: Vec<SegmentMatch> = Vec::new();
    for &[a, b] in curve_pairs {
        match match_curves(network, x, plane, a, b, &mut spent)? {
            Some(m) => {
                for s in &m {
                    mirror_of[s.source as usize] = Some((s.partner, s.reversed));
                    mirror_of[s.partner as usize] = Some((s.source, s.reversed));
                }
                matches.extend(m);
            }
            None => {
                for c in [a, b] {
                    if !info.unmatched_curves.contains(&network.curves[c].name) {
                        info.unmatched_curves.push(network.curves[c].name.clone());
                    }
                }
            }
        }
    }
    // A curve nobody marked whose two ends are mirror partners (a silhouette running
    // along the direction of symmetry, where §5.3 finds no correspondences) is
    // self-symmetric too, when its segments match.
    let mut node_partner: std::collections::HashMap<u32, u32> = Default::default();
    for m in &matches {
        let (ps, pp) = (
            network.segments[m.source as usize].points,
            network.segments[m.partner as usize].points,
        );
        for k in [0, 3] {
            let kb = if m.reversed { 3 - k } else { k };
            node_partner.insert(ps[k], pp[kb]);
            node_partner.insert(pp[kb], ps[k]);
        }
    }
    for (c, curve) in network.curves.iter().enumerate() {
        if curve.closed || curve_pairs.iter().any(|p| p.contains(&c)) {
            continue;
        }
        let first = network.segments[curve.segments[0] as usize].points[0];
        let last = network.segments[*curve.segments.last().expect("a curve has segments") as usize].points[3];
        if node_partner.get(&first) == Some(&last) {
            if let Some(m) = match_curves(network, x, plane, c, c, &mut spent)? {
                for s in &m {
                    mirror_of[s.source as usize] = Some((s.partner, s.reversed));
                }
                matches.extend(m);
            }
        }
    }
    // A ruled strip only partly mirrored (one side's curve has no mirror image in the
    // drawing: the visible front arc of a body of revolution whose plane is not the
    // view's) keeps its curves as solved: symmetrising one side alone would fight the
    // strip's own rulings, which do not mirror.
    let old_rulings: Vec<Vec<[CurvePoint; 2]>> = strips
        .iter()
        .map(|s| (0..s.rulings.len()).map(|i| s.ends(i)).collect())
        .collect();
    // Which strips' chains hold each segment, once (the strips' chains do not change
    // here); every ruling's lookups on it are charged.
    let index = ChainIndex::new(network.segments.len(), strips);
    let mut lookups = 0usize;
    let mut partial = vec![false; network.segments.len()];
    for (k, strip) in strips.iter().enumerate() {
        let whole = strip
            .chain_a
            .iter()
            .chain(&strip.chain_b)
            .all(|h| mirror_of[h.segment as usize].is_some());
        let mirrored = whole && {
            let mut cost = 0;
            let o = index.mirror_strip(&old_rulings, &mirror_of, k, &mut cost);
            charge_lookups(&mut lookups, cost, k, strip.patch)?;
            o.is_some()
        };
        if !mirrored {
            for h in strip.chain_a.iter().chain(&strip.chain_b) {
                partial[h.segment as usize] = true;
            }
        }
    }
    // Segments that share a node with such a strip's curves stay too (moving the node
    // would bend the strip).
    let mut partial_node = vec![false; network.points.len()];
    for (seg, _) in partial.iter().enumerate().filter(|(_, p)| **p) {
        let q = network.segments[seg].points;
        partial_node[q[0] as usize] = true;
        partial_node[q[3] as usize] = true;
    }
    let touches = |seg: u32| {
        let q = network.segments[seg as usize].points;
        partial[seg as usize] || partial_node[q[0] as usize] || partial_node[q[3] as usize]
    };
    matches.retain(|m| {
        let keep = !touches(m.source) && !touches(m.partner);
        if !keep {
            for seg in [m.source, m.partner] {
                let name = &network.curves[network.segments[seg as usize].curve as usize].name;
                if mirror_of[seg as usize].is_some() && !info.partly_mirrored_curves.contains(name) {
                    info.partly_mirrored_curves.push(name.clone());
                }
            }
        }
        keep
    });
    mirror_of = vec![None; network.segments.len()];
    for m in &matches {
        mirror_of[m.source as usize] = Some((m.partner, m.reversed));
        mirror_of[m.partner as usize] = Some((m.source, m.reversed));
    }
    // New control points: target ← mirror(source), averaged where a node gets several.
    // Each assignment: (target, source, projection onto the plane instead of mirror).
    let mut assignments: Vec<(u32, u32, bool)> = Vec::new();
    let mut assign = |target: u32, source: u32, project: bool| assignments.push((target, source, project));
    // Which segments take their partner's samples: (target, source, reversed), and
    // self-symmetric segments keeping their first (true) or second half.
    let mut mirrored: Vec<(u32, u32, bool)> = Vec::new();
    let mut halves: Vec<(u32, bool)> = Vec::new();
    let side = |s: u32, range: std::ops::Range<usize>| -> f64 {
        let q = network.segments[s as usize].points;
        q[range].iter().map(|&p| plane.signed_distance(point(x, p))).sum()
    };
    let mut done = vec![false; network.segments.len()];
    for m in &matches {
        if done[m.source as usize] || done[m.partner as usize] {
            continue;
        }
        done[m.source as usize] = true;
        done[m.partner as usize] = true;
        let (ps, pp) = (
            network.segments[m.source as usize].points,
            network.segments[m.partner as usize].points,
        );
        let corresponding = |k: usize| if m.reversed { 3 - k } else { k };
        if m.source == m.partner {
            let first_half = side(m.source, 0..2) >= side(m.source, 2..4);
            let keep = if first_half { 0..2 } else { 2..4 };
            for k in keep {
                assign(ps[3 - k], ps[k], false);
            }
            halves.push((m.source, first_half));
        } else {
            let (source, target, sp, tp) = if side(m.source, 0..4) >= side(m.partner, 0..4) {
                (m.source, m.partner, ps, pp)
            } else {
                (m.partner, m.source, pp, ps)
            };
            for k in 0..4 {
                let (from, to) = (sp[k], tp[corresponding(k)]);
                // A node matched with itself lies on the plane.
                assign(to, from, from == to);
            }
            mirrored.push((target, source, m.reversed));
        }
        info.mirrored_segment_count += 1;
    }
    // Nodes matched with themselves inside a self-symmetric segment map (the fixed points
    // of a closed curve's involution) are covered above; a self-symmetric segment's own
    // middle needs nothing more (`q₃ = M q₀` puts its midpoint on the plane).
    // x_t = mean over its assignments of L x_s + o, L = I − 2nnᵀ (mirror) or I − nnᵀ
    // (projection), o = 2(n·c)n or (n·c)n.
    let n = plane.normal;
    let nc = n.dot(&plane.point);
    let mut map = MirrorMap::identity(x.len());
    let mut offset = vec![0.0; x.len()];
    let mut per_target: std::collections::BTreeMap<u32, Vec<(u32, bool)>> = Default::default();
    for &(t, s, project) in &assignments {
        per_target.entry(t).or_default().push((s, project));
    }
    for (&t, sources) in &per_target {
        let share = 1.0 / sources.len() as f64;
        for axis in 0..3 {
            let row = &mut map.rows[3 * t as usize + axis];
            row.clear();
            for &(s, project) in sources {
                let f = if project { 1.0 } else { 2.0 };
                for j in 0..3 {
                    let a = share * (f64::from(u8::from(axis == j)) - f * n[axis] * n[j]);
                    if a != 0.0 {
                        row.push((3 * s as usize + j, a));
                    }
                }
                offset[3 * t as usize + axis] += share * f * nc * n[axis];
            }
        }
    }
    // Sources are never targets of another assignment in a consistent drawing; where
    // they are (a node judged on both sides), the map uses the source's free value.
    let mut y = map.apply(x);
    for (v, o) in y.iter_mut().zip(&offset) {
        *v += o;
    }
    // Unmatched segments whose end nodes moved: the affine blend.
    for (s, seg) in network.segments.iter().enumerate() {
        if mirror_of[s].is_some() {
            continue;
        }
        let delta = |p: u32| point(&y, p) - point(x, p);
        let (d0, d3) = (delta(seg.points[0]), delta(seg.points[3]));
        if d0 == Vec3::zeros() && d3 == Vec3::zeros() {
            continue;
        }
        for (k, &p) in seg.points.iter().enumerate().skip(1).take(2) {
            let w = k as f64 / 3.0;
            let v = point(x, p) + (1.0 - w) * d0 + w * d3;
            y[3 * p as usize..3 * p as usize + 3].copy_from_slice(v.as_slice());
        }
    }
    info.displacement_max_px = (0..network.points.len() as u32)
        .map(|p| (point(&y, p) - point(x, p)).norm())
        .fold(0.0, f64::max);
    // Samples: mirrored segments take their partner's; self-symmetric ones mirror their
    // kept half.
    for &(target, source, reversed) in &mirrored {
        let p = samples.parameters[source as usize].clone();
        samples.parameters[target as usize] = if reversed {
            p.iter().rev().map(|t| 1.0 - t).collect()
        } else {
            p
        };
    }
    for &(s, first_half) in &halves {
        let p = &samples.parameters[s as usize];
        let kept: Vec<f64> = if first_half {
            p.iter().copied().filter(|&t| t < 0.5).collect()
        } else {
            p.iter().rev().map(|t| 1.0 - t).filter(|&t| t < 0.5).collect()
        };
        let mut both = kept.clone();
        if p.contains(&0.5) {
            both.push(0.5);
        }
        both.extend(kept.iter().rev().map(|t| 1.0 - t));
        samples.parameters[s as usize] = both;
    }
    let mirror_place = |p: CurvePoint| mirror_place_of(&mirror_of, p);
    let distance = |p: CurvePoint| plane.signed_distance(crate::reconstruction::place_point(network, &y, p));
    let mut mirror_strips: Vec<Option<usize>> = Vec::with_capacity(strips.len());
    for (s, strip) in strips.iter().enumerate() {
        let mut cost = 0;
        mirror_strips.push(index.mirror_strip(&old_rulings, &mirror_of, s, &mut cost));
        charge_lookups(&mut lookups, cost, s, strip.patch)?;
    }
    let scale = x.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1.0);
    let epsilon = 1e-9 * scale;
    let mut new_rulings: Vec<Option<Vec<[CurvePoint; 2]>>> = vec![None; strips.len()];
    let mean_side = |s: usize| -> f64 {
        old_rulings[s]
            .iter()
            .map(|r| distance(r[0]) + distance(r[1]))
            .sum::<f64>()
            / old_rulings[s].len().max(1) as f64
    };
    for s in 0..strips.len() {
        let Some(o) = mirror_strips[s] else { continue };
        if o == s {
            let mut out = Vec::new();
            for r in &old_rulings[s] {
                let (da, db) = (distance(r[0]), distance(r[1]));
                if da >= -epsilon && db >= -epsilon {
                    out.push(*r);
                    if let (Some(a), Some(b)) = (mirror_place(r[0]), mirror_place(r[1])) {
                        out.push([a, b]);
                    }
                } else if da > epsilon || db > epsilon {
                    // Crossing the plane: join the positive end to its mirror.
                    let positive = if da > db { r[0] } else { r[1] };
                    if let Some(m) = mirror_place(positive) {
                        out.push([positive, m]);
                        info.crossing_ruling_count += 1;
                    }
                }
            }
            new_rulings[s] = Some(out);
            info.mirrored_strip_count += 1;
        } else if mean_side(s) > mean_side(o) && mirror_strips[o] == Some(s) {
            new_rulings[o] = Some(
                old_rulings[s]
                    .iter()
                    .filter_map(|r| Some([mirror_place(r[0])?, mirror_place(r[1])?]))
                    .collect(),
            );
            info.mirrored_strip_count += 1;
        }
    }
    // Every ruling end becomes a sample (mirrored ends already are; the ends of strips
    // left as they were may sit on a segment that took its partner's samples).
    let mut final_rulings: Vec<Vec<[CurvePoint; 2]>> = Vec::with_capacity(strips.len());
    for (s, old) in old_rulings.iter().enumerate() {
        let rulings = new_rulings[s].as_ref().unwrap_or(old);
        final_rulings.push(rulings.iter().map(|r| r.map(|p| ensure_sample(samples, p))).collect());
    }
    // Resample every strip and index its rulings (ends on either side).
    let mut sampled: Option<(usize, SampleLookup, SampleLookup)> = None;
    for (s, strip) in strips.iter_mut().enumerate() {
        // The strips of a group (one patch's runs, listed together) share their chains:
        // sampled and indexed once.
        let g = index.group_of[s];
        if sampled.as_ref().is_none_or(|(cached, _, _)| *cached != g) {
            sampled = Some((
                g,
                SampleLookup::new(SampledChain::new(network, samples, &strip.chain_a)),
                SampleLookup::new(SampledChain::new(network, samples, &strip.chain_b)),
            ));
        }
        let (_, lookup_a, lookup_b) = sampled.as_ref().expect("sampled above");
        let rulings = &final_rulings[s];
        let mut indexed: Vec<(usize, usize)> = Vec::with_capacity(rulings.len());
        let mut cost = 0;
        for r in rulings {
            let sides = index.sides(r[0].segment, g, &mut cost);
            let (a, b) = if sides & ON_A != 0 || sides & ON_B == 0 {
                (r[0], r[1])
            } else {
                (r[1], r[0])
            };
            if let (Some(k), Some(l)) = (
                lookup_a.nearest(network, a, &mut cost),
                lookup_b.nearest(network, b, &mut cost),
            ) {
                indexed.push((k, l));
            }
        }
        indexed.sort_unstable();
        let mut kept: Vec<(usize, usize)> = Vec::with_capacity(indexed.len());
        for r in indexed {
            match kept.last() {
                Some(&last) if r.0 <= last.0 || r.1 <= last.1 => {}
                _ => kept.push(r),
            }
        }
        if kept.len() < 2 {
            // Too few rulings survive: the strip keeps its own (resampled).
            kept = final_rulings[s]
                .iter()
                .filter_map(|r| {
                    Some((
                        lookup_a.nearest(network, r[0], &mut cost)?,
                        lookup_b.nearest(network, r[1], &mut cost)?,
                    ))
                })
                .collect();
        }
        charge_lookups(&mut lookups, cost, s, strip.patch)?;
        strip.rulings = kept;
        strip.side_a = lookup_a.chain.clone();
        strip.side_b = lookup_b.chain.clone();
    }
    Ok((y, info, map))
}

/// The mirror place of a place, when its segment is matched.
fn mirror_place_of(mirror_of: &[Option<(u32, bool)>], p: CurvePoint) -> Option<CurvePoint> {
    let (partner, reversed) = mirror_of[p.segment as usize]?;
    Some(CurvePoint {
        segment: partner,
        t: if reversed { 1.0 - p.t } else { p.t },
    })
}

/// Charges `cost` chain entries examined for ruled strip `s` (of patch `patch`) to
/// `spent`, against [`MAX_RULING_LOOKUP_WORK`].
fn charge_lookups(spent: &mut usize, cost: usize, s: usize, patch: usize) -> Result<(), PhotoError> {
    charge_field(
        spent,
        cost,
        MAX_RULING_LOOKUP_WORK,
        "chain entries examined",
        (
            "analysis.sample_spacing_px",
            "sample coarser or set analysis.symmetrize to false",
        ),
        || format!("placing the rulings of ruled strip {} (patch {})", s + 1, patch + 1),
    )
}

/// A segment is on a strip's chain a.
const ON_A: u8 = 1;
/// A segment is on a strip's chain b.
const ON_B: u8 = 2;

/// Which strips' chains hold each segment, built once. Strips with the same two chains
/// (the runs of rulings of one patch) form one group, so a segment is listed once per
/// patch whose cycle runs along it, not once per strip.
struct ChainIndex {
    /// Per strip, its group.
    group_of: Vec<usize>,
    /// Per group, its last strip.
    last_strip: Vec<usize>,
    /// Per segment, `(group, ON_A | ON_B)` for each group whose chains hold it, by
    /// increasing group.
    on: Vec<Vec<(usize, u8)>>,
}

impl ChainIndex {
    fn new(segment_count: usize, strips: &[RuledStrip]) -> Self {
        type Chain = Vec<(u32, bool)>;
        let key = |chain: &[crate::patch_cycles::HalfEdge]| -> Chain {
            chain.iter().map(|h| (h.segment, h.reversed)).collect()
        };
        let mut groups: std::collections::HashMap<(Chain, Chain), usize> = Default::default();
        let mut index = Self {
            group_of: Vec::with_capacity(strips.len()),
            last_strip: Vec::new(),
            on: vec![Vec::new(); segment_count],
        };
        for (s, strip) in strips.iter().enumerate() {
            let next = index.last_strip.len();
            let g = *groups.entry((key(&strip.chain_a), key(&strip.chain_b))).or_insert(next);
            index.group_of.push(g);
            if g < next {
                index.last_strip[g] = s;
                continue;
            }
            index.last_strip.push(s);
            for (chain, side) in [(&strip.chain_a, ON_A), (&strip.chain_b, ON_B)] {
                for h in chain {
                    let Some(list) = index.on.get_mut(h.segment as usize) else {
                        continue;
                    };
                    match list.last_mut() {
                        Some((last, sides)) if *last == g => *sides |= side,
                        _ => list.push((g, side)),
                    }
                }
            }
        }
        index
    }

    /// The groups whose chains hold segment `segment`.
    fn groups_on(&self, segment: u32) -> &[(usize, u8)] {
        self.on.get(segment as usize).map_or(&[], Vec::as_slice)
    }

    /// On which of group `g`'s chains segment `segment` lies (`ON_A`, `ON_B`); the
    /// entries examined go to `cost`.
    fn sides(&self, segment: u32, g: usize, cost: &mut usize) -> u8 {
        let list = self.groups_on(segment);
        *cost += 1 + list.len().max(1).ilog2() as usize;
        list.binary_search_by_key(&g, |&(group, _)| group)
            .map_or(0, |i| list[i].1)
    }

    /// The strip into which most of strip `s`'s rulings mirror, if more than half do
    /// (of strips with equally many, the last). The entries examined go to `cost`.
    fn mirror_strip(
        &self,
        rulings: &[Vec<[CurvePoint; 2]>],
        mirror_of: &[Option<(u32, bool)>],
        s: usize,
        cost: &mut usize,
    ) -> Option<usize> {
        // Votes per group: every strip of a group gets the same.
        let mut votes: std::collections::HashMap<usize, usize> = Default::default();
        for r in &rulings[s] {
            *cost += 1;
            let (Some(a), Some(b)) = (mirror_place_of(mirror_of, r[0]), mirror_place_of(mirror_of, r[1])) else {
                continue;
            };
            for &(g, on_a) in self.groups_on(a.segment) {
                let on_b = self.sides(b.segment, g, cost);
                let ab = on_a & ON_A != 0 && on_b & ON_B != 0;
                let ba = on_b & ON_A != 0 && on_a & ON_B != 0;
                if ab || ba {
                    *votes.entry(g).or_default() += 1;
                }
            }
        }
        let (v, best) = votes.iter().map(|(&g, &v)| (v, self.last_strip[g])).max()?;
        (v * 2 > rulings[s].len()).then_some(best)
    }
}

/// Makes a place a sample of its segment (or moves it onto a sample within 1e-12).
fn ensure_sample(samples: &mut CurveSamples, place: CurvePoint) -> CurvePoint {
    let params = &mut samples.parameters[place.segment as usize];
    let at = params.partition_point(|&t| t < place.t);
    for k in [at.wrapping_sub(1), at] {
        if let Some(&t) = params.get(k) {
            if (t - place.t).abs() <= 1e-12 {
                return CurvePoint {
                    segment: place.segment,
                    t,
                };
            }
        }
    }
    params.insert(at, place.t);
    place
}

/// Splits the curves of each symmetric pair (and each self-symmetric curve) where the
/// mirror image of a node of its partner falls (§5.3's correspondence: along the image
/// direction of the plane's normal), so that nodes mirror onto nodes and segments onto
/// segments. A mirror point within `tolerance` (pixels) of a node is taken to be that
/// node. The split is exact (de Casteljau) in the image and, for the 3D control points
/// `x` (`3 × point + axis`), in space, so neither the drawing nor the solved curves
/// change. A pair whose curves still do not match segment for segment is left unsplit.
/// Returns how many segments were split.
///
/// # Errors
/// [`PhotoError::Field`] on `analysis.symmetrize` when the search would take more than
/// [`MAX_MIRROR_SEARCH_EVALUATIONS`], or the matching of the split curves more than
/// [`MAX_SEGMENT_COMPARISONS`] (checked before the work; `network` and `x` are then
/// left as they were before the pair that failed).
pub fn split_at_mirror_nodes(
    network: &mut CurveNetwork,
    x: &mut Vec<f64>,
    plane: &SymmetryPlane,
    curve_pairs: &[[usize; 2]],
    tolerance: f64,
) -> Result<usize, PhotoError> {
    let mut count = 0;
    let (mut evaluations, mut comparisons) = (0, 0);
    for &[a, b] in curve_pairs {
        // Split in place; undone unless the pair then matches segment for segment.
        let undo = SplitUndo::new(network, x, a, b);
        let mut trial_count = 0;
        let directions: &[(usize, usize)] = if a == b { &[(a, a)] } else { &[(a, b), (b, a)] };
        for &(from, to) in directions {
            let nodes: Vec<Vector2<f64>> = network.curves[from]
                .segments
                .iter()
                .flat_map(|&s| {
                    let q = network.segments[s as usize].points;
                    [q[0], q[3]]
                })
                .map(|p| network.points[p as usize])
                .collect();
            // What is being done, for the error (the counts at the start).
            let onto = if from == to {
                "itself".to_string()
            } else {
                format!(
                    "{} ({} segments)",
                    curve_name(network, to),
                    network.curves[to].segments.len()
                )
            };
            let doing = format!(
                "finding where the nodes of curve {} ({} segments) mirror onto {onto}",
                curve_name(network, from),
                network.curves[from].segments.len(),
            );
            let step = || doing.clone();
            // One control-polygon test per node and segment, charged at once; the sign
            // tests and bisections of the segments that straddle a node's line, and the
            // tests of the segments each split adds, as they come.
            let nodes_count = nodes.len();
            let tests = nodes_count.saturating_mul(network.curves[to].segments.len());
            if let Err(e) = charge(
                &mut evaluations,
                tests,
                MAX_MIRROR_SEARCH_EVALUATIONS,
                "curve evaluations",
                step,
            ) {
                undo.restore(network, x);
                return Err(e);
            }
            for (k, p) in nodes.into_iter().enumerate() {
                let direction = plane.image_direction_at(p);
                let normal = Vector2::new(-direction.y, direction.x);
                // Crossings of `to` with the line through p along the direction.
                let mut best: Option<(f64, u32, f64)> = None;
                let mut work = 0usize;
                for &s in &network.curves[to].segments {
                    let control = network.control_points(s as usize);
                    // The curve lies in its control polygon's hull: no crossing when all
                    // four control points are strictly on one side of the line.
                    let offsets = control.map(|q| (q - p).dot(&normal));
                    let margin = 1e-9 * control.iter().fold(p.norm(), |m, q| m.max(q.norm())).max(1.0);
                    if offsets.iter().all(|&d| d > margin) || offsets.iter().all(|&d| d < -margin) {
                        continue;
                    }
                    let f = |t: f64| (cubic::point(&control, t) - p).dot(&normal);
                    let pieces = 32;
                    work += 2 * pieces;
                    for i in 0..pieces {
                        let Some(t) = cubic::bisect(f, i as f64 / pieces as f64, (i + 1) as f64 / pieces as f64) else {
                            continue;
                        };
                        work += BISECTION_EVALUATIONS;
                        let distance = (cubic::point(&control, t) - p).dot(&direction).abs();
                        if from == to && distance <= tolerance {
                            continue; // the node itself
                        }
                        if best.is_none_or(|(d, _, _)| distance < d) {
                            best = Some((distance, s, t));
                        }
                    }
                }
                // A split adds a segment for each node after this one to test.
                let added = if best.is_some() { nodes_count - k - 1 } else { 0 };
                if let Err(e) = charge(
                    &mut evaluations,
                    work + added,
                    MAX_MIRROR_SEARCH_EVALUATIONS,
                    "curve evaluations",
                    step,
                ) {
                    undo.restore(network, x);
                    return Err(e);
                }
                let Some((_, s, t)) = best else { continue };
                let control = network.control_points(s as usize);
                let q = cubic::point(&control, t);
                let near_node = network.curves[to].segments.iter().any(|&o| {
                    let ids = network.segments[o as usize].points;
                    [ids[0], ids[3]]
                        .iter()
                        .any(|&i| (network.points[i as usize] - q).norm() <= tolerance)
                });
                if near_node {
                    continue;
                }
                split_segment(network, x, s, t);
                trial_count += 1;
            }
        }
        let matched = if trial_count > 0 {
            match match_curves(network, x, plane, a, b, &mut comparisons) {
                Ok(m) => m.is_some(),
                Err(e) => {
                    undo.restore(network, x);
                    return Err(e);
                }
            }
        } else {
            false
        };
        if matched {
            count += trial_count;
        } else {
            undo.restore(network, x);
        }
    }
    Ok(count)
}

/// What [`split_segment`] may change while curves `a` and `b` are split, to put it back
/// (a trial costs the size of the two curves, not a copy of the network).
struct SplitUndo {
    point_count: usize,
    segment_count: usize,
    unknown_count: usize,
    /// Curve and its segment list.
    curves: Vec<(usize, Vec<u32>)>,
    segments: Vec<SavedSegment>,
}

/// A segment as it was before a trial split.
struct SavedSegment {
    segment: u32,
    /// Its control point indices.
    points: [u32; 4],
    /// Its two inner control points, in the image and in space.
    inner: [Vector2<f64>; 2],
    inner3: [Vec3; 2],
}

impl SplitUndo {
    fn new(network: &CurveNetwork, x: &[f64], a: usize, b: usize) -> Self {
        let curves: Vec<(usize, Vec<u32>)> = if a == b { vec![a] } else { vec![a, b] }
            .into_iter()
            .map(|c| (c, network.curves[c].segments.clone()))
            .collect();
        let segments = curves
            .iter()
            .flat_map(|(_, list)| list.iter())
            .map(|&segment| {
                let points = network.segments[segment as usize].points;
                SavedSegment {
                    segment,
                    points,
                    inner: [network.points[points[1] as usize], network.points[points[2] as usize]],
                    inner3: [point(x, points[1]), point(x, points[2])],
                }
            })
            .collect();
        Self {
            point_count: network.points.len(),
            segment_count: network.segments.len(),
            unknown_count: x.len(),
            curves,
            segments,
        }
    }

    fn restore(self, network: &mut CurveNetwork, x: &mut Vec<f64>) {
        for saved in self.segments {
            network.segments[saved.segment as usize].points = saved.points;
            for k in 0..2 {
                let i = saved.points[k + 1] as usize;
                network.points[i] = saved.inner[k];
                x[3 * i..3 * i + 3].copy_from_slice(saved.inner3[k].as_slice());
            }
        }
        for (c, list) in self.curves {
            network.curves[c].segments = list;
        }
        network.points.truncate(self.point_count);
        network.segments.truncate(self.segment_count);
        x.truncate(self.unknown_count);
    }
}

/// Splits segment `s` at `t` (de Casteljau): `s` keeps the first part, a new segment
/// after it in its curve takes the second.
fn split_segment(network: &mut CurveNetwork, x: &mut Vec<f64>, s: u32, t: f64) {
    let ids = network.segments[s as usize].points;
    // de Casteljau: the first half is (p0, a, d, m), the second (m, e, c, p3).
    fn de_casteljau<
        V: Copy + std::ops::Add<Output = V> + std::ops::Sub<Output = V> + std::ops::Mul<f64, Output = V>,
    >(
        p: [V; 4],
        t: f64,
    ) -> [V; 5] {
        let lerp = |a: V, b: V| a + (b - a) * t;
        let (a, b, c) = (lerp(p[0], p[1]), lerp(p[1], p[2]), lerp(p[2], p[3]));
        let (d, e) = (lerp(a, b), lerp(b, c));
        [a, d, lerp(d, e), e, c]
    }
    let [a, d, m, e, c] = de_casteljau(network.control_points(s as usize), t);
    network.points[ids[1] as usize] = a;
    network.points[ids[2] as usize] = c;
    let base = network.points.len() as u32;
    network.points.extend([d, m, e]);
    let [a, d, m, e, c] = de_casteljau(ids.map(|i| point(x, i)), t);
    x[3 * ids[1] as usize..3 * ids[1] as usize + 3].copy_from_slice(a.as_slice());
    x[3 * ids[2] as usize..3 * ids[2] as usize + 3].copy_from_slice(c.as_slice());
    for v in [d, m, e] {
        x.extend(v.iter());
    }
    let curve = network.segments[s as usize].curve;
    network.segments[s as usize].points = [ids[0], ids[1], base, base + 1];
    let new = network.segments.len() as u32;
    network.segments.push(crate::curve_network::NetworkSegment {
        points: [base + 1, base + 2, ids[2], ids[3]],
        curve,
    });
    let list = &mut network.curves[curve as usize].segments;
    let at = list.iter().position(|&x| x == s).expect("a segment is in its curve");
    list.insert(at + 1, new);
}

/// A sampled chain indexed for [`SampleLookup::nearest`]: its samples by segment and
/// parameter, and by position a grid (built at the first need).
struct SampleLookup {
    chain: SampledChain,
    /// `(segment, t, sample)` by segment, then increasing `t`, then sample.
    by_place: Vec<(u32, f64, usize)>,
    grid: std::cell::OnceCell<PositionGrid>,
}

/// The samples of a chain in square cells of side `cell`, a cell larger than four times
/// the tolerance of [`SampleLookup::nearest`] at any place that may be within it.
struct PositionGrid {
    /// Largest distance of a sample from the origin.
    radius: f64,
    cell: f64,
    /// Per cell, its samples in order.
    cells: std::collections::HashMap<(i64, i64), Vec<usize>>,
}

impl PositionGrid {
    fn cell_of(&self, p: Vector2<f64>) -> (i64, i64) {
        // (Saturating casts.)
        ((p.x / self.cell).floor() as i64, (p.y / self.cell).floor() as i64)
    }
}

impl SampleLookup {
    fn new(chain: SampledChain) -> Self {
        let mut by_place: Vec<(u32, f64, usize)> = chain
            .places
            .iter()
            .enumerate()
            .map(|(k, p)| (p.segment, p.t, k))
            .collect();
        // Stable: equal parameters stay in sample order (and a chain's samples mostly
        // come sorted already).
        by_place.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
        Self {
            chain,
            by_place,
            grid: std::cell::OnceCell::new(),
        }
    }

    fn grid(&self) -> &PositionGrid {
        self.grid.get_or_init(|| {
            let radius = self.chain.points.iter().fold(0.0f64, |m, p| m.max(p.norm()));
            let mut grid = PositionGrid {
                radius,
                cell: 4e-6 * (1.0 + radius),
                cells: Default::default(),
            };
            for (k, &p) in self.chain.points.iter().enumerate() {
                let c = grid.cell_of(p);
                grid.cells.entry(c).or_default().push(k);
            }
            grid
        })
    }

    /// The sample of the chain at a place: the same segment and parameter, else the
    /// nearest sample of that segment, else (a node reached through another segment) the
    /// nearest by position, within `1e-6 (1 + |q|)` of the place's position `q`. Of
    /// equally near samples, the first. The entries examined go to `cost`.
    fn nearest(&self, network: &CurveNetwork, place: CurvePoint, cost: &mut usize) -> Option<usize> {
        // Lexicographic minimum of (distance, sample).
        let better = |d: f64, k: usize, best: Option<(f64, usize)>| {
            best.is_none_or(|(bd, bk)| d.total_cmp(&bd).then(k.cmp(&bk)) == std::cmp::Ordering::Less)
        };
        let from = self.by_place.partition_point(|e| e.0 < place.segment);
        let to = from + self.by_place[from..].partition_point(|e| e.0 == place.segment);
        *cost += 2 * (1 + self.by_place.len().max(1).ilog2() as usize);
        let list = &self.by_place[from..to];
        if !list.is_empty() {
            if !place.t.is_finite() {
                // Every distance is the same (NaN or infinite): the first sample.
                *cost += list.len();
                return list.iter().map(|e| e.2).min();
            }
            // |t − q| (rounded) does not decrease away from q on either side: the
            // nearest are the runs of equal distance next to q.
            let at = list.partition_point(|e| e.1 < place.t);
            *cost += 1 + list.len().max(1).ilog2() as usize;
            let mut best: Option<(f64, usize)> = None;
            for run in [
                &mut list[at..].iter() as &mut dyn Iterator<Item = &(u32, f64, usize)>,
                &mut list[..at].iter().rev(),
            ] {
                for &(_, t, k) in run {
                    *cost += 1;
                    let d = (t - place.t).abs();
                    if best.is_some_and(|(bd, _)| d.total_cmp(&bd) == std::cmp::Ordering::Greater) {
                        break;
                    }
                    if better(d, k, best) {
                        best = Some((d, k));
                    }
                }
            }
            return best.map(|(_, k)| k);
        }
        if self.chain.is_empty() {
            return None;
        }
        let q = cubic::point(&network.control_points(place.segment as usize), place.t);
        let tolerance = 1e-6 * (1.0 + q.norm());
        if !(q.x.is_finite() && q.y.is_finite()) {
            // (Not from a finite drawing.) Every sample, as the grid cannot place q.
            *cost += self.chain.len();
            let (k, d) = self
                .chain
                .points
                .iter()
                .enumerate()
                .map(|(k, p)| (k, (p - q).norm()))
                .min_by(|a, b| a.1.total_cmp(&b.1))?;
            return (d <= tolerance).then_some(k);
        }
        let grid = self.grid();
        // Farther than the tolerance from every sample; else the tolerance is
        // under a quarter of a cell, and every sample within it is in the 3 × 3 cells
        // round q's.
        if q.norm() > grid.radius + 2.0 * tolerance {
            return None;
        }
        let (cx, cy) = grid.cell_of(q);
        let mut best: Option<(f64, usize)> = None;
        for i in cx.saturating_sub(1)..=cx.saturating_add(1) {
            for j in cy.saturating_sub(1)..=cy.saturating_add(1) {
                for &k in grid.cells.get(&(i, j)).map_or(&[][..], Vec::as_slice) {
                    *cost += 1;
                    let d = (self.chain.points[k] - q).norm();
                    if better(d, k, best) {
                        best = Some((d, k));
                    }
                }
            }
        }
        let (k, d) = best.map(|(d, k)| (k, d))?;
        (d <= tolerance).then_some(k)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::annotation::CurveKind;
    use crate::curve_network::{NetworkCurve, NetworkSegment};
    use crate::curve_samples::sample_curves;
    use crate::patch_cycles::HalfEdge;

    type Vec2 = Vector2<f64>;

    /// The strip lookups before the indices (linear scans), to compare with.
    fn on_chain_scan(chain: &[HalfEdge], p: CurvePoint) -> bool {
        chain.iter().any(|h| h.segment == p.segment)
    }

    fn mirror_strip_scan(
        strips: &[RuledStrip],
        rulings: &[Vec<[CurvePoint; 2]>],
        mirror_of: &[Option<(u32, bool)>],
        s: usize,
    ) -> Option<usize> {
        let mut votes = vec![0usize; strips.len()];
        for r in &rulings[s] {
            let (Some(a), Some(b)) = (mirror_place_of(mirror_of, r[0]), mirror_place_of(mirror_of, r[1])) else {
                continue;
            };
            for (o, other) in strips.iter().enumerate() {
                let ab = on_chain_scan(&other.chain_a, a) && on_chain_scan(&other.chain_b, b);
                let ba = on_chain_scan(&other.chain_a, b) && on_chain_scan(&other.chain_b, a);
                if ab || ba {
                    votes[o] += 1;
                }
            }
        }
        let (best, &v) = votes.iter().enumerate().max_by_key(|(_, v)| **v)?;
        (v * 2 > rulings[s].len()).then_some(best)
    }

    fn nearest_sample_scan(network: &CurveNetwork, chain: &SampledChain, place: CurvePoint) -> Option<usize> {
        let same = chain
            .places
            .iter()
            .enumerate()
            .filter(|(_, p)| p.segment == place.segment)
            .min_by(|a, b| (a.1.t - place.t).abs().total_cmp(&(b.1.t - place.t).abs()));
        if let Some((k, _)) = same {
            return Some(k);
        }
        let q = cubic::point(&network.control_points(place.segment as usize), place.t);
        let (k, d) = chain
            .points
            .iter()
            .enumerate()
            .map(|(k, p)| (k, (p - q).norm()))
            .min_by(|a, b| a.1.total_cmp(&b.1))?;
        (d <= 1e-6 * (1.0 + q.norm())).then_some(k)
    }

    /// A deterministic pseudo-random stream in [0, 1).
    fn stream(mut state: u64) -> impl FnMut() -> f64 {
        move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// Open curves of `n` straight segments each along `x = xs[c]`, `y` from 0 to `n`.
    fn lines(xs: &[f64], n: usize) -> CurveNetwork {
        let (mut points, mut segments, mut curves) = (Vec::new(), Vec::new(), Vec::new());
        for (c, &x) in xs.iter().enumerate() {
            let base = points.len() as u32;
            for k in 0..=n {
                let y = k as f64;
                points.push(Vec2::new(x, y));
                if k < n {
                    points.extend([Vec2::new(x, y + 1.0 / 3.0), Vec2::new(x, y + 2.0 / 3.0)]);
                }
            }
            let first = segments.len() as u32;
            segments.extend((0..n as u32).map(|k| NetworkSegment {
                points: [base + 3 * k, base + 3 * k + 1, base + 3 * k + 2, base + 3 * k + 3],
                curve: c as u32,
            }));
            curves.push(NetworkCurve {
                name: format!("line {c}"),
                kind: CurveKind::Boundary,
                segments: (first..first + n as u32).collect(),
                closed: false,
            });
        }
        CurveNetwork {
            points,
            segments,
            curves,
            junction_count: 0,
            occluded_crossing_count: 0,
        }
    }

    fn half_edges(segments: impl IntoIterator<Item = u32>, reversed: bool) -> Vec<HalfEdge> {
        segments
            .into_iter()
            .map(|segment| HalfEdge { segment, reversed })
            .collect()
    }

    fn strip(patch: usize, chain_a: Vec<HalfEdge>, chain_b: Vec<HalfEdge>) -> RuledStrip {
        RuledStrip {
            patch,
            side_a: SampledChain::default(),
            side_b: SampledChain::default(),
            rulings: Vec::new(),
            chain_a,
            chain_b,
        }
    }

    /// The indexed nearest sample is the scan's, ties (a segment traversed twice, a
    /// parameter halfway between samples, coincident nodes) and misses included.
    #[test]
    fn sample_lookup_matches_the_linear_scan() {
        let mut network = lines(&[0.0, 5.0], 8);
        // Curved handles, and a zero-length segment at the end of line 0.
        network.points[1] = Vec2::new(0.7, 0.1);
        network.points[5] = Vec2::new(-0.4, 1.9);
        let end = network.curves[0].segments[7] as usize;
        let node = network.segments[end].points[3];
        let q = network.points[node as usize];
        network.points.extend([q, q, q]);
        let base = network.points.len() as u32 - 3;
        network.segments.push(NetworkSegment {
            points: [node, base, base + 1, base + 2],
            curve: 0,
        });
        let samples = sample_curves(&network, 0.3);
        let segment_count = network.segments.len() as u32;
        let chains = [
            half_edges(0..4, false),
            // Segment 2 both ways, segment 6 backwards, the zero-length one.
            [
                half_edges(1..3, false),
                half_edges([2, 6], true),
                half_edges([16], false),
            ]
            .concat(),
            half_edges([8, 9, 10, 3], false),
            Vec::new(),
        ];
        let mut random = stream(7);
        for chain in &chains {
            let sampled = SampledChain::new(&network, &samples, chain);
            let lookup = SampleLookup::new(sampled.clone());
            let mut places: Vec<CurvePoint> = Vec::new();
            for segment in 0..segment_count {
                let params = &samples.parameters[segment as usize];
                let mut ts: Vec<f64> = params.clone();
                ts.extend(params.windows(2).map(|w| 0.5 * (w[0] + w[1])));
                ts.extend(params.iter().map(|t| t + 1e-13));
                ts.extend((0..5).map(|_| random()));
                ts.extend([-0.5, 1.5, f64::NAN, f64::INFINITY]);
                places.extend(ts.into_iter().map(|t| CurvePoint { segment, t }));
            }
            let mut found = 0;
            for place in places {
                let mut cost = 0;
                let got = lookup.nearest(&network, place, &mut cost);
                let expected = nearest_sample_scan(&network, &sampled, place);
                assert_eq!(got, expected, "{place:?}");
                found += usize::from(got.is_some());
            }
            assert!(chain.is_empty() || found > 0);
        }
    }

    /// The chain index gives the scans' sides and mirror strips, over random strips
    /// (repeated chains, one chain on both sides, empty ones) and random rulings.
    #[test]
    fn chain_index_matches_the_scans() {
        let network = lines(&[-3.0, 3.0], 6);
        let n = network.segments.len() as u32;
        let mut random = stream(11);
        let mut pick = |k: u32| (random() * f64::from(k)) as u32;
        for _ in 0..300 {
            let mut strips: Vec<RuledStrip> = Vec::new();
            let count = 1 + pick(6) as usize;
            for s in 0..count {
                let chain_of = |pick: &mut dyn FnMut(u32) -> u32| -> Vec<HalfEdge> {
                    (0..pick(5))
                        .map(|_| HalfEdge {
                            segment: pick(n),
                            reversed: pick(2) == 1,
                        })
                        .collect()
                };
                let next = match pick(4) {
                    0 if s > 0 => strips[pick(s as u32) as usize].clone(),
                    1 => {
                        let a = chain_of(&mut pick);
                        let b = a.iter().rev().map(|h| h.twin()).collect();
                        strip(s, a, b)
                    }
                    _ => strip(s, chain_of(&mut pick), chain_of(&mut pick)),
                };
                strips.push(next);
            }
            let mirror_of: Vec<Option<(u32, bool)>> = (0..n)
                .map(|s| (pick(4) > 0).then(|| ((s + n / 2) % n, pick(2) == 1)))
                .collect();
            let place = |pick: &mut dyn FnMut(u32) -> u32| CurvePoint {
                segment: pick(n),
                t: f64::from(pick(4)) / 3.0,
            };
            let rulings: Vec<Vec<[CurvePoint; 2]>> = (0..count)
                .map(|_| (0..pick(6)).map(|_| [place(&mut pick), place(&mut pick)]).collect())
                .collect();
            let index = ChainIndex::new(n as usize, &strips);
            for s in 0..count {
                let mut cost = 0;
                assert_eq!(
                    index.mirror_strip(&rulings, &mirror_of, s, &mut cost),
                    mirror_strip_scan(&strips, &rulings, &mirror_of, s)
                );
                for segment in 0..n {
                    let p = CurvePoint { segment, t: 0.5 };
                    let sides = index.sides(segment, index.group_of[s], &mut cost);
                    assert_eq!(sides & ON_A != 0, on_chain_scan(&strips[s].chain_a, p));
                    assert_eq!(sides & ON_B != 0, on_chain_scan(&strips[s].chain_b, p));
                }
            }
        }
    }

    /// The strip lookups cost a few entries a ruling however long the chains and however
    /// many strips share them: one patch of two mirror-image lines of 20 000 segments
    /// (90 000 samples a side) with a ruling at every sample, and 200 strips of 10
    /// rulings over lines of 2 000 segments (within the strips' sample bound). The
    /// scans took `rulings × chain length` (8e9 here: 11 s in a release build) and
    /// `strips² × rulings × chain length` (1.3 s).
    #[test]
    fn ruling_lookups_are_linear_in_the_rulings() {
        let plane = SymmetryPlane {
            normal: Vec3::new(1.0, 0.0, 0.0),
            point: Vec3::zeros(),
            camera: crate::Camera::orthographic(),
        };
        for (n, strip_count, per_strip) in [(20_000, 1, None), (2_000, 200, Some(10))] {
            let network = lines(&[10.0, -10.0], n);
            let x = crate::curve_lifting::image_prior(&network, &crate::Camera::orthographic(), 0.0);
            let mut samples = sample_curves(&network, 0.25);
            let chain = |c: usize| half_edges(network.curves[c].segments.iter().copied(), false);
            let sides = [chain(0), chain(1)].map(|c| SampledChain::new(&network, &samples, &c));
            let len = sides[0].len();
            let mut strips: Vec<RuledStrip> = (0..strip_count)
                .map(|s| {
                    let mut out = strip(0, chain(0), chain(1));
                    out.side_a = sides[0].clone();
                    out.side_b = sides[1].clone();
                    out.rulings = match per_strip {
                        None => (0..len).map(|k| (k, k)).collect(),
                        Some(r) => {
                            let start = s * (len - r) / strip_count;
                            (start..start + r).map(|k| (k, k)).collect()
                        }
                    };
                    out
                })
                .collect();
            let ruling_count: usize = strips.iter().map(|s| s.rulings.len()).sum();
            // The lookups symmetrize makes, counted.
            let old: Vec<Vec<[CurvePoint; 2]>> = strips
                .iter()
                .map(|s| (0..s.rulings.len()).map(|i| s.ends(i)).collect())
                .collect();
            let mut mirror_of = vec![None; network.segments.len()];
            for k in 0..n {
                mirror_of[k] = Some(((k + n) as u32, false));
                mirror_of[k + n] = Some((k as u32, false));
            }
            let index = ChainIndex::new(network.segments.len(), &strips);
            let lookups = [SampleLookup::new(sides[0].clone()), SampleLookup::new(sides[1].clone())];
            let mut cost = 0;
            for s in 0..strips.len() {
                let o = index.mirror_strip(&old, &mirror_of, s, &mut cost);
                assert_eq!(o, Some(strips.len() - 1));
                for r in &old[s] {
                    index.sides(r[0].segment, index.group_of[s], &mut cost);
                    for (lookup, &place) in lookups.iter().zip(r) {
                        assert!(lookup.nearest(&network, place, &mut cost).is_some());
                    }
                }
            }
            assert!(cost <= 100 * ruling_count, "{cost} entries for {ruling_count} rulings");
            // And the whole symmetrisation: one strip mirrored onto itself, every
            // ruling (crossing the plane) kept.
            let (_, info, _) = symmetrize(&network, &mut samples, &mut strips, &plane, &[[0, 1]], &x).unwrap();
            assert_eq!(info.mirrored_segment_count, n);
            assert_eq!(info.mirrored_strip_count, 1);
            let last = strips.last().unwrap();
            assert_eq!(last.rulings.len(), per_strip.unwrap_or(len));
            assert!(last.rulings.iter().all(|&(k, l)| k == l));
        }
    }

    /// Coincident samples (a chain of zero-length segments at one node) are the one
    /// place a lookup examines many entries: charged, and refused naming the spacing.
    #[test]
    fn coincident_samples_are_charged() {
        let mut network = lines(&[0.0], 1);
        let node = network.segments[0].points[3];
        let count = 30_000u32;
        for _ in 0..count {
            network.segments.push(NetworkSegment {
                points: [node; 4],
                curve: 0,
            });
        }
        let samples = sample_curves(&network, 0.3);
        let chain = SampledChain::new(&network, &samples, &half_edges(1..=count, false));
        let lookup = SampleLookup::new(chain);
        // The line's end, through the grid: every coincident sample is examined.
        let place = CurvePoint { segment: 0, t: 1.0 };
        let mut cost = 0;
        assert_eq!(lookup.nearest(&network, place, &mut cost), Some(0));
        assert!(cost > count as usize);
        let mut spent = 0;
        let error = (0..)
            .find_map(|_| charge_lookups(&mut spent, cost, 2, 4).err())
            .unwrap()
            .to_string();
        assert!(
            error.contains("analysis.sample_spacing_px")
                && error.contains("ruled strip 3 (patch 5)")
                && error.contains(&format!("at most {}", short_number(MAX_RULING_LOOKUP_WORK as f64))),
            "{error}"
        );
    }
}

//! Rulings propagated from straight silhouettes by dynamic time warping (§5.2, Eq. 2).
//!
//! A silhouette of a developable surface is a ruling (§3, Appendix A). Assuming the patch
//! is a generalised cone cut by two parallel planes, the two curves leaving the
//! silhouette's ends have parallel tangents where a ruling meets them, so the rulings are
//! a monotone matching of samples `C_i(k)`, `C_j(l)` of those two curves minimising
//!
//! `γ(k, l) = α(Ċ_i(k), Ċ_j(l)) + min_{(r,s)} [γ(r, s) + λ α(C_i(k) − C_j(l), C_i(r) − C_j(s))]`
//!
//! over the predecessors `(r, s) ∈ {(k−1, l−1), (k−1, l), (k, l−1)}` (Eq. 2): `α` of the
//! tangents is the angle between their *lines* (in `[0, π/2]`: the curves may run either
//! way), `α` of two rulings the angle between the vectors, and `λ` the
//! `dtw_smoothness_weight` (the paper gives no value; 1 by default). Angles in radians,
//! samples about `sample_spacing_px` apart.
//!
//! Which curves are matched (the paper shows it, Fig. 6, without a rule): going round the
//! patch from the silhouette, the two chains run on both sides until the *next*
//! silhouette of the same patch (a cylinder or cone seen whole: closed-end matching to the
//! far silhouette) or, with a single silhouette, until they meet (open end: the matching
//! stops at the cell of least mean cost on the frontier where the chains meet).
//! From the warping path, rulings are kept about `ruling_spacing_px` apart; each kept
//! ruling must lie inside its patch (9 interior points tested) or it is rejected, as in
//! the paper; the surviving consecutive rulings form ruled strips.

use crate::curve_network::CurveNetwork;
use crate::curve_samples::{CurvePoint, CurveSamples, SampledChain};
use crate::patch_cycles::{HalfEdge, Patch};
use crate::{CurveKind, PhotoError};
use nalgebra::Vector2;
use sheetform_geometry::short_number;

type Vec2 = Vector2<f64>;

/// A run of consecutive rulings in one patch: the part of the patch the rulings sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct RuledStrip {
    /// The patch (index into the patch list).
    pub patch: usize,
    /// The chain on the first side (starting at the silhouette's end).
    pub side_a: SampledChain,
    /// The chain on the other side.
    pub side_b: SampledChain,
    /// Rulings as sample-index pairs `(k on side_a, l on side_b)`, increasing.
    pub rulings: Vec<(usize, usize)>,
    /// The half-edges of side a (to resample the chain).
    pub chain_a: Vec<HalfEdge>,
    /// The half-edges of side b.
    pub chain_b: Vec<HalfEdge>,
}

impl RuledStrip {
    /// The network places of ruling `i`'s two ends.
    pub fn ends(&self, i: usize) -> [CurvePoint; 2] {
        let (k, l) = self.rulings[i];
        [self.side_a.places[k], self.side_b.places[l]]
    }

    /// Ruling `i` in the image (model frame).
    pub fn segment(&self, i: usize) -> [Vec2; 2] {
        let (k, l) = self.rulings[i];
        [self.side_a.points[k], self.side_b.points[l]]
    }
}

/// What the propagation did, for the report.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PropagationCounts {
    /// Rulings taken from the warping paths before the inside test.
    pub candidate_count: usize,
    /// Rulings rejected because they leave their patch.
    pub rejected_count: usize,
}

/// Knobs of [`propagate_rulings`] (pixels and the DTW weight).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PropagationOptions {
    /// Spacing of kept rulings.
    pub ruling_spacing: f64,
    /// `λ` of Eq. 2.
    pub smoothness_weight: f64,
}

/// Most sample pairs one warping may weigh (the table of Eq. 2 is quadratic).
pub const MAX_WARPING_CELLS: usize = 20_000_000;

/// Most sample pairs the warpings of all patches together may weigh. A cell takes about
/// 70 ns (measured: 7.7 million cells of one cylinder in 0.5 s), so about 7 s; the
/// table is freed after each patch, so [`MAX_WARPING_CELLS`] bounds the memory. Without
/// it 90 patches of 20 million cells each (the 200 000 samples split between them) would
/// take two minutes.
pub const MAX_WARPING_CELLS_TOTAL: usize = 100_000_000;

/// Most samples the ruled strips may hold together. Each strip (a run of rulings inside
/// its patch) keeps copies of its patch's two sampled chains, which the later stages
/// resample in turn: a patch whose rulings leave it every third time (a wavy outline)
/// makes a strip per run, each holding the whole chains (quadratic memory: about
/// 0.8 GB for one patch of 4 500 samples a side). 4 million samples are about
/// 230 MB (56 bytes a sample); a patch holds its chains once or a few times, and the
/// curves have at most [`crate::MAX_CURVE_SAMPLES`] samples.
pub const MAX_STRIP_SAMPLES: usize = 4_000_000;

/// Rulings of every patch bounded by a silhouette.
///
/// # Errors
/// [`PhotoError::Field`] on `analysis.sample_spacing_px` when a warping would exceed
/// [`MAX_WARPING_CELLS`], all of them [`MAX_WARPING_CELLS_TOTAL`], or the strips would
/// hold more than [`MAX_STRIP_SAMPLES`] samples.
pub fn propagate_rulings(
    network: &CurveNetwork,
    samples: &CurveSamples,
    patches: &[Patch],
    options: &PropagationOptions,
) -> Result<(Vec<RuledStrip>, PropagationCounts), PhotoError> {
    // The warping tables' sizes first: one too large (~180 MB) or all together too long
    // (~70 ns a cell: ~7 s) is refused before any work.
    let mut cells_total = 0usize;
    for (p, patch) in patches.iter().enumerate() {
        if patch.opening {
            continue;
        }
        let Some((chain_a, chain_b, _)) = matching_chains(network, &patch.cycle) else {
            continue;
        };
        let (len_a, len_b) = (
            chain_sample_count(samples, &chain_a),
            chain_sample_count(samples, &chain_b),
        );
        if len_a < 2 || len_b < 2 {
            continue;
        }
        if len_a * len_b > MAX_WARPING_CELLS {
            return Err(PhotoError::field(
                "analysis.sample_spacing_px",
                format!(
                    "patch {}'s two chains have {len_a} × {len_b} samples (at most {MAX_WARPING_CELLS} pairs): \
                     sample coarser",
                    p + 1
                ),
            ));
        }
        cells_total += len_a * len_b;
    }
    if cells_total > MAX_WARPING_CELLS_TOTAL {
        return Err(PhotoError::field(
            "analysis.sample_spacing_px",
            format!(
                "the ruling warpings of all patches weigh {} sample pairs (at most {}): sample coarser",
                short_number(cells_total as f64),
                short_number(MAX_WARPING_CELLS_TOTAL as f64)
            ),
        ));
    }
    let mut strips = Vec::new();
    let mut counts = PropagationCounts::default();
    let mut strip_samples = 0usize;
    for (p, patch) in patches.iter().enumerate() {
        if patch.opening {
            continue;
        }
        let Some((chain_a, chain_b, closed_end)) = matching_chains(network, &patch.cycle) else {
            continue;
        };
        let side_a = SampledChain::new(network, samples, &chain_a);
        let side_b = SampledChain::new(network, samples, &chain_b);
        if side_a.len() < 2 || side_b.len() < 2 {
            continue;
        }
        let path = warping_path(&side_a, &side_b, closed_end, options.smoothness_weight);
        let chosen = thin_path(&path, &side_a, &side_b, options.ruling_spacing);
        counts.candidate_count += chosen.len();
        // The first ruling is the silhouette (on the boundary), and so is the last of a
        // closed-end match; the rest must lie inside the patch.
        let last = chosen.len() - 1;
        let mut run: Vec<(usize, usize)> = Vec::new();
        // Each strip holds copies of both chains: bounded in all (~230 MB).
        let held = side_a.len() + side_b.len();
        let flush = |run: &mut Vec<(usize, usize)>,
                     strips: &mut Vec<RuledStrip>,
                     strip_samples: &mut usize|
         -> Result<(), PhotoError> {
            if run.len() >= 2 {
                *strip_samples += held;
                if *strip_samples > MAX_STRIP_SAMPLES {
                    return Err(PhotoError::field(
                        "analysis.sample_spacing_px",
                        format!(
                            "the ruled strips hold {} samples by patch {} (at most {} in all: each strip keeps \
                             its patch's two curve chains, and the rulings leave patch {} between strips): \
                             sample coarser",
                            short_number(*strip_samples as f64),
                            p + 1,
                            short_number(MAX_STRIP_SAMPLES as f64),
                            p + 1
                        ),
                    ));
                }
                strips.push(RuledStrip {
                    patch: p,
                    side_a: side_a.clone(),
                    side_b: side_b.clone(),
                    rulings: std::mem::take(run),
                    chain_a: chain_a.clone(),
                    chain_b: chain_b.clone(),
                });
            } else {
                run.clear();
            }
            Ok(())
        };
        for (i, &(k, l)) in chosen.iter().enumerate() {
            let on_boundary = i == 0 || (closed_end && i == last);
            let (a, b) = (side_a.points[k], side_b.points[l]);
            let degenerate = (a - b).norm() < 1e-9;
            let inside = on_boundary
                || (!degenerate && (1..10).all(|j| patch.polygon.contains(a + (b - a) * (j as f64 / 10.0))));
            if inside && !degenerate {
                run.push((k, l));
            } else {
                if !degenerate {
                    counts.rejected_count += 1;
                }
                flush(&mut run, &mut strips, &mut strip_samples)?;
            }
        }
        flush(&mut run, &mut strips, &mut strip_samples)?;
    }
    Ok((strips, counts))
}

/// Samples of [`SampledChain::new`] on a chain (shared nodes once), without sampling it.
fn chain_sample_count(samples: &CurveSamples, chain: &[HalfEdge]) -> usize {
    if chain.is_empty() {
        return 0;
    }
    1 + chain
        .iter()
        .map(|h| samples.parameters[h.segment as usize].len().saturating_sub(1))
        .sum::<usize>()
}

/// The two chains to match in a patch's cycle and whether the match is closed-ended
/// (between two silhouettes), or `None` when the patch has no silhouette.
fn matching_chains(network: &CurveNetwork, cycle: &[HalfEdge]) -> Option<(Vec<HalfEdge>, Vec<HalfEdge>, bool)> {
    let n = cycle.len();
    let is_silhouette = |h: &HalfEdge| {
        network.curves[network.segments[h.segment as usize].curve as usize].kind == CurveKind::Silhouette
    };
    // Runs of consecutive silhouette half-edges: (first index, length).
    let flags: Vec<bool> = cycle.iter().map(is_silhouette).collect();
    if flags.iter().all(|&f| f) || !flags.iter().any(|&f| f) {
        return None;
    }
    let start = (0..n).find(|&i| !flags[i]).expect("a non-silhouette half-edge");
    let mut runs: Vec<(usize, usize, f64)> = Vec::new();
    let mut i = 0;
    while i < n {
        let idx = (start + i) % n;
        if flags[idx] {
            let mut len = 0;
            let mut chord = 0.0;
            while len < n && flags[(idx + len) % n] {
                let b = cycle[(idx + len) % n].control_points(network);
                chord += (b[3] - b[0]).norm();
                len += 1;
            }
            runs.push((idx, len, chord));
            i += len;
        } else {
            i += 1;
        }
    }
    let take = |from: usize, count: usize| -> Vec<HalfEdge> { (0..count).map(|k| cycle[(from + k) % n]).collect() };
    if runs.len() == 1 {
        let (first, len, _) = runs[0];
        let rest = n - len;
        let after = (first + len) % n;
        let a = take(after, rest);
        let b: Vec<HalfEdge> = a.iter().rev().map(|h| h.twin()).collect();
        return Some((a, b, false));
    }
    // The two longest silhouette runs, in cycle order.
    let mut order: Vec<usize> = (0..runs.len()).collect();
    order.sort_by(|&x, &y| runs[y].2.total_cmp(&runs[x].2));
    let (mut r1, mut r2) = (runs[order[0]], runs[order[1]]);
    if (r2.0 + n - r1.0) % n < (r1.0 + n - r2.0) % n {
        // r1 first going round from r1 … fine as is.
    } else {
        std::mem::swap(&mut r1, &mut r2);
    }
    // Side a: after r1's end up to r2's start; side b: before r1's start back to r2's end.
    let a_from = (r1.0 + r1.1) % n;
    let a_len = (r2.0 + n - a_from) % n;
    let b_from = (r2.0 + r2.1) % n;
    let b_len = (r1.0 + n - b_from) % n;
    if a_len == 0 || b_len == 0 {
        return None;
    }
    let a = take(a_from, a_len);
    let b: Vec<HalfEdge> = take(b_from, b_len).iter().rev().map(|h| h.twin()).collect();
    Some((a, b, true))
}

/// Angle between two lines (radians, `[0, π/2]`).
fn line_angle(u: Vec2, v: Vec2) -> f64 {
    let c = (u.dot(&v) / (u.norm() * v.norm())).abs();
    if c.is_finite() {
        c.min(1.0).acos()
    } else {
        0.0
    }
}

/// Angle between two vectors (radians, `[0, π]`); zero when one vanishes.
fn vector_angle(u: Vec2, v: Vec2) -> f64 {
    let n = u.norm() * v.norm();
    if n < 1e-300 {
        return 0.0;
    }
    (u.x * v.y - u.y * v.x).atan2(u.dot(&v)).abs()
}

/// Dynamic time warping of Eq. 2; returns the path from `(0, 0)`.
fn warping_path(a: &SampledChain, b: &SampledChain, closed_end: bool, lambda: f64) -> Vec<(usize, usize)> {
    let (n, m) = (a.len(), b.len());
    let total = a.arc_length[n - 1];
    // Open end: both chains run over the same curve from opposite ends; a match is
    // valid while they have not passed each other.
    let valid = |k: usize, l: usize| closed_end || a.arc_length[k] + b.arc_length[l] <= total * (1.0 + 1e-12);
    let mut gamma = vec![f64::INFINITY; n * m];
    let mut from = vec![u8::MAX; n * m];
    let at = |k: usize, l: usize| k * m + l;
    for k in 0..n {
        for l in 0..m {
            if !valid(k, l) {
                continue;
            }
            let local = line_angle(a.tangents[k], b.tangents[l]);
            if k == 0 && l == 0 {
                gamma[0] = local;
                continue;
            }
            let ruling = a.points[k] - b.points[l];
            let mut best = (f64::INFINITY, u8::MAX);
            for (code, (r, s)) in [
                (0u8, (k.wrapping_sub(1), l.wrapping_sub(1))),
                (1, (k.wrapping_sub(1), l)),
                (2, (k, l.wrapping_sub(1))),
            ] {
                if r >= n || s >= m || !gamma[at(r, s)].is_finite() {
                    continue;
                }
                let c = gamma[at(r, s)] + lambda * vector_angle(ruling, a.points[r] - b.points[s]);
                if c < best.0 {
                    best = (c, code);
                }
            }
            if best.1 != u8::MAX {
                gamma[at(k, l)] = local + best.0;
                from[at(k, l)] = best.1;
            }
        }
    }
    let end = if closed_end {
        (n - 1, m - 1)
    } else {
        // The frontier: valid cells with no valid successor; the least mean cost.
        let mut best = ((0, 0), f64::INFINITY);
        for k in 0..n {
            for l in 0..m {
                if !gamma[at(k, l)].is_finite() {
                    continue;
                }
                let next_a = k + 1 < n && valid(k + 1, l);
                let next_b = l + 1 < m && valid(k, l + 1);
                if next_a || next_b {
                    continue;
                }
                let mean = gamma[at(k, l)] / (k + l + 1) as f64;
                if mean < best.1 {
                    best = ((k, l), mean);
                }
            }
        }
        best.0
    };
    let mut path = vec![end];
    let (mut k, mut l) = end;
    while (k, l) != (0, 0) {
        match from[at(k, l)] {
            0 => {
                k -= 1;
                l -= 1;
            }
            1 => k -= 1,
            2 => l -= 1,
            _ => break,
        }
        path.push((k, l));
    }
    path.reverse();
    path
}

/// Keeps path cells about `spacing` apart (by the mean arc length of the two sides), the
/// first and the last always.
fn thin_path(path: &[(usize, usize)], a: &SampledChain, b: &SampledChain, spacing: f64) -> Vec<(usize, usize)> {
    let measure = |&(k, l): &(usize, usize)| 0.5 * (a.arc_length[k] + b.arc_length[l]);
    let mut out = vec![path[0]];
    let mut last = measure(&path[0]);
    for cell in &path[1..] {
        let m = measure(cell);
        if m - last >= spacing {
            out.push(*cell);
            last = m;
        }
    }
    let end = *path.last().expect("a path has cells");
    if *out.last().expect("non-empty") != end {
        if out.len() > 1 && measure(&end) - measure(&out[out.len() - 2]) < 1.5 * spacing {
            out.pop();
        }
        out.push(end);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chain(points: Vec<Vec2>) -> SampledChain {
        let mut c = SampledChain::default();
        for (i, &p) in points.iter().enumerate() {
            let d = if i + 1 < points.len() {
                points[i + 1] - p
            } else {
                p - points[i - 1]
            };
            c.arc_length.push(
                c.arc_length.last().copied().unwrap_or(0.0) + c.points.last().map_or(0.0, |&q: &Vec2| (p - q).norm()),
            );
            c.points.push(p);
            c.tangents.push(d.normalize());
            c.places.push(CurvePoint { segment: 0, t: 0.0 });
        }
        c
    }

    /// Two translated copies of a curve (a generalised cylinder seen orthographically):
    /// the warping must match each sample with its translate, the exact rulings.
    #[test]
    fn translated_curves_match_sample_for_sample() {
        let curve = |shift: f64| -> Vec<Vec2> {
            (0..=40)
                .map(|i| {
                    let s = std::f64::consts::PI * i as f64 / 40.0;
                    Vec2::new(60.0 * s.cos(), 20.0 * s.sin() + shift)
                })
                .collect()
        };
        let a = chain(curve(0.0));
        let b = chain(curve(-100.0));
        let path = warping_path(&a, &b, true, 1.0);
        assert_eq!(path.len(), 41);
        for (k, l) in path {
            assert_eq!(k, l);
        }
    }
}

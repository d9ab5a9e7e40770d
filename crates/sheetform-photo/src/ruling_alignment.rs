//! Sub-sample alignment of the propagated rulings (§5.2's first criterion, made exact).
//!
//! The warping of Eq. 2 matches *samples*, so a ruling's far end is off its true place by
//! up to half a sample spacing, and the ruling's direction by that over its length (0.5°
//! on a 100-pixel ruling with 1-pixel samples). The paper's assumption — the two curves
//! have parallel tangents where a ruling meets them (a generalised cone cut by two
//! parallel planes, orthographic view) — fixes the end exactly: on each side-b chain
//! piece next to the matched sample, `T_a × T_b(t) = 0` is solved for `t` by bisection
//! where it changes sign, and the root becomes a new sample of that segment (shared by
//! every patch along it, so meshes still match). Ends where it has no root (a straight
//! or noisy stretch) stay where the warping put them. The silhouettes (the first and a
//! closed end's last ruling) are not moved.
//!
//! **Perspective** (beyond the paper): parallel 3D tangents are not parallel in a
//! perspective image; they meet at the vanishing point of their direction. Given a
//! solution `x` of the 3D curves, [`align_rulings_in_perspective`] puts each interior
//! end `b` where the image tangent of side b points at the vanishing point of the 3D
//! tangent `T_a` at the ruling's other end: `ŝ(t) × T̄_b(t) = 0` with
//! `ŝ = ` [`Camera::image_direction`]`(T_a, b̄(t))`, the root nearest the end along the
//! whole side-b chain (the warping, blind to perspective, can be several samples off).

use crate::cubic;
use crate::curve_network::CurveNetwork;
use crate::curve_samples::{CurvePoint, CurveSamples, SampledChain};
use crate::ruling_propagation::RuledStrip;
use crate::Camera;
use sheetform_geometry::cross2;

/// Moves interior ruling ends onto the points of parallel tangents; returns how many
/// moved. `samples` gains the new parameters and every strip's chains are resampled.
pub fn align_rulings(network: &CurveNetwork, samples: &mut CurveSamples, strips: &mut [RuledStrip]) -> usize {
    // New ends, per strip and ruling.
    let mut moved: Vec<Vec<Option<CurvePoint>>> = Vec::with_capacity(strips.len());
    for strip in strips.iter() {
        let last = strip.rulings.len() - 1;
        let mut ends = vec![None; strip.rulings.len()];
        for (i, &(k, l)) in strip.rulings.iter().enumerate() {
            if i == 0 || i == last {
                continue;
            }
            let ta = strip.side_a.tangents[k];
            let b = &strip.side_b;
            let mut best: Option<(f64, CurvePoint)> = None;
            for (from, to) in [(l.wrapping_sub(1), l), (l, l + 1)] {
                if from >= b.len() || to >= b.len() || b.places[from].segment != b.places[to].segment {
                    continue;
                }
                let segment = b.places[from].segment;
                let control = network.control_points(segment as usize);
                let f = |t: f64| cross2(ta, cubic::derivative(&control, t));
                let Some(t) = cubic::bisect(f, b.places[from].t, b.places[to].t) else {
                    continue;
                };
                let distance = (t - b.places[l].t).abs();
                if best.is_none_or(|(d, _)| distance < d) {
                    best = Some((distance, CurvePoint { segment, t }));
                }
            }
            ends[i] = best.map(|(_, p)| p);
        }
        moved.push(ends);
    }
    move_ruling_ends(network, samples, strips, &moved)
}

/// Moves the `b` ends of rulings (`new_ends[strip][ruling]`, `None`: unchanged) to new
/// places, which become samples of their segments; every strip's chains are resampled
/// and its rulings re-indexed (a ruling whose end slid past its neighbour's is dropped,
/// so the rulings stay ordered along both sides). Returns how many ends moved.
pub fn move_ruling_ends(
    network: &CurveNetwork,
    samples: &mut CurveSamples,
    strips: &mut [RuledStrip],
    new_ends: &[Vec<Option<CurvePoint>>],
) -> usize {
    // Ends closer to an existing sample than a quarter of the local spacing do not get a
    // sample of their own (it would make sliver triangles) when that sample is free (no
    // other ruling ends there, not a node): it is moved onto the end. Otherwise the end
    // becomes a new sample, however close.
    let key = |p: CurvePoint| (p.segment, p.t.to_bits());
    let mut used: std::collections::HashSet<(u32, u64)> = std::collections::HashSet::new();
    for (strip, ends) in strips.iter().zip(new_ends) {
        for (i, &(k, l)) in strip.rulings.iter().enumerate() {
            used.insert(key(strip.side_a.places[k]));
            // An end's target may be the sample it already is: protect it too.
            used.insert(key(ends[i].unwrap_or(strip.side_b.places[l])));
        }
    }
    let mut moved: Vec<Vec<Option<CurvePoint>>> = new_ends.to_vec();
    let mut count = 0;
    for ends in &mut moved {
        for place in ends.iter_mut().flatten() {
            let params = &mut samples.parameters[place.segment as usize];
            let at = params.partition_point(|&t| t < place.t);
            if params.get(at) == Some(&place.t) {
                count += 1;
                continue;
            }
            // Neighbouring samples: params[at - 1] < t < params[at].
            let (lo, hi) = (at - 1, at);
            let gap = params[hi] - params[lo];
            let nearest = if place.t - params[lo] < params[hi] - place.t {
                lo
            } else {
                hi
            };
            let offset = (place.t - params[nearest]).abs();
            let speed = cubic::derivative(&network.control_points(place.segment as usize), place.t).norm();
            let interior = nearest > 0 && nearest + 1 < params.len();
            if offset * speed <= 1e-9 {
                // The same point to a nanopixel.
                place.t = params[nearest];
            } else if offset < 0.25 * gap && interior && !used.contains(&(place.segment, params[nearest].to_bits())) {
                params[nearest] = place.t;
            } else {
                params.insert(at, place.t);
            }
            used.insert(key(*place));
            count += 1;
        }
    }
    let moved = &moved;
    // Resample every chain and find each ruling's ends in it.
    // A node (t = 0 or 1) may appear in a chain as the end of the neighbouring segment:
    // then it is found by position.
    let index_of = |chain: &SampledChain, place: CurvePoint| -> usize {
        chain
            .places
            .iter()
            .position(|p| p.segment == place.segment && p.t == place.t)
            .or_else(|| {
                let q = cubic::point(&network.control_points(place.segment as usize), place.t);
                chain
                    .points
                    .iter()
                    .position(|p| (p - q).norm() <= 1e-9 * (1.0 + q.norm()))
            })
            .expect("a ruling end is a sample of its chain")
    };
    for (strip, ends) in strips.iter_mut().zip(moved) {
        let side_a = SampledChain::new(network, samples, &strip.chain_a);
        let side_b = SampledChain::new(network, samples, &strip.chain_b);
        for (i, r) in strip.rulings.iter_mut().enumerate() {
            let a = strip.side_a.places[r.0];
            let b = ends[i].unwrap_or(strip.side_b.places[r.1]);
            *r = (index_of(&side_a, a), index_of(&side_b, b));
        }
        // Rulings must stay in order along both sides (a strip is a zipper between
        // them): an end that slid past its neighbour's is dropped with its ruling.
        let mut kept: Vec<(usize, usize)> = Vec::with_capacity(strip.rulings.len());
        for &r in &strip.rulings {
            match kept.last() {
                Some(&last) if r.0 < last.0 || r.1 < last.1 || r == last => {}
                _ => kept.push(r),
            }
        }
        strip.rulings = kept;
        strip.side_a = side_a;
        strip.side_b = side_b;
    }
    count
}

/// Moves interior ruling ends to where the image tangents of both ends point at the same
/// vanishing point, that of the 3D tangent at end `a` of the solution `x` seen through
/// `camera` (see the module's comment); returns how many moved. Like [`align_rulings`]
/// otherwise (the silhouettes stay, `samples` gains the new ends).
pub fn align_rulings_in_perspective(
    network: &CurveNetwork,
    samples: &mut CurveSamples,
    strips: &mut [RuledStrip],
    camera: &Camera,
    x: &[f64],
) -> usize {
    let mut moved: Vec<Vec<Option<CurvePoint>>> = Vec::with_capacity(strips.len());
    for strip in strips.iter() {
        let last = strip.rulings.len() - 1;
        let b = &strip.side_b;
        let mut ends = vec![None; strip.rulings.len()];
        for (i, &(k, l)) in strip.rulings.iter().enumerate() {
            if i == 0 || i == last {
                continue;
            }
            let a = strip.side_a.places[k];
            let ta = crate::curve_lifting::combine3(network, x, a.segment, cubic::bernstein_derivative(a.t));
            if ta.norm() < 1e-12 {
                continue;
            }
            let mismatch = |segment: u32, t: f64| {
                let control = network.control_points(segment as usize);
                let at = cubic::point(&control, t);
                match camera.image_direction(ta, at) {
                    Some(towards) => cross2(towards, cubic::derivative(&control, t)),
                    None => 0.0,
                }
            };
            // The sign changes along the chain, nearest the current end first.
            let mut best: Option<(usize, CurvePoint)> = None;
            for j in 0..b.len().saturating_sub(1) {
                let (from, to) = (b.places[j], b.places[j + 1]);
                if from.segment != to.segment {
                    continue;
                }
                let distance = if j < l { l - j - 1 } else { j - l };
                if best.is_some_and(|(d, _)| d <= distance) {
                    continue;
                }
                let segment = from.segment;
                if let Some(t) = cubic::bisect(|t| mismatch(segment, t), from.t, to.t) {
                    best = Some((distance, CurvePoint { segment, t }));
                }
            }
            ends[i] = best.map(|(_, p)| p);
        }
        moved.push(ends);
    }
    move_ruling_ends(network, samples, strips, &moved)
}

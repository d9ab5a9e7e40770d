//! Point-to-point correspondences between mirror-symmetric curves (§5.3).
//!
//! Under orthographic projection the segment joining two mirror points is parallel to the
//! image of the plane's normal; under perspective it lies on the line through the
//! normal's vanishing point ([`SymmetryPlane::image_direction_at`]). Each sample of one
//! curve is paired with the point where the line through it along that direction meets
//! the other curve (the nearest such point; the paper takes the nearest *sample*, this
//! intersects the sampled polyline, so the pair is exact to the sampling's chord error). For a self-symmetric curve the other
//! crossing of the same curve is taken, and each pair is kept once. A sample whose line
//! misses the other curve (the curves do not overlap along the direction, an occluded
//! part) gets no partner.
//!
//! Each sample is tested against every polyline segment of the other curve, so the cost
//! is the product of the two curves' sample counts, bounded over all the annotation's
//! pairs by [`MAX_CORRESPONDENCE_TESTS`].

use crate::curve_network::CurveNetwork;
use crate::curve_samples::{CurvePoint, CurveSamples, SampledChain};
use crate::patch_cycles::HalfEdge;
use crate::symmetry_plane::SymmetryPlane;
use crate::PhotoError;
use nalgebra::Vector2;
use sheetform_geometry::short_number;

type Vec2 = Vector2<f64>;

/// Most sample-against-segment tests of the mirror correspondences, over all symmetric
/// and self-symmetric curves of an annotation together (the work is the product of each
/// pair's sample counts). About 2 s: a test takes about 2 ns (measured on a comb-shaped
/// curve of 194 000 samples paired with itself: 3.8e10 tests took 80 s before this
/// bound). A curve of 31 000 samples fits with itself; a traced photo at the default
/// spacing has a few hundred samples per curve.
pub const MAX_CORRESPONDENCE_TESTS: usize = 1_000_000_000;

/// A mirror pair of points on the network.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SymmetricPair {
    /// The two places.
    pub places: [CurvePoint; 2],
    /// Their image positions (model frame).
    pub image: [Vec2; 2],
}

/// The whole traced curve `curve` as a sampled chain.
pub fn curve_chain(network: &CurveNetwork, samples: &CurveSamples, curve: usize) -> SampledChain {
    let chain: Vec<HalfEdge> = network.curves[curve]
        .segments
        .iter()
        .map(|&s| HalfEdge {
            segment: s,
            reversed: false,
        })
        .collect();
    SampledChain::new(network, samples, &chain)
}

/// Samples of the whole traced curve `curve` (its segments' shared nodes once).
fn curve_sample_count(network: &CurveNetwork, samples: &CurveSamples, curve: usize) -> usize {
    1 + network.curves[curve]
        .segments
        .iter()
        .map(|&s| samples.parameters[s as usize].len().saturating_sub(1))
        .sum::<usize>()
}

/// Sample-against-segment tests of [`symmetric_pairs`] between curves `a` and `b`.
fn correspondence_tests(network: &CurveNetwork, samples: &CurveSamples, a: usize, b: usize) -> usize {
    curve_sample_count(network, samples, a).saturating_mul(curve_sample_count(network, samples, b).saturating_sub(1))
}

/// The error for correspondences over [`MAX_CORRESPONDENCE_TESTS`]; `a`, `b` the pair
/// that weighs most.
fn too_many_tests(network: &CurveNetwork, samples: &CurveSamples, total: usize, a: usize, b: usize) -> PhotoError {
    let (na, nb) = (
        curve_sample_count(network, samples, a),
        curve_sample_count(network, samples, b),
    );
    let (name_a, name_b) = (
        sheetform_geometry::quoted_token(&network.curves[a].name),
        sheetform_geometry::quoted_token(&network.curves[b].name),
    );
    let curves = if a == b {
        format!("curve `{name_a}` ({na} samples) with itself")
    } else {
        format!("curves `{name_a}` and `{name_b}` ({na} and {nb} samples)")
    };
    PhotoError::field(
        "analysis.sample_spacing_px",
        format!(
            "the mirror correspondences would test {} sample pairs, most of them between {curves} \
             (at most {} over all symmetric curves): sample coarser",
            short_number(total as f64),
            short_number(MAX_CORRESPONDENCE_TESTS as f64)
        ),
    )
}

/// The pairs of every entry of `curve_pairs` (`[a, b]`, or `[a, a]` for a self-symmetric
/// curve), in order, by [`symmetric_pairs`].
///
/// # Errors
/// [`PhotoError::Field`] on `analysis.sample_spacing_px` when they would together make
/// more than [`MAX_CORRESPONDENCE_TESTS`] tests (checked before any work).
pub fn symmetric_pairs_of_curves(
    network: &CurveNetwork,
    samples: &CurveSamples,
    curve_pairs: &[[usize; 2]],
    plane: &SymmetryPlane,
) -> Result<Vec<SymmetricPair>, PhotoError> {
    let mut total = 0usize;
    let mut heaviest = (0, [0, 0]);
    for &[a, b] in curve_pairs {
        let tests = correspondence_tests(network, samples, a, b);
        total = total.saturating_add(tests);
        if tests > heaviest.0 {
            heaviest = (tests, [a, b]);
        }
    }
    if total > MAX_CORRESPONDENCE_TESTS {
        let [a, b] = heaviest.1;
        return Err(too_many_tests(network, samples, total, a, b));
    }
    let mut out = Vec::new();
    for &[a, b] in curve_pairs {
        out.extend(symmetric_pairs(network, samples, a, b, plane)?);
    }
    Ok(out)
}

/// Pairs between curves `a` and `b` (indices into the network's curves; equal for a
/// self-symmetric curve) along the image direction of the plane's normal at each sample
/// ([`SymmetryPlane::image_direction_at`]).
///
/// # Errors
/// [`PhotoError::Field`] on `analysis.sample_spacing_px` when the pair alone would make
/// more than [`MAX_CORRESPONDENCE_TESTS`] tests.
pub fn symmetric_pairs(
    network: &CurveNetwork,
    samples: &CurveSamples,
    a: usize,
    b: usize,
    plane: &SymmetryPlane,
) -> Result<Vec<SymmetricPair>, PhotoError> {
    let tests = correspondence_tests(network, samples, a, b);
    if tests > MAX_CORRESPONDENCE_TESTS {
        return Err(too_many_tests(network, samples, tests, a, b));
    }
    let chain_a = curve_chain(network, samples, a);
    let chain_b = if a == b {
        chain_a.clone()
    } else {
        curve_chain(network, samples, b)
    };
    // Exclusion around the sample itself on a self-symmetric curve: a few samples.
    let spacing = chain_a.arc_length.last().copied().unwrap_or(0.0) / chain_a.len().max(2) as f64;
    let mut out = Vec::new();
    for (k, &p) in chain_a.points.iter().enumerate() {
        let direction = plane.image_direction_at(p);
        let normal = Vec2::new(-direction.y, direction.x);
        let mut best: Option<(f64, SymmetricPair)> = None;
        for j in 0..chain_b.len().saturating_sub(1) {
            let (q0, q1) = (chain_b.points[j], chain_b.points[j + 1]);
            // Signed offsets of the segment's ends from the line through p.
            let (d0, d1) = ((q0 - p).dot(&normal), (q1 - p).dot(&normal));
            if d0 * d1 > 0.0 || (d0 == d1) {
                continue;
            }
            let f = d0 / (d0 - d1);
            let q = q0 + (q1 - q0) * f;
            let distance = (q - p).dot(&direction).abs();
            if a == b {
                // Skip the crossing at the sample itself and pairs already found the other
                // way round.
                if distance < 3.0 * spacing || j < k {
                    continue;
                }
            }
            if best.as_ref().is_none_or(|(d, _)| distance < *d) {
                let (c0, c1) = (chain_b.places[j], chain_b.places[j + 1]);
                let place = if c0.segment == c1.segment {
                    CurvePoint {
                        segment: c0.segment,
                        t: c0.t + (c1.t - c0.t) * f,
                    }
                } else if f < 0.5 {
                    c0
                } else {
                    c1
                };
                best = Some((
                    distance,
                    SymmetricPair {
                        places: [chain_a.places[k], place],
                        image: [p, q],
                    },
                ));
            }
        }
        if let Some((_, pair)) = best {
            out.push(pair);
        }
    }
    Ok(out)
}

//! Point-to-point correspondences between mirror-symmetric curves (§5.3).
//!
//! Under orthographic projection the segment joining two mirror points is parallel to the
//! image of the plane's normal. Each sample of one curve is paired with the point where
//! the line through it along that direction meets the other curve (the nearest such
//! point; the paper takes the nearest *sample*, this intersects the sampled polyline, so
//! the pair is exact to the sampling's chord error). For a self-symmetric curve the other
//! crossing of the same curve is taken, and each pair is kept once. A sample whose line
//! misses the other curve (the curves do not overlap along the direction, an occluded
//! part) gets no partner.

use crate::curve_network::CurveNetwork;
use crate::curve_samples::{CurvePoint, CurveSamples, SampledChain};
use crate::patch_cycles::HalfEdge;
use nalgebra::Vector2;

type Vec2 = Vector2<f64>;

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

/// Pairs between curves `a` and `b` (indices into the network's curves; equal for a
/// self-symmetric curve) along the image direction `direction` of the plane's normal.
pub fn symmetric_pairs(
    network: &CurveNetwork,
    samples: &CurveSamples,
    a: usize,
    b: usize,
    direction: Vec2,
) -> Vec<SymmetricPair> {
    let chain_a = curve_chain(network, samples, a);
    let chain_b = if a == b {
        chain_a.clone()
    } else {
        curve_chain(network, samples, b)
    };
    let normal = Vec2::new(-direction.y, direction.x);
    // Exclusion around the sample itself on a self-symmetric curve: a few samples.
    let spacing = chain_a.arc_length.last().copied().unwrap_or(0.0) / chain_a.len().max(2) as f64;
    let mut out = Vec::new();
    for (k, &p) in chain_a.points.iter().enumerate() {
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
    out
}

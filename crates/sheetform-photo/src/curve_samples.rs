//! Samples along the curve network at a near-uniform arc-length spacing (§5.2, §5.3:
//! "sampling them curvilinearly"). Every segment is sampled once; the rulings, the
//! symmetric correspondences and the mesh boundaries all use these samples, so patches
//! that share a curve share its mesh vertices and their pattern edges match.

use crate::cubic;
use crate::curve_network::CurveNetwork;
use crate::patch_cycles::HalfEdge;
use nalgebra::Vector2;
use sheetform_geometry::{gauss_legendre_length, Bezier2};

type Vec2 = Vector2<f64>;

/// A place on the network: segment and parameter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurvePoint {
    /// Segment index.
    pub segment: u32,
    /// Parameter in `[0, 1]`.
    pub t: f64,
}

/// The sample parameters of every segment (first 0, last 1).
#[derive(Debug, Clone, PartialEq)]
pub struct CurveSamples {
    /// Per segment, increasing parameters from 0 to 1.
    pub parameters: Vec<Vec<f64>>,
}

/// Samples every segment at about `spacing` (pixels) of arc length, at least one piece
/// per segment.
pub fn sample_curves(network: &CurveNetwork, spacing: f64) -> CurveSamples {
    let parameters = (0..network.segments.len())
        .map(|s| {
            let b = Bezier2::new(network.control_points(s).to_vec()).expect("validated: finite control points");
            // Arc length at 64 uniform parameters (8-point Gauss–Legendre per interval),
            // inverted piecewise linearly.
            let n = 64;
            let mut table = vec![0.0; n + 1];
            for i in 0..n {
                table[i + 1] = table[i] + gauss_legendre_length(&b, i as f64 / n as f64, (i + 1) as f64 / n as f64);
            }
            let length = table[n];
            let pieces = ((length / spacing).ceil() as usize).clamp(1, 100_000);
            (0..=pieces)
                .map(|k| {
                    if k == 0 {
                        return 0.0;
                    }
                    if k == pieces {
                        return 1.0;
                    }
                    let target = length * k as f64 / pieces as f64;
                    let i = table.partition_point(|&a| a < target).clamp(1, n);
                    let (a0, a1) = (table[i - 1], table[i]);
                    let f = if a1 > a0 { (target - a0) / (a1 - a0) } else { 0.0 };
                    (i as f64 - 1.0 + f) / n as f64
                })
                .collect()
        })
        .collect();
    CurveSamples { parameters }
}

/// A sampled chain of half-edges: positions, unit tangents in traversal direction, the
/// network place of each sample and the arc length from the chain's start.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SampledChain {
    /// Positions (model frame, pixels).
    pub points: Vec<Vec2>,
    /// Unit tangents along the traversal.
    pub tangents: Vec<Vec2>,
    /// Where each sample is on the network.
    pub places: Vec<CurvePoint>,
    /// Arc length (polyline) from the first sample.
    pub arc_length: Vec<f64>,
}

impl SampledChain {
    /// Samples of the half-edges in order (their shared nodes once).
    pub fn new(network: &CurveNetwork, samples: &CurveSamples, chain: &[HalfEdge]) -> Self {
        let mut out = Self::default();
        for (k, h) in chain.iter().enumerate() {
            let b = network.control_points(h.segment as usize);
            let params = &samples.parameters[h.segment as usize];
            let n = params.len();
            for i in 0..n {
                if k > 0 && i == 0 {
                    continue;
                }
                let t = if h.reversed { params[n - 1 - i] } else { params[i] };
                let p = cubic::point(&b, t);
                let mut d = cubic::derivative(&b, t);
                if h.reversed {
                    d = -d;
                }
                if d.norm() == 0.0 {
                    // A degenerate handle: the chord direction instead.
                    d = if h.reversed { b[0] - b[3] } else { b[3] - b[0] };
                }
                let length = out.points.last().map_or(0.0, |&q: &Vec2| (p - q).norm());
                out.arc_length
                    .push(out.arc_length.last().copied().unwrap_or(0.0) + length);
                out.points.push(p);
                out.tangents.push(d.normalize());
                out.places.push(CurvePoint { segment: h.segment, t });
            }
        }
        out
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Whether it has no sample.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }
}

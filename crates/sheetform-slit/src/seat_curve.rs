//! The seat curve on the symmetry plane, approximated by segments as in the paper (§3.1,
//! "cross-section" anchor): the distance from a point to the curve is the distance to the
//! nearest segment.

use nalgebra::Vector2;
use sheetform_geometry::{Bezier2, ParametricCurve};

type Vec2 = Vector2<f64>;

/// The seat curve as a polyline in the symmetry plane, points `[z, y]`.
#[derive(Debug, Clone, PartialEq)]
pub struct SeatCurve {
    /// Polyline vertices `[z, y]`.
    pub points: Vec<Vec2>,
}

/// The point of a [`SeatCurve`] nearest to a query.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeatProjection {
    /// The nearest point `[z, y]`.
    pub point: Vec2,
    /// Unit direction of the segment when the nearest point is inside it (then the
    /// nearest point slides with the query along it); `None` at a polyline vertex.
    pub tangent: Option<Vec2>,
}

impl SeatCurve {
    /// Samples a Bézier at `segments + 1` evenly spaced parameters.
    pub fn from_bezier(curve: &Bezier2, segments: usize) -> Self {
        let segments = segments.max(1);
        Self {
            points: (0..=segments)
                .map(|k| curve.point(k as f64 / segments as f64))
                .collect(),
        }
    }

    /// The nearest point to `query` (`[z, y]`).
    pub fn project(&self, query: Vec2) -> SeatProjection {
        let mut best = (
            f64::INFINITY,
            SeatProjection {
                point: self.points[0],
                tangent: None,
            },
        );
        for w in self.points.windows(2) {
            let d = w[1] - w[0];
            let len2 = d.norm_squared();
            let (point, tangent) = if len2 == 0.0 {
                (w[0], None)
            } else {
                let t = (query - w[0]).dot(&d) / len2;
                if t <= 0.0 {
                    (w[0], None)
                } else if t >= 1.0 {
                    (w[1], None)
                } else {
                    (w[0] + d * t, Some(d / len2.sqrt()))
                }
            };
            let dist = (query - point).norm_squared();
            if dist < best.0 {
                best = (dist, SeatProjection { point, tangent });
            }
        }
        best.1
    }

    /// The curve's `z` range.
    pub fn z_range(&self) -> (f64, f64) {
        self.points
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p.x), hi.max(p.x))
            })
    }

    /// The height `y` of the curve at depth `z` (first crossing), if it spans `z`.
    pub fn height_at(&self, z: f64) -> Option<f64> {
        self.points.windows(2).find_map(|w| {
            let (a, b) = (w[0], w[1]);
            let (lo, hi) = if a.x <= b.x { (a, b) } else { (b, a) };
            (lo.x <= z && z <= hi.x).then(|| {
                if hi.x - lo.x < 1e-300 {
                    lo.y
                } else {
                    lo.y + (hi.y - lo.y) * (z - lo.x) / (hi.x - lo.x)
                }
            })
        })
    }
}

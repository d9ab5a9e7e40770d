//! Where each flat ruling meets the sheet's boundary (Bo & Wang 2007, §3.3, steps 3–4).

use sheetform_geometry::{Polygon, Vec2};

/// A point on the polygon boundary: ring, edge and position along the edge (0..1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoundaryPoint {
    /// Ring (0 = outline, k = hole k−1).
    pub ring: usize,
    /// Edge index in the ring.
    pub edge: usize,
    /// Position along the edge.
    pub edge_parameter: f64,
}

/// The part of one flat ruling that lies on the sheet.
///
/// The ruling through the geodesic point `p̄` with unit direction `r̄` is clipped to the
/// piece of `line ∩ outline` that contains `p̄`: `[negative_end, positive_end]` in signed
/// distance along `r̄` (`l1 ≤ 0 ≤ l0` in the paper's notation). A ruling that leaves the
/// outline stops there, even if the line re-enters the sheet further on (§3.3 keeps only
/// the first crossing on each side).
///
/// Departure from the paper: a ruling *continues across a hole*. The material beyond a
/// hole is joined to the rest of the sheet around the hole, and the only tear-free way to
/// bend it is along the same ruling lines, so the hole's intervals are returned as `gaps`
/// (where the mesh has no faces) instead of ending the ruling there. Eq. 6 is tested
/// against the whole extent, since rulings that crossed behind a hole would tear it.
#[derive(Debug, Clone, PartialEq)]
pub struct RulingExtent {
    /// `l1 ≤ 0`: signed distance to the boundary on the negative side.
    pub negative_end: f64,
    /// `l0 ≥ 0`: signed distance to the boundary on the positive side.
    pub positive_end: f64,
    /// Where the two ends lie on the boundary.
    pub ends: [BoundaryPoint; 2],
    /// Intervals `[a, b]` (signed distances, increasing) that lie inside holes, with the
    /// boundary points at both ends.
    pub gaps: Vec<([f64; 2], [BoundaryPoint; 2])>,
    /// Boundary points strictly inside the extent and outside the gaps, where the ruling
    /// touches the boundary (a reflex vertex, or a stretch along an edge): they must be
    /// vertices of the ruling in the mesh.
    pub touches: Vec<(f64, BoundaryPoint)>,
}

/// Distance from `p` to the boundary of ring `ring`, with the closest edge.
fn nearest_on_ring(polygon: &Polygon, ring: usize, p: Vec2) -> (f64, BoundaryPoint) {
    let pts = polygon.ring(ring);
    let n = pts.len();
    let mut best = (
        f64::INFINITY,
        BoundaryPoint {
            ring,
            edge: 0,
            edge_parameter: 0.0,
        },
    );
    for i in 0..n {
        let (a, b) = (pts[i], pts[(i + 1) % n]);
        let e = b - a;
        let len2 = e.norm_squared();
        let t = if len2 > 0.0 {
            ((p - a).dot(&e) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let d = (a + e * t - p).norm_squared();
        if d < best.0 {
            best = (
                d,
                BoundaryPoint {
                    ring,
                    edge: i,
                    edge_parameter: t,
                },
            );
        }
    }
    best.0 = best.0.sqrt();
    best
}

/// The closest boundary point to `p` over the given rings.
pub fn locate_on_boundary(polygon: &Polygon, p: Vec2, rings: impl Iterator<Item = usize>) -> (f64, BoundaryPoint) {
    rings
        .map(|r| nearest_on_ring(polygon, r, p))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .expect("at least one ring")
}

fn inside_outline_closed(polygon: &Polygon, p: Vec2, eps: f64) -> bool {
    polygon.outline_contains(p) || nearest_on_ring(polygon, 0, p).0 <= eps
}

fn inside_hole_open(polygon: &Polygon, p: Vec2, eps: f64) -> bool {
    (1..polygon.ring_count()).any(|r| polygon.ring_contains(r, p) && nearest_on_ring(polygon, r, p).0 > eps)
}

/// Clips the flat ruling through `origin` with unit direction `direction` to the sheet
/// (see [`RulingExtent`]). `scale` is the model's length scale (for tolerances).
///
/// One pass of [`Polygon::line_hits`] over all rings; the extent is found by walking the
/// sorted outline hits outwards from the geodesic point and testing, between consecutive
/// hits, whether the line is still on the (closed) sheet.
pub fn ruling_extent(polygon: &Polygon, origin: Vec2, direction: Vec2, scale: f64) -> RulingExtent {
    let eps = 1e-11 * scale;
    let hits = polygon.line_hits(origin, direction, |_| true);
    let walk = |sign: f64| {
        if sign > 0.0 {
            walk_outline(polygon, origin, direction, hits.iter(), 1.0, eps)
        } else {
            walk_outline(polygon, origin, direction, hits.iter().rev(), -1.0, eps)
        }
    };
    let (positive_end, positive_hit) = walk(1.0);
    let (negative_end, negative_hit) = walk(-1.0);
    // The outline hit where the walk stopped is the end point; a ruling that never left
    // its geodesic point (zero extent on that side) is located by distance.
    let end_point = |l: f64, hit: Option<&sheetform_geometry::RayHit>| match hit {
        Some(h) => BoundaryPoint {
            ring: h.ring,
            edge: h.edge,
            edge_parameter: h.edge_parameter,
        },
        None => locate_on_boundary(polygon, origin + direction * l, 0..polygon.ring_count()).1,
    };
    let ends = [
        end_point(negative_end, negative_hit),
        end_point(positive_end, positive_hit),
    ];

    let mut gaps = Vec::new();
    if polygon.ring_count() > 1 {
        let mut previous: Option<f64> = None;
        for h in hits
            .iter()
            .filter(|h| h.ring > 0 && h.t > negative_end + eps && h.t < positive_end - eps)
        {
            if let Some(a) = previous {
                if (h.t - a).abs() > eps {
                    let mid = origin + direction * (0.5 * (a + h.t));
                    if inside_hole_open(polygon, mid, eps) {
                        let pa = locate_on_boundary(polygon, origin + direction * a, 1..polygon.ring_count()).1;
                        let pb = locate_on_boundary(polygon, origin + direction * h.t, 1..polygon.ring_count()).1;
                        gaps.push(([a, h.t], [pa, pb]));
                    }
                }
            }
            if previous.is_none_or(|a| (h.t - a).abs() > eps) {
                previous = Some(h.t);
            }
        }
    }
    let mut touches: Vec<(f64, BoundaryPoint)> = Vec::new();
    for h in &hits {
        if h.t <= negative_end + eps || h.t >= positive_end - eps {
            continue;
        }
        if gaps.iter().any(|(g, _)| h.t >= g[0] - eps && h.t <= g[1] + eps) {
            continue;
        }
        if touches.last().is_some_and(|(t, _)| (h.t - t).abs() <= eps) {
            continue;
        }
        touches.push((
            h.t,
            BoundaryPoint {
                ring: h.ring,
                edge: h.edge,
                edge_parameter: h.edge_parameter,
            },
        ));
    }
    RulingExtent {
        negative_end,
        positive_end,
        ends,
        gaps,
        touches,
    }
}

/// Walks the outline hits (`hits` ordered away from `t = 0` in direction `sign`) and
/// returns the signed distance where the line leaves the closed sheet, with the outline
/// hit there (`None` when the line leaves at `t = 0`).
fn walk_outline<'a>(
    polygon: &Polygon,
    origin: Vec2,
    direction: Vec2,
    hits: impl Iterator<Item = &'a sheetform_geometry::RayHit>,
    sign: f64,
    eps: f64,
) -> (f64, Option<&'a sheetform_geometry::RayHit>) {
    let mut prev = (0.0, None);
    for h in hits {
        let t = sign * h.t;
        if h.ring != 0 || t <= eps || (t - prev.0).abs() <= eps {
            continue;
        }
        let mid = origin + direction * (sign * 0.5 * (prev.0 + t));
        if !inside_outline_closed(polygon, mid, eps) {
            break;
        }
        prev = (t, Some(h));
    }
    (sign * prev.0, prev.1)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> Vec2 {
        Vec2::new(x, y)
    }

    #[test]
    fn rectangle_chord() {
        let p = Polygon::new(vec![v(0.0, 0.0), v(10.0, 0.0), v(10.0, 4.0), v(0.0, 4.0)], vec![]).unwrap();
        let e = ruling_extent(&p, v(5.0, 1.0), v(0.0, 1.0), 10.0);
        assert!((e.positive_end - 3.0).abs() < 1e-12 && (e.negative_end + 1.0).abs() < 1e-12);
        // A ruling lying along an edge spans that edge.
        let e = ruling_extent(&p, v(0.0, 1.0), v(0.0, 1.0), 10.0);
        assert!((e.positive_end - 3.0).abs() < 1e-12 && (e.negative_end + 1.0).abs() < 1e-12);
    }

    #[test]
    fn concave_outline_keeps_the_piece_with_the_geodesic_point() {
        // A U shape: the vertical line x = 5 leaves through the bottom of the notch.
        let p = Polygon::new(
            vec![
                v(0.0, 0.0),
                v(10.0, 0.0),
                v(10.0, 10.0),
                v(7.0, 10.0),
                v(7.0, 3.0),
                v(3.0, 3.0),
                v(3.0, 10.0),
                v(0.0, 10.0),
            ],
            vec![],
        )
        .unwrap();
        let e = ruling_extent(&p, v(5.0, 1.0), v(0.0, 1.0), 14.0);
        assert!((e.positive_end - 2.0).abs() < 1e-12 && (e.negative_end + 1.0).abs() < 1e-12);
    }

    #[test]
    fn holes_become_gaps() {
        let p = Polygon::new(
            vec![v(0.0, 0.0), v(10.0, 0.0), v(10.0, 10.0), v(0.0, 10.0)],
            vec![vec![v(4.0, 4.0), v(6.0, 4.0), v(6.0, 6.0), v(4.0, 6.0)]],
        )
        .unwrap();
        let e = ruling_extent(&p, v(5.0, 1.0), v(0.0, 1.0), 14.0);
        assert!((e.positive_end - 9.0).abs() < 1e-12);
        assert_eq!(e.gaps.len(), 1);
        assert!((e.gaps[0].0[0] - 3.0).abs() < 1e-12 && (e.gaps[0].0[1] - 5.0).abs() < 1e-12);
    }
}

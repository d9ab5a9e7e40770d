use crate::{GeometryError, Vec2};

/// A polygon with holes in the plane: one outer ring and any number of hole rings.
///
/// After [`Polygon::new`] the outer ring is counter-clockwise and every hole clockwise,
/// no two edges cross or touch (apart from consecutive edges at their shared vertex),
/// every hole lies inside the outline and outside every other hole.
/// Rings are stored without repeating the first vertex.
#[derive(Debug, Clone, PartialEq)]
pub struct Polygon {
    outer: Vec<Vec2>,
    holes: Vec<Vec<Vec2>>,
}

/// One edge of a [`Polygon`]: ring 0 is the outline, ring `k ≥ 1` is hole `k − 1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PolygonEdge {
    /// Ring index (0 = outline, k = hole k−1).
    pub ring: usize,
    /// Edge index within the ring (edge i goes from vertex i to vertex i+1).
    pub index: usize,
    /// Start point.
    pub start: Vec2,
    /// End point.
    pub end: Vec2,
}

/// Where a line `origin + t · direction` meets a polygon edge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RayHit {
    /// Line parameter of the hit (distance if `direction` is unit).
    pub t: f64,
    /// Ring of the edge hit.
    pub ring: usize,
    /// Edge index within the ring.
    pub edge: usize,
    /// Position along the edge, 0 at its start, 1 at its end.
    pub edge_parameter: f64,
}

/// Signed area of a closed ring (shoelace formula): positive when counter-clockwise.
pub fn signed_area(ring: &[Vec2]) -> f64 {
    let n = ring.len();
    (0..n)
        .map(|i| {
            let (a, b) = (ring[i], ring[(i + 1) % n]);
            a.x * b.y - b.x * a.y
        })
        .sum::<f64>()
        * 0.5
}

/// The 2D cross product `a.x b.y − a.y b.x` (twice the signed area of the triangle `0, a, b`).
pub fn cross2(a: Vec2, b: Vec2) -> f64 {
    cross(a, b)
}

/// Whether the closed segments `p0p1` and `q0q1` meet (touching counts).
pub fn segments_meet(p0: Vec2, p1: Vec2, q0: Vec2, q1: Vec2) -> bool {
    let (r, s) = (p1 - p0, q1 - q0);
    let (d1, d2) = (cross(r, q0 - p0), cross(r, q1 - p0));
    let (d3, d4) = (cross(s, p0 - q0), cross(s, p1 - q0));
    if segments_cross(p0, p1, q0, q1) {
        return true;
    }
    let on = |a: Vec2, b: Vec2, p: Vec2, d: f64| {
        d == 0.0 && p.x >= a.x.min(b.x) && p.x <= a.x.max(b.x) && p.y >= a.y.min(b.y) && p.y <= a.y.max(b.y)
    };
    on(p0, p1, q0, d1) || on(p0, p1, q1, d2) || on(q0, q1, p0, d3) || on(q0, q1, p1, d4)
}

/// Whether the segments `p0p1` and `q0q1` cross properly: each one's ends strictly on
/// either side of the other's line (touching and collinear overlaps do not count).
pub fn segments_cross(p0: Vec2, p1: Vec2, q0: Vec2, q1: Vec2) -> bool {
    let (r, s) = (p1 - p0, q1 - q0);
    cross(r, q0 - p0) * cross(r, q1 - p0) < 0.0 && cross(s, p0 - q0) * cross(s, p1 - q0) < 0.0
}

/// Whether the interiors of two triangles overlap by more than `tolerance` (a length):
/// the separating axis test over the six edge normals, the triangles counted as
/// disjoint when, along one of them, their projections overlap by at most `tolerance`.
/// Triangles that only touch (a shared edge or vertex, or lying side by side) do not
/// overlap; a tolerance of a small fraction of the edge lengths absorbs rounding. For
/// convex polygons a separating line, when one exists, is parallel to an edge, so the
/// test is exact. Either vertex order.
pub fn triangles_overlap(a: [Vec2; 3], b: [Vec2; 3], tolerance: f64) -> bool {
    for tri in [a, b] {
        for k in 0..3 {
            let edge = tri[(k + 1) % 3] - tri[k];
            let length = edge.norm();
            if length == 0.0 {
                continue;
            }
            let axis = Vec2::new(-edge.y, edge.x) / length;
            let span = |t: [Vec2; 3]| {
                t.iter()
                    .map(|p| p.dot(&axis))
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| (lo.min(x), hi.max(x)))
            };
            let ((a0, a1), (b0, b1)) = (span(a), span(b));
            if a1.min(b1) - a0.max(b0) <= tolerance {
                return false;
            }
        }
    }
    true
}

/// Whether `p` is inside a set of rings by the even–odd rule (an outline and its holes, or
/// several loops). Points exactly on a ring may go either way.
pub fn rings_contain<'a>(rings: impl IntoIterator<Item = &'a [Vec2]>, p: Vec2) -> bool {
    rings
        .into_iter()
        .filter(|r| !r.is_empty() && ring_contains(r, p))
        .count()
        % 2
        == 1
}

/// The shortest distance between the closed segments `[a, b]` and `[c, d]` (0 when they
/// meet), by `geo`'s Euclidean distance between lines.
pub fn segment_distance([a, b]: [Vec2; 2], [c, d]: [Vec2; 2]) -> f64 {
    use geo::{Distance, Euclidean, Line};
    Euclidean.distance(
        &Line::new(geo::coord! { x: a.x, y: a.y }, geo::coord! { x: b.x, y: b.y }),
        &Line::new(geo::coord! { x: c.x, y: c.y }, geo::coord! { x: d.x, y: d.y }),
    )
}

/// Convex hull of points, counter-clockwise without collinear points (Andrew's monotone
/// chain, O(n log n)); fewer than three distinct points come back as they are (sorted).
pub fn convex_hull(mut points: Vec<Vec2>) -> Vec<Vec2> {
    points.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    points.dedup();
    if points.len() < 3 {
        return points;
    }
    let turn = |o: Vec2, a: Vec2, b: Vec2| cross(a - o, b - o);
    let mut hull: Vec<Vec2> = Vec::with_capacity(points.len() * 2);
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &Vec2>> = if pass == 0 {
            Box::new(points.iter())
        } else {
            Box::new(points.iter().rev())
        };
        for &p in iter {
            while hull.len() >= start + 2 && turn(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0 {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

/// Whether a convex polygon (counter-clockwise) fits in a `width × height` rectangle,
/// turned as [`fitting_rotation`] turns it.
pub fn hull_fits_rectangle(hull: &[Vec2], width: f64, height: f64) -> bool {
    // As it lies, either way round, first (most polygons asked about are far smaller
    // than the rectangle: one look instead of some 180 turns).
    let (lo, hi) = hull.iter().fold(
        (Vec2::repeat(f64::INFINITY), Vec2::repeat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.inf(p), hi.sup(p)),
    );
    let size = hi - lo;
    let (long, short) = (width.max(height), width.min(height));
    if hull.is_empty() || (size.x.max(size.y) <= long && size.x.min(size.y) <= short) {
        return true;
    }
    fitting_rotation(hull, width, height).is_some()
}

/// Whether points turned by `turn` (radians, counter-clockwise) fit a `width × height`
/// rectangle, either way round: one look where [`fitting_rotation`] searches (a turn that
/// fitted a smaller polygon often fits it grown a little).
pub fn fits_turned(points: &[Vec2], turn: f64, width: f64, height: f64) -> bool {
    let (s, c) = turn.sin_cos();
    let (mut lo, mut hi) = (Vec2::repeat(f64::INFINITY), Vec2::repeat(f64::NEG_INFINITY));
    for p in points {
        let q = Vec2::new(c * p.x - s * p.y, s * p.x + c * p.y);
        (lo, hi) = (lo.inf(&q), hi.sup(&q));
    }
    let size = hi - lo;
    let (long, short) = (width.max(height), width.min(height));
    points.is_empty() || (size.x.max(size.y) <= long && size.x.min(size.y) <= short)
}

/// Turns [`fitting_rotation`] tries besides the hull's edges: every half degree of a
/// quarter turn (with each turned a further quarter turn, every half degree of a half
/// turn).
const FIT_ANGLE_STEPS: usize = 180;

/// A rotation (radians, counter-clockwise) that turns a convex polygon (or any points:
/// every point is measured) into a
/// `width × height` rectangle, and the size of its bounding box then (within `width ×
/// height`): of the turns that lay one of its edges along the rectangle's sides (where
/// the smallest bounding rectangles lie) or any multiple of half a degree, either way
/// round, the one of the smallest bounding box. A polygon that fits only between those
/// angles (within a hair of the rectangle) is refused. `None` when none fits.
pub fn fitting_rotation(hull: &[Vec2], width: f64, height: f64) -> Option<(f64, Vec2)> {
    let size_along = |u: Vec2| {
        let normal = Vec2::new(-u.y, u.x);
        let (mut a0, mut a1, mut b0, mut b1) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
        for p in hull {
            let (a, b) = (p.dot(&u), p.dot(&normal));
            (a0, a1, b0, b1) = (a0.min(a), a1.max(a), b0.min(b), b1.max(b));
        }
        Vec2::new(a1 - a0, b1 - b0)
    };
    if hull.is_empty() {
        return Some((0.0, Vec2::zeros()));
    }
    let n = hull.len();
    let directions = (0..FIT_ANGLE_STEPS)
        .map(|k| {
            let a = std::f64::consts::FRAC_PI_2 * k as f64 / FIT_ANGLE_STEPS as f64;
            Vec2::new(a.cos(), a.sin())
        })
        .chain((0..n).filter_map(|i| {
            let e = hull[(i + 1) % n] - hull[i];
            // (hypot: no overflow for a hull far from the origin or huge.)
            let length = e.x.hypot(e.y);
            let u = e / length;
            (length > 0.0 && u.x.is_finite() && u.y.is_finite()).then_some(u)
        }));
    let mut best: Option<(f64, Vec2)> = None;
    for u in directions {
        let size = size_along(u);
        // Turning by −angle(u) lays u along +x; a further quarter turn swaps the sides.
        let angle = -u.y.atan2(u.x);
        for (turn, s) in [
            (angle, size),
            (angle + std::f64::consts::FRAC_PI_2, Vec2::new(size.y, size.x)),
        ] {
            let fits = s.x <= width * (1.0 + 1e-12) && s.y <= height * (1.0 + 1e-12);
            if fits && best.is_none_or(|(_, b)| s.x * s.y < b.x * b.y) {
                best = Some((turn, s));
            }
        }
    }
    best
}

fn cross(a: Vec2, b: Vec2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// Intersection of segments `[a, b]` and `[c, d]`: the parameters `(s, t)` with
/// `a + s(b−a) = c + t(d−c)`, both in `[0, 1]`, or `None` (also for parallel segments).
pub fn segment_intersection(a: Vec2, b: Vec2, c: Vec2, d: Vec2) -> Option<(f64, f64)> {
    let r = b - a;
    let q = d - c;
    let den = cross(r, q);
    if den == 0.0 {
        return None;
    }
    let s = cross(c - a, q) / den;
    let t = cross(c - a, r) / den;
    ((0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t)).then_some((s, t))
}

fn ring_name(ring: usize) -> String {
    if ring == 0 {
        "outline".into()
    } else {
        format!("hole {}", ring - 1)
    }
}

fn check_ring(ring: &[Vec2], index: usize) -> Result<Vec<Vec2>, GeometryError> {
    let what = if index == 0 {
        "outline vertex".to_string()
    } else {
        format!("hole {} vertex", index - 1)
    };
    for (i, p) in ring.iter().enumerate() {
        if !(p.x.is_finite() && p.y.is_finite()) {
            return Err(GeometryError::NonFinite { what, index: i });
        }
    }
    // Drop a repeated closing vertex and consecutive duplicates.
    let mut out: Vec<Vec2> = Vec::with_capacity(ring.len());
    for p in ring {
        if out.last().is_none_or(|q| (q - p).norm() > 0.0) {
            out.push(*p);
        }
    }
    if out.len() > 1 && out.first() == out.last() {
        out.pop();
    }
    if out.len() < 3 {
        return Err(GeometryError::DegeneratePolygon {
            ring: ring_name(index),
            reason: format!("needs at least 3 distinct vertices, has {}", out.len()),
        });
    }
    Ok(out)
}

impl Polygon {
    /// Validates and normalises a polygon (see the type's invariants).
    ///
    /// # Errors
    /// Non-finite coordinates, rings with fewer than three distinct vertices or zero
    /// area, crossing or touching edges ([`GeometryError::SelfIntersection`] names both
    /// edges and the place), holes outside the outline or inside another hole.
    pub fn new(outer: Vec<Vec2>, holes: Vec<Vec<Vec2>>) -> Result<Self, GeometryError> {
        let mut outer = check_ring(&outer, 0)?;
        if signed_area(&outer) < 0.0 {
            outer.reverse();
        }
        let mut rings = Vec::with_capacity(holes.len());
        for (k, h) in holes.iter().enumerate() {
            let mut h = check_ring(h, k + 1)?;
            if signed_area(&h) > 0.0 {
                h.reverse();
            }
            rings.push(h);
        }
        let polygon = Self { outer, holes: rings };
        polygon.check_crossings()?;
        for r in 0..polygon.ring_count() {
            let ring = polygon.ring(r);
            let scale = ring.iter().map(|p| p.norm()).fold(0.0, f64::max).max(1e-300);
            if signed_area(ring).abs() <= 1e-14 * scale * scale {
                return Err(GeometryError::DegeneratePolygon {
                    ring: ring_name(r),
                    reason: "has zero area".into(),
                });
            }
        }
        for (k, h) in polygon.holes.iter().enumerate() {
            if !ring_contains(&polygon.outer, h[0]) {
                return Err(GeometryError::HoleOutside { hole: k });
            }
            for (j, other) in polygon.holes.iter().enumerate() {
                if j != k && ring_contains(other, h[0]) {
                    return Err(GeometryError::HoleOutside { hole: k });
                }
            }
        }
        Ok(polygon)
    }

    /// Every pair of non-adjacent edges must be disjoint; adjacent edges must not fold
    /// back onto each other. Uses a sort along x to skip far-apart pairs.
    fn check_crossings(&self) -> Result<(), GeometryError> {
        let edges: Vec<PolygonEdge> = self.edges().collect();
        let mut order: Vec<usize> = (0..edges.len()).collect();
        let min_x = |e: &PolygonEdge| e.start.x.min(e.end.x);
        let max_x = |e: &PolygonEdge| e.start.x.max(e.end.x);
        order.sort_by(|&a, &b| min_x(&edges[a]).total_cmp(&min_x(&edges[b])));
        for (oi, &i) in order.iter().enumerate() {
            let ei = edges[i];
            for &j in &order[oi + 1..] {
                let ej = edges[j];
                if min_x(&ej) > max_x(&ei) {
                    break;
                }
                let ring_len = self.ring(ei.ring).len();
                let adjacent = ei.ring == ej.ring
                    && ((ei.index + 1) % ring_len == ej.index || (ej.index + 1) % ring_len == ei.index);
                let hit = if adjacent {
                    // Consecutive edges share one vertex; they are invalid only if they
                    // overlap (the ring doubles back on itself).
                    let (shared, a, b) = if (ei.index + 1) % ring_len == ej.index {
                        (ei.end, ei.start, ej.end)
                    } else {
                        (ej.end, ej.start, ei.end)
                    };
                    let (u, v) = (a - shared, b - shared);
                    let collinear = cross(u, v).abs() <= 1e-14 * u.norm() * v.norm();
                    (collinear && u.dot(&v) > 0.0).then_some(shared)
                } else {
                    touch_point(ei.start, ei.end, ej.start, ej.end)
                };
                if let Some(p) = hit {
                    let (a, b) = if (ei.ring, ei.index) <= (ej.ring, ej.index) {
                        (ei, ej)
                    } else {
                        (ej, ei)
                    };
                    return Err(GeometryError::SelfIntersection {
                        ring_a: ring_name(a.ring),
                        edge_a: a.index,
                        ring_b: ring_name(b.ring),
                        edge_b: b.index,
                        x: p.x,
                        y: p.y,
                    });
                }
            }
        }
        Ok(())
    }

    /// The outline (counter-clockwise).
    pub fn outer(&self) -> &[Vec2] {
        &self.outer
    }

    /// The holes (each clockwise).
    pub fn holes(&self) -> &[Vec<Vec2>] {
        &self.holes
    }

    /// Ring `k`: 0 = outline, k ≥ 1 = hole k−1.
    pub fn ring(&self, k: usize) -> &[Vec2] {
        if k == 0 {
            &self.outer
        } else {
            &self.holes[k - 1]
        }
    }

    /// Number of rings (outline + holes).
    pub fn ring_count(&self) -> usize {
        1 + self.holes.len()
    }

    /// Every edge of every ring.
    pub fn edges(&self) -> impl Iterator<Item = PolygonEdge> + '_ {
        (0..self.ring_count()).flat_map(move |r| {
            let ring = self.ring(r);
            (0..ring.len()).map(move |i| PolygonEdge {
                ring: r,
                index: i,
                start: ring[i],
                end: ring[(i + 1) % ring.len()],
            })
        })
    }

    /// Area (outline minus holes).
    pub fn area(&self) -> f64 {
        signed_area(&self.outer) + self.holes.iter().map(|h| signed_area(h)).sum::<f64>()
    }

    /// Axis-aligned bounding box `(min, max)` of the outline.
    pub fn bounding_box(&self) -> (Vec2, Vec2) {
        let mut lo = Vec2::repeat(f64::INFINITY);
        let mut hi = Vec2::repeat(f64::NEG_INFINITY);
        for p in &self.outer {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        (lo, hi)
    }

    /// Length of the bounding-box diagonal: the model's length scale for tolerances.
    pub fn scale(&self) -> f64 {
        let (lo, hi) = self.bounding_box();
        (hi - lo).norm()
    }

    /// Whether `p` is inside the polygon (inside the outline, outside every hole).
    /// Points exactly on the boundary may go either way.
    pub fn contains(&self, p: Vec2) -> bool {
        ring_contains(&self.outer, p) && !self.holes.iter().any(|h| ring_contains(h, p))
    }

    /// Whether `p` is inside the outline, ignoring holes.
    pub fn outline_contains(&self, p: Vec2) -> bool {
        ring_contains(&self.outer, p)
    }

    /// Whether `p` is inside ring `k` (0 = outline, k = hole k−1) by the even–odd rule.
    /// Points exactly on the ring may go either way.
    pub fn ring_contains(&self, k: usize, p: Vec2) -> bool {
        ring_contains(self.ring(k), p)
    }

    /// All points where the line `origin + t · direction` meets edges of the rings
    /// selected by `rings` (a predicate on the ring index), sorted by `t`. A line through
    /// a vertex reports it once per edge there; edges parallel to the line (to 1e-12) are
    /// not reported, their end points are (through the neighbouring edges).
    pub fn line_hits(&self, origin: Vec2, direction: Vec2, rings: impl Fn(usize) -> bool) -> Vec<RayHit> {
        let mut hits = Vec::new();
        for r in 0..self.ring_count() {
            if !rings(r) {
                continue;
            }
            let ring = self.ring(r);
            let n = ring.len();
            for i in 0..n {
                let (a, b) = (ring[i], ring[(i + 1) % n]);
                let e = b - a;
                let den = cross(direction, e);
                // Nearly parallel edges (sin of the angle below 1e-12) count as parallel:
                // their end points are found through the neighbouring edges.
                if den.abs() <= 1e-12 * direction.norm() * e.norm() {
                    continue;
                }
                let w = a - origin;
                let u = cross(w, direction) / den;
                // A line through a vertex must hit the edges there despite rounding.
                if !(-1e-12..=1.0 + 1e-12).contains(&u) {
                    continue;
                }
                let u = u.clamp(0.0, 1.0);
                let t = cross(w, e) / den;
                hits.push(RayHit {
                    t,
                    ring: r,
                    edge: i,
                    edge_parameter: u,
                });
            }
        }
        hits.sort_by(|a, b| a.t.total_cmp(&b.t));
        hits
    }
}

/// Even–odd point-in-ring test (crossing number).
fn ring_contains(ring: &[Vec2], p: Vec2) -> bool {
    let n = ring.len();
    let mut inside = false;
    let mut j = n - 1;
    for i in 0..n {
        let (a, b) = (ring[i], ring[j]);
        if (a.y > p.y) != (b.y > p.y) {
            let x = a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y);
            if p.x < x {
                inside = !inside;
            }
        }
        j = i;
    }
    inside
}

/// A point shared by closed segments `[a,b]` and `[c,d]`, if any (including touching and
/// collinear overlap).
fn touch_point(a: Vec2, b: Vec2, c: Vec2, d: Vec2) -> Option<Vec2> {
    let o1 = cross(b - a, c - a);
    let o2 = cross(b - a, d - a);
    let o3 = cross(d - c, a - c);
    let o4 = cross(d - c, b - c);
    let scale = (b - a).norm().max((d - c).norm());
    let eps = 1e-14 * scale * scale;
    let sgn = |x: f64| {
        if x > eps {
            1
        } else if x < -eps {
            -1
        } else {
            0
        }
    };
    let (s1, s2, s3, s4) = (sgn(o1), sgn(o2), sgn(o3), sgn(o4));
    if s1 * s2 < 0 && s3 * s4 < 0 {
        let t = o3 / (o3 - o4);
        return Some(a + (b - a) * t);
    }
    let on = |p: Vec2, q: Vec2, r: Vec2| {
        r.x >= p.x.min(q.x) - 1e-14 * scale
            && r.x <= p.x.max(q.x) + 1e-14 * scale
            && r.y >= p.y.min(q.y) - 1e-14 * scale
            && r.y <= p.y.max(q.y) + 1e-14 * scale
    };
    if s1 == 0 && on(a, b, c) {
        return Some(c);
    }
    if s2 == 0 && on(a, b, d) {
        return Some(d);
    }
    if s3 == 0 && on(c, d, a) {
        return Some(a);
    }
    if s4 == 0 && on(c, d, b) {
        return Some(b);
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> Vec2 {
        Vec2::new(x, y)
    }

    #[test]
    fn orientation_area_and_containment() {
        let sq = vec![v(0.0, 0.0), v(0.0, 4.0), v(4.0, 4.0), v(4.0, 0.0)]; // clockwise
        let hole = vec![v(1.0, 1.0), v(2.0, 1.0), v(2.0, 2.0), v(1.0, 2.0)]; // ccw
        let p = Polygon::new(sq, vec![hole]).unwrap();
        assert!(signed_area(p.outer()) > 0.0);
        assert!(signed_area(&p.holes()[0]) < 0.0);
        assert!((p.area() - 15.0).abs() < 1e-12);
        assert!(p.contains(v(3.0, 3.0)));
        assert!(!p.contains(v(1.5, 1.5)));
        assert!(!p.contains(v(5.0, 1.0)));
    }

    #[test]
    fn bow_tie_is_rejected_with_place() {
        let err = Polygon::new(vec![v(0.0, 0.0), v(2.0, 2.0), v(2.0, 0.0), v(0.0, 2.0)], vec![]).unwrap_err();
        match err {
            GeometryError::SelfIntersection { x, y, .. } => assert!((x - 1.0).abs() < 1e-12 && (y - 1.0).abs() < 1e-12),
            e => panic!("unexpected {e}"),
        }
    }

    #[test]
    fn hole_outside_is_rejected() {
        let sq = vec![v(0.0, 0.0), v(1.0, 0.0), v(1.0, 1.0), v(0.0, 1.0)];
        let hole = vec![v(2.0, 2.0), v(3.0, 2.0), v(3.0, 3.0)];
        assert!(matches!(
            Polygon::new(sq, vec![hole]),
            Err(GeometryError::HoleOutside { hole: 0 })
        ));
    }

    #[test]
    fn line_hits_sorted() {
        let p = Polygon::new(vec![v(0.0, 0.0), v(4.0, 0.0), v(4.0, 4.0), v(0.0, 4.0)], vec![]).unwrap();
        let h = p.line_hits(v(2.0, 2.0), v(1.0, 0.0), |_| true);
        assert_eq!(h.len(), 2);
        assert!((h[0].t + 2.0).abs() < 1e-12 && (h[1].t - 2.0).abs() < 1e-12);
    }

    #[test]
    fn segment_predicates_and_even_odd_rings() {
        let v = Vec2::new;
        assert!(segments_cross(v(0.0, 0.0), v(2.0, 2.0), v(0.0, 2.0), v(2.0, 0.0)));
        // Touching at an end point: they meet but do not cross.
        assert!(!segments_cross(v(0.0, 0.0), v(1.0, 1.0), v(1.0, 1.0), v(2.0, 0.0)));
        assert!(segments_meet(v(0.0, 0.0), v(1.0, 1.0), v(1.0, 1.0), v(2.0, 0.0)));
        // Collinear overlap meets; parallel apart does not.
        assert!(segments_meet(v(0.0, 0.0), v(2.0, 0.0), v(1.0, 0.0), v(3.0, 0.0)));
        assert!(!segments_meet(v(0.0, 0.0), v(2.0, 0.0), v(0.0, 1.0), v(2.0, 1.0)));
        assert_eq!(cross2(v(1.0, 0.0), v(0.0, 1.0)), 1.0);
        let square = [v(0.0, 0.0), v(4.0, 0.0), v(4.0, 4.0), v(0.0, 4.0)];
        let hole = [v(1.0, 1.0), v(3.0, 1.0), v(3.0, 3.0), v(1.0, 3.0)];
        let rings = [&square[..], &hole[..]];
        assert!(rings_contain(rings, v(0.5, 0.5)));
        assert!(!rings_contain(rings, v(2.0, 2.0)));
        assert!(!rings_contain(rings, v(5.0, 2.0)));
    }

    #[test]
    fn segment_intersection_basic() {
        let (s, t) = segment_intersection(v(0.0, 0.0), v(2.0, 0.0), v(1.0, -1.0), v(1.0, 1.0)).unwrap();
        assert!((s - 0.5).abs() < 1e-15 && (t - 0.5).abs() < 1e-15);
        assert!(segment_intersection(v(0.0, 0.0), v(1.0, 0.0), v(0.0, 1.0), v(1.0, 1.0)).is_none());
    }

    #[test]
    fn triangles_overlap_only_with_interiors_in_common() {
        let v = |x: f64, y: f64| Vec2::new(x, y);
        let t = [v(0.0, 0.0), v(1.0, 0.0), v(0.0, 1.0)];
        // Sharing an edge, sharing a vertex, apart: no overlap.
        assert!(!triangles_overlap(t, [v(1.0, 0.0), v(1.0, 1.0), v(0.0, 1.0)], 1e-12));
        assert!(!triangles_overlap(t, [v(1.0, 0.0), v(2.0, 0.0), v(2.0, 1.0)], 1e-12));
        assert!(!triangles_overlap(t, [v(3.0, 3.0), v(4.0, 3.0), v(3.0, 4.0)], 1e-12));
        // Crossing, one inside the other, the same triangle: overlap.
        assert!(triangles_overlap(t, [v(0.5, -0.5), v(0.5, 0.5), v(-0.5, 0.5)], 1e-12));
        assert!(triangles_overlap(t, [v(0.1, 0.1), v(0.3, 0.1), v(0.1, 0.3)], 1e-12));
        assert!(triangles_overlap(t, [t[2], t[0], t[1]], 1e-12));
        // A sliver of overlap below the tolerance is touching.
        assert!(!triangles_overlap(
            t,
            [v(0.999_999, 0.0), v(2.0, 0.0), v(2.0, 1.0)],
            1e-3
        ));
        assert!(triangles_overlap(t, [v(0.9, 0.0), v(2.0, 0.0), v(2.0, 1.0)], 1e-3));
    }
}

#[cfg(test)]
mod hull_tests {
    use super::*;

    #[test]
    fn a_hull_fits_a_rectangle_either_way_round_and_turned() {
        let v = Vec2::new;
        let hull = convex_hull(vec![v(0.0, 0.0), v(4.0, 0.0), v(4.0, 1.0), v(0.0, 1.0), v(2.0, 0.5)]);
        assert_eq!(hull.len(), 4, "the inner point is not on the hull: {hull:?}");
        assert!(hull_fits_rectangle(&hull, 4.0, 1.0));
        assert!(hull_fits_rectangle(&hull, 1.0, 4.0));
        assert!(!hull_fits_rectangle(&hull, 3.9, 1.1));
        // A 4 × 1 bar turned by 30°: its axis-aligned box is 3.96 × 2.87, but turned back
        // onto its edge it fits 4 × 1.
        let (s, c) = 30f64.to_radians().sin_cos();
        let turned: Vec<Vec2> = hull.iter().map(|p| v(c * p.x - s * p.y, s * p.x + c * p.y)).collect();
        assert!(hull_fits_rectangle(&convex_hull(turned), 1.0, 4.0));
        assert!(segment_distance([v(0.0, 0.0), v(1.0, 0.0)], [v(0.5, 2.0), v(0.5, 1.0)]) == 1.0);
        assert!(segment_distance([v(0.0, 0.0), v(1.0, 0.0)], [v(0.5, -1.0), v(0.5, 1.0)]) == 0.0);
    }
}

//! The surface patches of §5.1: the minimal cycles of the curve network.
//!
//! Fondevilla et al. list all cycles of the network graph and reject every cycle that
//! contains another. For a drawing (a plane graph) those are exactly the bounded faces
//! of its embedding, found here in linear time by walking half-edges: at each node the
//! outgoing half-edges are sorted by angle, and the half-edge after `u → v` is the one
//! immediately clockwise of `v → u` at `v`, which keeps the face on the left. Bounded
//! faces come out counter-clockwise (positive area, model frame `y` up), the outer face
//! of each connected drawing clockwise.
//!
//! Angles are taken along the chord from the node to the segment's point at a quarter of
//! its length, and at least a thirtieth of the photo's diagonal along its curve (into the
//! curve's next segments when it is shorter), not along the end tangent: a silhouette
//! meets its rim *tangentially* (the contour of a cone or cylinder touches its end
//! ellipses), and only the curve's bending away separates the two; a short chord (a few
//! pixels) is swamped by a pixel of tracing noise. Segments cross only at nodes, and a
//! chord is followed past no node where other curves meet, so the chords keep the
//! segments' order. A face's outline that crosses itself in a small loop
//! (a noisy silhouette crossing its rim a hair from their node) has the loop cut out.
//! Two segments between the same two nodes, both shorter than the chord (a noisy rim
//! bulging past its silhouette and crossing it again), are ordered along the chords to
//! their midpoints; the sliver between them (a face of two or three segments whose mean
//! width `2 area / perimeter` is at most [`SLIVER_WIDTH_SNAPS`] snap distances and
//! [`SLIVER_WIDTH_MAX_PX`]) is no patch, and its segments need bound no other.

use crate::annotation::{image_to_model, PhotoAnnotation};
use crate::cubic;
use crate::curve_network::CurveNetwork;
use crate::PhotoError;
use nalgebra::Vector2;
use sheetform_geometry::{signed_area, Polygon};

type Vec2 = Vector2<f64>;

/// Widest mean width (`2 area / perimeter`), in snap distances, of a face of two or three
/// segments, one of them leaving a node along the same chord as another, that is a sliver
/// of tracing noise rather than a surface (2.3 snap distances on a drawing with 2 px of
/// noise).
const SLIVER_WIDTH_SNAPS: f64 = 3.0;

/// The same width's bound in pixels, whatever the snap distance.
const SLIVER_WIDTH_MAX_PX: f64 = 5.0;

/// Most segments of a curve followed to order the curves leaving a node.
const MAX_ORDER_SEGMENTS: usize = 8;

/// A traversal of a segment: `segment` from its first to its last control point, or the
/// other way when `reversed`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HalfEdge {
    /// Segment index.
    pub segment: u32,
    /// Traversed from its last control point to its first.
    pub reversed: bool,
}

impl HalfEdge {
    fn id(self) -> usize {
        2 * self.segment as usize + usize::from(self.reversed)
    }

    fn from_id(id: usize) -> Self {
        Self {
            segment: (id / 2) as u32,
            reversed: id % 2 == 1,
        }
    }

    /// The same segment the other way.
    pub fn twin(self) -> Self {
        Self {
            segment: self.segment,
            reversed: !self.reversed,
        }
    }

    /// The control points in traversal order.
    pub fn control_points(self, network: &CurveNetwork) -> [Vec2; 4] {
        let b = network.control_points(self.segment as usize);
        if self.reversed {
            [b[3], b[2], b[1], b[0]]
        } else {
            b
        }
    }

    /// The segment parameter of traversal parameter `s`.
    pub fn segment_parameter(self, s: f64) -> f64 {
        if self.reversed {
            1.0 - s
        } else {
            s
        }
    }

    /// First and last node (point indices) in traversal order.
    pub fn nodes(self, network: &CurveNetwork) -> (u32, u32) {
        let p = network.segments[self.segment as usize].points;
        if self.reversed {
            (p[3], p[0])
        } else {
            (p[0], p[3])
        }
    }
}

/// A surface patch: a bounded face of the drawing.
#[derive(Debug, Clone, PartialEq)]
pub struct Patch {
    /// Its boundary, counter-clockwise (model frame).
    pub cycle: Vec<HalfEdge>,
    /// The boundary as a polygon (16 points per segment), for inside tests.
    pub polygon: Polygon,
    /// Area (square pixels).
    pub area: f64,
    /// Marked as an opening (`openings`): no surface.
    pub opening: bool,
}

/// Finds the patches of a network.
///
/// # Errors
/// [`PhotoError::Curve`] naming a curve that bounds no patch (a dangling or lone curve),
/// [`PhotoError::NoPatch`] when nothing closes.
pub fn find_patches(network: &CurveNetwork, annotation: &PhotoAnnotation) -> Result<Vec<Patch>, PhotoError> {
    let lengths = annotation.lengths();
    let half_count = 2 * network.segments.len();
    // Short dangling tails (a traced end that overshoots a crossing) are trimmed:
    // segments with a free end, shorter than the grazing distance of the network.
    let graze = (8.0 * lengths.snap).max(annotation.diagonal() / 60.0);
    let mut trimmed = vec![false; network.segments.len()];
    loop {
        let mut degree = vec![0usize; network.points.len()];
        for (s, seg) in network.segments.iter().enumerate() {
            if !trimmed[s] {
                degree[seg.points[0] as usize] += 1;
                degree[seg.points[3] as usize] += 1;
            }
        }
        let mut changed = false;
        for (s, seg) in network.segments.iter().enumerate() {
            let free = degree[seg.points[0] as usize] == 1 || degree[seg.points[3] as usize] == 1;
            if trimmed[s] || !free {
                continue;
            }
            // Short, or up to four times as long but hugging another curve (within twice
            // the snap distance all along: the tail of an end that grazed a rim, see
            // `curve_network.rs`).
            let b = network.control_points(s);
            let length = cubic::hull_length(&b);
            let hugs = || {
                (0..=10).all(|k| {
                    let p = cubic::point(&b, k as f64 / 10.0);
                    (0..network.segments.len()).any(|o| {
                        o != s
                            && !trimmed[o]
                            && cubic::nearest_parameter(&network.control_points(o), p).1 <= 2.0 * lengths.snap
                    })
                })
            };
            if length <= graze || (length <= 4.0 * graze && hugs()) {
                trimmed[s] = true;
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    // Outgoing half-edges per node with their angle, taken along a chord of at least a
    // thirtieth of the diagonal (16 px on a 480 px photo): two curves that leave a node
    // tangentially (a silhouette and its rim) are told apart by how far they have bent
    // apart, `c²κ/2` at chord `c` (5 px at 20 px on a rim's end, κ ≈ 1/35 px), which a
    // pixel of tracing noise must not swamp; a segment shorter than that is followed into
    // the next segments of its curve, up to the first node where other curves meet (past
    // it the chord could pass them, and the order would no longer be the segments').
    let order_distance = annotation.diagonal() / 30.0;
    let mut degree = vec![0usize; network.points.len()];
    for (s, seg) in network.segments.iter().enumerate() {
        if !trimmed[s] {
            degree[seg.points[0] as usize] += 1;
            degree[seg.points[3] as usize] += 1;
        }
    }
    let mut outgoing: Vec<Vec<(f64, usize)>> = vec![Vec::new(); network.points.len()];
    for id in 0..half_count {
        let h = HalfEdge::from_id(id);
        if trimmed[h.segment as usize] {
            continue;
        }
        let b = h.control_points(network);
        let (start, _) = h.nodes(network);
        let d = leaving_direction(
            network,
            h,
            &trimmed,
            &degree,
            (0.25 * cubic::hull_length(&b)).max(order_distance),
        );
        outgoing[start as usize].push((d.y.atan2(d.x), id));
    }
    // Two segments between the same two nodes, each shorter than the chord (a noisy rim
    // bulging a pixel or two past its silhouette and crossing it again), end their
    // chords at the same node: the same angle, and an order left to chance. Those are
    // told apart along the chord to each one's midpoint, which bulge apart.
    // The tie is broken by a nudge far below any other gap (the midpoint's side of the
    // shared chord), so the tied pair keeps its place among the other half-edges.
    let mut tied_half_edges = vec![false; half_count];
    for list in &mut outgoing {
        let n = list.len();
        let tied: Vec<usize> = (0..n)
            .filter(|&k| (0..n).any(|j| j != k && list[k].0 == list[j].0))
            .collect();
        for k in tied {
            let b = HalfEdge::from_id(list[k].1).control_points(network);
            let d = cubic::point(&b, 0.5) - b[0];
            let turn = (d.y.atan2(d.x) - list[k].0 + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
                - std::f64::consts::PI;
            list[k].0 += 1e-12 * turn;
            tied_half_edges[list[k].1] = true;
        }
        list.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    // Position of each half-edge in its start node's list.
    let mut slot = vec![(0u32, 0usize); half_count];
    for (node, list) in outgoing.iter().enumerate() {
        for (k, &(_, id)) in list.iter().enumerate() {
            slot[id] = (node as u32, k);
        }
    }
    let next = |id: usize| -> usize {
        let twin = HalfEdge::from_id(id).twin().id();
        let (node, k) = slot[twin];
        let list = &outgoing[node as usize];
        list[(k + list.len() - 1) % list.len()].1
    };
    let mut face_of = vec![usize::MAX; half_count];
    let mut faces: Vec<Vec<usize>> = Vec::new();
    for start in 0..half_count {
        if face_of[start] != usize::MAX || trimmed[start / 2] {
            continue;
        }
        let mut face = Vec::new();
        let mut h = start;
        while face_of[h] == usize::MAX {
            face_of[h] = faces.len();
            face.push(h);
            h = next(h);
            if face.len() > half_count {
                break;
            }
        }
        faces.push(face);
    }
    let mut patches = Vec::new();
    let mut face_patch = vec![usize::MAX; faces.len()];
    let mut sliver = vec![false; faces.len()];
    for (f, face) in faces.iter().enumerate() {
        let ring: Vec<Vec2> = face
            .iter()
            .flat_map(|&id| {
                let b = HalfEdge::from_id(id).control_points(network);
                (0..16).map(move |i| cubic::point(&b, i as f64 / 16.0))
            })
            .collect();
        let area = signed_area(&ring);
        // A face that uses both sides of a segment is a dangling curve's, not a patch.
        let dangling = face.iter().any(|&id| face_of[HalfEdge::from_id(id).twin().id()] == f);
        if area <= 0.0 || dangling {
            continue;
        }
        // A sliver between two tied half-edges (a noisy rim bulging past the silhouette
        // it leaves tangentially, and crossing it again) is no surface: two or three
        // segments, one of them tied, a mean width `2 area / perimeter` of at most
        // `SLIVER_WIDTH_SNAPS` snap distances and `SLIVER_WIDTH_MAX_PX`.
        if (2..=3).contains(&face.len()) && face.iter().any(|&id| tied_half_edges[id]) {
            let perimeter: f64 = (0..ring.len())
                .map(|i| (ring[(i + 1) % ring.len()] - ring[i]).norm())
                .sum();
            let width = 2.0 * area / perimeter;
            if width <= (SLIVER_WIDTH_SNAPS * lengths.snap).min(SLIVER_WIDTH_MAX_PX) {
                tracing::debug!(
                    width,
                    area,
                    at = ?ring[0],
                    "photo: a sliver between a curve and one it leaves tangentially is no patch"
                );
                sliver[f] = true;
                continue;
            }
        }
        // A pixel of tracing noise where a silhouette leaves its rim tangentially can make
        // the two cross a hair from their node: that small loop is cut out of the ring.
        let polygon = match Polygon::new(ring.clone(), vec![]) {
            Ok(polygon) => polygon,
            Err(_) => {
                let small = (16.0 * lengths.snap * lengths.snap).max(1e-3 * area);
                let Ok(polygon) = Polygon::new(without_small_loops(ring, small), vec![]) else {
                    continue;
                };
                polygon
            }
        };
        let opening = annotation.openings.iter().any(|&o| polygon.contains(image_to_model(o)));
        face_patch[f] = patches.len();
        patches.push(Patch {
            cycle: face.iter().map(|&id| HalfEdge::from_id(id)).collect(),
            polygon,
            area,
            opening,
        });
    }
    // Every segment must bound a patch on at least one side.
    for (s, seg) in network.segments.iter().enumerate() {
        if trimmed[s] {
            continue;
        }
        let sides = [face_of[2 * s], face_of[2 * s + 1]];
        if sides.iter().all(|&f| face_patch[f] == usize::MAX) && !sides.iter().any(|&f| sliver[f]) {
            let curve = &network.curves[seg.curve as usize];
            // The curve's ends that meet nothing: where a curve is missing (a silhouette
            // left out) or an end stops short.
            let mut degree = vec![0usize; network.points.len()];
            for other in &network.segments {
                degree[other.points[0] as usize] += 1;
                degree[other.points[3] as usize] += 1;
            }
            let free: Vec<String> = curve
                .segments
                .iter()
                .flat_map(|&k| {
                    let ids = network.segments[k as usize].points;
                    [ids[0], ids[3]]
                })
                .filter(|&id| degree[id as usize] == 1)
                .map(|id| {
                    let p = network.points[id as usize];
                    format!("[{:.1}, {:.1}]", p.x, -p.y)
                })
                .collect();
            let message = if free.is_empty() {
                let b = network.control_points(s);
                let mid = cubic::point(&b, 0.5);
                format!(
                    "closes no cycle near [{:.1}, {:.1}] px: its ends must meet other curves (within {:.2} px)",
                    mid.x, -mid.y, lengths.snap
                )
            } else {
                format!(
                    "closes no cycle: its end at {} px meets no other curve (within {:.2} px). A curve from there \
                     is missing (a silhouette or boundary not traced yet?), or the end must reach the curve it \
                     stops at",
                    free.join(" and "),
                    lengths.snap
                )
            };
            return Err(PhotoError::curve(&curve.name, message));
        }
    }
    if patches.iter().all(|p| p.opening) {
        return Err(PhotoError::NoPatch(if patches.is_empty() {
            "no closed cycle of curves".into()
        } else {
            "every closed region is marked as an opening".into()
        }));
    }
    Ok(patches)
}

/// `ring` with every loop of at most `max_area` that two of its edges cut off by crossing
/// replaced by the crossing point (at most 16 loops; the bigger side is kept).
fn without_small_loops(mut ring: Vec<Vec2>, max_area: f64) -> Vec<Vec2> {
    let orient = |p: Vec2, q: Vec2, r: Vec2| (q - p).perp(&(r - p));
    for _ in 0..16 {
        let n = ring.len();
        let mut crossing = None;
        'search: for i in 0..n {
            let (a, b) = (ring[i], ring[(i + 1) % n]);
            for j in i + 2..n {
                if i == 0 && j == n - 1 {
                    continue;
                }
                let (c, d) = (ring[j], ring[(j + 1) % n]);
                let (s1, s2) = (orient(a, b, c), orient(a, b, d));
                let (s3, s4) = (orient(c, d, a), orient(c, d, b));
                if s1 * s2 < 0.0 && s3 * s4 < 0.0 {
                    crossing = Some((i, j, a + (b - a) * (s3 / (s3 - s4))));
                    break 'search;
                }
            }
        }
        let Some((i, j, p)) = crossing else {
            break;
        };
        let mut inner: Vec<Vec2> = ring[i + 1..=j].to_vec();
        inner.push(p);
        let mut outer: Vec<Vec2> = ring[j + 1..].iter().chain(&ring[..=i]).copied().collect();
        outer.push(p);
        let (inner_area, outer_area) = (signed_area(&inner).abs(), signed_area(&outer).abs());
        if inner_area.min(outer_area) > max_area {
            break;
        }
        ring = if inner_area <= outer_area { outer } else { inner };
    }
    ring
}

/// Direction from a half-edge's start to the point at chord distance `r` along its
/// curve: past the segment's end into the next segments of the same traced curve (not
/// trimmed ones, and not past a node of `degree` above 2) while it is shorter, to the last point reached when the curve ends
/// first. The tangent at the start if that point is the start.
fn leaving_direction(network: &CurveNetwork, h: HalfEdge, trimmed: &[bool], degree: &[usize], r: f64) -> Vec2 {
    let first = h.control_points(network);
    let start = first[0];
    let curve = &network.curves[network.segments[h.segment as usize].curve as usize];
    let mut at = curve.segments.iter().position(|&s| s == h.segment);
    let mut current = h;
    let mut last = start;
    for _ in 0..MAX_ORDER_SEGMENTS {
        let b = current.control_points(network);
        // The first sample at chord distance `r`, then bisection between it and the one
        // before.
        let samples = 32;
        let mut previous = 0.0;
        for k in 1..=samples {
            let t = k as f64 / samples as f64;
            let q = cubic::point(&b, t);
            if (q - start).norm() >= r {
                let (mut lo, mut hi) = (previous, t);
                for _ in 0..40 {
                    let mid = 0.5 * (lo + hi);
                    if (cubic::point(&b, mid) - start).norm() < r {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                return cubic::point(&b, hi) - start;
            }
            previous = t;
            last = q;
        }
        // The next segment of the curve in the direction of travel, unless other curves
        // meet at the node between.
        let (_, node) = current.nodes(network);
        if degree[node as usize] > 2 {
            break;
        }
        let Some(k) = at else { break };
        let n = curve.segments.len();
        let next = if current.reversed {
            if k > 0 {
                Some(k - 1)
            } else if curve.closed {
                Some(n - 1)
            } else {
                None
            }
        } else if k + 1 < n {
            Some(k + 1)
        } else if curve.closed {
            Some(0)
        } else {
            None
        };
        let Some(next) = next else { break };
        let segment = curve.segments[next];
        if trimmed[segment as usize] || segment == h.segment {
            break;
        }
        at = Some(next);
        current = HalfEdge {
            segment,
            reversed: current.reversed,
        };
    }
    let d = last - start;
    if d.norm() > 0.0 {
        d
    } else {
        cubic::derivative(&first, 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 100 px square whose right side, near its top corner, makes a 2 px wide loop
    /// across the top side (a noisy silhouette crossing its rim a hair from their node):
    /// the loop is cut out and the outline is valid with the square's area; a loop over the
    /// bound (0.01 px² here) is left.
    #[test]
    fn a_small_loop_at_a_tangential_node_is_cut_out() {
        let ring = vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(100.0, 0.0),
            Vec2::new(100.0, 99.0),
            Vec2::new(97.0, 101.0),
            Vec2::new(99.0, 100.5),
            Vec2::new(0.0, 100.0),
        ];
        assert!(
            Polygon::new(ring.clone(), vec![]).is_err(),
            "the loop crosses the outline"
        );
        let repaired = without_small_loops(ring.clone(), 50.0);
        let polygon = Polygon::new(repaired.clone(), vec![]).expect("the loop is cut out");
        let area = signed_area(polygon.outer()).abs();
        assert!((area - 10_000.0).abs() < 50.0, "{area}: {repaired:?}");
        assert_eq!(
            without_small_loops(ring.clone(), 0.01),
            ring,
            "a loop over the bound is kept"
        );
    }
}

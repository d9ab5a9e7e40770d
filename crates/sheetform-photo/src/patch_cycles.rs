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
//! its length, not along the end tangent: a silhouette meets its rim *tangentially* (the
//! contour of a cone or cylinder touches its end ellipses), and only the curve's bending
//! away separates the two; a short chord (a few pixels) is swamped by a pixel of tracing
//! noise. Segments cross only at nodes, so the chords keep the segments' order.

use crate::annotation::{image_to_model, PhotoAnnotation};
use crate::cubic;
use crate::curve_network::CurveNetwork;
use crate::PhotoError;
use nalgebra::Vector2;
use sheetform_geometry::{signed_area, Polygon};

type Vec2 = Vector2<f64>;

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
            if !trimmed[s] && free && cubic::hull_length(&network.control_points(s)) <= graze {
                trimmed[s] = true;
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    // Outgoing half-edges per node with their angle.
    let mut outgoing: Vec<Vec<(f64, usize)>> = vec![Vec::new(); network.points.len()];
    for id in 0..half_count {
        let h = HalfEdge::from_id(id);
        if trimmed[h.segment as usize] {
            continue;
        }
        let b = h.control_points(network);
        let (start, _) = h.nodes(network);
        let d = leaving_direction(&b, 0.25 * cubic::hull_length(&b));
        outgoing[start as usize].push((d.y.atan2(d.x), id));
    }
    for list in &mut outgoing {
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
        let Ok(polygon) = Polygon::new(ring, vec![]) else {
            continue;
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
        if sides.iter().all(|&f| face_patch[f] == usize::MAX) {
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

/// Direction from a segment's start to its point at chord distance `r` (or its end
/// when shorter).
fn leaving_direction(b: &[Vec2; 4], r: f64) -> Vec2 {
    let chord = (b[3] - b[0]).norm();
    let r = r.min(0.3 * cubic::hull_length(b)).max(1e-9);
    let (mut lo, mut hi) = (0.0, 1.0);
    if chord > r {
        for _ in 0..50 {
            let mid = 0.5 * (lo + hi);
            if (cubic::point(b, mid) - b[0]).norm() < r {
                lo = mid;
            } else {
                hi = mid;
            }
        }
    } else {
        hi = 1.0;
    }
    let d = cubic::point(b, hi) - b[0];
    if d.norm() > 0.0 {
        d
    } else {
        cubic::derivative(b, 0.0)
    }
}

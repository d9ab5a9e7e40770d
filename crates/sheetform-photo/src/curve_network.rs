//! The curve network of §5.1: the traced curves split at their intersections into cubic
//! segments whose end points are shared, so that crossing curves meet in 3D.
//!
//! Fondevilla et al. "detect intersections between the traced curves and resample them
//! to obtain C¹ piecewise cubic curves with endpoints at intersections". Here the curves
//! are *split* exactly (de Casteljau, `sheetform_geometry::Bezier::segment`) at each
//! intersection instead of refitted, so the
//! network has the drawing's exact shape and stays C¹ within each curve. Intersections
//! are found on 32-piece polylines of each segment pair whose control hulls' boxes
//! overlap, then refined by Newton's method on `B₁(t₁) − B₂(t₂) = 0`.
//!
//! Beyond the paper (hand tracing is never exact): a curve end within the snap distance
//! of another curve is joined to it (a T-junction); a junction within
//! [`knot_snap_radius`] of a knot (a curve's end or segment join) is moved to that knot
//! (no sliver segments), and a node sits at its firmest points (a traced node rather than
//! a split or a curve's end); an end that grazes a curve and crosses it a few pixels on
//! is joined at the crossing, and the short tail beyond it is dropped. Crossings near an
//! `occlusions` mark are left unjoined (§4). A curve that crosses itself is refused.

use crate::annotation::{image_to_model, CurveKind, PhotoAnnotation};
use crate::cubic;
use crate::PhotoError;
use nalgebra::Vector2;
use sheetform_geometry::{segment_intersection, Bezier2};

/// Most crossings between the traced curves: matching and clustering them is quadratic
/// (two zig-zag curves of 1 440 control points crossing each other ran out of 6.5 GB
/// after 10 minutes); a traced photo has tens.
pub const MAX_CROSSINGS: usize = 2_000;
/// Most samples along all curves (their control polygons' length over the sample
/// spacing).
pub const MAX_CURVE_SAMPLES: usize = 200_000;

type Vec2 = Vector2<f64>;

/// One cubic segment of the network.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NetworkSegment {
    /// Its four control points (indices into [`CurveNetwork::points`]); the first and
    /// last are the segment's end nodes.
    pub points: [u32; 4],
    /// The traced curve it belongs to (index into [`CurveNetwork::curves`]).
    pub curve: u32,
}

/// One traced curve after splitting.
#[derive(Debug, Clone, PartialEq)]
pub struct NetworkCurve {
    /// The annotation's name.
    pub name: String,
    /// Silhouette or boundary.
    pub kind: CurveKind,
    /// Its segments in order along the curve.
    pub segments: Vec<u32>,
    /// Whether it ends where it starts.
    pub closed: bool,
}

/// The traced curves as a network of cubic segments with shared control points.
#[derive(Debug, Clone, PartialEq)]
pub struct CurveNetwork {
    /// Control points in the model frame (pixels, `y` up): the unknowns of §6 in 2D.
    pub points: Vec<Vec2>,
    /// The cubic segments.
    pub segments: Vec<NetworkSegment>,
    /// The traced curves, in the annotation's order.
    pub curves: Vec<NetworkCurve>,
    /// Points where two or more curves are joined.
    pub junction_count: usize,
    /// Crossings left unjoined because of an `occlusions` mark.
    pub occluded_crossing_count: usize,
}

impl CurveNetwork {
    /// The control points of segment `s`.
    pub fn control_points(&self, s: usize) -> [Vec2; 4] {
        self.segments[s].points.map(|i| self.points[i as usize])
    }

    /// The control points of the annotation (before splitting), over all curves.
    pub fn annotated_control_point_count(annotation: &PhotoAnnotation) -> usize {
        annotation.curves.iter().map(|c| c.control_points.len()).sum()
    }
}

/// A place on a traced curve: global parameter `u = segment + t`.
#[derive(Debug, Clone, Copy)]
struct CurvePlace {
    curve: usize,
    u: f64,
}

/// How far a junction may be from a knot of a curve (an end or a join of its traced
/// segments) and still be moved onto it: the snap distance, and at least one sample
/// spacing. A split nearer the knot would leave a sliver segment without a sample of its
/// own, whose control points nothing but the C¹ rows hold (one 1.5 px from a rim's node
/// left 3 % of a depth shift free across the strip).
pub fn knot_snap_radius(lengths: &crate::AnalysisLengths) -> f64 {
    lengths.snap.max(lengths.sample)
}

/// Builds the network: intersections, snapping, splitting, shared end points.
///
/// # Errors
/// [`PhotoError::Curve`] for a curve of zero length or one that crosses itself.
pub fn build_curve_network(annotation: &PhotoAnnotation) -> Result<CurveNetwork, PhotoError> {
    let lengths = annotation.lengths();
    let diagonal = annotation.diagonal();
    let occlusion_radius = diagonal / 60.0;
    // Each curve's cubic segments in the model frame.
    let curves: Vec<Vec<[Vec2; 4]>> = annotation
        .curves
        .iter()
        .map(|c| {
            let p: Vec<Vec2> = c.control_points.iter().map(|&q| image_to_model(q)).collect();
            (0..(p.len() - 1) / 3)
                .map(|j| [p[3 * j], p[3 * j + 1], p[3 * j + 2], p[3 * j + 3]])
                .collect()
        })
        .collect();
    let mut hull_total = 0.0;
    for (c, segs) in curves.iter().enumerate() {
        let hull: f64 = segs.iter().map(cubic::hull_length).sum();
        if hull < 1e-3 {
            return Err(PhotoError::curve(&annotation.curves[c].name, "has zero length"));
        }
        hull_total += hull;
    }
    // The control polygons bound the curves' lengths: at most this many samples.
    let samples = hull_total / lengths.sample;
    if samples > MAX_CURVE_SAMPLES as f64 {
        return Err(PhotoError::field(
            "analysis.sample_spacing_px",
            format!(
                "up to {} samples along the curves at {} px (at most {MAX_CURVE_SAMPLES}); give a larger spacing",
                sheetform_geometry::short_number(samples.ceil()),
                sheetform_geometry::short_number(lengths.sample)
            ),
        ));
    }
    let polylines: Vec<Vec<Vec<Vec2>>> = curves
        .iter()
        .map(|segs| segs.iter().map(|b| cubic::polyline(b, 32)).collect())
        .collect();
    let boxes: Vec<Vec<(Vec2, Vec2)>> = curves
        .iter()
        .map(|segs| {
            segs.iter()
                .map(|b| {
                    let lo = b.iter().fold(Vec2::repeat(f64::INFINITY), |a, p| a.inf(p));
                    let hi = b.iter().fold(Vec2::repeat(f64::NEG_INFINITY), |a, p| a.sup(p));
                    (lo, hi)
                })
                .collect()
        })
        .collect();
    let overlap = |a: (Vec2, Vec2), b: (Vec2, Vec2), pad: f64| {
        a.0.x <= b.1.x + pad && b.0.x <= a.1.x + pad && a.0.y <= b.1.y + pad && b.0.y <= a.1.y + pad
    };
    let near_occlusion = |p: Vec2| {
        annotation
            .occlusions
            .iter()
            .any(|&o| (image_to_model(o) - p).norm() <= occlusion_radius)
    };
    // Junction candidates: a 2D position and the places on curves that meet there.
    let mut junctions: Vec<(Vec2, Vec<CurvePlace>)> = Vec::new();
    let mut occluded = 0usize;
    let knot_radius = knot_snap_radius(&lengths);
    let curve_end = |c: usize, u: f64| -> Option<f64> {
        // The knot (a curve end or a join of the traced segments) a place is within
        // `knot_radius` of: splitting there instead leaves no sliver segment. A closed
        // curve's start and end are the same knot.
        let segs = &curves[c];
        let p = point_at(segs, u);
        let n = segs.len();
        let knot = |k: usize| if k == n { segs[n - 1][3] } else { segs[k][0] };
        let lo = (u.floor() as usize).min(n);
        let hi = (u.ceil() as usize).min(n);
        [lo, hi]
            .into_iter()
            .filter(|&k| (p - knot(k)).norm() <= knot_radius)
            .min_by(|&x, &y| (p - knot(x)).norm().total_cmp(&(p - knot(y)).norm()))
            .map(|k| k as f64)
    };
    for a in 0..curves.len() {
        for b in a..curves.len() {
            for (i, sa) in curves[a].iter().enumerate() {
                for (j, sb) in curves[b].iter().enumerate() {
                    if a == b {
                        let n = curves[a].len();
                        let adjacent = j <= i + 1 || (annotation.curves[a].closed && i == 0 && j == n - 1);
                        if adjacent {
                            continue;
                        }
                    }
                    if !overlap(boxes[a][i], boxes[b][j], lengths.snap) {
                        continue;
                    }
                    for (ta, tb) in polyline_crossings(&polylines[a][i], &polylines[b][j]) {
                        let (ta, tb) = refine_crossing(sa, sb, ta, tb);
                        let p = cubic::point(sa, ta);
                        if a == b {
                            return Err(PhotoError::curve(
                                &annotation.curves[a].name,
                                format!(
                                    "crosses itself near [{:.1}, {:.1}] px; trace it as separate curves",
                                    p.x, -p.y
                                ),
                            ));
                        }
                        if near_occlusion(p) {
                            occluded += 1;
                            continue;
                        }
                        let ua = curve_end(a, i as f64 + ta).unwrap_or(i as f64 + ta);
                        let ub = curve_end(b, j as f64 + tb).unwrap_or(j as f64 + tb);
                        junctions.push((p, vec![CurvePlace { curve: a, u: ua }, CurvePlace { curve: b, u: ub }]));
                        if junctions.len() > MAX_CROSSINGS {
                            return Err(PhotoError::field(
                                "curves",
                                format!(
                                    "the curves cross more than {MAX_CROSSINGS} times (`{}` and `{}` among them); \
                                     trace the boundaries and silhouettes of the pieces, not a hatching",
                                    annotation.curves[a].name, annotation.curves[b].name
                                ),
                            ));
                        }
                    }
                }
            }
        }
    }
    // Ends that stop short of (or just touch) another curve: T-junctions.
    for a in 0..curves.len() {
        if annotation.curves[a].closed {
            continue;
        }
        let n = curves[a].len();
        for (u_end, p) in [(0.0, curves[a][0][0]), (n as f64, curves[a][n - 1][3])] {
            let mut best: Option<(f64, CurvePlace)> = None;
            for b in 0..curves.len() {
                if b == a {
                    continue;
                }
                for (j, sb) in curves[b].iter().enumerate() {
                    let bx = boxes[b][j];
                    if !overlap((p, p), bx, lengths.snap) {
                        continue;
                    }
                    let (t, d) = cubic::nearest_parameter(sb, p);
                    if d <= lengths.snap && best.is_none_or(|(bd, _)| d < bd) {
                        let ub = curve_end(b, j as f64 + t).unwrap_or(j as f64 + t);
                        best = Some((d, CurvePlace { curve: b, u: ub }));
                    }
                }
            }
            if let Some((_, place)) = best {
                if near_occlusion(p) {
                    occluded += 1;
                    continue;
                }
                junctions.push((p, vec![CurvePlace { curve: a, u: u_end }, place]));
            }
        }
    }
    // A traced end that touches a curve tangentially (a silhouette on its rim ellipse)
    // grazes it: tracing noise makes it cross the curve a few pixels from the end. Of two
    // junctions of the same two curves closer than `graze`, the real crossing is kept and
    // the end's contact dropped; the short tail beyond the crossing dangles and is
    // trimmed when the patches are found.
    let graze = (8.0 * lengths.snap).max(diagonal / 60.0);
    let at_end =
        |pl: &CurvePlace| !annotation.curves[pl.curve].closed && (pl.u == 0.0 || pl.u == curves[pl.curve].len() as f64);
    let mut keep = vec![true; junctions.len()];
    for i in 0..junctions.len() {
        for j in 0..junctions.len() {
            if i == j || !keep[i] || !keep[j] {
                continue;
            }
            let same_pair = same_two_curves(&junctions[i].1, &junctions[j].1);
            let distance = (junctions[i].0 - junctions[j].0).norm();
            let (end_i, end_j) = (junctions[i].1.iter().any(at_end), junctions[j].1.iter().any(at_end));
            if !(same_pair && end_i && !end_j) {
                continue;
            }
            // Farther than `graze` (up to four times), the end's tail up to the crossing
            // still grazes when it never leaves the other curve by more than twice the
            // snap distance: a sliver, not a region (a noisy straight silhouette along a
            // rim's short segment, 1.7 px from it over 12 px).
            let grazing = distance <= graze
                || (distance <= 4.0 * graze
                    && tail_hugs(&curves, at_end, &junctions[i].1, &junctions[j].1, 2.0 * lengths.snap));
            if grazing {
                keep[i] = false;
            }
        }
    }
    let mut junctions: Vec<(Vec2, Vec<CurvePlace>)> = junctions
        .into_iter()
        .zip(keep)
        .filter_map(|(j, k)| k.then_some(j))
        .collect();
    // Where the end of one curve is traced a pixel or two past the end of the other (a
    // silhouette's end moved along the rim it stops on), the two curves cross near their
    // ends as well as touch: two junctions of the same two curves, each at an end, a
    // few pixels apart, and between them a sliver patch. They are one node: the second
    // is moved onto the first, and the clustering below keeps each curve's end there.
    for j in 0..junctions.len() {
        for i in 0..j {
            let same_pair = same_two_curves(&junctions[i].1, &junctions[j].1);
            let close = (junctions[i].0 - junctions[j].0).norm() <= graze;
            if same_pair && close && junctions[i].1.iter().any(at_end) && junctions[j].1.iter().any(at_end) {
                junctions[j].0 = junctions[i].0;
                break;
            }
        }
    }
    // Junctions closer than the snap distance are one node (three curves through one
    // point give three pairwise crossings); a node takes one place per curve (two
    // places of one curve there would make a zero-length loop), a curve's end first.
    let mut clusters: Vec<(Vec2, Vec<CurvePlace>)> = Vec::new();
    for (p, places) in junctions {
        let k = match clusters
            .iter()
            .position(|(q, _)| (q - p).norm() <= lengths.snap.max(1e-6))
        {
            Some(k) => k,
            None => {
                clusters.push((p, Vec::new()));
                clusters.len() - 1
            }
        };
        let list = &mut clusters[k].1;
        for place in places {
            match list.iter().position(|q| q.curve == place.curve) {
                Some(i) if at_end(&place) && !at_end(&list[i]) => list[i] = place,
                Some(_) => {}
                None => list.push(place),
            }
        }
    }
    // Split parameters per curve, and the knot (by global parameter) each junction uses.
    let mut splits: Vec<Vec<f64>> = curves
        .iter()
        .map(|s| (0..=s.len()).map(|k| k as f64).collect())
        .collect();
    for (_, places) in &clusters {
        for place in places {
            splits[place.curve].push(place.u);
        }
    }
    for s in &mut splits {
        s.sort_by(f64::total_cmp);
        s.dedup_by(|x, y| (*x - *y).abs() < 1e-7);
    }
    let knot_of = |splits: &Vec<f64>, u: f64| -> usize {
        splits
            .iter()
            .enumerate()
            .min_by(|x, y| (x.1 - u).abs().total_cmp(&(y.1 - u).abs()))
            .map(|(k, _)| k)
            .expect("a curve has knots")
    };
    // Points: every knot of every curve gets one, interior handles their own.
    let mut points: Vec<Vec2> = Vec::new();
    let mut segments: Vec<NetworkSegment> = Vec::new();
    let mut network_curves: Vec<NetworkCurve> = Vec::new();
    let mut knot_points: Vec<Vec<u32>> = Vec::new();
    // How firmly each point is placed, for the junctions: a knot the user traced (a join
    // of a curve's segments, or any knot of a closed curve) 2, a split made at a crossing
    // 1, the end of an open curve (where the user stopped drawing) 0.
    let mut firmness: Vec<u8> = Vec::new();
    for (c, segs) in curves.iter().enumerate() {
        let knots = &splits[c];
        let mut ids: Vec<u32> = Vec::with_capacity(knots.len());
        let closed = annotation.curves[c].closed;
        for &u in knots {
            ids.push(points.len() as u32);
            points.push(point_at(segs, u));
            let stop = !closed && (u == 0.0 || u == segs.len() as f64);
            firmness.push(if stop {
                0
            } else if u.fract() == 0.0 {
                2
            } else {
                1
            });
        }
        if closed {
            // The last knot is the first.
            let last = ids.len() - 1;
            ids[last] = ids[0];
        }
        let mut curve_segments = Vec::new();
        for k in 0..knots.len() - 1 {
            let (u0, u1) = (knots[k], knots[k + 1]);
            let piece = sub_cubic(segs, u0, u1);
            let i1 = points.len() as u32;
            points.push(piece[1]);
            points.push(piece[2]);
            firmness.extend([1, 1]);
            curve_segments.push(segments.len() as u32);
            segments.push(NetworkSegment {
                points: [ids[k], i1, i1 + 1, ids[k + 1]],
                curve: c as u32,
            });
        }
        knot_points.push(ids);
        network_curves.push(NetworkCurve {
            name: annotation.curves[c].name.clone(),
            kind: annotation.curves[c].kind,
            segments: curve_segments,
            closed,
        });
    }
    // Merge the points of each junction (union–find), at their mean position.
    let mut parent: Vec<u32> = (0..points.len() as u32).collect();
    fn find(parent: &mut [u32], mut i: u32) -> u32 {
        while parent[i as usize] != i {
            parent[i as usize] = parent[parent[i as usize] as usize];
            i = parent[i as usize];
        }
        i
    }
    for (_, places) in &clusters {
        let ids: Vec<u32> = places
            .iter()
            .map(|pl| knot_points[pl.curve][knot_of(&splits[pl.curve], pl.u)])
            .collect();
        for &id in &ids[1..] {
            let (ra, rb) = (find(&mut parent, ids[0]), find(&mut parent, id));
            if ra != rb {
                parent[rb as usize] = ra;
            }
        }
    }
    let mut new_index = vec![u32::MAX; points.len()];
    let mut merged: Vec<Vec2> = Vec::new();
    let mut counts: Vec<f64> = Vec::new();
    for i in 0..points.len() as u32 {
        let r = find(&mut parent, i);
        if new_index[r as usize] == u32::MAX {
            new_index[r as usize] = merged.len() as u32;
            merged.push(Vec2::zeros());
            counts.push(0.0);
        }
        let k = new_index[r as usize];
        new_index[i as usize] = k;
    }
    // Only points that are referenced count towards the mean (a closed curve's last
    // knot point is replaced by its first and never used).
    let mut used = vec![false; points.len()];
    for s in &segments {
        for &p in &s.points {
            used[p as usize] = true;
        }
    }
    // A node is the mean of its firmest points: an end traced a pixel or two off a rim's
    // node, or a crossing moved onto it, moves onto the node, and the rim keeps its shape.
    let mut firmest = vec![0u8; merged.len()];
    for i in 0..points.len() {
        if used[i] {
            let k = new_index[i] as usize;
            firmest[k] = firmest[k].max(firmness[i]);
        }
    }
    for i in 0..points.len() {
        let k = new_index[i] as usize;
        if used[i] && firmness[i] == firmest[k] {
            merged[k] += points[i];
            counts[k] += 1.0;
        }
    }
    for (m, c) in merged.iter_mut().zip(&counts) {
        if *c > 0.0 {
            *m /= *c;
        }
    }
    // A node moved to its junction's place takes its handles along: moved alone, it
    // would kink the curve (a rim's node moved along its own tangent folds the rim into a
    // loop the patch outline crosses). A straight segment (a silhouette) stays straight:
    // its handles keep their places along the new chord.
    for seg in &segments {
        let old: [Vec2; 4] = seg.points.map(|p| points[p as usize]);
        let (a, b) = (
            merged[new_index[seg.points[0] as usize] as usize],
            merged[new_index[seg.points[3] as usize] as usize],
        );
        let chord = old[3] - old[0];
        let length = chord.norm();
        let straight = length > 0.0
            && [old[1], old[2]]
                .iter()
                .all(|q| (chord.x * (q - old[0]).y - chord.y * (q - old[0]).x).abs() <= 1e-3 * length * length);
        for (new_end, handle, k) in [(a, seg.points[1], 1), (b, seg.points[2], 2)] {
            let place = if straight {
                a + (b - a) * ((old[k] - old[0]).dot(&chord) / (length * length))
            } else {
                old[k] + (new_end - old[3 * (k - 1)])
            };
            merged[new_index[handle as usize] as usize] = place;
        }
    }
    for s in &mut segments {
        s.points = s.points.map(|p| new_index[p as usize]);
    }
    // Tails: a traced end that grazes a curve and crosses it a few pixels on leaves the
    // piece beyond the crossing dangling. It bounds no patch, and its free end has no
    // depth anything fixes (a 1.4-pixel tail of a silhouette that started 1 px past the
    // rim's node left 29 % of a depth shift free across the whole strip): an end segment
    // of an open curve whose free end meets nothing and whose other end is a junction
    // of three or more segment ends is dropped when it is shorter than `graze`.
    let mut degree = vec![0usize; merged.len()];
    for seg in &segments {
        degree[seg.points[0] as usize] += 1;
        degree[seg.points[3] as usize] += 1;
    }
    let mut dropped = vec![false; segments.len()];
    for (c, curve) in network_curves.iter_mut().enumerate() {
        if annotation.curves[c].closed {
            continue;
        }
        for from_start in [true, false] {
            if curve.segments.len() < 2 {
                break;
            }
            let s = if from_start {
                curve.segments[0]
            } else {
                curve.segments[curve.segments.len() - 1]
            };
            let ids = segments[s as usize].points;
            let (free, joined) = if from_start { (ids[0], ids[3]) } else { (ids[3], ids[0]) };
            let hull = cubic::hull_length(&ids.map(|i| merged[i as usize]));
            if degree[free as usize] == 1 && degree[joined as usize] >= 3 && hull <= graze {
                dropped[s as usize] = true;
                degree[joined as usize] -= 1;
                if from_start {
                    curve.segments.remove(0);
                } else {
                    curve.segments.pop();
                }
            }
        }
    }
    if dropped.iter().any(|&d| d) {
        let mut new_segment = vec![u32::MAX; segments.len()];
        let mut kept = Vec::with_capacity(segments.len());
        for (k, seg) in segments.iter().enumerate() {
            if !dropped[k] {
                new_segment[k] = kept.len() as u32;
                kept.push(*seg);
            }
        }
        for curve in &mut network_curves {
            for s in &mut curve.segments {
                *s = new_segment[*s as usize];
            }
        }
        tracing::debug!(
            "photo: {} dangling tails dropped",
            dropped.iter().filter(|&&d| d).count()
        );
        segments = kept;
    }
    // Drop unreferenced points (compact).
    let mut compact = vec![u32::MAX; merged.len()];
    let mut final_points = Vec::new();
    for s in &mut segments {
        for p in &mut s.points {
            if compact[*p as usize] == u32::MAX {
                compact[*p as usize] = final_points.len() as u32;
                final_points.push(merged[*p as usize]);
            }
            *p = compact[*p as usize];
        }
    }
    Ok(CurveNetwork {
        points: final_points,
        segments,
        curves: network_curves,
        junction_count: clusters.len(),
        occluded_crossing_count: occluded,
    })
}

/// Whether the curve that ends at junction `end` (an open curve's end by `at_end`) stays
/// within `width` of the other curve all along its tail from that end to its place at
/// junction `crossing` (the same two curves): sampled every tenth of a segment.
fn tail_hugs(
    curves: &[Vec<[Vec2; 4]>],
    at_end: impl Fn(&CurvePlace) -> bool,
    end: &[CurvePlace],
    crossing: &[CurvePlace],
    width: f64,
) -> bool {
    let Some(tail) = end.iter().find(|p| at_end(p)) else {
        return false;
    };
    let Some(other) = end.iter().find(|p| p.curve != tail.curve) else {
        return false;
    };
    let Some(to) = crossing.iter().find(|p| p.curve == tail.curve) else {
        return false;
    };
    let (from, to) = (tail.u.min(to.u), tail.u.max(to.u));
    let steps = ((to - from) * 10.0).ceil().max(1.0) as usize;
    (0..=steps).all(|k| {
        let p = point_at(&curves[tail.curve], from + (to - from) * k as f64 / steps as f64);
        curves[other.curve]
            .iter()
            .any(|segment| cubic::nearest_parameter(segment, p).1 <= width)
    })
}

/// Whether two junctions are each the meeting of the same two curves.
fn same_two_curves(a: &[CurvePlace], b: &[CurvePlace]) -> bool {
    a.len() == 2 && b.len() == 2 && a.iter().all(|p| b.iter().any(|q| q.curve == p.curve))
}

/// Point of a piecewise cubic at global parameter `u = segment + t`.
fn point_at(segs: &[[Vec2; 4]], u: f64) -> Vec2 {
    let (j, t) = locate(segs.len(), u);
    cubic::point(&segs[j], t)
}

fn locate(n: usize, u: f64) -> (usize, f64) {
    let j = (u.floor() as usize).min(n - 1);
    (j, (u - j as f64).clamp(0.0, 1.0))
}

/// The cubic covering `[u0, u1]` of a piecewise cubic (both in one original segment,
/// which holds because every original knot is a split).
fn sub_cubic(segs: &[[Vec2; 4]], u0: f64, u1: f64) -> [Vec2; 4] {
    let j = (u0.floor() as usize).min(segs.len() - 1);
    let (t0, t1) = ((u0 - j as f64).clamp(0.0, 1.0), (u1 - j as f64).clamp(0.0, 1.0));
    let piece = Bezier2::new(segs[j].to_vec())
        .expect("validated: finite control points")
        .segment(t0, t1);
    let p = piece.control_points();
    [p[0], p[1], p[2], p[3]]
}

/// Crossings of two polylines of equal piece count: `(t_a, t_b)` in segment parameters.
fn polyline_crossings(a: &[Vec2], b: &[Vec2]) -> Vec<(f64, f64)> {
    let (na, nb) = ((a.len() - 1) as f64, (b.len() - 1) as f64);
    let mut hits: Vec<(f64, f64)> = Vec::new();
    for i in 0..a.len() - 1 {
        for j in 0..b.len() - 1 {
            if let Some((s, t)) = segment_intersection(a[i], a[i + 1], b[j], b[j + 1]) {
                let hit = ((i as f64 + s) / na, (j as f64 + t) / nb);
                // A crossing exactly at a polyline vertex is found twice.
                if !hits
                    .iter()
                    .any(|h| (h.0 - hit.0).abs() < 1e-6 && (h.1 - hit.1).abs() < 1e-6)
                {
                    hits.push(hit);
                }
            }
        }
    }
    hits
}

/// Newton's method on `B_a(t_a) − B_b(t_b) = 0` from a polyline crossing.
fn refine_crossing(a: &[Vec2; 4], b: &[Vec2; 4], mut ta: f64, mut tb: f64) -> (f64, f64) {
    for _ in 0..30 {
        let f = cubic::point(a, ta) - cubic::point(b, tb);
        if f.norm() < 1e-13 {
            break;
        }
        let (da, db) = (cubic::derivative(a, ta), -cubic::derivative(b, tb));
        let det = da.x * db.y - da.y * db.x;
        if det.abs() < 1e-300 {
            break;
        }
        let dta = (-f.x * db.y + f.y * db.x) / det;
        let dtb = (-da.x * f.y + da.y * f.x) / det;
        ta = (ta + dta).clamp(0.0, 1.0);
        tb = (tb + dtb).clamp(0.0, 1.0);
    }
    (ta, tb)
}

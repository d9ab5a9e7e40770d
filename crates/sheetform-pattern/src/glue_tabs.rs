//! Glue tabs along seams: exactly one tab per glued edge pair, never narrower than a
//! minimum depth, never closer than a cutting clearance to another cut line.

use crate::pattern::{Fold, FoldStyle};
use crate::seam_matching::SeamRun;
use crate::{PatternError, Vec2};
use rstar::primitives::{GeomWithData, Rectangle};
use rstar::{RTree, AABB};
use sheetform_geometry::{cross2, refused_number, segment_distance, segments_cross, short_number};

/// Which side of a seam carries the tabs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TabSides {
    /// The side met first, unless its tab does not fit there (then the other side).
    #[default]
    One,
    /// Alternating from seam to seam (even seam IDs on the first side, odd on the other),
    /// which spreads the tabs over the pieces.
    Alternate,
}

/// Knobs of the glue tabs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TabOptions {
    /// Tab depth away from the seam (mm). Default 5.
    pub width_mm: f64,
    /// Angle between the seam and the tab's slanted sides (degrees, in (0, 90]); 90 gives
    /// straight (rectangular) tabs. Default 45 (trapezoids).
    pub angle_degrees: f64,
    /// One side of every seam, or alternating.
    pub sides: TabSides,
    /// The shallowest tab drawn, as a fraction of `width_mm` (in (0, 1]): a tab that
    /// fits only shallower moves to the other copy of its edges, or is left out and
    /// counted; never a sliver that cannot be glued. Default 0.4.
    pub min_width_fraction: f64,
    /// Cutting clearance (mm): no tab comes closer than this to another cut line or tab
    /// (other than the edges it stands on and their neighbours at its corners). Default 1.
    pub clearance_mm: f64,
}

impl Default for TabOptions {
    fn default() -> Self {
        Self {
            width_mm: 5.0,
            angle_degrees: 45.0,
            sides: TabSides::One,
            min_width_fraction: DEFAULT_MIN_TAB_FRACTION,
            clearance_mm: DEFAULT_CUT_CLEARANCE_MM,
        }
    }
}

/// The default shallowest tab, as a fraction of the tab depth asked for.
pub const DEFAULT_MIN_TAB_FRACTION: f64 = 0.4;

/// The default cutting clearance between a tab and any other cut line (mm).
pub const DEFAULT_CUT_CLEARANCE_MM: f64 = 1.0;

/// What happened to the tabs: every figure counts what was drawn.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct TabReport {
    /// Tabs drawn.
    pub placed: usize,
    /// Tabs drawn shallower than asked (the full depth would have come too close to a
    /// cut line), but no shallower than `depth_min_allowed_mm`.
    pub narrowed: usize,
    /// Stretches of glued edges that got no tab on either copy: no tab of at least the
    /// smallest depth fitted with the clearance on either side.
    pub dropped: usize,
    /// Stretches of glued edges too short for a tab of the smallest depth on either copy.
    pub too_short: usize,
    /// Tabs drawn on the other copy of their edges because they did not fit on the side
    /// asked for (counted in `placed`).
    pub moved_to_other_side: usize,
    /// Seams left with no tab on either side (to be glued with a strip behind them).
    #[serde(default)]
    pub seams_without_tab: usize,
    /// Glued edge pairs (each cut edge and its partner, counted once).
    #[serde(default)]
    pub glued_edge_pair_count: usize,
    /// Glued edge pairs that carry no tab on either copy (the stretches `dropped` and
    /// `too_short`); every other pair carries exactly one.
    #[serde(default)]
    pub glued_edge_pairs_without_tab: usize,
    /// Depth of the shallowest tab drawn (mm; 0 without tabs).
    #[serde(default)]
    pub depth_min_mm: f64,
    /// The smallest depth a tab may have (mm): the tab depth times its minimum fraction.
    #[serde(default)]
    pub depth_min_allowed_mm: f64,
    /// The cutting clearance every tab keeps from other cut lines (mm).
    #[serde(default)]
    pub clearance_mm: f64,
}

/// Even-odd point-in-region over a set of loops.
fn inside_loops<'a>(loops: impl Iterator<Item = &'a Vec<Vec2>>, p: Vec2) -> bool {
    sheetform_geometry::rings_contain(loops.map(Vec::as_slice), p)
}

/// Loops with their tabs spliced in, the tab-base folds per loop, and the report.
pub type TabbedLoops = (Vec<Vec<Vec2>>, Vec<Vec<Fold>>, TabReport);

struct PlacedTab {
    loop_index: usize,
    /// First and last loop vertex of the stretch the tab stands on.
    from: usize,
    to: usize,
    /// The points that replace the stretch between them in the cut path.
    outer: Vec<Vec2>,
    /// The tab's base when it covers part of the stretch only (its fold line); `None`:
    /// the whole stretch is the base.
    partial_base: Option<[Vec2; 2]>,
}

/// A segment in an R-tree of bounding boxes, with its two end points.
type IndexedSegment = GeomWithData<Rectangle<[f64; 2]>, [Vec2; 2]>;

/// A loop edge in an R-tree of bounding boxes: `(loop, edge)`.
type IndexedLoopEdge = GeomWithData<Rectangle<[f64; 2]>, (usize, usize)>;

fn indexed(a: Vec2, b: Vec2) -> IndexedSegment {
    let (lo, hi) = (a.inf(&b), a.sup(&b));
    GeomWithData::new(Rectangle::from_corners([lo.x, lo.y], [hi.x, hi.y]), [a, b])
}

/// Whether the quadrilateral `q` (convex or a triangle with a repeated point) holds `p`
/// strictly inside.
fn quad_contains(q: &[Vec2; 4], p: Vec2) -> bool {
    let s: Vec<f64> = (0..4)
        .filter(|&k| q[k] != q[(k + 1) % 4])
        .map(|k| cross2(q[(k + 1) % 4] - q[k], p - q[k]))
        .collect();
    s.iter().all(|&x| x > 0.0) || s.iter().all(|&x| x < 0.0)
}

/// The cut lines and the tabs placed so far, and the tests a new tab must pass.
struct TabSpace<'a> {
    loops: &'a [Vec<Vec2>],
    cut: RTree<IndexedLoopEdge>,
    tabs: RTree<IndexedSegment>,
    clearance: f64,
}

impl TabSpace<'_> {
    /// Whether the tab `[b0, q0, q1, b1]` standing on loop `li`'s edges `from..to` is
    /// clear: it crosses no cut line or tab, keeps the clearance from every one of them
    /// (measured from its far side and its slanted sides but for their first twice the
    /// clearance at the base corners, where the outline it stands on meets it), holds no
    /// cut line, and lies on no piece.
    fn is_clear(&self, li: usize, from: usize, to: usize, tab: [Vec2; 4]) -> bool {
        let [b0, q0, q1, b1] = tab;
        let n = self.loops[li].len().max(1);
        let on_stretch = |l: usize, i: usize| l == li && (i + n - from % n) % n < to - from;
        let sides = [[b0, q0], [q0, q1], [q1, b1]];
        let (lo, hi) = tab.iter().fold((tab[0], tab[0]), |(lo, hi), p| (lo.inf(p), hi.sup(p)));
        let c = self.clearance;
        let envelope = AABB::from_corners([lo.x - c, lo.y - c], [hi.x + c, hi.y + c]);
        // The slanted sides less their first stretch at the base corners (twice the
        // clearance along them): lines that run into a corner (the neighbouring edges, and
        // the short edges of an outline running on straight from them) meet the tab there
        // and are not measured where they do.
        let trimmed = |base: Vec2, far: Vec2| {
            let length = (far - base).norm();
            let t = if length > 0.0 { (2.0 * c / length).min(0.9) } else { 0.0 };
            [base + (far - base) * t, far]
        };
        let measured = [trimmed(b0, q0), [q0, q1], trimmed(b1, q1)];
        // A line `[u, v]` against the tab: crossing none of its sides (other than at a
        // base corner it passes through), clear of the measured parts by the clearance.
        let clear_of = |u: Vec2, v: Vec2| {
            let crosses = sides.iter().any(|&[p, q]| {
                segments_cross(p, q, u, v)
                    && ![b0, b1]
                        .iter()
                        .any(|&corner| segment_distance([u, v], [corner, corner]) <= 1e-9 * (1.0 + corner.norm()))
            });
            !crosses && measured.iter().all(|&side| segment_distance([u, v], side) >= c)
        };
        for hit in self.cut.locate_in_envelope_intersecting(&envelope) {
            let (l, i) = hit.data;
            if on_stretch(l, i) {
                continue;
            }
            let points = &self.loops[l];
            let (u, v) = (points[i], points[(i + 1) % points.len()]);
            if !clear_of(u, v) || quad_contains(&tab, (u + v) * 0.5) {
                return false;
            }
        }
        for hit in self.tabs.locate_in_envelope_intersecting(&envelope) {
            let [u, v] = hit.data;
            if !clear_of(u, v) || quad_contains(&tab, (u + v) * 0.5) {
                return false;
            }
        }
        let centre = (b0 + b1 + q0 + q1) * 0.25;
        !inside_loops(self.loops.iter(), centre)
    }

    fn insert(&mut self, tab: [Vec2; 4]) {
        for k in 0..3 {
            self.tabs.insert(indexed(tab[k], tab[k + 1]));
        }
    }
}

/// A stretch of one loop to stand a tab on: loop vertices `from..=to` (indices may run
/// past the loop's length), which glued edges of the seam's first run it covers.
struct Stretch {
    loop_index: usize,
    from: usize,
    to: usize,
}

/// Splits the loop edges `first..first + count` of loop `l` (consecutive) into nearly
/// straight stretches: edges within 10° of the stretch's chord, points within `bend` of it.
fn straight_stretches(l: &[Vec2], loop_index: usize, first: usize, count: usize, bend: f64) -> Vec<Stretch> {
    let n = l.len();
    let point = |i: usize| l[i % n];
    let mut out = Vec::new();
    let mut s = 0;
    while s < count {
        let a = first + s;
        let mut e = s + 1;
        while e < count {
            let (p0, p1) = (point(a), point(first + e + 1));
            let chord = p1 - p0;
            let len = chord.norm();
            let straight = (a..=first + e).all(|i| {
                let d = point(i + 1) - point(i);
                let dist = cross2(chord, point(i + 1) - p0).abs() / len.max(f64::MIN_POSITIVE);
                d.dot(&chord) >= d.norm() * len * 10f64.to_radians().cos() && dist <= bend
            });
            if !straight {
                break;
            }
            e += 1;
        }
        out.push(Stretch {
            loop_index,
            from: a,
            to: first + e,
        });
        s = e;
    }
    out
}

/// What trying a stretch gave.
enum Attempt {
    /// A tab of this depth (mm).
    Placed(f64),
    /// Too short for the shallowest tab.
    TooShort,
    /// No tab fitted.
    NoRoom,
}

/// Adds glue tabs to the cut loops along the seam runs, exactly one per glued edge pair
/// where one fits.
///
/// Each seam's run on the side asked for ([`TabSides`]) is split into nearly straight
/// stretches (edges within 10° of the stretch's chord, points within a tenth of the tab
/// depth of it); each stretch gets a trapezoid (or, at 90°, a rectangle) outside the
/// piece, its base a tab-base fold, at the full depth, then shallower down to
/// `min_width_fraction` of it, then (on a stretch of one edge, for the narrow V-shaped gaps
/// of nets) on part of the edge. The edges of a stretch where none fits are tried on their
/// other copy (the partner run), split into stretches there; what fits on neither is left
/// out and counted (`dropped`, `too_short`). So no glued edge pair carries two tabs, and a
/// pair carries none only when it is counted.
///
/// A tab is kept only when it crosses no cut line or tab placed before it, keeps
/// `clearance_mm` from each of them (a line through one of its base corners — the
/// neighbouring edge — from the tab's far side and the far end of its slanted side), holds
/// no cut line inside, and lies on no piece.
///
/// Returns the new loops (tabs spliced into the cut path), the tab-base folds per loop,
/// and the report.
///
/// # Errors
/// A depth that is not positive, an angle outside (0°, 90°], a minimum fraction outside
/// (0, 1] or a clearance that is negative or not finite.
pub fn add_glue_tabs(loops: &[Vec<Vec2>], runs: &[SeamRun], options: &TabOptions) -> Result<TabbedLoops, PatternError> {
    if !(options.width_mm.is_finite() && options.width_mm > 0.0) {
        return Err(PatternError::Option {
            option: "tab width",
            message: format!(
                "must be a positive number of millimetres, got {}",
                short_number(options.width_mm)
            ),
        });
    }
    if !(options.angle_degrees > 0.0 && options.angle_degrees <= 90.0) {
        return Err(PatternError::Option {
            option: "tab angle",
            message: format!(
                "must be in (0, 90] degrees, got {}",
                refused_number(options.angle_degrees, &[0.0, 90.0])
            ),
        });
    }
    if !(options.min_width_fraction > 0.0 && options.min_width_fraction <= 1.0) {
        return Err(PatternError::Option {
            option: "tab minimum fraction",
            message: format!(
                "must be in (0, 1] (0.4 = 40 % of the tab depth), got {}",
                refused_number(options.min_width_fraction, &[0.0, 1.0])
            ),
        });
    }
    if !(options.clearance_mm.is_finite() && (0.0..=crate::MAX_ALLOWANCE_MM).contains(&options.clearance_mm)) {
        return Err(PatternError::Option {
            option: "cut clearance",
            message: format!(
                "must be between 0 and {} mm, got {}",
                crate::MAX_ALLOWANCE_MM,
                refused_number(options.clearance_mm, &[0.0, crate::MAX_ALLOWANCE_MM])
            ),
        });
    }
    let width = options.width_mm;
    let min_depth = width * options.min_width_fraction;
    let cot = 1.0 / options.angle_degrees.to_radians().tan();
    let mut report = TabReport {
        depth_min_allowed_mm: min_depth,
        clearance_mm: options.clearance_mm,
        ..Default::default()
    };
    let mut space = TabSpace {
        loops,
        cut: RTree::bulk_load(
            loops
                .iter()
                .enumerate()
                .flat_map(|(li, l)| {
                    (0..l.len()).map(move |i| {
                        let (a, b) = (l[i], l[(i + 1) % l.len()]);
                        let (lo, hi) = (a.inf(&b), a.sup(&b));
                        GeomWithData::new(Rectangle::from_corners([lo.x, lo.y], [hi.x, hi.y]), (li, i))
                    })
                })
                .collect(),
        ),
        tabs: RTree::new(),
        clearance: options.clearance_mm,
    };
    let mut placed: Vec<PlacedTab> = Vec::new();
    // Depths from full down to the smallest, on the whole stretch; then, on one edge,
    // parts of it (the outer half either way, the middle half).
    let mut depths: Vec<f64> = [1.0, 0.85, 0.7, 0.55]
        .iter()
        .map(|f| f * width)
        .filter(|&d| d > min_depth)
        .collect();
    depths.push(min_depth);
    let try_stretch = |stretch: &Stretch, space: &mut TabSpace, placed: &mut Vec<PlacedTab>| -> Attempt {
        let l = &loops[stretch.loop_index];
        let n = l.len();
        let (p0, p1) = (l[stretch.from % n], l[stretch.to % n]);
        let chord = p1 - p0;
        let len = chord.norm();
        if len < min_depth {
            return Attempt::TooShort;
        }
        let d = chord / len;
        // Outside: right of a counter-clockwise outline, left of a mirrored piece's
        // clockwise one (a layout whose faces run clockwise): the side of the first edge
        // off the piece.
        let (e0, e1) = (l[stretch.from % n], l[(stretch.from + 1) % n]);
        let right = Vec2::new((e1 - e0).y, -(e1 - e0).x).normalize();
        let probe = (e0 + e1) * 0.5 + right * (1e-6 * len.max(1.0));
        let out = if inside_loops(loops.iter(), probe) {
            -Vec2::new(d.y, -d.x)
        } else {
            Vec2::new(d.y, -d.x)
        };
        let single_edge = stretch.to - stretch.from == 1;
        let mut candidates: Vec<(f64, f64, f64)> = depths.iter().map(|&w| (0.0, 1.0, w)).collect();
        if single_edge {
            for &w in &depths {
                candidates.extend([(0.5, 1.0, w), (0.0, 0.5, w), (0.25, 0.75, w)]);
            }
        }
        for (t0, t1, w) in candidates {
            let base = (t1 - t0) * len;
            if base < w {
                continue;
            }
            let (b0, b1) = (p0 + chord * t0, p0 + chord * t1);
            let inset = (w * cot).min(0.45 * base);
            let q0 = b0 + out * w + d * inset;
            let q1 = b1 + out * w - d * inset;
            let tab = [b0, q0, q1, b1];
            if !space.is_clear(stretch.loop_index, stretch.from, stretch.to, tab) {
                continue;
            }
            space.insert(tab);
            let whole = t0 == 0.0 && t1 == 1.0;
            let mut outer = Vec::with_capacity(4);
            if t0 > 0.0 {
                outer.push(b0);
            }
            outer.extend([q0, q1]);
            if t1 < 1.0 {
                outer.push(b1);
            }
            placed.push(PlacedTab {
                loop_index: stretch.loop_index,
                from: stretch.from % n,
                to: stretch.to % n,
                outer,
                partial_base: (!whole).then_some([b0, b1]),
            });
            return Attempt::Placed(w);
        }
        Attempt::NoRoom
    };
    // The runs of each seam: (side 0, side 1).
    let seam_count = runs.iter().map(|r| r.seam + 1).max().unwrap_or(0);
    let mut sides: Vec<[Option<&SeamRun>; 2]> = vec![[None, None]; seam_count];
    for r in runs {
        sides[r.seam][usize::from(r.side.min(1))] = Some(r);
    }
    let mut depth_min = f64::INFINITY;
    for (seam, pair) in sides.iter().enumerate() {
        let [Some(first), second] = *pair else { continue };
        report.glued_edge_pair_count += first.edges;
        let wanted = match options.sides {
            TabSides::One => 0,
            TabSides::Alternate => seam % 2,
        };
        // The run asked for and its partner (a seam without a partner run has one side).
        let (here, there) = match (wanted, second) {
            (1, Some(s)) => (s, Some(first)),
            _ => (first, second),
        };
        let mut tabbed = false;
        // Edges of `here` (0-based along it) that found no tab, and why.
        let mut missing: Vec<(usize, bool)> = Vec::new();
        let l = &loops[here.loop_index];
        for stretch in straight_stretches(l, here.loop_index, here.start, here.edges, 0.1 * width) {
            match try_stretch(&stretch, &mut space, &mut placed) {
                Attempt::Placed(w) => {
                    tabbed = true;
                    report.placed += 1;
                    report.narrowed += usize::from(w < width);
                    depth_min = depth_min.min(w);
                }
                attempt => {
                    let short = matches!(attempt, Attempt::TooShort);
                    missing.extend((stretch.from - here.start..stretch.to - here.start).map(|j| (j, short)));
                }
            }
        }
        // The partner's copies of those edges, in its own order: edge j of `here` is edge
        // `edges − 1 − j` of `there`.
        let mut on_other: Vec<(usize, bool)> = match there {
            Some(t) => missing.iter().map(|&(j, short)| (t.edges - 1 - j, short)).collect(),
            None => Vec::new(),
        };
        on_other.sort_unstable();
        if there.is_none() {
            for group in consecutive_groups(&missing) {
                count_missing(&mut report, group);
            }
        }
        if let Some(t) = there {
            let lt = &loops[t.loop_index];
            for group in consecutive_groups(&on_other) {
                let (first_edge, count) = (group[0].0, group.len());
                for stretch in straight_stretches(lt, t.loop_index, t.start + first_edge, count, 0.1 * width) {
                    let covered = &group[stretch.from - t.start - first_edge..stretch.to - t.start - first_edge];
                    match try_stretch(&stretch, &mut space, &mut placed) {
                        Attempt::Placed(w) => {
                            tabbed = true;
                            report.placed += 1;
                            report.moved_to_other_side += 1;
                            report.narrowed += usize::from(w < width);
                            depth_min = depth_min.min(w);
                        }
                        _ => count_missing(&mut report, covered),
                    }
                }
            }
        }
        report.seams_without_tab += usize::from(!tabbed);
    }
    report.depth_min_mm = if depth_min.is_finite() { depth_min } else { 0.0 };
    // Splice the tabs into their loops; their bases become tab-base folds.
    let mut new_loops = Vec::with_capacity(loops.len());
    let mut folds: Vec<Vec<Fold>> = vec![Vec::new(); loops.len()];
    for (li, l) in loops.iter().enumerate() {
        let n = l.len();
        let mut tab_at: std::collections::HashMap<usize, &PlacedTab> = std::collections::HashMap::new();
        for t in placed.iter().filter(|t| t.loop_index == li) {
            tab_at.insert(t.from, t);
            if let Some([a, b]) = t.partial_base {
                folds[li].push(Fold {
                    a,
                    b,
                    style: FoldStyle::TabBase,
                    angle_degrees: 0.0,
                });
                continue;
            }
            let mut i = t.from;
            while i != t.to {
                folds[li].push(Fold {
                    a: l[i],
                    b: l[(i + 1) % n],
                    style: FoldStyle::TabBase,
                    angle_degrees: 0.0,
                });
                i = (i + 1) % n;
            }
        }
        if tab_at.is_empty() {
            new_loops.push(l.clone());
            continue;
        }
        let begin = *tab_at.keys().min().expect("non-empty");
        let mut out = Vec::with_capacity(n + 2 * tab_at.len());
        let mut steps = 0;
        let mut i = begin;
        while steps < n {
            out.push(l[i]);
            if let Some(t) = tab_at.get(&i) {
                out.extend(t.outer.iter().copied());
                let skip = (t.to + n - t.from) % n;
                steps += skip.max(1);
                i = t.to;
            } else {
                steps += 1;
                i = (i + 1) % n;
            }
        }
        new_loops.push(out);
    }
    Ok((new_loops, folds, report))
}

/// Runs of consecutive edge numbers in a sorted list of `(edge, too short)`.
fn consecutive_groups(edges: &[(usize, bool)]) -> Vec<&[(usize, bool)]> {
    let mut groups = Vec::new();
    let mut start = 0;
    for i in 1..=edges.len() {
        if i == edges.len() || edges[i].0 != edges[i - 1].0 + 1 {
            if start < i {
                groups.push(&edges[start..i]);
            }
            start = i;
        }
    }
    groups
}

/// Counts a stretch of glued edges left without a tab: too short on the first side it was
/// tried on, or without room.
fn count_missing(report: &mut TabReport, edges: &[(usize, bool)]) {
    if edges.is_empty() {
        return;
    }
    report.glued_edge_pairs_without_tab += edges.len();
    if edges.iter().all(|e| e.1) {
        report.too_short += 1;
    } else {
        report.dropped += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sheetform_geometry::segments_meet;

    #[test]
    fn segment_test_counts_touching() {
        let v = Vec2::new;
        assert!(segments_meet(v(0.0, 0.0), v(2.0, 0.0), v(1.0, -1.0), v(1.0, 1.0)));
        assert!(segments_meet(v(0.0, 0.0), v(2.0, 0.0), v(2.0, 0.0), v(3.0, 1.0)));
        assert!(!segments_meet(v(0.0, 0.0), v(2.0, 0.0), v(0.0, 1.0), v(2.0, 1.0)));
    }

    fn square(x: f64, y: f64, size: f64) -> Vec<Vec2> {
        vec![
            Vec2::new(x, y),
            Vec2::new(x + size, y),
            Vec2::new(x + size, y + size),
            Vec2::new(x, y + size),
        ]
    }

    fn run(loop_index: usize, start: usize, seam: usize, side: u8) -> SeamRun {
        SeamRun {
            loop_index,
            start,
            edges: 1,
            seam,
            side,
        }
    }

    /// Two squares side by side, `gap` apart, their facing edges glued (the right edge
    /// of the first, edge 1, and the left edge of the second, edge 3).
    fn facing_squares(gap: f64) -> (Vec<Vec<Vec2>>, Vec<SeamRun>) {
        (
            vec![square(0.0, 0.0, 20.0), square(20.0 + gap, 0.0, 20.0)],
            vec![run(0, 1, 0, 0), run(1, 3, 0, 1)],
        )
    }

    /// The shortest distance from the tab's outer points (those not on the loop) to
    /// the other loop's edges.
    fn outer_points(new_loop: &[Vec2], old: &[Vec2]) -> Vec<Vec2> {
        new_loop.iter().copied().filter(|p| !old.contains(p)).collect()
    }

    #[test]
    fn a_tab_takes_the_full_depth_where_there_is_room() {
        let (loops, runs) = facing_squares(20.0);
        let (new, folds, report) = add_glue_tabs(&loops, &runs, &TabOptions::default()).unwrap();
        assert_eq!((report.placed, report.narrowed, report.moved_to_other_side), (1, 0, 0));
        assert_eq!(
            (report.glued_edge_pair_count, report.glued_edge_pairs_without_tab),
            (1, 0)
        );
        assert_eq!(report.depth_min_mm, 5.0);
        // On the first square, 5 mm deep: its outer points at x = 25.
        let outer = outer_points(&new[0], &loops[0]);
        assert_eq!(outer.len(), 2);
        assert!(outer.iter().all(|p| (p.x - 25.0).abs() < 1e-12));
        assert_eq!(new[1], loops[1]);
        assert_eq!(folds[0].len(), 1);
        assert_eq!(folds[0][0].style, FoldStyle::TabBase);
    }

    #[test]
    fn a_tab_is_narrowed_to_keep_the_clearance_and_never_below_the_minimum() {
        // 4 mm between the squares: a tab 5 mm deep would cross, one 3 mm deep keeps
        // the 1 mm clearance at 2.75 mm (0.55 of 5).
        let (loops, runs) = facing_squares(4.0);
        let (new, _, report) = add_glue_tabs(&loops, &runs, &TabOptions::default()).unwrap();
        assert_eq!((report.placed, report.narrowed), (1, 1));
        assert!((report.depth_min_mm - 2.75).abs() < 1e-12, "{report:?}");
        let outer = outer_points(&new[0], &loops[0]);
        assert!(outer.iter().all(|p| 24.0 - p.x >= 1.0 - 1e-12), "{outer:?}");
        // 2.5 mm: the shallowest tab (2 mm) would come within 0.5 mm of the other square,
        // and so would one on the other copy: no tab, counted, never a sliver.
        let (loops, runs) = facing_squares(2.5);
        let (new, folds, report) = add_glue_tabs(&loops, &runs, &TabOptions::default()).unwrap();
        assert_eq!(
            (report.placed, report.dropped, report.glued_edge_pairs_without_tab),
            (0, 1, 1)
        );
        assert_eq!(report.seams_without_tab, 1);
        assert_eq!(new, loops);
        assert!(folds.iter().all(Vec::is_empty));
    }

    #[test]
    fn a_tab_that_does_not_fit_moves_to_the_other_copy() {
        // The first square's right edge faces a third square 1.5 mm away; the glued
        // partner, the left edge of the second square, has room.
        let loops = vec![square(0.0, 0.0, 20.0), square(60.0, 0.0, 20.0), square(21.5, 0.0, 20.0)];
        let runs = vec![run(0, 1, 0, 0), run(1, 3, 0, 1)];
        let (new, folds, report) = add_glue_tabs(&loops, &runs, &TabOptions::default()).unwrap();
        assert_eq!((report.placed, report.moved_to_other_side, report.dropped), (1, 1, 0));
        assert_eq!(new[0], loops[0]);
        let outer = outer_points(&new[1], &loops[1]);
        assert!(outer.iter().all(|p| (p.x - 55.0).abs() < 1e-12), "{outer:?}");
        assert!(folds[0].is_empty() && folds[1].len() == 1);
    }

    #[test]
    fn bad_options_are_named() {
        let (loops, runs) = facing_squares(20.0);
        for (options, name) in [
            (
                TabOptions {
                    min_width_fraction: 0.0,
                    ..Default::default()
                },
                "tab minimum fraction",
            ),
            (
                TabOptions {
                    clearance_mm: f64::NAN,
                    ..Default::default()
                },
                "cut clearance",
            ),
        ] {
            match add_glue_tabs(&loops, &runs, &options) {
                Err(PatternError::Option { option, .. }) => assert_eq!(option, name),
                other => panic!("{other:?}"),
            }
        }
    }
}

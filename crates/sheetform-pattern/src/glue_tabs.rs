//! Glue tabs along seams, placed only where they overlap nothing.

use crate::pattern::{Fold, FoldStyle};
use crate::seam_matching::SeamRun;
use crate::{PatternError, Vec2};
use sheetform_geometry::{cross2, segments_meet, short_number};

/// Which side of a seam carries the tabs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TabSides {
    /// Always the side met first (one piece of each pair gets all its tabs).
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
}

impl Default for TabOptions {
    fn default() -> Self {
        Self {
            width_mm: 5.0,
            angle_degrees: 45.0,
            sides: TabSides::One,
        }
    }
}

/// What happened to the tabs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct TabReport {
    /// Tabs drawn.
    pub placed: usize,
    /// Tabs drawn narrower or shorter than asked (the full tab would have overlapped
    /// something).
    pub narrowed: usize,
    /// Tabs left out because even a quarter width overlapped something.
    pub dropped: usize,
    /// Seam stretches too short (under half the tab width) to take a tab.
    pub too_short: usize,
    /// Tabs placed on the other side of a seam none of whose tabs fitted on the wanted
    /// side (counted in `placed`; that seam's failures are not counted in `dropped`).
    #[serde(default)]
    pub moved_to_other_side: usize,
    /// Seams left with no tab on either side (to be glued with a strip behind them).
    #[serde(default)]
    pub seams_without_tab: usize,
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

/// Adds glue tabs to the cut loops along the seam runs. Each run that carries tabs (see [`TabSides`]) is split into nearly straight
/// stretches (edges within 10° of the stretch's chord, points within a tenth of the tab
/// width of it); every stretch at least twice the tab width long gets a trapezoid (or,
/// at 90°, a rectangle) of depth `width_mm` outside the piece, its base a tab-base fold.
///
/// Overlap is checked, not assumed: a tab's three new edges must not meet any cut edge
/// (other than at the two base corners) nor any tab placed before it, and the tab must
/// not lie on a piece. A tab that fails is retried at half and a quarter width, then
/// left out; the report counts each case.
///
/// Returns the new loops (tabs spliced into the cut path), the tab-base folds per loop,
/// and the report.
///
/// # Errors
/// A width that is not positive or an angle outside (0°, 90°].
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
                short_number(options.angle_degrees)
            ),
        });
    }
    let width = options.width_mm;
    let cot = 1.0 / options.angle_degrees.to_radians().tan();
    let mut report = TabReport::default();
    let mut placed: Vec<PlacedTab> = Vec::new();
    let mut tab_edges: Vec<[Vec2; 2]> = Vec::new();
    let all_cut_edges: Vec<[Vec2; 2]> = loops
        .iter()
        .flat_map(|l| (0..l.len()).map(move |i| [l[i], l[(i + 1) % l.len()]]))
        .collect();
    // Seams none of whose tabs could be placed on the wanted side are tried on the other
    // side (a seam partly tabbed keeps its tabs where they are: the other side's
    // stretches need not match, and a stretch must never get a tab on both sides).
    let mut attempted: std::collections::HashMap<usize, usize> = std::collections::HashMap::new();
    let mut failed: std::collections::HashMap<usize, usize> = std::collections::HashMap::new();
    let mut rescued: std::collections::HashSet<usize> = std::collections::HashSet::new();
    let mut tabbed: std::collections::HashSet<usize> = std::collections::HashSet::new();
    let all_failed = |seam: usize,
                      attempted: &std::collections::HashMap<usize, usize>,
                      failed: &std::collections::HashMap<usize, usize>| {
        failed
            .get(&seam)
            .is_some_and(|&n| n > 0 && Some(&n) == attempted.get(&seam))
    };
    let passes = runs.iter().map(|r| (0, r)).chain(runs.iter().map(|r| (1, r)));
    for (pass, run) in passes {
        let wanted_side = match options.sides {
            TabSides::One => 0,
            TabSides::Alternate => (run.seam % 2) as u8,
        };
        if (pass == 0) != (run.side == wanted_side) || (pass == 1 && !all_failed(run.seam, &attempted, &failed)) {
            continue;
        }
        let l = &loops[run.loop_index];
        let n = l.len();
        let point = |i: usize| l[i % n];
        // Split the run into nearly straight stretches.
        let mut s = 0;
        while s < run.edges {
            let a = run.start + s;
            let mut e = s + 1;
            while e < run.edges {
                let (p0, p1) = (point(a), point(run.start + e + 1));
                let chord = p1 - p0;
                let len = chord.norm();
                let straight = (a..=run.start + e).all(|i| {
                    let d = point(i + 1) - point(i);
                    let dist = cross2(chord, point(i + 1) - p0).abs() / len.max(f64::MIN_POSITIVE);
                    d.dot(&chord) >= d.norm() * len * 10f64.to_radians().cos() && dist <= 0.1 * width
                });
                if !straight {
                    break;
                }
                e += 1;
            }
            let (from, to) = (a, run.start + e);
            s = e;
            let (p0, p1) = (point(from), point(to));
            let chord = p1 - p0;
            let len = chord.norm();
            if len < 0.5 * width {
                if pass == 0 {
                    report.too_short += 1;
                }
                continue;
            }
            if pass == 0 {
                *attempted.entry(run.seam).or_default() += 1;
            }
            let d = chord / len;
            let out = Vec2::new(d.y, -d.x);
            let mut placed_tab = None;
            // Full, half and quarter width along the whole stretch, as far as the base is
            // twice as long as the tab is deep; then, for the narrow V-shaped gaps of nets,
            // a tab on the outer half (either half), then the middle half of the stretch.
            let candidates = [
                (0.0, 1.0, width),
                (0.0, 1.0, 0.5 * width),
                (0.0, 1.0, 0.25 * width),
                (0.5, 1.0, 0.5 * width),
                (0.0, 0.5, 0.5 * width),
                (0.5, 1.0, 0.25 * width),
                (0.0, 0.5, 0.25 * width),
                (0.25, 0.75, 0.25 * width),
            ];
            // (Partial tabs only on a stretch of one edge, whose chord is the edge itself:
            // the cut then runs exactly along it on both sides of the tab.)
            let single_edge = (to - from) == 1;
            for (attempt, &(t0, t1, w)) in candidates
                .iter()
                .enumerate()
                .filter(|&(_, &(t0, t1, w))| (t1 - t0) * len >= 2.0 * w && (single_edge || (t0 == 0.0 && t1 == 1.0)))
            {
                let (b0, b1) = (p0 + chord * t0, p0 + chord * t1);
                let base = (t1 - t0) * len;
                let inset = (w * cot).min(0.45 * base);
                let q0 = b0 + out * w + d * inset;
                let q1 = b1 + out * w - d * inset;
                let new_edges = [[b0, q0], [q0, q1], [q1, b1]];
                // Trim the two edges that start/end at the base corners so touching the
                // outline there is not a hit.
                let trim = |[a, b]: [Vec2; 2], at_start: bool, at_end: bool| {
                    let t = (b - a) * 1e-6;
                    [if at_start { a + t } else { a }, if at_end { b - t } else { b }]
                };
                let tested = [
                    trim(new_edges[0], true, false),
                    new_edges[1],
                    trim(new_edges[2], false, true),
                ];
                let hits_cut = tested
                    .iter()
                    .any(|&[a, b]| all_cut_edges.iter().any(|&[c, e]| segments_meet(a, b, c, e)));
                let hits_tab = tested
                    .iter()
                    .any(|&[a, b]| tab_edges.iter().any(|&[c, e]| segments_meet(a, b, c, e)));
                let centre = (b0 + b1 + q0 + q1) * 0.25;
                let on_piece = inside_loops(loops.iter(), centre);
                if !hits_cut && !hits_tab && !on_piece {
                    tab_edges.extend(new_edges);
                    if attempt > 0 {
                        report.narrowed += 1;
                    }
                    let whole = t0 == 0.0 && t1 == 1.0;
                    let mut outer = Vec::with_capacity(4);
                    if t0 > 0.0 {
                        outer.push(b0);
                    }
                    outer.extend([q0, q1]);
                    if t1 < 1.0 {
                        outer.push(b1);
                    }
                    placed_tab = Some((outer, (!whole).then_some([b0, b1])));
                    break;
                }
            }
            match placed_tab {
                Some((outer, partial_base)) => {
                    report.placed += 1;
                    tabbed.insert(run.seam);
                    if pass == 1 {
                        report.moved_to_other_side += 1;
                        rescued.insert(run.seam);
                    }
                    placed.push(PlacedTab {
                        loop_index: run.loop_index,
                        from: from % n,
                        to: to % n,
                        outer,
                        partial_base,
                    });
                }
                None if pass == 0 => {
                    *failed.entry(run.seam).or_default() += 1;
                    report.dropped += 1;
                }
                None => {}
            }
        }
    }
    // The seams tabbed on their other side have no dropped tab.
    for seam in &rescued {
        report.dropped -= failed[seam];
    }
    let seams: std::collections::HashSet<usize> = runs.iter().map(|r| r.seam).collect();
    report.seams_without_tab = seams.difference(&tabbed).count();
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_test_counts_touching() {
        let v = Vec2::new;
        assert!(segments_meet(v(0.0, 0.0), v(2.0, 0.0), v(1.0, -1.0), v(1.0, 1.0)));
        assert!(segments_meet(v(0.0, 0.0), v(2.0, 0.0), v(2.0, 0.0), v(3.0, 1.0)));
        assert!(!segments_meet(v(0.0, 0.0), v(2.0, 0.0), v(0.0, 1.0), v(2.0, 1.0)));
    }
}

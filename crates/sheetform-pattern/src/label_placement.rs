//! Placing labels on a pattern: upright, inside their piece, over no line and no other
//! label.

use crate::pattern::{upright, Label, LabelKind, PatternPiece};
use crate::Vec2;
use rstar::primitives::{GeomWithData, Rectangle};
use rstar::{RTree, AABB};
use sheetform_geometry::{rings_contain, triangles_overlap};

/// Where a label may go: a point on its piece's border (or inside it) and the direction
/// to move inward from there; the text runs along `direction` (radians from +x).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct LabelSpot {
    /// Anchor on the border (seam IDs) or inside the piece (names).
    pub(crate) point: Vec2,
    /// Unit vector into the piece (zero for a spot inside the piece: the label is
    /// centred on the point).
    pub(crate) inward: Vec2,
    /// Text direction (radians from +x), made upright when placed.
    pub(crate) direction: f64,
}

/// A label to place and the spots it may take, best first.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct LabelRequest {
    /// Piece of the pattern it belongs to.
    pub(crate) piece: usize,
    /// The text.
    pub(crate) text: String,
    /// Piece name or seam ID.
    pub(crate) kind: LabelKind,
    /// Preferred text height (mm).
    pub(crate) height_mm: f64,
    /// Candidate spots, best first.
    pub(crate) spots: Vec<LabelSpot>,
    /// The cut edges the label names (a seam ID's run; empty for a piece name): the label
    /// goes only where no other cut edge of its piece is nearer to it than these, so that
    /// a maker reads it as the ID of the edge it names.
    pub(crate) anchor: Vec<(Vec2, Vec2)>,
}

/// Labels are shrunk down to this fraction of their height before they are left out.
const SMALLEST_SCALE: f64 = 0.4;
/// Advance of one character as a fraction of the text height (Helvetica's digits and
/// average lower case are about 0.55 em) plus room around the text.
const CHARACTER_WIDTH: f64 = 0.6;
/// Most line and label tests of one placement (see [`place_labels`]).
const MAX_LABEL_WORK: usize = 200_000_000;

/// Free margin around a label's text box (fraction of its height).
const MARGIN: f64 = 0.15;

/// The text box of a label: centre, unit direction, half width, half height (mm).
struct TextBox {
    centre: Vec2,
    along: Vec2,
    half_width: f64,
    half_height: f64,
}

impl TextBox {
    fn corners(&self) -> [Vec2; 4] {
        let across = Vec2::new(-self.along.y, self.along.x);
        let (u, v) = (self.along * self.half_width, across * self.half_height);
        [
            self.centre - u - v,
            self.centre + u - v,
            self.centre + u + v,
            self.centre - u + v,
        ]
    }

    /// Whether the segment `a b` meets the box (Liang–Barsky clipping in the box frame).
    fn meets_segment(&self, a: Vec2, b: Vec2) -> bool {
        let across = Vec2::new(-self.along.y, self.along.x);
        let local = |p: Vec2| Vec2::new((p - self.centre).dot(&self.along), (p - self.centre).dot(&across));
        let (p, q) = (local(a), local(b));
        let d = q - p;
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        for (delta, start, half) in [(d.x, p.x, self.half_width), (d.y, p.y, self.half_height)] {
            for (num, den) in [(half - start, delta), (half + start, -delta)] {
                // Inside the slab where `den · t ≤ num`.
                if den == 0.0 {
                    if num < 0.0 {
                        return false;
                    }
                } else if den > 0.0 {
                    t1 = t1.min(num / den);
                } else {
                    t0 = t0.max(num / den);
                }
            }
        }
        t0 <= t1
    }

    fn overlaps(&self, other: &TextBox) -> bool {
        let [a, b, c, d] = self.corners();
        let [e, f, g, h] = other.corners();
        [[a, b, c], [a, c, d]]
            .iter()
            .any(|s| [[e, f, g], [e, g, h]].iter().any(|t| triangles_overlap(*s, *t, 0.0)))
    }
}

/// What label placement did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct LabelPlacement {
    /// Labels printed smaller than asked to fit.
    pub(crate) shrunk: usize,
    /// Labels left out: no spot in their piece was free even at the smallest size.
    pub(crate) dropped: usize,
}

/// Places each request on the first of its spots (at the first of the sizes 1, ¾, ½,
/// [`SMALLEST_SCALE`] of its height) where the label's text box, with a margin, lies
/// inside its piece's cut loops and meets none of the piece's cut or fold lines nor a
/// label placed before it, and (for a label with anchor edges) no other cut edge lies
/// nearer to it than its anchor; the text is turned upright (its direction within ±90°
/// of +x, so no label reads upside down). Requests are placed in order (seam IDs first by the
/// caller), a label with no free spot is left out and counted; so are the labels left
/// when [`MAX_LABEL_WORK`] tests have been spent.
pub(crate) fn place_labels(pieces: &mut [PatternPiece], requests: &[LabelRequest]) -> LabelPlacement {
    let mut report = LabelPlacement::default();
    let mut placed: Vec<Vec<TextBox>> = (0..pieces.len()).map(|_| Vec::new()).collect();
    // Every line of each piece, in an R-tree of their bounding boxes.
    let lines: Vec<PieceLines> = pieces
        .iter()
        .map(|piece| {
            let cut = piece
                .cut
                .iter()
                .flat_map(|l| (0..l.len()).map(move |i| (l[i], l[(i + 1) % l.len()])));
            let folds = piece.folds.iter().map(|f| (f.a, f.b));
            let segments: Vec<(Vec2, Vec2)> = cut.chain(folds).collect();
            let cut_count = piece.cut.iter().map(Vec::len).sum();
            let boxes = segments
                .iter()
                .enumerate()
                .map(|(i, (a, b))| {
                    let (lo, hi) = (a.inf(b), a.sup(b));
                    GeomWithData::new(Rectangle::from_corners([lo.x, lo.y], [hi.x, hi.y]), i)
                })
                .collect();
            PieceLines {
                segments,
                cut_count,
                tree: RTree::bulk_load(boxes),
            }
        })
        .collect();
    // Work budget in line tests (about a second): beyond it the remaining labels are
    // left out and counted, so no pattern makes the placement run away.
    let mut work: usize = 0;
    for request in requests {
        let piece = &pieces[request.piece];
        let mut chosen = None;
        'search: for (k, scale) in [1.0, 0.75, 0.5, SMALLEST_SCALE].into_iter().enumerate() {
            let height = request.height_mm * scale;
            let half_height = 0.5 * height * (1.0 + 2.0 * MARGIN);
            let half_width = 0.5 * height * (CHARACTER_WIDTH * request.text.chars().count() as f64 + 2.0 * MARGIN);
            for spot in &request.spots {
                let direction = upright(spot.direction);
                let along = Vec2::new(direction.cos(), direction.sin());
                // Clear of the border: half the box's extent along the inward direction
                // plus a margin.
                let across = Vec2::new(-along.y, along.x);
                let reach = half_width * spot.inward.dot(&along).abs() + half_height * spot.inward.dot(&across).abs();
                let centre = spot.point + spot.inward * (reach + MARGIN * height);
                let candidate = TextBox {
                    centre,
                    along,
                    half_width,
                    half_height,
                };
                let (mut is_free, tests) = free(&candidate, piece, &lines[request.piece], &placed[request.piece]);
                work += tests;
                if is_free && !request.anchor.is_empty() {
                    let (nearest, tests) =
                        nearest_to_anchor(centre, &request.anchor, &lines[request.piece], 0.25 * height);
                    work += tests;
                    is_free = nearest;
                }
                if work > MAX_LABEL_WORK {
                    break 'search;
                }
                if is_free {
                    chosen = Some((candidate, direction, height, k > 0));
                    break 'search;
                }
            }
        }
        match chosen {
            Some((text_box, direction, height, smaller)) => {
                report.shrunk += usize::from(smaller);
                pieces[request.piece].labels.push(Label {
                    position: text_box.centre,
                    text: request.text.clone(),
                    height_mm: height,
                    angle_radians: direction,
                    kind: request.kind,
                });
                placed[request.piece].push(text_box);
            }
            None => report.dropped += 1,
        }
    }
    report
}

/// A piece's cut and fold lines (the cut lines first) and an R-tree of their bounding
/// boxes.
struct PieceLines {
    segments: Vec<(Vec2, Vec2)>,
    /// The first `cut_count` segments are cut lines.
    cut_count: usize,
    tree: RTree<GeomWithData<Rectangle<[f64; 2]>, usize>>,
}

fn point_segment_distance(p: Vec2, (a, b): (Vec2, Vec2)) -> f64 {
    let d = b - a;
    let t = if d.norm_squared() > 0.0 {
        ((p - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + d * t)).norm()
}

/// Whether every cut line of the piece other than the anchor edges lies farther from
/// `centre` than the anchor does by `margin` (so that a label at a corner, as near to the
/// next edge as to its own, is not taken for the next edge's), and how many tests that
/// took.
fn nearest_to_anchor(centre: Vec2, anchor: &[(Vec2, Vec2)], lines: &PieceLines, margin: f64) -> (bool, usize) {
    let own = anchor
        .iter()
        .map(|&s| point_segment_distance(centre, s))
        .fold(f64::INFINITY, f64::min);
    let reach = own + margin;
    let same = |(a, b): (Vec2, Vec2), (c, d): (Vec2, Vec2)| (a == c && b == d) || (a == d && b == c);
    let mut tests = anchor.len();
    let envelope = AABB::from_corners(
        [centre.x - reach, centre.y - reach],
        [centre.x + reach, centre.y + reach],
    );
    let other_nearer = lines.tree.locate_in_envelope_intersecting(&envelope).any(|hit| {
        tests += 1;
        let segment = lines.segments[hit.data];
        hit.data < lines.cut_count
            && point_segment_distance(centre, segment) < reach
            && !anchor.iter().any(|&s| same(s, segment))
    });
    (!other_nearer, tests)
}

/// Whether a text box lies inside its piece, off every line and off the labels placed,
/// and how many tests that took (for the work budget).
///
/// The lines (cut loops included) whose bounding boxes meet the box's are tested first
/// (found in the R-tree): a box that meets none of them has its whole border on one
/// side of every cut loop, so one corner decides whether it lies inside (one even–odd
/// test instead of four).
fn free(text_box: &TextBox, piece: &PatternPiece, lines: &PieceLines, placed: &[TextBox]) -> (bool, usize) {
    let corners = text_box.corners();
    let lo = corners[0].inf(&corners[1]).inf(&corners[2]).inf(&corners[3]);
    let hi = corners[0].sup(&corners[1]).sup(&corners[2]).sup(&corners[3]);
    let mut tests = 1;
    let crossed = lines
        .tree
        .locate_in_envelope_intersecting(&AABB::from_corners([lo.x, lo.y], [hi.x, hi.y]))
        .any(|candidate| {
            tests += 1;
            let (a, b) = lines.segments[candidate.data];
            text_box.meets_segment(a, b)
        });
    if crossed {
        return (false, tests);
    }
    let rings = piece.cut.iter().map(|l| l.as_slice());
    tests += piece.cut.iter().map(Vec::len).sum::<usize>() + placed.len();
    let inside = rings_contain(rings, corners[0]) && !placed.iter().any(|p| p.overlaps(text_box));
    (inside, tests)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pattern::{Fold, FoldStyle};

    fn square_piece() -> PatternPiece {
        PatternPiece {
            name: "p".into(),
            mesh_pieces: vec![],
            cut: vec![vec![
                Vec2::new(0.0, 0.0),
                Vec2::new(40.0, 0.0),
                Vec2::new(40.0, 40.0),
                Vec2::new(0.0, 40.0),
            ]],
            folds: vec![Fold {
                a: Vec2::new(20.0, 0.0),
                b: Vec2::new(20.0, 40.0),
                style: FoldStyle::Mountain,
                angle_degrees: 90.0,
            }],
            labels: vec![],
            sheet: 0,
            placement: Default::default(),
        }
    }

    #[test]
    fn labels_are_upright_inside_and_clear_of_lines_and_each_other() {
        let mut pieces = vec![square_piece()];
        // Two IDs on the top edge, the edge run right to left (upside down if followed),
        // the first spot on the fold line; a name asked for at the fold.
        let seam = |text: &str| LabelRequest {
            piece: 0,
            text: text.into(),
            kind: LabelKind::Seam,
            height_mm: 3.0,
            spots: [20.0, 12.0, 28.0, 6.0, 34.0]
                .iter()
                .map(|&x| LabelSpot {
                    point: Vec2::new(x, 40.0),
                    inward: Vec2::new(0.0, -1.0),
                    direction: std::f64::consts::PI,
                })
                .collect(),
            anchor: vec![],
        };
        let name = LabelRequest {
            piece: 0,
            text: "name".into(),
            kind: LabelKind::Piece,
            height_mm: 4.0,
            spots: vec![
                LabelSpot {
                    point: Vec2::new(20.0, 20.0),
                    inward: Vec2::zeros(),
                    direction: 0.0,
                },
                LabelSpot {
                    point: Vec2::new(10.0, 20.0),
                    inward: Vec2::zeros(),
                    direction: 0.0,
                },
            ],
            anchor: vec![],
        };
        let report = place_labels(&mut pieces, &[name, seam("12"), seam("13")]);
        assert_eq!(report, LabelPlacement::default());
        let labels = &pieces[0].labels;
        assert_eq!(labels.len(), 3);
        assert_eq!(labels[0].position, Vec2::new(10.0, 20.0));
        for l in labels {
            assert!(l.angle_radians.abs() <= std::f64::consts::FRAC_PI_2, "{l:?}");
            // Off the fold at x = 20 and inside the square.
            let half = 0.5 * l.height_mm * (CHARACTER_WIDTH * l.text.len() as f64);
            assert!((l.position.x - 20.0).abs() > half, "{l:?}");
            assert!(l.position.y < 40.0 - 0.5 * l.height_mm);
        }
        assert_ne!(labels[1].position, labels[2].position);
        // A label with nowhere to go is left out and counted.
        let crowded = LabelRequest {
            piece: 0,
            text: "a very long label that fits nowhere".into(),
            kind: LabelKind::Piece,
            height_mm: 4.0,
            spots: vec![LabelSpot {
                point: Vec2::new(10.0, 10.0),
                inward: Vec2::zeros(),
                direction: 0.0,
            }],
            anchor: vec![],
        };
        assert_eq!(place_labels(&mut pieces, &[crowded]).dropped, 1);
    }

    #[test]
    fn a_segment_meets_a_turned_box_only_where_it_does() {
        let b = TextBox {
            centre: Vec2::new(1.0, 1.0),
            along: Vec2::new(1.0, 1.0).normalize(),
            half_width: 1.0,
            half_height: 0.2,
        };
        assert!(b.meets_segment(Vec2::new(0.0, 2.0), Vec2::new(2.0, 0.0)));
        assert!(b.meets_segment(Vec2::new(1.0, 1.0), Vec2::new(1.1, 1.1)));
        assert!(!b.meets_segment(Vec2::new(2.0, 0.0), Vec2::new(3.0, 0.0)));
        assert!(!b.meets_segment(Vec2::new(0.0, 1.5), Vec2::new(0.2, 2.0)));
    }
}

//! Packing pattern pieces onto sheets of a given size.

use crate::{Pattern, PatternError, Vec2};

/// Sheet size and spacing for [`pack_pieces`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SheetOptions {
    /// Sheet width (mm).
    pub width_mm: f64,
    /// Sheet height (mm).
    pub height_mm: f64,
    /// Gap kept between pieces and from the sheet's edges (mm). Default 5.
    pub gap_mm: f64,
}

impl SheetOptions {
    /// A sheet of `width_mm × height_mm` with the default 5 mm gap.
    pub fn new(width_mm: f64, height_mm: f64) -> Self {
        Self {
            width_mm,
            height_mm,
            gap_mm: 5.0,
        }
    }
}

/// Space between sheets in the combined drawing (mm).
const SHEET_SPACING_MM: f64 = 20.0;

/// `p` turned by `angle` radians about the origin.
pub fn rotated(p: Vec2, angle: f64) -> Vec2 {
    let (s, c) = angle.sin_cos();
    Vec2::new(c * p.x - s * p.y, s * p.x + c * p.y)
}

/// Convex hull (counter-clockwise, Andrew's monotone chain).
fn convex_hull(mut points: Vec<Vec2>) -> Vec<Vec2> {
    points.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    points.dedup();
    if points.len() < 3 {
        return points;
    }
    let cross = |o: Vec2, a: Vec2, b: Vec2| (a - o).x * (b - o).y - (a - o).y * (b - o).x;
    let mut hull: Vec<Vec2> = Vec::with_capacity(points.len() * 2);
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &Vec2>> = if pass == 0 {
            Box::new(points.iter())
        } else {
            Box::new(points.iter().rev())
        };
        for &p in iter {
            while hull.len() >= start + 2 && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0 {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

/// The rotation (radians) that gives the smallest-area axis-aligned bounding rectangle
/// (one hull edge lies on the rectangle: rotating calipers, tested edge by edge), turned
/// a further quarter turn when needed so the rectangle is at least as wide as high; and
/// that rectangle's size.
pub fn smallest_bounding_rotation(points: &[Vec2]) -> (f64, Vec2) {
    let hull = convex_hull(points.to_vec());
    let size_at = |angle: f64| {
        let turned: Vec<Vec2> = hull.iter().map(|&p| rotated(p, angle)).collect();
        let (lo, hi) = crate::point_bounds(&turned);
        hi - lo
    };
    let mut best = (0.0, size_at(0.0));
    for i in 0..hull.len() {
        let e = hull[(i + 1) % hull.len()] - hull[i];
        if e.norm() == 0.0 {
            continue;
        }
        let angle = -e.y.atan2(e.x);
        let size = size_at(angle);
        if size.x * size.y < best.1.x * best.1.y * (1.0 - 1e-12) {
            best = (angle, size);
        }
    }
    if best.1.x < best.1.y {
        (best.0 + std::f64::consts::FRAC_PI_2, Vec2::new(best.1.y, best.1.x))
    } else {
        best
    }
}

/// Lower-left corners for rectangles of `sizes` set in rows no wider than `row_width`
/// (a rectangle wider than that gets a row of its own), `gap` apart, in decreasing
/// height order (first-fit decreasing height on an unbounded strip).
pub fn arrange_in_rows(sizes: &[Vec2], row_width: f64, gap: f64) -> Vec<Vec2> {
    let mut order: Vec<usize> = (0..sizes.len()).collect();
    order.sort_by(|&a, &b| sizes[b].y.total_cmp(&sizes[a].y).then(a.cmp(&b)));
    // Rows: (y, height, x cursor).
    let mut rows: Vec<(f64, f64, f64)> = Vec::new();
    let mut top = 0.0;
    let mut corners = vec![Vec2::zeros(); sizes.len()];
    for i in order {
        let s = sizes[i];
        let row = match rows
            .iter()
            .position(|&(_, h, x)| s.y <= h && (x == 0.0 || x + s.x <= row_width))
        {
            Some(r) => r,
            None => {
                rows.push((top, s.y, 0.0));
                top += s.y + gap;
                rows.len() - 1
            }
        };
        corners[i] = Vec2::new(rows[row].2, rows[row].0);
        rows[row].2 += s.x + gap;
    }
    corners
}

/// Packs the pieces onto as few sheets as a shelf packer finds: each piece is turned to
/// its smallest bounding rectangle (landscape), turned upright instead when only that
/// fits, then placed first-fit on shelves in order of decreasing height (FFDH), with
/// `gap_mm` between pieces and from the sheet's edges. Sheets are drawn side by side
/// 20 mm apart; [`Pattern::sheet_pattern`] extracts one.
///
/// # Errors
/// A sheet size or gap that is not a positive (non-negative for the gap) number; a piece
/// that fits the sheet in no orientation (named, with its size).
pub fn pack_pieces(pattern: &mut Pattern, options: &SheetOptions) -> Result<(), PatternError> {
    let (w, h, gap) = (options.width_mm, options.height_mm, options.gap_mm);
    if !(w.is_finite() && w > 0.0 && h.is_finite() && h > 0.0) {
        return Err(PatternError::Option {
            option: "sheet",
            message: format!("the sheet size must be positive, got {w} × {h} mm"),
        });
    }
    if !(gap.is_finite() && gap >= 0.0) {
        return Err(PatternError::Option {
            option: "sheet gap",
            message: format!("must be a non-negative number of millimetres, got {gap}"),
        });
    }
    let (usable_w, usable_h) = (w - 2.0 * gap, h - 2.0 * gap);
    // Orientation and size of each piece.
    let mut items: Vec<(usize, f64, Vec2)> = Vec::with_capacity(pattern.pieces.len());
    for (i, piece) in pattern.pieces.iter().enumerate() {
        let points: Vec<Vec2> = piece.cut.iter().flatten().copied().collect();
        let (angle, size) = smallest_bounding_rotation(&points);
        let fits = |s: Vec2| s.x <= usable_w + 1e-9 && s.y <= usable_h + 1e-9;
        let (angle, size) = if fits(size) {
            (angle, size)
        } else if fits(Vec2::new(size.y, size.x)) {
            (angle + std::f64::consts::FRAC_PI_2, Vec2::new(size.y, size.x))
        } else {
            return Err(PatternError::PieceTooLarge {
                piece: piece.name.clone(),
                width_mm: size.x,
                height_mm: size.y,
                sheet_width_mm: w,
                sheet_height_mm: h,
                gap_mm: gap,
            });
        };
        items.push((i, angle, size));
    }
    items.sort_by(|a, b| b.2.y.total_cmp(&a.2.y).then(a.0.cmp(&b.0)));
    // Shelves: (sheet, y, height, x cursor).
    let mut shelves: Vec<(usize, f64, f64, f64)> = Vec::new();
    let mut sheet_top: Vec<f64> = Vec::new();
    let mut placed = Vec::with_capacity(items.len());
    for &(i, angle, size) in &items {
        let slot = shelves
            .iter()
            .position(|&(_, _, height, x)| size.y <= height + 1e-9 && x + size.x <= usable_w + 1e-9);
        let shelf = match slot {
            Some(s) => s,
            None => {
                let sheet = sheet_top.iter().position(|&top| top + size.y <= usable_h + 1e-9);
                let sheet = match sheet {
                    Some(s) => s,
                    None => {
                        sheet_top.push(0.0);
                        sheet_top.len() - 1
                    }
                };
                shelves.push((sheet, sheet_top[sheet], size.y, 0.0));
                sheet_top[sheet] += size.y + gap;
                shelves.len() - 1
            }
        };
        let (sheet, y, _, x) = shelves[shelf];
        shelves[shelf].3 += size.x + gap;
        placed.push((i, angle, sheet, Vec2::new(x, y)));
    }
    pattern.sheets = (0..sheet_top.len())
        .map(|s| (Vec2::new(s as f64 * (w + SHEET_SPACING_MM), 0.0), Vec2::new(w, h)))
        .collect();
    for (i, angle, sheet, corner) in placed {
        let turned = pattern.pieces[i].transformed(|p| rotated(p, angle), angle);
        let (lo, _) = turned.bounds();
        let target = pattern.sheets[sheet].0 + Vec2::new(gap, gap) + corner;
        let mut moved = turned.translated(target - lo);
        moved.sheet = sheet;
        pattern.pieces[i] = moved;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::PatternPiece;

    fn square(name: &str, side: f64, turn: f64) -> PatternPiece {
        let (s, c) = turn.sin_cos();
        let r = |x: f64, y: f64| Vec2::new(c * x - s * y, s * x + c * y);
        PatternPiece {
            name: name.into(),
            cut: vec![vec![r(0.0, 0.0), r(side, 0.0), r(side, side / 2.0), r(0.0, side / 2.0)]],
            folds: vec![],
            labels: vec![],
            sheet: 0,
            placement: Default::default(),
        }
    }

    #[test]
    fn pieces_are_turned_square_and_never_overlap_or_leave_their_sheet() {
        let mut pattern = Pattern {
            pieces: (0..12)
                .map(|i| square(&format!("p{i}"), 80.0 + 10.0 * i as f64, 0.3 * i as f64))
                .collect(),
            ..Default::default()
        };
        let sheet = SheetOptions::new(210.0, 297.0);
        pack_pieces(&mut pattern, &sheet).unwrap();
        assert!(pattern.sheets.len() >= 2);
        let boxes: Vec<(usize, Vec2, Vec2)> = pattern
            .pieces
            .iter()
            .map(|p| (p.sheet, p.bounds().0, p.bounds().1))
            .collect();
        for (i, &(s, lo, hi)) in boxes.iter().enumerate() {
            // Turned to the smallest rectangle: a 2:1 rectangle, landscape.
            let size = hi - lo;
            assert!((size.x - 2.0 * size.y).abs() < 1e-9, "{size:?}");
            let (origin, extent) = pattern.sheets[s];
            assert!(lo.x >= origin.x + 5.0 - 1e-9 && lo.y >= origin.y + 5.0 - 1e-9);
            assert!(hi.x <= origin.x + extent.x - 5.0 + 1e-9 && hi.y <= origin.y + extent.y - 5.0 + 1e-9);
            for &(t, lo2, hi2) in &boxes[i + 1..] {
                let apart = lo.x >= hi2.x + 5.0 - 1e-9
                    || lo2.x >= hi.x + 5.0 - 1e-9
                    || lo.y >= hi2.y + 5.0 - 1e-9
                    || lo2.y >= hi.y + 5.0 - 1e-9;
                assert!(s != t || apart, "pieces overlap on sheet {s}");
            }
        }
    }

    #[test]
    fn a_piece_larger_than_the_sheet_is_named() {
        let mut pattern = Pattern {
            pieces: vec![square("small", 50.0, 0.0), square("huge", 400.0, 0.0)],
            ..Default::default()
        };
        let e = pack_pieces(&mut pattern, &SheetOptions::new(210.0, 297.0)).unwrap_err();
        let text = e.to_string();
        assert!(text.contains("`huge`") && text.contains("400.0 × 200.0"), "{text}");
    }
}

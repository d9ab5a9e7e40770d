//! Packing pattern pieces onto sheets of a given size.

use crate::{Pattern, PatternError, Vec2};
use sheetform_geometry::{refused_number, short_number};

/// A sheet size as a user writes it: `a4`, `a3`, `letter` (portrait), or `WIDTHxHEIGHT`
/// in millimetres (`600x400`).
///
/// # Errors
/// The text is neither, or a size is not a positive finite number; the message quotes it.
pub fn sheet_size_from_text(text: &str) -> Result<(f64, f64), String> {
    match text.to_ascii_lowercase().as_str() {
        "a4" => return Ok((210.0, 297.0)),
        "a3" => return Ok((297.0, 420.0)),
        "letter" => return Ok((215.9, 279.4)),
        _ => {}
    }
    let (w, h) = text
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("`{text}`: expected WIDTHxHEIGHT in mm, e.g. 600x400"))?;
    let number = |s: &str| {
        s.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite() && *v > 0.0)
            .ok_or_else(|| format!("`{s}` in `{text}` is not a positive number of millimetres"))
    };
    Ok((number(w)?, number(h)?))
}

/// Sheet size and spacing for [`pack_pieces`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SheetOptions {
    /// Sheet width (mm).
    pub width_mm: f64,
    /// Sheet height (mm).
    pub height_mm: f64,
    /// Gap kept between pieces and from the sheet's edges (mm), at most
    /// [`MAX_SHEET_GAP_MM`]. Default 5.
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

/// Largest gap between packed pieces and from the sheet's edges (mm): a metre, more
/// than any sheet a cutter takes needs.
pub const MAX_SHEET_GAP_MM: f64 = 1000.0;

/// Space between sheets in the combined drawing (mm).
const SHEET_SPACING_MM: f64 = 20.0;

/// `p` turned by `angle` radians about the origin.
pub fn rotated(p: Vec2, angle: f64) -> Vec2 {
    let (s, c) = angle.sin_cos();
    Vec2::new(c * p.x - s * p.y, s * p.x + c * p.y)
}

/// The rotation (radians) that gives the smallest-area axis-aligned bounding rectangle
/// (one hull edge lies on the rectangle), turned a further quarter turn when needed so
/// the rectangle is at least as wide as high; and that rectangle's size.
///
/// A hull of up to 256 points is turned onto each of its edges in turn (as
/// it always was: where edges tie, as the three of an acute triangle do, rounding picks
/// one, and the pick stays the same). A larger hull is measured by rotating calipers
/// (Toussaint 1983): for each hull edge in turn, the hull points farthest along the
/// edge, back along it and away from it only move forward around the hull, so all edges
/// are measured in time linear in the hull (after the hull's O(n log n)); the chosen
/// rectangle is measured again by turning the hull.
pub fn smallest_bounding_rotation(points: &[Vec2]) -> (f64, Vec2) {
    let hull = sheetform_geometry::convex_hull(points.to_vec());
    let size_at = |angle: f64| {
        let turned: Vec<Vec2> = hull.iter().map(|&p| rotated(p, angle)).collect();
        let (lo, hi) = crate::point_bounds(&turned);
        hi - lo
    };
    let mut best = (0.0, size_at(0.0));
    let n = hull.len();
    if n > SMALL_HULL {
        // Hull counter-clockwise without collinear points: the inside is on the left of
        // every edge. Indices of the points farthest along the edge (`ahead`), farthest
        // from it (`across`) and farthest back along it (`behind`).
        let (mut ahead, mut across, mut behind) = (1, 1, 1);
        let mut best_area = best.1.x * best.1.y;
        let mut best_edge = None;
        for i in 0..n {
            let e = hull[(i + 1) % n] - hull[i];
            let length = e.norm();
            if length == 0.0 {
                continue;
            }
            let u = e / length;
            let normal = Vec2::new(-u.y, u.x);
            // (From the first point: the products stay as small as the piece.)
            let along = |k: usize| (hull[k % n] - hull[0]).dot(&u);
            let off = |k: usize| (hull[k % n] - hull[0]).dot(&normal);
            // Each pointer moves on while that improves it (at most once around).
            let advance = |mut k: usize, value: &dyn Fn(usize) -> f64| {
                let mut steps = 0;
                while steps < n && value(k + 1) > value(k) {
                    k = (k + 1) % n;
                    steps += 1;
                }
                k
            };
            if i == 0 {
                ahead = (0..n).max_by(|&a, &b| along(a).total_cmp(&along(b))).unwrap_or(0);
                across = (0..n).max_by(|&a, &b| off(a).total_cmp(&off(b))).unwrap_or(0);
                behind = (0..n).min_by(|&a, &b| along(a).total_cmp(&along(b))).unwrap_or(0);
            } else {
                ahead = advance(ahead, &along);
                across = advance(across, &off);
                behind = advance(behind, &|k| -along(k));
            }
            let area = (along(ahead) - along(behind)) * (off(across) - off(i));
            if area < best_area * (1.0 - 1e-12) {
                best_area = area;
                best_edge = Some(e);
            }
        }
        if let Some(e) = best_edge {
            let angle = -e.y.atan2(e.x);
            best = (angle, size_at(angle));
        }
    } else {
        for i in 0..n {
            let e = hull[(i + 1) % n] - hull[i];
            if e.norm() == 0.0 {
                continue;
            }
            let angle = -e.y.atan2(e.x);
            let size = size_at(angle);
            if size.x * size.y < best.1.x * best.1.y * (1.0 - 1e-12) {
                best = (angle, size);
            }
        }
    }
    if best.1.x < best.1.y {
        (best.0 + std::f64::consts::FRAC_PI_2, Vec2::new(best.1.y, best.1.x))
    } else {
        best
    }
}

/// Values in slots `0..capacity` (unset slots +∞) and the smallest of every power-of-two
/// block of them (a segment tree), to find the first slot whose value passes a test
/// that every smaller value passes too, in O(log n): the first shelf, row or sheet with
/// room for a piece, without scanning them all (first-fit packing in O(n log n)).
struct FirstFit {
    /// Leaves from `leaves`; node `k` holds the minimum of nodes `2k` and `2k + 1`.
    min: Vec<f64>,
    leaves: usize,
}

impl FirstFit {
    fn new(capacity: usize) -> Self {
        let leaves = capacity.max(1).next_power_of_two();
        Self {
            min: vec![f64::INFINITY; 2 * leaves],
            leaves,
        }
    }

    fn set(&mut self, slot: usize, value: f64) {
        let mut k = self.leaves + slot;
        self.min[k] = value;
        while k > 1 {
            k /= 2;
            self.min[k] = self.min[2 * k].min(self.min[2 * k + 1]);
        }
    }

    fn get(&self, slot: usize) -> f64 {
        self.min[self.leaves + slot]
    }

    /// The first slot whose value passes `fits` (monotone: a value passes when a larger
    /// one does; +∞ never passes).
    fn first(&self, fits: impl Fn(f64) -> bool) -> Option<usize> {
        if !fits(self.min[1]) {
            return None;
        }
        let mut k = 1;
        while k < self.leaves {
            k = if fits(self.min[2 * k]) { 2 * k } else { 2 * k + 1 };
        }
        Some(k - self.leaves)
    }
}

/// Largest hull [`smallest_bounding_rotation`] measures edge by edge (O(n²)); larger ones
/// by rotating calipers (O(n)).
const SMALL_HULL: usize = 256;

/// Lower-left corners for rectangles of `sizes` set in rows no wider than `row_width`
/// (a rectangle wider than that gets a row of its own), `gap` (≥ 0) apart, in decreasing
/// height order (first-fit decreasing height on an unbounded strip; every row is as high
/// as the rectangles still to come, so the first row with room along it is taken).
pub fn arrange_in_rows(sizes: &[Vec2], row_width: f64, gap: f64) -> Vec<Vec2> {
    let mut order: Vec<usize> = (0..sizes.len()).collect();
    order.sort_by(|&a, &b| sizes[b].y.total_cmp(&sizes[a].y).then(a.cmp(&b)));
    // Rows: (y, height); their x cursors in `cursors`.
    let mut rows: Vec<(f64, f64)> = Vec::new();
    let mut cursors = FirstFit::new(sizes.len());
    let mut top = 0.0;
    let mut corners = vec![Vec2::zeros(); sizes.len()];
    for i in order {
        let s = sizes[i];
        let row = match cursors.first(|x| x == 0.0 || x + s.x <= row_width) {
            Some(r) => r,
            None => {
                rows.push((top, s.y));
                cursors.set(rows.len() - 1, 0.0);
                top += s.y + gap;
                rows.len() - 1
            }
        };
        debug_assert!(s.y <= rows[row].1 || s.y.is_nan());
        let x = cursors.get(row);
        corners[i] = Vec2::new(x, rows[row].0);
        cursors.set(row, x + (s.x + gap));
    }
    corners
}

/// Packs the pieces onto as few sheets as a shelf packer finds: each piece is turned to
/// its smallest bounding rectangle (landscape), turned upright instead when only that
/// fits, or to another of its hull's edges when only that fits
/// ([`sheetform_geometry::fitting_rotation`]), then placed first-fit on shelves in order of decreasing height (FFDH), with
/// `gap_mm` between pieces and from the sheet's edges. Sheets are drawn side by side
/// 20 mm apart; [`Pattern::sheet_pattern`] extracts one.
///
/// # Errors
/// A sheet size or gap that is not a positive (non-negative for the gap) number, a gap
/// over [`MAX_SHEET_GAP_MM`]; a piece that fits the sheet in no orientation (named, with
/// its size).
pub fn pack_pieces(pattern: &mut Pattern, options: &SheetOptions) -> Result<(), PatternError> {
    let (w, h, gap) = (options.width_mm, options.height_mm, options.gap_mm);
    if !(w.is_finite() && w > 0.0 && h.is_finite() && h > 0.0) {
        return Err(PatternError::Option {
            option: "sheet",
            message: format!(
                "the sheet size must be positive, got {} × {} mm",
                short_number(w),
                short_number(h)
            ),
        });
    }
    if !(gap.is_finite() && (0.0..=MAX_SHEET_GAP_MM).contains(&gap)) {
        return Err(PatternError::Option {
            option: "sheet_gap",
            message: format!(
                "must be between 0 and {MAX_SHEET_GAP_MM} mm (--sheet-gap), got {}",
                refused_number(gap, &[0.0, MAX_SHEET_GAP_MM])
            ),
        });
    }
    let (usable_w, usable_h) = (w - 2.0 * gap, h - 2.0 * gap);
    // Orientation and size of each piece.
    let mut items: Vec<(usize, f64, Vec2)> = Vec::with_capacity(pattern.pieces.len());
    for (i, piece) in pattern.pieces.iter().enumerate() {
        let points: Vec<Vec2> = piece.cut.iter().flatten().copied().collect();
        let (angle, size) = smallest_bounding_rotation(&points);
        let fits = |s: Vec2| s.x <= usable_w + 1e-9 && s.y <= usable_h + 1e-9;
        let turned_to_fit = || {
            // (A hull that rounding folds up, at absurd sizes, is measured by every point.)
            let hull = sheetform_geometry::convex_hull(points.clone());
            sheetform_geometry::fitting_rotation(if hull.len() >= 3 { &hull } else { &points }, usable_w, usable_h)
        };
        let (angle, size) = if fits(size) {
            (angle, size)
        } else if fits(Vec2::new(size.y, size.x)) {
            (angle + std::f64::consts::FRAC_PI_2, Vec2::new(size.y, size.x))
        } else if let Some(turn) = turned_to_fit() {
            // Fits only at another angle than its smallest rectangle's (a long bent
            // strip: lying along the sheet's diagonal side by side with its bend).
            turn
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
    // Shelves: (sheet, y, height), their x cursors in `cursors`; the sheets' tops in
    // `tops`. Every shelf is as high as the pieces still to come (decreasing height),
    // so the first shelf with room along it is taken, found in O(log n).
    let mut shelves: Vec<(usize, f64, f64)> = Vec::new();
    let mut cursors = FirstFit::new(items.len());
    let mut sheet_count = 0;
    let mut tops = FirstFit::new(items.len());
    let mut placed = Vec::with_capacity(items.len());
    for &(i, angle, size) in &items {
        let slot = cursors.first(|x| x + size.x <= usable_w + 1e-9);
        let shelf = match slot {
            Some(s) => s,
            None => {
                let sheet = match tops.first(|top| top + size.y <= usable_h + 1e-9) {
                    Some(s) => s,
                    None => {
                        tops.set(sheet_count, 0.0);
                        sheet_count += 1;
                        sheet_count - 1
                    }
                };
                let top = tops.get(sheet);
                shelves.push((sheet, top, size.y));
                cursors.set(shelves.len() - 1, 0.0);
                tops.set(sheet, top + (size.y + gap));
                shelves.len() - 1
            }
        };
        let (sheet, y, height) = shelves[shelf];
        debug_assert!(size.y <= height + 1e-9);
        let x = cursors.get(shelf);
        cursors.set(shelf, x + (size.x + gap));
        placed.push((i, angle, sheet, Vec2::new(x, y)));
    }
    pattern.sheets = (0..sheet_count)
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
    use sheetform_geometry::convex_hull;

    fn square(name: &str, side: f64, turn: f64) -> PatternPiece {
        let (s, c) = turn.sin_cos();
        let r = |x: f64, y: f64| Vec2::new(c * x - s * y, s * x + c * y);
        PatternPiece {
            name: name.into(),
            mesh_pieces: vec![],
            cut: vec![vec![r(0.0, 0.0), r(side, 0.0), r(side, side / 2.0), r(0.0, side / 2.0)]],
            folds: vec![],
            labels: vec![],
            sheet: 0,
            placement: Default::default(),
        }
    }

    /// Issue 19: `--sheet-gap 1e308` was accepted and the piece that then fitted nowhere
    /// was reported with its sizes in 300 digits. The gap is bounded (naming the option),
    /// and every number in these messages is short.
    #[test]
    fn sheet_options_out_of_range_are_refused_in_short_numbers() {
        let pattern = || Pattern {
            pieces: vec![square("p", 80.0, 0.0)],
            ..Default::default()
        };
        let message = |sheet: SheetOptions| pack_pieces(&mut pattern(), &sheet).unwrap_err().to_string();
        for gap in [1e308, MAX_SHEET_GAP_MM + 1.0, -1.0, f64::NAN] {
            let e = message(SheetOptions {
                gap_mm: gap,
                ..SheetOptions::new(210.0, 297.0)
            });
            assert!(
                e.contains("`sheet_gap`") && e.contains("--sheet-gap") && e.contains("1000 mm"),
                "{e}"
            );
            assert!(e.len() < 200, "{e}");
        }
        let e = message(SheetOptions::new(1e300, -1e300));
        assert!(e.contains("1e300 × -1e300 mm"), "{e}");
        // The largest gap is allowed; the piece then fits no sheet, said in short numbers.
        let e = message(SheetOptions {
            gap_mm: MAX_SHEET_GAP_MM,
            ..SheetOptions::new(1999.0, 1e300)
        });
        assert!(
            e.contains("does not fit") && e.contains("1999 × 1e300 mm") && e.contains(" 1000 mm margin"),
            "{e}"
        );
        let mut huge = pattern();
        huge.pieces[0] = square("p", 1e300, 0.0);
        let e = pack_pieces(&mut huge, &SheetOptions::new(210.0, 297.0))
            .unwrap_err()
            .to_string();
        assert!(e.contains("measures 1e300 × 5e299 mm"), "{e}");
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
        assert!(text.contains("`huge`") && text.contains("400 × 200 mm"), "{text}");
    }

    fn random(seed: &mut u64) -> f64 {
        *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Issue 19: the smallest rectangle turned the whole hull onto every edge, O(n²) (a
    /// piece outline of 100 000 points, 1e10 rotations). A rounded rectangle of 2 000 points
    /// turned by 0.3 rad: rotating calipers find its 300 × 100 mm.
    #[test]
    fn the_smallest_rectangle_of_a_large_hull_is_found_by_rotating_calipers() {
        use std::f64::consts::{FRAC_PI_2, PI};
        let (w, h, r) = (300.0, 100.0, 20.0);
        let mut points = Vec::new();
        for (cx, cy, start) in [
            (w / 2.0 - r, h / 2.0 - r, 0.0),
            (r - w / 2.0, h / 2.0 - r, FRAC_PI_2),
            (r - w / 2.0, r - h / 2.0, PI),
            (w / 2.0 - r, r - h / 2.0, 3.0 * FRAC_PI_2),
        ] {
            for k in 0..=500 {
                let a = start + FRAC_PI_2 * k as f64 / 500.0;
                points.push(rotated(
                    Vec2::new(cx + r * a.cos(), cy + r * a.sin()) + Vec2::new(1e4, -3e3),
                    0.3,
                ));
            }
        }
        assert!(convex_hull(points.clone()).len() > SMALL_HULL);
        let (angle, size) = smallest_bounding_rotation(&points);
        assert!((size - Vec2::new(w, h)).norm() < 1e-6, "{size:?}");
        let turned: Vec<Vec2> = points.iter().map(|&p| rotated(p, angle)).collect();
        let (lo, hi) = crate::point_bounds(&turned);
        assert!((hi - lo - size).norm() < 1e-9);
        // Against every edge tried, on a random cloud.
        let mut seed = 3;
        let cloud: Vec<Vec2> = (0..5000)
            .map(|_| {
                let (a, d) = (random(&mut seed) * 2.0 * PI, random(&mut seed).sqrt());
                Vec2::new(120.0 * d * a.cos(), 40.0 * d * a.sin())
            })
            .collect();
        let hull = convex_hull(cloud.clone());
        let every_edge = (0..hull.len())
            .map(|i| {
                let e = hull[(i + 1) % hull.len()] - hull[i];
                let turned: Vec<Vec2> = hull.iter().map(|&p| rotated(p, -e.y.atan2(e.x))).collect();
                let (lo, hi) = crate::point_bounds(&turned);
                (hi - lo).x * (hi - lo).y
            })
            .fold(f64::INFINITY, f64::min);
        let (_, size) = smallest_bounding_rotation(&cloud);
        assert!(
            (size.x * size.y - every_edge).abs() <= 1e-9 * every_edge,
            "{} {every_edge}",
            size.x * size.y
        );
    }

    /// The first-fit search agrees with a scan from the front.
    #[test]
    fn first_fit_finds_the_first_slot_a_scan_finds() {
        let mut seed = 11;
        let mut fit = FirstFit::new(300);
        let mut values = vec![f64::INFINITY; 300];
        for step in 0..3000 {
            let slot = (random(&mut seed) * 300.0) as usize;
            let value = (random(&mut seed) * 100.0).floor();
            fit.set(slot, value);
            values[slot] = value;
            let bound = random(&mut seed) * 100.0;
            let scan = values.iter().position(|&v| v <= bound);
            assert_eq!(fit.first(|v| v <= bound), scan, "step {step}");
            assert_eq!(fit.get(slot), value);
        }
    }

    /// Issue 19: each piece scanned every shelf and every sheet before (O(n²) over
    /// thousands of pieces). 3 000 rectangles packed as the scan packed them.
    #[test]
    fn many_pieces_are_packed_on_the_shelves_a_scan_picks() {
        let mut seed = 5;
        let sizes: Vec<Vec2> = (0..3000)
            .map(|_| {
                let (a, b) = (5.0 + 60.0 * random(&mut seed), 5.0 + 60.0 * random(&mut seed));
                Vec2::new(a.max(b), a.min(b))
            })
            .collect();
        let mut pattern = Pattern {
            pieces: sizes
                .iter()
                .enumerate()
                .map(|(i, s)| PatternPiece {
                    name: format!("p{i}"),
                    mesh_pieces: vec![],
                    cut: vec![vec![Vec2::zeros(), Vec2::new(s.x, 0.0), *s, Vec2::new(0.0, s.y)]],
                    folds: vec![],
                    labels: vec![],
                    sheet: 0,
                    placement: Default::default(),
                })
                .collect(),
            ..Default::default()
        };
        let options = SheetOptions::new(300.0, 200.0);
        pack_pieces(&mut pattern, &options).unwrap();
        // The scan: first shelf with room, else the first sheet with room, else a new one.
        let (usable_w, usable_h, gap) = (290.0, 190.0, 5.0);
        let mut order: Vec<usize> = (0..sizes.len()).collect();
        order.sort_by(|&a, &b| sizes[b].y.total_cmp(&sizes[a].y).then(a.cmp(&b)));
        let mut shelves: Vec<(usize, f64, f64, f64)> = Vec::new();
        let mut tops: Vec<f64> = Vec::new();
        for i in order {
            let size = sizes[i];
            let shelf = match shelves
                .iter()
                .position(|&(_, _, height, x)| size.y <= height + 1e-9 && x + size.x <= usable_w + 1e-9)
            {
                Some(s) => s,
                None => {
                    let sheet = match tops.iter().position(|&top| top + size.y <= usable_h + 1e-9) {
                        Some(s) => s,
                        None => {
                            tops.push(0.0);
                            tops.len() - 1
                        }
                    };
                    shelves.push((sheet, tops[sheet], size.y, 0.0));
                    tops[sheet] += size.y + gap;
                    shelves.len() - 1
                }
            };
            let (sheet, y, _, x) = shelves[shelf];
            shelves[shelf].3 += size.x + gap;
            let piece = &pattern.pieces[i];
            assert_eq!(piece.sheet, sheet, "piece {i}");
            let corner = pattern.sheets[sheet].0 + Vec2::new(gap + x, gap + y);
            assert!((piece.bounds().0 - corner).norm() < 1e-9, "piece {i}");
        }
        assert_eq!(pattern.sheets.len(), tops.len());
        // Rows for the flat layout: the same first fit.
        let corners = arrange_in_rows(&sizes, 400.0, 3.0);
        assert!(corners
            .iter()
            .zip(&sizes)
            .all(|(c, s)| c.x == 0.0 || c.x + s.x <= 400.0));
    }

    /// Issue 19: one cutter file per sheet looked at every piece for every sheet;
    /// `sheet_patterns` sorts them out in one pass, with the same result.
    #[test]
    fn the_sheets_patterns_in_one_pass_are_each_sheets_pattern() {
        let mut pattern = Pattern {
            pieces: (0..40)
                .map(|i| square(&format!("p{i}"), 60.0 + 3.0 * i as f64, 0.1 * i as f64))
                .collect(),
            bend_flat_changes_mm: vec![0.5],
            ..Default::default()
        };
        pack_pieces(&mut pattern, &SheetOptions::new(210.0, 297.0)).unwrap();
        assert!(pattern.sheets.len() > 3);
        let each: Vec<Pattern> = (0..pattern.sheets.len()).map(|s| pattern.sheet_pattern(s)).collect();
        assert_eq!(pattern.sheet_patterns(), each);
        assert_eq!(each.iter().map(|p| p.pieces.len()).sum::<usize>(), 40);
    }
}

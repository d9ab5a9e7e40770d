//! Material allowances on a pattern: seam allowance with notches and grain lines for
//! fabric and leather, kerf compensation for laser-cut card and plywood, bend allowance
//! for a sheet with thickness ([`crate::bend_allowance`]).

use crate::bend_allowance::BendAllowance;
use crate::pattern::{Fold, FoldStyle, PatternPiece};
use crate::{PatternError, Vec2};
use geo::algorithm::buffer::{BufferStyle, LineJoin};
use geo::{Buffer, LineString, Polygon};
use sheetform_geometry::{refused_number, short_number};

/// What the material needs around the design lines (every command's pattern; all zero by
/// default: the pattern is the design as it is).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MaterialAllowance {
    /// Seam allowance (mm) added outside every piece for sewing or gluing: the design
    /// outline becomes the stitch line and the cut line moves out by this much (mitred
    /// corners; those sharper than 30° cut square). Fabric and leather panels.
    pub seam_allowance_mm: f64,
    /// Notches: short cuts into the seam allowance at both ends and the middle of every
    /// seam, to match pieces when sewing (with a seam allowance only).
    pub notches: bool,
    /// Laser kerf (mm): the width the beam burns away. The cut line moves out by half of
    /// it (holes shrink by half of it) so that the parts come out at their design size.
    pub kerf_mm: f64,
    /// A grain line on every piece: the direction on the flat piece that runs up the
    /// model (+z), where the fabric's straight grain should lie (pieces lying level get
    /// none).
    pub grain_lines: bool,
    /// Thickness, inner bend radius and K-factor of the sheet: every mountain and valley
    /// fold becomes a bend zone of its flat length (`None`: zero-thickness folds).
    pub bend: Option<BendAllowance>,
}

/// Largest seam allowance or kerf accepted (mm).
pub const MAX_ALLOWANCE_MM: f64 = 100.0;

impl MaterialAllowance {
    /// Whether anything is to be added.
    pub fn is_none(&self) -> bool {
        self.seam_allowance_mm == 0.0 && self.kerf_mm == 0.0 && !self.grain_lines && self.bend.is_none()
    }

    /// Checks the sizes: finite, non-negative, at most [`MAX_ALLOWANCE_MM`]; the bend
    /// allowance's figures ([`BendAllowance::validate`]); not both a seam allowance and a
    /// bend allowance (stitched fabric has no thickness to bend, a bent sheet no seam
    /// allowance to sew).
    ///
    /// # Errors
    /// The option named, with the value and the bound.
    pub fn validate(&self) -> Result<(), PatternError> {
        for (option, value) in [("seam_allowance_mm", self.seam_allowance_mm), ("kerf_mm", self.kerf_mm)] {
            if !(value.is_finite() && (0.0..=MAX_ALLOWANCE_MM).contains(&value)) {
                return Err(PatternError::Option {
                    option,
                    message: format!(
                        "must be between 0 and {MAX_ALLOWANCE_MM} mm, got {}",
                        refused_number(value, &[0.0, MAX_ALLOWANCE_MM])
                    ),
                });
            }
        }
        if let Some(bend) = &self.bend {
            bend.validate()?;
            if self.seam_allowance_mm > 0.0 {
                return Err(PatternError::Option {
                    option: "seam_allowance_mm",
                    message: "a seam allowance (sewn fabric) and a sheet thickness (bend allowance) do not go together: choose one".into(),
                });
            }
        }
        Ok(())
    }
}

/// A piece's cut loops moved out by `distance` (mm): the region of the piece (outline
/// counter-clockwise, holes clockwise, even–odd) buffered with mitred joins (geo's
/// `Buffer`; corners sharper than 30° are cut square instead of running out into a
/// spike), its exterior and interior rings as the new loops.
///
/// # Errors
/// A hole narrower than twice `distance` closes up: its cut line would be lost, so the
/// hole (its centre and width) is returned instead.
fn offset_loops(loops: &[Vec<Vec2>], distance: f64) -> Result<Vec<Vec<Vec2>>, ClosedHole> {
    let ring = |l: &Vec<Vec2>| LineString::from(l.iter().map(|p| (p.x, p.y)).collect::<Vec<_>>());
    let area = |l: &Vec<Vec2>| sheetform_geometry::signed_area(l);
    let outers: Vec<&Vec<Vec2>> = loops.iter().filter(|l| area(l) > 0.0).collect();
    let holes: Vec<&Vec<Vec2>> = loops.iter().filter(|l| area(l) < 0.0).collect();
    let mut out = Vec::new();
    for outer in outers {
        let inside: Vec<LineString> = holes
            .iter()
            .filter(|h| sheetform_geometry::rings_contain([outer.as_slice()], h[0]))
            .map(|h| ring(h))
            .collect();
        let polygon = Polygon::new(ring(outer), inside);
        let style = BufferStyle::new(distance).line_join(LineJoin::Miter(std::f64::consts::FRAC_PI_6));
        let buffered = polygon.buffer_with_style(style);
        let kept: Vec<Vec<Vec2>> = buffered
            .iter()
            .flat_map(|p| p.interiors().iter().map(|r| ring_loop(r, false)))
            .collect();
        // Each hole shrinks to a ring inside it; one with none inside closed up.
        for hole in holes
            .iter()
            .filter(|h| sheetform_geometry::rings_contain([outer.as_slice()], h[0]))
        {
            let survives = kept
                .iter()
                .any(|k| sheetform_geometry::rings_contain([hole.as_slice()], k[0]));
            if !survives {
                let (low, high) = hole.iter().fold(
                    (Vec2::repeat(f64::INFINITY), Vec2::repeat(f64::NEG_INFINITY)),
                    |(low, high), p| (low.inf(p), high.sup(p)),
                );
                let size = high - low;
                return Err(ClosedHole {
                    centre: (low + high) * 0.5,
                    width: size.x.min(size.y),
                });
            }
        }
        for p in &buffered {
            out.push(ring_loop(p.exterior(), true));
        }
        out.extend(kept);
    }
    Ok(out)
}

/// A hole that an offset closes up.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ClosedHole {
    /// The centre of the hole's bounding box (mm, pattern coordinates).
    pub centre: Vec2,
    /// The smaller side of its bounding box (mm).
    pub width: f64,
}

impl ClosedHole {
    /// The error naming `option` (its value `value`) and the piece.
    fn error(&self, option: &'static str, value: f64, what: &str, piece: &str) -> PatternError {
        PatternError::Option {
            option,
            message: format!(
                "a {} mm {what} closes the hole about {} mm wide at ({}, {}) mm in piece `{piece}`, \
                 whose cut line would be lost: use a smaller {what} (under half the hole's width) \
                 or a design without the hole",
                short_number(value),
                short_number(self.width),
                short_number(self.centre.x),
                short_number(self.centre.y),
            ),
        }
    }
}

/// A ring of geo's as a cut loop: the closing point dropped, turned counter-clockwise
/// (an outline) or clockwise (a hole).
pub(crate) fn ring_loop(ring: &LineString, counter_clockwise: bool) -> Vec<Vec2> {
    let mut points: Vec<Vec2> = ring.coords().map(|c| Vec2::new(c.x, c.y)).collect();
    if points.len() > 1 && points.first() == points.last() {
        points.pop();
    }
    let area = sheetform_geometry::signed_area(&points);
    if (counter_clockwise && area < 0.0) || (!counter_clockwise && area > 0.0) {
        points.reverse();
    }
    points
}

/// Adds the seam allowance to a piece: its loops become stitch lines, its cut loops the
/// loops moved out by the allowance; notches at `notch_points` (points on the stitch line
/// with the outward direction there) cross the allowance.
///
/// # Errors
/// The allowance closes a hole of the piece (named with the option).
pub(crate) fn add_seam_allowance(
    piece: &mut PatternPiece,
    allowance_mm: f64,
    notch_points: &[(Vec2, Vec2)],
) -> Result<(), PatternError> {
    let cut = offset_loops(&piece.cut, allowance_mm)
        .map_err(|hole| hole.error("seam_allowance_mm", allowance_mm, "seam allowance", &piece.name))?;
    for l in &piece.cut {
        for i in 0..l.len() {
            piece.folds.push(Fold {
                a: l[i],
                b: l[(i + 1) % l.len()],
                style: FoldStyle::Stitch,
                angle_degrees: 0.0,
            });
        }
    }
    let mut notched: Vec<Vec2> = Vec::new();
    for &(point, outward) in notch_points {
        // Runs meeting at a corner both ask for a notch there: one is enough.
        if notched.iter().any(|q| (q - point).norm() <= 1e-6) {
            continue;
        }
        notched.push(point);
        piece.folds.push(Fold {
            a: point,
            b: point + outward * (0.6 * allowance_mm),
            style: FoldStyle::Notch,
            angle_degrees: 0.0,
        });
    }
    piece.cut = cut;
    Ok(())
}

/// Moves a piece's cut loops out by half the kerf.
///
/// # Errors
/// The kerf closes a hole of the piece (named with the option).
pub(crate) fn add_kerf(piece: &mut PatternPiece, kerf_mm: f64) -> Result<(), PatternError> {
    piece.cut =
        offset_loops(&piece.cut, 0.5 * kerf_mm).map_err(|hole| hole.error("kerf_mm", kerf_mm, "kerf", &piece.name))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(loops: &[Vec<Vec2>]) -> f64 {
        loops.iter().map(|l| sheetform_geometry::signed_area(l)).sum()
    }

    fn square_with_hole() -> PatternPiece {
        let v = |x: f64, y: f64| Vec2::new(x, y);
        PatternPiece {
            name: "p".into(),
            mesh_pieces: vec![],
            cut: vec![
                vec![v(0.0, 0.0), v(100.0, 0.0), v(100.0, 100.0), v(0.0, 100.0)],
                vec![v(40.0, 40.0), v(40.0, 60.0), v(60.0, 60.0), v(60.0, 40.0)],
            ],
            folds: vec![],
            labels: vec![],
            sheet: 0,
            placement: Default::default(),
        }
    }

    #[test]
    fn a_seam_allowance_grows_the_outline_and_keeps_the_design_as_stitch_lines() {
        let mut piece = square_with_hole();
        add_seam_allowance(&mut piece, 8.0, &[(Vec2::new(50.0, 0.0), Vec2::new(0.0, -1.0))]).unwrap();
        // Mitred corners: the outline becomes 116 × 116; the 20 mm hole shrinks by 8 mm
        // on each side to 4 × 4.
        assert!(
            (area(&piece.cut) - (116.0 * 116.0 - 4.0 * 4.0)).abs() < 1e-3,
            "{}",
            area(&piece.cut)
        );
        assert_eq!(piece.cut.len(), 2);
        assert_eq!(piece.folds.iter().filter(|f| f.style == FoldStyle::Stitch).count(), 8);
        let notch = piece.folds.iter().find(|f| f.style == FoldStyle::Notch).unwrap();
        assert!((notch.b - Vec2::new(50.0, -4.8)).norm() < 1e-12);
    }

    /// Issue 35: an allowance or kerf that closes a hole is refused naming the option,
    /// the hole and the piece (its cut line was silently lost, status ok).
    #[test]
    fn an_offset_that_closes_a_hole_is_refused_naming_the_option_and_the_hole() {
        let mut piece = square_with_hole();
        let error = add_seam_allowance(&mut piece, 12.0, &[]).unwrap_err().to_string();
        for part in ["seam_allowance_mm", "20 mm wide", "(50, 50)", "`p`"] {
            assert!(error.contains(part), "{part} missing in: {error}");
        }
        let mut piece = square_with_hole();
        let error = add_kerf(&mut piece, 25.0).unwrap_err().to_string();
        assert!(error.contains("kerf_mm") && error.contains("(50, 50)"), "{error}");
        assert_eq!(piece.cut, square_with_hole().cut, "the piece changed");
    }

    #[test]
    fn kerf_moves_the_cut_out_by_half_its_width_and_shrinks_holes() {
        let mut piece = square_with_hole();
        add_kerf(&mut piece, 0.2).unwrap();
        let expected = 100.2 * 100.2 - 19.8 * 19.8;
        // geo's boolean engine rounds to an integer grid: about 1e-7 of the size.
        assert!(
            (area(&piece.cut) - expected).abs() < 1e-3,
            "{} vs {expected}",
            area(&piece.cut)
        );
        assert_eq!(piece.cut.len(), 2);
    }

    #[test]
    fn allowances_are_bounded() {
        let bad = MaterialAllowance {
            kerf_mm: f64::NAN,
            ..Default::default()
        };
        assert!(bad.validate().unwrap_err().to_string().contains("kerf_mm"));
        let huge = MaterialAllowance {
            seam_allowance_mm: 1e6,
            ..Default::default()
        };
        assert!(huge.validate().is_err());
        assert!(MaterialAllowance::default().validate().is_ok() && MaterialAllowance::default().is_none());
    }
}

//! The focal length of a perspective photo, estimated from its drawing (beyond the paper,
//! whose §9 and Fig. 14 name a camera model as future work; used when neither the
//! annotation nor the photo's EXIF gives one).
//!
//! Through the camera that took the photo, the linear solve of §6 leaves a developable
//! object's rulings nearly developable: the mean of §8.2's error (the angle between the
//! surface normals at a ruling's two ends) is 0.07–0.55° on the synthetic perspective
//! views. Through a wrong focal length the rays, and with them the mirror pairs (§5.3)
//! and the rulings' ends in 3D, are wrong, and the error grows: at 0.8 × the true focal
//! length 0.3–3.8°, at 1.4 × 0.7–5.7° on the same views (figures in
//! `docs/benchmarks-history.md`, "Photos: the focal length from the drawing"). The
//! estimate is the focal length of least mean error: a scan of [`SCAN_COUNT`] focal
//! lengths, each [`SCAN_RATIO`] times the last, from [`SCAN_FIRST_DIAGONALS`] image
//! diagonals (a diagonal field of view of 127°) to 4 (14°), then a golden-section search
//! in `ln f` on the two scan intervals round the best, to 1 %. The mean error is not
//! convex in `f` far from its minimum (a few views have a second, shallower dip), so the
//! scan comes first. [`SCAN_COUNT`] + [`REFINEMENT_COUNT`] linear solves in all.

use crate::PhotoError;

/// The first focal length of the scan, in image diagonals.
pub const SCAN_FIRST_DIAGONALS: f64 = 0.25;
/// The ratio of one focal length of the scan to the one before (`2^(1/4)`).
pub const SCAN_RATIO: f64 = 1.189_207_115_002_721;
/// How many focal lengths the scan tries (0.25 to 4 diagonals).
pub const SCAN_COUNT: usize = 17;
/// Golden-section steps after the scan: the bracket `SCAN_RATIO²` narrows to 1 %.
pub const REFINEMENT_COUNT: usize = 8;

/// A focal length estimated from the drawing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FocalLengthEstimate {
    /// The estimate, in pixels.
    pub focal_length_px: f64,
    /// The mean developability error (§8.2) of the linear solve through it (radians).
    pub mean_error_rad: f64,
    /// The least error was at an end of the scanned range (0.25 or 4 diagonals): the
    /// drawing hardly tells the focal length (a nearly orthographic view, or a drawing
    /// whose rulings fit any camera).
    pub at_range_end: bool,
}

/// Estimates the focal length of a photo of diagonal `diagonal` (pixels) as the one
/// whose linear solve has the least mean developability error; `mean_error(f)` is that
/// error through focal length `f` (pixels). A focal length whose solve fails is skipped.
///
/// # Errors
/// The error of the last failed solve when every solve of the scan fails.
pub fn estimate_focal_length(
    diagonal: f64,
    mut mean_error: impl FnMut(f64) -> Result<f64, PhotoError>,
) -> Result<FocalLengthEstimate, PhotoError> {
    let mut evaluate = |f: f64, failure: &mut Option<PhotoError>| match mean_error(f) {
        Ok(e) if e.is_finite() => e,
        Ok(_) => f64::INFINITY,
        Err(e) => {
            *failure = Some(e);
            f64::INFINITY
        }
    };
    let mut failure = None;
    let scan: Vec<(f64, f64)> = (0..SCAN_COUNT)
        .map(|k| {
            let f = diagonal * SCAN_FIRST_DIAGONALS * SCAN_RATIO.powi(k as i32);
            (f, evaluate(f, &mut failure))
        })
        .collect();
    let best = (0..SCAN_COUNT)
        .min_by(|&a, &b| scan[a].1.total_cmp(&scan[b].1))
        .expect("a scan");
    if !scan[best].1.is_finite() {
        return Err(failure.unwrap_or_else(|| PhotoError::field("camera", "no focal length gives a finite error")));
    }
    // Golden section on ln f over the scan's neighbours of the best.
    let (mut lo, mut hi) = (
        scan[best.saturating_sub(1)].0.ln(),
        scan[(best + 1).min(SCAN_COUNT - 1)].0.ln(),
    );
    let golden = 0.5 * (5f64.sqrt() - 1.0);
    let mut inner = [hi - golden * (hi - lo), lo + golden * (hi - lo)];
    let mut values = [
        evaluate(inner[0].exp(), &mut failure),
        evaluate(inner[1].exp(), &mut failure),
    ];
    let (mut best_f, mut best_error) = scan[best];
    for _ in 2..REFINEMENT_COUNT {
        if values[0] <= values[1] {
            hi = inner[1];
            inner = [hi - golden * (hi - lo), inner[0]];
            values = [evaluate(inner[0].exp(), &mut failure), values[0]];
        } else {
            lo = inner[0];
            inner = [inner[1], lo + golden * (hi - lo)];
            values = [values[1], evaluate(inner[1].exp(), &mut failure)];
        }
    }
    for (x, v) in inner.iter().zip(values) {
        if v < best_error {
            (best_f, best_error) = (x.exp(), v);
        }
    }
    Ok(FocalLengthEstimate {
        focal_length_px: best_f,
        mean_error_rad: best_error,
        at_range_end: best == 0 || best == SCAN_COUNT - 1,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bowl-shaped error with its least value at 612 px (a 1 000 px diagonal) is found
    /// to 1 %, in 25 evaluations; a second, shallower dip far from it does not catch the
    /// scan; a minimum below the range is reported at the range's end.
    #[test]
    fn the_least_error_is_found_to_a_percent() {
        let mut calls = 0;
        // The bowl at 612 px, and a dip of least value 0.2 at 2 500 px.
        let error = |f: f64| (f / 612.0).ln().powi(2).min(0.2 + 4.0 * (f / 2500.0).ln().powi(2));
        let estimate = estimate_focal_length(1000.0, |f| {
            calls += 1;
            Ok(error(f))
        })
        .unwrap();
        assert!((estimate.focal_length_px / 612.0 - 1.0).abs() < 0.01, "{estimate:?}");
        assert!(!estimate.at_range_end);
        assert_eq!(calls, SCAN_COUNT + REFINEMENT_COUNT);
        let low = estimate_focal_length(1000.0, |f| Ok((f / 100.0).ln().powi(2))).unwrap();
        assert!(low.at_range_end && (low.focal_length_px - 250.0).abs() < 1.0, "{low:?}");
    }

    /// Failed solves are skipped; when all fail, the last failure is the error.
    #[test]
    fn failed_solves_are_skipped() {
        let estimate = estimate_focal_length(1000.0, |f| {
            if f < 400.0 {
                Err(PhotoError::field("symmetry", "degenerate"))
            } else {
                Ok((f / 800.0).ln().powi(2))
            }
        })
        .unwrap();
        assert!((estimate.focal_length_px / 800.0 - 1.0).abs() < 0.01, "{estimate:?}");
        let e = estimate_focal_length(1000.0, |_| Err(PhotoError::field("symmetry", "degenerate"))).unwrap_err();
        assert!(e.to_string().contains("degenerate"), "{e}");
    }
}

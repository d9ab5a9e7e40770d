//! The side panel (the chair's leg): the leg curve swept along `z`.

use crate::SlitError;
use nalgebra::{Vector2, Vector3};
use sheetform_geometry::{numbers_apart, short_number, Bezier2, ParametricCurve};

type Vec2 = Vector2<f64>;
type Vec3 = Vector3<f64>;

/// The side panel's profile as a polyline inscribed in the leg curve.
///
/// The polyline has `segments` chords, each exactly `L2 / segments` long, with every
/// vertex on the curve; so the swept panel is *exactly* isometric to its flat rectangle
/// (a cylinder made of planar strips), and its top end, where the strips begin (ridge
/// line E0), lies on the curve just past arc length `L2` (the chords are a little shorter
/// than the arcs they cut off; the difference is `O(L2 κ² h²)`). This is a choice of ours:
/// the paper's leg is a smooth curve and does not say how it meets the sheet's length.
#[derive(Debug, Clone, PartialEq)]
pub struct SidePanel {
    /// Profile points `[x, y]` from the foot to the top (E0), `segments + 1` of them.
    pub profile: Vec<Vec2>,
}

impl SidePanel {
    /// Inscribes the panel in the leg curve.
    ///
    /// # Errors
    /// A curve shorter than the panel, or a top (E0) on the wrong side of the symmetry
    /// plane, naming `leg_curve`.
    pub fn new(curve: &Bezier2, panel_length: f64, segments: usize) -> Result<Self, SlitError> {
        let segments = segments.max(1);
        let chord = panel_length / segments as f64;
        let mut profile = vec![curve.point(0.0)];
        let mut t = 0.0;
        for k in 0..segments {
            let from = profile[k];
            // The first parameter after `t` at chord distance `chord`: march, then bisect.
            let distance = |u: f64| (curve.point(u) - from).norm() - chord;
            let steps = 4096;
            let mut lo = t;
            let mut hi = None;
            for i in 1..=steps {
                let u = t + (1.0 - t) * i as f64 / steps as f64;
                if distance(u) >= 0.0 {
                    hi = Some(u);
                    break;
                }
                lo = u;
            }
            let Some(mut hi) = hi else {
                return Err(SlitError::field(
                    "leg_curve",
                    format!(
                        "the leg curve ends after about {} of the side panel's length l2_panel_length = {}: \
                         it must be at least as long as the panel",
                        numbers_apart(k as f64 * chord + (curve.point(1.0) - from).norm(), panel_length)[0],
                        numbers_apart(k as f64 * chord + (curve.point(1.0) - from).norm(), panel_length)[1]
                    ),
                ));
            };
            for _ in 0..80 {
                let mid = 0.5 * (lo + hi);
                if distance(mid) >= 0.0 {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            t = hi;
            profile.push(curve.point(hi));
        }
        let top = *profile.last().expect("non-empty");
        if top.x <= 0.0 {
            return Err(SlitError::field(
                "leg_curve",
                format!(
                    "the strips would start at x = {} (where the leg curve has run l2_panel_length), on or beyond \
                     the symmetry plane x = 0; the leg must stay at x > 0",
                    short_number(top.x)
                ),
            ));
        }
        Ok(Self { profile })
    }

    /// The default leg (Fig. 9): a vertical panel at `x = x0` from the ground up.
    pub fn vertical(x0: f64, panel_length: f64, segments: usize) -> Self {
        let segments = segments.max(1);
        Self {
            profile: (0..=segments)
                .map(|k| Vec2::new(x0, panel_length * k as f64 / segments as f64))
                .collect(),
        }
    }

    /// Where the strips begin (ridge line E0), `[x, y]`.
    pub fn top(&self) -> Vec2 {
        *self.profile.last().expect("non-empty")
    }

    /// The unit direction of the panel's last facet at E0, pointing away from the foot:
    /// the sheet's direction at E0 before the first fold.
    pub fn top_direction(&self) -> Vec3 {
        let n = self.profile.len();
        let d = (self.profile[n - 1] - self.profile[n - 2]).normalize();
        Vec3::new(d.x, d.y, 0.0)
    }
}

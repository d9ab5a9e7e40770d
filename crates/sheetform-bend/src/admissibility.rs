//! The admissibility test (Bo & Wang 2007, Eq. 6 and §4.3).

use crate::{ruling_extent::RulingExtent, InadmissibleDetail, RulingSample};
use sheetform_geometry::{refused_number, segment_intersection, short_number};

/// Admissibility of one curved region.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct RegionAdmissibility {
    /// No regression point on the sheet and no crossing rulings.
    pub admissible: bool,
    /// Smallest distance (model unit) by which the curve of regression stays off the
    /// sheet over all rulings; negative where it enters. `None` if every `l(s)` is
    /// infinite (all rulings parallel).
    pub regression_margin: Option<f64>,
    /// Where it first fails.
    pub failure: Option<InadmissibleDetail>,
}

/// Tests Eq. 6, `l(s) ≥ l0(s)` or `l(s) ≤ l1(s)`, on every sampled ruling (the curve of
/// regression must not lie on the ruling's extent across the sheet), and that no two
/// neighbouring sampled rulings cross on the sheet (the discrete form of the same
/// condition, which also catches crossings near straight spans). A regression point on
/// the boundary itself is allowed (`tolerance` in model units).
pub fn check_region(
    region: usize,
    samples: &[RulingSample],
    extents: &[RulingExtent],
    tolerance: f64,
) -> RegionAdmissibility {
    let mut margin: Option<f64> = None;
    let mut bad: Option<(usize, usize)> = None;
    for (j, (s, e)) in samples.iter().zip(extents).enumerate() {
        let l = s.regression_distance;
        if !l.is_finite() {
            continue;
        }
        let m = if l >= e.positive_end {
            l - e.positive_end
        } else if l <= e.negative_end {
            e.negative_end - l
        } else {
            -(l - e.negative_end).min(e.positive_end - l)
        };
        margin = Some(margin.map_or(m, |x: f64| x.min(m)));
        if m < -tolerance {
            bad = Some(match bad {
                None => (j, j),
                Some((a, _)) => (a, j),
            });
        }
    }
    if let Some((a, b)) = bad {
        let s = &samples[a];
        let l = s.regression_distance;
        let flat = s.flat_point + s.flat_ruling * l;
        let point = s.point + s.ruling * l;
        return RegionAdmissibility {
            admissible: false,
            regression_margin: margin,
            failure: Some(InadmissibleDetail {
                // In the user's terms (the paper's test is Eq. 6, see the module doc).
                message: format!(
                    "region {region}: the sheet would fold onto itself there: its rulings meet (the curve of \
                     regression) {} from the curve, inside the sheet, where the curve is between {} and {} from its \
                     start, first near flat ({}, {}); bend the curve less there, or cut the sheet back before that \
                     point",
                    short_number(l.abs()),
                    refused_number(s.arc_length, &[samples[b].arc_length]),
                    refused_number(samples[b].arc_length, &[s.arc_length]),
                    short_number(flat.x),
                    short_number(flat.y)
                ),
                region,
                arc_length_range: [s.arc_length, samples[b].arc_length],
                flat_point: [flat.x, flat.y],
                point: Some([point.x, point.y, point.z]),
            }),
        };
    }
    for j in 0..samples.len().saturating_sub(1) {
        let seg = |k: usize| {
            let (s, e) = (&samples[k], &extents[k]);
            (
                s.flat_point + s.flat_ruling * e.negative_end,
                s.flat_point + s.flat_ruling * e.positive_end,
            )
        };
        let (a0, a1) = seg(j);
        let (b0, b1) = seg(j + 1);
        if let Some((t, _)) = segment_intersection(a0, a1, b0, b1) {
            let p = a0 + (a1 - a0) * t;
            let near_end = [a0, a1, b0, b1].iter().any(|q| (q - p).norm() <= tolerance);
            if !near_end {
                return RegionAdmissibility {
                    admissible: false,
                    regression_margin: margin,
                    failure: Some(InadmissibleDetail {
                        message: format!(
                            "region {region}: the rulings at s = {} and s = {} cross on the sheet at flat ({}, {})",
                            refused_number(samples[j].arc_length, &[samples[j + 1].arc_length]),
                            refused_number(samples[j + 1].arc_length, &[samples[j].arc_length]),
                            short_number(p.x),
                            short_number(p.y)
                        ),
                        region,
                        arc_length_range: [samples[j].arc_length, samples[j + 1].arc_length],
                        flat_point: [p.x, p.y],
                        point: None,
                    }),
                };
            }
        }
    }
    RegionAdmissibility {
        admissible: true,
        regression_margin: margin,
        failure: None,
    }
}

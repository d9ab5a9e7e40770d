//! The curve of regression of a rectifying developable (Bo & Wang 2007, §3.2).

/// Signed distance `l(s)` from the geodesic point to the curve of regression along the
/// ruling (Bo & Wang 2007, Eq. 4):
///
/// `l(s) = sin α(s) / α'(s)`,
///
/// where `α` is the angle from the tangent to the ruling (preserved by the isometry to the
/// flat sheet) and `α' = dα/ds`. Positive values lie on the ruling's positive side (the
/// flat sheet's left of the geodesic). Returns `±∞` where `α' = 0` (the neighbouring
/// rulings are parallel, as on a cylinder).
///
/// `α'` is computed exactly from curvature and torsion and their arc-length derivatives:
/// with the signed normal curvature `k` and torsion `τ`, `α = atan2(|k|, −sign(k) τ)`, so
/// `α' = (k τ' − k' τ) / (k² + τ²)`.
///
/// Units: lengths in the model unit, `k, τ` in 1/length, `k', τ'` in 1/length².
pub fn regression_distance(k: f64, tau: f64, dk: f64, dtau: f64, sin_alpha: f64) -> f64 {
    let w2 = k * k + tau * tau;
    if w2 == 0.0 {
        return f64::INFINITY;
    }
    let dalpha = (k * dtau - dk * tau) / w2;
    if dalpha == 0.0 {
        return f64::INFINITY;
    }
    let l = sin_alpha / dalpha;
    if l.is_finite() {
        l
    } else {
        f64::INFINITY.copysign(l)
    }
}

/// The stretches of a region's curve of regression that come near its sheet, as
/// polylines in the region's curve coordinates (the caller places them with the region's
/// rigid motion): the points `p(s) + l(s) r(s)` (Bo & Wang 2007, Eq. 4; `p` the geodesic
/// point, `r` the unit 3D ruling, `l` [`regression_distance`]) of the samples whose `l`
/// lies within `reach` times the ruling's extent beyond either end of it on the sheet
/// (`reach` = 0: only where it lies on the sheet, which makes the shape inadmissible).
/// A stretch ends where a sample is farther, where `l` is infinite (parallel rulings),
/// or where `l` changes sign far from the geodesic (more than half a ruling's extent
/// on both sides: the curve of regression passes through infinity); a sign change near
/// the geodesic is the curve crossing the sheet, kept whole.
///
/// Units: the model unit, as the samples.
pub fn curve_of_regression_near_sheet(
    samples: &[crate::RulingSample],
    extents: &[crate::RulingExtent],
    reach: f64,
) -> Vec<Vec<sheetform_geometry::Vec3>> {
    let mut stretches = Vec::new();
    let mut current: Vec<sheetform_geometry::Vec3> = Vec::new();
    // The last kept sample's `l` (`NaN`: none).
    let mut last = f64::NAN;
    for (sample, extent) in samples.iter().zip(extents) {
        let l = sample.regression_distance;
        let width = extent.positive_end - extent.negative_end;
        let margin = reach * width;
        let near = l.is_finite() && l >= extent.negative_end - margin && l <= extent.positive_end + margin;
        let through_infinity = last.signum() != l.signum() && last.abs().min(l.abs()) > 0.5 * width;
        if !near || through_infinity {
            if current.len() >= 2 {
                stretches.push(std::mem::take(&mut current));
            }
            current.clear();
        }
        if near {
            current.push(sample.point + l * sample.ruling);
            last = l;
        } else {
            last = f64::NAN;
        }
    }
    if current.len() >= 2 {
        stretches.push(current);
    }
    stretches
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The stretches near the sheet: real samples of the bundled bent rectangle with
    /// their `l` set by hand — on the sheet, within reach, far, infinite, a sign change.
    #[test]
    fn the_curve_of_regression_is_kept_where_it_comes_near_the_sheet() {
        let text = std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../examples/bent-rectangle.json"
        ))
        .unwrap();
        let model = crate::BendModel::from_scene(&crate::BendScene::from_json(&text).unwrap()).unwrap();
        let geometry = crate::region_geometry(&model, 0).unwrap();
        let (mut samples, extents) = (geometry.samples.clone(), geometry.extents.clone());
        assert!(samples.len() >= 12);
        let width = |j: usize| extents[j].positive_end - extents[j].negative_end;
        for (j, sample) in samples.iter_mut().enumerate() {
            sample.regression_distance = match j {
                // On the sheet's positive half, then just beyond its positive end.
                0..=2 => 0.5 * extents[j].positive_end,
                3..=4 => extents[j].positive_end + 0.5 * width(j),
                // Far away, then parallel rulings.
                5 => extents[j].positive_end + 10.0 * width(j),
                6 => f64::INFINITY,
                // Near the negative end, then across to the positive side (through infinity).
                7..=8 => extents[j].negative_end - 0.2 * width(j),
                9..=10 => extents[j].positive_end + 0.2 * width(j),
                // Far, then across the geodesic (through zero): one stretch.
                11 => f64::INFINITY,
                12 => -0.05 * width(j),
                13 => 0.05 * width(j),
                _ => f64::NEG_INFINITY,
            };
        }
        assert!(samples.len() >= 15);
        let stretches = curve_of_regression_near_sheet(&samples, &extents, 1.0);
        assert_eq!(stretches.iter().map(Vec::len).collect::<Vec<_>>(), [5, 2, 2, 2]);
        let expected = |j: usize| samples[j].point + samples[j].regression_distance * samples[j].ruling;
        for (got, j) in stretches[0].iter().zip(0..5) {
            assert!((got - expected(j)).norm() <= 1e-12);
        }
        assert!((stretches[1][0] - expected(7)).norm() <= 1e-12);
        assert!((stretches[2][1] - expected(10)).norm() <= 1e-12);
        // Nothing within reach 0 but the points on the sheet.
        let on_sheet = curve_of_regression_near_sheet(&samples, &extents, 0.0);
        assert_eq!(on_sheet.iter().map(Vec::len).collect::<Vec<_>>(), [3, 2]);
    }

    #[test]
    fn cylinder_has_no_regression_point() {
        // Planar curve: τ = 0, α = π/2 everywhere, α' = 0.
        assert!(regression_distance(0.5, 0.0, 0.1, 0.0, 1.0).is_infinite());
    }

    #[test]
    fn sign_follows_alpha_derivative() {
        let l = regression_distance(1.0, 0.5, 0.0, 0.2, 0.8);
        assert!((l - 0.8 / (0.2 / 1.25)).abs() < 1e-12);
    }
}

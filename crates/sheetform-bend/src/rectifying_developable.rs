//! Sampling the rectifying developable of a control curve (Bo & Wang 2007, §3.1, §3.3).

use crate::{curve_of_regression::regression_distance, BendError, ControlCurve, TessellationOptions};
use sheetform_geometry::{curve_frame, Vec2, Vec3};

/// The rectifying developable at one ruling.
///
/// Frame conventions: `T` is the unit tangent, `n` the unit surface normal (`±N`, the
/// sign kept continuous along the curve and chosen at the start from the region's `up`),
/// `b = n × T` the in-surface side direction. The flat sheet has the geodesic along `e`
/// and `n̄ = rot90(e)`; the isometry maps `e ↦ T`, `n̄ ↦ b`, flat `+z ↦ n`.
///
/// In that frame the frame's angular velocity per unit arc length is `w = (τ, −k, 0)`
/// with the signed normal curvature `k = σκ` (`n = σN`). The ruling is the line along `w`
/// (the Darboux vector `τT + κB`, Eq. 1 / §3.1), so the ruling makes the angle
/// `α = atan2(|k|, −sign(k) τ) ∈ (0, π)` with the tangent, measured towards `b`; the same
/// angle on the flat sheet gives the flat ruling `cos α e + sin α n̄` (§3.3 step 2). The
/// strips on either side of a ruling turn about it at the rate
/// `ρ = w · r̄ = τ cos α − k sin α = −sign(k) √(k² + τ²)` (radians per unit length).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RulingSample {
    /// Arc length `s` along the control curve.
    pub arc_length: f64,
    /// Curve parameter `u` at `s`.
    pub parameter: f64,
    /// `p(s)`.
    pub point: Vec3,
    /// Unit tangent `T`.
    pub tangent: Vec3,
    /// Unit side direction `b = n × T` (image of the flat `n̄`).
    pub side: Vec3,
    /// Unit surface normal `n`.
    pub normal: Vec3,
    /// Angle `α ∈ (0, π)` from the tangent to the ruling.
    pub angle: f64,
    /// Fold rate `ρ` (radians per unit length).
    pub fold_rate: f64,
    /// Signed normal curvature `k`.
    pub curvature: f64,
    /// Torsion `τ`.
    pub torsion: f64,
    /// Signed distance `l(s)` to the curve of regression along the ruling (Eq. 4).
    pub regression_distance: f64,
    /// The geodesic point on the flat sheet, `p̄(s)`.
    pub flat_point: Vec2,
    /// Unit flat ruling direction `r̄(s)`.
    pub flat_ruling: Vec2,
    /// Unit 3D ruling direction `r(s) = cos α T + sin α b`.
    pub ruling: Vec3,
    /// The curve is straight here (κ = 0): the sheet is planar and `α` is carried over
    /// from the nearest curved sample.
    pub straight: bool,
}

/// Curvature below this multiple of `1/L` counts as zero (straight span).
const STRAIGHT_CURVATURE: f64 = 1e-9;

/// Samples the rectifying developable of `curve` at rulings spaced so that the fold angle
/// between neighbouring strips stays below `options.max_fold_angle_degrees` (rulings are
/// equidistributed in `∫ (|w| + Φ/L) ds`, `Φ = ∫|w| ds` the total turning), from `s = 0`
/// to `s = L` inclusive.
///
/// `flat_start`, `flat_direction` (unit) place the flat geodesic; `up` picks the sheet's
/// top side at the start.
///
/// # Errors
/// A cusp (zero speed), a curve straight everywhere, or a straight span joining two bends
/// whose surface normals differ (a planar span cannot join them).
pub fn sample_rulings(
    region: usize,
    name: &str,
    curve: &ControlCurve,
    flat_start: Vec2,
    flat_direction: Vec2,
    up: Vec3,
    options: &TessellationOptions,
) -> Result<Vec<RulingSample>, BendError> {
    let length = curve.length();
    let (u0, u1) = curve.domain();
    let degenerate = |reason: String| BendError::DegenerateCurve {
        region,
        name: name.to_string(),
        reason,
    };

    // 1. Pre-grid: total turning and a monitor for the ruling spacing. The monitor only
    //    sets the spacing (arc lengths of the rulings are integrated exactly below), so a
    //    coarse grid with trapezoid speeds suffices: 16 points per polynomial span, at
    //    least 64.
    let spans = curve.shape().breakpoints().len().max(2) - 1;
    let grid = (16 * spans).max(64);
    let mut grid_u = Vec::with_capacity(grid + 1);
    let mut grid_s = Vec::with_capacity(grid + 1);
    let mut grid_w = Vec::with_capacity(grid + 1);
    let mut grid_speed = Vec::with_capacity(grid + 1);
    for i in 0..=grid {
        let u = u0 + (u1 - u0) * i as f64 / grid as f64;
        let d = curve.derivatives4(u);
        let f = curve_frame(&d)
            .ok_or_else(|| degenerate(format!("the curve has zero speed (a cusp) at parameter {u:.6}")))?;
        let s = if i == 0 {
            0.0
        } else {
            grid_s[i - 1] + 0.5 * (f.speed + grid_speed[i - 1]) * (u - grid_u[i - 1])
        };
        grid_u.push(u);
        grid_s.push(s);
        grid_speed.push(f.speed);
        grid_w.push(f.darboux().norm());
    }
    let length_estimate = grid_s[grid];
    let mut turning = vec![0.0; grid + 1];
    for i in 1..=grid {
        turning[i] = turning[i - 1] + 0.5 * (grid_w[i] + grid_w[i - 1]) * (grid_s[i] - grid_s[i - 1]);
    }
    let total_turning = turning[grid];
    let max_fold = options.max_fold_angle_degrees.to_radians().max(1e-9);
    let count = match options.rulings {
        Some(n) => n.max(2),
        None => {
            let needed = (2.0 * total_turning / max_fold).ceil();
            let needed = if needed.is_finite() {
                needed as usize
            } else {
                options.max_rulings
            };
            needed.max(options.min_rulings).min(options.max_rulings).max(2)
        }
    };
    let intervals = count - 1;
    let uniform_weight = if total_turning > 0.0 {
        total_turning / length_estimate
    } else {
        1.0
    };
    let monitor: Vec<f64> = (0..=grid).map(|i| turning[i] + uniform_weight * grid_s[i]).collect();
    let monitor_total = monitor[grid];

    // 2. Ruling parameters: equidistribute the monitor, then exact arc lengths.
    let mut params = Vec::with_capacity(count);
    let mut cursor = 0usize;
    for j in 0..count {
        if j == 0 {
            params.push(u0);
            continue;
        }
        if j == intervals {
            params.push(u1);
            continue;
        }
        let target = monitor_total * j as f64 / intervals as f64;
        while cursor + 1 < grid && monitor[cursor + 1] < target {
            cursor += 1;
        }
        let (m0, m1) = (monitor[cursor], monitor[cursor + 1]);
        let f = if m1 > m0 { (target - m0) / (m1 - m0) } else { 0.0 };
        params.push(grid_u[cursor] + f * (grid_u[cursor + 1] - grid_u[cursor]));
    }
    let mut lengths = Vec::with_capacity(count);
    let mut s = 0.0;
    for j in 0..count {
        if j > 0 {
            s += sheetform_geometry::gauss_legendre_length(curve.shape(), params[j - 1], params[j]);
        }
        lengths.push(s);
    }
    // Pin the last ruling to the exact total length.
    if let Some(last) = lengths.last_mut() {
        *last = length;
    }

    // 3. Frames with a continuous surface normal.
    let flat_side = Vec2::new(-flat_direction.y, flat_direction.x);
    let straight_limit = STRAIGHT_CURVATURE / length;
    let mut samples = Vec::with_capacity(count);
    let mut prev_normal: Option<Vec3> = None;
    let mut straight_from: Option<f64> = None;
    for j in 0..count {
        let u = params[j];
        let d = curve.derivatives4(u);
        let f = curve_frame(&d)
            .ok_or_else(|| degenerate(format!("the curve has zero speed (a cusp) at s = {:.6}", lengths[j])))?;
        let straight = f.curvature <= straight_limit || f.normal.is_none();
        let (normal, sigma) = if straight {
            match prev_normal {
                Some(n) => {
                    let n = n - f.tangent * n.dot(&f.tangent);
                    (n.normalize(), 1.0)
                }
                None => (Vec3::zeros(), 1.0),
            }
        } else {
            let big_n = f.normal.expect("curved sample has a normal");
            let sigma = match prev_normal {
                Some(prev) => {
                    if let Some(from) = straight_from {
                        // A planar span must join two bends with the same tangent plane.
                        let c = big_n.dot(&prev).abs();
                        if c < 1.0 - 1e-6 {
                            return Err(degenerate(format!(
                                "the curve is straight for s in [{from:.6}, {:.6}] and the bends on either side have \
                                 surface normals {:.3} degrees apart: a planar span cannot join them",
                                lengths[j],
                                c.clamp(-1.0, 1.0).acos().to_degrees()
                            )));
                        }
                    }
                    if big_n.dot(&prev) >= 0.0 {
                        1.0
                    } else {
                        -1.0
                    }
                }
                None => {
                    let c = big_n.dot(&up);
                    if c.abs() > 1e-9 && c < 0.0 {
                        -1.0
                    } else {
                        1.0
                    }
                }
            };
            (big_n * sigma, sigma)
        };
        if straight {
            straight_from.get_or_insert(lengths[j]);
        } else {
            straight_from = None;
        }
        if normal != Vec3::zeros() {
            prev_normal = Some(normal);
        }
        let k = sigma * f.curvature;
        let tau = if straight { 0.0 } else { f.torsion };
        samples.push((f, normal, k, tau, sigma, straight, d[0]));
    }
    let first_curved = samples
        .iter()
        .position(|x| !x.5)
        .ok_or_else(|| degenerate(format!(
            "the control curve is straight everywhere (s in [0, {length:.6}]): a straight line lies on every plane through it, so it does not determine a developable"
        )))?;
    // Leading straight samples take the first curved sample's normal.
    let lead_normal = samples[first_curved].1;
    for x in samples.iter_mut().take(first_curved) {
        let t = x.0.tangent;
        x.1 = (lead_normal - t * lead_normal.dot(&t)).normalize();
    }

    // 4. Angles, fold rates, regression distances; α carried over on straight spans.
    let mut out: Vec<RulingSample> = Vec::with_capacity(count);
    for (j, (f, normal, k, tau, sigma, straight, point)) in samples.iter().copied().enumerate() {
        let side = normal.cross(&f.tangent);
        let (angle, fold_rate, regression) = if straight {
            (f64::NAN, 0.0, f64::INFINITY)
        } else {
            let angle = k.abs().atan2(-k.signum() * tau);
            let rate = tau * angle.cos() - k * angle.sin();
            let l = regression_distance(
                k,
                tau,
                sigma * f.derivatives.curvature,
                f.derivatives.torsion,
                angle.sin(),
            );
            (angle, rate, l)
        };
        out.push(RulingSample {
            arc_length: lengths[j],
            parameter: params[j],
            point,
            tangent: f.tangent,
            side,
            normal,
            angle,
            fold_rate,
            curvature: k,
            torsion: tau,
            regression_distance: regression,
            flat_point: flat_start + flat_direction * lengths[j],
            flat_ruling: Vec2::zeros(),
            ruling: Vec3::zeros(),
            straight,
        });
    }
    // Fill α on straight spans from the nearest curved sample (by arc length).
    let curved: Vec<usize> = (0..out.len()).filter(|&j| !out[j].straight).collect();
    for j in 0..out.len() {
        if out[j].straight {
            let nearest = curved
                .iter()
                .min_by(|&&a, &&b| {
                    (out[a].arc_length - out[j].arc_length)
                        .abs()
                        .total_cmp(&(out[b].arc_length - out[j].arc_length).abs())
                })
                .copied()
                .expect("at least one curved sample");
            out[j].angle = out[nearest].angle;
        }
        let (c, s) = (out[j].angle.cos(), out[j].angle.sin());
        out[j].flat_ruling = flat_direction * c + flat_side * s;
        out[j].ruling = out[j].tangent * c + out[j].side * s;
    }
    Ok(out)
}

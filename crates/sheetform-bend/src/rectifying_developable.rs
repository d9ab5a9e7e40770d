//! Sampling the rectifying developable of a control curve (Bo & Wang 2007, §3.1, §3.3).

use crate::{curve_of_regression::regression_distance, BendError, ControlCurve, FlatPath, TessellationOptions};
use rayon::prelude::*;
use sheetform_geometry::{curve_frame, numbers_apart, short_number, Vec2, Vec3};

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
    /// Unit tangent `ē(s)` of the flat path there.
    pub flat_tangent: Vec2,
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

/// From this many rulings on, per-ruling work runs on all cores (measured: below about
/// 4 000 rulings the thread hand-off costs more than it saves on 2 cores).
pub(crate) const PARALLEL_RULINGS: usize = 4096;

/// Samples the rectifying developable of `curve` at rulings spaced so that the fold angle
/// between neighbouring strips stays below `options.max_fold_angle_degrees` (rulings are
/// equidistributed in `∫ (|w| + Φ/L) ds`, `Φ = ∫|w| ds` the total turning), from `s = 0`
/// to `s = L` inclusive.
///
/// `flat` is the curve's image on the flat sheet (a straight segment for a geodesic,
/// §3; any planar curve for a non-geodesic control curve, §5); `up` picks the sheet's top
/// side at the start.
///
/// Non-geodesic control curves (§5): the curvature vector splits as
/// `p'' = κ_g b + κ_n n` with `κ_g` the flat curve's signed curvature, so the surface
/// normal is `n = cos ψ N + sin ψ B` with `sin ψ = κ_g / κ` (needs `|κ_g| < κ`), the
/// normal curvature is `κ_n = κ cos ψ` and the geodesic torsion `τ_g = τ + ψ'`. The frame
/// `(T, b, n)` turns at `(τ_g, −κ_n, κ_g)`; the flat frame carries the `κ_g` part, so the
/// ruling is the line along `(τ_g, −κ_n)` and everything below holds with `k = κ_n`,
/// `τ = τ_g` (for a geodesic `κ_g = 0`, `ψ = 0`). For those curves the curve of
/// regression is taken from neighbouring rulings (the discrete form of Eq. 2), since its
/// exact form needs a fifth derivative.
///
/// # Errors
/// A cusp (zero speed), a curve straight everywhere, a straight span joining two bends
/// whose surface normals differ (a planar span cannot join them), or (§5) a control
/// curve whose curvature is not larger than its flat curve's.
pub fn sample_rulings(
    region: usize,
    name: &str,
    curve: &ControlCurve,
    flat: &FlatPath,
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
        let f = curve_frame(&d).ok_or_else(|| {
            degenerate(format!(
                "the curve has zero speed (a cusp) at parameter {}",
                short_number(u)
            ))
        })?;
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
    // Derivatives at every ruling (used for the frames below), then exact arc lengths:
    // 4-point Gauss–Lobatto per interval (exact for degree 5; reuses the end speeds, two
    // new evaluations), checked against the table's total; 8-point Gauss–Legendre where
    // that check fails (coarse sampling of a wiggly curve).
    let derivatives: Vec<[Vec3; 5]> = if count >= PARALLEL_RULINGS {
        params.par_iter().map(|&u| curve.derivatives4(u)).collect()
    } else {
        params.iter().map(|&u| curve.derivatives4(u)).collect()
    };
    let speed = |u: f64| {
        let mut d = [Vec3::zeros(); 2];
        sheetform_geometry::ParametricCurve::derivatives_into(curve.shape(), u, &mut d);
        d[1].norm()
    };
    const LOBATTO_X: f64 = 0.447_213_595_499_957_9; // 1/√5
    let lobatto = |j: usize| {
        let (a, b) = (params[j - 1], params[j]);
        let (m, h) = (0.5 * (a + b), 0.5 * (b - a));
        let ends = derivatives[j - 1][1].norm() + derivatives[j][1].norm();
        h * (ends / 6.0 + 5.0 / 6.0 * (speed(m - h * LOBATTO_X) + speed(m + h * LOBATTO_X)))
    };
    let pieces: Vec<f64> = if count >= PARALLEL_RULINGS {
        (1..count).into_par_iter().map(lobatto).collect()
    } else {
        (1..count).map(lobatto).collect()
    };
    let mut lengths = Vec::with_capacity(count);
    let mut s = 0.0;
    lengths.push(0.0);
    for piece in pieces {
        s += piece;
        lengths.push(s);
    }
    if (s - length).abs() > 1e-13 * length {
        s = 0.0;
        for (j, l) in lengths.iter_mut().enumerate() {
            if j > 0 {
                s += sheetform_geometry::gauss_legendre_length(curve.shape(), params[j - 1], params[j]);
            }
            *l = s;
        }
    }
    // Pin the last ruling to the exact total length.
    if let Some(last) = lengths.last_mut() {
        *last = length;
    }

    // 3. Frames with a continuous surface normal.
    let straight_limit = STRAIGHT_CURVATURE / length;
    let geodesic = flat.is_straight();
    struct Raw {
        frame: sheetform_geometry::CurveFrame,
        flat: crate::FlatFrame,
        normal: Vec3,
        k: f64,
        tau: f64,
        dk: f64,
        dtau: f64,
        straight: bool,
        point: Vec3,
    }
    let mut raw: Vec<Raw> = Vec::with_capacity(count);
    let mut prev_normal: Option<Vec3> = None;
    let mut straight_from: Option<f64> = None;
    let mut too_curved: Option<(f64, f64, f64, f64)> = None;
    for j in 0..count {
        let d = derivatives[j];
        let f = curve_frame(&d).ok_or_else(|| {
            degenerate(format!(
                "the curve has zero speed (a cusp) at s = {}",
                short_number(lengths[j])
            ))
        })?;
        let ff = flat.frame(lengths[j]);
        let straight = f.curvature <= straight_limit || f.normal.is_none();
        if straight {
            if ff.curvature.abs() > straight_limit {
                too_curved.get_or_insert((lengths[j], lengths[j], f.curvature, ff.curvature));
            }
            let normal = match prev_normal {
                Some(n) => (n - f.tangent * n.dot(&f.tangent)).normalize(),
                None => Vec3::zeros(),
            };
            straight_from.get_or_insert(lengths[j]);
            if normal != Vec3::zeros() {
                prev_normal = Some(normal);
            }
            raw.push(Raw {
                frame: f,
                flat: ff,
                normal,
                k: 0.0,
                tau: 0.0,
                dk: 0.0,
                dtau: 0.0,
                straight,
                point: d[0],
            });
            continue;
        }
        let (big_n, big_b) = (f.normal.expect("curved"), f.binormal.expect("curved"));
        let x = ff.curvature / f.curvature;
        if x.abs() >= 1.0 - 1e-9 {
            let entry = too_curved.get_or_insert((lengths[j], lengths[j], f.curvature, ff.curvature));
            entry.1 = lengths[j];
            continue;
        }
        let cos0 = (1.0 - x * x).sqrt();
        let candidates = [big_n * cos0 + big_b * x, -big_n * cos0 + big_b * x];
        let sigma = match prev_normal {
            Some(prev) => {
                if let Some(from) = straight_from {
                    // A planar span must join two bends with the same tangent plane: the
                    // bend after it turns the tangent and normal about the side direction
                    // b, so the span's normal must stay orthogonal to b.
                    let n_next = if candidates[0].dot(&prev) >= candidates[1].dot(&prev) {
                        candidates[0]
                    } else {
                        candidates[1]
                    };
                    let off = prev.dot(&n_next.cross(&f.tangent)).abs();
                    if off > 1e-6 {
                        return Err(degenerate(format!(
                            "the curve is straight for s in [{}, {}] and the bends on either side have \
                             tangent planes {:.3} degrees apart: a planar span cannot join them",
                            short_number(from),
                            short_number(lengths[j]),
                            off.clamp(-1.0, 1.0).asin().to_degrees()
                        )));
                    }
                }
                if candidates[0].dot(&prev) >= candidates[1].dot(&prev) {
                    1.0
                } else {
                    -1.0
                }
            }
            None => {
                let c = candidates[0].dot(&up) - candidates[1].dot(&up);
                if c.abs() > 1e-9 && c < 0.0 {
                    -1.0
                } else {
                    1.0
                }
            }
        };
        straight_from = None;
        let normal = if sigma > 0.0 { candidates[0] } else { candidates[1] };
        prev_normal = Some(normal);
        // κ_n = σ κ cos ψ0; τ_g = τ + ψ', ψ' = σ x' / cos ψ0, x' = (κ_g' κ − κ_g κ') / κ².
        let k = sigma * f.curvature * cos0;
        let dx = (ff.curvature_derivative * f.curvature - ff.curvature * f.derivatives.curvature)
            / (f.curvature * f.curvature);
        let tau = f.torsion + sigma * dx / cos0;
        // Exact derivatives for Eq. 4 on geodesics (ψ ≡ 0); §5 curves use Eq. 2 below.
        let (dk, dtau) = (sigma * f.derivatives.curvature, f.derivatives.torsion);
        raw.push(Raw {
            frame: f,
            flat: ff,
            normal,
            k,
            tau,
            dk,
            dtau,
            straight,
            point: d[0],
        });
    }
    if let Some((from, to, kappa, flat_kappa)) = too_curved {
        return Err(degenerate(format!(
            "for s in [{}, {}] the control curve's curvature ({}) is not larger than the flat curve's ({}): \
             the bent curve cannot keep that geodesic curvature (§5 needs |p''| > the flat curvature)",
            short_number(from),
            short_number(to),
            numbers_apart(kappa, flat_kappa.abs())[0],
            numbers_apart(kappa, flat_kappa.abs())[1]
        )));
    }
    let first_curved = raw.iter().position(|x| !x.straight).ok_or_else(|| {
        degenerate(format!(
            "the control curve is straight everywhere (s in [0, {}]): a straight line lies on every plane through it, so it does not determine a developable",
            short_number(length)
        ))
    })?;
    // Leading straight samples take the first curved sample's normal.
    let lead_normal = raw[first_curved].normal;
    for x in raw.iter_mut().take(first_curved) {
        let t = x.frame.tangent;
        x.normal = (lead_normal - t * lead_normal.dot(&t)).normalize();
    }

    // 4. Angles, fold rates, regression distances; α carried over on straight spans.
    let mut out: Vec<RulingSample> = Vec::with_capacity(count);
    // (cos α, sin α) per sample, kept beside α so the ruling directions need no sin_cos.
    let mut cos_sin: Vec<(f64, f64)> = Vec::with_capacity(count);
    for (j, r) in raw.iter().enumerate() {
        let side = r.normal.cross(&r.frame.tangent);
        let (angle, fold_rate, regression) = if r.straight {
            cos_sin.push((f64::NAN, f64::NAN));
            (f64::NAN, 0.0, f64::INFINITY)
        } else {
            // cos α = −sign(k) τ / |w|, sin α = |k| / |w|, ρ = −sign(k) |w| (no trigonometry).
            let w = r.k.hypot(r.tau);
            let (cos, sin) = (-r.k.signum() * r.tau / w, r.k.abs() / w);
            let angle = sin.atan2(cos);
            cos_sin.push((cos, sin));
            let rate = -r.k.signum() * w;
            let l = if geodesic {
                regression_distance(r.k, r.tau, r.dk, r.dtau, sin)
            } else {
                f64::INFINITY
            };
            (angle, rate, l)
        };
        out.push(RulingSample {
            arc_length: lengths[j],
            parameter: params[j],
            point: r.point,
            tangent: r.frame.tangent,
            side,
            normal: r.normal,
            angle,
            fold_rate,
            curvature: r.k,
            torsion: r.tau,
            regression_distance: regression,
            flat_point: r.flat.point,
            flat_tangent: r.flat.tangent,
            flat_ruling: Vec2::zeros(),
            ruling: Vec3::zeros(),
            straight: r.straight,
        });
    }
    // Fill α on straight spans from the nearest curved sample (by index, both ways).
    let mut last_curved: Option<usize> = None;
    let mut nearest_before = vec![None; out.len()];
    for (j, s) in out.iter().enumerate() {
        if !s.straight {
            last_curved = Some(j);
        }
        nearest_before[j] = last_curved;
    }
    let mut next_curved: Option<usize> = None;
    for j in (0..out.len()).rev() {
        if !out[j].straight {
            next_curved = Some(j);
            continue;
        }
        let pick = match (nearest_before[j], next_curved) {
            (Some(a), Some(b)) => {
                if out[j].arc_length - out[a].arc_length <= out[b].arc_length - out[j].arc_length {
                    a
                } else {
                    b
                }
            }
            (Some(a), None) => a,
            (None, Some(b)) => b,
            (None, None) => unreachable!("at least one curved sample"),
        };
        out[j].angle = out[pick].angle;
        cos_sin[j] = cos_sin[pick];
    }
    for ((s, r), &(c, sn)) in out.iter_mut().zip(&raw).zip(&cos_sin) {
        s.flat_ruling = r.flat.tangent * c + r.flat.normal * sn;
        s.ruling = s.tangent * c + s.side * sn;
    }
    if !geodesic {
        // Discrete Eq. 2: where neighbouring flat rulings meet.
        let n = out.len();
        for j in 0..n {
            let (a, b) = if j + 1 < n { (j, j + 1) } else { (j - 1, j) };
            let (pa, ra, pb, rb) = (
                out[a].flat_point,
                out[a].flat_ruling,
                out[b].flat_point,
                out[b].flat_ruling,
            );
            let cross = |u: Vec2, v: Vec2| u.x * v.y - u.y * v.x;
            let den = cross(ra, rb);
            let l_a = if den.abs() > 1e-15 {
                cross(pb - pa, rb) / den
            } else {
                f64::INFINITY
            };
            // Distance from this ruling's own geodesic point.
            let meet = pa + ra * l_a;
            out[j].regression_distance = if l_a.is_finite() {
                (meet - out[j].flat_point).dot(&out[j].flat_ruling)
            } else {
                f64::INFINITY
            };
        }
    }
    Ok(out)
}

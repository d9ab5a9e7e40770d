use crate::Vec3;

/// The Frenet frame of a space curve at one parameter, with curvature, torsion and the
/// Darboux vector, computed exactly from the derivatives `p', p'', p''', p''''` of an
/// arbitrary (not necessarily arc-length) parametrisation.
///
/// With `v = |p'|` and `c = p' × p''`:
/// - tangent `T = p'/v`; curvature `κ = |c| / v³` (1/length);
/// - principal normal `N = (c × p') / |c × p'|`, binormal `B = T × N` (undefined where
///   `κ = 0`: then `normal` and `binormal` are `None`);
/// - torsion `τ = (c · p''') / |c|²` (1/length);
/// - Darboux vector `ω = τ T + κ B` (Gray 1935; Bo & Wang 2007, §3.1: the ruling
///   direction of the rectifying developable), the angular velocity of the frame per unit
///   arc length.
///
/// [`CurveFrameDerivatives`] gives `dκ/ds` and `dτ/ds` (needs `p''''`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurveFrame {
    /// Unit tangent `T`.
    pub tangent: Vec3,
    /// Unit principal normal `N`, `None` where the curvature vanishes.
    pub normal: Option<Vec3>,
    /// Unit binormal `B = T × N`, `None` where the curvature vanishes.
    pub binormal: Option<Vec3>,
    /// Curvature κ ≥ 0 (1/length).
    pub curvature: f64,
    /// Torsion τ (1/length); 0 where the curvature vanishes.
    pub torsion: f64,
    /// Speed `|p'(u)|` of the parametrisation (length per parameter unit).
    pub speed: f64,
    /// Curvature vector `κ N = d²p/ds²` (zero at inflections; always defined).
    pub curvature_vector: Vec3,
    /// Arc-length derivatives of curvature and torsion.
    pub derivatives: CurveFrameDerivatives,
}

/// Arc-length derivatives of curvature and torsion.
///
/// With `c = p'×p''`, `c' = p'×p'''`, `v' = (p'·p'')/v`:
/// `dκ/du = (c·c')/(|c| v³) − 3 |c| v' / v⁴`,
/// `dτ/du = ((c'·p''' + c·p'''') |c|² − 2 (c·p''')(c·c')) / |c|⁴`
/// (and `c'·p''' = 0`), then `d/ds = (1/v) d/du`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CurveFrameDerivatives {
    /// `dκ/ds` (1/length²).
    pub curvature: f64,
    /// `dτ/ds` (1/length²).
    pub torsion: f64,
}

impl CurveFrame {
    /// The Darboux vector `ω = τ T + κ B` (zero vector where κ = 0 and τ is undefined).
    pub fn darboux(&self) -> Vec3 {
        match self.binormal {
            Some(b) => self.tangent * self.torsion + b * self.curvature,
            None => Vec3::zeros(),
        }
    }
}

/// Relative threshold under which `|p' × p''|` counts as zero (`p''` parallel to `p'`):
/// `|p'×p''| ≤ 1e-12 |p'| |p''|`.
pub const ZERO_CURVATURE_RELATIVE: f64 = 1e-12;

/// Frenet frame, curvature, torsion and their arc-length derivatives from
/// `d = [p, p', p'', p''', p'''']`.
///
/// Returns `None` if the speed `|p'|` is zero or not finite (a cusp of the
/// parametrisation: the frame does not exist).
pub fn curve_frame(d: &[Vec3; 5]) -> Option<CurveFrame> {
    let (d1, d2, d3, d4) = (d[1], d[2], d[3], d[4]);
    let speed = d1.norm();
    if !(speed.is_finite() && speed > 0.0) {
        return None;
    }
    let tangent = d1 / speed;
    let c = d1.cross(&d2);
    let cn = c.norm();
    let v3 = speed * speed * speed;
    let along = d2.dot(&tangent);
    let curvature_vector = (d2 - tangent * along) / (speed * speed);
    if cn <= ZERO_CURVATURE_RELATIVE * speed * d2.norm() || cn == 0.0 {
        return Some(CurveFrame {
            tangent,
            normal: None,
            binormal: None,
            curvature: 0.0,
            torsion: 0.0,
            speed,
            curvature_vector: Vec3::zeros(),
            derivatives: CurveFrameDerivatives::default(),
        });
    }
    let curvature = cn / v3;
    let normal = c.cross(&d1).normalize();
    let binormal = tangent.cross(&normal);
    let c_dot_d3 = c.dot(&d3);
    let torsion = c_dot_d3 / (cn * cn);
    let c1 = d1.cross(&d3);
    let dv = d1.dot(&d2) / speed;
    let dk_du = c.dot(&c1) / (cn * v3) - 3.0 * cn * dv / (v3 * speed);
    let dt_du = (c.dot(&d4) * cn * cn - 2.0 * c_dot_d3 * c.dot(&c1)) / (cn * cn * cn * cn);
    Some(CurveFrame {
        tangent,
        normal: Some(normal),
        binormal: Some(binormal),
        curvature,
        torsion,
        speed,
        curvature_vector,
        derivatives: CurveFrameDerivatives {
            curvature: dk_du / speed,
            torsion: dt_du / speed,
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Helix (r cos u, r sin u, h u): κ = r/(r²+h²), τ = h/(r²+h²).
    fn helix(u: f64, r: f64, h: f64) -> [Vec3; 5] {
        let (s, c) = u.sin_cos();
        [
            Vec3::new(r * c, r * s, h * u),
            Vec3::new(-r * s, r * c, h),
            Vec3::new(-r * c, -r * s, 0.0),
            Vec3::new(r * s, -r * c, 0.0),
            Vec3::new(r * c, r * s, 0.0),
        ]
    }

    #[test]
    fn helix_curvature_torsion_darboux() {
        let (r, h) = (2.0, 0.5);
        let f = curve_frame(&helix(0.7, r, h)).unwrap();
        let q = r * r + h * h;
        assert!((f.curvature - r / q).abs() < 1e-14);
        assert!((f.torsion - h / q).abs() < 1e-14);
        // The Darboux vector of a helix is parallel to its axis (z).
        let w = f.darboux();
        assert!(w.x.abs() < 1e-14 && w.y.abs() < 1e-14);
        assert!(f.derivatives.curvature.abs() < 1e-14 && f.derivatives.torsion.abs() < 1e-14);
    }

    #[test]
    fn straight_line_has_no_normal() {
        let d = [Vec3::zeros(), Vec3::x(), Vec3::x() * 3.0, Vec3::zeros(), Vec3::zeros()];
        let f = curve_frame(&d).unwrap();
        assert!(f.normal.is_none() && f.curvature == 0.0);
        assert!(curve_frame(&[Vec3::zeros(); 5]).is_none());
    }
}

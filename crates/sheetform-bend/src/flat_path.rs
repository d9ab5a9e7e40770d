//! The flat image of a control curve (Bo & Wang 2007, §3 for geodesics, §5 for
//! non-geodesic control curves), parametrised by arc length.

use sheetform_geometry::{ArcLengthTable, BSpline2, Bezier2, ParametricCurve, Vec2};

/// A planar curve on the flat sheet.
#[derive(Debug, Clone, PartialEq)]
pub enum FlatCurve {
    /// Bézier curve in the plane.
    Bezier(Bezier2),
    /// B-spline curve in the plane.
    BSpline(BSpline2),
}

impl ParametricCurve<2> for FlatCurve {
    fn domain(&self) -> (f64, f64) {
        match self {
            FlatCurve::Bezier(c) => c.domain(),
            FlatCurve::BSpline(c) => c.domain(),
        }
    }
    fn derivatives_into(&self, u: f64, out: &mut [nalgebra::SVector<f64, 2>]) {
        match self {
            FlatCurve::Bezier(c) => c.derivatives_into(u, out),
            FlatCurve::BSpline(c) => c.derivatives_into(u, out),
        }
    }
}

impl FlatCurve {
    fn breakpoints(&self) -> Vec<f64> {
        match self {
            FlatCurve::Bezier(_) => vec![],
            FlatCurve::BSpline(c) => c.breakpoints(),
        }
    }
}

/// Where the control curve lies on the flat sheet.
#[derive(Debug, Clone)]
pub enum FlatPath {
    /// A straight segment from `start` along the unit `direction`: the control curve is a
    /// geodesic of the bent sheet (§3). Its length is the control curve's.
    Straight {
        /// Start point.
        start: Vec2,
        /// Unit direction.
        direction: Vec2,
    },
    /// A circular arc from `start`, leaving along the unit `direction`, with signed
    /// curvature `curvature` (positive: turning left, counter-clockwise). Its length is the
    /// control curve's (§5).
    Arc {
        /// Start point.
        start: Vec2,
        /// Unit start direction.
        direction: Vec2,
        /// Signed curvature (1/length).
        curvature: f64,
    },
    /// Any planar curve (§5); its length must equal the control curve's.
    Curve {
        /// The curve.
        curve: FlatCurve,
        /// Its arc-length table.
        table: ArcLengthTable,
    },
}

/// The flat path at one arc length: point, unit tangent `ē`, left normal `n̄ = rot90(ē)`,
/// signed curvature `κ_g` (the geodesic curvature the bent curve must keep, §5) and
/// `dκ_g/ds`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlatFrame {
    /// Point on the flat sheet.
    pub point: Vec2,
    /// Unit tangent.
    pub tangent: Vec2,
    /// Left unit normal.
    pub normal: Vec2,
    /// Signed curvature (positive: turning left).
    pub curvature: f64,
    /// Arc-length derivative of the curvature.
    pub curvature_derivative: f64,
}

fn rot90(v: Vec2) -> Vec2 {
    Vec2::new(-v.y, v.x)
}

impl FlatPath {
    /// Builds a `Curve` path.
    ///
    /// # Errors
    /// Zero length.
    pub fn curve(curve: FlatCurve) -> Result<Self, sheetform_geometry::GeometryError> {
        let table = ArcLengthTable::new(&curve, &curve.breakpoints(), Default::default())?;
        Ok(FlatPath::Curve { curve, table })
    }

    /// Whether the path is straight (the control curve a geodesic).
    pub fn is_straight(&self) -> bool {
        matches!(self, FlatPath::Straight { .. })
    }

    /// The path's own length, if it has one (`Curve`); straight segments and arcs take
    /// the control curve's length.
    pub fn fixed_length(&self) -> Option<f64> {
        match self {
            FlatPath::Curve { table, .. } => Some(table.total_length()),
            _ => None,
        }
    }

    /// The frame at arc length `s`.
    pub fn frame(&self, s: f64) -> FlatFrame {
        match self {
            FlatPath::Straight { start, direction } => FlatFrame {
                point: start + direction * s,
                tangent: *direction,
                normal: rot90(*direction),
                curvature: 0.0,
                curvature_derivative: 0.0,
            },
            FlatPath::Arc {
                start,
                direction,
                curvature,
            } => {
                let k = *curvature;
                let theta = k * s;
                let (sn, cs) = theta.sin_cos();
                let t = Vec2::new(direction.x * cs - direction.y * sn, direction.x * sn + direction.y * cs);
                // ∫ tangent ds: (sin θ / k) e + ((1 − cos θ) / k) n̄, stable for small k.
                let (a, b) = if (k * s).abs() < 1e-4 {
                    let t2 = theta * theta;
                    (s * (1.0 - t2 / 6.0), s * theta * (0.5 - t2 / 24.0))
                } else {
                    (sn / k, (1.0 - cs) / k)
                };
                FlatFrame {
                    point: start + direction * a + rot90(*direction) * b,
                    tangent: t,
                    normal: rot90(t),
                    curvature: k,
                    curvature_derivative: 0.0,
                }
            }
            FlatPath::Curve { curve, table } => {
                let u = table.parameter_at(curve, s);
                let mut d = [Vec2::zeros(); 4];
                curve.derivatives_into(u, &mut d);
                let v = d[1].norm();
                let t = d[1] / v;
                let cross = |a: Vec2, b: Vec2| a.x * b.y - a.y * b.x;
                let c = cross(d[1], d[2]);
                let k = c / (v * v * v);
                let dk_du = cross(d[1], d[3]) / (v * v * v) - 3.0 * c * d[1].dot(&d[2]) / (v * v * v * v * v);
                FlatFrame {
                    point: d[0],
                    tangent: t,
                    normal: rot90(t),
                    curvature: k,
                    curvature_derivative: dk_du / v,
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arc_is_a_circle() {
        let p = FlatPath::Arc {
            start: Vec2::new(1.0, 2.0),
            direction: Vec2::x(),
            curvature: 0.5,
        };
        let centre = Vec2::new(1.0, 4.0);
        for i in 0..20 {
            let f = p.frame(i as f64 * 0.7);
            assert!(((f.point - centre).norm() - 2.0).abs() < 1e-12);
            assert!((f.point - centre).dot(&f.tangent).abs() < 1e-12);
            assert!((f.normal - (centre - f.point) / 2.0).norm() < 1e-12);
        }
        let g = FlatPath::Arc {
            start: Vec2::zeros(),
            direction: Vec2::x(),
            curvature: 1e-9,
        };
        assert!((g.frame(3.0).point - Vec2::new(3.0, 4.5e-9)).norm() < 1e-15);
    }

    #[test]
    fn bezier_path_curvature_and_derivative() {
        let c = Bezier2::new(vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(2.0, 1.0),
            Vec2::new(4.0, 0.0),
            Vec2::new(5.0, 3.0),
        ])
        .unwrap();
        let p = FlatPath::curve(FlatCurve::Bezier(c)).unwrap();
        let h = 1e-5;
        for s in [0.5, 1.7, 3.1] {
            let (a, b, m) = (p.frame(s - h), p.frame(s + h), p.frame(s));
            // κ = dθ/ds, dκ/ds by finite differences.
            let dtheta = (a.tangent.x * b.tangent.y - a.tangent.y * b.tangent.x).asin() / (2.0 * h);
            assert!((dtheta - m.curvature).abs() < 1e-6);
            assert!(((b.curvature - a.curvature) / (2.0 * h) - m.curvature_derivative).abs() < 1e-5);
        }
    }
}

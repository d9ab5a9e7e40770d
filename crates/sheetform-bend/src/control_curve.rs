use nalgebra::SVector;
use sheetform_geometry::{
    ArcLengthOptions, ArcLengthTable, BSpline3, Bezier3, GeometryError, Helix, ParametricCurve, Vec3,
};
use std::sync::Arc;

/// The 3D control curve of a curved region: a Bézier curve of any degree or a B-spline,
/// with its arc-length table (so that arc length ↔ parameter is exact to ~1e-14).
#[derive(Debug, Clone)]
pub struct ControlCurve {
    shape: CurveShape,
    table: ArcLengthTable,
}

/// An exact analytic curve supplied through the API (tests, generators).
pub type AnalyticCurve = Arc<dyn ParametricCurve<3> + Send + Sync>;

/// The form of a control curve.
#[derive(Clone)]
pub enum CurveShape {
    /// A Bézier curve on `[0, 1]`.
    Bezier(Bezier3),
    /// A B-spline (open or closed) on its knot domain.
    BSpline(BSpline3),
    /// An exact circular helix (or circle).
    Helix(Helix),
    /// Any other exact curve (no control points: cannot be edited).
    Analytic(AnalyticCurve),
}

impl std::fmt::Debug for CurveShape {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CurveShape::Bezier(c) => f.debug_tuple("Bezier").field(c).finish(),
            CurveShape::BSpline(c) => f.debug_tuple("BSpline").field(c).finish(),
            CurveShape::Helix(c) => f.debug_tuple("Helix").field(c).finish(),
            CurveShape::Analytic(_) => f.write_str("Analytic(..)"),
        }
    }
}

impl ParametricCurve<3> for CurveShape {
    fn domain(&self) -> (f64, f64) {
        match self {
            CurveShape::Bezier(c) => c.domain(),
            CurveShape::BSpline(c) => c.domain(),
            CurveShape::Helix(c) => c.domain(),
            CurveShape::Analytic(c) => c.domain(),
        }
    }
    fn derivatives_into(&self, u: f64, out: &mut [SVector<f64, 3>]) {
        match self {
            CurveShape::Bezier(c) => c.derivatives_into(u, out),
            CurveShape::BSpline(c) => c.derivatives_into(u, out),
            CurveShape::Helix(c) => c.derivatives_into(u, out),
            CurveShape::Analytic(c) => c.derivatives_into(u, out),
        }
    }
}

impl CurveShape {
    /// The control points (empty for analytic curves).
    pub fn control_points(&self) -> &[Vec3] {
        match self {
            CurveShape::Bezier(c) => c.control_points(),
            CurveShape::BSpline(c) => c.control_points(),
            CurveShape::Helix(_) | CurveShape::Analytic(_) => &[],
        }
    }

    /// The same kind of curve with other control points (same degree and knots).
    ///
    /// # Errors
    /// Invalid points (non-finite, wrong count for a B-spline).
    pub fn with_control_points(&self, points: Vec<Vec3>) -> Result<Self, GeometryError> {
        Ok(match self {
            CurveShape::Bezier(_) => CurveShape::Bezier(Bezier3::new(points)?),
            CurveShape::BSpline(c) => CurveShape::BSpline(c.with_control_points(points)?),
            CurveShape::Helix(_) | CurveShape::Analytic(_) => {
                return Err(GeometryError::DegenerateCurve {
                    reason: "an analytic curve has no control points to edit".into(),
                })
            }
        })
    }

    /// Parameters where the curve is only piecewise polynomial.
    pub fn breakpoints(&self) -> Vec<f64> {
        match self {
            CurveShape::BSpline(c) => c.breakpoints(),
            _ => vec![],
        }
    }
}

impl ControlCurve {
    /// Wraps a curve and tabulates its arc length.
    ///
    /// # Errors
    /// Zero length.
    pub fn new(shape: CurveShape) -> Result<Self, GeometryError> {
        let table = ArcLengthTable::new(&shape, &shape.breakpoints(), ArcLengthOptions::default())?;
        Ok(Self { shape, table })
    }

    /// The polynomial curve.
    pub fn shape(&self) -> &CurveShape {
        &self.shape
    }

    /// Total arc length `L`.
    pub fn length(&self) -> f64 {
        self.table.total_length()
    }

    /// The parameter at arc length `s`.
    pub fn parameter_at(&self, s: f64) -> f64 {
        self.table.parameter_at(&self.shape, s)
    }

    /// The arc length at parameter `u`.
    pub fn length_at(&self, u: f64) -> f64 {
        self.table.length_at(&self.shape, u)
    }

    /// Position and derivatives up to order 4 at parameter `u`.
    pub fn derivatives4(&self, u: f64) -> [Vec3; 5] {
        self.shape.derivatives4(u)
    }

    /// The parameter domain.
    pub fn domain(&self) -> (f64, f64) {
        self.shape.domain()
    }

    /// The point at arc length `s`.
    pub fn point_at_length(&self, s: f64) -> Vec3 {
        self.shape.point(self.parameter_at(s))
    }
}

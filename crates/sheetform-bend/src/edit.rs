//! Editing a bent sheet (Bo & Wang 2007, §4.1): move a control point, drag the end
//! handles (position + surface normal), drag with the curve's length preserved. Every
//! edit keeps the last admissible state when it would create a singularity.

use crate::{bend, BendError, BendModel, BentSheet, CurveShape};
use nalgebra::{DMatrix, DVector, Matrix3};
#[cfg(test)]
use sheetform_geometry::ParametricCurve;
use sheetform_geometry::{Bezier3, Vec3};
use sheetform_solve::{levenberg_marquardt, LeastSquaresProblem, LevenbergMarquardtOptions, SolverInfo};

/// What an edit did.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct EditInfo {
    /// The edit was applied; otherwise the previous (admissible) state is kept.
    pub applied: bool,
    /// Why it was not applied.
    pub rejected_because: Option<String>,
    /// The solver's report, for edits that solve.
    pub solver: Option<SolverInfo>,
    /// Length of the edited control curve before the edit.
    pub curve_length_before: f64,
    /// Its length after (equal to `before` when rejected).
    pub curve_length_after: f64,
}

/// An end handle: where the curve's end goes and the surface normal wanted there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EndHandle {
    /// New position of the end point (`None`: keep it).
    pub position: Option<Vec3>,
    /// Desired principal normal of the curve (= surface normal) at that end (`None`: no
    /// constraint). Need not be unit.
    pub normal: Option<Vec3>,
}

/// Knobs of the end-handle solve (§4.1.2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EndHandleOptions {
    /// Weight `λ` of the regulariser `λ |ΔX|²` that keeps the change gradual (the paper:
    /// 0.1). Relative to the squared size of the curve, so it does not depend on units.
    pub regularization: f64,
    /// Solver settings.
    pub solver: LevenbergMarquardtOptions,
}

impl Default for EndHandleOptions {
    fn default() -> Self {
        Self {
            regularization: 0.1,
            solver: LevenbergMarquardtOptions::default(),
        }
    }
}

/// How a length-preserving drag restores the length (§4.1.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LengthPreservation {
    /// The paper's method: cut (or extend) the edited Bézier curve exactly at the original
    /// arc length by de Casteljau subdivision, then translate it so the dragged control
    /// point stays where it was dropped. Bézier curves only.
    Trim,
    /// Scale the edited curve about the dragged control point by `L0 / L` (any curve; the
    /// paper's tube example, §5).
    Scale,
}

/// A bent sheet being edited: the model and its bent sheet, always admissible.
#[derive(Debug, Clone)]
pub struct BendEditor {
    model: BendModel,
    sheet: BentSheet,
}

impl BendEditor {
    /// Starts editing an admissible model.
    ///
    /// # Errors
    /// The model cannot be bent.
    pub fn new(model: BendModel) -> Result<Self, BendError> {
        let sheet = bend(&model)?;
        Ok(Self { model, sheet })
    }

    /// The current model.
    pub fn model(&self) -> &BendModel {
        &self.model
    }

    /// The current bent sheet.
    pub fn sheet(&self) -> &BentSheet {
        &self.sheet
    }

    fn control_points(&self, region: usize) -> Result<Vec<Vec3>, BendError> {
        let r = self.model.regions.get(region).ok_or_else(|| BendError::Edit {
            message: format!(
                "there is no region {region} (the model has {})",
                self.model.regions.len()
            ),
        })?;
        let pts = r.curve.shape().control_points().to_vec();
        if pts.is_empty() {
            return Err(BendError::Edit {
                message: format!("region {region}'s curve is analytic: it has no control points"),
            });
        }
        Ok(pts)
    }

    /// `region`'s curve with control point `index` moved to `position` (not yet applied).
    fn moved_shape(&self, region: usize, index: usize, position: Vec3) -> Result<CurveShape, BendError> {
        let mut pts = self.control_points(region)?;
        check_control_point_index(index, pts.len())?;
        check_edit_coordinates(position.as_slice())?;
        pts[index] = position;
        self.model.regions[region]
            .curve
            .shape()
            .with_control_points(pts)
            .map_err(|e| BendError::Edit { message: e.to_string() })
    }

    /// Tries a new curve for `region`: applied if the result is valid and admissible.
    fn try_curve(&mut self, region: usize, shape: CurveShape, solver: Option<SolverInfo>) -> EditInfo {
        let before = self.model.regions[region].curve.length();
        let attempt = self
            .model
            .with_curve(region, shape)
            .and_then(|m| bend(&m).map(|s| (m, s)));
        match attempt {
            Ok((model, sheet)) => {
                let after = model.regions[region].curve.length();
                self.model = model;
                self.sheet = sheet;
                EditInfo {
                    applied: true,
                    rejected_because: None,
                    solver,
                    curve_length_before: before,
                    curve_length_after: after,
                }
            }
            Err(e) => EditInfo {
                applied: false,
                rejected_because: Some(e.to_string()),
                solver,
                curve_length_before: before,
                curve_length_after: before,
            },
        }
    }

    /// Moves control point `index` of `region`'s curve to `position` (§4.1.1). The flat
    /// geodesic keeps its start and direction and takes the new curve length.
    ///
    /// # Errors
    /// No such region or control point, or an analytic curve. An edit that would make the
    /// shape inadmissible is not an error: it is reported in [`EditInfo`] and not applied.
    pub fn move_control_point(&mut self, region: usize, index: usize, position: Vec3) -> Result<EditInfo, BendError> {
        let shape = self.moved_shape(region, index, position)?;
        Ok(self.try_curve(region, shape, None))
    }

    /// Drags the end handles of a Bézier control curve (§4.1.2): the end points go where
    /// the handles say, and the interior control points `P_1 … P_{n−1}` move by the `ΔX`
    /// minimising
    ///
    /// `f(ΔX) = |N0/|N0| − N̄0|² + |N1/|N1| − N̄1|² + λ |ΔX|² / ℓ²`
    ///
    /// with `N0 = (P1−P0) × (P2−2P1+P0) × (P1−P0)` and `N1 = (Pn−Pn−1) × (Pn−2Pn−1+Pn−2) ×
    /// (Pn−Pn−1)` the principal normals at the ends (up to the positive factor `n³(n−1)`),
    /// `N̄` the wanted unit normals, and `ℓ` the curve's control-polygon length (the paper's
    /// `λ|ΔX|²` made unit-free). Solved by Levenberg–Marquardt with the exact Jacobian,
    /// from the current state.
    ///
    /// # Errors
    /// Not a Bézier curve of degree ≥ 3 (degree 2 has no free interior points to solve
    /// for both normals), bad handles.
    pub fn drag_end_handles(
        &mut self,
        region: usize,
        start: EndHandle,
        end: EndHandle,
        options: &EndHandleOptions,
    ) -> Result<EditInfo, BendError> {
        let mut pts = self.control_points(region)?;
        if !matches!(self.model.regions[region].curve.shape(), CurveShape::Bezier(_)) {
            return Err(BendError::Edit {
                message: "end handles need a Bézier control curve (§4.1.2)".into(),
            });
        }
        let n = pts.len() - 1;
        if n < 3 {
            return Err(BendError::Edit {
                message: format!("end handles need degree ≥ 3, the curve has degree {n}"),
            });
        }
        for h in [start, end] {
            if let Some(p) = h.position {
                check_edit_coordinates(p.as_slice())?;
            }
            if let Some(v) = h.normal {
                check_edit_coordinates(v.as_slice())?;
                if v.norm() == 0.0 {
                    return Err(BendError::Edit {
                        message: "a normal handle is the zero vector".into(),
                    });
                }
            }
        }
        if let Some(p) = start.position {
            pts[0] = p;
        }
        if let Some(p) = end.position {
            pts[n] = p;
        }
        let (solved, info) = solve_end_normals(&pts, start.normal, end.normal, options);
        let shape = CurveShape::Bezier(Bezier3::new(solved).map_err(|e| BendError::Edit { message: e.to_string() })?);
        Ok(self.try_curve(region, shape, Some(info)))
    }

    /// Moves control point `index` to `position` and restores the curve's original length
    /// (§4.1.3), exactly: to 1e-12 relative with [`LengthPreservation::Trim`], to rounding
    /// with [`LengthPreservation::Scale`]. The dragged control point ends where it was
    /// dropped.
    ///
    /// # Errors
    /// As [`BendEditor::move_control_point`]; `Trim` on a non-Bézier curve.
    pub fn drag_preserving_length(
        &mut self,
        region: usize,
        index: usize,
        position: Vec3,
        method: LengthPreservation,
    ) -> Result<EditInfo, BendError> {
        let target = self.model.regions[region].curve.length();
        let shape = self.moved_shape(region, index, position)?;
        let (fixed, info) = match method {
            LengthPreservation::Scale => {
                let length = crate::ControlCurve::new(shape.clone())
                    .map_err(|e| BendError::Edit { message: e.to_string() })?
                    .length();
                let f = target / length;
                let pts: Vec<Vec3> = shape
                    .control_points()
                    .iter()
                    .map(|p| position + (p - position) * f)
                    .collect();
                (
                    shape
                        .with_control_points(pts)
                        .map_err(|e| BendError::Edit { message: e.to_string() })?,
                    None,
                )
            }
            LengthPreservation::Trim => {
                let CurveShape::Bezier(curve) = &shape else {
                    return Err(BendError::Edit {
                        message: "trimming to length needs a Bézier control curve; use LengthPreservation::Scale"
                            .into(),
                    });
                };
                let (trimmed, info) = trim_to_length(curve, target);
                let moved = trimmed.control_points()[index];
                (CurveShape::Bezier(trimmed.translated(position - moved)), Some(info))
            }
        };
        Ok(self.try_curve(region, fixed, info))
    }
}

/// The end-handle solve of §4.1.2 on its own: the control points `points` (ends already
/// placed) with the interior points moved to bring the end principal normals to
/// `start_normal` / `end_normal` (see [`BendEditor::drag_end_handles`]).
pub fn solve_end_normals(
    points: &[Vec3],
    start_normal: Option<Vec3>,
    end_normal: Option<Vec3>,
    options: &EndHandleOptions,
) -> (Vec<Vec3>, SolverInfo) {
    let n = points.len() - 1;
    let scale: f64 = points
        .windows(2)
        .map(|w| (w[1] - w[0]).norm())
        .sum::<f64>()
        .max(f64::MIN_POSITIVE);
    let problem = EndNormalProblem {
        base: points.to_vec(),
        start_normal: start_normal.map(|v| v.normalize()),
        end_normal: end_normal.map(|v| v.normalize()),
        weight: (options.regularization / (scale * scale)).sqrt(),
    };
    let (dx, info) = levenberg_marquardt(&problem, DVector::zeros(3 * (n - 1)), &options.solver);
    (problem.points(&dx), info)
}

/// The Bézier curve `curve` cut (or extended) exactly where its arc length reaches
/// `target` (§4.1.3): the segment `[0, t1]` by de Casteljau subdivision, with `t1` found
/// to 1e-14 relative.
pub fn trim_to_length(curve: &Bezier3, target: f64) -> (Bezier3, SolverInfo) {
    let (t1, info) = parameter_at_length(curve, target);
    (extended_segment(curve, t1), info)
}

/// Control point `index` exists on a curve of `count` points.
///
/// # Errors
/// [`BendError::Edit`] naming the index and the count.
pub fn check_control_point_index(index: usize, count: usize) -> Result<(), BendError> {
    if index >= count {
        return Err(BendError::Edit {
            message: format!("control point {index} does not exist (the curve has {count})"),
        });
    }
    Ok(())
}

/// The largest coordinate an edit may move a point to (model units: 1 000 km in mm).
/// Far beyond any sheet, and far below where the curve's arithmetic overflows (a drag
/// to 1e200 panicked in the trim's de Casteljau steps).
pub const MAX_EDIT_COORDINATE: f64 = 1e9;

/// A position or direction an edit asks for (3D, or a point of the flat sheet) is finite
/// and within [`MAX_EDIT_COORDINATE`] of the origin.
///
/// # Errors
/// [`BendError::Edit`] quoting the coordinates.
pub fn check_edit_coordinates(coordinates: &[f64]) -> Result<(), BendError> {
    if coordinates
        .iter()
        .all(|c| c.is_finite() && c.abs() <= MAX_EDIT_COORDINATE)
    {
        return Ok(());
    }
    let quoted: Vec<String> = coordinates
        .iter()
        .map(|c| sheetform_geometry::short_number(*c).to_string())
        .collect();
    Err(BendError::Edit {
        message: format!(
            "a position or direction must be finite and within {MAX_EDIT_COORDINATE:e} of the origin, got ({})",
            quoted.join(", ")
        ),
    })
}

/// A number an edit sets (a radius, an angle) is finite and at most
/// [`MAX_EDIT_COORDINATE`] in size.
///
/// # Errors
/// [`BendError::Edit`] naming it.
pub fn check_edit_number(name: &str, value: f64) -> Result<(), BendError> {
    if value.is_finite() && value.abs() <= MAX_EDIT_COORDINATE {
        return Ok(());
    }
    Err(BendError::Edit {
        message: format!("{name} must be finite and at most {MAX_EDIT_COORDINATE:e} in size, got {value}"),
    })
}

/// The Bézier curve on `[0, t1]` of the polynomial `curve` (also for `t1 > 1`:
/// de Casteljau's algorithm extrapolates exactly), reparametrised to `[0, 1]`.
fn extended_segment(curve: &Bezier3, t1: f64) -> Bezier3 {
    let p = curve.control_points();
    let n = p.len();
    let mut work = p.to_vec();
    let mut left = Vec::with_capacity(n);
    left.push(work[0]);
    for level in 1..n {
        for i in 0..n - level {
            work[i] = work[i] * (1.0 - t1) + work[i + 1] * t1;
        }
        left.push(work[0]);
    }
    Bezier3::new(left).expect("segment of a valid curve is valid")
}

/// Speed of the polynomial `curve` at any `t` (no clamping to [0, 1]).
fn speed_unclamped(curve: &Bezier3, t: f64) -> f64 {
    extended_segment(curve, t.max(1e-300))
        .control_points()
        .windows(2)
        .last()
        .map_or(0.0, |w| (w[1] - w[0]).norm() * (curve.degree() as f64) / t.max(1e-300))
}

/// Solves `∫_0^{t1} |P'(t)| dt = target` for `t1` (Newton on the exact integral of the
/// extended polynomial, with bisection safeguard).
fn parameter_at_length(curve: &Bezier3, target: f64) -> (f64, SolverInfo) {
    let length_to = |t: f64| {
        // Length of [0, t] = length of the segment curve on [0, 1].
        let seg = extended_segment(curve, t);
        let table = sheetform_geometry::ArcLengthTable::new(&seg, &[], Default::default());
        table.map(|x| x.total_length()).unwrap_or(0.0)
    };
    let total = sheetform_geometry::ArcLengthTable::new(curve, &[], Default::default())
        .map(|x| x.total_length())
        .unwrap_or(0.0);
    let mut t = if total > 0.0 { target / total } else { 1.0 };
    let (mut lo, mut hi) = (0.0f64, f64::INFINITY);
    let mut info = SolverInfo {
        initial_cost: (total - target).abs(),
        ..Default::default()
    };
    for it in 0..100 {
        let f = length_to(t) - target;
        info.iterations = it + 1;
        info.cost = f.abs();
        if f.abs() <= 1e-14 * target {
            info.converged = true;
            break;
        }
        if f > 0.0 {
            hi = t;
        } else {
            lo = t;
        }
        let v = speed_unclamped(curve, t);
        let mut next = if v > 0.0 { t - f / v } else { f64::NAN };
        if !(next > lo && next < hi) {
            next = if hi.is_finite() {
                0.5 * (lo + hi)
            } else {
                2.0 * t.max(lo)
            };
        }
        t = next;
    }
    (t, info)
}

/// The end-normal least-squares problem of §4.1.2 in the interior increments `ΔX`.
struct EndNormalProblem {
    base: Vec<Vec3>,
    start_normal: Option<Vec3>,
    end_normal: Option<Vec3>,
    weight: f64,
}

/// `N = (a × b) × a = b (a·a) − a (a·b)` and its derivatives `∂N/∂a`, `∂N/∂b`.
fn normal_and_jacobians(a: Vec3, b: Vec3) -> (Vec3, Matrix3<f64>, Matrix3<f64>) {
    let n = b * a.dot(&a) - a * a.dot(&b);
    let dn_da = 2.0 * b * a.transpose() - Matrix3::identity() * a.dot(&b) - a * b.transpose();
    let dn_db = Matrix3::identity() * a.dot(&a) - a * a.transpose();
    (n, dn_da, dn_db)
}

/// `N/|N|` and its derivative `(I − n̂n̂ᵀ)/|N|`.
fn unit_and_jacobian(n: Vec3) -> (Vec3, Matrix3<f64>) {
    let len = n.norm().max(f64::MIN_POSITIVE);
    let u = n / len;
    (u, (Matrix3::identity() - u * u.transpose()) / len)
}

impl EndNormalProblem {
    fn points(&self, dx: &DVector<f64>) -> Vec<Vec3> {
        let mut p = self.base.clone();
        let n = p.len() - 1;
        for (i, q) in p.iter_mut().enumerate().take(n).skip(1) {
            *q += Vec3::new(dx[3 * (i - 1)], dx[3 * (i - 1) + 1], dx[3 * (i - 1) + 2]);
        }
        p
    }

    /// The normal residual at one end with its derivative blocks for the control points
    /// it depends on: `(residual, [(point index, 3×3 block)])`.
    fn end_term(&self, p: &[Vec3], at_start: bool) -> (Vec3, [(usize, Matrix3<f64>); 2]) {
        let n = p.len() - 1;
        let (a, b, ia, ib) = if at_start {
            (p[1] - p[0], p[2] - 2.0 * p[1] + p[0], 1, 2)
        } else {
            (p[n] - p[n - 1], p[n] - 2.0 * p[n - 1] + p[n - 2], n - 1, n - 2)
        };
        let (big, dn_da, dn_db) = normal_and_jacobians(a, b);
        let (u, du) = unit_and_jacobian(big);
        // Start: a depends on P1 (+I), b on P1 (−2I) and P2 (+I).
        // End:   a depends on Pn−1 (−I), b on Pn−1 (−2I) and Pn−2 (+I).
        let da_dfirst = if at_start { 1.0 } else { -1.0 };
        let first = du * (dn_da * da_dfirst + dn_db * -2.0);
        let second = du * dn_db;
        let target = if at_start { self.start_normal } else { self.end_normal }.expect("called only with a target");
        (u - target, [(ia, first), (ib, second)])
    }
}

impl LeastSquaresProblem for EndNormalProblem {
    fn residuals(&self, dx: &DVector<f64>) -> DVector<f64> {
        let p = self.points(dx);
        let mut r: Vec<f64> = Vec::with_capacity(6 + dx.len());
        for (at_start, wanted) in [(true, self.start_normal), (false, self.end_normal)] {
            if wanted.is_some() {
                r.extend(self.end_term(&p, at_start).0.iter());
            }
        }
        r.extend(dx.iter().map(|v| v * self.weight));
        DVector::from_vec(r)
    }

    fn jacobian(&self, dx: &DVector<f64>) -> DMatrix<f64> {
        let p = self.points(dx);
        let rows = 3 * (self.start_normal.is_some() as usize + self.end_normal.is_some() as usize) + dx.len();
        let mut j = DMatrix::zeros(rows, dx.len());
        let n = p.len() - 1;
        let mut row = 0;
        for (at_start, wanted) in [(true, self.start_normal), (false, self.end_normal)] {
            if wanted.is_none() {
                continue;
            }
            for (index, block) in self.end_term(&p, at_start).1 {
                if index >= 1 && index < n {
                    let col = 3 * (index - 1);
                    for r in 0..3 {
                        for c in 0..3 {
                            j[(row + r, col + c)] += block[(r, c)];
                        }
                    }
                }
            }
            row += 3;
        }
        for k in 0..dx.len() {
            j[(row + k, k)] = self.weight;
        }
        j
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn end_normal_jacobian_matches_finite_differences() {
        let base = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(30.0, 2.0, 5.0),
            Vec3::new(60.0, -4.0, 20.0),
            Vec3::new(80.0, 3.0, 50.0),
            Vec3::new(90.0, 8.0, 90.0),
        ];
        let problem = EndNormalProblem {
            base,
            start_normal: Some(Vec3::new(0.0, 0.3, 1.0).normalize()),
            end_normal: Some(Vec3::new(-1.0, 0.2, 0.1).normalize()),
            weight: 0.01,
        };
        let x = DVector::from_fn(9, |i, _| ((i as f64) * 0.7).sin());
        let j = problem.jacobian(&x);
        let h = 1e-6;
        for c in 0..9 {
            let mut xp = x.clone();
            let mut xm = x.clone();
            xp[c] += h;
            xm[c] -= h;
            let fd = (problem.residuals(&xp) - problem.residuals(&xm)) / (2.0 * h);
            for r in 0..fd.len() {
                assert!(
                    (fd[r] - j[(r, c)]).abs() < 1e-7,
                    "J[{r},{c}] = {} vs fd {}",
                    j[(r, c)],
                    fd[r]
                );
            }
        }
    }

    #[test]
    fn extended_segment_extrapolates_the_polynomial() {
        let c = Bezier3::new(vec![
            Vec3::zeros(),
            Vec3::new(1.0, 2.0, 0.0),
            Vec3::new(3.0, 1.0, 1.0),
            Vec3::new(4.0, 0.0, 3.0),
        ])
        .unwrap();
        let e = extended_segment(&c, 1.3);
        // The cubic through the same coefficients: compare with direct evaluation.
        let direct = |t: f64| {
            let p = c.control_points();
            let s = 1.0 - t;
            p[0] * s * s * s + p[1] * 3.0 * s * s * t + p[2] * 3.0 * s * t * t + p[3] * t * t * t
        };
        for i in 0..=10 {
            let s = i as f64 / 10.0;
            assert!((e.point(s) - direct(1.3 * s)).norm() < 1e-12);
        }
    }
}

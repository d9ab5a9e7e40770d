//! A validated bend model, built from a [`BendScene`].

use crate::{
    control_curve::{ControlCurve, CurveShape},
    flat_path::{FlatCurve, FlatPath},
    scene::{BendScene, CurveSpec, CurvedRegionSpec, FlatCurveSpec},
    BendError, TessellationOptions,
};
use sheetform_geometry::{BSpline2, BSpline3, Bezier2, Bezier3, ParametricCurve, Polygon, Vec2, Vec3};
use sheetform_mesh::LengthUnit;

/// One curved region, validated.
#[derive(Debug, Clone)]
pub struct CurvedRegion {
    /// Name (from the scene or `curved-K`).
    pub name: String,
    /// The 3D control curve (a geodesic of the bent sheet when `flat` is straight).
    pub curve: ControlCurve,
    /// Its image on the flat sheet.
    pub flat: FlatPath,
    /// Preferred direction of the sheet's top normal at the start of the curve.
    pub up: Vec3,
    /// Closed strip: the two end rulings are glued.
    pub closed: bool,
}

impl CurvedRegion {
    /// Start of the flat path.
    pub fn flat_start(&self) -> Vec2 {
        self.flat.frame(0.0).point
    }

    /// End of the flat path.
    pub fn flat_end(&self) -> Vec2 {
        self.flat.frame(self.curve.length()).point
    }
}

/// A validated model of a bent sheet: the flat outline with holes and its curved regions.
#[derive(Debug, Clone)]
pub struct BendModel {
    /// Optional name.
    pub name: Option<String>,
    /// Length unit.
    pub unit: LengthUnit,
    /// The flat sheet.
    pub sheet: Polygon,
    /// Curved regions; region 0 is placed in world coordinates.
    pub regions: Vec<CurvedRegion>,
    /// Tessellation knobs.
    pub tessellation: TessellationOptions,
    /// Texture path as written in the scene (relative to the scene file).
    pub texture: Option<String>,
}

fn field(field: impl Into<String>, message: impl Into<String>) -> BendError {
    BendError::Field {
        field: field.into(),
        message: message.into(),
    }
}

fn finite2(p: [f64; 2], name: &str) -> Result<Vec2, BendError> {
    if p.iter().all(|c| c.is_finite()) {
        Ok(Vec2::new(p[0], p[1]))
    } else {
        Err(field(name, "has a non-finite coordinate (NaN or infinity)"))
    }
}

fn points3(points: &[[f64; 3]], name: &str) -> Result<Vec<Vec3>, BendError> {
    points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            if p.iter().all(|c| c.is_finite()) {
                Ok(Vec3::new(p[0], p[1], p[2]))
            } else {
                Err(field(
                    format!("{name}[{i}]"),
                    "has a non-finite coordinate (NaN or infinity)",
                ))
            }
        })
        .collect()
}

/// Builds the polynomial curve of a [`CurveSpec`].
///
/// # Errors
/// Degree below 2 (a degree-1 curve is a straight polyline and bends nothing), bad knots,
/// non-finite points.
pub fn curve_shape(spec: &CurveSpec, name: &str) -> Result<CurveShape, BendError> {
    let geometry = |source| BendError::Geometry {
        field: name.to_string(),
        source,
    };
    match spec {
        CurveSpec::Bezier { control_points } => {
            let pts = points3(control_points, &format!("{name}.control_points"))?;
            if pts.len() < 3 {
                return Err(field(
                    format!("{name}.control_points"),
                    format!(
                        "a Bézier control curve needs at least 3 control points (degree ≥ 2), got {}: a degree-1 curve is a straight line and does not determine a developable",
                        pts.len()
                    ),
                ));
            }
            Ok(CurveShape::Bezier(Bezier3::new(pts).map_err(geometry)?))
        }
        CurveSpec::Bspline {
            degree,
            control_points,
            knots,
            periodic,
        } => {
            let mut pts = points3(control_points, &format!("{name}.control_points"))?;
            if *degree < 2 {
                return Err(field(
                    format!("{name}.degree"),
                    format!("B-spline control curves need degree ≥ 2 (degree {degree} has no curvature)"),
                ));
            }
            if *degree > sheetform_geometry::MAX_BSPLINE_DEGREE {
                return Err(field(
                    format!("{name}.degree"),
                    format!("at most {}, got {degree}", sheetform_geometry::MAX_BSPLINE_DEGREE),
                ));
            }
            if *periodic {
                if knots.is_some() {
                    return Err(field(
                        format!("{name}.knots"),
                        "give either `knots` or `periodic`, not both",
                    ));
                }
                if pts.len() < *degree + 1 {
                    return Err(field(
                        format!("{name}.control_points"),
                        format!(
                            "a periodic B-spline of degree {degree} needs at least {} control points",
                            degree + 1
                        ),
                    ));
                }
                let wrap: Vec<Vec3> = pts[..*degree].to_vec();
                pts.extend(wrap);
                let count = pts.len() + degree + 1;
                let knots: Vec<f64> = (0..count).map(|i| i as f64).collect();
                return Ok(CurveShape::BSpline(
                    BSpline3::new(*degree, pts, knots).map_err(geometry)?,
                ));
            }
            let spline = match knots {
                Some(k) => BSpline3::new(*degree, pts, k.clone()),
                None => BSpline3::clamped_uniform(*degree, pts),
            }
            .map_err(geometry)?;
            Ok(CurveShape::BSpline(spline))
        }
        CurveSpec::Helix {
            radius,
            rise_per_radian,
            start_angle,
            end_angle,
            center,
        } => {
            let c = points3(&[*center], &format!("{name}.center"))?[0];
            let helix = sheetform_geometry::Helix::new(*radius, *rise_per_radian, *start_angle, *end_angle)
                .map_err(geometry)?;
            if c == Vec3::zeros() {
                Ok(CurveShape::Helix(helix))
            } else {
                Ok(CurveShape::Analytic(std::sync::Arc::new(Offset {
                    curve: helix,
                    offset: c,
                })))
            }
        }
    }
}

impl BendModel {
    /// Validates a scene.
    ///
    /// # Errors
    /// Every problem named by field: non-finite numbers, an outline that crosses itself,
    /// holes outside the sheet, degree-1 or zero-length curves, a curve whose length
    /// differs from its flat segment's, a flat geodesic that leaves the sheet, a closed
    /// region whose curve is not closed, nonsensical tessellation settings.
    pub fn from_scene(scene: &BendScene) -> Result<Self, BendError> {
        let outline_vertices = scene.outline.len() + scene.holes.iter().map(Vec::len).sum::<usize>();
        if outline_vertices > crate::MAX_OUTLINE_VERTICES {
            return Err(field(
                "outline/holes",
                format!(
                    "{outline_vertices} vertices in all (at most {})",
                    crate::MAX_OUTLINE_VERTICES
                ),
            ));
        }
        if scene.regions.len() > crate::MAX_REGIONS {
            return Err(field(
                "regions",
                format!("{} regions (at most {})", scene.regions.len(), crate::MAX_REGIONS),
            ));
        }
        if let Some(n) = scene.tessellation.rulings {
            if n.saturating_mul(scene.regions.len()) > crate::MAX_RULINGS {
                return Err(field(
                    "tessellation.rulings",
                    format!(
                        "{n} rulings in each of {} regions: at most {} in all",
                        scene.regions.len(),
                        crate::MAX_RULINGS
                    ),
                ));
            }
        }
        let outer = scene
            .outline
            .iter()
            .enumerate()
            .map(|(i, p)| finite2(*p, &format!("outline[{i}]")))
            .collect::<Result<Vec<_>, _>>()?;
        let holes = scene
            .holes
            .iter()
            .enumerate()
            .map(|(h, ring)| {
                ring.iter()
                    .enumerate()
                    .map(|(i, p)| finite2(*p, &format!("holes[{h}][{i}]")))
                    .collect::<Result<Vec<_>, _>>()
            })
            .collect::<Result<Vec<_>, _>>()?;
        let sheet = Polygon::new(outer, holes).map_err(|source| BendError::Geometry {
            field: "outline/holes".into(),
            source,
        })?;
        let t = scene.tessellation;
        if !(t.max_fold_angle_degrees.is_finite() && t.max_fold_angle_degrees > 0.0 && t.max_fold_angle_degrees <= 45.0)
        {
            return Err(field("tessellation.max_fold_angle_degrees", "must be in (0, 45]"));
        }
        if t.min_rulings < 2 || t.max_rulings < t.min_rulings {
            return Err(field("tessellation", "need 2 ≤ min_rulings ≤ max_rulings"));
        }
        if t.max_rulings > crate::MAX_RULINGS {
            return Err(field(
                "tessellation.max_rulings",
                format!(
                    "at most {} rulings per region (a few hundred bytes each), got {}",
                    crate::MAX_RULINGS,
                    t.max_rulings
                ),
            ));
        }
        if t.rulings.is_some_and(|n| !(2..=crate::MAX_RULINGS).contains(&n)) {
            return Err(field(
                "tessellation.rulings",
                format!(
                    "need 2 to {} rulings, got {}",
                    crate::MAX_RULINGS,
                    t.rulings.unwrap_or(0)
                ),
            ));
        }
        if !(t.length_tolerance.is_finite() && t.length_tolerance > 0.0) {
            return Err(field("tessellation.length_tolerance", "must be a positive number"));
        }
        if scene.regions.is_empty() {
            return Err(field("regions", "needs at least one curved region"));
        }
        let mut regions = Vec::with_capacity(scene.regions.len());
        for (k, spec) in scene.regions.iter().enumerate() {
            regions.push(Self::region(k, spec, &sheet, &t)?);
        }
        Ok(Self {
            name: scene.name.clone(),
            unit: scene.units,
            sheet,
            regions,
            tessellation: t,
            texture: scene.texture.clone(),
        })
    }

    fn region(
        k: usize,
        spec: &CurvedRegionSpec,
        sheet: &Polygon,
        t: &TessellationOptions,
    ) -> Result<CurvedRegion, BendError> {
        let path = format!("regions[{k}]");
        let name = spec.name.clone().unwrap_or_else(|| format!("curved-{k}"));
        let shape = curve_shape(&spec.curve, &format!("{path}.curve"))?;
        let curve = ControlCurve::new(shape).map_err(|source| BendError::DegenerateCurve {
            region: k,
            name: name.clone(),
            reason: format!("{source} (a zero-length curve cannot bend a sheet)"),
        })?;
        let length = curve.length();
        let flat = flat_path(k, spec, &name, length, t)?;
        let up = match spec.up {
            None => Vec3::z(),
            Some(u) => {
                let u = Vec3::new(u[0], u[1], u[2]);
                if !u.iter().all(|c| c.is_finite()) || u.norm() == 0.0 {
                    return Err(field(format!("{path}.up"), "must be a finite non-zero vector"));
                }
                u.normalize()
            }
        };
        let region = CurvedRegion {
            name: name.clone(),
            curve,
            flat,
            up,
            closed: spec.closed,
        };
        check_region_on_sheet(k, &region, sheet)?;
        Ok(region)
    }

    /// The same model with region `k`'s control curve replaced (the flat geodesic keeps
    /// its start and direction; its length follows the curve's), validated again.
    ///
    /// # Errors
    /// A degenerate curve, a geodesic that leaves the sheet, a closed region no longer closed.
    pub fn with_curve(&self, k: usize, shape: CurveShape) -> Result<Self, BendError> {
        let old = &self.regions[k];
        let curve = ControlCurve::new(shape).map_err(|source| BendError::DegenerateCurve {
            region: k,
            name: old.name.clone(),
            reason: format!("{source}"),
        })?;
        let region = CurvedRegion { curve, ..old.clone() };
        check_region_on_sheet(k, &region, &self.sheet)?;
        let mut model = self.clone();
        model.regions[k] = region;
        Ok(model)
    }
}

/// A curve moved by a constant offset.
struct Offset<C> {
    curve: C,
    offset: Vec3,
}

impl<C: ParametricCurve<3>> ParametricCurve<3> for Offset<C> {
    fn domain(&self) -> (f64, f64) {
        self.curve.domain()
    }
    fn derivatives_into(&self, u: f64, out: &mut [nalgebra::SVector<f64, 3>]) {
        self.curve.derivatives_into(u, out);
        if let Some(p) = out.first_mut() {
            *p += self.offset;
        }
    }
}

/// The flat geodesic of a region must stay on the sheet, and a closed region's curve must
/// be closed.
fn check_region_on_sheet(k: usize, region: &CurvedRegion, sheet: &Polygon) -> Result<(), BendError> {
    let name = region.name.clone();
    let path = format!("regions[{k}]");
    let length = region.curve.length();
    // The flat path must stay on the sheet: every chord of a fine polyline along it (one
    // chord for a straight path).
    let eps = 1e-9 * sheet.scale();
    let pieces = if region.flat.is_straight() { 1 } else { 256 };
    // `p` on chord `i` of the polyline below: its arc length from the start.
    let leaves = |p: Vec2, i: usize, a: Vec2| BendError::GeodesicLeavesSheet {
        region: k,
        name: name.clone(),
        curve_length: length,
        on_sheet_length: length * i as f64 / pieces as f64 + (p - a).norm(),
        x: p.x,
        y: p.y,
    };
    let points: Vec<Vec2> = (0..=pieces)
        .map(|i| region.flat.frame(length * i as f64 / pieces as f64).point)
        .collect();
    for (chord, w) in points.windows(2).enumerate() {
        let (a, b) = (w[0], w[1]);
        // The crossing nearest the chord's start (the edges come in the outline's order).
        let mut first: Option<f64> = None;
        for edge in sheet.edges() {
            if let Some((s, _)) = sheetform_geometry::segment_intersection(a, b, edge.start, edge.end) {
                let p = a + (b - a) * s;
                if (p - points[0]).norm() > eps && (p - points[pieces]).norm() > eps {
                    // Touching the boundary at an interior point is only fine if the
                    // path does not cross it: probe on both sides.
                    let d = (b - a).normalize() * (10.0 * eps);
                    if (!sheet.contains(p + d) || !sheet.contains(p - d)) && first.is_none_or(|f| s < f) {
                        first = Some(s);
                    }
                }
            }
        }
        if let Some(s) = first {
            return Err(leaves(a + (b - a) * s, chord, a));
        }
        for i in 1..16 {
            let p = a + (b - a) * (i as f64 / 16.0);
            if !sheet.contains(p) {
                let (d, _) = crate::ruling_extent::locate_on_boundary(sheet, p, 0..sheet.ring_count());
                if d > eps {
                    return Err(leaves(p, chord, a));
                }
            }
        }
    }
    if region.closed {
        let (u0, u1) = region.curve.domain();
        let (d0, d1) = (region.curve.derivatives4(u0), region.curve.derivatives4(u1));
        let gap = (d0[0] - d1[0]).norm();
        let turn = d0[1].normalize().dot(&d1[1].normalize());
        if gap > 1e-6 * length || turn < 1.0 - 1e-9 {
            return Err(field(
                    format!("{path}.closed"),
                    format!(
                        "the curve is not closed: its ends are {gap:.3e} apart and its end tangents {:.3e} degrees apart (use a periodic B-spline)",
                        turn.clamp(-1.0, 1.0).acos().to_degrees()
                    ),
                ));
        }
    }
    Ok(())
}

fn points2(points: &[[f64; 2]], name: &str) -> Result<Vec<Vec2>, BendError> {
    points
        .iter()
        .enumerate()
        .map(|(i, p)| finite2(*p, &format!("{name}[{i}]")))
        .collect()
}

/// The flat path of a region spec: a straight segment (`flat_start` + `flat_end` or
/// `flat_direction`), an arc (`flat_start` + `flat_direction` + `flat_curve: arc`), or a
/// planar Bézier/B-spline (`flat_curve`), whose length must match the control curve's.
fn flat_path(
    k: usize,
    spec: &CurvedRegionSpec,
    name: &str,
    length: f64,
    t: &TessellationOptions,
) -> Result<FlatPath, BendError> {
    let path = format!("regions[{k}]");
    let start = spec
        .flat_start
        .map(|p| finite2(p, &format!("{path}.flat_start")))
        .transpose()?;
    let direction = spec
        .flat_direction
        .map(|d| {
            let d = finite2(d, &format!("{path}.flat_direction"))?;
            // Scaled by its largest component before normalising: a direction of huge (or
            // tiny) components squared to infinity (or 0), became the zero vector and
            // panicked in the placement, or was read as another direction.
            let largest = d.x.abs().max(d.y.abs());
            if largest == 0.0 {
                return Err(field(format!("{path}.flat_direction"), "is the zero vector"));
            }
            Ok((d / largest).normalize())
        })
        .transpose()?;
    let mismatch = |flat_length: f64| {
        let relative = (flat_length - length).abs() / length;
        if relative > t.length_tolerance {
            Err(BendError::LengthMismatch {
                region: k,
                name: name.to_string(),
                curve_length: length,
                flat_length,
                relative,
                tolerance: t.length_tolerance,
            })
        } else {
            Ok(())
        }
    };
    match &spec.flat_curve {
        None => {
            let start = start.ok_or_else(|| field(&path, "needs `flat_start` (or a `flat_curve`)"))?;
            let direction = match (spec.flat_end, direction) {
                (Some(_), Some(_)) => return Err(field(&path, "give either `flat_end` or `flat_direction`, not both")),
                (None, None) => return Err(field(&path, "needs `flat_end` or `flat_direction`")),
                (Some(end), None) => {
                    let end = finite2(end, &format!("{path}.flat_end"))?;
                    let flat_length = (end - start).norm();
                    if flat_length == 0.0 {
                        return Err(field(
                            format!("{path}.flat_end"),
                            "equals `flat_start`: the flat geodesic has zero length",
                        ));
                    }
                    mismatch(flat_length)?;
                    (end - start) / flat_length
                }
                (None, Some(d)) => d,
            };
            Ok(FlatPath::Straight { start, direction })
        }
        Some(FlatCurveSpec::Arc { radius, turn }) => {
            let start = start.ok_or_else(|| field(&path, "an arc `flat_curve` needs `flat_start`"))?;
            let direction = direction
                .ok_or_else(|| field(&path, "an arc `flat_curve` needs `flat_direction` (its start tangent)"))?;
            if spec.flat_end.is_some() {
                return Err(field(
                    format!("{path}.flat_end"),
                    "not used with an arc `flat_curve` (its length is the curve's)",
                ));
            }
            if !(radius.is_finite() && *radius > 0.0) {
                return Err(field(format!("{path}.flat_curve.radius"), "must be a positive number"));
            }
            let sign = match turn.as_str() {
                "left" => 1.0,
                "right" => -1.0,
                other => {
                    return Err(field(
                        format!("{path}.flat_curve.turn"),
                        format!("must be `left` or `right`, got `{other}`"),
                    ))
                }
            };
            Ok(FlatPath::Arc {
                start,
                direction,
                curvature: sign / radius,
            })
        }
        Some(spec_curve @ (FlatCurveSpec::Bezier { .. } | FlatCurveSpec::Bspline { .. })) => {
            if start.is_some() || direction.is_some() || spec.flat_end.is_some() {
                return Err(field(&path, "a Bézier or B-spline `flat_curve` gives its own start and direction: leave out `flat_start`, `flat_end` and `flat_direction`"));
            }
            let field_name = format!("{path}.flat_curve");
            let geometry = |source| BendError::Geometry {
                field: field_name.clone(),
                source,
            };
            let curve = match spec_curve {
                FlatCurveSpec::Bezier { control_points } => FlatCurve::Bezier(
                    Bezier2::new(points2(control_points, &format!("{field_name}.control_points"))?)
                        .map_err(geometry)?,
                ),
                FlatCurveSpec::Bspline {
                    degree,
                    control_points,
                    knots,
                } => {
                    let pts = points2(control_points, &format!("{field_name}.control_points"))?;
                    FlatCurve::BSpline(
                        match knots {
                            Some(k) => BSpline2::new(*degree, pts, k.clone()),
                            None => BSpline2::clamped_uniform(*degree, pts),
                        }
                        .map_err(geometry)?,
                    )
                }
                FlatCurveSpec::Arc { .. } => unreachable!("handled above"),
            };
            let flat = FlatPath::curve(curve).map_err(geometry)?;
            mismatch(flat.fixed_length().expect("curve paths have a length"))?;
            Ok(flat)
        }
    }
}

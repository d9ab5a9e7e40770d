//! Analytic oracles for system A (issue 2, "Must show"): a helix gives its own cylinder,
//! a planar curve the right cylinder over it, a cone geodesic its cone with the curve of
//! regression at the apex; every mesh is an exact isometry of its flat pattern.

use nalgebra::SVector;
use sheetform_bend::{bend, BendModel, ControlCurve, CurveShape, CurvedRegion, FlatPath, TessellationOptions};
use sheetform_geometry::{Bezier3, Helix, ParametricCurve, Polygon, Vec2, Vec3};
use sheetform_mesh::{isometry_error, LengthUnit, PieceKind};
use std::sync::Arc;

fn rectangle(x0: f64, x1: f64, y0: f64, y1: f64) -> Polygon {
    Polygon::new(
        vec![
            Vec2::new(x0, y0),
            Vec2::new(x1, y0),
            Vec2::new(x1, y1),
            Vec2::new(x0, y1),
        ],
        vec![],
    )
    .unwrap()
}

fn model(sheet: Polygon, shape: CurveShape, tessellation: TessellationOptions) -> BendModel {
    let curve = ControlCurve::new(shape).unwrap();
    BendModel {
        name: None,
        unit: LengthUnit::Mm,
        sheet,
        regions: vec![CurvedRegion {
            name: "test".into(),
            curve,
            flat: FlatPath::Straight {
                start: Vec2::zeros(),
                direction: Vec2::x(),
            },
            up: Vec3::z(),
            closed: false,
        }],
        tessellation,
        texture: None,
    }
}

fn fine(max_fold_angle_degrees: f64) -> TessellationOptions {
    TessellationOptions {
        max_fold_angle_degrees,
        max_rulings: 1_000_000,
        ..Default::default()
    }
}

fn curved_vertices(mesh: &sheetform_mesh::SheetMesh) -> Vec<usize> {
    let mut v: Vec<usize> = mesh
        .triangles
        .iter()
        .zip(&mesh.face_pieces)
        .filter(|(_, &p)| mesh.pieces[p as usize].kind == PieceKind::Curved)
        .flat_map(|(t, _)| t.iter().map(|&i| i as usize))
        .collect();
    v.sort_unstable();
    v.dedup();
    v
}

#[test]
fn helix_gives_its_own_cylinder() {
    let (r, c) = (50.0, 20.0);
    let helix = Helix::new(r, c, 0.0, std::f64::consts::FRAC_PI_2).unwrap();
    let length = std::f64::consts::FRAC_PI_2 * (r * r + c * c).sqrt();
    // The flat rulings are oblique, so the sheet's corners stay planar.
    let m = model(
        rectangle(0.0, length, -25.0, 25.0),
        CurveShape::Helix(helix),
        fine(0.005),
    );
    let sheet = bend(&m).unwrap();
    let mesh = &sheet.mesh;
    let curved = curved_vertices(mesh);
    assert!(curved.len() > 1000);
    for &v in &curved {
        let p = mesh.positions[v];
        let radius = (p.x * p.x + p.y * p.y).sqrt();
        assert!((radius - r).abs() <= 1e-9 * r, "vertex {v} at radius {radius}");
    }
    for ruling in &mesh.rulings {
        let a = mesh.positions[ruling.vertices[0] as usize];
        let b = mesh.positions[*ruling.vertices.last().unwrap() as usize];
        let d = (b - a).normalize();
        assert!(
            d.cross(&Vec3::z()).norm() <= 1e-9,
            "ruling not parallel to the axis: {d}"
        );
    }
    assert!(isometry_error(mesh).max_relative <= 1e-10);
    assert!(sheet.regions[0].admissibility.admissible);
}

#[test]
fn helix_mesh_converges_quadratically() {
    // The folded strip's distance to the cylinder shrinks with the square of the fold angle.
    let helix = Helix::new(10.0, 3.0, 0.0, 2.0).unwrap();
    let length = 2.0 * (100.0f64 + 9.0).sqrt();
    let error = |deg: f64| {
        let m = model(rectangle(0.0, length, -5.0, 5.0), CurveShape::Helix(helix), fine(deg));
        let sheet = bend(&m).unwrap();
        let mesh = &sheet.mesh;
        let on_rulings = mesh
            .rulings
            .iter()
            .flat_map(|r| r.vertices.iter())
            .map(|&v| {
                ((mesh.positions[v as usize].x.powi(2) + mesh.positions[v as usize].y.powi(2)).sqrt() - 10.0).abs()
            })
            .fold(0.0, f64::max);
        (on_rulings, sheet.regions[0].curve_deviation)
    };
    let ((r1, d1), (r2, d2)) = (error(2.0), error(1.0));
    for (a, b) in [(r1, r2), (d1, d2)] {
        let ratio = a / b;
        assert!(
            ratio > 3.5 && ratio < 4.5,
            "halving the fold angle should quarter the error: {a} / {b} = {ratio}"
        );
    }
}

#[test]
fn planar_curve_gives_the_right_cylinder_over_it() {
    // A planar S-curve in the xz-plane (with an inflection): rulings must be parallel to y,
    // and every point keeps its flat y as its 3D y.
    let curve = Bezier3::new(vec![
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(40.0, 0.0, 30.0),
        Vec3::new(80.0, 0.0, -30.0),
        Vec3::new(120.0, 0.0, 0.0),
    ])
    .unwrap();
    let shape = CurveShape::Bezier(curve.clone());
    let length = ControlCurve::new(shape.clone()).unwrap().length();
    let m = model(rectangle(0.0, length, -20.0, 20.0), shape, fine(0.05));
    let sheet = bend(&m).unwrap();
    let mesh = &sheet.mesh;
    for ruling in &mesh.rulings {
        let a = mesh.positions[ruling.vertices[0] as usize];
        let b = mesh.positions[*ruling.vertices.last().unwrap() as usize];
        assert!((b - a).normalize().cross(&Vec3::y()).norm() <= 1e-12);
    }
    for v in 0..mesh.vertex_count() {
        assert!((mesh.positions[v].y - mesh.flat[v].y).abs() <= 1e-9 * length);
    }
    // The 3D section stays on the curve to the discretisation tolerance.
    assert!(
        sheet.regions[0].curve_deviation <= 1e-4 * length,
        "{}",
        sheet.regions[0].curve_deviation
    );
    assert!(isometry_error(mesh).max_relative <= 1e-10);
}

/// Truncated Taylor series `Σ a_k ε^k`, k ≤ 4 (exact derivatives: f⁽ᵏ⁾ = k! a_k).
#[derive(Clone, Copy, Debug)]
struct Jet([f64; 5]);

impl Jet {
    fn variable(t: f64) -> Self {
        Jet([t, 1.0, 0.0, 0.0, 0.0])
    }
    fn constant(c: f64) -> Self {
        Jet([c, 0.0, 0.0, 0.0, 0.0])
    }
    fn mul(self, o: Jet) -> Jet {
        let mut r = [0.0; 5];
        for i in 0..5 {
            for j in 0..5 - i {
                r[i + j] += self.0[i] * o.0[j];
            }
        }
        Jet(r)
    }
    fn add(self, o: Jet) -> Jet {
        Jet(std::array::from_fn(|i| self.0[i] + o.0[i]))
    }
    fn scale(self, c: f64) -> Jet {
        Jet(self.0.map(|a| a * c))
    }
    /// `h(self)` given `h, h', h'', h''', h''''` at `self.0[0]`.
    fn compose(self, h: [f64; 5]) -> Jet {
        let mut d = self;
        d.0[0] = 0.0;
        let mut power = Jet::constant(1.0);
        let mut out = Jet::constant(0.0);
        let mut factorial = 1.0;
        for (k, hk) in h.iter().enumerate() {
            if k > 0 {
                power = power.mul(d);
                factorial *= k as f64;
            }
            out = out.add(power.scale(hk / factorial));
        }
        out
    }
    fn sqrt(self) -> Jet {
        let x = self.0[0];
        let s = x.sqrt();
        self.compose([
            s,
            0.5 / s,
            -0.25 / (s * x),
            0.375 / (s * x * x),
            -0.9375 / (s * x * x * x),
        ])
    }
    fn atan(self) -> Jet {
        let x = self.0[0];
        let q = 1.0 + x * x;
        self.compose([
            x.atan(),
            1.0 / q,
            -2.0 * x / (q * q),
            (6.0 * x * x - 2.0) / (q * q * q),
            24.0 * x * (1.0 - x * x) / (q * q * q * q),
        ])
    }
    fn cos(self) -> Jet {
        let (s, c) = self.0[0].sin_cos();
        self.compose([c, -s, -c, s, c])
    }
    fn sin(self) -> Jet {
        let (s, c) = self.0[0].sin_cos();
        self.compose([s, c, -s, -c, s])
    }
}

/// The geodesic of the cone with apex at the origin, axis +z and half-angle β, that is
/// the straight line at distance `d` from the apex in the cone's development, by its arc
/// length `t`: `ρ = √(d² + t²)`, `θ = atan(t/d) / sin β`,
/// `p = ρ (sin β cos θ, sin β sin θ, cos β)`.
struct ConeGeodesic {
    half_angle: f64,
    distance: f64,
    range: (f64, f64),
}

impl ParametricCurve<3> for ConeGeodesic {
    fn domain(&self) -> (f64, f64) {
        self.range
    }
    fn derivatives_into(&self, u: f64, out: &mut [SVector<f64, 3>]) {
        let (sb, cb) = self.half_angle.sin_cos();
        let t = Jet::variable(u.clamp(self.range.0, self.range.1));
        let rho = t.mul(t).add(Jet::constant(self.distance * self.distance)).sqrt();
        let theta = t.scale(1.0 / self.distance).atan().scale(1.0 / sb);
        let x = rho.mul(theta.cos()).scale(sb);
        let y = rho.mul(theta.sin()).scale(sb);
        let z = rho.scale(cb);
        let mut factorial = 1.0;
        for (k, slot) in out.iter_mut().enumerate().take(5) {
            if k > 0 {
                factorial *= k as f64;
            }
            *slot = SVector::<f64, 3>::new(x.0[k], y.0[k], z.0[k]) * factorial;
        }
    }
}

#[test]
fn cone_geodesic_gives_its_cone_with_regression_at_the_apex() {
    let (beta, d) = (0.5f64, 80.0);
    let (t0, t1) = (-60.0, 70.0);
    let curve = ConeGeodesic {
        half_angle: beta,
        distance: d,
        range: (t0, t1),
    };
    let shape = CurveShape::Analytic(Arc::new(curve));
    // The apex is at distance d from the flat geodesic: keep the sheet narrower than d.
    let m = model(rectangle(0.0, t1 - t0, -40.0, 40.0), shape, fine(0.004));
    let sheet = bend(&m).unwrap();
    // The curve of regression (Eq. 4–5) is the apex.
    for s in &sheet.geometries[0].samples {
        let c = s.point + s.ruling * s.regression_distance;
        assert!(c.norm() <= 1e-9 * d, "regression point {c} at s = {}", s.arc_length);
    }
    let mesh = &sheet.mesh;
    for &v in &curved_vertices(mesh) {
        let p = mesh.positions[v];
        let angle = (p.x * p.x + p.y * p.y).sqrt().atan2(p.z);
        assert!((angle - beta).abs() <= 1e-9, "vertex {v} at angle {angle}");
    }
    assert!(isometry_error(mesh).max_relative <= 1e-10);
    assert!(sheet.regions[0].admissibility.admissible);
}

#[test]
fn cone_sheet_reaching_the_apex_is_inadmissible() {
    let curve = ConeGeodesic {
        half_angle: 0.5,
        distance: 30.0,
        range: (-40.0, 40.0),
    };
    let m = model(
        rectangle(0.0, 80.0, -50.0, 50.0),
        CurveShape::Analytic(Arc::new(curve)),
        TessellationOptions::default(),
    );
    match bend(&m) {
        Err(sheetform_bend::BendError::Inadmissible(detail)) => {
            // It enters where the apex is: 30 from the geodesic on one side.
            assert!((detail.flat_point[1].abs() - 30.0).abs() < 1e-6, "{detail:?}");
        }
        other => panic!("expected inadmissible, got {:?}", other.map(|_| ())),
    }
}

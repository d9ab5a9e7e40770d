//! The symmetrisation of §7 on a drawing built here from a known model: a horizontal
//! open tube (radius 60 px, length 300 px) turned 25° about the vertical and tilted 20°
//! towards the viewer, seen orthographically. The plane halfway along the tube is its
//! mirror plane; the two end arcs are a symmetric pair and every ruling crosses the
//! plane — the case where the paper drops the rulings and joins mirror points instead.
//! (The silhouettes are self-symmetric too, but they run along the image direction of
//! the plane's normal, so §5.3's correspondences along that direction cannot be found on
//! them: they are not marked, and follow their ends.)

use nalgebra::{Rotation3, Vector3};
use serde_json::json;
use sheetform_photo::{reconstruct, PhotoAnnotation, PhotoReconstruction, REFINEMENT_BOUND};

type Vec3 = Vector3<f64>;

const RADIUS: f64 = 60.0;
const HALF_LENGTH: f64 = 150.0;
const CENTRE: [f64; 2] = [240.0, 180.0];

/// World (x along the axis, y up, z towards the viewer before turning) to the camera
/// frame (x right, y up, z towards the viewer).
fn camera() -> Rotation3<f64> {
    Rotation3::from_axis_angle(&Vec3::x_axis(), 20f64.to_radians())
        * Rotation3::from_axis_angle(&Vec3::y_axis(), 25f64.to_radians())
}

fn image(p: Vec3) -> [f64; 2] {
    let c = camera() * p;
    [CENTRE[0] + c.x, CENTRE[1] - c.y]
}

/// Angle on the circle at which the tube's surface normal `(0, cos a, sin a)` is
/// perpendicular to the view: `(R n)_z = 0`.
fn silhouette_angle() -> f64 {
    let r = camera();
    let (ny, nz) = (r * Vec3::y(), r * Vec3::z());
    // cos a · ny_z + sin a · nz_z = 0.
    (-ny.z).atan2(nz.z)
}

/// The visible half of the end circle at `x` from one silhouette to the other as four
/// cubic arcs (13 control points), in the image; `noise` moves every point.
fn end_arc(x: f64, noise: &mut impl FnMut() -> [f64; 2]) -> Vec<[f64; 2]> {
    let a0 = silhouette_angle();
    // The front half: the normal there faces the viewer.
    let facing = |a: f64| (camera() * Vec3::new(0.0, a.cos(), a.sin())).z;
    let (start, sweep) = if facing(a0 + 0.5 * std::f64::consts::PI) > 0.0 {
        (a0, std::f64::consts::PI)
    } else {
        (a0, -std::f64::consts::PI)
    };
    let step = sweep / 4.0;
    let k = 4.0 / 3.0 * (step / 4.0).tan();
    let at = |a: f64| Vec3::new(x, RADIUS * a.cos(), RADIUS * a.sin());
    let tangent = |a: f64| Vec3::new(0.0, -RADIUS * a.sin(), RADIUS * a.cos());
    let mut points = vec![at(start)];
    for i in 0..4 {
        let (a, b) = (start + step * i as f64, start + step * (i + 1) as f64);
        points.push(at(a) + tangent(a) * k);
        points.push(at(b) - tangent(b) * k);
        points.push(at(b));
    }
    points
        .into_iter()
        .map(|p| {
            let [u, v] = image(p);
            let [du, dv] = noise();
            [u + du, v + dv]
        })
        .collect()
}

fn straight(a: [f64; 2], b: [f64; 2]) -> Vec<[f64; 2]> {
    let lerp = |t: f64| [a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t];
    vec![a, lerp(1.0 / 3.0), lerp(2.0 / 3.0), b]
}

/// The tube's annotation; `sigma` (pixels) of seeded noise on the end arcs' points.
fn tube(sigma: f64) -> PhotoAnnotation {
    // A fixed-seed generator (xorshift) and Box–Muller.
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut uniform = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut noise = move || {
        let (u, v) = (uniform().max(1e-300), uniform());
        let r = sigma * (-2.0 * u.ln()).sqrt();
        let a = 2.0 * std::f64::consts::PI * v;
        [r * a.cos(), r * a.sin()]
    };
    let left = end_arc(-HALF_LENGTH, &mut noise);
    let right = end_arc(HALF_LENGTH, &mut noise);
    let (l0, l1) = (left[0], left[12]);
    let (r0, r1) = (right[0], right[12]);
    let a0 = silhouette_angle();
    let silhouette_end = |x: f64| Vec3::new(x, RADIUS * a0.cos(), RADIUS * a0.sin());
    // Frame: two directions in the plane x = 0; pair: the silhouette's two ends.
    let o = Vec3::zeros();
    let mut points = [silhouette_end(-HALF_LENGTH), silhouette_end(HALF_LENGTH)];
    if (camera() * points[0]).z > (camera() * points[1]).z {
        points.swap(0, 1);
    }
    let value = json!({
        "name": "tube for the symmetrisation test",
        "image": {"path": "tube.png", "width": 480, "height": 360},
        "units": "mm",
        "curves": [
            {"name": "left-end", "kind": "boundary", "control_points": left},
            {"name": "right-end", "kind": "boundary", "control_points": right},
            {"name": "first-silhouette", "kind": "silhouette", "control_points": straight(l0, r0)},
            {"name": "second-silhouette", "kind": "silhouette", "control_points": straight(l1, r1)},
        ],
        "symmetry": {
            "frame": [[image(o), image(Vec3::new(0.0, RADIUS, 0.0))],
                      [image(o), image(Vec3::new(0.0, 0.0, RADIUS))]],
            "points": [image(points[0]), image(points[1])],
        },
        "symmetric_curves": [["left-end", "right-end"]],
        "true_size": {"from": image(silhouette_end(-HALF_LENGTH)), "to": image(silhouette_end(HALF_LENGTH)), "length": 300.0},
    });
    PhotoAnnotation::from_json(&value.to_string()).expect("a valid annotation")
}

/// Largest distance from the mirror image of a mesh vertex to the nearest vertex.
fn mirror_gap(r: &PhotoReconstruction) -> f64 {
    let s = r.unit_per_pixel;
    let (n, c) = (r.plane.normal, r.plane.point * s);
    r.mesh
        .positions
        .iter()
        .map(|p| {
            let m = p - 2.0 * n.dot(&(p - c)) * n;
            r.mesh
                .positions
                .iter()
                .map(|q| (q - m).norm())
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}

fn check(sigma: f64) -> PhotoReconstruction {
    let r = reconstruct(&tube(sigma)).unwrap();
    let info = r.symmetrization.as_ref().expect("on by default");
    assert!(!info.abandoned, "σ = {sigma}: {info:?}");
    assert!(info.unmatched_curves.is_empty(), "σ = {sigma}: {info:?}");
    // The 4 + 4 arcs in pairs (more if split at mirrored nodes).
    assert!(info.mirrored_segment_count >= 4, "σ = {sigma}: {info:?}");
    assert_eq!(info.mirrored_strip_count, 1, "σ = {sigma}: {info:?}");
    assert!(info.crossing_ruling_count > 5, "σ = {sigma}: {info:?}");
    // Exactly symmetric: every vertex's mirror image is a vertex (model units: mm).
    let gap = mirror_gap(&r);
    assert!(
        gap < 1e-9,
        "σ = {sigma}: a mirrored vertex is {gap:e} mm from the nearest vertex"
    );
    // Every ruling joins mirror points: it is perpendicular to the plane.
    for strip in &r.strips {
        for i in 0..strip.rulings.len() {
            let [a, b] = strip.ends(i);
            let d = r.point(b) - r.point(a);
            let off = d.cross(&r.plane.normal).norm() / d.norm();
            assert!(
                off < 1e-9,
                "σ = {sigma}: ruling {i} is {off:e} rad off the plane's normal"
            );
        }
    }
    // Still exactly developable.
    let worst = r.ruling_errors_final.iter().copied().fold(0.0, f64::max);
    assert!(
        worst.sin() <= REFINEMENT_BOUND,
        "σ = {sigma}: developability error {worst:e} rad"
    );
    r
}

#[test]
fn exact_tube_is_symmetric_developable_and_true_to_size() {
    let r = check(0.0);
    // The truth: the visible half of a 60 mm tube 300 mm long (1 mm per pixel), so the
    // strip unfolds to 300 mm × π·60 mm; its area, from the mesh.
    let area: f64 = r
        .mesh
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| r.mesh.positions[i as usize]);
            0.5 * (b - a).cross(&(c - a)).norm()
        })
        .sum();
    let expected = 300.0 * std::f64::consts::PI * RADIUS;
    assert!(
        (area / expected - 1.0).abs() < 0.02,
        "area {area:.0} mm², expected {expected:.0} mm²"
    );
    // The symmetrisation of an exact drawing moves the solved curves very little.
    let moved = r.symmetrization.as_ref().unwrap().displacement_max_px;
    assert!(moved < 1.0, "moved {moved} px");
}

#[test]
fn noisy_tube_comes_out_exactly_symmetric() {
    let r = check(1.0);
    // The noise is real: the symmetrisation moved the curves.
    let moved = r.symmetrization.as_ref().unwrap().displacement_max_px;
    assert!(moved > 0.1, "moved {moved} px");
}

#[test]
fn symmetrisation_can_be_switched_off() {
    let mut annotation = tube(1.0);
    annotation.analysis.symmetrize = false;
    let r = reconstruct(&annotation).unwrap();
    assert!(r.symmetrization.is_none());
    assert!(mirror_gap(&r) > 1e-3, "a noisy drawing is not symmetric by itself");
}

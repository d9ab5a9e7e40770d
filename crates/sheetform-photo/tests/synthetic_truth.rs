//! Reconstructions of annotations made from known 3D models (`tools/make_photo_examples.py`,
//! files in `examples/photo/synthetic/`), compared with their truth: rulings in the image,
//! 3D curves (after the depth offset, which one view cannot fix, is removed) and the
//! developability error of §8.2, and the hand-annotated espresso cup end to end.

use nalgebra::{Vector2, Vector3};
use serde_json::Value;
use sheetform_photo::{reconstruct, AngleSummary, BackSide, CurveKind, PhotoAnnotation, PhotoReconstruction};
use std::path::PathBuf;

type Vec2 = Vector2<f64>;
type Vec3 = Vector3<f64>;

fn examples() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/photo")
}

fn load(name: &str) -> (PhotoAnnotation, Value, PhotoReconstruction) {
    load_as(name, |_| {})
}

/// [`load`] with the annotation edited first.
fn load_as(name: &str, edit: impl Fn(&mut PhotoAnnotation)) -> (PhotoAnnotation, Value, PhotoReconstruction) {
    let dir = examples().join("synthetic");
    let mut annotation =
        PhotoAnnotation::from_json(&std::fs::read_to_string(dir.join(format!("{name}.json"))).unwrap())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
    edit(&mut annotation);
    let truth: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join(format!("{name}.truth.json"))).unwrap()).unwrap();
    let r = reconstruct(&annotation).unwrap_or_else(|e| panic!("{name}: {e}"));
    (annotation, truth, r)
}

fn vec3(v: &Value) -> Vec3 {
    Vec3::new(v[0].as_f64().unwrap(), v[1].as_f64().unwrap(), v[2].as_f64().unwrap())
}

/// A cubic chain's points at `n` parameters per segment.
fn truth_curve_points(truth: &Value, curve: &str, n: usize) -> Vec<Vec3> {
    let cps: Vec<Vec3> = truth["curves"][curve]["control_points_model"]
        .as_array()
        .unwrap()
        .iter()
        .map(vec3)
        .collect();
    let mut out = Vec::new();
    for j in 0..(cps.len() - 1) / 3 {
        let b = [cps[3 * j], cps[3 * j + 1], cps[3 * j + 2], cps[3 * j + 3]];
        for i in 0..n {
            out.push(sheetform_photo::cubic::point(&b, i as f64 / n as f64));
        }
    }
    out
}

/// Largest angle (degrees) between a reconstructed ruling and the true ruling through
/// its first end: through the projected apex for a cone, along the projected axis for a
/// cylinder. Each strip is compared with the truth patch whose silhouettes bound it.
fn ruling_angle_error_deg(r: &PhotoReconstruction, truth: &Value, linear: bool) -> f64 {
    let rulings: Vec<(usize, [Vec2; 2])> = if linear {
        r.rulings_linear.clone()
    } else {
        r.strips
            .iter()
            .flat_map(|s| (0..s.rulings.len()).map(move |i| (s.patch, s.segment(i))))
            .collect()
    };
    let mut worst = 0.0f64;
    for (patch_index, [a, b]) in rulings {
        let silhouettes: Vec<&str> = r.patches[patch_index]
            .cycle
            .iter()
            .map(|h| &r.network.curves[r.network.segments[h.segment as usize].curve as usize])
            .filter(|c| c.kind == CurveKind::Silhouette)
            .map(|c| c.name.as_str())
            .collect();
        let patch = truth["patches"]
            .as_array()
            .unwrap()
            .iter()
            .find(|p| {
                p["silhouette_curves"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .any(|s| silhouettes.contains(&s.as_str().unwrap()))
            })
            .expect("a truth patch for the ruling");
        let true_direction = if patch["type"] == "cone" {
            let apex = vec3(&patch["apex_model"]);
            Vec2::new(apex.x, apex.y) - a
        } else {
            let axis = vec3(&patch["axis_direction_model"]);
            Vec2::new(axis.x, axis.y)
        };
        let d = b - a;
        let c = (d.dot(&true_direction) / (d.norm() * true_direction.norm()))
            .abs()
            .min(1.0);
        worst = worst.max(c.acos().to_degrees());
    }
    worst
}

/// Largest 3D distance (pixels) from the reconstructed curves to the true ones, after the
/// best depth offset; the reconstructed points are matched to the true curve point
/// nearest in the image. (A curve without mirror pairs would keep a free depth: the
/// planar-quad term of Eq. 4 is blind to sliding a whole circle along the view. With
/// only the top rim marked self-symmetric the cylinder's bottom was 6 px off and the
/// cones leaned; every circle is marked now, see docs/benchmarks-history.md.)
fn curve_error_px(r: &PhotoReconstruction, x: &[f64], truth: &Value, only: &[String]) -> f64 {
    let mut pairs: Vec<(Vec3, Vec3)> = Vec::new();
    for curve in &r.network.curves {
        if !only.is_empty() && !only.contains(&curve.name) {
            continue;
        }
        let truth_points = truth_curve_points(truth, &curve.name, 200);
        for &s in &curve.segments {
            for &t in &r.samples.parameters[s as usize] {
                let p = sheetform_photo::place_point(&r.network, x, sheetform_photo::CurvePoint { segment: s, t });
                let q = truth_points
                    .iter()
                    .min_by(|x, y| {
                        let dx = (Vec2::new(x.x, x.y) - Vec2::new(p.x, p.y)).norm();
                        let dy = (Vec2::new(y.x, y.y) - Vec2::new(p.x, p.y)).norm();
                        dx.total_cmp(&dy)
                    })
                    .copied()
                    .unwrap();
                pairs.push((p, q));
            }
        }
    }
    let offset = pairs.iter().map(|(p, q)| q.z - p.z).sum::<f64>() / pairs.len() as f64;
    if std::env::var("PHOTO_DEBUG").is_ok() {
        for (p, q) in pairs.iter().step_by(7) {
            println!(
                "  p {:.1} {:.1} {:.1}  q {:.1} {:.1} {:.1}",
                p.x,
                p.y,
                p.z + offset,
                q.x,
                q.y,
                q.z
            );
        }
    }
    pairs
        .iter()
        .map(|(p, q)| (p + Vec3::new(0.0, 0.0, offset) - q).norm())
        .fold(0.0, f64::max)
}

struct Figures {
    ruling_deg: f64,
    ruling_linear_deg: f64,
    curve_px: f64,
    curve_linear_px: f64,
    linear: AngleSummary,
    refined: AngleSummary,
    scale_error: f64,
}

fn figures(name: &str) -> Figures {
    let (annotation, truth, r) = load(name);
    // Every curve (an empty filter).
    let every: Vec<String> = Vec::new();
    assert!(!annotation.self_symmetric_curves.is_empty());
    let f = Figures {
        ruling_deg: ruling_angle_error_deg(&r, &truth, false),
        ruling_linear_deg: ruling_angle_error_deg(&r, &truth, true),
        curve_px: curve_error_px(&r, &r.points3d, &truth, &every),
        curve_linear_px: curve_error_px(&r, &r.linear, &truth, &every),
        linear: AngleSummary::of(&r.ruling_errors_linear),
        refined: AngleSummary::of(&r.ruling_errors_refined),
        scale_error: (r.unit_per_pixel / truth["mm_per_px"].as_f64().unwrap() - 1.0).abs(),
    };
    println!(
        "{name}: rulings within {:.3}° ({:.3}° before the refinement), curves within {:.3} px (linear {:.3}), developability linear mean {:.3}° max {:.3}°, refined mean {:.2e}° max {:.2e}°, scale error {:.2e}, rulings {}, pairs {}",
        f.ruling_deg,
        f.ruling_linear_deg,
        f.curve_px,
        f.curve_linear_px,
        f.linear.mean_deg,
        f.linear.max_deg,
        f.refined.mean_deg,
        f.refined.max_deg,
        f.scale_error,
        r.ruling_count(),
        r.pairs.len()
    );
    f
}

#[test]
fn exact_orthographic_drawings_are_reconstructed() {
    for name in ["cylinder-ortho", "cone-ortho", "composite-ortho"] {
        let f = figures(name);
        // Aligned to the point of parallel tangents and slid by the refinement, the
        // rulings are the true ones to the tracing's Bézier approximation of a circle.
        assert!(
            f.ruling_linear_deg < 0.01,
            "{name}: rulings off by {:.3}°",
            f.ruling_linear_deg
        );
        assert!(
            f.ruling_deg < 0.25,
            "{name}: refined rulings off by {:.3}°",
            f.ruling_deg
        );
        assert!(f.curve_px < 1.5, "{name}: curves off by {:.3} px", f.curve_px);
        assert!(
            f.linear.mean_deg < 1.0,
            "{name}: linear error {:.3}°",
            f.linear.mean_deg
        );
        // The bound on exact input after the refinement.
        assert!(
            f.refined.mean_deg <= 0.1,
            "{name}: refined error {:.3e}°",
            f.refined.mean_deg
        );
        assert!(f.scale_error < 0.01, "{name}: scale off by {:.2e}", f.scale_error);
    }
}

#[test]
fn noisy_and_perspective_drawings_stay_under_the_papers_error() {
    for name in [
        "cylinder-noisy",
        "cone-noisy",
        "composite-noisy",
        "cylinder-perspective",
        "cone-perspective",
    ] {
        let f = figures(name);
        // The paper's Table 1 reports 6.6–16.3° of mean developability error on real drawings;
        // its linear solve stays within that, the refinement goes far below.
        assert!(
            f.linear.mean_deg < 16.5,
            "{name}: linear error {:.3}°",
            f.linear.mean_deg
        );
        assert!(
            f.refined.mean_deg <= 0.1,
            "{name}: refined error {:.3e}°",
            f.refined.mean_deg
        );
        // Perspective bends the rulings' images (the method assumes an orthographic view).
        // One pixel of noise at both ends of a 90-pixel ruling turns it by up to ~1.3°.
        let bound = if name.ends_with("perspective") { 12.0 } else { 5.0 };
        assert!(
            f.ruling_linear_deg < bound,
            "{name}: rulings off by {:.3}°",
            f.ruling_linear_deg
        );
        // The refinement slides ruling ends to make the noisy curves developable: on the
        // noisy composite (28 px of depth error from the linear solve) some end slides
        // far and its ruling turns by 24° (recorded in docs/benchmarks-history.md); elsewhere
        // within a few degrees of the analysis.
        let refined_bound = if name == "composite-noisy" { 30.0 } else { bound };
        assert!(
            f.ruling_deg < refined_bound,
            "{name}: refined rulings off by {:.3}°",
            f.ruling_deg
        );
        // The perspective truth is the camera-frame model scaled at the object's centre
        // depth, the reconstruction is scaled about the camera centre to put the marked
        // pair's midpoint at depth 0: only the depth offset is removed here (the shape in
        // mm is checked by `perspective_views_are_reconstructed_through_their_camera`).
        // Noise: a pixel on a mirror pair a few tens of pixels apart tilts its depth by
        // several pixels over the object's ~300-pixel depth range.
        // The noisy composite's linear solve is 28 px off (its neck's mirror pairs are
        // short); recorded in docs/benchmarks-history.md.
        let bound = match name {
            _ if name.ends_with("perspective") => 15.0,
            "composite-noisy" => 30.0,
            _ => 12.0,
        };
        assert!(f.curve_px < bound, "{name}: curves off by {:.3} px", f.curve_px);
    }
}

#[test]
fn the_espresso_cup_photo_is_reconstructed() {
    let path = examples().join("coffee-cup.json");
    let annotation = PhotoAnnotation::from_json(&std::fs::read_to_string(path).unwrap()).unwrap();
    let r = reconstruct(&annotation).unwrap();
    let linear = AngleSummary::of(&r.ruling_errors_linear);
    let refined = AngleSummary::of(&r.ruling_errors_refined);
    println!(
        "coffee cup: {} rulings, {} pairs, linear mean {:.3}° max {:.3}°, refined mean {:.2e}° max {:.2e}°, reprojection {:.3} px",
        r.ruling_count(),
        r.pairs.len(),
        linear.mean_deg,
        linear.max_deg,
        refined.mean_deg,
        refined.max_deg,
        r.reprojection_error_px.1
    );
    assert_eq!(r.patches.iter().filter(|p| !p.opening).count(), 1, "the cup's body");
    assert_eq!(r.patches.iter().filter(|p| p.opening).count(), 1, "the cup's mouth");
    assert!(r.ruling_count() >= 20);
    assert!(linear.mean_deg < 6.0);
    assert!(refined.mean_deg <= 0.1);
    // The rim's true diameter is the given 62 mm; the body's height is then plausible for
    // an espresso cup (tens of millimetres).
    let heights: Vec<f64> = (0..r.strips[0].rulings.len())
        .map(|i| {
            let [a, b] = r.strips[0].ends(i);
            (r.point(a) - r.point(b)).norm()
        })
        .collect();
    let longest = heights.iter().copied().fold(0.0, f64::max);
    assert!((10.0..80.0).contains(&longest), "ruling length {longest} mm");
}

/// The perspective composite ended `not developable` when its view was taken for an
/// orthographic one (issue 37: 0.013° left against the 1e-7 rad bound); through its
/// camera the refinement meets the bound.
#[test]
fn a_perspective_composite_is_made_developable() {
    let f = figures("composite-perspective");
    assert!(f.linear.mean_deg < 1.0, "linear error {:.3}°", f.linear.mean_deg);
    let (_, _, r) = load("composite-perspective");
    assert!(r.refinement.unwrap().converged);
    let worst = r.ruling_errors_refined.iter().copied().fold(0.0, f64::max);
    assert!(worst.sin() <= sheetform_photo::REFINEMENT_BOUND, "{worst}");
}

/// Shape and size against the truth, in the units of the pattern (mm): every curve
/// sample of the final model (scaled by the annotation's true size) is matched to the
/// truth curve point seen nearest to where it is seen (each through its camera), the
/// best translation is removed (one view fixes no position along the view), and
/// returned are the largest distance over the object's height, and the relative
/// difference of the spreads (RMS distance from the centroid): a size error that does
/// not depend on the true-size mark itself.
fn shape_and_size_errors(name: &str) -> (f64, f64) {
    shape_and_size_errors_of(load(name))
}

/// [`shape_and_size_errors`] of a loaded view.
fn shape_and_size_errors_of((_, truth, r): (PhotoAnnotation, Value, PhotoReconstruction)) -> (f64, f64) {
    let mm_per_px = truth["mm_per_px"].as_f64().unwrap();
    let camera = &truth["camera"];
    let project = |p: Vec3| -> Vec2 {
        if camera["type"] == "perspective" {
            let f = camera["focal_px"].as_f64().unwrap();
            let c = Vec2::new(240.0, -240.0);
            c + (Vec2::new(p.x, p.y) - c) * (f / (f - p.z))
        } else {
            Vec2::new(p.x, p.y)
        }
    };
    let mut pairs: Vec<(Vec3, Vec3)> = Vec::new();
    for curve in &r.network.curves {
        let truth_points = truth_curve_points(&truth, &curve.name, 400);
        let seen: Vec<Vec2> = truth_points.iter().map(|&q| project(q)).collect();
        for &s in &curve.segments {
            for &t in &r.samples.parameters[s as usize] {
                let place = sheetform_photo::CurvePoint { segment: s, t };
                let image = r
                    .plane
                    .camera
                    .project(sheetform_photo::place_point(&r.network, &r.points3d, place));
                let k = (0..seen.len())
                    .min_by(|&i, &j| (seen[i] - image).norm().total_cmp(&(seen[j] - image).norm()))
                    .unwrap();
                pairs.push((r.point(place), truth_points[k] * mm_per_px));
            }
        }
    }
    let n = pairs.len() as f64;
    let centroid_p = pairs.iter().map(|(p, _)| p).sum::<Vec3>() / n;
    let centroid_q = pairs.iter().map(|(_, q)| q).sum::<Vec3>() / n;
    let shift = centroid_q - centroid_p;
    let axis = &truth["symmetry"]["frame_model"][0];
    let height = (vec3(&axis[1]) - vec3(&axis[0])).norm() * mm_per_px;
    let shape = pairs.iter().map(|(p, q)| (p + shift - q).norm()).fold(0.0, f64::max) / height;
    let spread = |points: &mut dyn Iterator<Item = Vec3>, c: Vec3| {
        (points.map(|p| (p - c).norm_squared()).sum::<f64>() / n).sqrt()
    };
    let size = spread(&mut pairs.iter().map(|(p, _)| *p), centroid_p)
        / spread(&mut pairs.iter().map(|(_, q)| *q), centroid_q)
        - 1.0;
    (shape, size.abs())
}

/// Issue 37: through the camera the photo was taken with, a perspective view is
/// reconstructed to 0.8-1.5 % of the object's height (19-27 % when it was taken for an
/// orthographic view) and to its size within 0.5 %; the exact orthographic views stay
/// within 0.5 % and 0.1 %. Figures in docs/benchmarks-history.md.
#[test]
fn perspective_views_are_reconstructed_through_their_camera() {
    for (name, shape_bound, size_bound) in [
        ("cylinder-ortho", 0.005, 0.001),
        ("cone-ortho", 0.005, 0.001),
        ("composite-ortho", 0.005, 0.001),
        ("cylinder-perspective", 0.01, 0.005),
        ("cone-perspective", 0.02, 0.005),
        ("composite-perspective", 0.01, 0.005),
    ] {
        let (shape, size) = shape_and_size_errors(name);
        println!(
            "{name}: shape within {:.2} % of the height, size within {:.2} %",
            100.0 * shape,
            100.0 * size
        );
        assert!(
            shape < shape_bound,
            "{name}: shape off by {:.2} % of the height",
            100.0 * shape
        );
        assert!(size < size_bound, "{name}: size off by {:.2} %", 100.0 * size);
        // The same view read as orthographic (the annotation without its camera): the
        // figures before issue 37, far off.
        if name.ends_with("perspective") {
            let (shape, size) = shape_and_size_errors_of(load_as(name, |a| a.camera = Default::default()));
            println!(
                "{name} without its camera: shape within {:.2} % of the height, size within {:.2} %",
                100.0 * shape,
                100.0 * size
            );
            assert!(shape > 0.1, "{name}: {:.2} % without the camera", 100.0 * shape);
        }
    }
}

/// A band as (heights of its lower and upper circle along the axis, their radii), in mm.
type BandFigures = ([f64; 2], [f64; 2]);

/// How far closed bands are from the truth's cones: the axis' angle (degrees), the largest
/// difference of a band's radii or height along the axis (mm), the object's height (mm),
/// the axis (pointing as the truth's), and the bands and true bands from the lowest.
fn revolution_errors(
    name: &str,
    truth: &Value,
    revolution: &sheetform_photo::Revolution,
) -> (f64, f64, f64, Vec3, Vec<BandFigures>, Vec<BandFigures>) {
    let mm_per_px = truth["mm_per_px"].as_f64().unwrap();
    let patches = truth["patches"].as_array().unwrap();
    let true_axis = vec3(&patches[0]["axis_direction_model"]).normalize();
    let mut axis = Vec3::from(revolution.axis_direction);
    // Heights along the truth's axis direction.
    let sign = axis.dot(&true_axis).signum();
    axis *= sign;
    let angle = axis.dot(&true_axis).clamp(-1.0, 1.0).acos().to_degrees();
    // True bands, from the lowest: (height of the lower and upper circle's centres
    // along the axis, radii), in mm.
    let mut true_bands: Vec<([f64; 2], [f64; 2])> = patches
        .iter()
        .map(|p| {
            let (lo, hi) = (&p["lower_circle"], &p["upper_circle"]);
            (
                [
                    vec3(&lo["centre_model"]).dot(&true_axis) * mm_per_px,
                    vec3(&hi["centre_model"]).dot(&true_axis) * mm_per_px,
                ],
                [
                    lo["radius_px"].as_f64().unwrap() * mm_per_px,
                    hi["radius_px"].as_f64().unwrap() * mm_per_px,
                ],
            )
        })
        .collect();
    true_bands.sort_by(|a, b| a.0[0].total_cmp(&b.0[0]));
    let height = true_bands.last().unwrap().0[1] - true_bands[0].0[0];
    let mut bands: Vec<([f64; 2], [f64; 2])> = revolution
        .bands
        .iter()
        .map(|b| {
            if sign > 0.0 {
                (b.heights, b.radii)
            } else {
                ([-b.heights[1], -b.heights[0]], [b.radii[1], b.radii[0]])
            }
        })
        .collect();
    bands.sort_by(|a, b| a.0[0].total_cmp(&b.0[0]));
    assert_eq!(bands.len(), true_bands.len(), "{name}");
    let mut worst: f64 = 0.0;
    for (band, truth_band) in bands.iter().zip(&true_bands) {
        for k in 0..2 {
            worst = worst.max((band.1[k] - truth_band.1[k]).abs());
        }
        let (length, true_length) = (band.0[1] - band.0[0], truth_band.0[1] - truth_band.0[0]);
        worst = worst.max((length - true_length).abs());
    }
    (angle, worst, height, axis, bands, true_bands)
}

/// `back_side: revolve` on every synthetic view: the fitted axis is the truth's, each band
/// closes round it as the truth's cone or cylinder (radii and height along the axis within
/// 1 % of the object's height, the shape target), and the closed mesh is exactly
/// developable (each quad between two rulings planar) and closed round the axis (every
/// edge but those of the outer rings has two faces).
#[test]
fn bands_closed_round_their_axis_are_the_true_cones() {
    for name in [
        "cylinder-ortho",
        "cone-ortho",
        "composite-ortho",
        "cylinder-perspective",
        "cone-perspective",
        "composite-perspective",
        // (Not `composite-noisy`: its visible reconstruction is itself no pair of coaxial
        // cones: the best cone of each band is 2.3–2.9 mm RMS off it, about axes 40°
        // apart. The noise item of issue 37.)
        "cylinder-noisy",
        "cone-noisy",
    ] {
        let (_, truth, r) = load_as(name, |a| a.back_side = BackSide::Revolve);
        let revolution = r.revolution.as_ref().unwrap_or_else(|| panic!("{name}: not closed"));
        let (angle, worst, height, axis, bands, true_bands) = revolution_errors(name, &truth, revolution);
        println!(
            "{name}: axis {angle:.3}° off, radii and band heights within {:.3} % of the height, fit rms {:?}, \
             silhouette angles {:?}",
            100.0 * worst / height,
            revolution.bands.iter().map(|b| b.fit_rms_relative).collect::<Vec<_>>(),
            revolution
                .bands
                .iter()
                .map(|b| b.silhouette_angle_degrees)
                .collect::<Vec<_>>()
        );
        // Drawings with 1 px of noise: within 5 % and 3° (the noise item of issue 37 is
        // open: `cone-noisy`'s visible half is itself 4.3 % off in shape).
        let (angle_bound, bound) = if name.ends_with("noisy") {
            (3.0, 0.05)
        } else {
            (0.5, 0.01)
        };
        assert!(angle < angle_bound, "{name}: the axis is {angle}° off the truth's");
        assert!(worst < bound * height, "{name}: {bands:?} against {true_bands:?}");
        // Closed round the axis, exactly developable.
        let mesh = &r.mesh;
        let mut edge_faces: std::collections::HashMap<(u32, u32), Vec<usize>> = Default::default();
        for (f, t) in mesh.triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                edge_faces.entry((a.min(b), a.max(b))).or_default().push(f);
            }
        }
        let axis_point = Vec3::from(revolution.axis_point);
        let along = |v: u32| (mesh.positions[v as usize] - axis_point).dot(&axis);
        let (lowest, highest) = (bands[0].0[0], bands.last().unwrap().0[1]);
        for (&(a, b), faces) in &edge_faces {
            if faces.len() == 1 {
                let outer = |v| {
                    let z = along(v);
                    (z - lowest).abs() < 1e-9 * height || (z - highest).abs() < 1e-9 * height
                };
                assert!(outer(a) && outer(b), "{name}: an open edge inside the whole object");
            } else {
                assert_eq!(faces.len(), 2, "{name}");
            }
        }
        let normal = |f: usize| {
            let [p, q, s] = mesh.triangles[f].map(|v| mesh.positions[v as usize]);
            (q - p).cross(&(s - p)).normalize()
        };
        let radial = |v: u32| {
            let d = mesh.positions[v as usize] - axis_point;
            (d - axis * d.dot(&axis)).normalize()
        };
        let mut diagonals = 0;
        for &[a, c] in &mesh.bending_edges {
            let faces = &edge_faces[&(a.min(c), a.max(c))];
            // The diagonal of a quad between two rulings (not a meridian edge, where the
            // band bends).
            if radial(a).dot(&radial(c)) < 1.0 - 1e-12 {
                diagonals += 1;
                assert_eq!(faces.len(), 2, "{name}");
                let sine = normal(faces[0]).cross(&normal(faces[1])).norm();
                assert!(sine < 1e-9, "{name}: a quad between rulings folds by {sine:e}");
            }
        }
        assert_eq!(diagonals, mesh.triangles.len() / 2, "{name}: every quad checked");
        assert_eq!(
            revolution.seam_edges.len(),
            bands.len(),
            "{name}: one seam ruling per band"
        );
    }
}

/// Property test over random views (issue 37): 24 exact cylinders, cones and
/// cylinders on cones drawn by `tools/photo_random_views.py` with a fixed seed (random
/// sizes, elevation 15–50°, any azimuth, roll, symmetry plane, orthographic or
/// perspective at 35–65° of field). Every view is reconstructed, developable, with every
/// depth fixed, within the figures of its truth; its bands closed round their
/// axis are the truth's cones.
#[test]
fn random_views_of_exact_developables_are_reconstructed() {
    let failures = random_views(2029, 24, &[]);
    assert!(
        failures.is_empty(),
        "{} views failed:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// The same random views with the examples' annotation noise (`add_noise`, σ = 1 and
/// 2 px, and 1 px on the curves only, the symmetry marks exact): figures for
/// docs/benchmarks-history.md, not a test (the noise item is open):
/// `cargo test --release -p sheetform-photo --test synthetic_truth noisy_random_views --
/// --ignored --nocapture`.
#[test]
#[ignore = "figures of the open noise item, printed for docs/benchmarks-history.md"]
fn noisy_random_views_figures() {
    for (label, extra) in [
        ("σ = 1 px", &["--noise", "1"][..]),
        ("σ = 2 px", &["--noise", "2"][..]),
        ("σ = 1 px on the curves only", &["--noise", "1", "--exact-marks"][..]),
    ] {
        let failures = random_views(2029, 24, extra);
        println!(
            "{label}: {} views out of the bounds:\n{}",
            failures.len(),
            failures.join("\n")
        );
    }
}

/// The random views with 1 px of annotation noise (`add_noise`: nodes moved, handles slid,
/// C¹ joins kept) are all reconstructed: before the curves leaving a node were ordered
/// along longer chords, small loops cut out of a face's outline and grazing tails of up
/// to four times the graze distance trimmed, 4 of these 24 were refused ("closes no
/// cycle": a noisy silhouette crossing its rim a pixel or two from their node). Each is
/// refined to exact developability (the refinement's bound): before its steps became
/// projections once Gauss–Newton stopped halving the violation, and ends that hop back
/// to the half-edge they left stayed at the join, 4 of them ended at 1e-4 to 0.07 rad
/// (`not developable`, exit 5), and 6 of the 22 reconstructed at 2 px. At 2 px two more
/// were refused ("closes no cycle"): a rim bulging past its silhouette and crossing it
/// again, two segments between the same two nodes whose order was left to chance; they
/// are now told apart, and the sliver between them is no patch. Each view has the truth's
/// surface patches, no more. How close they come is the open noise item
/// (`noisy_random_views_figures`).
#[test]
fn noisy_random_views_are_all_reconstructed_and_refined() {
    for sigma in ["1", "2"] {
        let dir = drawn_random_views(2029, 24, &["--noise", sigma]);
        let mut failures = Vec::new();
        for k in 0..24 {
            let read = |stem: &str| std::fs::read_to_string(dir.path().join(format!("{stem}.json"))).unwrap();
            let annotation = PhotoAnnotation::from_json(&read(&format!("view-{k:02}"))).unwrap();
            let truth: Value = serde_json::from_str(&read(&format!("view-{k:02}.truth"))).unwrap();
            match reconstruct(&annotation) {
                Ok(r) => {
                    let refinement = r.refinement.expect("refined");
                    if !refinement.converged {
                        failures.push(format!("view-{k:02}: {refinement:?}"));
                    }
                    let surfaces = r.patches.iter().filter(|p| !p.opening).count();
                    let expected = truth["patches"].as_array().unwrap().len();
                    if surfaces != expected {
                        failures.push(format!(
                            "view-{k:02}: {surfaces} surface patches, the truth has {expected}"
                        ));
                    }
                }
                Err(e) => failures.push(format!("view-{k:02}: {e}")),
            }
        }
        assert!(failures.is_empty(), "σ = {sigma} px:\n{}", failures.join("\n"));
    }
}

/// `count` random views drawn by `tools/photo_random_views.py` (seed `seed`; `extra`:
/// its noise options) in a new temporary directory: `view-KK.json` and
/// `view-KK.truth.json` each.
fn drawn_random_views(seed: u64, count: usize, extra: &[&str]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let script = examples().join("../../tools/photo_random_views.py");
    let done = std::process::Command::new("python3")
        .arg(&script)
        .arg(seed.to_string())
        .arg(count.to_string())
        .arg(dir.path())
        .args(extra)
        .output()
        .expect("python3 runs");
    assert!(done.status.success(), "{}", String::from_utf8_lossy(&done.stderr));
    dir
}

/// Reconstructs `count` random views (seed `seed`; `extra`: the generator's noise
/// options) as they are and closed round their axis; what is out of the bounds, one line
/// each.
fn random_views(seed: u64, count: usize, extra: &[&str]) -> Vec<String> {
    let dir = drawn_random_views(seed, count, extra);
    let mut failures = Vec::new();
    for k in 0..count {
        let name = format!("view-{k:02}");
        let read = |stem: &str| std::fs::read_to_string(dir.path().join(format!("{stem}.json"))).unwrap();
        let annotation = PhotoAnnotation::from_json(&read(&name)).unwrap();
        let truth: Value = serde_json::from_str(&read(&format!("{name}.truth"))).unwrap();
        let what = format!(
            "{name} ({} {}, elevation {:.0}°)",
            truth["model_kind"].as_str().unwrap(),
            truth["variant"].as_str().unwrap(),
            truth["camera"]["elevation_deg"].as_f64().unwrap()
        );
        let r = match reconstruct(&annotation) {
            Ok(r) => r,
            Err(e) => {
                failures.push(format!("{what}: {e}"));
                continue;
            }
        };
        let converged = r.refinement.is_none_or(|i| i.converged);
        let undetermined = r.depth_undetermined_curves();
        let (shape, size) = shape_and_size_errors_of((annotation.clone(), truth.clone(), r));
        println!(
            "{what}: converged {converged}, depth undetermined {undetermined:?}, shape {:.2} % of the height, size {:.2} %",
            100.0 * shape,
            100.0 * size
        );
        // The 1 % of the height, met by every orthographic view (at most 0.34 %);
        // perspective cones reach 2.2 % (the cone item is open), perspective
        // cylinders and composites 1.4 %.
        let perspective = truth["variant"] == "perspective";
        let shape_bound = if perspective { 0.025 } else { 0.01 };
        if !converged || !undetermined.is_empty() || shape > shape_bound || size > 0.01 {
            failures.push(format!(
                "{what}: shape {shape:.4}, size {size:.4}, converged {converged}, {undetermined:?}"
            ));
        }
        // Closed round its axis: the truth's cones to 1 % of the height.
        let mut whole = annotation.clone();
        whole.back_side = BackSide::Revolve;
        match reconstruct(&whole) {
            Ok(r) => {
                let (angle, worst, height, ..) = revolution_errors(&name, &truth, r.revolution.as_ref().unwrap());
                println!(
                    "    closed: axis {angle:.2}° off, bands within {:.2} % of the height",
                    100.0 * worst / height
                );
                if angle > 1.0 || worst > 0.01 * height {
                    failures.push(format!("{what} closed: axis {angle:.2}°, bands {:.4}", worst / height));
                }
            }
            Err(e) => failures.push(format!("{what} closed: {e}")),
        }
    }
    failures
}

/// Issue 37: without a focal length (none given, no EXIF), a perspective drawing's focal
/// length is estimated from the drawing, as the one whose linear solve leaves the
/// rulings most nearly developable. On the three bundled perspective views it comes
/// within 7 % of the true 514.7 px (0.974, 1.024, 1.069) and the shape within 1.5 % of
/// the height (1.02-1.13 %; through the true focal length 0.75-1.51 %; taken for an
/// orthographic view, 19-27 %); on the random perspective views (seed 2029) within
/// 16 % and 4.2 % (figures in docs/benchmarks-history.md).
#[test]
fn a_perspective_views_focal_length_is_estimated_from_the_drawing() {
    for name in ["cylinder-perspective", "cone-perspective", "composite-perspective"] {
        let (annotation, truth, r) = load_as(name, |a| a.camera.focal_length_px = None);
        let f = r.focal_length_estimate.expect("estimated").focal_length_px;
        let ms = r.times.focal_length_estimate_ms;
        let true_f = truth["camera"]["focal_px"].as_f64().unwrap();
        let (shape, size) = shape_and_size_errors_of((annotation, truth, r));
        println!(
            "{name}: f {f:.1} px (true {true_f:.1}), shape {:.2} %, size {:.2} %, estimated in {ms:.0} ms",
            100.0 * shape,
            100.0 * size
        );
        assert!((f / true_f - 1.0).abs() < 0.08, "{name}: {f} against {true_f}");
        assert!(shape < 0.015 && size < 0.005, "{name}: shape {shape}, size {size}");
    }
    let dir = drawn_random_views(2029, 24, &[]);
    let mut estimated = 0;
    for k in 0..24 {
        let read = |stem: &str| std::fs::read_to_string(dir.path().join(format!("{stem}.json"))).unwrap();
        let mut annotation = PhotoAnnotation::from_json(&read(&format!("view-{k:02}"))).unwrap();
        let truth: Value = serde_json::from_str(&read(&format!("view-{k:02}.truth"))).unwrap();
        if annotation.camera.focal_length_px.take().is_none() {
            continue;
        }
        let r = reconstruct(&annotation).unwrap_or_else(|e| panic!("view-{k:02}: {e}"));
        let f = r.focal_length_estimate.expect("estimated").focal_length_px;
        let true_f = truth["camera"]["focal_px"].as_f64().unwrap();
        assert!(r.refinement.is_none_or(|i| i.converged), "view-{k:02}");
        let ms = r.times.focal_length_estimate_ms;
        let (shape, _) = shape_and_size_errors_of((annotation, truth, r));
        println!(
            "view-{k:02}: f / truth {:.3}, shape {:.2} %, estimated in {ms:.0} ms",
            f / true_f,
            100.0 * shape
        );
        assert!(
            (f / true_f - 1.0).abs() < 0.2 && shape < 0.05,
            "view-{k:02}: f {f} against {true_f}, shape {shape}"
        );
        estimated += 1;
    }
    assert_eq!(estimated, 11, "the perspective views of seed 2029");
}

//! Issue 37: where a user puts a curve's end must not matter within the stated radii.
//! Every silhouette end of the synthetic views (orthographic and perspective) is moved
//! along the curve it stops on, up to [`knot_snap_radius`] from that curve's node, and
//! along its own line, up to the snap distance past or short of the curve: each drawing
//! keeps the base drawing's patches (the same curves round each), and within 2 px of the
//! node reconstructs with every depth fixed and every ruled patch developable. Before
//! the fix 6-12 of 48 moves along the curve failed per single-patch view and 24-25 of 96
//! on the cylinder on a cone ("depth not fixed"; `tools/photo_point_sweep.py`).

use nalgebra::Vector2;
use serde_json::Value;
use sheetform_photo::{cubic, knot_snap_radius, reconstruct, CurveKind, PhotoAnnotation, PhotoReconstruction};
use std::collections::BTreeSet;
use std::path::PathBuf;

type Vec2 = Vector2<f64>;

fn load(name: &str) -> Value {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../../examples/photo/synthetic/{name}.json"));
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn point(v: &Value) -> Vec2 {
    Vec2::new(v[0].as_f64().unwrap(), v[1].as_f64().unwrap())
}

/// Dense points of a curve's control polygon as cubics (image pixels).
fn polyline(curve: &Value) -> Vec<Vec2> {
    let cps: Vec<Vec2> = curve["control_points"].as_array().unwrap().iter().map(point).collect();
    let mut out = Vec::new();
    for j in 0..(cps.len() - 1) / 3 {
        let b = [cps[3 * j], cps[3 * j + 1], cps[3 * j + 2], cps[3 * j + 3]];
        for i in 0..2_000 {
            out.push(cubic::point(&b, i as f64 / 2_000.0));
        }
    }
    out.push(*cps.last().unwrap());
    out
}

/// The point `distance` pixels of arc length along `curve` from its point nearest `from`
/// (backwards for a negative distance).
fn along(curve: &Value, from: Vec2, distance: f64) -> Vec2 {
    let points = polyline(curve);
    let closed = curve["closed"].as_bool().unwrap_or(false);
    let mut i = (0..points.len())
        .min_by(|&a, &b| (points[a] - from).norm().total_cmp(&(points[b] - from).norm()))
        .unwrap();
    let mut travelled = 0.0;
    while travelled < distance.abs() {
        let j = if distance > 0.0 {
            if i + 1 == points.len() {
                if !closed {
                    break;
                }
                1
            } else {
                i + 1
            }
        } else if i == 0 {
            if !closed {
                break;
            }
            points.len() - 2
        } else {
            i - 1
        };
        travelled += (points[j] - points[i]).norm();
        i = j;
    }
    points[i]
}

/// Sets a straight silhouette's end and its handles on the line to its other end.
fn set_end(silhouette: &mut Value, end: usize, at: Vec2) {
    let cps = silhouette["control_points"].as_array_mut().unwrap();
    let last = cps.len() - 1;
    let index = if end == 0 { 0 } else { last };
    cps[index] = serde_json::json!([at.x, at.y]);
    let (a, b) = (point(&cps[0]), point(&cps[last]));
    for (k, handle) in cps.iter_mut().enumerate().take(last).skip(1) {
        let q = a + (b - a) * (k as f64 / last as f64);
        *handle = serde_json::json!([q.x, q.y]);
    }
}

/// Each patch as the set of the curves round it.
fn topology(r: &PhotoReconstruction) -> BTreeSet<(bool, BTreeSet<String>)> {
    r.patches
        .iter()
        .map(|p| {
            let names = p
                .cycle
                .iter()
                .map(|h| {
                    r.network.curves[r.network.segments[h.segment as usize].curve as usize]
                        .name
                        .clone()
                })
                .collect();
            (p.opening, names)
        })
        .collect()
}

/// Reconstructs and checks the patches; with `exact`, also that every depth is fixed and
/// every ruled patch developable.
fn check(name: &str, what: &str, value: &Value, expected: &BTreeSet<(bool, BTreeSet<String>)>, exact: bool) {
    let annotation = PhotoAnnotation::from_json(&value.to_string()).unwrap();
    let r = reconstruct(&annotation).unwrap_or_else(|e| panic!("{name}, {what}: {e}"));
    assert_eq!(&topology(&r), expected, "{name}, {what}: the patches changed");
    if !exact {
        return;
    }
    assert!(
        r.depth_undetermined_curves().is_empty(),
        "{name}, {what}: depth of {:?} not fixed",
        r.depth_undetermined_curves()
    );
    let refinement = r.refinement.unwrap();
    assert!(refinement.converged, "{name}, {what}: not developable");
}

#[test]
fn silhouette_ends_near_a_node_or_a_curve_keep_the_drawing() {
    for name in [
        "cylinder-ortho",
        "cone-ortho",
        "composite-ortho",
        "cylinder-perspective",
        "cone-perspective",
        "composite-perspective",
    ] {
        let base = load(name);
        let annotation = PhotoAnnotation::from_json(&base.to_string()).unwrap();
        let expected = topology(&reconstruct(&annotation).unwrap());
        let radius = knot_snap_radius(&annotation.lengths());
        let snap = annotation.lengths().snap;
        assert!(radius > 2.5, "{name}: the node radius {radius} px");
        let curves = base["curves"].as_array().unwrap().clone();
        for (k, silhouette) in curves.iter().enumerate() {
            if silhouette["kind"] != serde_json::json!(CurveKind::Silhouette) {
                continue;
            }
            let cps = silhouette["control_points"].as_array().unwrap();
            for end in [0, 1] {
                let (p, other) = if end == 0 {
                    (point(&cps[0]), point(cps.last().unwrap()))
                } else {
                    (point(cps.last().unwrap()), point(&cps[0]))
                };
                // The boundary with a node at the end.
                let host = curves
                    .iter()
                    .filter(|c| c["kind"] == serde_json::json!(CurveKind::Boundary))
                    .min_by(|a, b| {
                        let d = |c: &Value| {
                            c["control_points"]
                                .as_array()
                                .unwrap()
                                .iter()
                                .step_by(3)
                                .map(|q| (point(q) - p).norm())
                                .fold(f64::INFINITY, f64::min)
                        };
                        d(a).total_cmp(&d(b))
                    })
                    .unwrap();
                // Within the node radius the patches stay; within 2 px the model is exact
                // too (at 2.5 px the composite's left side, which only the planar quads
                // from the silhouettes reach, keeps up to 11 % of a depth shift: exit 5).
                for distance in [-2.5, -2.0, -1.5, -1.0, -0.5, 0.5, 1.0, 1.5, 2.0, 2.5] {
                    let mut moved = base.clone();
                    set_end(&mut moved["curves"][k], end, along(host, p, distance));
                    let what = format!(
                        "{} end {end} moved {distance} px along {}",
                        silhouette["name"], host["name"]
                    );
                    check(name, &what, &moved, &expected, f64::abs(distance) <= 2.0);
                }
                let direction = (p - other).normalize();
                for past in [-snap * 0.9, snap * 0.9] {
                    let mut moved = base.clone();
                    set_end(&mut moved["curves"][k], end, p + direction * past);
                    let what = format!("{} end {end} {past:.2} px past its curve", silhouette["name"]);
                    check(name, &what, &moved, &expected, true);
                }
            }
        }
    }
}

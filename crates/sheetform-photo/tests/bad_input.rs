//! Bad annotations get an error naming the curve or field (the CLI turns it into exit
//! code 1 with nothing written).

use serde_json::{json, Value};
use sheetform_photo::{reconstruct, PhotoAnnotation};

fn base() -> Value {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/photo/synthetic/cylinder-ortho.json"
    );
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn error_of(value: &Value) -> String {
    match PhotoAnnotation::from_json(&value.to_string()) {
        Err(e) => e.to_string(),
        Ok(a) => reconstruct(&a)
            .err()
            .map(|e| e.to_string())
            .expect("the annotation must be refused"),
    }
}

fn curve_index(v: &Value, name: &str) -> usize {
    v["curves"]
        .as_array()
        .unwrap()
        .iter()
        .position(|c| c["name"] == name)
        .unwrap()
}

#[test]
fn the_base_annotation_is_valid() {
    let a = PhotoAnnotation::from_json(&base().to_string()).unwrap();
    assert!(reconstruct(&a).is_ok());
}

#[test]
fn a_curve_that_closes_no_cycle_is_named() {
    let mut v = base();
    v["curves"].as_array_mut().unwrap().push(json!({
        "name": "stray", "kind": "boundary",
        "control_points": [[20, 20], [40, 25], [60, 25], [80, 20]]
    }));
    let e = error_of(&v);
    assert!(e.contains("`stray`") && e.contains("closes no cycle"), "{e}");
}

#[test]
fn a_degenerate_symmetry_annotation_is_refused() {
    let mut v = base();
    // Frame images perpendicular: no plane tilt can be recovered.
    v["symmetry"]["frame"] = json!([[[100, 100], [100, 200]], [[100, 100], [200, 100]]]);
    let e = error_of(&v);
    assert!(e.contains("symmetry.frame"), "{e}");
    let mut v = base();
    // A pair along a frame segment: s_z² ≤ 0.
    let f = v["symmetry"]["frame"][0].clone();
    v["symmetry"]["points"] = f;
    let e = error_of(&v);
    assert!(e.contains("symmetry") && e.contains("no real plane normal"), "{e}");
}

#[test]
fn self_intersecting_and_zero_length_curves_are_named() {
    let mut v = base();
    v["curves"].as_array_mut().unwrap().push(json!({
        "name": "loop", "kind": "boundary",
        "control_points": [[10, 50], [35, 50], [65, 50], [90, 50], [100, 30], [70, 10], [50, 10], [40, 40], [50, 60], [50, 90]]
    }));
    let e = error_of(&v);
    assert!(e.contains("`loop`") && e.contains("crosses itself"), "{e}");
    let mut v = base();
    v["curves"].as_array_mut().unwrap().push(json!({
        "name": "dot", "kind": "boundary",
        "control_points": [[10, 10], [10, 10], [10, 10], [10, 10]]
    }));
    let e = error_of(&v);
    assert!(e.contains("`dot`") && e.contains("zero length"), "{e}");
}

#[test]
fn field_ranges_are_checked() {
    let mut v = base();
    v["true_size"]["length"] = json!(0.0);
    assert!(error_of(&v).contains("true_size.length"));
    let mut v = base();
    v["true_size"]["to"] = v["true_size"]["from"].clone();
    assert!(error_of(&v).contains("true_size"));
    let mut v = base();
    v["true_size"]["from"] = json!([1.0, 1.0]);
    let e = error_of(&v);
    assert!(
        e.contains("true_size.from") && e.contains("from the nearest curve"),
        "{e}"
    );
    let mut v = base();
    let k = curve_index(&v, "top");
    v["curves"][k]["control_points"].as_array_mut().unwrap().pop();
    let e = error_of(&v);
    assert!(e.contains("curves[") && e.contains("3k + 1"), "{e}");
    let mut v = base();
    v["image"]["width"] = json!(0);
    assert!(error_of(&v).contains("image"));
    let mut v = base();
    v["analysis"] = json!({"sample_spacing_px": 1e-9});
    assert!(error_of(&v).contains("analysis.sample_spacing_px"));
    let mut v = base();
    v["symmetric_curves"] = json!([["top", "nowhere"]]);
    assert!(error_of(&v).contains("nowhere"));
    let mut v = base();
    v["curves"][0]["control_points"][1] = json!([1e300, 5]);
    assert!(error_of(&v).contains("far outside"));
    let e = error_of(&json!({"image": 3}));
    assert!(e.contains("line 1"), "{e}");
}

/// No spacing a user may set breaks the reconstruction (the ruling ends moved onto new
/// samples once collided with other rulings' ends at some spacings).
#[test]
fn every_allowed_spacing_reconstructs() {
    let (mut converged, mut runs) = (0, 0);
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/photo/");
    for file in ["bench/lamp.json", "coffee-cup.json", "synthetic/composite-noisy.json"] {
        let base: Value = serde_json::from_str(&std::fs::read_to_string(format!("{root}{file}")).unwrap()).unwrap();
        for (sample, ruling) in [
            (None, 3.0),
            (None, 5.2),
            (None, 5.4),
            (Some(1.0), 1.0),
            (Some(1.5), 7.0),
            (Some(4.0), 30.0),
        ] {
            let mut v = base.clone();
            v["analysis"]["ruling_spacing_px"] = json!(ruling);
            if let Some(s) = sample {
                v["analysis"]["sample_spacing_px"] = json!(s);
            }
            let a = PhotoAnnotation::from_json(&v.to_string()).unwrap();
            let r = reconstruct(&a).unwrap_or_else(|e| panic!("{file} {sample:?} {ruling}: {e}"));
            // The refinement may fail to meet its bound on a hard drawing (then the CLI
            // exits 5 and says so), but what it reports must be true.
            let worst = r.ruling_errors_refined.iter().copied().fold(0.0, f64::max);
            let info = r.refinement.expect("refined by default");
            if info.converged {
                assert!(worst < 1e-6, "{file} {sample:?} {ruling}: converged but {worst} rad");
            }
            // The clean drawings converge at every spacing; the noisy composite (a pixel of
            // noise on short mirror pairs, 14° of linear error) does not at every one.
            if !file.contains("noisy") {
                assert!(info.converged, "{file} {sample:?} {ruling}: {worst} rad");
            }
            converged += usize::from(info.converged);
            runs += 1;
        }
    }
    // Today 16 of the 18 (composite-noisy at 5.2-pixel rulings and at 1.5/7 does not).
    assert!(converged + 2 >= runs, "{converged} of {runs} converged");
}

/// A drawing whose lower circle no mirror pair reaches: its depth is free (the cup leaned
/// by 19° until the bottom arc was marked self-symmetric). The reconstruction must name
/// the curves it cannot place, and place them once the mark is there.
#[test]
fn curves_whose_depth_the_drawing_does_not_fix_are_named() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/photo/coffee-cup.json");
    let mut v: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let marked = reconstruct(&PhotoAnnotation::from_json(&v.to_string()).unwrap()).unwrap();
    assert!(marked.depth_undetermined_curves().is_empty());
    v["self_symmetric_curves"] = json!(["rim"]);
    let r = reconstruct(&PhotoAnnotation::from_json(&v.to_string()).unwrap()).unwrap();
    let mut free = r.depth_undetermined_curves();
    free.sort();
    assert_eq!(free, ["bottom", "left-silhouette", "right-silhouette"]);
    // The rim keeps its depth (its sensitivity is 2e-5 of the shift).
    let rim = r.network.curves.iter().position(|c| c.name == "rim").unwrap();
    assert!(r.depth_sensitivity[rim] < 1e-3, "{}", r.depth_sensitivity[rim]);
}

/// The warping table of Eq. 2 is quadratic in the samples of a patch's two chains: a
/// sampling fine enough to exceed `MAX_WARPING_CELLS` (here 0.01 px on the cylinder,
/// finer than the annotation's own bound lets through) is an error naming the spacing,
/// not an allocation of gigabytes.
#[test]
fn a_warping_table_over_its_bound_is_refused() {
    use sheetform_photo::{
        build_curve_network, find_patches, propagate_rulings, sample_curves, PropagationOptions, MAX_WARPING_CELLS,
    };
    let annotation = PhotoAnnotation::from_json(&base().to_string()).unwrap();
    let network = build_curve_network(&annotation).unwrap();
    let patches = find_patches(&network, &annotation).unwrap();
    let options = PropagationOptions {
        ruling_spacing: 5.0,
        smoothness_weight: 1.0,
    };
    // At the annotation's spacing it runs.
    let samples = sample_curves(&network, annotation.lengths().sample);
    assert!(propagate_rulings(&network, &samples, &patches, &options).is_ok());
    let fine = sample_curves(&network, 0.01);
    let longest = fine.parameters.iter().map(Vec::len).max().unwrap();
    assert!(longest * longest > MAX_WARPING_CELLS, "the test must exceed the bound");
    let error = propagate_rulings(&network, &fine, &patches, &options)
        .unwrap_err()
        .to_string();
    assert!(error.contains("analysis.sample_spacing_px"), "{error}");
}

/// Issue 37: the camera's fields are checked and each refusal names its field.
#[test]
fn a_camera_without_a_usable_focal_length_is_refused() {
    for (camera, field, words) in [
        (
            json!({"projection": "perspective", "focal_length_px": 500, "focal_length_35mm": 26}),
            "camera",
            "once",
        ),
        (
            json!({"projection": "perspective", "focal_length_px": 0}),
            "camera.focal_length_px",
            "must be within",
        ),
        (
            json!({"projection": "perspective", "focal_length_px": 1e9}),
            "camera.focal_length_px",
            "must be within",
        ),
        (
            json!({"projection": "perspective", "focal_length_35mm": -26}),
            "camera.focal_length_35mm",
            "must be within",
        ),
        (
            json!({"projection": "perspective", "focal_length_35mm": 26, "principal_point": [900, 10]}),
            "camera.principal_point",
            "must lie in",
        ),
        (json!({"focal_length_px": 500}), "camera.focal_length_px", "perspective"),
    ] {
        let mut v = base();
        v["camera"] = camera.clone();
        let e = error_of(&v);
        assert!(e.contains(field) && e.contains(words), "{camera}: {e}");
    }
    // No focal length anywhere is estimated from the rulings; a drawing without any (every
    // curve a boundary: patches filled, not ruled) is refused naming the camera.
    let mut v = base();
    v["camera"] = json!({"projection": "perspective"});
    for curve in v["curves"].as_array_mut().unwrap() {
        curve["kind"] = json!("boundary");
    }
    let e = error_of(&v);
    assert!(e.contains("camera") && e.contains("ruled patches"), "{e}");
}

/// The 35 mm equivalent and the focal length in pixels it stands for give the same
/// model.
#[test]
fn a_focal_length_in_35mm_film_is_the_same_camera() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/photo/synthetic/cone-perspective.json"
    );
    let v: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let px = v["camera"]["focal_length_px"].as_f64().unwrap();
    let diagonal = 480f64.hypot(480.0);
    let mut film = v.clone();
    film["camera"] = json!({"projection": "perspective",
        "focal_length_35mm": px / diagonal * sheetform_photo::FILM_35MM_DIAGONAL_MM});
    let [a, b] = [v, film].map(|v| reconstruct(&PhotoAnnotation::from_json(&v.to_string()).unwrap()).unwrap());
    let gap = a
        .mesh
        .positions
        .iter()
        .zip(&b.mesh.positions)
        .map(|(p, q)| (p - q).norm())
        .fold(0.0, f64::max);
    assert_eq!(a.mesh.positions.len(), b.mesh.positions.len());
    assert!(gap < 1e-6, "{gap}");
}

/// Issue 37: a silhouette left out was refused naming only the curve it should have met
/// ("closes no cycle near" the middle of the bottom arc); the refusal now says which end
/// is left hanging, and where, so the missing curve can be drawn from there.
#[test]
fn a_missing_silhouette_is_refused_at_the_end_it_leaves_hanging() {
    let mut v = base();
    let k = curve_index(&v, "right-silhouette");
    let end = v["curves"][k]["control_points"]
        .as_array()
        .unwrap()
        .last()
        .unwrap()
        .clone();
    v["curves"].as_array_mut().unwrap().remove(k);
    let e = error_of(&v);
    let at = format!("[{:.1}, {:.1}]", end[0].as_f64().unwrap(), end[1].as_f64().unwrap());
    assert!(
        e.contains("`bottom-front`") && e.contains(&at) && e.contains("missing"),
        "{at}: {e}"
    );
}

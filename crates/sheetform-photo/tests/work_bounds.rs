//! Issue 19: every stage of the photo reconstruction whose work grows faster than its
//! input has a work bound, and a drawing over it is refused with an error naming the
//! field and the limit — before the work, not after minutes of it. Each test builds the
//! smallest case that used to be slow (timings from the release build before the
//! bounds) and checks the message; none measures time.

use nalgebra::Vector2;
use serde_json::{json, Value};
use sheetform_geometry::Polygon;
use sheetform_photo::*;

type Vec2 = Vector2<f64>;

fn annotation(name: &str) -> PhotoAnnotation {
    let path = format!("{}/../../examples/photo/{name}", env!("CARGO_MANIFEST_DIR"));
    PhotoAnnotation::from_json(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// The cylinder's network and patches.
fn cylinder() -> (PhotoAnnotation, CurveNetwork, Vec<Patch>) {
    let a = annotation("synthetic/cylinder-ortho.json");
    let network = build_curve_network(&a).unwrap();
    let patches = find_patches(&network, &a).unwrap();
    (a, network, patches)
}

/// The audit's comb (`comb.py`): one closed boundary running `2 rows` times across the
/// image, marked self-symmetric, sampled every `spacing` pixels.
fn comb(rows: usize, spacing: Option<f64>) -> Value {
    let ys: Vec<f64> = (0..2 * rows)
        .map(|i| 20.0 + 360.0 * i as f64 / (2 * rows - 1) as f64)
        .collect();
    let mut path = vec![[40.0, ys[0]], [540.0, ys[0]]];
    for &y in &ys[1..] {
        let x = path.last().unwrap()[0];
        path.push([x, y]);
        path.push([if x == 540.0 { 80.0 } else { 540.0 }, y]);
    }
    path.push([40.0, ys[ys.len() - 1]]);
    path.push([40.0, ys[0]]);
    let mut points = vec![path[0]];
    for w in path.windows(2) {
        let ([px, py], [qx, qy]) = (w[0], w[1]);
        points.push([px + (qx - px) / 3.0, py + (qy - py) / 3.0]);
        points.push([px + 2.0 * (qx - px) / 3.0, py + 2.0 * (qy - py) / 3.0]);
        points.push([qx, qy]);
    }
    let mut v = json!({
        "name": "comb", "image": {"path": "coffee.png", "width": 600, "height": 400},
        "curves": [{"name": "comb", "kind": "boundary", "closed": true, "control_points": points}],
        "symmetry": {
            "frame": [[[284.26, 165.13], [290.24, 112.77]], [[290.24, 112.77], [240.04, 196.81]]],
            "points": [[183.81, 67.94], [396.68, 157.6]]
        },
        "self_symmetric_curves": ["comb"],
        "true_size": {"from": [100.0, ys[0]], "to": [500.0, ys[0]], "length": 62.0}
    });
    if let Some(s) = spacing {
        v["analysis"] = json!({"sample_spacing_px": s, "ruling_spacing_px": s});
    }
    v
}

/// The mirror correspondences test every sample of a curve against every segment of its
/// partner. The audit's comb (80 rows, 196 000 samples at 0.38 px, 3.8e10 tests) spent
/// 79 s in them and 108 s in all; 20 rows at the finest spacing the annotation allows
/// make 2.6e9 tests, and are refused at once.
#[test]
fn issue_19_comb_correspondences_are_refused_before_the_work() {
    let a = PhotoAnnotation::from_json(&comb(20, Some(0.37)).to_string()).unwrap();
    let error = reconstruct(&a).unwrap_err().to_string();
    assert!(
        error.contains("analysis.sample_spacing_px")
            && error.contains("curve `comb`")
            && error.contains(&format!(
                "at most {}",
                sheetform_geometry::short_number(MAX_CORRESPONDENCE_TESTS as f64)
            )),
        "{error}"
    );
    // At the default spacing the same comb runs.
    let a = PhotoAnnotation::from_json(&comb(4, None).to_string()).unwrap();
    assert!(reconstruct(&a).is_ok());
    // The one-pair function is bounded too.
    let (_, network, _) = cylinder();
    let rim = network.curves.iter().position(|c| c.name == "top").unwrap();
    let fine = sample_curves(&network, 0.004);
    let plane = SymmetryPlane {
        normal: nalgebra::Vector3::new(1.0, 0.0, 0.0),
        point: nalgebra::Vector3::zeros(),
        camera: Camera::orthographic(),
    };
    let error = symmetric_pairs(&network, &fine, rim, rim, &plane)
        .unwrap_err()
        .to_string();
    assert!(error.contains("analysis.sample_spacing_px"), "{error}");
}

/// A closed self-symmetric curve of `n` straight segments round an ellipse, built
/// directly (the annotation caps its control points at 30 000).
fn ring(n: usize) -> CurveNetwork {
    let mut points = Vec::with_capacity(3 * n);
    let at = |k: usize| {
        let a = std::f64::consts::TAU * k as f64 / n as f64;
        Vec2::new(240.0 + 200.0 * a.cos(), 240.0 + 120.0 * a.sin())
    };
    for k in 0..n {
        let (p, q) = (at(k), at(k + 1));
        points.extend([p, p + (q - p) / 3.0, p + (q - p) * (2.0 / 3.0)]);
    }
    let segments = (0..n as u32)
        .map(|k| NetworkSegment {
            points: [3 * k, 3 * k + 1, 3 * k + 2, (3 * k + 3) % (3 * n as u32)],
            curve: 0,
        })
        .collect();
    CurveNetwork {
        points,
        segments,
        curves: vec![NetworkCurve {
            name: "ring".into(),
            kind: CurveKind::Boundary,
            segments: (0..n as u32).collect(),
            closed: true,
        }],
        junction_count: 0,
        occluded_crossing_count: 0,
    }
}

/// The symmetrisation splits curves where their partner's nodes mirror (each node
/// searches every segment) and scores every cyclic map of a closed curve onto its mirror
/// image: quadratic in the segments. A closed curve of 9 000 segments took 108 s and
/// 1.6 GB there (now 3 s); one of 15 000 is refused at once by both steps, and the
/// refused split leaves the network as it was.
#[test]
fn issue_19_symmetrisation_of_a_huge_closed_curve_is_refused() {
    let a = annotation("synthetic/cylinder-ortho.json");
    let plane = SymmetryPlane::from_annotation(&a.symmetry, &Camera::orthographic()).unwrap();
    let network = ring(15_000);
    let x = image_prior(&network, &Camera::orthographic(), 0.0);
    let (mut split, mut split_x) = (network.clone(), x.clone());
    let error = split_at_mirror_nodes(&mut split, &mut split_x, &plane, &[[0, 0]], 1.0)
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("analysis.symmetrize")
            && error.contains("curve `ring` (15000 segments)")
            && error.contains(&format!(
                "at most {}",
                sheetform_geometry::short_number(MAX_MIRROR_SEARCH_EVALUATIONS as f64)
            )),
        "{error}"
    );
    assert!(split == network && split_x == x, "a refused split changes nothing");
    let mut samples = sample_curves(&network, 1000.0);
    let error = symmetrize(&network, &mut samples, &mut [], &plane, &[[0, 0]], &x)
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("analysis.symmetrize")
            && error.contains(&format!(
                "at most {}",
                sheetform_geometry::short_number(MAX_SEGMENT_COMPARISONS as f64)
            )),
        "{error}"
    );
    // A ring of 300 segments goes through both.
    let (mut small, network) = (ring(300), ring(300));
    let mut x = image_prior(&small, &Camera::orthographic(), 0.0);
    split_at_mirror_nodes(&mut small, &mut x, &plane, &[[0, 0]], 1.0).unwrap();
    let mut samples = sample_curves(&small, 10.0);
    symmetrize(&small, &mut samples, &mut [], &plane, &[[0, 0]], &x).unwrap();
    assert_eq!(network.curves[0].segments.len(), 300);
}

/// The cylinder's ruled strip resampled every `spacing` pixels with `count` rulings
/// spread evenly along it.
fn dense_strip(r: &PhotoReconstruction, spacing: f64, count: usize) -> RuledStrip {
    let mut strip = r.strips[0].clone();
    let samples = sample_curves(&r.network, spacing);
    strip.side_a = SampledChain::new(&r.network, &samples, &strip.chain_a);
    strip.side_b = SampledChain::new(&r.network, &samples, &strip.chain_b);
    let (na, nb) = (strip.side_a.len(), strip.side_b.len());
    assert!(na > count && nb > count, "{na} {nb} samples for {count} rulings");
    strip.rulings = (0..count)
        .map(|i| (i * (na - 1) / (count - 1), i * (nb - 1) / (count - 1)))
        .collect();
    strip
}

/// Each refinement iteration is a dense LU of one row per ruling (cubic): 6 000 rulings,
/// which the dense-memory bound lets through, would take about 10 s an iteration and up
/// to 50 iterations, twice. Refused before the first, naming the spacing and how many
/// rulings fit.
#[test]
fn issue_19_refinement_of_too_many_rulings_is_refused() {
    let a = annotation("synthetic/cylinder-ortho.json");
    let r = reconstruct(&a).unwrap();
    let n = r.linear.len();
    let map = MirrorMap::identity(n);
    let many = dense_strip(&r, 0.02, 6_000);
    assert!(
        n * 6_000 + 6_000 * 6_000 <= MAX_DENSE_VALUES,
        "the test must pass the memory bound"
    );
    assert!(5.0 * refinement_iteration_work(n, 6_000) > MAX_REFINEMENT_WORK);
    let error = refine_developability(&r.network, &r.energy, &[many], &r.linear, 1.0, &map)
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("analysis.ruling_spacing_px") && error.contains("6000 rulings") && error.contains("at most"),
        "{error}"
    );
    // 300 rulings refine.
    let few = dense_strip(&r, 0.5, 300);
    let (_, _, info) = refine_developability(&r.network, &r.energy, &[few], &r.linear, 1.0, &map).unwrap();
    assert_eq!(info.constraint_count, 300);
    assert!(!info.work_bound_reached);
}

/// One warping may weigh 20 million cells (about 1.4 s); many patches each under that
/// add up (90 such patches: two minutes). The total is checked before the first: here
/// the cylinder's patch, listed as often as it takes.
#[test]
fn issue_19_warpings_over_their_total_bound_are_refused() {
    let (_, network, patches) = cylinder();
    let samples = sample_curves(&network, 0.06);
    let ruled: Vec<&Patch> = patches.iter().filter(|p| !p.opening).collect();
    let lengths: Vec<usize> = samples.parameters.iter().map(Vec::len).collect();
    let longest = lengths.iter().max().unwrap();
    let copies = MAX_WARPING_CELLS_TOTAL / (longest * longest / 4) + 1;
    let many: Vec<Patch> = (0..copies).map(|_| ruled[0].clone()).collect();
    let options = PropagationOptions {
        ruling_spacing: 5.0,
        smoothness_weight: 1.0,
    };
    let error = propagate_rulings(&network, &samples, &many, &options)
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("analysis.sample_spacing_px")
            && error.contains("of all patches")
            && error.contains(&format!(
                "at most {}",
                sheetform_geometry::short_number(MAX_WARPING_CELLS_TOTAL as f64)
            )),
        "{error}"
    );
}

/// Each ruled strip (a run of rulings inside its patch) keeps copies of its patch's two
/// sampled chains. A patch whose rulings leave it every third time — here the cylinder
/// with a pinhole on every third ruling — makes a strip per run, each holding the whole
/// chains: quadratic memory, bounded over all strips.
#[test]
fn issue_19_strips_over_their_sample_bound_are_refused() {
    let (_, network, patches) = cylinder();
    let options = PropagationOptions {
        ruling_spacing: 1e-9,
        smoothness_weight: 1.0,
    };
    // Side a sampled finely, side b coarsely: many rulings for few warping cells.
    let coarse = sample_curves(&network, 4.0);
    let (strips, _) = propagate_rulings(&network, &coarse, &patches, &options).unwrap();
    let mut samples = sample_curves(&network, 0.2);
    for h in &strips[0].chain_b {
        samples.parameters[h.segment as usize] = coarse.parameters[h.segment as usize].clone();
    }
    let (strips, _) = propagate_rulings(&network, &samples, &patches, &options).unwrap();
    assert_eq!(strips.len(), 1, "the cylinder is one strip");
    let strip = &strips[0];
    // A pinhole at the middle of every third ruling (of those clear of the outline).
    let outline = patches[strip.patch].polygon.outer();
    let clear = |m: Vec2| {
        (0..outline.len()).all(|k| {
            let (p, q) = (outline[k], outline[(k + 1) % outline.len()]);
            let t = ((m - p).dot(&(q - p)) / (q - p).norm_squared()).clamp(0.0, 1.0);
            (p + (q - p) * t - m).norm() > 0.1
        })
    };
    let holes: Vec<Vec<Vec2>> = (0..strip.rulings.len())
        .filter(|i| i % 3 == 1)
        .map(|i| {
            let [a, b] = strip.segment(i);
            0.5 * (a + b)
        })
        .filter(|&m| clear(m))
        .map(|m| {
            let r = 0.01;
            vec![
                m + Vec2::new(-r, -r),
                m + Vec2::new(r, -r),
                m + Vec2::new(r, r),
                m + Vec2::new(-r, r),
            ]
        })
        .collect();
    let holes_count = holes.len();
    let mut patch = patches[strip.patch].clone();
    patch.polygon = Polygon::new(patch.polygon.outer().to_vec(), holes).unwrap();
    let held = strip.side_a.len() + strip.side_b.len();
    let per_patch = holes_count * held;
    let copies = MAX_STRIP_SAMPLES / per_patch + 2;
    let many: Vec<Patch> = (0..copies).map(|_| patch.clone()).collect();
    assert!(
        copies * strip.side_a.len() * strip.side_b.len() <= MAX_WARPING_CELLS_TOTAL,
        "the test must stay under the warping bound"
    );
    let error = propagate_rulings(&network, &samples, &many, &options)
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("analysis.sample_spacing_px")
            && error.contains("ruled strips")
            && error.contains(&format!(
                "at most {}",
                sheetform_geometry::short_number(MAX_STRIP_SAMPLES as f64)
            )),
        "{error}"
    );
}

/// A patch without rulings is filled by a Delaunay refinement (at most 200 000 vertices
/// each) and a Laplace solve; many such patches add up. Bounded below from the patches'
/// areas before any fill: here the cylinder's patch without its rulings, four times, at a
/// fine spacing.
#[test]
fn issue_19_fills_over_their_total_bound_are_refused() {
    let (a, network, patches) = cylinder();
    let spacing = 0.05;
    let samples = sample_curves(&network, spacing);
    let body = patches.iter().find(|p| !p.opening).unwrap();
    let many: Vec<Patch> = (0..4).map(|_| body.clone()).collect();
    let x = image_prior(&network, &Camera::orthographic(), 0.0);
    let error = mesh_patches(&network, &samples, &many, &[], &x, spacing)
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("analysis.sample_spacing_px")
            && error.contains(&format!(
                "more than {}",
                sheetform_geometry::short_number(MAX_FILL_VERTICES as f64)
            )),
        "{error}"
    );
    // One copy at the annotation's spacing fills.
    let lengths = a.lengths();
    let samples = sample_curves(&network, lengths.sample);
    let mesh = mesh_patches(&network, &samples, &many[..1], &[], &x, lengths.sample).unwrap();
    assert!(mesh.fill_vertex_count > 0);
}

//! `sheetform develop` (issue 36): a target, with seams drawn or found automatically,
//! becomes exactly developable pieces, checked on the written model: every vertex inside
//! a piece of the pattern (an interior vertex of the `vt` mesh) has 3D angle sum 2π, the
//! pattern is the model at 1:1, and the model stays near the target.

use crate::common::{example_mesh, grid_obj_in_groups, obj_isometry_error, read_obj, sheetform, write_obj, Obj};
use std::collections::HashMap;

/// The largest distance of the model's vertices from the sphere of `radius` about the
/// origin.
fn farthest_from_sphere(o: &Obj, radius: f64) -> f64 {
    o.v.iter()
        .map(|p| (nalgebra::Vector3::from(*p).norm() - radius).abs())
        .fold(0.0, f64::max)
}

/// The largest |2π − Σ θ| over the pattern's interior vertices (vt indices whose every
/// vt edge has a face on both sides), angles measured on the 3D positions.
fn max_interior_defect(o: &Obj) -> (f64, usize) {
    let mut edge_faces: HashMap<(usize, usize), usize> = HashMap::new();
    for f in &o.faces {
        for k in 0..3 {
            let (a, b) = (f[k].1, f[(k + 1) % 3].1);
            *edge_faces.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    let mut boundary = vec![false; o.vt.len()];
    for (&(a, b), &count) in &edge_faces {
        if count < 2 {
            boundary[a] = true;
            boundary[b] = true;
        }
    }
    let mut sums = vec![0.0; o.vt.len()];
    for f in &o.faces {
        for k in 0..3 {
            let p = |i: usize| nalgebra::Vector3::from(o.v[f[(k + i) % 3].0]);
            let (u, w) = (p(1) - p(0), p(2) - p(0));
            sums[f[k].1] += u.cross(&w).norm().atan2(u.dot(&w));
        }
    }
    let interior: Vec<usize> = (0..o.vt.len()).filter(|&t| !boundary[t] && sums[t] > 0.0).collect();
    let worst = interior
        .iter()
        .map(|&t| (std::f64::consts::TAU - sums[t]).abs())
        .fold(0.0, f64::max);
    (worst, interior.len())
}

#[test]
fn a_sphere_with_gore_seams_becomes_exact_globe_gores() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let mesh = example_mesh("sphere-gore-seams.obj");
    let o = sheetform(&["develop", mesh.to_str().unwrap(), "-o", out.to_str().unwrap(), "-q"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let model = read_obj(&out.join("model.obj"));
    let (defect, interior) = max_interior_defect(&model);
    assert!(interior > 500, "{interior} interior vertices");
    assert!(defect <= 1e-8, "angle defect {defect} rad inside a piece");
    assert!(obj_isometry_error(&model) <= 1e-9, "{}", obj_isometry_error(&model));
    // Globe gores of 30°: within R (1 − cos 15°) of the radius-50 sphere.
    let bound = 50.0 * (1.0 - 15f64.to_radians().cos());
    let off = farthest_from_sphere(&model, 50.0);
    assert!(off <= bound, "{off} > {bound}");
    let report: serde_json::Value = crate::common::report(&out);
    assert_eq!(report["command"], "develop");
    assert_eq!(report["status"], "ok");
    assert_eq!(report["develop"]["piece_count"], 12);
    // The report's distance is at least how far the written model's vertices moved off
    // the sphere (a vertex off the surface by `off` is that far from it at least... up
    // to the target's chord error, 50 (1 − cos 3.75°) = 0.107 mm).
    let hausdorff = report["develop"]["hausdorff_mm"].as_f64().unwrap();
    assert!(hausdorff + 0.11 >= off && hausdorff <= bound, "{hausdorff} vs {off}");
    // Twelve pieces in the pattern: the SVG's cut loops.
    let svg = std::fs::read_to_string(out.join("pattern.svg")).unwrap();
    assert_eq!(crate::common::svg_cut_loops(&svg).len(), 12);
}

#[test]
fn targets_develop_cannot_take_are_refused_naming_the_cause() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    // A closed sphere without seams.
    let text = std::fs::read_to_string(example_mesh("sphere-gore-seams.obj")).unwrap();
    let closed: String = text
        .lines()
        .filter(|l| !l.starts_with("l "))
        .map(|l| format!("{l}\n"))
        .collect();
    let path = dir.path().join("closed.obj");
    std::fs::write(&path, closed).unwrap();
    let o = sheetform(&[
        "develop",
        path.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "-q",
        "--seams",
        "drawn",
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--seams automatic"));
    assert!(!out.exists());
    // A seam that does not run along an edge (vertices 1 and 300 are not neighbours).
    let path = dir.path().join("off.obj");
    std::fs::write(&path, format!("{text}l 1 300\n")).unwrap();
    let o = sheetform(&["develop", path.to_str().unwrap(), "-o", out.to_str().unwrap(), "-q"]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("not an edge of the mesh"), "{stderr}");
    // Options out of range.
    let mesh = example_mesh("sphere-gore-seams.obj");
    for (option, field) in [
        ("--smoothness=-1", "smoothness"),
        ("--tolerance=0", "defect_tolerance"),
        ("--max-iterations=0", "max_iterations"),
        ("--max-pieces=0", "max_pieces"),
        ("--normal-tolerance=91", "normal_tolerance_degrees"),
        ("--max-distance=0", "max_distance"),
        ("--max-distance=200%", "max_distance"),
    ] {
        let o = sheetform(&["develop", mesh.to_str().unwrap(), "-o", out.to_str().unwrap(), option]);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{option}: {stderr}");
        assert!(stderr.contains(field), "{option}: {stderr}");
    }
    assert!(!out.exists());
}

/// The pattern's cut edges (vt edges with a face on one side only), as pairs of 3D
/// vertex indices.
fn cut_edges(o: &Obj) -> Vec<(usize, usize)> {
    let mut edge_faces: HashMap<(usize, usize), (usize, usize, usize)> = HashMap::new();
    for f in &o.faces {
        for k in 0..3 {
            let (a, b) = (f[k], f[(k + 1) % 3]);
            let entry = edge_faces.entry((a.1.min(b.1), a.1.max(b.1))).or_insert((a.0, b.0, 0));
            entry.2 += 1;
        }
    }
    edge_faces.values().filter(|e| e.2 == 1).map(|e| (e.0, e.1)).collect()
}

/// Automatic seams on a closed box: each side whole (no cut across a side's diagonal,
/// where a maker would never cut), the box's corners freed by slits, and the model the
/// box itself (it is developable piecewise already: nothing moves).
#[test]
fn a_closed_box_is_cut_along_its_edges_into_whole_sides() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let mesh = example_mesh("gift-box.obj");
    let o = sheetform(&["develop", mesh.to_str().unwrap(), "-o", out.to_str().unwrap(), "-q"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let model = read_obj(&out.join("model.obj"));
    let target: Vec<nalgebra::Vector3<f64>> = std::fs::read_to_string(&mesh)
        .unwrap()
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| nalgebra::Vector3::from_iterator(l.split_whitespace().map(|x| x.parse::<f64>().unwrap())))
        .collect();
    // The model's vertices (split along the seams) are the box's corners.
    for p in &model.v {
        let moved = target
            .iter()
            .map(|q| (nalgebra::Vector3::from(*p) - q).norm())
            .fold(f64::INFINITY, f64::min);
        assert!(moved < 1e-9, "a box corner moved by {moved}");
    }
    assert!(obj_isometry_error(&model) <= 1e-9);
    let cuts = cut_edges(&model);
    assert!(!cuts.is_empty());
    for (a, b) in cuts {
        let (p, q) = (model.v[a], model.v[b]);
        let differing = (0..3).filter(|&k| (p[k] - q[k]).abs() > 1e-9).count();
        assert_eq!(differing, 1, "a cut across a side, from {p:?} to {q:?}");
    }
    let report: serde_json::Value = crate::common::report(&out);
    assert_eq!(report["status"], "ok");
    assert_eq!(report["develop"]["seams"], "automatic");
    assert_eq!(report["develop"]["hausdorff_mm"], 0.0);
    let pieces = report["develop"]["piece_count"].as_u64().unwrap();
    assert!((2..=6).contains(&pieces), "{pieces} pieces");
    let svg = std::fs::read_to_string(out.join("pattern.svg")).unwrap();
    assert_eq!(crate::common::svg_cut_loops(&svg).len() as u64, pieces);
}

/// Automatic seams on a closed sphere (no seam drawn): at most the budget of pieces,
/// every one exact, the pattern the model at 1:1, and the model near the sphere.
#[test]
fn a_closed_sphere_gets_automatic_seams_and_exact_pieces() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let text = std::fs::read_to_string(example_mesh("sphere-gore-seams.obj")).unwrap();
    let closed: String = text
        .lines()
        .filter(|l| !l.starts_with("l "))
        .map(|l| format!("{l}\n"))
        .collect();
    let path = dir.path().join("sphere.obj");
    std::fs::write(&path, closed).unwrap();
    let o = sheetform(&["develop", path.to_str().unwrap(), "-o", out.to_str().unwrap(), "-q"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let model = read_obj(&out.join("model.obj"));
    let (defect, interior) = max_interior_defect(&model);
    assert!(interior > 500, "{interior} interior vertices");
    assert!(defect <= 1e-8, "angle defect {defect} rad inside a piece");
    assert!(obj_isometry_error(&model) <= 1e-9, "{}", obj_isometry_error(&model));
    // Globe gores or better (the target): within R (1 − cos 15°) = 1.70 mm of
    // the radius-50 sphere, the farthest 12 globe gores are. The default 12 pieces are
    // bands of latitude: 0.38 mm measured (2.3 mm before, in patches).
    let off = farthest_from_sphere(&model, 50.0);
    assert!(
        off <= 50.0 * (1.0 - 15f64.to_radians().cos()),
        "{off} mm off the sphere"
    );
    let report: serde_json::Value = crate::common::report(&out);
    let pieces = report["develop"]["piece_count"].as_u64().unwrap();
    assert!((2..=12).contains(&pieces), "{pieces} pieces");
    let svg = std::fs::read_to_string(out.join("pattern.svg")).unwrap();
    assert!(crate::common::svg_cut_loops(&svg).len() as u64 >= pieces);
    // The distance colour map: each vertex's distance to the target is its offset from
    // the sphere (up to the target's chord error, 0.107 mm), red where it is largest.
    let ply = std::fs::read_to_string(out.join("distance.ply")).unwrap();
    let body = ply.split("end_header\n").nth(1).unwrap();
    let count: usize = ply
        .lines()
        .find_map(|l| l.strip_prefix("element vertex "))
        .unwrap()
        .parse()
        .unwrap();
    assert!(ply.contains("property double distance_mm"));
    let rows: Vec<Vec<f64>> = body
        .lines()
        .take(count)
        .map(|l| l.split_whitespace().map(|x| x.parse().unwrap()).collect())
        .collect();
    let mut largest = (0.0, [0.0; 3]);
    for row in &rows {
        let offset = (nalgebra::Vector3::new(row[0], row[1], row[2]).norm() - 50.0).abs();
        assert!(
            (row[6] - offset).abs() <= 0.11,
            "distance {} at offset {offset}",
            row[6]
        );
        if row[6] > largest.0 {
            largest = (row[6], [row[3], row[4], row[5]]);
        }
    }
    let hausdorff = report["develop"]["hausdorff_mm"].as_f64().unwrap();
    assert!(
        largest.0 > 0.2 && largest.0 <= hausdorff + 1e-9,
        "{} vs {hausdorff}",
        largest.0
    );
    assert!(
        largest.1[0] > 150.0 && largest.1[2] < 100.0,
        "the farthest vertex is {:?}",
        largest.1
    );
    crate::common::validate_glb(&[out.join("distance.glb")]);
}

/// The largest per-vertex distance in `distance.ply` (mm).
fn largest_ply_distance(dir: &std::path::Path) -> f64 {
    let ply = std::fs::read_to_string(dir.join("distance.ply")).unwrap();
    let count: usize = ply
        .lines()
        .find_map(|l| l.strip_prefix("element vertex "))
        .unwrap()
        .parse()
        .unwrap();
    ply.split("end_header\n")
        .nth(1)
        .unwrap()
        .lines()
        .take(count)
        .map(|l| l.split_whitespace().nth(6).unwrap().parse::<f64>().unwrap())
        .fold(0.0, f64::max)
}

/// `--max-distance`: pieces are added until the developed surface is within the bound
/// (the coarse bunny needs several tries), and a bound no budget meets is `out of
/// tolerance`, exit 5, with the closest result written.
#[test]
fn a_distance_bound_adds_pieces_until_it_holds() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = example_mesh("bunny-99.stl");
    let out = dir.path().join("near");
    let o = sheetform(&[
        "develop",
        mesh.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "-q",
        "--max-distance",
        "0.2%",
        "--max-pieces",
        "30",
        // Slits from its cone points (the coarse bunny's tips): without them 30 pieces
        // end at 1.2 %.
        "--cone-angle",
        "5.7",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r: serde_json::Value = crate::common::report(&out);
    let d = &r["develop"];
    let bound = d["max_distance_mm"].as_f64().unwrap();
    let diagonal = d["bounding_box_diagonal_mm"].as_f64().unwrap();
    assert!((bound - 0.002 * diagonal).abs() < 1e-12 * diagonal);
    assert!(d["attempt_count"].as_u64().unwrap() > 1, "{d}");
    assert!(d["hausdorff_mm"].as_f64().unwrap() <= bound);
    assert!(largest_ply_distance(&out) <= bound);
    let model = read_obj(&out.join("model.obj"));
    assert!(max_interior_defect(&model).0 <= 1e-8);

    let out = dir.path().join("far");
    let o = sheetform(&[
        "develop",
        mesh.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--max-distance",
        "0.001%",
        "--max-pieces",
        "4",
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(5), "{stderr}");
    assert!(stderr.contains("--max-pieces"), "{stderr}");
    let r: serde_json::Value = crate::common::report(&out);
    assert_eq!(r["status"], "out of tolerance");
    let d = &r["develop"];
    assert!(d["hausdorff_mm"].as_f64().unwrap() > d["max_distance_mm"].as_f64().unwrap());
    assert!(largest_ply_distance(&out) > d["max_distance_mm"].as_f64().unwrap());
    assert!(out.join("model.obj").exists() && out.join("pattern.svg").exists());
}

/// Issue 36's anchor: GIT (Binninger et al. 2021) brings the coffee cup within 0.5 % of
/// its diagonal in 25 pieces. Under the same bound with a budget of 25, develop's
/// attempts draw their pieces to where the last one was far (the handle, the rim's
/// fillets), and the cup comes out exact within the bound in fewer pieces (13 when
/// written; 1.13 % in 18 printed pieces, out of tolerance, when pieces were placed by their
/// cone fits alone). Read from the written files: the distance map's largest vertex
/// distance, the printed pieces of the `vt` mesh, the model's angle defects.
#[test]
fn the_coffee_cup_comes_within_half_a_percent_in_fewer_pieces_than_git() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = example_mesh("coffee-cup.obj");
    let out = dir.path().join("cup");
    let o = sheetform(&[
        "develop",
        mesh.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "-q",
        "--max-distance",
        "0.5%",
        "--max-pieces",
        "25",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r: serde_json::Value = crate::common::report(&out);
    let d = &r["develop"];
    let diagonal = d["bounding_box_diagonal_mm"].as_f64().unwrap();
    let model = read_obj(&out.join("model.obj"));
    let largest = largest_ply_distance(&out);
    assert!(largest <= 0.005 * diagonal, "{largest} mm of a {diagonal} mm diagonal");
    let pieces = pattern_piece_count(&model);
    assert!(pieces < 25, "{pieces} printed pieces");
    assert!(max_interior_defect(&model).0 <= 1e-8);
}

/// Pieces of the written pattern: connected parts of the `vt` mesh (faces sharing a
/// texture vertex).
fn pattern_piece_count(o: &Obj) -> usize {
    pattern_pieces(o).len()
}

/// The edges a maker cuts and glues, read from the model: edges of the surface (its `v`
/// welded by position) whose two faces give a vertex different `vt`s.
fn cut_edge_count(o: &Obj) -> usize {
    let mut welded: HashMap<[u64; 3], usize> = HashMap::new();
    let point: Vec<usize> =
        o.v.iter()
            .map(|p| {
                let next = welded.len();
                *welded.entry(p.map(f64::to_bits)).or_insert(next)
            })
            .collect();
    let mut sides: HashMap<(usize, usize), Vec<[usize; 2]>> = HashMap::new();
    for f in &o.faces {
        for k in 0..3 {
            let (a, b) = (f[k], f[(k + 1) % 3]);
            let (pa, pb) = (point[a.0], point[b.0]);
            // The side's texture vertices, ordered by the edge's ends.
            let uv = if pa < pb { [a.1, b.1] } else { [b.1, a.1] };
            sides.entry((pa.min(pb), pa.max(pb))).or_default().push(uv);
        }
    }
    sides.values().filter(|s| s.len() == 2 && s[0] != s[1]).count()
}

/// The wing nut (Stein et al.'s flow left cone points of 0.1–0.24 rad): automatic seams
/// and every piece exact. By default its cone points are flattened (no slit, the budget
/// of 12 pieces kept); `--cone-angle 5.7` slits them, which brings it closer to the
/// target but opens wedges that make pieces overlap themselves in the plane, so the
/// unfolding cuts them again: more pieces, each counted in the report as in the files.
/// Before the damped polish and the stall rule it stayed out of tolerance (1.7e-3 rad
/// after 100 steps).
#[test]
fn the_wing_nut_develops_into_exact_pieces() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = example_mesh("wingnut.obj");
    let mut figures = Vec::new();
    for (name, extra) in [("default", &[][..]), ("slits", &["--cone-angle", "5.7"][..])] {
        let out = dir.path().join(name);
        let mut args = vec!["develop", mesh.to_str().unwrap(), "-o", out.to_str().unwrap(), "-q"];
        args.extend_from_slice(extra);
        let o = sheetform(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let model = read_obj(&out.join("model.obj"));
        let (defect, interior) = max_interior_defect(&model);
        assert!(interior > 2000, "{interior} interior vertices");
        assert!(defect <= 1e-8, "angle defect {defect} rad inside a piece");
        assert!(obj_isometry_error(&model) <= 1e-9, "{}", obj_isometry_error(&model));
        let r: serde_json::Value = crate::common::report(&out);
        let d = &r["develop"];
        let pieces = pattern_piece_count(&model);
        assert_eq!(d["piece_count"].as_u64().unwrap() as usize, pieces, "{d}");
        assert_eq!(
            d["seam_piece_count"].as_u64().unwrap() + d["overlap_split_count"].as_u64().unwrap(),
            pieces as u64
        );
        // More printed pieces than the budget (the unfolding's splits) are said so.
        let over_budget = r["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .any(|w| w.as_str().unwrap().contains("more than the 12 of --max-pieces"));
        assert_eq!(over_budget, pieces > 12, "{pieces} pieces: {}", r["warnings"]);
        // The cut edges as drawn, the unfolding's own cuts among them.
        assert_eq!(
            d["seam_edge_count"].as_u64().unwrap() as usize,
            cut_edge_count(&model),
            "{d}"
        );
        figures.push((
            pieces,
            d["slit_count"].as_u64().unwrap(),
            d["hausdorff_relative"].as_f64().unwrap(),
        ));
    }
    let [(pieces, slits, distance), (slit_pieces, more_slits, closer)] = figures[..] else {
        unreachable!()
    };
    assert!(pieces <= 12 && slits == 0 && distance < 0.02, "{figures:?}");
    assert!(more_slits > 0 && closer < 0.01 && slit_pieces > pieces, "{figures:?}");
}

/// The coffee cup (2 142 faces, a handle joined to the wall by a boolean union): where
/// the handle meets the wall the target has saddle vertices (−0.98 rad) that no small
/// move flattens, and the first solve stops with 0.25 rad left inside a piece (measured
/// before the slit rounds: out of tolerance, exit 5, 69 printed pieces). Those vertices
/// get slits and the pieces are solved again: exact, every piece counted. At
/// `--smoothness 1` (steps in the full metric): at the default smoothness the steps' metric
/// is diagonal and its first solve reaches the tolerance without slits (one slit, 19
/// pieces, 1.82 %: session 29), so this case is held where the slit rounds run.
#[test]
fn cone_points_the_solve_leaves_get_slits_and_the_cup_comes_out_exact() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("cup");
    let mesh = example_mesh("coffee-cup.obj");
    let o = sheetform(&[
        "develop",
        mesh.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "-q",
        "--smoothness",
        "1",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let model = read_obj(&out.join("model.obj"));
    let (defect, interior) = max_interior_defect(&model);
    assert!(interior > 500, "{interior} interior vertices");
    assert!(defect <= 1e-8, "angle defect {defect} rad inside a piece");
    assert!(obj_isometry_error(&model) <= 1e-9, "{}", obj_isometry_error(&model));
    let r: serde_json::Value = crate::common::report(&out);
    let d = &r["develop"];
    assert_eq!(r["status"], "ok");
    assert!(d["slit_count"].as_u64().unwrap() > 1, "{d}");
    assert_eq!(
        d["piece_count"].as_u64().unwrap() as usize,
        pattern_piece_count(&model),
        "{d}"
    );
    assert!(d["piece_count"].as_u64().unwrap() <= 30, "{d}");
    assert!(d["hausdorff_relative"].as_f64().unwrap() < 0.02, "{d}");
}

/// `--size`, as `flatten` has it: the pattern scaled so that the model prints at that
/// height (along +y), whatever the file's unit; with `--scale` too it is refused.
#[test]
fn develop_prints_the_model_at_the_height_asked() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = example_mesh("bunny-99.stl");
    let out = dir.path().join("sized");
    let o = sheetform(&[
        "develop",
        mesh.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "-q",
        "--units",
        "m",
        "--size",
        "150",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let model = read_obj(&out.join("model.obj"));
    let (low, high) = model.v.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
        (l.min(p[1]), h.max(p[1]))
    });
    let r: serde_json::Value = crate::common::report(&out);
    // model.obj is in the file's unit (m); the pattern is scaled by `pattern.scale`.
    let printed = (high - low) * 1000.0 * r["pattern"]["scale"].as_f64().unwrap();
    assert!((printed - 150.0).abs() < 1e-6, "{printed} mm");
    let o = sheetform(&[
        "develop",
        mesh.to_str().unwrap(),
        "-o",
        dir.path().join("both").to_str().unwrap(),
        "--size",
        "150",
        "--scale",
        "2",
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("--size") && stderr.contains("not both"), "{stderr}");
}

/// A 100 mm square sheet, 20 × 20 cells, with a bump in the middle (a doubly curved cap
/// of radius 25 mm, 10 mm high) and flat wings at |x| ≥ 30 mm in the OBJ group `wings`.
fn bump_with_wings() -> String {
    let n = 20;
    grid_obj_in_groups(
        n,
        |x, y| {
            let r2 = (x * x + y * y) * (100.0 * 100.0) / (25.0 * 25.0);
            if r2 < 1.0 {
                10.0 * (1.0 - r2) * (1.0 - r2)
            } else {
                0.0
            }
        },
        // Cells whose both columns lie at |x| ≥ 30 mm (the 4 outer columns each side).
        |i, _| Some(if i < 4 || i >= n - 4 { "wings" } else { "middle" }),
    )
}

/// `--fixed GROUP`: the faces of that OBJ group stay where they are (their vertices in
/// model.obj are the input's, exactly), the rest is developed exact around them; without
/// it the same wings move. An unknown group is refused naming the mesh's groups.
#[test]
fn a_fixed_region_stays_where_it_is() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("bump.obj");
    let obj = bump_with_wings();
    std::fs::write(&mesh, &obj).unwrap();
    let points: Vec<[f64; 3]> = obj
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| {
            let c: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
            [c[0], c[1], c[2]]
        })
        .collect();
    let wing = |p: &[f64; 3]| p[0].abs() >= 30.0 - 1e-9;
    let mut moved_wings = Vec::new();
    for (name, extra) in [("free", &[][..]), ("fixed", &["--fixed", "wings"][..])] {
        let out = dir.path().join(name);
        let mut args = vec!["develop", mesh.to_str().unwrap(), "-o", out.to_str().unwrap(), "-q"];
        args.extend_from_slice(extra);
        let o = sheetform(&args);
        assert!(o.status.success(), "{name}: {}", String::from_utf8_lossy(&o.stderr));
        let model = read_obj(&out.join("model.obj"));
        assert!(max_interior_defect(&model).0 <= 1e-8, "{name}");
        assert!(obj_isometry_error(&model) <= 1e-9, "{name}");
        // Each wing vertex's distance to its nearest copy in model.obj (seam vertices
        // have a copy per piece; the grid's 5 mm spacing keeps a moved copy nearest).
        let moved = points
            .iter()
            .filter(|p| wing(p))
            .map(|p| {
                model
                    .v
                    .iter()
                    .map(|q| (0..3).map(|k| (p[k] - q[k]).abs()).fold(0.0, f64::max))
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max);
        moved_wings.push(moved);
        let r: serde_json::Value = crate::common::report(&out);
        // An open target: its own border is no seam; the cut edges as drawn.
        assert_eq!(
            r["develop"]["seam_edge_count"].as_u64().unwrap() as usize,
            cut_edge_count(&model),
            "{name}: {}",
            r["develop"]
        );
        let fixed = r["develop"]["fixed_vertex_count"].as_u64().unwrap() as usize;
        assert_eq!(
            fixed,
            if name == "fixed" {
                points.iter().filter(|p| wing(p)).count()
            } else {
                0
            }
        );
    }
    assert!(moved_wings[0] > 1e-3, "the free run moves the wings: {moved_wings:?}");
    assert_eq!(moved_wings[1], 0.0, "{moved_wings:?}");
    let o = sheetform(&[
        "develop",
        mesh.to_str().unwrap(),
        "-o",
        dir.path().join("unknown").to_str().unwrap(),
        "--fixed",
        "flange",
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("`flange`") && stderr.contains("`wings`"), "{stderr}");
}

/// `--sheet`: with automatic seams, a piece too large for the sheet asks for more pieces
/// until every one fits (the sheets are written); when no budget makes them fit, the
/// pattern is written without the sheets and the status is `out of tolerance` (exit 5).
#[test]
fn pieces_are_added_until_they_fit_the_sheet() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = example_mesh("bunny-99.stl");
    let run = |sheet: &str, out: &std::path::Path| {
        sheetform(&[
            "develop",
            mesh.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "-q",
            "--units",
            "m",
            "--max-pieces",
            "30",
            "--max-distance",
            "5%",
            "--sheet",
            sheet,
        ])
    };
    let report = crate::common::report;
    let loose = dir.path().join("loose");
    let o = sheetform(&[
        "develop",
        mesh.to_str().unwrap(),
        "-o",
        loose.to_str().unwrap(),
        "-q",
        "--units",
        "m",
        "--max-pieces",
        "30",
        "--max-distance",
        "5%",
    ]);
    assert!(o.status.success());
    let without_sheet = report(&loose)["develop"]["piece_count"].as_u64().unwrap();

    let fitted = dir.path().join("fitted");
    let o = run("150x150", &fitted);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let d = &report(&fitted)["develop"];
    assert_eq!(d["pieces_fit_sheet"], true);
    assert!(d["piece_count"].as_u64().unwrap() > without_sheet, "{d}");
    let sheets: Vec<_> = std::fs::read_dir(fitted.join("sheets")).unwrap().collect();
    assert!(!sheets.is_empty());
    // Every sheet is the size asked for.
    for sheet in sheets {
        let path = sheet.unwrap().path();
        if path.extension().is_some_and(|e| e == "svg") {
            let svg = std::fs::read_to_string(&path).unwrap();
            assert!(
                svg.contains("width=\"150.0000mm\" height=\"150.0000mm\""),
                "{}",
                path.display()
            );
        }
    }

    let tight = dir.path().join("tight");
    let o = run("100x100", &tight);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(5), "{stderr}");
    assert!(stderr.contains("does not fit on the sheet"), "{stderr}");
    let r = report(&tight);
    assert_eq!(r["status"], "out of tolerance");
    assert_eq!(r["develop"]["pieces_fit_sheet"], false);
    assert!(tight.join("pattern.svg").exists() && !tight.join("sheets").exists());
}

/// A target finer than `--work-faces` (a scan) is remeshed first: a 20 480-face sphere
/// developed on about 2 000 even faces, the model written with those faces, every piece
/// exact, the pattern the model at 1:1, the model near the sphere as given, and the
/// report giving both face counts. A working size under the minimum is refused by name.
#[test]
fn a_fine_target_is_remeshed_to_its_working_size() {
    let dir = tempfile::tempdir().unwrap();
    let sphere = sheetform::mesh::primitives::icosphere(50.0, 5);
    let path = write_obj(dir.path(), "fine-sphere", &sphere);
    let out = dir.path().join("out");
    let o = sheetform(&[
        "develop",
        path.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--work-faces",
        "2000",
        "-q",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let model = read_obj(&out.join("model.obj"));
    let faces = model.faces.len();
    assert!((1_500..=2_800).contains(&faces), "{faces} faces written");
    let r = crate::common::report(&out);
    assert_eq!(r["develop"]["target_face_count"], 20_480);
    assert_eq!(r["develop"]["work_face_count"].as_u64().unwrap() as usize, faces);
    let (defect, interior) = max_interior_defect(&model);
    assert!(interior > 300, "{interior} interior vertices");
    assert!(defect <= 1e-8, "angle defect {defect} rad inside a piece");
    assert!(obj_isometry_error(&model) <= 1e-9, "{}", obj_isometry_error(&model));
    let off = farthest_from_sphere(&model, 50.0);
    // Measured to the sphere as given (20 480 faces, chord error 0.02 mm), not to the
    // working mesh: no vertex farther than the report's Hausdorff distance says.
    let hausdorff = r["develop"]["hausdorff_mm"].as_f64().unwrap();
    assert!(
        off <= hausdorff + 0.05,
        "{off} mm off the sphere, Hausdorff {hausdorff}"
    );
    assert!(
        r["develop"]["hausdorff_relative"].as_f64().unwrap() <= 0.025,
        "{}",
        r["develop"]
    );
    let o = sheetform(&[
        "develop",
        path.to_str().unwrap(),
        "-o",
        dir.path().join("refused").to_str().unwrap(),
        "--work-faces",
        "10",
    ]);
    assert!(!o.status.success());
    let message = String::from_utf8_lossy(&o.stderr);
    assert!(
        message.contains("work_faces") || message.contains("work-faces"),
        "{message}"
    );
}

/// The pattern pieces of `o` (faces joined through shared texture vertices): for each,
/// the 3D positions of its vertices.
fn pattern_pieces(o: &Obj) -> Vec<Vec<[f64; 3]>> {
    let mut parts = sheetform::mesh::UnionFind::new(o.vt.len());
    for f in &o.faces {
        for k in 1..3 {
            parts.union(f[0].1 as u32, f[k].1 as u32);
        }
    }
    let mut pieces: HashMap<u32, Vec<[f64; 3]>> = HashMap::new();
    for f in &o.faces {
        let root = parts.find(f[0].1 as u32);
        pieces.entry(root).or_default().extend(f.iter().map(|c| o.v[c.0]));
    }
    pieces.into_values().collect()
}

/// `--mirror x`: a target symmetric in x = 0 (an icosphere bent and tapered in y and z
/// only) develops into exact pieces whose model is its own mirror image vertex for vertex;
/// each pattern piece is the mirror image of another or of itself, and one piece runs
/// across the plane (no seam is forced there). A half model (only x ≥ 0, its cut on the
/// plane) with `--mirror x=0` comes back whole and exact.
#[test]
fn a_mirror_plane_is_kept_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let mut target = sheetform::mesh::primitives::icosphere(40.0, 3);
    for p in &mut target.positions {
        let (x, y, z) = (p.x, p.y, p.z);
        *p = nalgebra::Vector3::new(x * (1.0 + 0.25 * z / 40.0), 0.7 * y + 0.15 * z * z / 40.0, 1.3 * z);
    }
    let path = crate::common::write_obj(dir.path(), "bent.obj", &target);
    let out = dir.path().join("mirrored");
    let o = sheetform(&[
        "develop",
        path.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--mirror",
        "x",
        "-q",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report = crate::common::report(&out);
    assert_eq!(report["status"], "ok");
    assert_eq!(report["develop"]["mirror_plane"], "x = 0");
    assert!(report["develop"]["mirror_asymmetry_relative"].as_f64().unwrap() < 1e-9);
    assert!(report["develop"]["mirror_seam"].is_boolean() && report.get("warnings").is_none());
    let model = read_obj(&out.join("model.obj"));
    let (defect, interior) = max_interior_defect(&model);
    assert!(interior > 300, "{interior} interior vertices");
    assert!(defect <= 1e-8, "angle defect {defect} rad inside a piece");
    assert!(obj_isometry_error(&model) <= 1e-9, "{}", obj_isometry_error(&model));
    // Symmetric vertex for vertex: every vertex's mirror image is a vertex.
    let mirrored = |p: &[f64; 3]| [-p[0], p[1], p[2]];
    let near = |a: &[f64; 3], b: &[f64; 3]| (0..3).all(|i| (a[i] - b[i]).abs() <= 1e-9);
    for p in &model.v {
        let q = mirrored(p);
        assert!(model.v.iter().any(|r| near(r, &q)), "{p:?} has no mirror image");
    }
    // Pieces in mirrored pairs (or symmetric themselves): matched by their vertex sets.
    let pieces = pattern_pieces(&model);
    let key = |points: &[[f64; 3]]| {
        let mut keys: Vec<[i64; 3]> = points.iter().map(|p| p.map(|c| (c * 1e6).round() as i64)).collect();
        keys.sort_unstable();
        keys.dedup();
        keys
    };
    let keys: Vec<Vec<[i64; 3]>> = pieces.iter().map(|p| key(p)).collect();
    let mut crossing = 0;
    for piece in &pieces {
        let image: Vec<[f64; 3]> = piece.iter().map(mirrored).collect();
        assert!(keys.contains(&key(&image)), "a piece without its mirror image");
        let (low, high) = piece
            .iter()
            .fold((f64::MAX, f64::MIN), |(l, h), p| (l.min(p[0]), h.max(p[0])));
        if low < -1.0 && high > 1.0 {
            crossing += 1;
        }
    }
    assert!(crossing >= 1, "no piece crosses the plane");
    let count = report["develop"]["piece_count"].as_u64().unwrap() as usize;
    assert_eq!(count, pieces.len());
    assert!(count <= 12, "{count} pieces");
    // Close to the target: the bent sphere within 3 % of its diagonal.
    let hausdorff = report["develop"]["hausdorff_relative"].as_f64().unwrap();
    assert!(hausdorff < 0.03, "{hausdorff}");

    // A half model: a saddle over x in [0, 40], its cut exported a hair off x = 0 (at
    // 1e-6: it came back as two halves, each moved on its own, before the cut's
    // boundary was snapped).
    let saddle = sheetform::mesh::TriangleMesh::grid(12, 18, |u, v| {
        let (x, y) = (40.0 * u, 60.0 * v - 30.0);
        [if x == 0.0 { 1e-6 } else { x }, y, (x * x - y * y) / 80.0]
    });
    let path = crate::common::write_obj(dir.path(), "half-saddle.obj", &saddle);
    let out = dir.path().join("whole");
    let o = sheetform(&[
        "develop",
        path.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--mirror",
        "x=0",
        "--max-distance",
        "1%",
        "-q",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let model = read_obj(&out.join("model.obj"));
    // One sheet: every vertex on x = 0 is shared by the two sides' faces.
    let on_plane_faces = model
        .faces
        .iter()
        .filter(|f| f.iter().any(|c| model.v[c.0][0] == 0.0))
        .count();
    assert!(on_plane_faces >= 36, "{on_plane_faces} faces touch the plane");
    let sides = |i: usize| model.faces.iter().any(|f| f.iter().any(|c| c.0 == i)) as usize;
    assert!(model
        .v
        .iter()
        .enumerate()
        .filter(|(_, p)| p[0] == 0.0)
        .all(|(i, _)| sides(i) == 1));
    let (defect, interior) = max_interior_defect(&model);
    assert!(
        defect <= 1e-8 && interior > 200,
        "{defect} rad over {interior} vertices"
    );
    assert!(obj_isometry_error(&model) <= 1e-9);
    let (low, high) = model
        .v
        .iter()
        .fold((f64::MAX, f64::MIN), |(l, h), p| (l.min(p[0]), h.max(p[0])));
    assert!(
        (low + 40.0).abs() < 1.0 && (high - 40.0).abs() < 1.0,
        "x from {low} to {high}"
    );
    // Completed by its image: distances are to both halves (the 1 % bound holds; to the
    // half alone it was 57 %, out of tolerance), and it is symmetric by construction.
    let report = crate::common::report(&out);
    assert_eq!(report["status"], "ok");
    assert!(report["develop"]["hausdorff_relative"].as_f64().unwrap() <= 0.01);
    assert_eq!(report["develop"]["mirror_asymmetry_relative"], 0.0);
    assert!(report.get("warnings").is_none(), "{}", report["warnings"]);

    // A target 7.5 % of its size from symmetric: warned (the result repeats one half).
    let whole_saddle = sheetform::mesh::TriangleMesh::grid(16, 12, |u, v| {
        let (x, y) = (80.0 * u - 40.0, 60.0 * v - 30.0);
        [x, y, (x * x - y * y) / 80.0 + 0.1 * x]
    });
    let path = crate::common::write_obj(dir.path(), "saddle.obj", &whole_saddle);
    let out = dir.path().join("saddle");
    let o = sheetform(&[
        "develop",
        path.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--mirror",
        "x",
        "-q",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let warnings = crate::common::report(&out)["warnings"].to_string();
    assert!(warnings.contains("from symmetric in the plane x = 0"), "{warnings}");

    // The cup about its handle's plane under a 1 % bound: the centre seam is kept (pieces
    // across the plane met the bound with 100 slits and printed 60 pieces from 4), and
    // the bound holds with few printed pieces (without a mirror it ends out of
    // tolerance at 1.33 %).
    let out = dir.path().join("cup");
    let cup = example_mesh("coffee-cup.obj");
    let o = sheetform(&[
        "develop",
        cup.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--mirror",
        "y",
        "--max-distance",
        "1%",
        "-q",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report = crate::common::report(&out);
    let model = read_obj(&out.join("model.obj"));
    let printed = pattern_pieces(&model).len();
    assert!(printed <= 20, "{printed} printed pieces");
    assert!(report["develop"]["hausdorff_relative"].as_f64().unwrap() <= 0.01);
    assert!(max_interior_defect(&model).0 <= 1e-8);

    // Refused, naming the option.
    for bad in ["w", "x=abc", "x=inf"] {
        let o = sheetform(&[
            "develop",
            path.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--mirror",
            bad,
        ]);
        assert_eq!(o.status.code(), Some(2), "{bad}");
        assert!(String::from_utf8_lossy(&o.stderr).contains("--mirror"), "{bad}");
    }
}

/// Corners of the printed cut loops (pattern.svg's cut layer) where the cut turns by
/// more than 30°, and the loops' total length (mm).
fn cut_corners(svg: &str) -> (usize, f64) {
    let mut corners = 0;
    let mut length = 0.0;
    for mut points in crate::common::svg_cut_loops(svg) {
        if points.len() > 1 && points.first() == points.last() {
            points.pop();
        }
        let n = points.len();
        for i in 0..n {
            let [a, b, c] = [points[(i + n - 1) % n], points[i], points[(i + 1) % n]];
            let (u, w) = ([b[0] - a[0], b[1] - a[1]], [c[0] - b[0], c[1] - b[1]]);
            length += w[0].hypot(w[1]);
            let turn = (u[0] * w[1] - u[1] * w[0]).atan2(u[0] * w[0] + u[1] * w[1]).abs();
            if turn > 30f64.to_radians() {
                corners += 1;
            }
        }
    }
    (corners, length)
}

#[test]
fn automatic_seams_are_cut_along_smooth_curves() {
    // An icosphere's automatic seams run along its edges in steps (its edges run in no
    // band's direction); slid onto smooth curves they print with far fewer corners and
    // a shorter cut, the pieces as exact and as close (measured on trimesh's icosphere at
    // 200 mm: 440 → 64 corners, cut 11.5 → 10.6 m, Hausdorff 0.75 → 0.76 %).
    let dir = tempfile::tempdir().unwrap();
    let path = write_obj(dir.path(), "sphere", &sheetform::mesh::primitives::icosphere(50.0, 3));
    let run = |name: &str, sweeps: &str| {
        let out = dir.path().join(name);
        let o = sheetform(&[
            "develop",
            path.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--tabs",
            "none",
            "--seam-smoothing",
            sweeps,
            "-q",
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let model = read_obj(&out.join("model.obj"));
        assert!(max_interior_defect(&model).0 <= 1e-8);
        assert!(obj_isometry_error(&model) <= 1e-9);
        let svg = std::fs::read_to_string(out.join("pattern.svg")).unwrap();
        let report = crate::common::report(&out);
        let hausdorff = report["develop"]["hausdorff_relative"].as_f64().unwrap();
        let moved = report["develop"]["seam_smoothed_vertex_count"].as_u64().unwrap();
        (cut_corners(&svg), hausdorff, farthest_from_sphere(&model, 50.0), moved)
    };
    let ((stepped, stepped_length), stepped_distance, _, none) = run("stepped", "0");
    let ((smooth, smooth_length), smooth_distance, off, moved) = run("smooth", "6");
    assert_eq!(none, 0);
    assert!(moved > 50, "{moved} seam vertices smoothed");
    assert!(smooth * 3 < stepped, "{stepped} → {smooth} corners");
    assert!(
        smooth_length < 0.97 * stepped_length,
        "cut {stepped_length} → {smooth_length} mm"
    );
    assert!(
        smooth_distance <= 1.1 * stepped_distance,
        "{stepped_distance} → {smooth_distance}"
    );
    assert!(
        off <= 50.0 * (1.0 - 15f64.to_radians().cos()),
        "{off} mm off the sphere"
    );
}

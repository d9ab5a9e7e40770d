//! Edge unfolding into nets on the shapes a maker tries first.

use sheetform_flatten::{unfold_net, Net, NetOptions};
use sheetform_geometry::triangles_overlap;
use sheetform_mesh::{primitives, TriangleMesh};

fn wingnut() -> TriangleMesh {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/meshes/wingnut.obj");
    let mut mesh = sheetform_io::read_mesh(std::path::Path::new(path)).unwrap();
    mesh.weld(1e-9);
    mesh
}

/// Every piece an exact copy of its faces, no two faces of a piece overlapping, every
/// face in exactly one piece.
fn assert_exact_and_overlap_free(mesh: &TriangleMesh, net: &Net) {
    let mut seen = vec![0; mesh.triangles.len()];
    for piece in &net.pieces {
        assert!(
            piece.distortion.edge_length_max_relative < 1e-10,
            "{:?}",
            piece.distortion
        );
        assert!(piece.distortion.is_overlap_free(), "{:?}", piece.distortion);
        let mut tris: Vec<[_; 3]> = piece
            .triangles
            .iter()
            .map(|t| t.map(|v| piece.flat[v as usize]))
            .collect();
        let scale = tris.iter().flatten().map(|p| p.norm()).fold(0.0, f64::max);
        // Every pair whose x ranges meet (sweep over the smallest x).
        let x_range =
            |t: &[nalgebra::Vector2<f64>; 3]| (t[0].x.min(t[1].x).min(t[2].x), t[0].x.max(t[1].x).max(t[2].x));
        tris.sort_by(|a, b| x_range(a).0.total_cmp(&x_range(b).0));
        for i in 0..tris.len() {
            for j in i + 1..tris.len() {
                if x_range(&tris[j]).0 > x_range(&tris[i]).1 {
                    break;
                }
                assert!(
                    !triangles_overlap(tris[i], tris[j], 1e-7 * scale),
                    "faces {i} and {j} overlap"
                );
            }
        }
        for &f in &piece.faces {
            seen[f as usize] += 1;
        }
    }
    assert!(seen.iter().all(|&n| n == 1));
}

/// Piece counts on the shapes a maker tries first (at most, in one piece where the
/// papercraft tools make one), every net exact and free of overlaps.
#[test]
fn nets_of_primitives_are_exact_overlap_free_and_in_few_pieces() {
    let cases: Vec<(&str, TriangleMesh, usize)> = vec![
        ("box", primitives::cuboid([1.0, 2.0, 3.0]), 1),
        ("icosahedron", primitives::icosphere(1.0, 0), 1),
        ("icosphere 1", primitives::icosphere(1.0, 1), 5),
        ("icosphere 2", primitives::icosphere(1.0, 2), 5),
        ("icosphere 3", primitives::icosphere(1.0, 3), 5),
        ("closed cylinder", primitives::cylinder(1.0, 2.0, 32, true), 1),
        ("closed cone", primitives::cone(1.0, 2.0, 32, true), 1),
        ("hemisphere", primitives::hemisphere(1.0, 8, 32), 1),
        ("torus", primitives::torus(2.0, 0.7, 32, 16), 25),
    ];
    for (name, mesh, most) in cases {
        let net = unfold_net(&mesh, &NetOptions::default()).unwrap();
        assert!(net.pieces.len() <= most, "{name}: {} pieces", net.pieces.len());
        assert_eq!(net.budget_cut_count, 0, "{name}: within the overlap tests");
        assert_exact_and_overlap_free(&mesh, &net);
    }
}

#[test]
fn a_box_unfolds_into_one_cross_of_six_rectangles_joined_by_five_folds() {
    let mesh = primitives::cuboid([1.0, 2.0, 3.0]);
    let net = unfold_net(&mesh, &NetOptions::default()).unwrap();
    assert_eq!(net.pieces.len(), 1);
    // The diagonals are kept (coplanar, no fold); five of the twelve box edges are folds,
    // seven are cut.
    assert_eq!((net.fold_edge_count, net.cut_edge_count), (5, 7));
    let area: f64 = net.pieces[0]
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| net.pieces[0].flat[v as usize]);
            0.5 * ((b - a).x * (c - a).y - (b - a).y * (c - a).x)
        })
        .sum();
    assert!((area - 22.0).abs() < 1e-12, "{area}");
}

#[test]
fn user_seams_are_always_cut_and_must_be_edges() {
    let mut mesh = primitives::cuboid([1.0, 1.0, 1.0]);
    // The four edges around the top side: it comes off as its own piece.
    mesh.seam_edges = vec![[4, 5], [5, 7], [7, 6], [6, 4]];
    let net = unfold_net(&mesh, &NetOptions::default()).unwrap();
    assert_eq!(net.pieces.len(), 2);
    assert_eq!(net.pieces[1].faces.len(), 2);
    mesh.seam_edges = vec![[0, 7]];
    let e = unfold_net(&mesh, &NetOptions::default()).unwrap_err();
    assert!(e.to_string().contains("seam edge 0"), "{e}");
}

#[test]
fn the_wingnut_unfolds_exactly_without_overlap() {
    let mesh = wingnut();
    let net = unfold_net(&mesh, &NetOptions::default()).unwrap();
    assert_exact_and_overlap_free(&mesh, &net);
    // The body in two large pieces holding most faces (one before pieces were joined
    // across the saddles' cuts: 187 pieces, now 151), the rest its small parts.
    assert!((net.pieces[0].faces.len() + net.pieces[1].faces.len()) * 2 > mesh.triangles.len());
    assert!(
        net.pieces.len() * 30 < mesh.triangles.len(),
        "{} pieces",
        net.pieces.len()
    );
}

/// The classic developables with a boundary come out whole, cut along one ruling.
#[test]
fn an_open_tube_and_an_open_cone_are_cut_along_one_ruling_into_one_exact_piece() {
    use sheetform_flatten::{cut_into_charts, ChartOptions};
    for (name, mesh, sections) in [
        ("tube", primitives::cylinder(1.0, 2.0, 32, false), 32),
        ("cone", primitives::cone(1.0, 2.0, 32, false), 32),
        ("fine cone", primitives::cone(3.0, 1.0, 200, false), 200),
    ] {
        let set = cut_into_charts(&mesh, &ChartOptions::default()).unwrap();
        assert_eq!(set.charts.len(), 1, "{name}");
        assert_eq!((set.opened_count, set.split_count), (1, 0), "{name}");
        assert_eq!(set.seam_edge_count, 1, "{name}: the one ruling cut open");
        let chart = &set.charts[0];
        assert!(
            chart.distortion.edge_length_max_relative <= 1e-10,
            "{name}: {:?}",
            chart.distortion
        );
        assert!(chart.distortion.is_overlap_free());
        // One seam: exactly one mesh edge is cut (two more chart vertices than mesh ones
        // on a tube, one more on a cone whose apex is an end of the seam).
        let extra = chart.vertices.len() - mesh.positions.len();
        assert_eq!(extra, if name == "tube" { 2 } else { 1 }, "{name}");
        // The pattern is the development: a tube's is a rectangle of the perimeter by the
        // height; a cone's a sector of the slant height.
        if name == "tube" {
            // A rectangle, perimeter × height: its diameter is the diagonal and every
            // point lies within it (a staircase seam would reach further).
            let perimeter = sections as f64 * 2.0 * (std::f64::consts::PI / sections as f64).sin();
            let diameter = chart
                .flat
                .iter()
                .flat_map(|p| chart.flat.iter().map(move |q| (p - q).norm()))
                .fold(0.0, f64::max);
            assert!(
                (diameter - (perimeter * perimeter + 4.0).sqrt()).abs() < 1e-9,
                "{diameter}"
            );
        } else {
            let apex = chart.vertices.iter().position(|&v| v as usize == sections).unwrap();
            let slant = (mesh.positions[0] - mesh.positions[sections]).norm();
            for (i, p) in chart.flat.iter().enumerate() {
                if i != apex {
                    assert!(((p - chart.flat[apex]).norm() - slant).abs() < 1e-9);
                }
            }
        }
    }
}

/// A disk fanned around one saddle vertex: `faces` thin triangles from the centre to a
/// rim that waves up and down (angles around the centre add up to about 2.3 turns).
fn saddle_fan(faces: usize) -> TriangleMesh {
    use std::f64::consts::TAU;
    let mut positions = vec![nalgebra::Vector3::zeros()];
    for i in 0..faces {
        let a = TAU * i as f64 / faces as f64;
        positions.push(nalgebra::Vector3::new(a.cos(), a.sin(), 0.5 * (7.0 * a).sin()));
    }
    let triangles: Vec<[u32; 3]> = (0..faces as u32)
        .map(|i| [0, 1 + i, 1 + (i + 1) % faces as u32])
        .collect();
    TriangleMesh {
        positions,
        face_groups: vec![0; triangles.len()],
        triangles,
        groups: vec!["fan".into()],
        corner_uvs: None,
        seam_edges: Vec::new(),
    }
}

/// Issue 19: the thin triangles of a fan all meet at the centre, where no spatial index
/// tells them apart, so every placement is tested against the whole piece (a fan of
/// 40 000 faces took minutes). The overlap tests are a budget: spent, the attempts stop
/// and the growth cuts an edge where a face would take more tests, counted; the net
/// stays exact and free of overlaps.
#[test]
fn a_fan_of_thin_triangles_unfolds_within_the_budget_of_overlap_tests() {
    let mesh = saddle_fan(400);
    let full = unfold_net(&mesh, &NetOptions::default()).unwrap();
    assert_exact_and_overlap_free(&mesh, &full);
    assert_eq!((full.attempts, full.budget_cut_count), (12, 0));
    assert!(full.pieces.len() <= 4, "{} pieces", full.pieces.len());
    let options = NetOptions {
        overlap_tests: 20_000,
        ..NetOptions::default()
    };
    let net = unfold_net(&mesh, &options).unwrap();
    assert_exact_and_overlap_free(&mesh, &net);
    assert_eq!(net.attempts, 1, "no attempt after the budget is spent");
    assert!(net.budget_cut_count > 0);
    // A budget over the cap counts as the cap.
    let capped = NetOptions {
        overlap_tests: usize::MAX,
        ..NetOptions::default()
    };
    assert_eq!(unfold_net(&mesh, &capped).unwrap(), full);
}

/// Issue 34: with a clearance and a sheet, every piece fits the sheet (turned as needed),
/// its cut lines that share no point stay the clearance apart, and the two sides of a slit
/// (cut lines ending at one mesh vertex) the slit clearance; still exact and free of
/// overlaps, every face in one piece.
#[test]
fn nets_keep_their_cut_lines_apart_and_fit_the_sheet() {
    use sheetform_geometry::{convex_hull, hull_fits_rectangle, segment_distance};
    let mesh = primitives::icosphere(1.0, 2);
    let options = NetOptions {
        clearance: 0.02,
        slit_clearance: 0.06,
        sheet: Some((1.6, 1.1)),
        ..NetOptions::default()
    };
    let net = unfold_net(&mesh, &options).unwrap();
    assert_exact_and_overlap_free(&mesh, &net);
    let free = unfold_net(&mesh, &NetOptions::default()).unwrap();
    assert!(net.pieces.len() > free.pieces.len(), "the limits cost pieces here");
    for piece in &net.pieces {
        assert!(hull_fits_rectangle(&convex_hull(piece.flat.clone()), 1.6, 1.1));
        // The piece's cut lines: edges of one face of the piece.
        let mut count = std::collections::HashMap::new();
        for t in &piece.triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                *count.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
        }
        let cut: Vec<(u32, u32)> = count.into_iter().filter(|&(_, n)| n == 1).map(|(e, _)| e).collect();
        for (i, &(a, b)) in cut.iter().enumerate() {
            for &(c, d) in &cut[i + 1..] {
                let p = |v: u32| piece.flat[v as usize];
                let share = [a, b]
                    .iter()
                    .any(|&x| [c, d].iter().any(|&y| (p(x) - p(y)).norm() < 1e-9));
                if share {
                    continue;
                }
                let vertex = |v: u32| piece.vertices[v as usize];
                let slit = [a, b]
                    .iter()
                    .any(|&x| [c, d].contains(&x) || [vertex(c), vertex(d)].contains(&vertex(x)));
                let distance = segment_distance([p(a), p(b)], [p(c), p(d)]);
                let need = if slit { 0.06 } else { 0.02 };
                assert!(distance >= need - 1e-9, "{distance} < {need} (slit: {slit})");
            }
        }
    }
}

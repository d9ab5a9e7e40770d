//! Edge unfolding into nets on the shapes a maker tries first.

use sheetform_flatten::{unfold_net, Net, NetOptions};
use sheetform_geometry::triangles_overlap;
use sheetform_mesh::{primitives, TriangleMesh};

fn wingnut() -> TriangleMesh {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/testdata/wingnut.obj");
    let mut mesh = sheetform_io::read_mesh(std::path::Path::new(path)).unwrap();
    mesh.weld(1e-9);
    mesh
}

/// Every piece an exact copy of its faces, no two faces of a piece overlapping, every
/// face in exactly one piece.
fn assert_exact_and_overlap_free(mesh: &TriangleMesh, net: &Net) {
    let mut seen = vec![0; mesh.triangles.len()];
    for piece in &net.pieces {
        assert!(piece.distortion.edge_length_max_relative < 1e-10, "{:?}", piece.distortion);
        assert!(piece.distortion.is_overlap_free(), "{:?}", piece.distortion);
        let tris: Vec<[_; 3]> = piece.triangles.iter().map(|t| t.map(|v| piece.flat[v as usize])).collect();
        let scale = tris.iter().flatten().map(|p| p.norm()).fold(0.0, f64::max);
        for i in 0..tris.len() {
            for j in i + 1..tris.len() {
                assert!(!triangles_overlap(tris[i], tris[j], 1e-7 * scale), "faces {i} and {j} overlap");
            }
        }
        for &f in &piece.faces {
            seen[f as usize] += 1;
        }
    }
    assert!(seen.iter().all(|&n| n == 1));
}

#[test]
fn net_piece_counts() {
    let cases: Vec<(&str, TriangleMesh)> = vec![
        ("box", primitives::cuboid([1.0, 2.0, 3.0])),
        ("icosphere1", primitives::icosphere(1.0, 1)),
        ("icosphere2", primitives::icosphere(1.0, 2)),
        ("icosphere3", primitives::icosphere(1.0, 3)),
        ("torus", primitives::torus(2.0, 0.7, 32, 16)),
        ("cylinder", primitives::cylinder(1.0, 2.0, 32, true)),
        ("cone", primitives::cone(1.0, 2.0, 32, true)),
        ("hemisphere", primitives::hemisphere(1.0, 8, 32)),
        ("wingnut", wingnut()),
    ];
    for (name, mesh) in cases {
        let t = std::time::Instant::now();
        let net = unfold_net(&mesh, &NetOptions::default()).unwrap();
        eprintln!(
            "{name}: {} faces, {} pieces (merged {}), folds {}, cuts {}, {:.1} ms, sizes {:?}",
            mesh.triangles.len(),
            net.pieces.len(),
            net.merged_piece_count,
            net.fold_edge_count,
            net.cut_edge_count,
            t.elapsed().as_secs_f64() * 1e3,
            net.pieces.iter().map(|p| p.faces.len()).collect::<Vec<_>>()
        );
        assert_exact_and_overlap_free(&mesh, &net);
    }
}


//! Issue 3: the bent sheets of system A flatten exactly (edge-length error ≤ 1e-10) and
//! the unfolding reproduces their own flat pattern up to a rigid motion.

use sheetform::bend::{bend, BendModel, BendScene};
use sheetform::flatten::{align_rigid, distortion, exact_unfold, UnfoldOptions};

#[test]
fn every_example_bent_sheet_unfolds_exactly() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "json") {
            continue;
        }
        let scene = BendScene::from_json(&std::fs::read_to_string(&path).unwrap()).unwrap();
        let sheet = bend(&BendModel::from_scene(&scene).unwrap()).unwrap();
        let mesh = sheet.mesh.to_triangle_mesh();
        let topology = sheetform::mesh::mesh_topology(&mesh);
        if topology.boundary_loop_count != 1 || topology.euler_characteristic != 1 {
            // Closed strips and tubes (two boundary loops) and sheets with holes are not
            // disks; the cutting step will handle them.
            continue;
        }
        let u = exact_unfold(&mesh, &UnfoldOptions::default()).unwrap();
        let d = distortion(&mesh, &u.flat);
        assert!(
            d.edge_length_max_relative <= 1e-10,
            "{}: {}",
            path.display(),
            d.edge_length_max_relative
        );
        assert!(d.is_overlap_free(), "{}", path.display());
        let a = align_rigid(&u.flat, &sheet.mesh.flat, false);
        let (lo, hi) = sheet.mesh.flat_bounds();
        assert!(
            a.max_distance <= 1e-9 * (hi - lo).norm(),
            "{}: {}",
            path.display(),
            a.max_distance
        );
        n += 1;
    }
    assert!(n >= 5, "only {n} disk-like examples");
}

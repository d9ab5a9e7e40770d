//! Exact unfolding (issue 3, "Must show"): developable meshes flatten with edge-length
//! error ≤ 1e-10; the crumpled developable reproduces its stored flattening.

use nalgebra::Vector3;
use sheetform_flatten::{align_rigid, distortion, exact_unfold, FlattenError, UnfoldOptions, Vec2};
use sheetform_mesh::TriangleMesh;

/// A grid mesh whose rows follow rulings (`f(u, v)`, rulings at constant `u`), so each
/// quad is planar and the mesh exactly developable when the surface is.
fn ruled_grid(f: impl Fn(f64, f64) -> [f64; 3], nu: usize, nv: usize) -> TriangleMesh {
    TriangleMesh::grid(nu, nv, f)
}

/// A paraboloid cap (not developable), `n × n` cells.
fn dome(n: usize) -> TriangleMesh {
    TriangleMesh::grid(n, n, |u, v| {
        let (x, y) = (u - 0.5, v - 0.5);
        [x * 100.0, y * 100.0, 30.0 * (1.0 - x * x - y * y)]
    })
}

fn assert_exact(mesh: &TriangleMesh, label: &str) {
    let u = exact_unfold(mesh, &UnfoldOptions::default()).unwrap();
    let d = distortion(mesh, &u.flat);
    assert!(
        d.edge_length_max_relative <= 1e-10,
        "{label}: edge error {}",
        d.edge_length_max_relative
    );
    assert!(
        d.area_max_relative <= 1e-9,
        "{label}: area error {}",
        d.area_max_relative
    );
    assert!(d.is_overlap_free(), "{label}: {d:?}");
}

#[test]
fn cylinder_and_cone_unfold_exactly() {
    assert_exact(
        &ruled_grid(
            |u, v| [(3.0 * u).cos() * 50.0, (3.0 * u).sin() * 50.0, 80.0 * v],
            60,
            20,
        ),
        "cylinder",
    );
    // Cone z = r cot β with half-angle 0.4, rulings through the apex, sheet from r = 20 to 60.
    let (sb, cb) = 0.4f64.sin_cos();
    assert_exact(
        &ruled_grid(
            |u, v| {
                let (t, rho) = (4.0 * u, 20.0 + 40.0 * v);
                [rho * sb * t.cos(), rho * sb * t.sin(), rho * cb]
            },
            80,
            12,
        ),
        "cone",
    );
}

#[test]
fn unfolding_is_scale_invariant() {
    for scale in [1e-6, 1e6] {
        let m = ruled_grid(
            |u, v| [(2.0 * u).cos() * scale, (2.0 * u).sin() * scale, 2.0 * v * scale],
            30,
            10,
        );
        assert_exact(&m, &format!("cylinder at scale {scale}"));
    }
}

/// The paraboloid cap of [`dome`] with one more triangle on its border: a needle whose
/// third corner lies `offset` off the middle of a 25 mm border edge (face 32).
fn dome_with_a_needle(offset: f64) -> TriangleMesh {
    let mut m = dome(4);
    let (i, j) = m
        .triangles
        .iter()
        .find_map(|t| {
            (0..3).find_map(|k| {
                let (i, j) = (t[k], t[(k + 1) % 3]);
                (m.positions[i as usize].y == -50.0 && m.positions[j as usize].y == -50.0).then_some((j, i))
            })
        })
        .unwrap();
    let middle = (m.positions[i as usize] + m.positions[j as usize]) * 0.5;
    m.positions.push(middle - Vector3::y() * offset);
    m.triangles.push([i, j, (m.positions.len() - 1) as u32]);
    m.face_groups.push(0);
    m
}

/// Issue 35, messages: a mesh whose edge lengths do not fix its flat layout was refused as
/// "factorisation failed (the linear system has no unique solution …): the mesh is not
/// rigid in the plane", the solver's words. A needle-thin triangle (its corners almost in
/// a line) does that: the refusal says so, names the thinnest triangle and where it is,
/// and what to do.
#[test]
fn a_needle_thin_triangle_is_named_in_the_meshs_terms() {
    // Less thin, the same mesh unfolds (as a least-squares layout: the cap is curved).
    assert!(exact_unfold(&dome_with_a_needle(2.5e-4), &UnfoldOptions::default()).is_ok());
    let message = match exact_unfold(&dome_with_a_needle(2.5e-8), &UnfoldOptions::default()) {
        Err(e @ FlattenError::Solver { .. }) => e.to_string(),
        other => panic!("{:?}", other.map(|u| u.max_relative_residual)),
    };
    assert!(
        message.contains("needle-thin triangles, their three corners almost in a line")
            && message.contains("(the thinnest, face 32 near (-37.5, -50, ")
            && message.contains("is 2.5e-8 wide across its longest edge of 25.6"),
        "{message}"
    );
    assert!(
        message.starts_with("the mesh cannot be laid flat as it is: "),
        "{message}"
    );
    for internal in ["solver", "factoris", "linear system", "singular", "pivot", "rigid"] {
        assert!(!message.contains(internal), "`{internal}` in: {message}");
    }
}

#[test]
fn closed_and_non_manifold_meshes_are_refused() {
    // A tetrahedron: closed.
    let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let tet = TriangleMesh {
        positions: p.iter().map(|q| Vector3::from(*q)).collect(),
        triangles: vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]],
        face_groups: vec![0; 4],
        groups: vec!["g".into()],
        corner_uvs: None,
        seam_edges: Vec::new(),
    };
    assert!(matches!(
        exact_unfold(&tet, &UnfoldOptions::default()),
        Err(FlattenError::NotADisk { boundary_loops: 0, .. })
    ));
    let mut fin = tet.clone();
    fin.triangles = vec![[0, 1, 2], [1, 0, 3], [0, 1, 2]];
    fin.face_groups = vec![0; 3];
    assert!(matches!(
        exact_unfold(&fin, &UnfoldOptions::default()),
        Err(FlattenError::Topology { .. })
    ));
}

#[test]
fn crumpled_developable_reproduces_its_stored_flattening() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/meshes/crumpled-developable.obj");
    let mesh = sheetform_io_free_obj(&path);
    let u = exact_unfold(&mesh, &UnfoldOptions::default()).unwrap();
    let ours = distortion(&mesh, &u.flat);
    // The stored flattening, one point per vertex.
    let stored = stored_per_vertex(&mesh);
    let theirs = distortion(&mesh, &stored);
    assert!(
        ours.edge_length_max_relative <= theirs.edge_length_max_relative,
        "ours {} vs the file's {}",
        ours.edge_length_max_relative,
        theirs.edge_length_max_relative
    );
    assert!(ours.is_overlap_free());
    let a = align_rigid(&u.flat, &stored, true);
    let size = stored.iter().fold(0.0f64, |m, p| m.max(p.norm()));
    assert!(
        a.max_distance <= 1e-4 * size,
        "differs from the stored flattening by {} (size {size})",
        a.max_distance
    );
}

/// The file's `vt`, one per vertex (this mesh has no seams).
fn stored_per_vertex(mesh: &TriangleMesh) -> Vec<Vec2> {
    let mut out = vec![Vec2::zeros(); mesh.positions.len()];
    for (t, q) in mesh.triangles.iter().zip(mesh.corner_uvs.as_ref().unwrap()) {
        for k in 0..3 {
            out[t[k] as usize] = q[k];
        }
    }
    out
}

fn sheetform_io_free_obj(path: &std::path::Path) -> TriangleMesh {
    sheetform_io::read_mesh(path).unwrap()
}

#[test]
fn lscm_is_isometric_on_developable_meshes_and_conformal_on_others() {
    use sheetform_flatten::lscm;
    let cylinder = ruled_grid(
        |u, v| [(3.0 * u).cos() * 50.0, (3.0 * u).sin() * 50.0, 80.0 * v],
        40,
        16,
    );
    let u = lscm(&cylinder).unwrap();
    let d = distortion(&cylinder, &u.flat);
    assert!(
        d.edge_length_max_relative <= 1e-9,
        "cylinder: {}",
        d.edge_length_max_relative
    );
    // A paraboloid cap: not developable; LSCM keeps angles (small distortion), no flips.
    let dome = dome(30);
    let u = lscm(&dome).unwrap();
    let d = distortion(&dome, &u.flat);
    assert!(d.is_overlap_free(), "{d:?}");
    // Angle distortion: the largest change of a triangle corner angle.
    let mut worst: f64 = 0.0;
    for t in &dome.triangles {
        for k in 0..3 {
            let (i, j, l) = (t[k] as usize, t[(k + 1) % 3] as usize, t[(k + 2) % 3] as usize);
            let a3 = (dome.positions[j] - dome.positions[i]).angle(&(dome.positions[l] - dome.positions[i]));
            let a2 = (u.flat[j] - u.flat[i]).angle(&(u.flat[l] - u.flat[i]));
            worst = worst.max((a3 - a2).abs());
        }
    }
    assert!(worst < 0.05, "largest angle change {worst} rad");
    assert!(
        d.area_max_relative > 0.01,
        "a curved cap cannot keep areas: {}",
        d.area_max_relative
    );
}

#[test]
fn arap_reaches_the_isometry_and_distorts_lengths_less_than_lscm() {
    use sheetform_flatten::{arap, lscm, ArapOptions};
    let cylinder = ruled_grid(
        |u, v| [(3.0 * u).cos() * 50.0, (3.0 * u).sin() * 50.0, 80.0 * v],
        30,
        12,
    );
    let u = arap(&cylinder, &ArapOptions::default()).unwrap();
    assert!(u.solver.converged, "{:?}", u.solver);
    let d = distortion(&cylinder, &u.flat);
    assert!(
        d.edge_length_max_relative <= 1e-9,
        "cylinder: {}",
        d.edge_length_max_relative
    );
    let dome = dome(24);
    let a = arap(&dome, &ArapOptions::default()).unwrap();
    let l = lscm(&dome).unwrap();
    let (da, dl) = (distortion(&dome, &a.flat), distortion(&dome, &l.flat));
    assert!(da.is_overlap_free(), "{da:?}");
    assert!(
        da.edge_length_mean_relative < dl.edge_length_mean_relative,
        "ARAP {} vs LSCM {}",
        da.edge_length_mean_relative,
        dl.edge_length_mean_relative
    );
    assert!(a.solver.cost <= a.solver.initial_cost);
}

//! Least-squares conformal maps (Lévy, Petitjean, Ray, Maillot 2002).

use crate::{FlattenError, Unfolding, Vec2};
use faer::sparse::Triplet;
use sheetform_mesh::{mesh_topology, TriangleMesh};
use sheetform_solve::SolverInfo;
use sheetform_solve::SparseCholesky;

/// Flattens a disk-like mesh by least-squares conformal maps: minimises
///
/// `E_LSCM = Σ_T |Σ_k W_{T,k} U_k|² / (2 A_T)`,
///
/// with `U_k = u_k + i v_k` the flat positions and `W_{T,k} = (x_{k+2} − x_{k+1}) + i (y_{k+2} − y_{k+1})`
/// from the triangle's own orthonormal 2D frame (Lévy et al. 2002, Eq. 8): the discrete
/// Cauchy–Riemann residual, zero for a conformal map. Two boundary vertices far apart are
/// pinned at `(0, 0)` and `(1, 0)` (the similarity gauge); the normal equations are solved
/// by faer's sparse Cholesky, and the result is scaled so that the pattern's area equals
/// the surface's. A developable mesh comes out isometric (its conformal flattening has
/// the right scale); a non-developable one is flattened with least angle distortion.
///
/// # Errors
/// As [`crate::exact_unfold`]: the mesh must be a clean disk.
pub fn lscm(mesh: &TriangleMesh) -> Result<Unfolding, FlattenError> {
    let topology = mesh_topology(mesh);
    if !topology.is_clean() {
        return Err(FlattenError::Topology {
            problem: "non-manifold edges or vertices, degenerate faces, or a non-orientable surface".into(),
        });
    }
    if topology.component_count != 1 || topology.boundary_loop_count != 1 || topology.euler_characteristic != 1 {
        return Err(FlattenError::NotADisk {
            components: topology.component_count,
            boundary_loops: topology.boundary_loop_count,
            euler: topology.euler_characteristic,
        });
    }
    let nv = mesh.positions.len();
    // Pins: the boundary vertex farthest from a boundary vertex, then the farthest from it.
    let boundary: Vec<usize> = (0..nv).filter(|&v| topology.boundary_vertex[v]).collect();
    let farthest = |from: usize| {
        *boundary
            .iter()
            .max_by(|&&a, &&b| {
                (mesh.positions[a] - mesh.positions[from])
                    .norm()
                    .total_cmp(&(mesh.positions[b] - mesh.positions[from]).norm())
            })
            .expect("a disk has a boundary")
    };
    let p0 = farthest(boundary[0]);
    let p1 = farthest(p0);
    let pinned = |v: usize| v == p0 || v == p1;
    let pin_value = |v: usize| if v == p0 { Vec2::zeros() } else { Vec2::new(1.0, 0.0) };
    let mut column = vec![usize::MAX; nv];
    let mut n = 0;
    for (v, c) in column.iter_mut().enumerate() {
        if !pinned(v) {
            *c = n;
            n += 1;
        }
    }
    // Rows of A (2 per triangle), as (vertex, coefficient on u, coefficient on v).
    let mut triplets: Vec<Triplet<usize, usize, f64>> = Vec::with_capacity(mesh.triangles.len() * 36);
    let mut rhs = vec![0.0; 2 * n];
    for (f, t) in mesh.triangles.iter().enumerate() {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        let e1 = b - a;
        let ex = e1.normalize();
        let normal = e1.cross(&(c - a));
        let area2 = normal.norm();
        if area2 <= 0.0 {
            return Err(FlattenError::Topology {
                problem: format!("face {f} has zero area"),
            });
        }
        let ey = normal.cross(&ex).normalize();
        let local = [
            Vec2::zeros(),
            Vec2::new(e1.dot(&ex), 0.0),
            Vec2::new((c - a).dot(&ex), (c - a).dot(&ey)),
        ];
        let w = 1.0 / area2.sqrt();
        // W_k = p_{k+2} − p_{k+1} (complex).
        let coeff: [(f64, f64); 3] = std::array::from_fn(|k| {
            let d = local[(k + 2) % 3] - local[(k + 1) % 3];
            (d.x * w, d.y * w)
        });
        // Row re: Σ (Wr u − Wi v); row im: Σ (Wi u + Wr v).
        let rows: [[(f64, f64); 3]; 2] = [coeff.map(|(wr, wi)| (wr, -wi)), coeff.map(|(wr, wi)| (wi, wr))];
        for row in rows {
            // Contribution of this row to AᵀA and to the right-hand side (pins moved over).
            let mut constant = 0.0;
            for k in 0..3 {
                let v = t[k] as usize;
                if pinned(v) {
                    let p = pin_value(v);
                    constant += row[k].0 * p.x + row[k].1 * p.y;
                }
            }
            for k in 0..3 {
                let vk = t[k] as usize;
                if pinned(vk) {
                    continue;
                }
                let (ck_u, ck_v) = (2 * column[vk], 2 * column[vk] + 1);
                rhs[ck_u] -= row[k].0 * constant;
                rhs[ck_v] -= row[k].1 * constant;
                for l in 0..3 {
                    let vl = t[l] as usize;
                    if pinned(vl) {
                        continue;
                    }
                    let (cl_u, cl_v) = (2 * column[vl], 2 * column[vl] + 1);
                    for (ci, ai) in [(ck_u, row[k].0), (ck_v, row[k].1)] {
                        for (cj, aj) in [(cl_u, row[l].0), (cl_v, row[l].1)] {
                            if cj <= ci {
                                triplets.push(Triplet::new(ci, cj, ai * aj));
                            }
                        }
                    }
                }
            }
        }
    }
    let llt = SparseCholesky::new(2 * n, &triplets).map_err(|e| FlattenError::Solver {
        message: format!("the layout solver failed: {e}"),
    })?;
    let x = llt.solve(&rhs);
    let mut flat: Vec<Vec2> = (0..nv)
        .map(|v| {
            if pinned(v) {
                pin_value(v)
            } else {
                Vec2::new(x[2 * column[v]], x[2 * column[v] + 1])
            }
        })
        .collect();
    // Scale so the pattern's area equals the surface's; keep counter-clockwise faces.
    let (mut area_flat, mut area_3d) = (0.0, 0.0);
    for (f, t) in mesh.triangles.iter().enumerate() {
        let [a, b, c] = t.map(|i| flat[i as usize]);
        area_flat += 0.5 * ((b - a).x * (c - a).y - (b - a).y * (c - a).x);
        area_3d += mesh.face_area(f);
    }
    let scale = (area_3d / area_flat.abs()).sqrt();
    let mirror = if area_flat < 0.0 { -1.0 } else { 1.0 };
    for p in &mut flat {
        *p = Vec2::new(p.x * scale, p.y * scale * mirror);
    }
    let residual = crate::distortion(mesh, &flat).edge_length_max_relative;
    Ok(Unfolding {
        flat,
        solver: SolverInfo {
            iterations: 1,
            converged: true,
            ..Default::default()
        },
        max_relative_residual: residual,
    })
}

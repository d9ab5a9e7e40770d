//! As-rigid-as-possible flattening (Liu, Zhang, Xu, Gotsman, Gortler 2008).

use crate::{lscm, FlattenError, Unfolding, Vec2};
use faer::sparse::Triplet;
use nalgebra::Matrix2;
use sheetform_mesh::TriangleMesh;
use sheetform_solve::SolverInfo;
use sheetform_solve::SparseCholesky;

/// Knobs of [`arap`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArapOptions {
    /// Most local/global iterations.
    pub max_iterations: usize,
    /// Stop when an iteration lowers the energy by less than this fraction.
    pub relative_tolerance: f64,
}

impl Default for ArapOptions {
    fn default() -> Self {
        Self {
            max_iterations: 100,
            relative_tolerance: 1e-5,
        }
    }
}

/// Flattens a disk-like mesh as rigidly as possible: minimises
///
/// `E = Σ_t Σ_{(i,j) ∈ t} cot θ_ij^t ‖(u_i − u_j) − R_t (x_i − x_j)‖²`
///
/// over the flat positions `u` and one rotation `R_t` per triangle (`x`: the triangle in
/// its own 2D frame, `θ_ij^t` the angle opposite edge `ij`) by alternating the *local*
/// step (each `R_t` from the SVD of its 2×2 covariance, reflections excluded) and the
/// *global* step (the cotangent-Laplacian system `L u = b`). `L` does not change, so it is
/// factorised once (faer sparse Cholesky) and each iteration is two triangular solves.
/// Starts from [`lscm`].
///
/// Departure: cotangent weights are clamped to at least `1e-3 ×` their mean so that `L`
/// stays positive definite on meshes with very obtuse triangles.
///
/// # Errors
/// As [`lscm`]: the mesh must be a clean disk.
// The corner loops use the cyclic indices k, k+1, k+2 of a triangle; an iterator form
// would hide that.
#[allow(clippy::needless_range_loop)]
pub fn arap(mesh: &TriangleMesh, options: &ArapOptions) -> Result<Unfolding, FlattenError> {
    let start = lscm(mesh)?;
    let nv = mesh.positions.len();
    let nt = mesh.triangles.len();
    // Each triangle in its own frame, and its cotangent weights (per edge k: opposite corner k).
    let mut local: Vec<[Vec2; 3]> = Vec::with_capacity(nt);
    let mut cot: Vec<[f64; 3]> = Vec::with_capacity(nt);
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        let ex = (b - a).normalize();
        let n = (b - a).cross(&(c - a));
        let ey = n.cross(&ex).normalize();
        let p = [
            Vec2::zeros(),
            Vec2::new((b - a).dot(&ex), 0.0),
            Vec2::new((c - a).dot(&ex), (c - a).dot(&ey)),
        ];
        let corner_cot = |k: usize| {
            let (u, v) = (p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]);
            u.dot(&v) / (u.x * v.y - u.y * v.x).abs().max(f64::MIN_POSITIVE)
        };
        local.push(p);
        cot.push([corner_cot(0), corner_cot(1), corner_cot(2)]);
    }
    let mean = cot.iter().flatten().map(|c| c.abs()).sum::<f64>() / (3 * nt).max(1) as f64;
    for c in cot.iter_mut().flatten() {
        *c = c.max(1e-3 * mean);
    }
    // Global matrix: vertex 0 pinned (translation gauge).
    let col = |v: usize| if v == 0 { usize::MAX } else { v - 1 };
    let n = nv - 1;
    let mut triplets: Vec<Triplet<usize, usize, f64>> = Vec::with_capacity(nt * 9);
    for (t, tri) in mesh.triangles.iter().enumerate() {
        for k in 0..3 {
            // Edge (i, j) opposite corner k.
            let (i, j) = (tri[(k + 1) % 3] as usize, tri[(k + 2) % 3] as usize);
            let w = cot[t][k];
            for (a, b, s) in [(i, i, w), (j, j, w), (i, j, -w), (j, i, -w)] {
                let (ca, cb) = (col(a), col(b));
                if ca != usize::MAX && cb != usize::MAX && cb <= ca {
                    triplets.push(Triplet::new(ca, cb, s));
                }
            }
        }
    }
    let llt = SparseCholesky::new(n, &triplets).map_err(|e| FlattenError::Solver {
        message: format!("the layout solver failed: {e}"),
    })?;

    let mut u = start.flat;
    let pin = u[0];
    let mut rotations = vec![Matrix2::<f64>::identity(); nt];
    let energy = |u: &[Vec2], rotations: &[Matrix2<f64>]| -> f64 {
        let mut e = 0.0;
        for (t, tri) in mesh.triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = ((k + 1) % 3, (k + 2) % 3);
                let d = (u[tri[a] as usize] - u[tri[b] as usize]) - rotations[t] * (local[t][a] - local[t][b]);
                e += cot[t][k] * d.norm_squared();
            }
        }
        e
    };
    let mut info = SolverInfo::default();
    let mut previous = f64::INFINITY;
    // The energy's natural scale (that of collapsing every edge): below 1e-20 of it the
    // flattening's RMS edge-length error is ~1e-10 and further iterations change nothing
    // a pattern could show.
    let energy_scale: f64 = (0..nt)
        .map(|t| {
            (0..3)
                .map(|k| cot[t][k] * (local[t][(k + 1) % 3] - local[t][(k + 2) % 3]).norm_squared())
                .sum::<f64>()
        })
        .sum();
    for it in 0..options.max_iterations {
        // Local step: best rotation per triangle.
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let mut s = Matrix2::<f64>::zeros();
            for k in 0..3 {
                let (a, b) = ((k + 1) % 3, (k + 2) % 3);
                let du = u[tri[a] as usize] - u[tri[b] as usize];
                let dx = local[t][a] - local[t][b];
                s += cot[t][k] * du * dx.transpose();
            }
            let svd = s.svd(true, true);
            let (uu, vt) = (svd.u.expect("requested"), svd.v_t.expect("requested"));
            let mut r = uu * vt;
            if r.determinant() < 0.0 {
                let mut uu = uu;
                uu.set_column(1, &(-uu.column(1)));
                r = uu * vt;
            }
            rotations[t] = r;
        }
        let e = energy(&u, &rotations);
        if it == 0 {
            info.initial_cost = e;
        }
        info.cost = e;
        info.iterations = it;
        let stalled =
            previous.is_finite() && previous - e <= options.relative_tolerance * previous.max(f64::MIN_POSITIVE);
        if stalled || e <= 1e-20 * energy_scale {
            info.converged = true;
            break;
        }
        previous = e;
        // Global step: L u = b for x and y.
        let mut bx = vec![0.0; n];
        let mut by = vec![0.0; n];
        for (t, tri) in mesh.triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = ((k + 1) % 3, (k + 2) % 3);
                let (i, j) = (tri[a] as usize, tri[b] as usize);
                let g = rotations[t] * (local[t][a] - local[t][b]) * cot[t][k];
                for (v, s, other) in [(i, 1.0, j), (j, -1.0, i)] {
                    if v == 0 {
                        continue;
                    }
                    bx[v - 1] += s * g.x;
                    by[v - 1] += s * g.y;
                    // The pinned vertex's known value moves to the right-hand side.
                    if other == 0 {
                        bx[v - 1] += cot[t][k] * pin.x;
                        by[v - 1] += cot[t][k] * pin.y;
                    }
                }
            }
        }
        let (sx, sy) = (llt.solve(&bx), llt.solve(&by));
        for v in 1..nv {
            u[v] = Vec2::new(sx[v - 1], sy[v - 1]);
        }
        info.iterations = it + 1;
    }
    let residual = crate::distortion(mesh, &u).edge_length_max_relative;
    Ok(Unfolding {
        flat: u,
        solver: info,
        max_relative_residual: residual,
    })
}

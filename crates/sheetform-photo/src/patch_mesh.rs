//! Triangle meshes of the patches (§7, "Generating a triangulated mesh").
//!
//! - A ruled strip is triangulated between consecutive rulings, as in the paper, with the
//!   curve samples between two rulings' ends on each side included (a zipper: the
//!   shorter diagonal first), so that the strip has no interior vertex — it unfolds
//!   exactly whatever the quads' planarity — and its boundary follows the curves as
//!   finely as the neighbouring patches, with which it shares those vertices.
//! - A patch without rulings gets the paper's Delaunay triangulation of its 2D outline
//!   (spade's constrained Delaunay with refinement: triangles at most `2 h²`, `h` the
//!   sample spacing, angles ≥ 25°, outline edges kept so the shared boundary stays
//!   shared) and a minimal-surface fill: the interior vertices solve the discrete
//!   Laplace equation `Σ_j w_ij (x_i − x_j) = 0` with the 3D outline fixed, `w_ij` the
//!   cotangent weights of the 2D triangulation (clamped at 1e-6 × their mean). Departure:
//!   the paper minimises mean curvature by the bi-Laplacian variational approach
//!   (Botsch & Kobbelt 2004); the harmonic (membrane) fill here needs only the outline,
//!   reproduces planar outlines exactly and is one sparse Cholesky solve.
//!
//! Every vertex also keeps its image position, the texture coordinate that projects the
//! photograph onto the model.

use crate::curve_network::CurveNetwork;
use crate::curve_samples::{CurvePoint, CurveSamples};
use crate::patch_cycles::Patch;
use crate::ruling_propagation::RuledStrip;
use crate::{cubic, PhotoError};
use faer::sparse::Triplet;
use faer::Mat;
use nalgebra::{Vector2, Vector3};
use sheetform_geometry::short_number;
use sheetform_solve::SparseCholesky;
use spade::{AngleLimit, ConstrainedDelaunayTriangulation, HasPosition, Point2, RefinementParameters, Triangulation};

type Vec2 = Vector2<f64>;
type Vec3 = Vector3<f64>;

/// Most interior vertices the Delaunay refinement adds to one filled patch; there it
/// stops, and the patch keeps triangles larger than `2 h²`.
pub const MAX_FILL_VERTICES_PER_PATCH: usize = 200_000;

/// Most interior vertices of all filled patches together. One patch at
/// [`MAX_FILL_VERTICES_PER_PATCH`] takes about 1.2 s (refinement and Laplace solve,
/// measured on the cylinder at 0.2 px) and the mesh about 100 bytes a vertex, so about
/// 4 s and 60 MB; without it, each of hundreds of patches could add 200 000 vertices.
pub const MAX_FILL_VERTICES: usize = 600_000;

/// The meshed model: one group per material patch, shared vertices along shared curves.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PatchMesh {
    /// 3D positions (model frame, pixels until scaled).
    pub positions: Vec<Vec3>,
    /// Image positions (model frame: `x`, `−y`).
    pub image: Vec<Vec2>,
    /// Triangles, counter-clockwise in the image.
    pub triangles: Vec<[u32; 3]>,
    /// Patch (index into the patch list) of each triangle.
    pub face_patch: Vec<u32>,
    /// For each patch: how its surface was made.
    pub patch_kind: Vec<PatchSurface>,
    /// Vertices of the patch interiors filled by the Laplace equation.
    pub fill_vertex_count: usize,
    /// The kept rulings as mesh edges, in order along each strip (the pattern's bending
    /// guides).
    pub ruling_edges: Vec<[u32; 2]>,
    /// The other edges across the ruled strips (the zipper between two rulings): the
    /// sheet bends along them smoothly; the pattern draws them neither as folds nor as
    /// guides.
    pub bending_edges: Vec<[u32; 2]>,
}

/// How a patch's surface was made.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PatchSurface {
    /// Marked as an opening: no surface.
    Opening,
    /// Swept by rulings.
    Ruled,
    /// Delaunay triangulation + minimal-surface fill.
    Filled,
}

#[derive(Clone, Copy)]
struct FillVertex {
    position: Point2<f64>,
}

impl HasPosition for FillVertex {
    type Scalar = f64;
    fn position(&self) -> Point2<f64> {
        self.position
    }
}

impl From<Point2<f64>> for FillVertex {
    fn from(position: Point2<f64>) -> Self {
        Self { position }
    }
}

/// Vertex numbering of the curve samples: nodes once, segment interiors once.
struct SampleVertices {
    node: Vec<u32>,
    interior_start: Vec<u32>,
}

impl SampleVertices {
    fn vertex(&self, network: &CurveNetwork, samples: &CurveSamples, place: CurvePoint) -> u32 {
        let params = &samples.parameters[place.segment as usize];
        let seg = network.segments[place.segment as usize].points;
        // The nearest sample (places are samples; parameters increase).
        let at = params.partition_point(|&t| t < place.t).min(params.len() - 1);
        let k = if at > 0 && place.t - params[at - 1] < params[at] - place.t {
            at - 1
        } else {
            at
        };
        if k == 0 {
            self.node[seg[0] as usize]
        } else if k == params.len() - 1 {
            self.node[seg[3] as usize]
        } else {
            self.interior_start[place.segment as usize] + (k as u32 - 1)
        }
    }
}

/// Meshes every material patch. `x` holds the solved 3D control points.
///
/// # Errors
/// [`PhotoError::Patch`] if a filled patch cannot be triangulated or its fill solved, and
/// [`PhotoError::Field`] on `analysis.sample_spacing_px` when the fills would need more
/// than [`MAX_FILL_VERTICES`] interior vertices (a lower bound from the patches' areas
/// is checked before any fill, the count before each patch's solve).
pub fn mesh_patches(
    network: &CurveNetwork,
    samples: &CurveSamples,
    patches: &[Patch],
    strips: &[RuledStrip],
    x: &[f64],
    sample_spacing: f64,
) -> Result<PatchMesh, PhotoError> {
    let control3 = |s: usize| -> [Vec3; 4] {
        network.segments[s]
            .points
            .map(|i| Vec3::new(x[3 * i as usize], x[3 * i as usize + 1], x[3 * i as usize + 2]))
    };
    let mut mesh = PatchMesh::default();
    // Sample vertices: every node, then every segment's interior samples.
    let mut numbering = SampleVertices {
        node: vec![u32::MAX; network.points.len()],
        interior_start: vec![0; network.segments.len()],
    };
    for seg in &network.segments {
        for &p in [seg.points[0], seg.points[3]].iter() {
            if numbering.node[p as usize] == u32::MAX {
                numbering.node[p as usize] = mesh.positions.len() as u32;
                mesh.positions.push(Vec3::new(
                    x[3 * p as usize],
                    x[3 * p as usize + 1],
                    x[3 * p as usize + 2],
                ));
                mesh.image.push(network.points[p as usize]);
            }
        }
    }
    for (s, params) in samples.parameters.iter().enumerate() {
        numbering.interior_start[s] = mesh.positions.len() as u32;
        let (b2, b3) = (network.control_points(s), control3(s));
        for &t in &params[1..params.len() - 1] {
            mesh.positions.push(cubic::point(&b3, t));
            mesh.image.push(cubic::point(&b2, t));
        }
    }
    let mut push_triangle = |mesh: &mut PatchMesh, mut t: [u32; 3], patch: usize| {
        let [a, b, c] = t.map(|i| mesh.image[i as usize]);
        let area = (b - a).x * (c - a).y - (b - a).y * (c - a).x;
        if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
            return;
        }
        if area < 0.0 {
            t.swap(1, 2);
        }
        mesh.triangles.push(t);
        mesh.face_patch.push(patch as u32);
    };
    let mut kinds = vec![PatchSurface::Filled; patches.len()];
    for (p, patch) in patches.iter().enumerate() {
        if patch.opening {
            kinds[p] = PatchSurface::Opening;
        }
    }
    for strip in strips {
        kinds[strip.patch] = PatchSurface::Ruled;
        let va: Vec<u32> = strip
            .side_a
            .places
            .iter()
            .map(|&pl| numbering.vertex(network, samples, pl))
            .collect();
        let vb: Vec<u32> = strip
            .side_b
            .places
            .iter()
            .map(|&pl| numbering.vertex(network, samples, pl))
            .collect();
        let first = strip.rulings[0];
        mesh.ruling_edges.push([va[first.0], vb[first.1]]);
        for w in strip.rulings.windows(2) {
            let ((k0, l0), (k1, l1)) = (w[0], w[1]);
            let (mut ka, mut lb) = (k0, l0);
            while ka < k1 || lb < l1 {
                let advance_a = if ka == k1 {
                    false
                } else if lb == l1 {
                    true
                } else {
                    let da = (mesh.image[va[ka + 1] as usize] - mesh.image[vb[lb] as usize]).norm();
                    let db = (mesh.image[va[ka] as usize] - mesh.image[vb[lb + 1] as usize]).norm();
                    da <= db
                };
                if advance_a {
                    push_triangle(&mut mesh, [va[ka], vb[lb], va[ka + 1]], strip.patch);
                    ka += 1;
                } else {
                    push_triangle(&mut mesh, [va[ka], vb[lb], vb[lb + 1]], strip.patch);
                    lb += 1;
                }
                if (ka, lb) == (k1, l1) {
                    mesh.ruling_edges.push([va[ka], vb[lb]]);
                } else {
                    mesh.bending_edges.push([va[ka], vb[lb]]);
                }
            }
        }
    }
    // The outline's vertices in cycle order.
    let ring_of = |patch: &Patch| -> Vec<u32> {
        let mut ring: Vec<u32> = Vec::new();
        for h in &patch.cycle {
            let params = &samples.parameters[h.segment as usize];
            let n = params.len();
            for i in 0..n - 1 {
                let t = if h.reversed { params[n - 1 - i] } else { params[i] };
                ring.push(numbering.vertex(network, samples, CurvePoint { segment: h.segment, t }));
            }
        }
        ring
    };
    // The fills' interior vertices, bounded below before any is made: an outline of area
    // `A` and `B` vertices cut into triangles of at most `2 h²` has `T ≥ A / 2h²` of them
    // and `(T − B + 2) / 2` interior vertices (Euler), unless the refinement stops at its
    // per-patch bound. Counted at half of `T` (triangles along the outline may stay
    // larger: its edges are not split; the cylinder's fill at 0.3 to 8 px has 1.6 to 2.7
    // times the full estimate).
    let mut least = 0usize;
    for (p, patch) in patches.iter().enumerate() {
        if kinds[p] != PatchSurface::Filled {
            continue;
        }
        let ring: Vec<Vec2> = ring_of(patch).iter().map(|&v| mesh.image[v as usize]).collect();
        let area = sheetform_geometry::signed_area(&ring).abs();
        let triangles = 0.5 * area / (2.0 * sample_spacing * sample_spacing);
        let interior = ((triangles - ring.len() as f64 + 2.0) / 2.0).clamp(0.0, MAX_FILL_VERTICES_PER_PATCH as f64);
        least = least.saturating_add(interior as usize);
        if least > MAX_FILL_VERTICES {
            return Err(too_many_fill_vertices(p));
        }
    }
    for (p, patch) in patches.iter().enumerate() {
        if kinds[p] != PatchSurface::Filled {
            continue;
        }
        let ring = ring_of(patch);
        fill_patch(&mut mesh, &ring, p, sample_spacing, &mut push_triangle)?;
    }
    mesh.patch_kind = kinds;
    Ok(mesh)
}

/// The error for fills over [`MAX_FILL_VERTICES`], passed at patch `patch`.
fn too_many_fill_vertices(patch: usize) -> PhotoError {
    PhotoError::field(
        "analysis.sample_spacing_px",
        format!(
            "the minimal-surface fills need more than {} interior vertices by patch {} (triangles of at most \
             twice the spacing squared): sample coarser",
            short_number(MAX_FILL_VERTICES as f64),
            patch + 1
        ),
    )
}

/// Constrained Delaunay triangulation of a patch outline and the Laplace fill.
fn fill_patch(
    mesh: &mut PatchMesh,
    ring: &[u32],
    patch: usize,
    spacing: f64,
    push_triangle: &mut impl FnMut(&mut PatchMesh, [u32; 3], usize),
) -> Result<(), PhotoError> {
    // At most one vertex over the total bound, so that passing it is seen.
    let remaining = MAX_FILL_VERTICES.saturating_sub(mesh.fill_vertex_count);
    let additional = MAX_FILL_VERTICES_PER_PATCH.min(remaining + 1);
    let n = ring.len();
    let vertices: Vec<FillVertex> = ring
        .iter()
        .map(|&v| FillVertex {
            position: Point2::new(mesh.image[v as usize].x, mesh.image[v as usize].y),
        })
        .collect();
    let constraints: Vec<[usize; 2]> = (0..n).map(|i| [i, (i + 1) % n]).collect();
    let mut conflict = false;
    let mut cdt =
        ConstrainedDelaunayTriangulation::<FillVertex>::try_bulk_load_cdt(vertices, constraints, |_| conflict = true)
            .map_err(|e| PhotoError::Patch {
            patch: format!("{}", patch + 1),
            message: format!(
                "its outline cannot be triangulated: {}",
                sheetform_geometry::triangulation_problem(&e)
            ),
        })?;
    if conflict || cdt.num_vertices() != n {
        return Err(PhotoError::Patch {
            patch: format!("{}", patch + 1),
            message: "its outline touches itself and cannot be triangulated".into(),
        });
    }
    let area_limit = 2.0 * spacing * spacing;
    let result = cdt.refine(
        RefinementParameters::new()
            .with_max_allowed_area(area_limit)
            .with_angle_limit(AngleLimit::from_deg(25.0))
            .keep_constraint_edges()
            .exclude_outer_faces(true)
            .with_max_additional_vertices(additional),
    );
    if cdt.num_vertices() - n > remaining {
        return Err(too_many_fill_vertices(patch));
    }
    let excluded: std::collections::HashSet<_> = result.excluded_faces.iter().copied().collect();
    // Interior vertices get new mesh indices.
    let total = cdt.num_vertices();
    let mut index: Vec<u32> = ring.to_vec();
    let first_new = mesh.positions.len() as u32;
    for (k, v) in cdt.vertices().enumerate().skip(n) {
        let p = v.position();
        index.push(first_new + (k - n) as u32);
        mesh.image.push(Vec2::new(p.x, p.y));
        mesh.positions.push(Vec3::zeros());
    }
    let mut faces: Vec<[usize; 3]> = Vec::new();
    for face in cdt.inner_faces() {
        if excluded.contains(&face.fix()) {
            continue;
        }
        faces.push(face.vertices().map(|v| v.fix().index()));
    }
    // Laplace fill of the interior vertices (local numbering: n.. total).
    let interior = total - n;
    mesh.fill_vertex_count += interior;
    if interior > 0 {
        let pos2 = |k: usize| mesh.image[index[k] as usize];
        let mut weights: Vec<(usize, usize, f64)> = Vec::new();
        for f in &faces {
            for c in 0..3 {
                // Cotangent at corner c weighs the opposite edge.
                let (i, j, k) = (f[c], f[(c + 1) % 3], f[(c + 2) % 3]);
                let (u, v) = (pos2(j) - pos2(i), pos2(k) - pos2(i));
                let cross = (u.x * v.y - u.y * v.x).abs().max(1e-300);
                weights.push((j, k, 0.5 * u.dot(&v) / cross));
            }
        }
        let mean = weights.iter().map(|w| w.2.abs()).sum::<f64>() / weights.len().max(1) as f64;
        let mut triplets: Vec<Triplet<usize, usize, f64>> = Vec::new();
        let mut rhs = vec![Vec3::zeros(); interior];
        for &(a, b, w) in &weights {
            let w = w.max(1e-6 * mean);
            for (i, j) in [(a, b), (b, a)] {
                if i < n {
                    continue;
                }
                let row = i - n;
                triplets.push(Triplet::new(row, row, w));
                if j < n {
                    rhs[row] += mesh.positions[index[j] as usize] * w;
                } else {
                    triplets.push(Triplet::new(row, j - n, -w));
                }
            }
        }
        let llt = SparseCholesky::new(interior, &triplets).map_err(|e| {
            tracing::debug!("photo: the minimal-surface fill of patch {}: {e:?}", patch + 1);
            PhotoError::Patch {
                patch: format!("{}", patch + 1),
                message: "its inside cannot be filled with a smooth surface: the fill's system has no \
                              solution (its outline collapses or doubles back on itself); look at the curves \
                              around it"
                    .into(),
            }
        })?;
        let x = llt.solve_columns(Mat::from_fn(interior, 3, |k, axis| rhs[k][axis]).as_ref());
        for (k, &vertex) in index[n..].iter().enumerate() {
            mesh.positions[vertex as usize] = Vec3::new(x[(k, 0)], x[(k, 1)], x[(k, 2)]);
        }
    }
    for f in faces {
        push_triangle(mesh, f.map(|k| index[k]), patch);
    }
    Ok(())
}

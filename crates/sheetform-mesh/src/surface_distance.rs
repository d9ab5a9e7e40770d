//! Distance between two triangle surfaces: the exact closest point of a triangle to a point,
//! a [`SurfaceIndex`] (an R-tree of the triangles, by bounding box) that finds the closest point of
//! a whole surface, and the two-sided figures ([`surface_distance`]: Hausdorff and mean
//! distances) and per-vertex distances ([`vertex_distances`], for a colour map) built on it.

use nalgebra::Vector3;
use rayon::prelude::*;
use rstar::{ParentNode, RTree, RTreeNode, RTreeObject, AABB};

use crate::TriangleMesh;

type Vec3 = Vector3<f64>;

/// The face index [`SurfaceIndex::closest_point`] returns when there is no closest point.
const NO_FACE: u32 = u32::MAX;

/// A triangle is treated as its three sides when `|ab × ac|² ≤ DEGENERATE · |ab|² |ac|²`,
/// i.e. when the sine of its angle at `a` is below `√ε ≈ 1.5e-8` (relative, so the same at
/// every model scale). Every angle of a zero-area triangle has a zero sine; the sides lie
/// within `1.5e-8 ×` the triangle's size of every point of such a triangle, and below this
/// threshold the plane's normal would be known no better than that.
const DEGENERATE: f64 = f64::EPSILON;

/// How densely [`surface_distance`] samples each surface.
///
/// Every vertex used by a triangle and every edge midpoint is always a sample; on top of
/// that each face gets `samples_per_face` interior samples, rounded up to a square `k²`:
/// the centroids of the `k²` triangles of the face's regular `k`-fold subdivision, plus the
/// corners and side midpoints of those sub-triangles (so that the mean is a proper composite
/// quadrature, see [`surface_distance`]). The default, 1, samples the face centroid.
/// `0` is read as 1.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SurfaceDistanceOptions {
    /// Interior samples per face (rounded up to a square; default 1, the centroid).
    pub samples_per_face: usize,
}

impl Default for SurfaceDistanceOptions {
    fn default() -> Self {
        Self { samples_per_face: 1 }
    }
}

impl SurfaceDistanceOptions {
    /// These options with `samples_per_face` interior samples per face.
    pub fn with_samples_per_face(mut self, samples_per_face: usize) -> Self {
        self.samples_per_face = samples_per_face;
        self
    }

    /// `k`: the faces are sampled on their `k`-fold subdivision, `k² ≥ samples_per_face`.
    fn subdivision(&self) -> usize {
        let wanted = self.samples_per_face.max(1);
        let mut k = (wanted as f64).sqrt() as usize;
        while k * k < wanted {
            k += 1;
        }
        while k > 1 && (k - 1) * (k - 1) >= wanted {
            k -= 1;
        }
        k.max(1)
    }
}

/// Two-sided distance figures between surfaces A and B (model units).
///
/// `a_to_b_*` are over the samples of A (see [`SurfaceDistanceOptions`]), each measured
/// exactly to the surface of B; `b_to_a_*` the other way round.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceDistance {
    /// The (sampled) Hausdorff distance: `max(a_to_b_max, b_to_a_max)`.
    pub hausdorff: f64,
    /// Largest distance from a sample of A to surface B.
    pub a_to_b_max: f64,
    /// Largest distance from a sample of B to surface A.
    pub b_to_a_max: f64,
    /// `(a_to_b_mean + b_to_a_mean) / 2`: the two one-sided area-weighted means, averaged.
    pub mean: f64,
    /// Area-weighted mean distance from surface A to surface B.
    pub a_to_b_mean: f64,
    /// Area-weighted mean distance from surface B to surface A.
    pub b_to_a_mean: f64,
}

impl SurfaceDistance {
    /// Every figure infinite: there is no surface to be near.
    const INFINITE: Self = Self {
        hausdorff: f64::INFINITY,
        a_to_b_max: f64::INFINITY,
        b_to_a_max: f64::INFINITY,
        mean: f64::INFINITY,
        a_to_b_mean: f64::INFINITY,
        b_to_a_mean: f64::INFINITY,
    };
}

/// An index of a surface's triangles for closest-point queries: an rstar R-tree of the
/// triangles' axis-aligned bounding boxes, bulk-loaded once (`O(n log n)`) and queried
/// many times: the stateful form of [`surface_distance`], for repeated queries against one
/// surface.
///
/// Triangles with a non-finite coordinate are left out (they have no place to be near).
#[derive(Debug, Clone)]
pub struct SurfaceIndex {
    /// The boxes of the finite triangles, each with its face index.
    tree: RTree<FaceBox>,
    /// Every face's corners and unit normal, by face index.
    faces: Vec<IndexedFace>,
}

/// A triangle's bounding box and face index: a leaf of the R-tree (kept small, so that a
/// node's children share few cache lines; the corners are in [`IndexedFace`]).
#[derive(Debug, Clone)]
struct FaceBox {
    bounds: AABB<[f64; 3]>,
    face: u32,
}

impl RTreeObject for FaceBox {
    type Envelope = AABB<[f64; 3]>;

    fn envelope(&self) -> Self::Envelope {
        self.bounds
    }
}

/// A face's corners and the unit normal that skips it on its plane's distance.
#[derive(Debug, Clone, Copy)]
struct IndexedFace {
    corners: [Vec3; 3],
    /// Zero (never skips) unless the sine of the angle at the first corner is above `1e-4`,
    /// so that the normal, and the plane's distance as a lower bound, are accurate to about
    /// `1e-12` (relative): a noisy normal could skip the closest triangle.
    normal: Vec3,
}

impl IndexedFace {
    fn new(corners @ [a, b, c]: [Vec3; 3]) -> Self {
        let (ab, ac) = (b - a, c - a);
        let cross = ab.cross(&ac);
        let normal_squared = cross.norm_squared();
        let normal = if normal_squared > 1e-8 * ab.norm_squared() * ac.norm_squared() && normal_squared.is_finite() {
            cross / normal_squared.sqrt()
        } else {
            Vec3::zeros()
        };
        Self { corners, normal }
    }
}

/// Squared distance from `p` to the box (0 inside): a lower bound of the squared distance
/// to anything in it.
#[inline]
fn box_distance_squared(bounds: &AABB<[f64; 3]>, p: &[f64; 3]) -> f64 {
    let (lo, hi) = (bounds.lower(), bounds.upper());
    (0..3)
        .map(|i| {
            let outside = (lo[i] - p[i]).max(p[i] - hi[i]).max(0.0);
            outside * outside
        })
        .sum()
}

impl SurfaceIndex {
    /// Indexes the triangles of `mesh`.
    ///
    /// # Panics
    /// If a triangle refers to a vertex that does not exist.
    pub fn new(mesh: &TriangleMesh) -> Self {
        let faces: Vec<IndexedFace> = mesh
            .triangles
            .iter()
            .map(|t| IndexedFace::new(t.map(|i| mesh.positions[i as usize])))
            .collect();
        let boxes = faces
            .iter()
            .enumerate()
            .filter(|(_, face)| face.corners.iter().all(|p| p.iter().all(|x| x.is_finite())))
            .map(|(f, face)| {
                let [a, b, c] = face.corners;
                FaceBox {
                    bounds: AABB::from_corners(a.inf(&b).inf(&c).into(), a.sup(&b).sup(&c).into()),
                    face: f as u32,
                }
            })
            .collect();
        Self {
            tree: RTree::bulk_load(boxes),
            faces,
        }
    }

    /// Whether the index has no (finite) triangle, so that no point has a closest point.
    pub fn is_empty(&self) -> bool {
        self.tree.size() == 0
    }

    /// The point of the surface closest to `p`: `(point, distance, face)`.
    ///
    /// Depth-first branch and bound over the R-tree (Roussopoulos, Kelley & Vincent 1995):
    /// a node's children are visited nearest box first, and a node or triangle whose box
    /// (or, for a triangle, whose plane) is no nearer than the best triangle so far is
    /// skipped, since these distances are lower bounds of the triangles' inside; the rest
    /// are measured exactly (Ericson's Voronoi-region method, *Real-Time Collision
    /// Detection* §5.1.5). So the result is the exact closest point (ties: any of the
    /// closest faces).
    ///
    /// An empty index, a `p` with a non-finite coordinate, or a squared distance beyond
    /// `f64`'s range (coordinates beyond ~1e154) gives `(p, ∞, u32::MAX)`.
    pub fn closest_point(&self, p: Vec3) -> (Vec3, f64, u32) {
        self.closest_point_from(p, NO_FACE)
    }

    /// [`Self::closest_point`], starting the search from face `guess` (a finite face, or
    /// `NO_FACE`): the same result, found sooner when `guess` is near (the previous query's
    /// face, for a run of nearby queries).
    fn closest_point_from(&self, p: Vec3, guess: u32) -> (Vec3, f64, u32) {
        if !p.iter().all(|x| x.is_finite()) || self.is_empty() {
            return (p, f64::INFINITY, NO_FACE);
        }
        let point: [f64; 3] = p.into();
        let (mut best, mut best_squared) = (NO_FACE, f64::INFINITY);
        if let Some(face) = self.faces.get(guess as usize) {
            best = guess;
            best_squared = (closest_point_on_triangle(p, face.corners) - p).norm_squared();
        }
        // Nodes to visit with their boxes' squared distances, nearest on top.
        let mut stack: Vec<(f64, &ParentNode<FaceBox>)> = Vec::with_capacity(64);
        stack.push((0.0, self.tree.root()));
        while let Some((node_squared, node)) = stack.pop() {
            if node_squared >= best_squared {
                continue;
            }
            let first_child = stack.len();
            for child in node.children() {
                match child {
                    RTreeNode::Leaf(leaf) => {
                        if box_distance_squared(&leaf.bounds, &point) >= best_squared {
                            continue;
                        }
                        let face = &self.faces[leaf.face as usize];
                        let plane = face.normal.dot(&(p - face.corners[0]));
                        if plane * plane >= best_squared {
                            continue;
                        }
                        let squared = (closest_point_on_triangle(p, face.corners) - p).norm_squared();
                        if squared < best_squared {
                            (best, best_squared) = (leaf.face, squared);
                        }
                    }
                    RTreeNode::Parent(parent) => {
                        let squared = box_distance_squared(&parent.envelope(), &point);
                        if squared < best_squared {
                            stack.push((squared, parent));
                        }
                    }
                }
            }
            stack[first_child..].sort_unstable_by(|a, b| b.0.total_cmp(&a.0));
        }
        match self.faces.get(best as usize) {
            Some(face) => {
                let q = closest_point_on_triangle(p, face.corners);
                (q, (q - p).norm(), best)
            }
            // Every squared distance overflowed (coordinates beyond ~1e154).
            None => (p, f64::INFINITY, NO_FACE),
        }
    }
}

/// The point of triangle `[a, b, c]` closest to `p` (exact, up to rounding).
///
/// Voronoi-region method (Ref: Ericson 2005, *Real-Time Collision Detection*, §5.1.5).
/// With `ab = b − a`, `ac = c − a` and `d₁ = ab·(p−a)`, `d₂ = ac·(p−a)`, `d₃ = ab·(p−b)`,
/// `d₄ = ac·(p−b)`, `d₅ = ab·(p−c)`, `d₆ = ac·(p−c)`, the regions are tested in the book's
/// order (`a`, `b`, `ab`, `c`, `ac`, `bc`, face):
/// - vertex `a` if `d₁ ≤ 0, d₂ ≤ 0`; vertex `b` if `d₃ ≥ 0, d₄ ≤ d₃`; vertex `c` if
///   `d₆ ≥ 0, d₅ ≤ d₆`;
/// - edge `ab` if `v_c = d₁d₄ − d₃d₂ ≤ 0, d₁ ≥ 0, d₃ ≤ 0`: `a + ab · d₁/(d₁ − d₃)`;
///   edge `ac` if `v_b = d₅d₂ − d₁d₆ ≤ 0, d₂ ≥ 0, d₆ ≤ 0`: `a + ac · d₂/(d₂ − d₆)`;
///   edge `bc` if `v_a = d₃d₆ − d₅d₄ ≤ 0, d₄ − d₃ ≥ 0, d₅ − d₆ ≥ 0`:
///   `b + (c − b) · (d₄ − d₃)/((d₄ − d₃) + (d₅ − d₆))`
///   (`v_a, v_b, v_c` are the barycentric coordinates of the projection of `p`, times
///   `|n|²`, `n = ab × ac`);
/// - else the face: the projection of `p` on the plane.
///
/// Departures from the book: the face case projects along the normal,
/// `p − n (n·(p−a))/|n|²`, rather than forming `a + ab·v_b/Σ + ac·v_c/Σ` (the same point;
/// the distance is then the better conditioned `|n·(p−a)|/|n|`); and a degenerate triangle
/// (`|ab × ac|² ≤ ε |ab|² |ac|²`: collinear corners, a repeated corner, a single point) is measured as
/// its three sides, so it never gives NaN.
pub fn closest_point_on_triangle(p: Vec3, [a, b, c]: [Vec3; 3]) -> Vec3 {
    let ab = b - a;
    let ac = c - a;
    let normal = ab.cross(&ac);
    let normal_squared = normal.norm_squared();
    // Asked this way round so that NaN and infinities take the degenerate path too.
    let well_shaped = normal_squared > DEGENERATE * ab.norm_squared() * ac.norm_squared();
    if !well_shaped {
        return [
            closest_point_on_segment(p, a, b),
            closest_point_on_segment(p, b, c),
            closest_point_on_segment(p, c, a),
        ]
        .into_iter()
        .min_by(|q, r| (q - p).norm_squared().total_cmp(&(r - p).norm_squared()))
        .unwrap_or(a);
    }
    let ap = p - a;
    let d1 = ab.dot(&ap);
    let d2 = ac.dot(&ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let d3 = ab.dot(&bp);
    let d4 = ac.dot(&bp);
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        // d₁ − d₃ = |ab|² > 0.
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let d5 = ab.dot(&cp);
    let d6 = ac.dot(&cp);
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        // d₂ − d₆ = |ac|² > 0.
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        // (d₄ − d₃) + (d₅ − d₆) = |bc|² > 0.
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    p - normal * (normal.dot(&ap) / normal_squared)
}

/// The point of segment `ab` closest to `p` (`a` if the segment is a point).
fn closest_point_on_segment(p: Vec3, a: Vec3, b: Vec3) -> Vec3 {
    let ab = b - a;
    let length_squared = ab.norm_squared();
    let has_length = length_squared > 0.0;
    if !has_length {
        return a;
    }
    let t = ((p - a).dot(&ab) / length_squared).clamp(0.0, 1.0);
    if t.is_nan() {
        a
    } else {
        a + ab * t
    }
}

/// Distance of each vertex of `a` to surface `b` (for a colour map), by vertex index.
///
/// Unused vertices are measured too. A vertex with a non-finite coordinate, or an empty
/// `b`, gives `∞`.
///
/// # Example
/// ```
/// use sheetform_mesh::{vertex_distances, SurfaceIndex, TriangleMesh};
///
/// let floor = TriangleMesh::grid(1, 1, |u, v| [u, v, 0.0]);
/// let shelf = TriangleMesh::grid(1, 1, |u, v| [u, v, 0.25]);
/// let distances = vertex_distances(&shelf, &SurfaceIndex::new(&floor));
/// assert!(distances.iter().all(|d| (d - 0.25).abs() < 1e-15));
/// ```
pub fn vertex_distances(a: &TriangleMesh, b: &SurfaceIndex) -> Vec<f64> {
    a.positions
        .par_chunks(CHUNK)
        .flat_map_iter(|chunk| {
            let mut guess = NO_FACE;
            chunk.iter().map(move |&p| {
                let (_, d, face) = b.closest_point_from(p, guess);
                guess = face;
                d
            })
        })
        .collect()
}

/// Two-sided distance between surfaces `a` and `b`: the sampled Hausdorff distance and the
/// area-weighted mean distances (model units).
///
/// `a_to_b_max = max_s d(s, B)` over the samples `s` of A ([`SurfaceDistanceOptions`]),
/// `d(s, B)` the exact distance to the closest point of B ([`SurfaceIndex`]); likewise
/// `b_to_a_max`, and `hausdorff = max(a_to_b_max, b_to_a_max)`. Since `d(·, B)` is
/// 1-Lipschitz, the sampled maximum is below the true one-sided Hausdorff distance by at
/// most the distance from a point of A to its nearest sample, less than
/// `ℓ / (2√3 k)` for faces of longest edge `ℓ` sampled on their `k`-fold subdivision;
/// it is exact when the farthest point is a vertex (two planar meshes, one moved).
///
/// `a_to_b_mean ≈ (1/|A|) ∫_A d(x, B) dA`, by the 7-point rule on each sub-triangle of area
/// `α`: weight `α/20` at each corner, `2α/15` at each side midpoint, `9α/20` at the
/// centroid (exact for cubic polynomials; composite over the `k`-fold subdivision). A mesh
/// whose faces all have zero area gets the plain mean of its samples.
/// `mean = (a_to_b_mean + b_to_a_mean) / 2`.
///
/// Each vertex and edge sample is measured once however many faces share it: with the
/// default options, `V + E + F ≈ 3F` closest-point queries per side, run on rayon's
/// thread pool in fixed chunks summed in order, so the figures do not depend on the number
/// of threads.
///
/// Empty or non-finite input: if either mesh has no triangle (or `b` none with finite
/// corners), every figure is `∞`; a sample with a non-finite coordinate is at distance `∞`,
/// so the figures of its side are `∞`. Never NaN.
///
/// # Panics
/// If a triangle refers to a vertex that does not exist.
///
/// # Example
/// ```
/// use sheetform_mesh::primitives::icosphere;
/// use sheetform_mesh::{surface_distance, SurfaceDistanceOptions};
///
/// let inner = icosphere(1.0, 3);
/// let mut outer = inner.clone();
/// outer.positions.iter_mut().for_each(|p| *p *= 1.1);
/// let distance = surface_distance(&inner, &outer, &SurfaceDistanceOptions::default());
/// assert!((distance.hausdorff - 0.1).abs() < 0.01);
/// assert!(distance.mean < distance.hausdorff);
/// ```
pub fn surface_distance(a: &TriangleMesh, b: &TriangleMesh, options: &SurfaceDistanceOptions) -> SurfaceDistance {
    if a.triangles.is_empty() || b.triangles.is_empty() {
        return SurfaceDistance::INFINITE;
    }
    let (index_a, index_b) = (SurfaceIndex::new(a), SurfaceIndex::new(b));
    if index_a.is_empty() || index_b.is_empty() {
        return SurfaceDistance::INFINITE;
    }
    let k = options.subdivision();
    let (a_to_b_max, a_to_b_mean) = one_sided(a, &index_b, k);
    let (b_to_a_max, b_to_a_mean) = one_sided(b, &index_a, k);
    SurfaceDistance {
        hausdorff: a_to_b_max.max(b_to_a_max),
        a_to_b_max,
        b_to_a_max,
        mean: 0.5 * (a_to_b_mean + b_to_a_mean),
        a_to_b_mean,
        b_to_a_mean,
    }
}

/// Samples measured in a row by one thread, each search starting from the previous
/// sample's face. Fixed, so that the sums (and so the figures) do not depend on the number
/// of threads.
const CHUNK: usize = 1024;

/// Samples gathered before they are measured in parallel (bounds the memory whatever the
/// sampling density).
const BATCH: usize = 64 * CHUNK;

/// Running figures of one side: the largest distance and the sums of the means.
#[derive(Debug, Clone, Copy, Default)]
struct Figures {
    max: f64,
    weighted_sum: f64,
    weight_total: f64,
    plain_sum: f64,
    count: usize,
}

impl Figures {
    /// The figures of `samples` (`(point, weight)`), measured to `surface` in order.
    fn measure(surface: &SurfaceIndex, samples: &[(Vec3, f64)]) -> Self {
        let mut figures = Self::default();
        let mut guess = NO_FACE;
        for &(p, weight) in samples {
            let (_, d, face) = surface.closest_point_from(p, guess);
            guess = face;
            figures.max = figures.max.max(d);
            if weight > 0.0 {
                figures.weighted_sum += weight * d;
                figures.weight_total += weight;
            }
            figures.plain_sum += d;
            figures.count += 1;
        }
        figures
    }

    /// Adds the figures of `batch`, measured in parallel chunks and summed in order.
    fn add_batch(&mut self, surface: &SurfaceIndex, batch: &[(Vec3, f64)]) {
        let parts: Vec<Self> = batch
            .par_chunks(CHUNK)
            .map(|chunk| Self::measure(surface, chunk))
            .collect();
        for part in parts {
            self.max = self.max.max(part.max);
            self.weighted_sum += part.weighted_sum;
            self.weight_total += part.weight_total;
            self.plain_sum += part.plain_sum;
            self.count += part.count;
        }
    }

    /// The area-weighted mean (the plain mean if there is no area; `∞` if any distance is).
    fn mean(&self) -> f64 {
        if self.max.is_infinite() {
            f64::INFINITY
        } else if self.weight_total > 0.0 {
            self.weighted_sum / self.weight_total
        } else if self.count > 0 {
            self.plain_sum / self.count as f64
        } else {
            f64::INFINITY
        }
    }
}

/// `(max, area-weighted mean)` of the distance from the samples of `mesh` to `surface`.
fn one_sided(mesh: &TriangleMesh, surface: &SurfaceIndex, k: usize) -> (f64, f64) {
    let mut figures = Figures::default();
    let mut batch = Vec::with_capacity(BATCH);
    for_each_sample(mesh, k, |p, weight| {
        batch.push((p, weight));
        if batch.len() == BATCH {
            figures.add_batch(surface, &batch);
            batch.clear();
        }
    });
    figures.add_batch(surface, &batch);
    (figures.max, figures.mean())
}

/// Calls `visit(point, weight)` once for every sample of `mesh` on the `k`-fold subdivision
/// of its faces: each used vertex, the `2k − 1` points splitting each edge into `2k`, and in
/// each face the interior corners and side midpoints of its `k²` sub-triangles and their
/// centroids. The weights are the composite 7-point rule's summed over the faces sharing a
/// sample; they add up to the mesh's area (non-finite face areas count as 0).
fn for_each_sample(mesh: &TriangleMesh, k: usize, mut visit: impl FnMut(Vec3, f64)) {
    let m = 2 * k;
    let sub_area = |f: usize| {
        let area = mesh.face_area(f) / (k * k) as f64;
        if area.is_finite() {
            area
        } else {
            0.0
        }
    };
    // A corner of a face is a corner of one of its sub-triangles.
    let mut vertex_weight = vec![0.0; mesh.positions.len()];
    let mut used = vec![false; mesh.positions.len()];
    let mut edges: Vec<(u32, u32, f64)> = Vec::with_capacity(3 * mesh.triangles.len());
    for (f, t) in mesh.triangles.iter().enumerate() {
        let area = sub_area(f);
        for side in 0..3 {
            let (i, j) = (t[side], t[(side + 1) % 3]);
            vertex_weight[i as usize] += area / 20.0;
            used[i as usize] = true;
            edges.push((i.min(j), i.max(j), area));
        }
    }
    for (v, &p) in mesh.positions.iter().enumerate() {
        if used[v] {
            visit(p, vertex_weight[v]);
        }
    }
    // Points along an edge: at an even step a corner of 3 sub-triangles of each face on
    // the edge, at an odd one a side midpoint of 1.
    edges.sort_unstable_by_key(|&(i, j, _)| (i, j));
    let mut start = 0;
    while start < edges.len() {
        let (i, j, _) = edges[start];
        let mut end = start;
        let mut area = 0.0;
        while end < edges.len() && (edges[end].0, edges[end].1) == (i, j) {
            area += edges[end].2;
            end += 1;
        }
        start = end;
        if i == j {
            continue;
        }
        let (p, q) = (mesh.positions[i as usize], mesh.positions[j as usize]);
        for step in 1..m {
            let weight = if step % 2 == 0 {
                3.0 * area / 20.0
            } else {
                2.0 * area / 15.0
            };
            visit(p + (q - p) * (step as f64 / m as f64), weight);
        }
    }
    // Inside each face: on the 2k-lattice, corners of 6 sub-triangles (even, even) or
    // side midpoints of 2; then the centroids.
    for (f, t) in mesh.triangles.iter().enumerate() {
        let area = sub_area(f);
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        let (ab, ac) = (b - a, c - a);
        let at = |u: f64, v: f64| a + ab * u + ac * v;
        for i in 1..m {
            for j in 1..m - i {
                let weight = if i % 2 == 0 && j % 2 == 0 {
                    6.0 * area / 20.0
                } else {
                    4.0 * area / 15.0
                };
                visit(at(i as f64 / m as f64, j as f64 / m as f64), weight);
            }
        }
        let kf = k as f64;
        for i in 0..k {
            for j in 0..k - i {
                visit(
                    at((i as f64 + 1.0 / 3.0) / kf, (j as f64 + 1.0 / 3.0) / kf),
                    9.0 * area / 20.0,
                );
                if i + j + 2 <= k {
                    visit(
                        at((i as f64 + 2.0 / 3.0) / kf, (j as f64 + 2.0 / 3.0) / kf),
                        9.0 * area / 20.0,
                    );
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::primitives::icosphere;

    /// A fixed-seed linear congruential generator (Knuth's MMIX constants).
    struct Lcg(u64);

    impl Lcg {
        /// Uniform in `[0, 1)`.
        fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }

        /// Uniform in `[lo, hi)`.
        fn range(&mut self, lo: f64, hi: f64) -> f64 {
            lo + (hi - lo) * self.next()
        }

        fn vector(&mut self, half_width: f64) -> Vec3 {
            Vec3::new(
                self.range(-half_width, half_width),
                self.range(-half_width, half_width),
                self.range(-half_width, half_width),
            )
        }
    }

    /// A random well-shaped triangle (no angle below ~10°) near the origin.
    fn random_triangle(rng: &mut Lcg) -> [Vec3; 3] {
        loop {
            let t = [rng.vector(1.0), rng.vector(1.0), rng.vector(1.0)];
            let [a, b, c] = t;
            let area2 = (b - a).cross(&(c - a)).norm();
            let longest = (b - a).norm().max((c - b).norm()).max((a - c).norm());
            if area2 > 0.2 * longest * longest {
                return t;
            }
        }
    }

    /// The smallest distance from `p` to the points of `[a, b, c]`'s barycentric lattice of
    /// `n` steps (every lattice point lies on the triangle), and the lattice's spacing
    /// bound: every point of the triangle is within one longest edge / `n` of a lattice point.
    fn brute_force_distance(p: Vec3, [a, b, c]: [Vec3; 3], n: usize) -> (f64, f64) {
        let mut best = f64::INFINITY;
        for i in 0..=n {
            for j in 0..=n - i {
                let q = a + (b - a) * (i as f64 / n as f64) + (c - a) * (j as f64 / n as f64);
                best = best.min((q - p).norm());
            }
        }
        let longest = (b - a).norm().max((c - b).norm()).max((a - c).norm());
        (best, longest / n as f64)
    }

    /// Checks the exact closest point against the expected one and against brute force.
    fn check_closest(p: Vec3, triangle: [Vec3; 3], expected: Vec3, region: &str) {
        let q = closest_point_on_triangle(p, triangle);
        assert!(
            (q - expected).norm() < 1e-12,
            "{region}: closest point {q:?}, expected {expected:?}, p = {p:?}"
        );
        let exact = (q - p).norm();
        let (brute, spacing) = brute_force_distance(p, triangle, 120);
        assert!(
            exact <= brute + 1e-12,
            "{region}: exact {exact} beats no lattice point ({brute})"
        );
        assert!(
            brute - exact <= spacing,
            "{region}: exact {exact}, lattice {brute}, spacing {spacing}"
        );
    }

    /// Points built in each Voronoi region of random triangles (each vertex's, each edge's,
    /// the face's, on both sides of the plane) get the region's closest point, and the
    /// distance agrees with a dense sampling of the triangle.
    #[test]
    fn closest_point_on_triangle_matches_each_voronoi_region_and_brute_force() {
        let mut rng = Lcg(36);
        for _ in 0..12 {
            let triangle = random_triangle(&mut rng);
            let [a, b, c] = triangle;
            let normal = (b - a).cross(&(c - a)).normalize();
            for _ in 0..4 {
                let height = rng.range(-1.0, 1.0);
                // Vertex regions: any point with (p − v)·(w − v) ≤ 0 for both other corners w.
                for v in 0..3 {
                    let (corner, u, w) = (triangle[v], triangle[(v + 1) % 3], triangle[(v + 2) % 3]);
                    let p = loop {
                        let p = corner + rng.vector(1.5);
                        if (p - corner).dot(&(u - corner)) < 0.0 && (p - corner).dot(&(w - corner)) < 0.0 {
                            break p;
                        }
                    };
                    check_closest(p, triangle, corner, "vertex");
                }
                // Edge regions: a point of the edge, moved outwards in the plane and off it.
                for e in 0..3 {
                    let (start, end, opposite) = (triangle[e], triangle[(e + 1) % 3], triangle[(e + 2) % 3]);
                    let along = end - start;
                    let mut outward = along.cross(&normal).normalize();
                    if outward.dot(&(opposite - start)) > 0.0 {
                        outward = -outward;
                    }
                    let foot = start + along * rng.range(0.02, 0.98);
                    let p = foot + outward * rng.range(0.01, 1.0) + normal * height;
                    check_closest(p, triangle, foot, "edge");
                }
                // Face region: a point of the face, moved along the normal.
                let (u, v) = (rng.next(), rng.next());
                let (u, v) = if u + v > 1.0 { (1.0 - u, 1.0 - v) } else { (u, v) };
                let foot = a + (b - a) * u + (c - a) * v;
                check_closest(foot + normal * height, triangle, foot, "face");
            }
            // Any point: only the brute force.
            for _ in 0..10 {
                let p = rng.vector(2.0);
                let exact = (closest_point_on_triangle(p, triangle) - p).norm();
                let (brute, spacing) = brute_force_distance(p, triangle, 120);
                assert!(exact <= brute + 1e-12 && brute - exact <= spacing, "{exact} vs {brute}");
            }
        }
    }

    /// Zero-area triangles (collinear corners in either order, a repeated corner, a single
    /// point) are measured as segments or points, never NaN.
    #[test]
    fn degenerate_triangles_are_segments_or_points() {
        let (a, b) = (Vec3::new(0.0, 0.0, 0.0), Vec3::new(2.0, 0.0, 0.0));
        let mid = Vec3::new(1.0, 0.0, 0.0);
        let p = Vec3::new(2.5, 1.0, 0.0);
        for triangle in [[a, b, mid], [a, mid, b], [mid, a, b], [a, b, b], [b, b, a]] {
            let q = closest_point_on_triangle(p, triangle);
            assert!((q - b).norm() < 1e-15, "{triangle:?}: {q:?}");
        }
        let above = Vec3::new(0.5, 3.0, 4.0);
        let q = closest_point_on_triangle(above, [a, b, mid]);
        assert!((q - Vec3::new(0.5, 0.0, 0.0)).norm() < 1e-15);
        let q = closest_point_on_triangle(above, [mid, mid, mid]);
        assert_eq!(q, mid);
        // A sliver far below the threshold of its size.
        let sliver = [a, b, Vec3::new(1.0, 1e-20, 0.0)];
        let q = closest_point_on_triangle(Vec3::new(1.0, 0.0, 1.0), sliver);
        assert!(q.iter().all(|x| x.is_finite()) && (q - mid).norm() < 1e-15);
        // A mesh of a degenerate face only.
        let mesh = TriangleMesh {
            positions: vec![a, b, mid],
            triangles: vec![[0, 1, 2]],
            ..Default::default()
        };
        let index = SurfaceIndex::new(&mesh);
        let (q, d, face) = index.closest_point(above);
        assert_eq!(face, 0);
        assert!((q - Vec3::new(0.5, 0.0, 0.0)).norm() < 1e-15 && (d - 5.0).abs() < 1e-15);
        let figures = surface_distance(&mesh, &mesh, &SurfaceDistanceOptions::default());
        assert!(
            figures.hausdorff.abs() < 1e-15 && figures.mean.abs() < 1e-15,
            "{figures:?}"
        );
    }

    /// A bumpy 25 × 20 grid: 1 000 faces.
    fn bumpy_grid() -> TriangleMesh {
        TriangleMesh::grid(25, 20, |u, v| {
            [
                2.0 * u,
                1.5 * v,
                0.2 * (7.0 * u).sin() * (5.0 * v).cos() + 0.1 * (u * v * 11.0).sin(),
            ]
        })
    }

    /// The index finds the same distance as a brute force over all triangles, and the
    /// point it returns lies on the face it names.
    #[test]
    fn index_closest_point_matches_brute_force_over_all_triangles() {
        let mesh = bumpy_grid();
        assert_eq!(mesh.triangles.len(), 1000);
        let index = SurfaceIndex::new(&mesh);
        let corners: Vec<[Vec3; 3]> = mesh
            .triangles
            .iter()
            .map(|t| t.map(|i| mesh.positions[i as usize]))
            .collect();
        let mut rng = Lcg(1000);
        for _ in 0..500 {
            let p = Vec3::new(rng.range(-0.3, 2.3), rng.range(-0.3, 1.8), rng.range(-0.6, 0.6));
            let brute = corners
                .iter()
                .map(|&t| (closest_point_on_triangle(p, t) - p).norm())
                .fold(f64::INFINITY, f64::min);
            let (q, d, face) = index.closest_point(p);
            assert!((d - brute).abs() < 1e-12, "{p:?}: index {d}, brute force {brute}");
            assert!(((q - p).norm() - d).abs() < 1e-12);
            assert!((closest_point_on_triangle(q, corners[face as usize]) - q).norm() < 1e-12);
        }
    }

    /// Two parallel unit squares `h` apart: every distance is `h`, at every model scale.
    #[test]
    fn parallel_squares_are_their_gap_apart_at_every_scale() {
        for scale in [1e-6, 1.0, 1e6] {
            let h = 0.3 * scale;
            let a = TriangleMesh::grid(1, 1, |u, v| [scale * u, scale * v, 0.0]);
            let b = TriangleMesh::grid(1, 1, |u, v| [scale * u, scale * v, h]);
            for samples in [1, 9] {
                let figures = surface_distance(
                    &a,
                    &b,
                    &SurfaceDistanceOptions::default().with_samples_per_face(samples),
                );
                for value in [
                    figures.hausdorff,
                    figures.a_to_b_max,
                    figures.b_to_a_max,
                    figures.mean,
                    figures.a_to_b_mean,
                    figures.b_to_a_mean,
                ] {
                    assert!((value - h).abs() < 1e-12 * scale, "scale {scale}: {figures:?}");
                }
            }
        }
    }

    /// A unit square against itself shifted by `d` in its plane: the Hausdorff distance is
    /// `d` (the far side's vertices), the one-sided mean `∫₀^d (d − x) dx = d²/2`, which the
    /// composite rule approaches as the sampling is refined.
    #[test]
    fn square_shifted_in_its_plane_is_its_shift_apart() {
        let d = 0.237;
        let a = TriangleMesh::grid(1, 1, |u, v| [u, v, 0.0]);
        let b = TriangleMesh::grid(1, 1, |u, v| [u + d, v, 0.0]);
        let coarse = surface_distance(&a, &b, &SurfaceDistanceOptions::default());
        assert!((coarse.hausdorff - d).abs() < 1e-15, "{coarse:?}");
        assert!((coarse.a_to_b_max - d).abs() < 1e-15 && (coarse.b_to_a_max - d).abs() < 1e-15);
        let fine = surface_distance(&a, &b, &SurfaceDistanceOptions::default().with_samples_per_face(1600));
        assert!((fine.hausdorff - d).abs() < 1e-15);
        let expected = d * d / 2.0;
        for mean in [fine.a_to_b_mean, fine.b_to_a_mean, fine.mean] {
            assert!((mean - expected).abs() < 1e-4, "{mean} vs {expected}");
        }
        assert!((fine.a_to_b_mean - expected).abs() < (coarse.a_to_b_mean - expected).abs());
    }

    /// The largest distance between a sphere mesh's faces and its circumscribed sphere:
    /// `r − ` the nearest face plane's distance to the centre.
    fn chord_error(mesh: &TriangleMesh, radius: f64) -> f64 {
        (0..mesh.triangles.len())
            .map(|f| {
                radius
                    - mesh
                        .face_normal(f)
                        .dot(&mesh.positions[mesh.triangles[f][0] as usize])
                        .abs()
            })
            .fold(0.0, f64::max)
    }

    /// An icosphere against a scaled copy: the Hausdorff distance is the difference of the
    /// radii within the larger mesh's chord error; the means lie below it.
    #[test]
    fn sphere_against_scaled_copy_is_radius_difference_apart() {
        let r1 = 1.0;
        let a = icosphere(r1, 3);
        for r2 in [1.3, 0.8] {
            let mut b = a.clone();
            b.positions.iter_mut().for_each(|p| *p *= r2 / r1);
            let figures = surface_distance(&a, &b, &SurfaceDistanceOptions::default());
            let tolerance = chord_error(if r2 > r1 { &b } else { &a }, r1.max(r2));
            assert!(tolerance > 0.0 && tolerance < 0.01);
            assert!(
                (figures.hausdorff - (r2 - r1).abs()).abs() <= tolerance,
                "r2 = {r2}: {figures:?}, tolerance {tolerance}"
            );
            assert!(figures.mean <= figures.hausdorff && figures.mean >= (r2 - r1).abs() - tolerance);
            // The same at other model scales.
            for scale in [1e-6, 1e6] {
                let scaled = |m: &TriangleMesh| {
                    let mut m = m.clone();
                    m.positions.iter_mut().for_each(|p| *p *= scale);
                    m
                };
                let at_scale = surface_distance(&scaled(&a), &scaled(&b), &SurfaceDistanceOptions::default());
                assert!(
                    (at_scale.hausdorff / scale - figures.hausdorff).abs() < 1e-9,
                    "scale {scale}"
                );
                assert!((at_scale.mean / scale - figures.mean).abs() < 1e-9, "scale {scale}");
            }
        }
    }

    /// A mesh against itself is 0 apart (up to rounding), and so are its vertices.
    #[test]
    fn mesh_against_itself_is_zero_apart() {
        for mesh in [bumpy_grid(), icosphere(2.0, 2)] {
            let figures = surface_distance(
                &mesh,
                &mesh,
                &SurfaceDistanceOptions::default().with_samples_per_face(4),
            );
            assert!(figures.hausdorff < 1e-13 * mesh.scale(), "{figures:?}");
            assert!(figures.mean < 1e-13 * mesh.scale(), "{figures:?}");
            let distances = vertex_distances(&mesh, &SurfaceIndex::new(&mesh));
            assert_eq!(distances.len(), mesh.positions.len());
            assert!(distances.iter().all(|&d| d == 0.0));
        }
    }

    /// The sample weights add up to the area and integrate cubic polynomials exactly over
    /// a triangle at every subdivision (the composite 7-point rule), and every sample
    /// lies on the triangle.
    #[test]
    fn sample_weights_integrate_cubics_exactly() {
        // The unit right triangle: ∫ x³ dA = 1/20, ∫ x²y dA = 1/60, ∫ 1 dA = 1/2.
        let mesh = TriangleMesh {
            positions: vec![Vec3::zeros(), Vec3::x(), Vec3::y()],
            triangles: vec![[0, 1, 2]],
            ..Default::default()
        };
        for k in 1..=4 {
            let (mut area, mut cube, mut mixed, mut count) = (0.0, 0.0, 0.0, 0);
            for_each_sample(&mesh, k, |p, w| {
                assert!(p.x >= -1e-15 && p.y >= -1e-15 && p.x + p.y <= 1.0 + 1e-15 && p.z == 0.0);
                area += w;
                cube += w * p.x.powi(3);
                mixed += w * p.x * p.x * p.y;
                count += 1;
            });
            assert!((area - 0.5).abs() < 1e-15, "k = {k}");
            assert!((cube - 1.0 / 20.0).abs() < 1e-15, "k = {k}: {cube}");
            assert!((mixed - 1.0 / 60.0).abs() < 1e-15, "k = {k}: {mixed}");
            // Lattice points of the 2k-lattice plus k² centroids.
            assert_eq!(count, (2 * k + 1) * (2 * k + 2) / 2 + k * k);
        }
        // Shared vertices and edges are visited once: V + E + F samples by default.
        let grid = bumpy_grid();
        let mut count = 0;
        for_each_sample(&grid, 1, |_, _| count += 1);
        assert_eq!(count, 26 * 21 + (25 * 21 + 26 * 20 + 25 * 20) + 1000);
    }

    /// Samples per face round up to a square.
    #[test]
    fn samples_per_face_round_up_to_a_square() {
        let k = |n| SurfaceDistanceOptions::default().with_samples_per_face(n).subdivision();
        assert_eq!(
            [k(0), k(1), k(2), k(4), k(5), k(9), k(10), k(1600)],
            [1, 1, 2, 2, 3, 3, 4, 40]
        );
    }

    /// No triangles on either side: every figure is infinite, never NaN; a non-finite
    /// vertex makes its side infinite; an empty index has no closest point; overflowing
    /// distances are infinite.
    #[test]
    fn empty_and_non_finite_meshes_give_infinity() {
        let square = TriangleMesh::grid(1, 1, |u, v| [u, v, 0.0]);
        let empty = TriangleMesh::default();
        for figures in [
            surface_distance(&square, &empty, &SurfaceDistanceOptions::default()),
            surface_distance(&empty, &square, &SurfaceDistanceOptions::default()),
            surface_distance(&empty, &empty, &SurfaceDistanceOptions::default()),
        ] {
            assert_eq!(figures, SurfaceDistance::INFINITE);
        }
        let index = SurfaceIndex::new(&empty);
        assert!(index.is_empty());
        let p = Vec3::new(1.0, 2.0, 3.0);
        assert_eq!(index.closest_point(p), (p, f64::INFINITY, u32::MAX));
        assert_eq!(vertex_distances(&square, &index), vec![f64::INFINITY; 4]);

        let mut broken = square.clone();
        broken.positions[1].x = f64::NAN;
        let figures = surface_distance(&broken, &square, &SurfaceDistanceOptions::default());
        assert_eq!(figures.a_to_b_max, f64::INFINITY);
        assert_eq!(figures.a_to_b_mean, f64::INFINITY);
        assert!(!figures.b_to_a_max.is_nan() && !figures.b_to_a_mean.is_nan());
        assert_eq!(
            SurfaceIndex::new(&square)
                .closest_point(Vec3::new(f64::NAN, 0.0, 0.0))
                .1,
            f64::INFINITY
        );
        // Squared distances beyond f64's range: ∞, no panic.
        let mut huge = square.clone();
        huge.positions.iter_mut().for_each(|p| *p *= 1e200);
        let figures = surface_distance(&huge, &square, &SurfaceDistanceOptions::default());
        assert_eq!((figures.hausdorff, figures.mean), (f64::INFINITY, f64::INFINITY));
    }
}

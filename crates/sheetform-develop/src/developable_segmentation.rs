//! Automatic seams: the target cut into a few pieces, each close to a developable surface
//! (its Gauss image close to a circle), so that [`crate::develop_pieces`] has little to
//! move.

use crate::cone_slits::cut_slits;
use crate::DevelopError;
use nalgebra::{Matrix3, Vector3};
use sheetform_mesh::{EdgeTable, TriangleMesh, UnionFind};
use std::cmp::Ordering as CmpOrdering;
use std::collections::BinaryHeap;
use std::f64::consts::TAU;
use std::sync::atomic::{AtomicBool, Ordering};

type Vec3 = Vector3<f64>;

/// Knobs of [`segment_developable`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SegmentationOptions {
    /// Most pieces (the piece budget; pieces the drawn seams already make count against
    /// it, and are kept even when there are more). Default 12.
    pub max_pieces: usize,
    /// Pieces are added (up to the budget) until the area-weighted RMS angle between each
    /// face's normal and its piece's cone is at most this (degrees). Default 2°.
    pub normal_tolerance_degrees: f64,
    /// Weight of compactness against developability when faces are shared out
    /// (dimensionless; the squared distance to a piece's seed over the area a piece
    /// would have if all were equal). 0 gives the best-fitting pieces, larger values
    /// rounder ones with shorter seams. Default 0.02.
    pub compactness: f64,
    /// Pieces smaller than this fraction of the total area are merged into a neighbour
    /// (no slivers to cut and glue). Default 0.005.
    pub min_piece_area_fraction: f64,
    /// A piece whose vertices inside add up to at most this total absolute angle defect
    /// (radians: the area of its Gauss image) is developable already, whatever its cone
    /// fit: it is not split further (a crumpled sheet stays one piece). Default 0.01.
    pub flat_tolerance_radians: f64,
    /// A vertex inside a piece whose angle defect is larger than this (radians) is a cone
    /// point (a box's corner, a coarse mesh's tip) no small move makes flat: a slit, the
    /// shortest edge path from it to its piece's border, is cut to free it. Default π/3
    /// (60°: a box's corner, 90°, is cut; the bumps of a coarse organic mesh are
    /// flattened by moving them). Measured (docs/benchmarks-history.md, session 25): at 0.1 the
    /// slits open wedges that make the developed pieces overlap themselves in the plane,
    /// so the unfolding cuts them again: 34 printed pieces from the wing nut's 11, 70 from
    /// the 1 654-face Spot's 12, 145 from the 7 116-face koala's 12; at 1 rad, 11, 17 and 25,
    /// within 1.7 %, 2.3 % and 2.4 % of the diagonal.
    pub cone_point_radians: f64,
}

impl Default for SegmentationOptions {
    fn default() -> Self {
        Self {
            max_pieces: 12,
            normal_tolerance_degrees: 2.0,
            compactness: 0.02,
            min_piece_area_fraction: 0.005,
            flat_tolerance_radians: 0.01,
            cone_point_radians: std::f64::consts::FRAC_PI_3,
        }
    }
}

/// Largest [`SegmentationOptions::max_pieces`] accepted (a pattern of more cannot be
/// assembled by hand; the work grows with it).
pub const MAX_SEGMENTATION_PIECES: usize = 1_000;

/// Refinement rounds of the faces' sharing-out per piece count (Lloyd iterations).
const LLOYD_ITERATIONS: usize = 12;

/// Passes of the seam straightening.
const STRAIGHTENING_PASSES: usize = 8;

impl SegmentationOptions {
    /// Checks the ranges.
    ///
    /// # Errors
    /// The option named with its value and bounds.
    pub fn validate(&self) -> Result<(), DevelopError> {
        let number = sheetform_geometry::short_number;
        if self.max_pieces == 0 || self.max_pieces > MAX_SEGMENTATION_PIECES {
            return Err(DevelopError::Option {
                option: "max_pieces",
                message: format!(
                    "must be between 1 and {MAX_SEGMENTATION_PIECES}, got {}",
                    self.max_pieces
                ),
            });
        }
        if !(self.normal_tolerance_degrees.is_finite() && (0.0..=90.0).contains(&self.normal_tolerance_degrees)) {
            return Err(DevelopError::Option {
                option: "normal_tolerance_degrees",
                message: format!(
                    "must be between 0 and 90 degrees, got {}",
                    number(self.normal_tolerance_degrees)
                ),
            });
        }
        if !(self.compactness.is_finite() && (0.0..=1e3).contains(&self.compactness)) {
            return Err(DevelopError::Option {
                option: "compactness",
                message: format!("must be between 0 and 1000, got {}", number(self.compactness)),
            });
        }
        if !(self.min_piece_area_fraction.is_finite() && (0.0..=0.5).contains(&self.min_piece_area_fraction)) {
            return Err(DevelopError::Option {
                option: "min_piece_area_fraction",
                message: format!(
                    "must be between 0 and 0.5, got {}",
                    number(self.min_piece_area_fraction)
                ),
            });
        }
        if !(self.flat_tolerance_radians.is_finite() && (0.0..=TAU).contains(&self.flat_tolerance_radians)) {
            return Err(DevelopError::Option {
                option: "flat_tolerance_radians",
                message: format!("must be between 0 and 2π, got {}", number(self.flat_tolerance_radians)),
            });
        }
        if !(self.cone_point_radians.is_finite() && self.cone_point_radians > 0.0) {
            return Err(DevelopError::Option {
                option: "cone_point_radians",
                message: format!("must be a positive angle, got {}", number(self.cone_point_radians)),
            });
        }
        Ok(())
    }
}

/// The developable surface a piece is fitted to, seen through its Gauss image: the
/// normals `n` with `n · axis = cosine`, a circle on the unit sphere. A cone with this
/// axis has it (half-opening `acos(cosine)` of its normals), a cylinder with `cosine = 0`,
/// a plane with `cosine = 1` (one point).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConeProxy {
    /// Unit axis.
    pub axis: Vec3,
    /// Cosine of the angle every normal makes with the axis.
    pub cosine: f64,
}

impl ConeProxy {
    /// The angle (radians) between the unit normal `n` and the nearest normal of the
    /// proxy's circle: `|acos(n · a) − acos(c)|`.
    pub fn deviation(&self, normal: &Vec3) -> f64 {
        (normal.dot(&self.axis).clamp(-1.0, 1.0).acos() - self.cosine.clamp(-1.0, 1.0).acos()).abs()
    }

    /// The circle nearest the area-weighted normals of `faces`: with `m` their mean and
    /// `C = Σ A (n − m)(n − m)ᵀ`, the axis is `C`'s eigenvector of the smallest
    /// eigenvalue (the normal of the plane the Gauss image lies closest to) and
    /// `cosine = axis · m`. A Gauss image close to one point (both smaller eigenvalues
    /// below 1e-10 of the area) is a plane: axis `m / |m|`, cosine 1.
    fn fit(faces: impl Iterator<Item = usize>, normals: &[Vec3], areas: &[f64]) -> Self {
        let mut total = 0.0;
        let mut mean = Vec3::zeros();
        let mut members = Vec::new();
        for f in faces {
            total += areas[f];
            mean += areas[f] * normals[f];
            members.push(f);
        }
        if total <= 0.0 {
            return Self {
                axis: Vec3::z(),
                cosine: 1.0,
            };
        }
        mean /= total;
        let mut covariance = Matrix3::zeros();
        for &f in &members {
            let d = normals[f] - mean;
            covariance += areas[f] / total * d * d.transpose();
        }
        let eigen = covariance.symmetric_eigen();
        let mut order = [0usize, 1, 2];
        order.sort_by(|&i, &j| eigen.eigenvalues[i].total_cmp(&eigen.eigenvalues[j]));
        let plane_like = eigen.eigenvalues[order[1]] < 1e-10;
        if plane_like && mean.norm() > 1e-12 {
            return Self {
                axis: mean.normalize(),
                cosine: 1.0,
            };
        }
        let mut axis: Vec3 = eigen.eigenvectors.column(order[0]).into_owned();
        axis.normalize_mut();
        let cosine = axis.dot(&mean);
        // The mean of unit normals lies inside the sphere: the circle through them has
        // |cosine| ≤ 1 anyway; keep the axis on the normals' side.
        if cosine < 0.0 {
            Self {
                axis: -axis,
                cosine: -cosine,
            }
        } else {
            Self { axis, cosine }
        }
    }
}

/// A target cut into nearly developable pieces.
#[derive(Debug, Clone, PartialEq)]
pub struct Segmentation {
    /// The piece of each face.
    pub face_piece: Vec<u32>,
    /// Number of pieces.
    pub piece_count: usize,
    /// The cone each piece's normals were fitted to.
    pub proxies: Vec<ConeProxy>,
    /// Every seam (vertex pairs, 0-based): edges between two pieces, the drawn seams and
    /// the slits to cone points.
    pub seams: Vec<[u32; 2]>,
    /// Slits cut to free cone points inside pieces.
    pub slit_count: usize,
    /// Area-weighted RMS angle between the faces' normals and their piece's cone, for the
    /// worst piece (radians).
    pub normal_deviation_rms: f64,
    /// Largest angle between a face's normal and its piece's cone (radians).
    pub normal_deviation_max: f64,
}

/// A face offered to a piece in the flooding, cheapest first.
#[derive(Debug, PartialEq)]
struct Offer {
    cost: f64,
    face: u32,
    piece: u32,
}

impl Eq for Offer {}

impl PartialOrd for Offer {
    fn partial_cmp(&self, other: &Self) -> Option<CmpOrdering> {
        Some(self.cmp(other))
    }
}

impl Ord for Offer {
    fn cmp(&self, other: &Self) -> CmpOrdering {
        // BinaryHeap is a max-heap: the smallest cost first, then the lowest face.
        other
            .cost
            .total_cmp(&self.cost)
            .then_with(|| other.face.cmp(&self.face))
            .then_with(|| other.piece.cmp(&self.piece))
    }
}

/// The faces and their neighbours across edges that are not hard seams.
struct FaceGraph {
    normals: Vec<Vec3>,
    areas: Vec<f64>,
    centroids: Vec<Vec3>,
    /// Up to three neighbours per face (`u32::MAX` where there is none).
    neighbours: Vec<[u32; 3]>,
    total_area: f64,
    /// The faces' total area without the emphasis' weights (the compactness term's
    /// scale: the weights draw pieces, they do not make them rounder).
    surface_area: f64,
    /// Angle defect `2π − Σ θ` of each vertex (radians); 0 where it is free (on the
    /// mesh's boundary or a drawn seam, or used by no face).
    defects: Vec<f64>,
}

impl FaceGraph {
    fn new(mesh: &TriangleMesh, table: &EdgeTable, hard: &[bool]) -> Self {
        let nf = mesh.triangles.len();
        let mut normals = Vec::with_capacity(nf);
        let mut areas = Vec::with_capacity(nf);
        let mut centroids = Vec::with_capacity(nf);
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|v| mesh.positions[v as usize]);
            let cross = (b - a).cross(&(c - a));
            let norm = cross.norm();
            let area = 0.5 * norm;
            // A degenerate face weighs nothing and fits every piece.
            if norm > 0.0 && norm.is_finite() {
                normals.push(cross / norm);
                areas.push(area);
            } else {
                normals.push(Vec3::zeros());
                areas.push(0.0);
            }
            centroids.push((a + b + c) / 3.0);
        }
        let mut neighbours = vec![[u32::MAX; 3]; nf];
        for (e, &hard) in hard.iter().enumerate() {
            if hard {
                continue;
            }
            if let [f, g] = table.sides(e) {
                for (x, y) in [(f.face, g.face), (g.face, f.face)] {
                    if let Some(slot) = neighbours[x as usize].iter_mut().find(|s| **s == u32::MAX) {
                        *slot = y;
                    }
                }
            }
        }
        let total_area = areas.iter().sum();
        let nv = mesh.positions.len();
        let angle_sum = sheetform_mesh::vertex_angle_sums(&mesh.positions, &mesh.triangles);
        let mut free = vec![false; nv];
        for (e, &hard) in hard.iter().enumerate() {
            if hard || table.sides(e).len() != 2 {
                for v in table.edges[e] {
                    free[v as usize] = true;
                }
            }
        }
        let defects = (0..nv)
            .map(|v| {
                if free[v] || angle_sum[v] == 0.0 {
                    0.0
                } else {
                    TAU - angle_sum[v]
                }
            })
            .collect();
        Self {
            normals,
            areas,
            centroids,
            neighbours,
            total_area,
            surface_area: total_area,
            defects,
        }
    }

    fn neighbours(&self, f: usize) -> impl Iterator<Item = usize> + '_ {
        self.neighbours[f]
            .iter()
            .filter(|&&g| g != u32::MAX)
            .map(|&g| g as usize)
    }
}

/// Cuts `mesh` into at most [`SegmentationOptions::max_pieces`] pieces whose normals lie
/// close to a circle of the unit sphere (a cone, a cylinder or a plane), never across a
/// drawn seam (`hard`, per edge of `table`) and always across one.
///
/// **Method**: variational shape approximation (Cohen-Steiner, Alliez & Desbrun 2004,
/// §3: Lloyd iterations of a flooding partition and a proxy fit) with the developable
/// proxies of D-Charts (Julius, Kraevoy & Sheffer 2005, §3: a cone per chart, the cost
/// of a face its normal's angle to the cone, plus a compactness term). Departures:
/// the cone is fitted in closed form to the chart's Gauss image (the plane nearest the
/// normals, the smallest-eigenvalue direction of their area-weighted covariance: the
/// Gauss image of a developable is a curve, and of a cone a circle — the idea of Gauss
/// image thinning, Binninger et al. 2021, §4, applied to a whole chart instead of a
/// vertex's ball), not by D-Charts' search over axes; the compactness term is the squared
/// distance to the chart's seed over `total area / pieces`, weighted by
/// [`SegmentationOptions::compactness`], not D-Charts' product of terms.
///
/// Pieces start one per part the drawn seams leave; while the worst piece's RMS normal
/// deviation is above the tolerance and the budget allows, a piece is seeded at the worst
/// face of the piece with the largest area-weighted squared deviation (VSA's insertion),
/// and the partition is refined again. When the budget is spent that way on a target
/// without drawn seams, bands around each principal axis are tried too (see
/// `bands_around`: the globe's or lamp shade's rings, which VSA's insertion from compact
/// seeds does not find) and kept when their total squared deviation is smaller (a
/// departure from both papers). Then pieces below the minimum area join the
/// neighbour they share the longest seam with, and seams are straightened: a face with
/// two or three neighbours in another piece moves there (removing a leaf never splits
/// a piece), which removes the sawtooth a flooding leaves on a triangle mesh.
///
/// `emphasis`: a positive weight per face multiplying its area in every fit, error and
/// area above except the compactness term's scale (a face weighing 4 counts as four of
/// its size: the pieces are drawn to where the weights are large), or empty for none.
///
/// # Errors
/// [`DevelopError::Option`] out of range (and `emphasis` not one positive weight per
/// face), [`DevelopError::Cancelled`] once `stop` is set.
pub fn segment_developable(
    mesh: &TriangleMesh,
    table: &EdgeTable,
    hard: &[bool],
    emphasis: &[f64],
    options: &SegmentationOptions,
    stop: Option<&AtomicBool>,
) -> Result<Segmentation, DevelopError> {
    options.validate()?;
    assert_eq!(hard.len(), table.len(), "one flag per edge of the table");
    let nf = mesh.triangles.len();
    if !emphasis.is_empty() && (emphasis.len() != nf || emphasis.iter().any(|w| !(w.is_finite() && *w > 0.0))) {
        let problem = if emphasis.len() != nf {
            format!("{} weights", emphasis.len())
        } else {
            let (f, w) = emphasis
                .iter()
                .enumerate()
                .find(|(_, w)| !(w.is_finite() && **w > 0.0))
                .expect("a weight is out of range");
            format!("{w} at face {f}")
        };
        return Err(DevelopError::Option {
            option: "emphasis",
            message: format!("must be one positive finite weight per face ({nf}), got {problem}"),
        });
    }
    let mut graph = FaceGraph::new(mesh, table, hard);
    if !emphasis.is_empty() {
        for (area, w) in graph.areas.iter_mut().zip(emphasis) {
            *area *= w;
        }
        graph.total_area = graph.areas.iter().sum();
    }
    let cancelled = || stop.is_some_and(|s| s.load(Ordering::Relaxed));
    // One seed per part the drawn seams leave.
    let mut parts = UnionFind::new(nf);
    for f in 0..nf {
        for g in graph.neighbours(f) {
            parts.union(f as u32, g as u32);
        }
    }
    let mut seeds: Vec<usize> = Vec::new();
    let mut seen = vec![false; nf];
    for f in 0..nf {
        let root = parts.find(f as u32) as usize;
        if !seen[root] {
            seen[root] = true;
            seeds.push(f);
        }
    }
    let part_count = seeds.len();
    let mut face_piece = flood(&graph, &seeds, None, options.compactness);
    let mut proxies = fit_all(&graph, &face_piece, seeds.len());
    loop {
        for _ in 0..LLOYD_ITERATIONS {
            if cancelled() {
                return Err(DevelopError::Cancelled);
            }
            seeds = best_seeds(&graph, &face_piece, &proxies, options.compactness);
            let next = flood(&graph, &seeds, Some(&proxies), options.compactness);
            let changed = next != face_piece;
            face_piece = next;
            proxies = fit_all(&graph, &face_piece, seeds.len());
            if !changed {
                break;
            }
        }
        let errors = piece_errors(&graph, &face_piece, &proxies);
        let curvature = piece_curvatures(mesh, &graph, &face_piece, seeds.len());
        let unfit = |p: usize| {
            errors[p].rms() > options.normal_tolerance_degrees.to_radians()
                && curvature[p] > options.flat_tolerance_radians
        };
        if seeds.len() >= options.max_pieces {
            break;
        }
        // VSA's insertion: the worst face of the piece with the most squared deviation,
        // among the pieces that are neither close to a cone nor flat already.
        let Some(worst_piece) = (0..errors.len())
            .filter(|&p| unfit(p))
            .max_by(|&i, &j| errors[i].squared.total_cmp(&errors[j].squared))
        else {
            break;
        };
        let Some(face) = errors[worst_piece].worst_face else {
            break;
        };
        if seeds.contains(&face) {
            break;
        }
        seeds.push(face);
        proxies.push(ConeProxy::fit(
            std::iter::once(face).chain(graph.neighbours(face)),
            &graph.normals,
            &graph.areas,
        ));
        face_piece = flood(&graph, &seeds, Some(&proxies), options.compactness);
        proxies = fit_all(&graph, &face_piece, seeds.len());
    }
    // A shape the budget does not fit within the tolerance (a sphere, a vase) may fit
    // better in bands around an axis, as globes and lamp shades are made: kept when their
    // normals lie closer to their cones than the pieces above do.
    let mut count = seeds.len();
    if count >= options.max_pieces && part_count == 1 && options.max_pieces >= 2 {
        let squared = |face_piece: &[u32], proxies: &[ConeProxy]| -> f64 {
            piece_errors(&graph, face_piece, proxies)
                .iter()
                .map(|e| e.squared)
                .sum()
        };
        let mut best = squared(&face_piece, &proxies);
        for axis in principal_axes(&graph) {
            if cancelled() {
                return Err(DevelopError::Cancelled);
            }
            let Some((banded, band_proxies)) = bands_around(&graph, axis, options.max_pieces) else {
                continue;
            };
            let error = squared(&banded, &band_proxies);
            tracing::debug!(error, best, "segmentation: bands around a principal axis");
            if error < best {
                best = error;
                count = band_proxies.len();
                face_piece = banded;
            }
        }
    }
    merge_small_pieces(&graph, &mut face_piece, &mut count, options.min_piece_area_fraction);
    straighten_seams(&graph, &mut face_piece, count);
    let proxies = fit_all(&graph, &face_piece, count);
    let errors = piece_errors(&graph, &face_piece, &proxies);
    let mut seam = vec![false; table.len()];
    for (e, flag) in seam.iter_mut().enumerate() {
        *flag = hard[e]
            || match table.sides(e) {
                [f, g] => face_piece[f.face as usize] != face_piece[g.face as usize],
                _ => false,
            };
    }
    // Cone points: inside a piece (not on a seam or the boundary), sharper than the
    // threshold, the sharpest first (a later one may end its slit on an earlier one's).
    let mut on_seam = vec![false; mesh.positions.len()];
    for (e, &cut) in seam.iter().enumerate() {
        if cut || table.sides(e).len() != 2 {
            for v in table.edges[e] {
                on_seam[v as usize] = true;
            }
        }
    }
    let mut cones: Vec<u32> = (0..mesh.positions.len() as u32)
        .filter(|&v| !on_seam[v as usize] && graph.defects[v as usize].abs() > options.cone_point_radians)
        .collect();
    cones.sort_by(|&a, &b| {
        graph.defects[b as usize]
            .abs()
            .total_cmp(&graph.defects[a as usize].abs())
    });
    let slit_count = cut_slits(mesh, table, &mut seam, &cones);
    let seams = (0..table.len()).filter(|&e| seam[e]).map(|e| table.edges[e]).collect();
    Ok(Segmentation {
        slit_count,
        piece_count: count,
        normal_deviation_rms: errors.iter().map(|e| e.rms()).fold(0.0, f64::max),
        normal_deviation_max: errors.iter().map(|e| e.max).fold(0.0, f64::max),
        face_piece,
        proxies,
        seams,
    })
}

/// The principal axes of the surface: the eigenvectors of the area-weighted covariance
/// of the face centroids (a surface of revolution's axis is one of them).
fn principal_axes(graph: &FaceGraph) -> [Vec3; 3] {
    let total = graph.total_area.max(f64::MIN_POSITIVE);
    let centre: Vec3 = graph
        .centroids
        .iter()
        .zip(&graph.areas)
        .map(|(c, a)| c * *a)
        .sum::<Vec3>()
        / total;
    let mut covariance = Matrix3::zeros();
    for (c, a) in graph.centroids.iter().zip(&graph.areas) {
        let d = c - centre;
        covariance += a / total * d * d.transpose();
    }
    let eigen = covariance.symmetric_eigen();
    [0, 1, 2].map(|k| eigen.eigenvectors.column(k).into_owned())
}

/// `count` pieces in bands around `axis`: band `i` starts as the cone whose normals
/// make the angle `(i + ½) π / count` with the axis (caps at both ends, for a sphere the
/// bands of equal latitude of a lamp shade or a globe cut in rings), seeded at its
/// best-fitting face and grown by fit alone (no compactness: a band goes round), then
/// refined by Lloyd iterations with the same cost. `None` when two bands would start from
/// one face (a shape with too few slopes along this axis).
fn bands_around(graph: &FaceGraph, axis: Vec3, count: usize) -> Option<(Vec<u32>, Vec<ConeProxy>)> {
    let mut proxies: Vec<ConeProxy> = (0..count)
        .map(|i| ConeProxy {
            axis,
            cosine: ((i as f64 + 0.5) * std::f64::consts::PI / count as f64).cos(),
        })
        .collect();
    let mut seeds: Vec<usize> = proxies
        .iter()
        .map(|proxy| {
            (0..graph.areas.len())
                .filter(|&f| graph.areas[f] > 0.0)
                .min_by(|&f, &g| {
                    proxy
                        .deviation(&graph.normals[f])
                        .total_cmp(&proxy.deviation(&graph.normals[g]))
                })
                .unwrap_or(0)
        })
        .collect();
    let mut distinct = seeds.clone();
    distinct.sort_unstable();
    distinct.dedup();
    if distinct.len() != seeds.len() {
        return None;
    }
    let mut face_piece = flood(graph, &seeds, Some(&proxies), 0.0);
    proxies = fit_all(graph, &face_piece, count);
    for _ in 0..LLOYD_ITERATIONS {
        seeds = best_seeds(graph, &face_piece, &proxies, 0.0);
        let next = flood(graph, &seeds, Some(&proxies), 0.0);
        let changed = next != face_piece;
        face_piece = next;
        proxies = fit_all(graph, &face_piece, count);
        if !changed {
            break;
        }
    }
    Some((face_piece, proxies))
}

/// Each piece's total absolute angle defect over the vertices inside it (all of whose
/// faces are in the piece; radians).
fn piece_curvatures(mesh: &TriangleMesh, graph: &FaceGraph, face_piece: &[u32], count: usize) -> Vec<f64> {
    let nv = mesh.positions.len();
    // The piece of each vertex's faces, or u32::MAX - 1 where they differ.
    let mut vertex_piece = vec![u32::MAX; nv];
    for (f, t) in mesh.triangles.iter().enumerate() {
        for &v in t {
            let slot = &mut vertex_piece[v as usize];
            if *slot == u32::MAX {
                *slot = face_piece[f];
            } else if *slot != face_piece[f] {
                *slot = u32::MAX - 1;
            }
        }
    }
    let mut curvature = vec![0.0; count];
    for (v, &p) in vertex_piece.iter().enumerate() {
        if (p as usize) < count {
            curvature[p as usize] += graph.defects[v].abs();
        }
    }
    curvature
}

/// How well one piece fits its cone.
#[derive(Debug, Clone, Copy, Default)]
struct PieceError {
    area: f64,
    squared: f64,
    max: f64,
    worst_face: Option<usize>,
}

impl PieceError {
    fn rms(&self) -> f64 {
        if self.area > 0.0 {
            (self.squared / self.area).sqrt()
        } else {
            0.0
        }
    }
}

fn piece_errors(graph: &FaceGraph, face_piece: &[u32], proxies: &[ConeProxy]) -> Vec<PieceError> {
    let mut errors = vec![PieceError::default(); proxies.len()];
    for (f, &p) in face_piece.iter().enumerate() {
        if graph.areas[f] <= 0.0 {
            continue;
        }
        let d = proxies[p as usize].deviation(&graph.normals[f]);
        let e = &mut errors[p as usize];
        e.area += graph.areas[f];
        e.squared += graph.areas[f] * d * d;
        if e.worst_face.is_none() || d > e.max {
            e.max = d;
            e.worst_face = Some(f);
        }
    }
    errors
}

fn fit_all(graph: &FaceGraph, face_piece: &[u32], count: usize) -> Vec<ConeProxy> {
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); count];
    for (f, &p) in face_piece.iter().enumerate() {
        members[p as usize].push(f);
    }
    members
        .iter()
        .map(|faces| ConeProxy::fit(faces.iter().copied(), &graph.normals, &graph.areas))
        .collect()
}

/// Each piece's new seed: the face that costs least against its cone and its centre.
fn best_seeds(graph: &FaceGraph, face_piece: &[u32], proxies: &[ConeProxy], compactness: f64) -> Vec<usize> {
    let count = proxies.len();
    let mut centre = vec![Vec3::zeros(); count];
    let mut area = vec![0.0; count];
    for (f, &p) in face_piece.iter().enumerate() {
        centre[p as usize] += graph.areas[f] * graph.centroids[f];
        area[p as usize] += graph.areas[f];
    }
    let scale = graph.surface_area / count as f64;
    let mut best: Vec<(f64, usize)> = vec![(f64::INFINITY, usize::MAX); count];
    for (f, &p) in face_piece.iter().enumerate() {
        let p = p as usize;
        let c = if area[p] > 0.0 {
            centre[p] / area[p]
        } else {
            graph.centroids[f]
        };
        let d = proxies[p].deviation(&graph.normals[f]);
        let cost = d * d + compactness * (graph.centroids[f] - c).norm_squared() / scale.max(f64::MIN_POSITIVE);
        if cost < best[p].0 || best[p].1 == usize::MAX {
            best[p] = (cost, f);
        }
    }
    best.into_iter().map(|(_, f)| f).collect()
}

/// Grows every piece from its seed, the cheapest offer first (VSA's flooding): a face's
/// cost against a piece is its squared angle to the piece's cone plus the compactness
/// term. Without proxies (the first partition) every face costs its distance only.
fn flood(graph: &FaceGraph, seeds: &[usize], proxies: Option<&[ConeProxy]>, compactness: f64) -> Vec<u32> {
    let nf = graph.areas.len();
    let scale = (graph.surface_area / seeds.len() as f64).max(f64::MIN_POSITIVE);
    let cost = |f: usize, p: usize| {
        let distance = (graph.centroids[f] - graph.centroids[seeds[p]]).norm_squared() / scale;
        match proxies {
            Some(proxies) => {
                let d = proxies[p].deviation(&graph.normals[f]);
                d * d + compactness * distance
            }
            None => distance,
        }
    };
    let mut face_piece = vec![u32::MAX; nf];
    let mut heap = BinaryHeap::new();
    for (p, &s) in seeds.iter().enumerate() {
        face_piece[s] = p as u32;
    }
    for (p, &s) in seeds.iter().enumerate() {
        for g in graph.neighbours(s) {
            if face_piece[g] == u32::MAX {
                heap.push(Offer {
                    cost: cost(g, p),
                    face: g as u32,
                    piece: p as u32,
                });
            }
        }
    }
    while let Some(Offer { face, piece, .. }) = heap.pop() {
        let f = face as usize;
        if face_piece[f] != u32::MAX {
            continue;
        }
        face_piece[f] = piece;
        for g in graph.neighbours(f) {
            if face_piece[g] == u32::MAX {
                heap.push(Offer {
                    cost: cost(g, piece as usize),
                    face: g as u32,
                    piece,
                });
            }
        }
    }
    // Every part has a seed, so every face is reached; a face no edge joins to anything
    // (isolated by drawn seams all round) is its own part and seed.
    debug_assert!(face_piece.iter().all(|&p| p != u32::MAX));
    face_piece
}

/// Pieces below `fraction` of the total area join the neighbour they share the most
/// seam edges with (repeatedly, smallest first); pieces are then renumbered densely.
fn merge_small_pieces(graph: &FaceGraph, face_piece: &mut [u32], count: &mut usize, fraction: f64) {
    loop {
        let mut area = vec![0.0; *count];
        for (f, &p) in face_piece.iter().enumerate() {
            area[p as usize] += graph.areas[f];
        }
        let limit = fraction * graph.total_area;
        let mut small: Vec<usize> = (0..*count).filter(|&p| area[p] < limit).collect();
        small.sort_by(|&a, &b| area[a].total_cmp(&area[b]));
        let mut merged = false;
        for p in small {
            let mut shared = vec![0usize; *count];
            for (f, &q) in face_piece.iter().enumerate() {
                if q as usize == p {
                    for g in graph.neighbours(f) {
                        let r = face_piece[g] as usize;
                        if r != p {
                            shared[r] += 1;
                        }
                    }
                }
            }
            if let Some((target, _)) = shared
                .iter()
                .enumerate()
                .filter(|(_, &n)| n > 0)
                .max_by_key(|(_, &n)| n)
            {
                for q in face_piece.iter_mut() {
                    if *q as usize == p {
                        *q = target as u32;
                    }
                }
                merged = true;
                break;
            }
        }
        // Renumber densely.
        let mut label = vec![u32::MAX; *count];
        let mut next = 0u32;
        for q in face_piece.iter_mut() {
            let l = &mut label[*q as usize];
            if *l == u32::MAX {
                *l = next;
                next += 1;
            }
            *q = *l;
        }
        *count = next as usize;
        if !merged {
            return;
        }
    }
}

/// Two faces whose normals differ by less than this (radians) are coplanar: a seam
/// between them runs across a flat face of the target (a box's side cut along its
/// diagonal), where no maker would cut.
const COPLANAR_RADIANS: f64 = 1e-3;

/// Straightens the seams for a few passes (see [`segment_developable`]): a face with two
/// or three neighbours in one other piece moves into it (unless that cuts a flat face of
/// the target in two); a face with more coplanar
/// neighbours in another piece than in its own moves there when its own piece stays
/// connected (each such move removes a seam edge across a flat face, so it ends).
fn straighten_seams(graph: &FaceGraph, face_piece: &mut [u32], count: usize) {
    let mut size = vec![0usize; count];
    for &p in face_piece.iter() {
        size[p as usize] += 1;
    }
    let coplanar = |f: usize, g: usize| {
        graph.areas[f] > 0.0
            && graph.areas[g] > 0.0
            && graph.normals[f].dot(&graph.normals[g]) >= COPLANAR_RADIANS.cos()
    };
    for _ in 0..STRAIGHTENING_PASSES {
        let mut moved = false;
        for f in 0..face_piece.len() {
            let own = face_piece[f];
            if size[own as usize] <= 1 {
                continue;
            }
            let others: Vec<u32> = graph
                .neighbours(f)
                .map(|g| face_piece[g])
                .filter(|&q| q != own)
                .collect();
            let majority = match others.as_slice() {
                [a, b, ..] if a == b => Some(*a),
                [a, _, c] if a == c => Some(*a),
                [_, b, c] if b == c => Some(*b),
                _ => None,
            };
            let flat_in = |q: u32| {
                graph
                    .neighbours(f)
                    .filter(|&g| face_piece[g] == q && coplanar(f, g))
                    .count()
            };
            let own_flat = flat_in(own);
            // The majority's move never cuts a flat face in two.
            let target = majority.filter(|&q| flat_in(q) >= own_flat).or_else(|| {
                others
                    .iter()
                    .copied()
                    .find(|&q| flat_in(q) > own_flat)
                    .filter(|_| stays_connected(graph, face_piece, f))
            });
            if let Some(target) = target {
                size[own as usize] -= 1;
                size[target as usize] += 1;
                face_piece[f] = target;
                moved = true;
            }
        }
        if !moved {
            return;
        }
    }
}

/// Whether `f`'s piece stays connected without `f`: its neighbours in the piece still
/// reach each other (a breadth-first search through the piece, ending once they do).
fn stays_connected(graph: &FaceGraph, face_piece: &[u32], f: usize) -> bool {
    let own = face_piece[f];
    let ends: Vec<usize> = graph.neighbours(f).filter(|&g| face_piece[g] == own).collect();
    if ends.len() <= 1 {
        return true;
    }
    let mut seen = std::collections::HashSet::from([f, ends[0]]);
    let mut queue = std::collections::VecDeque::from([ends[0]]);
    let mut found = 1;
    while let Some(g) = queue.pop_front() {
        for h in graph.neighbours(g) {
            if face_piece[h] == own && seen.insert(h) {
                if ends.contains(&h) {
                    found += 1;
                    if found == ends.len() {
                        return true;
                    }
                }
                queue.push_back(h);
            }
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cone_normal(axis: Vec3, angle: f64, around: f64) -> Vec3 {
        let u = axis
            .cross(&Vec3::x())
            .try_normalize(1e-9)
            .unwrap_or_else(|| axis.cross(&Vec3::y()).normalize());
        let v = axis.cross(&u);
        axis * angle.cos() + (u * around.cos() + v * around.sin()) * angle.sin()
    }

    /// Normals spread around a known cone are fitted back to it exactly.
    #[test]
    fn a_cone_is_fitted_from_its_normals() {
        let axis = Vec3::new(1.0, 2.0, 3.0).normalize();
        let normals: Vec<Vec3> = (0..7).map(|k| cone_normal(axis, 0.6, 0.3 * k as f64)).collect();
        let areas = vec![1.0; normals.len()];
        let proxy = ConeProxy::fit(0..normals.len(), &normals, &areas);
        assert!((proxy.axis - axis).norm() < 1e-9, "{:?}", proxy.axis);
        assert!((proxy.cosine - 0.6f64.cos()).abs() < 1e-9);
        for n in &normals {
            assert!(proxy.deviation(n) < 1e-9);
        }
        // A normal 0.1 rad farther from the axis deviates by 0.1 rad.
        assert!((proxy.deviation(&cone_normal(axis, 0.7, 1.0)) - 0.1).abs() < 1e-9);
    }

    /// A capped cylinder (a can) falls into its three natural pieces: the tube and two
    /// lids, each fitted exactly, with the seams on the two rims.
    #[test]
    fn a_can_is_cut_at_its_rims() {
        let sides = 24;
        let rows = 6;
        let mut positions = Vec::new();
        for i in 0..=rows {
            for j in 0..sides {
                let t = std::f64::consts::TAU * j as f64 / sides as f64;
                positions.push(Vec3::new(t.cos(), t.sin(), 2.0 * i as f64 / rows as f64));
            }
        }
        let mut triangles = Vec::new();
        let at = |i: usize, j: usize| (i * sides + j % sides) as u32;
        for i in 0..rows {
            for j in 0..sides {
                triangles.push([at(i, j), at(i, j + 1), at(i + 1, j + 1)]);
                triangles.push([at(i, j), at(i + 1, j + 1), at(i + 1, j)]);
            }
        }
        let bottom = positions.len() as u32;
        positions.push(Vec3::new(0.0, 0.0, 0.0));
        let top = positions.len() as u32;
        positions.push(Vec3::new(0.0, 0.0, 2.0));
        for j in 0..sides {
            triangles.push([bottom, at(0, j + 1), at(0, j)]);
            triangles.push([top, at(rows, j), at(rows, j + 1)]);
        }
        let mesh = TriangleMesh {
            positions,
            triangles,
            ..Default::default()
        };
        let table = EdgeTable::new(&mesh.triangles, mesh.positions.len());
        let hard = vec![false; table.len()];
        let s = segment_developable(&mesh, &table, &hard, &[], &SegmentationOptions::default(), None).unwrap();
        assert_eq!(s.piece_count, 3);
        assert!(s.normal_deviation_max < 1e-9, "{}", s.normal_deviation_max);
        assert_eq!(s.seams.len(), 2 * sides);
        for [a, b] in &s.seams {
            let z = [a, b].map(|&v| mesh.positions[v as usize].z);
            assert!(
                z[0] == z[1] && (z[0] == 0.0 || z[0] == 2.0),
                "seam off the rims at {z:?}"
            );
        }
    }

    /// A sphere the budget of 12 cannot fit within the tolerance is cut in bands around
    /// one axis, as a globe in rings or a lamp shade: every piece's cone has that axis,
    /// and the normals lie closer to them (4.7° RMS is the bound of 12 bands of equal
    /// latitude, ±7.5° each) than the patches VSA's insertion leaves (8.0° on a UV sphere).
    #[test]
    fn a_sphere_is_cut_in_bands_around_an_axis() {
        let sphere = sheetform_mesh::primitives::icosphere(50.0, 3);
        let table = EdgeTable::new(&sphere.triangles, sphere.positions.len());
        let hard = vec![false; table.len()];
        let s = segment_developable(&sphere, &table, &hard, &[], &SegmentationOptions::default(), None).unwrap();
        assert_eq!(s.piece_count, 12);
        let axis = s.proxies[0].axis;
        for proxy in &s.proxies {
            assert!(proxy.axis.dot(&axis).abs() > 0.99, "{:?} against {axis:?}", proxy.axis);
        }
        let rms = s.normal_deviation_rms.to_degrees();
        assert!(rms < 6.0, "{rms}° RMS");
    }

    /// Weights on a cap of a sphere draw the pieces there: with the cap's faces weighing
    /// 50 times their area, more of the 6 pieces share the cap than without (6 against
    /// 2 when written); weights that are not one positive number per face are
    /// refused naming `emphasis`.
    #[test]
    fn emphasis_draws_the_pieces_to_the_weighted_faces() {
        let sphere = sheetform_mesh::primitives::icosphere(50.0, 3);
        let table = EdgeTable::new(&sphere.triangles, sphere.positions.len());
        let hard = vec![false; table.len()];
        let options = SegmentationOptions {
            max_pieces: 6,
            normal_tolerance_degrees: 0.0,
            ..Default::default()
        };
        let cap: Vec<bool> = sphere
            .triangles
            .iter()
            .map(|t| t.iter().all(|&v| sphere.positions[v as usize].z > 35.0))
            .collect();
        let emphasis: Vec<f64> = cap.iter().map(|&c| if c { 50.0 } else { 1.0 }).collect();
        let pieces_on_cap = |s: &Segmentation| {
            let mut on: Vec<u32> = (0..cap.len()).filter(|&f| cap[f]).map(|f| s.face_piece[f]).collect();
            on.sort_unstable();
            on.dedup();
            on.len()
        };
        let plain = segment_developable(&sphere, &table, &hard, &[], &options, None).unwrap();
        let drawn = segment_developable(&sphere, &table, &hard, &emphasis, &options, None).unwrap();
        assert!(
            pieces_on_cap(&drawn) > pieces_on_cap(&plain),
            "{} pieces on the cap, {} without weights",
            pieces_on_cap(&drawn),
            pieces_on_cap(&plain)
        );
        for bad in [vec![1.0; 3], vec![0.0; cap.len()], vec![f64::NAN; cap.len()]] {
            let error = segment_developable(&sphere, &table, &hard, &bad, &options, None).unwrap_err();
            assert!(error.to_string().contains("emphasis"), "{error}");
        }
    }

    /// A developable whose Gauss image is a curve but no circle (a cone over a wavy
    /// curve) fits no single cone, yet is flat: it stays one piece.
    #[test]
    fn a_flat_piece_that_is_no_cone_is_not_split() {
        let mesh = TriangleMesh::grid(48, 6, |u, v| {
            let t = std::f64::consts::PI * u;
            let r = 1.0 + 0.3 * (3.0 * t).cos();
            let s = 0.3 + 0.7 * v;
            [s * r * t.cos(), s * r * t.sin(), s]
        });
        let table = EdgeTable::new(&mesh.triangles, mesh.positions.len());
        let hard = vec![false; table.len()];
        let s = segment_developable(&mesh, &table, &hard, &[], &SegmentationOptions::default(), None).unwrap();
        assert_eq!(s.piece_count, 1);
        assert!(
            s.normal_deviation_rms.to_degrees() > 2.0,
            "{}",
            s.normal_deviation_rms.to_degrees()
        );
        assert!(s.seams.is_empty());
    }

    #[test]
    fn options_out_of_range_are_named() {
        for (options, name) in [
            (
                SegmentationOptions {
                    max_pieces: 0,
                    ..Default::default()
                },
                "max_pieces",
            ),
            (
                SegmentationOptions {
                    normal_tolerance_degrees: f64::NAN,
                    ..Default::default()
                },
                "normal_tolerance_degrees",
            ),
            (
                SegmentationOptions {
                    compactness: -1.0,
                    ..Default::default()
                },
                "compactness",
            ),
        ] {
            match options.validate() {
                Err(DevelopError::Option { option, .. }) => assert_eq!(option, name),
                other => panic!("{other:?}"),
            }
        }
    }
}

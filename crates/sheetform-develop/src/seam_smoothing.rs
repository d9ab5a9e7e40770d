//! Seams along smooth curves: the staircase of mesh edges that a face labelling leaves
//! is pulled straight by sliding the seams' vertices over the target.

use crate::DevelopError;
use nalgebra::Vector3;
use sheetform_mesh::{closest_point_on_triangle, EdgeTable, TriangleMesh};

type Vec3 = Vector3<f64>;

/// Options of [`smooth_seams`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeamSmoothingOptions {
    /// Smoothing sweeps (0: none). Each halves the seam's wiggle of the next larger
    /// period, so a few remove the staircase while the seam's course stays.
    pub iterations: usize,
    /// The fraction `λ` of the way each sweep moves a seam vertex towards the midpoint
    /// of its two seam neighbours (in (0, 1]).
    pub step: f64,
    /// The least area a face next to a moved vertex keeps, as a fraction of its area in
    /// the target (in (0, 1)): no face becomes a sliver or turns over.
    pub min_area_ratio: f64,
    /// How far the faces round a moved vertex may pass from where the vertex was in
    /// the target, as a fraction of its edges' mean length there (≥ 0): a seam slides
    /// along a flat or gently curved surface, never across a crease (a seam along a
    /// crease stays on it) nor so as to cut a corner off the target.
    pub max_deviation: f64,
    /// How far those faces may pass from where the vertex was, as a fraction of how far
    /// it moves (≥ 0): `0.3` lets a vertex slide across edges whose faces turn by up to
    /// about 35° (`2 asin 0.3`; a developed surface bends along its rulings) and keeps it
    /// off sharper creases and corners at any mesh size (a box's corner stays, where
    /// [`Self::max_deviation`] alone would let it move by a twentieth of the box's edge).
    /// Measured (docs/benchmarks-history.md, session 32): 0.1 kept most of the staircase of a
    /// developed sphere (369 of 440 corners), 0.3 and 0.5 removed most (64, 54).
    pub max_deviation_per_move: f64,
}

impl Default for SeamSmoothingOptions {
    fn default() -> Self {
        Self {
            iterations: 6,
            step: 0.5,
            min_area_ratio: 0.25,
            max_deviation: 0.05,
            max_deviation_per_move: 0.3,
        }
    }
}

/// Most [`SeamSmoothingOptions::iterations`] accepted (more change nothing: each vertex
/// stays in the faces round it).
pub const MAX_SEAM_SMOOTHING_ITERATIONS: usize = 100;

impl SeamSmoothingOptions {
    /// Checks the options' ranges.
    ///
    /// # Errors
    /// [`DevelopError::Option`] naming the option out of range.
    pub fn validate(&self) -> Result<(), DevelopError> {
        if self.iterations > MAX_SEAM_SMOOTHING_ITERATIONS {
            return Err(DevelopError::Option {
                option: "seam_smoothing",
                message: format!(
                    "must be at most {MAX_SEAM_SMOOTHING_ITERATIONS} sweeps, got {}",
                    self.iterations
                ),
            });
        }
        if !(self.step > 0.0 && self.step <= 1.0) {
            return Err(DevelopError::Option {
                option: "seam_smoothing.step",
                message: format!("must be in (0, 1], got {}", self.step),
            });
        }
        if !(self.min_area_ratio > 0.0 && self.min_area_ratio < 1.0) {
            return Err(DevelopError::Option {
                option: "seam_smoothing.min_area_ratio",
                message: format!("must be in (0, 1), got {}", self.min_area_ratio),
            });
        }
        for (option, value) in [
            ("seam_smoothing.max_deviation", self.max_deviation),
            ("seam_smoothing.max_deviation_per_move", self.max_deviation_per_move),
        ] {
            if !(value >= 0.0 && value.is_finite()) {
                return Err(DevelopError::Option {
                    option,
                    message: format!("must be finite and at least 0, got {value}"),
                });
            }
        }
        Ok(())
    }
}

/// What [`smooth_seams`] did.
#[derive(Debug, Clone, PartialEq)]
pub struct SmoothedSeams {
    /// Every vertex's position: the seams' inner vertices slid over the target, the
    /// others as they were.
    pub positions: Vec<Vec3>,
    /// Vertices that moved.
    pub moved_count: usize,
    /// Largest distance a vertex moved (model units).
    pub displacement_max: f64,
}

/// Slides the inner vertices of `seams` (vertex pairs along edges of `table`) over the
/// target so that each seam runs along a smooth curve instead of the staircase of mesh
/// edges a face labelling leaves.
///
/// **Method**: Laplacian smoothing of each seam as a polyline (Taubin 1995, §3, with the
/// umbrella operator of a curve: `p ← p + λ ((p₋ + p₊)/2 − p)`, Jacobi sweeps), each new
/// point projected to the closest point of the vertex's own star in the target (Ericson
/// 2005, §5.1.5), so that the surface stays the target's and no vertex leaves the faces
/// round it. A move that would leave a face round the vertex smaller than
/// [`SeamSmoothingOptions::min_area_ratio`] of its area, or turned over, or whose faces
/// would pass farther from the vertex's place in the target than
/// [`SeamSmoothingOptions::max_deviation`] edge lengths or
/// [`SeamSmoothingOptions::max_deviation_per_move`] times the move (a crease cut across,
/// a corner cut off), is halved (three times
/// at most) and otherwise not taken. The bounds are checked for each move: a face's
/// area and side are checked again by every later move of one of its corners, the
/// deviation from a vertex's place only when that vertex moves (a neighbour moving after
/// it may bend its faces a little more). A sweep with `λ = ½` removes the zigzag of
/// period two edges and halves that of period four; a seam's course (lower frequencies)
/// moves by `λ κ h²/2` per sweep at most, `κ` its curvature and `h` the edge length.
///
/// Only a vertex on exactly two seam edges, inside the mesh (every edge round it has two
/// faces) and not `locked` moves: the ends of slits, the corners where three pieces
/// meet, the mesh's boundary and the locked vertices (fixed, on a mirror plane, on drawn
/// seams) stay. The connectivity is unchanged, so every vertex keeps its number.
/// A departure from the papers of `develop` (segmentations cut along mesh edges): the
/// smooth seams that VSA and D-Charts leave to a remeshing, here without one.
pub fn smooth_seams(
    mesh: &TriangleMesh,
    table: &EdgeTable,
    seams: &[[u32; 2]],
    locked: &[bool],
    options: &SeamSmoothingOptions,
) -> SmoothedSeams {
    let nv = mesh.positions.len();
    let original = &mesh.positions;
    let mut positions = original.clone();
    // Each vertex's seam neighbours (its distinct seam edges).
    let mut neighbours: Vec<Vec<u32>> = vec![Vec::new(); nv];
    let mut seam_edge = vec![false; table.len()];
    for &[a, b] in seams {
        if let Some(e) = table.find(a, b) {
            if !seam_edge[e] {
                seam_edge[e] = true;
                neighbours[a as usize].push(b);
                neighbours[b as usize].push(a);
            }
        }
    }
    let mut on_boundary = vec![false; nv];
    for (e, &[a, b]) in table.edges.iter().enumerate() {
        if table.sides(e).len() != 2 {
            on_boundary[a as usize] = true;
            on_boundary[b as usize] = true;
        }
    }
    let movable: Vec<u32> = (0..nv as u32)
        .filter(|&v| {
            let v = v as usize;
            neighbours[v].len() == 2 && !on_boundary[v] && !locked.get(v).copied().unwrap_or(false)
        })
        .collect();
    // The faces round each movable vertex, with their normals (twice the area) in the
    // target.
    let mut star: Vec<Vec<usize>> = vec![Vec::new(); nv];
    let mut is_movable = vec![false; nv];
    for &v in &movable {
        is_movable[v as usize] = true;
    }
    for (f, t) in mesh.triangles.iter().enumerate() {
        for &v in t {
            if is_movable[v as usize] {
                star[v as usize].push(f);
            }
        }
    }
    let normal = |positions: &[Vec3], f: usize| {
        let [a, b, c] = mesh.triangles[f].map(|v| positions[v as usize]);
        (b - a).cross(&(c - a))
    };
    let target_normals: Vec<Vec3> = (0..mesh.triangles.len()).map(|f| normal(original, f)).collect();
    // Each movable vertex's deviation allowed (its edges' mean length in the target
    // times the fraction).
    let mut reach = vec![0.0; nv];
    {
        let mut count = vec![0usize; nv];
        for &[a, b] in &table.edges {
            let length = (original[a as usize] - original[b as usize]).norm();
            for v in [a, b] {
                reach[v as usize] += length;
                count[v as usize] += 1;
            }
        }
        for (r, &c) in reach.iter_mut().zip(&count) {
            *r *= options.max_deviation / c.max(1) as f64;
        }
    }
    // Whether `v` may stand at `to`: every face round it keeps its side and enough area,
    // and they pass within the deviation allowed of where it was in the target.
    let admissible = |positions: &mut [Vec3], v: usize, to: Vec3| {
        let was = positions[v];
        positions[v] = to;
        let corners = |f: usize| mesh.triangles[f].map(|w| positions[w as usize]);
        let shaped = star[v].iter().all(|&f| {
            let now = normal(positions, f);
            let before = &target_normals[f];
            now.dot(before) > 0.0 && now.norm() >= options.min_area_ratio * before.norm()
        });
        let deviation = star[v]
            .iter()
            .map(|&f| (closest_point_on_triangle(original[v], corners(f)) - original[v]).norm())
            .fold(f64::INFINITY, f64::min);
        let close =
            shaped && deviation <= reach[v] && deviation <= options.max_deviation_per_move * (to - original[v]).norm();
        positions[v] = was;
        close
    };
    // The closest point to `p` on the faces round `v` in the target.
    let onto_star = |v: usize, p: Vec3| {
        star[v]
            .iter()
            .map(|&f| closest_point_on_triangle(p, mesh.triangles[f].map(|w| original[w as usize])))
            .min_by(|q, r| (q - p).norm_squared().total_cmp(&(r - p).norm_squared()))
            .unwrap_or(original[v])
    };
    for _ in 0..options.iterations {
        let goals: Vec<Vec3> = movable
            .iter()
            .map(|&v| {
                let v = v as usize;
                let [a, b] = [neighbours[v][0], neighbours[v][1]].map(|w| positions[w as usize]);
                positions[v] + options.step * ((a + b) / 2.0 - positions[v])
            })
            .collect();
        for (&v, goal) in movable.iter().zip(goals) {
            let v = v as usize;
            let from = positions[v];
            let mut fraction = 1.0;
            for _ in 0..4 {
                let to = onto_star(v, from + fraction * (goal - from));
                if to.iter().all(|c| c.is_finite()) && admissible(&mut positions, v, to) {
                    positions[v] = to;
                    break;
                }
                fraction *= 0.5;
            }
        }
    }
    let mut moved_count = 0;
    let mut displacement_max: f64 = 0.0;
    for (p, q) in positions.iter().zip(original) {
        let d = (p - q).norm();
        if d > 0.0 {
            moved_count += 1;
            displacement_max = displacement_max.max(d);
        }
    }
    tracing::debug!(moved_count, displacement_max, "develop: seams smoothed");
    SmoothedSeams {
        positions,
        moved_count,
        displacement_max,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat grid of unit squares, each cut along the diagonal from its lower left to
    /// its upper right corner; `n × n` squares.
    fn grid(n: u32) -> TriangleMesh {
        let mut positions = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                positions.push(Vec3::new(i as f64, j as f64, 0.0));
            }
        }
        let at = |i: u32, j: u32| j * (n + 1) + i;
        let mut triangles = Vec::new();
        for j in 0..n {
            for i in 0..n {
                triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
        TriangleMesh {
            positions,
            triangles,
            ..Default::default()
        }
    }

    /// A staircase of the grid's horizontal and vertical edges from the upper left
    /// corner to the lower right one (right, down, right, down, ...: across the
    /// diagonals, so no face has two of its edges, as after the segmentation's own
    /// straightening), its ends on the grid's boundary.
    fn staircase(n: u32) -> Vec<[u32; 2]> {
        let at = |i: u32, j: u32| j * (n + 1) + i;
        (0..n)
            .flat_map(|i| {
                [
                    [at(i, n - i), at(i + 1, n - i)],
                    [at(i + 1, n - i), at(i + 1, n - i - 1)],
                ]
            })
            .collect()
    }

    /// Distance of a point from the staircase's centre line `x + y = n + ½`.
    fn off_centre(p: &Vec3, n: u32) -> f64 {
        (p.x + p.y - n as f64 - 0.5).abs() / 2f64.sqrt()
    }

    #[test]
    fn a_staircase_across_a_grid_becomes_nearly_straight_and_stays_on_the_sheet() {
        let n = 12;
        let mesh = grid(n);
        let table = EdgeTable::new(&mesh.triangles, mesh.positions.len());
        let seams = staircase(n);
        let wiggle = |positions: &[Vec3], inner: bool| {
            seams
                .iter()
                .flatten()
                .filter(|&&v| !inner || (2.5..9.5).contains(&mesh.positions[v as usize].x))
                .map(|&v| off_centre(&positions[v as usize], n))
                .fold(0.0, f64::max)
        };
        let before = wiggle(&mesh.positions, false);
        assert!((before - 0.5 / 2f64.sqrt()).abs() < 1e-12);
        let smoothed = smooth_seams(&mesh, &table, &seams, &[], &SeamSmoothingOptions::default());
        // The ends stay on the boundary, so the first and last steps keep some wiggle;
        // inside, the staircase is flattened.
        assert!(wiggle(&smoothed.positions, false) <= before + 1e-12);
        let inner = wiggle(&smoothed.positions, true);
        assert!(inner < 0.1 * before, "inner wiggle {before} → {inner}");
        // Every vertex stays on the sheet (z = 0) and near where it was; the boundary
        // stays.
        for (p, q) in smoothed.positions.iter().zip(&mesh.positions) {
            assert_eq!(p.z, 0.0);
            if [q.x, q.y].iter().any(|&c| c == 0.0 || c == n as f64) {
                assert_eq!(p, q);
            }
            assert!((p - q).norm() < 1.0, "a vertex left its star: {q} → {p}");
        }
        // No face turned over or became a sliver.
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|v| smoothed.positions[v as usize]);
            let area = 0.5 * (b - a).cross(&(c - a)).z;
            assert!(area >= 0.25 * 0.5 - 1e-12, "face area {area}");
        }
        assert!(smoothed.moved_count > 0 && smoothed.moved_count < 2 * n as usize);
    }

    #[test]
    fn a_face_between_two_seam_edges_is_not_flattened() {
        // A staircase along the diagonals (right, up, ...): each corner's face has two seam
        // edges, which a straight seam would flatten; they keep a quarter of their area.
        let mesh = grid(6);
        let table = EdgeTable::new(&mesh.triangles, mesh.positions.len());
        let at = |i: u32, j: u32| j * 7 + i;
        let seams: Vec<[u32; 2]> = (0..6)
            .flat_map(|i| [[at(i, i), at(i + 1, i)], [at(i + 1, i), at(i + 1, i + 1)]])
            .collect();
        let smoothed = smooth_seams(&mesh, &table, &seams, &[], &SeamSmoothingOptions::default());
        assert!(smoothed.moved_count > 0);
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|v| smoothed.positions[v as usize]);
            assert!(0.5 * (b - a).cross(&(c - a)).z >= 0.25 * 0.5 - 1e-12);
        }
    }

    #[test]
    fn locked_vertices_ends_and_straight_seams_stay() {
        let mesh = grid(8);
        let table = EdgeTable::new(&mesh.triangles, mesh.positions.len());
        let at = |i: u32, j: u32| j * 9 + i;
        // A straight seam along a grid line: nothing to smooth.
        let straight: Vec<[u32; 2]> = (0..8).map(|i| [at(i, 4), at(i + 1, 4)]).collect();
        let smoothed = smooth_seams(&mesh, &table, &straight, &[], &SeamSmoothingOptions::default());
        assert_eq!(smoothed.moved_count, 0);
        assert_eq!(smoothed.positions, mesh.positions);
        // A staircase whose every vertex is locked stays; a slit's end (one seam edge)
        // stays.
        let seams = staircase(8);
        let locked = vec![true; mesh.positions.len()];
        let smoothed = smooth_seams(&mesh, &table, &seams, &locked, &SeamSmoothingOptions::default());
        assert_eq!(smoothed.moved_count, 0);
        let slit = [[at(2, 2), at(3, 2)], [at(3, 2), at(3, 3)], [at(3, 3), at(4, 3)]];
        let smoothed = smooth_seams(&mesh, &table, &slit, &[], &SeamSmoothingOptions::default());
        assert_eq!(smoothed.positions[at(2, 2) as usize], mesh.positions[at(2, 2) as usize]);
        assert_eq!(smoothed.positions[at(4, 3) as usize], mesh.positions[at(4, 3) as usize]);
        assert!(smoothed.moved_count == 2);
        // No iterations: nothing moves.
        let none = SeamSmoothingOptions {
            iterations: 0,
            ..Default::default()
        };
        assert_eq!(smooth_seams(&mesh, &table, &seams, &[], &none).moved_count, 0);
    }

    #[test]
    fn on_a_curved_surface_the_seam_stays_on_the_target() {
        // A cylinder of radius 10 (48 sections, 12 rings of height 1) and a staircase
        // down it from section 0 at height 10 to section 10 at the bottom (a slit's end
        // inside, the other on the boundary): unrolled, the staircase of the grid above.
        let (sections, rings) = (48u32, 12u32);
        let mut positions = Vec::new();
        for j in 0..=rings {
            for i in 0..sections {
                let t = std::f64::consts::TAU * i as f64 / sections as f64;
                positions.push(Vec3::new(10.0 * t.cos(), 10.0 * t.sin(), j as f64));
            }
        }
        let at = |i: u32, j: u32| j * sections + (i % sections);
        let mut triangles = Vec::new();
        for j in 0..rings {
            for i in 0..sections {
                triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
        let mesh = TriangleMesh {
            positions,
            triangles,
            ..Default::default()
        };
        let table = EdgeTable::new(&mesh.triangles, mesh.positions.len());
        let seams: Vec<[u32; 2]> = (0..10)
            .flat_map(|i| {
                [
                    [at(i, 10 - i), at(i + 1, 10 - i)],
                    [at(i + 1, 10 - i), at(i + 1, 9 - i)],
                ]
            })
            .collect();
        let smoothed = smooth_seams(&mesh, &table, &seams, &[], &SeamSmoothingOptions::default());
        assert!(smoothed.moved_count > 0);
        let index = sheetform_mesh::SurfaceIndex::new(&mesh);
        for p in &smoothed.positions {
            let (_, distance, _) = index.closest_point(*p);
            assert!(distance < 1e-9, "a vertex left the target by {distance}");
        }
        // Unrolled (section number, height), the inner vertices gather on the centre
        // line `u + z = 10.5`.
        let off = |p: &Vec3| {
            let u = p.y.atan2(p.x).rem_euclid(std::f64::consts::TAU) * sections as f64 / std::f64::consts::TAU;
            (u + p.z - 10.5).abs()
        };
        let inner = |positions: &[Vec3]| {
            seams
                .iter()
                .flatten()
                .filter(|&&v| (2.5..7.5).contains(&mesh.positions[v as usize].z))
                .map(|&v| off(&positions[v as usize]))
                .fold(0.0, f64::max)
        };
        let (before, after) = (inner(&mesh.positions), inner(&smoothed.positions));
        assert!((before - 0.5).abs() < 1e-9);
        assert!(after < 0.2 * before, "wiggle {before} → {after}");
    }
}

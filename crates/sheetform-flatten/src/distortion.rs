use crate::Vec2;
use sheetform_geometry::cross2;
use sheetform_mesh::TriangleMesh;

/// How far a flattening is from an isometry, and whether it overlaps itself.
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize)]
pub struct Distortion {
    /// `max | |e_flat| − |e_3D| | / |e_3D|` over edges.
    pub edge_length_max_relative: f64,
    /// Mean of the same.
    pub edge_length_mean_relative: f64,
    /// `max | A_flat − A_3D | / A_3D` over faces.
    pub area_max_relative: f64,
    /// Mean of the same.
    pub area_mean_relative: f64,
    /// Faces whose flat image is clockwise (flipped) or degenerate.
    pub flipped_faces: Vec<u32>,
    /// Pairs of boundary edges that cross on the pattern (the pattern overlaps itself).
    pub boundary_crossings: usize,
    /// The first such pair, as vertex pairs (where a chart that overlaps is split).
    #[serde(skip)]
    pub first_crossing: Option<[[u32; 2]; 2]>,
}

impl Distortion {
    /// No flipped faces and no boundary crossings.
    pub fn is_overlap_free(&self) -> bool {
        self.flipped_faces.is_empty() && self.boundary_crossings == 0
    }
}

/// Distortion of the flattening `flat` (one point per vertex) of `mesh`.
pub fn distortion(mesh: &TriangleMesh, flat: &[Vec2]) -> Distortion {
    let mut d = Distortion::default();
    let (mut sum, mut n, mut area_sum) = (0.0, 0usize, 0.0);
    for (f, t) in mesh.triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k] as usize, t[(k + 1) % 3] as usize);
            // Each interior edge is seen twice; counting both is harmless for max/mean.
            let l3 = (mesh.positions[a] - mesh.positions[b]).norm();
            if l3 > 0.0 {
                let rel = ((flat[a] - flat[b]).norm() - l3).abs() / l3;
                d.edge_length_max_relative = d.edge_length_max_relative.max(rel);
                sum += rel;
                n += 1;
            }
        }
        let [p, q, r] = t.map(|i| flat[i as usize]);
        let a2 = 0.5 * cross2(q - p, r - p);
        let a3 = mesh.face_area(f);
        if a2 <= 0.0 {
            d.flipped_faces.push(f as u32);
        }
        if a3 > 0.0 {
            let rel = (a2.abs() - a3).abs() / a3;
            d.area_max_relative = d.area_max_relative.max(rel);
            area_sum += rel;
        }
    }
    if n > 0 {
        d.edge_length_mean_relative = sum / n as f64;
    }
    if !mesh.triangles.is_empty() {
        d.area_mean_relative = area_sum / mesh.triangles.len() as f64;
    }
    // Boundary edges crossing each other (sort by x to skip far pairs).
    let mut edges: Vec<([Vec2; 2], [u32; 2])> = sheetform_mesh::EdgeTable::new(&mesh.triangles, mesh.positions.len())
        .boundary_edges()
        .map(|[a, b]| ([flat[a as usize], flat[b as usize]], [a, b]))
        .collect();
    edges.sort_by(|(a, _), (b, _)| a[0].x.min(a[1].x).total_cmp(&b[0].x.min(b[1].x)));
    for i in 0..edges.len() {
        let ([a, b], first) = edges[i];
        let max_x = a.x.max(b.x);
        for &([c, dd], second) in &edges[i + 1..] {
            if c.x.min(dd.x) > max_x {
                break;
            }
            // Edges meeting at a vertex, or at two copies of a vertex that lie on the same
            // point up to rounding (where the pieces of a net touch), only touch.
            let near = 1e-9 * (b - a).norm().max((dd - c).norm());
            let shares = [a, b].iter().any(|p| [c, dd].iter().any(|q| (p - q).norm() <= near));
            if shares {
                continue;
            }
            if crosses_beyond_rounding(a, b, c, dd) {
                d.boundary_crossings += 1;
                d.first_crossing.get_or_insert([first, second]);
            }
        }
    }
    d
}

/// Whether segments `ab` and `cd` cross properly with every end more than `1e-9` of the
/// longer segment's length from the other segment's line: a vertex of a net lying on
/// another piece's edge up to rounding touches, it does not cross.
fn crosses_beyond_rounding(a: Vec2, b: Vec2, c: Vec2, d: Vec2) -> bool {
    let (r, s) = (b - a, d - c);
    let (lr, ls) = (r.norm(), s.norm());
    if lr == 0.0 || ls == 0.0 {
        return false;
    }
    let tolerance = 1e-9 * lr.max(ls);
    let (d1, d2) = (cross2(r, c - a) / lr, cross2(r, d - a) / lr);
    let (d3, d4) = (cross2(s, a - c) / ls, cross2(s, b - c) / ls);
    d1 * d2 < 0.0 && d3 * d4 < 0.0 && d1.abs().min(d2.abs()) > tolerance && d3.abs().min(d4.abs()) > tolerance
}

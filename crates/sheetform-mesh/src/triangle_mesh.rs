use nalgebra::{Vector2, Vector3};

type Vec2 = Vector2<f64>;
type Vec3 = Vector3<f64>;

/// A triangle mesh as read from a file: positions, triangles, a group per face and,
/// optionally, a texture coordinate per face corner (OBJ `vt`; a vertex on a seam has
/// different coordinates in the faces on either side).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TriangleMesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Triangles (vertex indices).
    pub triangles: Vec<[u32; 3]>,
    /// Group (index into `groups`) of each triangle.
    pub face_groups: Vec<u32>,
    /// Group names (OBJ `g`/`o`; one unnamed group if the file has none).
    pub groups: Vec<String>,
    /// Texture coordinates per face corner, if the file has them for every face.
    pub corner_uvs: Option<Vec<[Vec2; 3]>>,
    /// Edges the user marked as seams (OBJ `l` polylines): chart boundaries when the mesh
    /// is cut for flattening.
    pub seam_edges: Vec<[u32; 2]>,
}

impl TriangleMesh {
    /// A parametric grid: `(nu + 1) × (nv + 1)` vertices at `surface(i / nu, j / nv)`, two
    /// triangles per cell, one group. When the grid lines of constant `u` are rulings of a
    /// developable surface every cell is planar and the mesh is exactly developable (the
    /// test and benchmark meshes of cylinders and cones).
    pub fn grid(nu: usize, nv: usize, surface: impl Fn(f64, f64) -> [f64; 3]) -> Self {
        let mut positions = Vec::with_capacity((nu + 1) * (nv + 1));
        for i in 0..=nu {
            for j in 0..=nv {
                positions.push(Vec3::from(surface(i as f64 / nu as f64, j as f64 / nv as f64)));
            }
        }
        let id = |i: usize, j: usize| (i * (nv + 1) + j) as u32;
        let mut triangles = Vec::with_capacity(2 * nu * nv);
        for i in 0..nu {
            for j in 0..nv {
                triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        let faces = triangles.len();
        Self {
            positions,
            triangles,
            face_groups: vec![0; faces],
            groups: vec!["grid".into()],
            corner_uvs: None,
            seam_edges: Vec::new(),
        }
    }

    /// Unit normal of face `f` (zero for a degenerate face).
    pub fn face_normal(&self, f: usize) -> Vec3 {
        let [a, b, c] = self.triangles[f].map(|i| self.positions[i as usize]);
        let n = (b - a).cross(&(c - a));
        let l = n.norm();
        if l > 0.0 {
            n / l
        } else {
            Vec3::zeros()
        }
    }

    /// The unsigned angle (radians) between the normals of the two faces on each edge of
    /// `table` (this mesh's edge table): 0 where the faces are coplanar, and on boundary
    /// or non-manifold edges.
    pub fn dihedral_angles(&self, table: &crate::EdgeTable) -> Vec<f64> {
        let normals: Vec<Vec3> = (0..self.triangles.len()).map(|f| self.face_normal(f)).collect();
        (0..table.len())
            .map(|e| match table.sides(e) {
                [f, g] => {
                    let (n, m) = (normals[f.face as usize], normals[g.face as usize]);
                    n.cross(&m).norm().atan2(n.dot(&m))
                }
                _ => 0.0,
            })
            .collect()
    }

    /// Area of face `f`.
    pub fn face_area(&self, f: usize) -> f64 {
        let [a, b, c] = self.triangles[f].map(|i| self.positions[i as usize]);
        0.5 * (b - a).cross(&(c - a)).norm()
    }

    /// Length of the bounding-box diagonal (the length scale for tolerances).
    pub fn scale(&self) -> f64 {
        let mut lo = Vec3::repeat(f64::INFINITY);
        let mut hi = Vec3::repeat(f64::NEG_INFINITY);
        for p in &self.positions {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        if self.positions.is_empty() {
            0.0
        } else {
            (hi - lo).norm()
        }
    }

    /// Merges vertices closer than `tolerance` (absolute, model units) into one, keeping
    /// the first; drops faces that become degenerate. Returns the number of vertices
    /// merged away. Grid hashing: expected linear time.
    pub fn weld(&mut self, tolerance: f64) -> usize {
        let before = self.positions.len();
        self.weld_keeping_origins(tolerance);
        before - self.positions.len()
    }

    /// [`Self::weld`], returning for each vertex kept the input vertex it is (the first of
    /// those merged into it).
    pub fn weld_keeping_origins(&mut self, tolerance: f64) -> Vec<u32> {
        let remap = coincident_vertices(&self.positions, tolerance);
        let kept_count = remap.iter().map(|&i| i as usize + 1).max().unwrap_or(0);
        let mut kept = vec![Vec3::zeros(); kept_count];
        for (p, &i) in self.positions.iter().zip(&remap).rev() {
            kept[i as usize] = *p;
        }
        let mut origins = vec![u32::MAX; kept.len()];
        for (input, &i) in remap.iter().enumerate().rev() {
            origins[i as usize] = input as u32;
        }
        self.positions = kept;
        for e in &mut self.seam_edges {
            *e = e.map(|i| remap[i as usize]);
        }
        self.seam_edges.retain(|e| e[0] != e[1]);
        let mut keep = Vec::with_capacity(self.triangles.len());
        for t in &mut self.triangles {
            *t = t.map(|i| remap[i as usize]);
            keep.push(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]);
        }
        let mut i = 0;
        self.triangles.retain(|_| {
            i += 1;
            keep[i - 1]
        });
        let mut i = 0;
        self.face_groups.retain(|_| {
            i += 1;
            keep[i - 1]
        });
        if let Some(uv) = &mut self.corner_uvs {
            let mut i = 0;
            uv.retain(|_| {
                i += 1;
                keep[i - 1]
            });
        }
        origins
    }
}

/// Classes of coincident points: `class[i]` is the index (in order of first appearance)
/// of the first earlier point within `tolerance` (absolute, model units) of point `i`,
/// or a new class. Grid hashing (cells of `2 × tolerance`, the 27 neighbouring cells
/// searched): expected linear time. Used to weld meshes and to find the linked vertices
/// of assembled panels.
///
/// The cells are at least `1e-12 ×` the largest coordinate magnitude: with a tolerance
/// of 0 (exact coincidence) or far below the coordinates' precision, cells of
/// `2 × tolerance` made every key saturate to the same `i64` extreme and the search
/// quadratic (90k vertices at `--weld 0`: 6.5 s instead of 0.3 s).
pub fn coincident_vertices(positions: &[Vec3], tolerance: f64) -> Vec<u32> {
    let largest = positions
        .iter()
        .map(|p| p.amax())
        .filter(|m| m.is_finite())
        .fold(0.0f64, f64::max);
    let cell = (tolerance * 2.0).max(largest * 1e-12).max(f64::MIN_POSITIVE);
    let key = |p: &Vec3| {
        [
            (p.x / cell).floor() as i64,
            (p.y / cell).floor() as i64,
            (p.z / cell).floor() as i64,
        ]
    };
    let mut grid: rustc_hash::FxHashMap<[i64; 3], Vec<u32>> = rustc_hash::FxHashMap::default();
    let mut remap: Vec<u32> = Vec::with_capacity(positions.len());
    let mut kept: Vec<Vec3> = Vec::new();
    for p in positions {
        let k = key(p);
        let mut found = None;
        'search: for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    if let Some(list) = grid.get(&[
                        k[0].saturating_add(dx),
                        k[1].saturating_add(dy),
                        k[2].saturating_add(dz),
                    ]) {
                        for &i in list {
                            if (kept[i as usize] - p).norm() <= tolerance {
                                found = Some(i);
                                break 'search;
                            }
                        }
                    }
                }
            }
        }
        let index = found.unwrap_or_else(|| {
            kept.push(*p);
            let i = (kept.len() - 1) as u32;
            grid.entry(k).or_default().push(i);
            i
        });
        remap.push(index);
    }
    remap
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 19: a weld tolerance of 0 welds exactly coincident points only, in expected
    /// linear time (the cells no longer shrink to nothing: all 80 000 points used to
    /// share one saturated key and be compared with each other).
    #[test]
    fn a_zero_tolerance_welds_exact_duplicates_only() {
        let grid: Vec<Vec3> = (0..40_000)
            .map(|i| Vec3::new(f64::from(i % 200) * 0.37, f64::from(i / 200) * 0.37, 1e3))
            .collect();
        let mut positions = grid.clone();
        positions.extend(grid.iter().map(|p| p + Vec3::new(0.0, 0.0, 0.0)));
        positions.push(grid[5] + Vec3::new(1e-9, 0.0, 0.0));
        let classes = coincident_vertices(&positions, 0.0);
        assert_eq!(classes[..40_000], (0..40_000).collect::<Vec<u32>>()[..]);
        assert_eq!(classes[40_000..80_000], classes[..40_000]);
        assert_eq!(
            classes[80_000], 40_000,
            "a point 1e-9 away is not the same at tolerance 0"
        );
    }
}

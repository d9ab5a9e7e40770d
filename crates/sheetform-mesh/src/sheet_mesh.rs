use crate::EdgeTable;
use crate::{LengthUnit, MeshError};
use nalgebra::{Vector2, Vector3};
use std::collections::HashMap;

type Vec2 = Vector2<f64>;
type Vec3 = Vector3<f64>;

/// Whether a piece of the sheet is bent or stays flat.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PieceKind {
    /// Part of a curved developable (swept by rulings of one control curve).
    Curved,
    /// A planar piece moved rigidly with the curved piece it is attached to.
    Planar,
    /// A chart of a flattened mesh (a piece of the pattern cut from any surface).
    Chart,
}

/// A named piece of the sheet: a label for a set of faces.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Piece {
    /// Human-readable name (from the scene, or generated).
    pub name: String,
    /// Curved or planar.
    pub kind: PieceKind,
}

/// A ruling of the bent sheet: a straight segment on the surface along which the surface
/// normal is constant, stored as the chain of mesh vertices it runs through.
#[derive(Debug, Clone, PartialEq)]
pub struct Ruling {
    /// Mesh vertices along the ruling, from one end to the other (at least two).
    pub vertices: Vec<u32>,
    /// Piece (index into [`SheetMesh::pieces`]) whose control curve produced the ruling.
    pub piece: u32,
    /// Arc length along that piece's control curve where the ruling starts.
    pub arc_length: f64,
}

/// A triangle mesh of a bent sheet that carries its own exact flat pattern.
///
/// Vertex `i` sits at `positions[i]` in 3D and at `flat[i]` on the flat sheet; both are in
/// [`SheetMesh::unit`]. Triangles are counter-clockwise seen from the sheet's top side in
/// the flat pattern (positive flat area). `face_pieces[f]` labels face `f` with a piece.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SheetMesh {
    /// 3D positions of the bent sheet.
    pub positions: Vec<Vec3>,
    /// Positions on the flat sheet (same unit, 1:1).
    pub flat: Vec<Vec2>,
    /// Triangles as vertex indices.
    pub triangles: Vec<[u32; 3]>,
    /// Piece label of each triangle.
    pub face_pieces: Vec<u32>,
    /// The pieces (curved developables and planar regions).
    pub pieces: Vec<Piece>,
    /// Rulings, as vertex chains.
    pub rulings: Vec<Ruling>,
    /// Interior edges the sheet bends along smoothly that are not rulings to draw (the
    /// triangulation between the rulings of a ruled strip): the pattern draws them
    /// neither as folds nor as guides.
    pub smooth_edges: Vec<[u32; 2]>,
    /// Length unit of both coordinate sets.
    pub unit: LengthUnit,
}

impl SheetMesh {
    /// Checks array lengths, indices, finiteness and labels.
    ///
    /// # Errors
    /// The first inconsistency found.
    pub fn validate(&self) -> Result<(), MeshError> {
        let n = self.positions.len();
        if self.flat.len() != n {
            return Err(MeshError::LengthMismatch {
                what: "flat positions",
                expected: n,
                found: self.flat.len(),
            });
        }
        if self.face_pieces.len() != self.triangles.len() {
            return Err(MeshError::LengthMismatch {
                what: "face piece labels",
                expected: self.triangles.len(),
                found: self.face_pieces.len(),
            });
        }
        for (i, (p, q)) in self.positions.iter().zip(&self.flat).enumerate() {
            if p.iter().any(|c| !c.is_finite()) {
                return Err(MeshError::NonFinite { vertex: i, which: "3D" });
            }
            if q.iter().any(|c| !c.is_finite()) {
                return Err(MeshError::NonFinite {
                    vertex: i,
                    which: "flat",
                });
            }
        }
        for (f, t) in self.triangles.iter().enumerate() {
            for &v in t {
                if v as usize >= n {
                    return Err(MeshError::IndexOutOfRange {
                        face: f,
                        vertex: v,
                        vertex_count: n,
                    });
                }
            }
            if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                return Err(MeshError::DegenerateFace { face: f });
            }
        }
        for (f, &p) in self.face_pieces.iter().enumerate() {
            if p as usize >= self.pieces.len() {
                return Err(MeshError::PieceOutOfRange {
                    face: f,
                    piece: p,
                    piece_count: self.pieces.len(),
                });
            }
        }
        Ok(())
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Unit normal of face `f` in 3D (zero for a degenerate face).
    pub fn face_normal(&self, f: usize) -> Vec3 {
        let [a, b, c] = self.triangles[f].map(|i| self.positions[i as usize]);
        let n = (b - a).cross(&(c - a));
        let len = n.norm();
        if len > 0.0 {
            n / len
        } else {
            Vec3::zeros()
        }
    }

    /// Area-weighted vertex normals in 3D.
    pub fn vertex_normals(&self) -> Vec<Vec3> {
        crate::area_weighted_normals(&self.positions, &self.triangles)
    }

    /// Every undirected edge once, as `[smaller, larger]` vertex index.
    pub fn edges(&self) -> Vec<[u32; 2]> {
        let mut edges: Vec<[u32; 2]> = self
            .triangles
            .iter()
            .flat_map(|t| [[t[0], t[1]], [t[1], t[2]], [t[2], t[0]]])
            .map(|[a, b]| if a < b { [a, b] } else { [b, a] })
            .collect();
        edges.sort_unstable();
        edges.dedup();
        edges
    }

    /// The undirected edges and the faces on each ([`EdgeTable`]).
    pub fn edge_table(&self) -> EdgeTable {
        EdgeTable::new(&self.triangles, self.positions.len())
    }

    /// Boundary loops of the mesh as directed vertex cycles (edges used by one face,
    /// oriented as in that face, so the outline runs counter-clockwise in the flat
    /// pattern and holes clockwise).
    pub fn boundary_loops(&self) -> Vec<Vec<u32>> {
        let table = self.edge_table();
        let mut next: HashMap<u32, u32> = HashMap::new();
        for [from, to] in table.boundary_edges() {
            next.insert(from, to);
        }
        let mut starts: Vec<u32> = next.keys().copied().collect();
        starts.sort_unstable();
        let mut loops = Vec::new();
        let mut seen = std::collections::HashSet::new();
        for s in starts {
            if seen.contains(&s) {
                continue;
            }
            let mut cycle = vec![s];
            seen.insert(s);
            let mut v = s;
            while let Some(&w) = next.get(&v) {
                if w == s || !seen.insert(w) {
                    break;
                }
                cycle.push(w);
                v = w;
            }
            loops.push(cycle);
        }
        loops
    }

    /// Axis-aligned bounds `(min, max)` of the flat pattern.
    pub fn flat_bounds(&self) -> (Vec2, Vec2) {
        let mut lo = Vec2::repeat(f64::INFINITY);
        let mut hi = Vec2::repeat(f64::NEG_INFINITY);
        for p in &self.flat {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        (lo, hi)
    }

    /// Axis-aligned bounds `(min, max)` of the 3D model.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let mut lo = Vec3::repeat(f64::INFINITY);
        let mut hi = Vec3::repeat(f64::NEG_INFINITY);
        for p in &self.positions {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        (lo, hi)
    }

    /// Total area of the flat pattern.
    pub fn flat_area(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.flat[i as usize]);
                0.5 * ((b - a).x * (c - a).y - (b - a).y * (c - a).x)
            })
            .sum()
    }

    /// The 3D mesh as a plain [`crate::TriangleMesh`] (one group per piece), for the
    /// measures that work on any mesh.
    pub fn to_triangle_mesh(&self) -> crate::TriangleMesh {
        crate::TriangleMesh {
            positions: self.positions.clone(),
            triangles: self.triangles.clone(),
            face_groups: self.face_pieces.clone(),
            groups: self.pieces.iter().map(|p| p.name.clone()).collect(),
            corner_uvs: Some(
                self.triangles
                    .iter()
                    .map(|t| t.map(|i| self.flat[i as usize]))
                    .collect(),
            ),
            seam_edges: Vec::new(),
        }
    }

    /// Total area of the 3D surface.
    pub fn area(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.positions[i as usize]);
                0.5 * (b - a).cross(&(c - a)).norm()
            })
            .sum()
    }
}

//! Cutting a mesh open along a set of its edges.

use crate::{EdgeTable, TriangleMesh, UnionFind};

/// A mesh cut open along some of its edges, and where each new vertex came from.
#[derive(Debug, Clone, PartialEq)]
pub struct CutMesh {
    /// The cut mesh: same faces in the same order, vertices split along the cut.
    pub mesh: TriangleMesh,
    /// Vertex of the input mesh that each vertex of the cut mesh is a copy of.
    pub origin: Vec<u32>,
}

/// Cuts `mesh` open along the edges `cut` (vertex pairs; pairs that are not mesh edges
/// are ignored): the faces on either side of a cut edge no longer share its vertices.
///
/// Every face corner starts as its own vertex; corners are merged across each uncut
/// edge with two faces (union–find). A vertex then splits into one copy per fan of faces
/// between the cut (or boundary) edges around it, which is what opening the cut means.
/// Seam edges of the input that lie on the cut are dropped, the others kept. Linear in
/// the size of the mesh.
pub fn cut_along_edges(mesh: &TriangleMesh, cut: &[[u32; 2]]) -> CutMesh {
    let table = EdgeTable::new(&mesh.triangles, mesh.positions.len());
    let mut is_cut = vec![false; table.len()];
    for &[a, b] in cut {
        if let Some(e) = table.find(a, b) {
            is_cut[e] = true;
        }
    }
    let nf = mesh.triangles.len();
    let mut corners = UnionFind::new(3 * nf);
    let corner_of = |f: u32, v: u32| -> Option<u32> {
        let k = mesh.triangles[f as usize].iter().position(|&w| w == v)?;
        Some(3 * f + k as u32)
    };
    for (e, &[a, b]) in table.edges.iter().enumerate() {
        if is_cut[e] {
            continue;
        }
        if let [f, g] = table.sides(e) {
            for v in [a, b] {
                if let (Some(x), Some(y)) = (corner_of(f.face, v), corner_of(g.face, v)) {
                    corners.union(x, y);
                }
            }
        }
    }
    let mut new_index = vec![u32::MAX; 3 * nf];
    let mut origin = Vec::new();
    let mut triangles = Vec::with_capacity(nf);
    for (f, t) in mesh.triangles.iter().enumerate() {
        let mut out = [0u32; 3];
        for k in 0..3 {
            let root = corners.find((3 * f + k) as u32) as usize;
            if new_index[root] == u32::MAX {
                new_index[root] = origin.len() as u32;
                origin.push(t[k]);
            }
            out[k] = new_index[root];
        }
        triangles.push(out);
    }
    let seam_edges = mesh
        .seam_edges
        .iter()
        .filter(|&&[a, b]| table.find(a, b).is_none_or(|e| !is_cut[e]))
        .filter_map(|&[a, b]| {
            // The copies of a and b that share a face (the seam as it runs in the cut mesh).
            let f = table.faces_of(a, b).next()?;
            let t = triangles[f as usize];
            let ka = mesh.triangles[f as usize].iter().position(|&w| w == a)?;
            let kb = mesh.triangles[f as usize].iter().position(|&w| w == b)?;
            Some([t[ka], t[kb]])
        })
        .collect();
    CutMesh {
        mesh: TriangleMesh {
            positions: origin.iter().map(|&v| mesh.positions[v as usize]).collect(),
            triangles,
            face_groups: mesh.face_groups.clone(),
            groups: mesh.groups.clone(),
            corner_uvs: mesh.corner_uvs.clone(),
            seam_edges,
        },
        origin,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{mesh_topology, primitives};

    #[test]
    fn a_tube_cut_along_one_ruling_becomes_a_disk() {
        let tube = primitives::cylinder(1.0, 2.0, 12, false);
        // Vertex 0 (bottom) and 12 (top) are joined by a vertical edge.
        let cut = cut_along_edges(&tube, &[[0, 12]]);
        let t = mesh_topology(&cut.mesh);
        assert_eq!((t.euler_characteristic, t.boundary_loop_count), (1, 1));
        assert_eq!(cut.mesh.positions.len(), tube.positions.len() + 2);
        for (v, &o) in cut.origin.iter().enumerate() {
            assert_eq!(cut.mesh.positions[v], tube.positions[o as usize]);
        }
    }

    #[test]
    fn cutting_nothing_or_non_edges_keeps_the_mesh() {
        let ball = primitives::icosphere(1.0, 1);
        let cut = cut_along_edges(&ball, &[[0, 3]]);
        assert_eq!(cut.mesh.positions.len(), ball.positions.len());
        assert_eq!(mesh_topology(&cut.mesh).euler_characteristic, 2);
    }

    #[test]
    fn a_closed_loop_of_cut_edges_splits_the_surface() {
        // Cutting the four edges around the top side lets it come off as its own piece.
        let cube = primitives::cuboid([1.0, 1.0, 1.0]);
        let cut = cut_along_edges(&cube, &[[4, 5], [5, 7], [7, 6], [6, 4]]);
        let t = mesh_topology(&cut.mesh);
        assert_eq!(t.component_count, 2);
        assert_eq!(t.boundary_loop_count, 2);
    }
}

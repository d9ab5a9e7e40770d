//! The pieces a target is cut into along its seams, and the vertices whose angle sum must
//! be 2π for every piece to be developable.

use crate::DevelopError;
use sheetform_mesh::{EdgeTable, TriangleMesh, UnionFind};

/// A mesh cut into pieces along seam edges.
#[derive(Debug, Clone, PartialEq)]
pub struct SeamPieces {
    /// The piece of each face: faces connected across edges that are not seams.
    pub face_piece: Vec<u32>,
    /// Number of pieces.
    pub piece_count: usize,
    /// Whether each vertex lies inside one piece (on no seam and not on the mesh's
    /// boundary): its angle sum must be 2π (zero angle defect) for its piece to unfold
    /// without stretching. Seam and boundary vertices are free: a piece's boundary may
    /// bend any way.
    pub interior: Vec<bool>,
    /// The edge-table index of every seam edge.
    pub seam_edges: Vec<usize>,
}

/// Cuts `mesh` into pieces along `seams` (vertex pairs, 0-based; each must be an edge of
/// the mesh).
///
/// # Errors
/// [`DevelopError::SeamOffMesh`] naming the first seam segment that is not a mesh edge.
pub fn seam_pieces(mesh: &TriangleMesh, table: &EdgeTable, seams: &[[u32; 2]]) -> Result<SeamPieces, DevelopError> {
    let nv = mesh.positions.len();
    let nf = mesh.triangles.len();
    let mut is_seam = vec![false; table.len()];
    let mut seam_edges = Vec::with_capacity(seams.len());
    for (i, &[a, b]) in seams.iter().enumerate() {
        let e = table.find(a, b).ok_or(DevelopError::SeamOffMesh {
            index: i + 1,
            a: a + 1,
            b: b + 1,
        })?;
        if !is_seam[e] {
            is_seam[e] = true;
            seam_edges.push(e);
        }
    }
    let mut faces = UnionFind::new(nf);
    let mut interior = vec![true; nv];
    for (e, &seam) in is_seam.iter().enumerate() {
        let [a, b] = table.edges[e];
        match table.sides(e) {
            [f, g] if !seam => {
                faces.union(f.face, g.face);
            }
            _ => {
                interior[a as usize] = false;
                interior[b as usize] = false;
            }
        }
    }
    // Vertices no face uses are not constrained either.
    let mut used = vec![false; nv];
    for t in &mesh.triangles {
        for &v in t {
            used[v as usize] = true;
        }
    }
    for (flag, used) in interior.iter_mut().zip(&used) {
        *flag &= *used;
    }
    let mut label = vec![u32::MAX; nf];
    let mut face_piece = vec![0u32; nf];
    let mut piece_count = 0usize;
    for (f, piece) in face_piece.iter_mut().enumerate() {
        let root = faces.find(f as u32) as usize;
        if label[root] == u32::MAX {
            label[root] = piece_count as u32;
            piece_count += 1;
        }
        *piece = label[root];
    }
    Ok(SeamPieces {
        face_piece,
        piece_count,
        interior,
        seam_edges,
    })
}

/// The vertices of a half target on its mirror plane (`on_plane`) that lie inside a
/// piece of the whole (the half joined with its mirror image): every boundary edge of the
/// half at them runs along the plane (they are not on the target's own boundary), and
/// no seam reaches them. Their angle sum in the half must be π (2π in the whole).
pub fn mirror_interior(table: &EdgeTable, pieces: &SeamPieces, on_plane: &[bool]) -> Vec<bool> {
    let nv = pieces.interior.len();
    let mut inside = on_plane.to_vec();
    inside.resize(nv, false);
    let mut touched = vec![false; nv];
    let mut seam = vec![false; table.len()];
    for &e in &pieces.seam_edges {
        seam[e] = true;
    }
    for (e, &[a, b]) in table.edges.iter().enumerate() {
        let along_plane = on_plane[a as usize] && on_plane[b as usize];
        let open = table.sides(e).len() != 2;
        if seam[e] || (open && !along_plane) {
            inside[a as usize] = false;
            inside[b as usize] = false;
        }
        touched[a as usize] = true;
        touched[b as usize] = true;
    }
    for (flag, touched) in inside.iter_mut().zip(&touched) {
        *flag &= *touched;
    }
    inside
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closed cylinder side cut along one ruling and around its middle: two pieces;
    /// the vertices on the cuts and the rims are free, the others constrained.
    #[test]
    fn seams_cut_a_tube_into_pieces_and_free_their_vertices() {
        let (sections, rings) = (12usize, 4usize);
        let mut mesh = TriangleMesh::default();
        for r in 0..=rings {
            for s in 0..sections {
                let t = std::f64::consts::TAU * s as f64 / sections as f64;
                mesh.positions.push(nalgebra::Vector3::new(t.cos(), t.sin(), r as f64));
            }
        }
        let at = |r: usize, s: usize| (r * sections + s % sections) as u32;
        for r in 0..rings {
            for s in 0..sections {
                mesh.triangles.push([at(r, s), at(r, s + 1), at(r + 1, s + 1)]);
                mesh.triangles.push([at(r, s), at(r + 1, s + 1), at(r + 1, s)]);
            }
        }
        let mut seams: Vec<[u32; 2]> = (0..rings).map(|r| [at(r, 0), at(r + 1, 0)]).collect();
        seams.extend((0..sections).map(|s| [at(2, s), at(2, s + 1)]));
        let table = EdgeTable::new(&mesh.triangles, mesh.positions.len());
        let pieces = seam_pieces(&mesh, &table, &seams).unwrap();
        assert_eq!(pieces.piece_count, 2);
        for r in 0..=rings {
            for s in 0..sections {
                let free = r == 0 || r == rings || r == 2 || s == 0;
                assert_eq!(pieces.interior[at(r, s) as usize], !free, "ring {r} section {s}");
            }
        }
        let off = seam_pieces(&mesh, &table, &[[at(0, 0), at(2, 3)]]).unwrap_err();
        assert!(off.to_string().contains("seam segment 1"), "{off}");
    }
}

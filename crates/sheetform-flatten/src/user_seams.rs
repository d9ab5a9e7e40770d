//! The user's seams (OBJ `l` polylines): checked against the mesh, and opened.

use crate::FlattenError;
use sheetform_mesh::{cut_along_edges, CutMesh, EdgeTable, TriangleMesh};

/// The edge-table index of every user seam edge (`mesh.seam_edges`).
///
/// # Errors
/// A seam edge that is not an edge of the mesh, named 1-based as in the file.
pub fn user_seam_edges(mesh: &TriangleMesh, table: &EdgeTable) -> Result<Vec<usize>, FlattenError> {
    mesh.seam_edges
        .iter()
        .enumerate()
        .map(|(i, &[a, b])| {
            table.find(a, b).ok_or_else(|| FlattenError::Topology {
                problem: format!(
                    "seam edge {i} ({} – {}, 1-based as in the file) is not an edge of the mesh",
                    a + 1,
                    b + 1
                ),
            })
        })
        .collect()
}

/// `mesh` cut open along the user's seams (see [`cut_along_edges`]), with the input vertex
/// each of its vertices is a copy of; `None` when it has none.
///
/// # Errors
/// As [`user_seam_edges`].
pub fn open_user_seams(mesh: &TriangleMesh) -> Result<Option<CutMesh>, FlattenError> {
    if mesh.seam_edges.is_empty() {
        return Ok(None);
    }
    user_seam_edges(mesh, &EdgeTable::new(&mesh.triangles, mesh.positions.len()))?;
    Ok(Some(cut_along_edges(mesh, &mesh.seam_edges)))
}

//! Meshes handed over as flat arrays (a binding's numpy arrays, a mesh built in memory):
//! checked once here, with errors that name the array and the row, before any pipeline
//! step sees them.

use super::error::PipelineError;
use sheetform_geometry::{Vec2, Vec3};
use sheetform_mesh::{LengthUnit, Piece, PieceKind, SheetMesh, TriangleMesh};

/// Most vertices or faces an array mesh may have: indices are 32-bit.
pub const MAX_ARRAY_MESH_ELEMENTS: usize = u32::MAX as usize;

fn invalid(array: &'static str, message: String) -> PipelineError {
    PipelineError::InvalidArray { array, message }
}

/// `values` as rows of `N` finite numbers (row-major).
fn finite_rows<const N: usize>(array: &'static str, values: &[f64]) -> Result<Vec<[f64; N]>, PipelineError> {
    if values.len() % N != 0 {
        return Err(invalid(
            array,
            format!("{} numbers do not make rows of {N} coordinates", values.len()),
        ));
    }
    values
        .chunks_exact(N)
        .enumerate()
        .map(|(i, c)| {
            if c.iter().all(|x| x.is_finite()) {
                Ok(c.try_into().expect("a chunk of N"))
            } else {
                Err(invalid(array, format!("row {i} has a non-finite coordinate {c:?}")))
            }
        })
        .collect()
}

/// `values` as rows of `N` vertex indices (row-major), each below `vertex_count`; `rows`
/// says what a row is, for the message when the length does not divide.
fn vertex_index_rows<I: Copy + TryInto<i64> + std::fmt::Display, const N: usize>(
    array: &'static str,
    values: &[I],
    vertex_count: usize,
    rows: &str,
) -> Result<Vec<[u32; N]>, PipelineError> {
    if values.len() % N != 0 {
        return Err(invalid(
            array,
            format!("{} indices do not make rows of {N} ({rows})", values.len()),
        ));
    }
    values
        .chunks_exact(N)
        .enumerate()
        .map(|(row, c)| {
            let mut indices = [0u32; N];
            for (k, &index) in c.iter().enumerate() {
                let v: i64 = index.try_into().unwrap_or(i64::MAX);
                if v < 0 || v as u64 >= vertex_count as u64 {
                    return Err(invalid(
                        array,
                        format!(
                            "row {row} names vertex {index}, but the vertices are numbered 0 to {}",
                            vertex_count as i64 - 1
                        ),
                    ));
                }
                indices[k] = v as u32;
            }
            Ok(indices)
        })
        .collect()
}

fn positions_from(vertices: &[f64]) -> Result<Vec<Vec3>, PipelineError> {
    if vertices.len() / 3 > MAX_ARRAY_MESH_ELEMENTS {
        return Err(invalid(
            "vertices",
            format!("more than {MAX_ARRAY_MESH_ELEMENTS} vertices"),
        ));
    }
    Ok(finite_rows::<3>("vertices", vertices)?
        .into_iter()
        .map(Vec3::from)
        .collect())
}

fn triangles_from<I: Copy + TryInto<i64> + std::fmt::Display>(
    faces: &[I],
    vertex_count: usize,
) -> Result<Vec<[u32; 3]>, PipelineError> {
    if faces.len() / 3 > MAX_ARRAY_MESH_ELEMENTS {
        return Err(invalid("faces", format!("more than {MAX_ARRAY_MESH_ELEMENTS} faces")));
    }
    if faces.is_empty() {
        // (As the mesh readers say of a file without faces.)
        return Err(invalid("faces", "the mesh has no faces".into()));
    }
    vertex_index_rows("faces", faces, vertex_count, "triangles only")
}

/// A triangle mesh from `vertices` (`n × 3` coordinates, row-major) and `faces` (`m × 3`
/// vertex indices of any integer type, row-major), one group named `name`.
///
/// # Errors
/// [`PipelineError::InvalidArray`] naming `vertices` or `faces` and the row: a length
/// that is not a multiple of 3, a non-finite coordinate, an index out of range, no faces,
/// more than [`MAX_ARRAY_MESH_ELEMENTS`] rows.
pub fn mesh_from_arrays<I: Copy + TryInto<i64> + std::fmt::Display>(
    vertices: &[f64],
    faces: &[I],
    name: &str,
) -> Result<TriangleMesh, PipelineError> {
    let positions = positions_from(vertices)?;
    let triangles = triangles_from(faces, positions.len())?;
    Ok(TriangleMesh {
        face_groups: vec![0; triangles.len()],
        groups: vec![name.to_string()],
        positions,
        triangles,
        corner_uvs: None,
        seam_edges: Vec::new(),
    })
}

/// The seams a user drew on a mesh (`drawn_seams`: `k × 2` vertex indices, row-major, each
/// row an edge of `mesh`), to be cut open when it is flattened (as an OBJ's `l` lines).
///
/// # Errors
/// [`PipelineError::InvalidArray`] naming `drawn_seams` and the row: a length that is not a multiple
/// of 2, an index out of range, a pair of vertices that is not an edge of the mesh.
pub fn seam_edges_from_array<I: Copy + TryInto<i64> + std::fmt::Display>(
    mesh: &TriangleMesh,
    drawn_seams: &[I],
) -> Result<Vec<[u32; 2]>, PipelineError> {
    let table = sheetform_mesh::EdgeTable::new(&mesh.triangles, mesh.positions.len());
    vertex_index_rows::<I, 2>("drawn_seams", drawn_seams, mesh.positions.len(), "one edge per row")?
        .into_iter()
        .enumerate()
        .map(|(row, edge)| match table.find(edge[0], edge[1]) {
            Some(_) => Ok(edge),
            None => Err(invalid(
                "drawn_seams",
                format!("row {row} ({}, {}) is not an edge of the mesh", edge[0], edge[1]),
            )),
        })
        .collect()
}

/// A mesh with its flat pattern from arrays: `vertices` (`n × 3`), `faces` (`m × 3`),
/// `uv` (`n × 2`, the flat position of each vertex at 1:1 in `unit`), and optionally the
/// piece of each face (`face_pieces`, `m` labels from 0) with the pieces' names (by
/// default `name-1`, `name-2`, …).
///
/// # Errors
/// [`PipelineError::InvalidArray`] naming the array and the row, as [`mesh_from_arrays`], and
/// for `uv` rows that do not match the vertices, piece labels that do not match the faces
/// or name no piece.
pub fn sheet_mesh_from_arrays<I: Copy + TryInto<i64> + std::fmt::Display>(
    vertices: &[f64],
    faces: &[I],
    uv: &[f64],
    face_pieces: Option<&[i64]>,
    piece_names: Option<&[String]>,
    name: &str,
    unit: LengthUnit,
) -> Result<SheetMesh, PipelineError> {
    let positions = positions_from(vertices)?;
    let triangles = triangles_from(faces, positions.len())?;
    if uv.len() != 2 * positions.len() {
        return Err(invalid(
            "uv",
            format!(
                "{} numbers, but {} vertices need {} (one row of 2 per vertex)",
                uv.len(),
                positions.len(),
                2 * positions.len()
            ),
        ));
    }
    let flat = finite_rows::<2>("uv", uv)?.into_iter().map(Vec2::from).collect();
    let labels: Vec<u32> = match face_pieces {
        None => vec![0; triangles.len()],
        Some(labels) => {
            if labels.len() != triangles.len() {
                return Err(invalid(
                    "face_pieces",
                    format!("{} labels for {} faces", labels.len(), triangles.len()),
                ));
            }
            labels
                .iter()
                .enumerate()
                .map(|(f, &l)| match u32::try_from(l) {
                    // (At most one piece per face: a label is not a count to allocate for.)
                    Ok(piece) if (piece as usize) < labels.len() => Ok(piece),
                    _ => Err(invalid(
                        "face_pieces",
                        format!(
                            "row {f} is {l}, not a piece number from 0 to {} (at most one piece per face)",
                            labels.len() - 1
                        ),
                    )),
                })
                .collect::<Result<_, _>>()?
        }
    };
    let piece_count = labels.iter().map(|&l| l as usize + 1).max().unwrap_or(1);
    let pieces = match piece_names {
        Some(names) => {
            if names.len() != piece_count {
                return Err(invalid(
                    "piece_names",
                    format!("{} names, but the faces name {piece_count} pieces", names.len()),
                ));
            }
            names.to_vec()
        }
        None if piece_count == 1 => vec![name.to_string()],
        None => (1..=piece_count).map(|p| format!("{name}-{p}")).collect(),
    };
    let mesh = SheetMesh {
        positions,
        flat,
        triangles,
        face_pieces: labels,
        pieces: pieces
            .into_iter()
            .map(|name| Piece {
                name,
                kind: PieceKind::Chart,
            })
            .collect(),
        rulings: vec![],
        smooth_edges: vec![],
        unit,
    };
    mesh.validate().map_err(|e| invalid("uv", e.to_string()))?;
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arrays_make_the_mesh_they_describe() {
        let mesh = mesh_from_arrays(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0], &[0, 1, 2], "m").unwrap();
        assert_eq!(mesh.positions[1], Vec3::x());
        assert_eq!(mesh.triangles, vec![[0, 1, 2]]);
        assert_eq!(mesh.face_groups, vec![0]);
    }

    #[test]
    fn bad_arrays_are_refused_naming_the_array_and_row() {
        let v = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
        let message = |e: PipelineError| e.to_string();
        assert!(message(mesh_from_arrays(&v[..8], &[0, 1, 2], "m").unwrap_err()).contains("vertices"));
        let mut nan = v;
        nan[4] = f64::NAN;
        assert!(message(mesh_from_arrays(&nan, &[0, 1, 2], "m").unwrap_err()).contains("row 1 has a non-finite"));
        let e = message(mesh_from_arrays(&v, &[0, 1, 3], "m").unwrap_err());
        assert!(e.contains("faces") && e.contains("row 0 names vertex 3"), "{e}");
        assert!(message(mesh_from_arrays(&v, &[0, -1, 2], "m").unwrap_err()).contains("vertex -1"));
        assert_eq!(
            message(mesh_from_arrays::<i64>(&v, &[], "m").unwrap_err()),
            "faces: the mesh has no faces"
        );
        let e =
            message(sheet_mesh_from_arrays(&v, &[0, 1, 2], &[0.0; 4], None, None, "m", LengthUnit::Mm).unwrap_err());
        assert!(e.contains("uv") && e.contains("3 vertices need 6"), "{e}");
        let e = message(
            sheet_mesh_from_arrays(&v, &[0, 1, 2], &[0.0; 6], Some(&[-2]), None, "m", LengthUnit::Mm).unwrap_err(),
        );
        assert!(e.contains("face_pieces") && e.contains("row 0 is -2"), "{e}");
        // A label past the faces is refused before any piece is made for it.
        let e = message(
            sheet_mesh_from_arrays(
                &v,
                &[0, 1, 2],
                &[0.0; 6],
                Some(&[4_000_000_000]),
                None,
                "m",
                LengthUnit::Mm,
            )
            .unwrap_err(),
        );
        assert!(e.contains("not a piece number from 0 to 0"), "{e}");
        let mesh = mesh_from_arrays(&v, &[0, 1, 2], "m").unwrap();
        assert_eq!(seam_edges_from_array(&mesh, &[2, 1]).unwrap(), vec![[2, 1]]);
        let e = message(seam_edges_from_array(&mesh, &[0, 1, 1, 3]).unwrap_err());
        assert!(e.contains("drawn_seams") && e.contains("row 1 names vertex 3"), "{e}");
        let e = message(seam_edges_from_array(&mesh, &[0, 0]).unwrap_err());
        assert!(e.contains("row 0 (0, 0) is not an edge"), "{e}");
    }
}

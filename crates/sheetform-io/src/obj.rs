use sheetform_mesh::SheetMesh;
use std::fmt::Write;

/// Wavefront OBJ text of the bent sheet.
///
/// - `v x y z`: 3D positions in the model unit;
/// - `vt u v`: the vertex's position on the flat sheet **at 1:1 scale** in the same unit
///   (not normalised to [0, 1]): the pattern to cut;
/// - `vn`: area-weighted vertex normals;
/// - one group `g <piece name>` per piece, faces `f v/vt/vn` (1-based, same index for all
///   three), counter-clockwise seen from the sheet's top side.
pub fn obj_string(mesh: &SheetMesh, name: &str) -> String {
    let mut s = String::with_capacity(mesh.positions.len() * 96 + mesh.triangles.len() * 40);
    let _ = writeln!(s, "# sheetform bent sheet `{name}`");
    let _ = writeln!(
        s,
        "# units: {} (3D and flat); vt = flat-sheet coordinates at 1:1 scale",
        mesh.unit.symbol()
    );
    let _ = writeln!(s, "o {}", sanitize(name));
    for p in &mesh.positions {
        let _ = writeln!(s, "v {} {} {}", p.x, p.y, p.z);
    }
    for q in &mesh.flat {
        let _ = writeln!(s, "vt {} {}", q.x, q.y);
    }
    for n in mesh.vertex_normals() {
        let _ = writeln!(s, "vn {} {} {}", n.x, n.y, n.z);
    }
    for (piece_index, piece) in mesh.pieces.iter().enumerate() {
        let faces: Vec<&[u32; 3]> = mesh
            .triangles
            .iter()
            .zip(&mesh.face_pieces)
            .filter(|(_, &p)| p as usize == piece_index)
            .map(|(t, _)| t)
            .collect();
        if faces.is_empty() {
            continue;
        }
        let _ = writeln!(s, "g {}", sanitize(&piece.name));
        for t in faces {
            let [a, b, c] = t.map(|i| i + 1);
            let _ = writeln!(s, "f {a}/{a}/{a} {b}/{b}/{b} {c}/{c}/{c}");
        }
    }
    s
}

fn sanitize(name: &str) -> String {
    let cleaned: String = name.chars().map(|c| if c.is_whitespace() { '_' } else { c }).collect();
    if cleaned.is_empty() {
        "sheet".into()
    } else {
        cleaned
    }
}

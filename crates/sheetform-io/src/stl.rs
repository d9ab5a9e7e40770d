use sheetform_mesh::SheetMesh;

/// Binary STL of the bent sheet (80-byte header, triangle count, then per triangle the
/// unit normal, three vertices as little-endian `f32`, and a zero attribute word).
/// Coordinates are in the model unit (STL has none; the header says which).
pub fn stl_bytes(mesh: &SheetMesh) -> Vec<u8> {
    let mut out = Vec::with_capacity(84 + mesh.triangles.len() * 50);
    let mut header = format!("sheetform bent sheet, units {}", mesh.unit.symbol()).into_bytes();
    header.resize(80, b' ');
    out.extend_from_slice(&header);
    out.extend_from_slice(&(mesh.triangles.len() as u32).to_le_bytes());
    for (f, t) in mesh.triangles.iter().enumerate() {
        let n = mesh.face_normal(f);
        for c in n.iter() {
            out.extend_from_slice(&(*c as f32).to_le_bytes());
        }
        for &v in t {
            for c in mesh.positions[v as usize].iter() {
                out.extend_from_slice(&(*c as f32).to_le_bytes());
            }
        }
        out.extend_from_slice(&0u16.to_le_bytes());
    }
    out
}

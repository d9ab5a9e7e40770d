use serde_json::json;
use sheetform_mesh::{PieceKind, SheetMesh};

/// Name of the application-specific glTF vertex attribute that holds the flat-sheet
/// coordinates at 1:1 scale (in metres, like every glTF length).
pub const GLB_FLAT_ATTRIBUTE: &str = "_FLAT";

/// glTF 2.0 binary (`.glb`) of the bent sheet.
///
/// Lengths are converted to metres, glTF's unit. One mesh with one primitive per piece
/// (its own material: curved pieces blue, planar pieces sand, double-sided), sharing the
/// vertex attributes `POSITION`, `NORMAL`, `TEXCOORD_0` (the flat pattern scaled
/// uniformly into the unit square, for textures) and [`GLB_FLAT_ATTRIBUTE`] (the flat
/// pattern at 1:1 in metres).
pub fn glb_bytes(mesh: &SheetMesh, name: &str) -> Vec<u8> {
    let to_m = mesh.unit.millimetres() / 1000.0;
    let n = mesh.positions.len();
    let mut bin: Vec<u8> = Vec::new();
    let mut views = Vec::new();
    let mut accessors = Vec::new();
    let mut push_view = |bin: &mut Vec<u8>, bytes: &[u8], target: u32| -> usize {
        while bin.len() % 4 != 0 {
            bin.push(0);
        }
        views.push(json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": bytes.len(), "target": target}));
        bin.extend_from_slice(bytes);
        views.len() - 1
    };
    let f32s =
        |values: &mut dyn Iterator<Item = f64>| -> Vec<u8> { values.flat_map(|v| (v as f32).to_le_bytes()).collect() };

    // POSITION with exact f32 min/max.
    let pos32: Vec<[f32; 3]> = mesh
        .positions
        .iter()
        .map(|p| [(p.x * to_m) as f32, (p.y * to_m) as f32, (p.z * to_m) as f32])
        .collect();
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for p in &pos32 {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let bytes: Vec<u8> = pos32
        .iter()
        .flat_map(|p| p.iter().flat_map(|c| c.to_le_bytes()))
        .collect();
    let v = push_view(&mut bin, &bytes, 34962);
    accessors.push(json!({"bufferView": v, "componentType": 5126, "count": n, "type": "VEC3", "min": lo, "max": hi}));
    let position = accessors.len() - 1;

    let normals: Vec<_> = mesh
        .vertex_normals()
        .into_iter()
        .map(|v| if v.norm() > 0.5 { v } else { nalgebra::Vector3::z() })
        .collect();
    let bytes = f32s(&mut normals.iter().flat_map(|v| [v.x, v.y, v.z]));
    let v = push_view(&mut bin, &bytes, 34962);
    accessors.push(json!({"bufferView": v, "componentType": 5126, "count": n, "type": "VEC3"}));
    let normal = accessors.len() - 1;

    let (flo, fhi) = mesh.flat_bounds();
    let size = (fhi - flo).max().max(f64::MIN_POSITIVE);
    let bytes = f32s(
        &mut mesh
            .flat
            .iter()
            .flat_map(|q| [(q.x - flo.x) / size, 1.0 - (q.y - flo.y) / size]),
    );
    let v = push_view(&mut bin, &bytes, 34962);
    accessors.push(json!({"bufferView": v, "componentType": 5126, "count": n, "type": "VEC2"}));
    let texcoord = accessors.len() - 1;

    let bytes = f32s(&mut mesh.flat.iter().flat_map(|q| [q.x * to_m, q.y * to_m]));
    let v = push_view(&mut bin, &bytes, 34962);
    accessors.push(json!({"bufferView": v, "componentType": 5126, "count": n, "type": "VEC2"}));
    let flat = accessors.len() - 1;

    let mut primitives = Vec::new();
    let mut materials = Vec::new();
    for (p, piece) in mesh.pieces.iter().enumerate() {
        let idx: Vec<u8> = mesh
            .triangles
            .iter()
            .zip(&mesh.face_pieces)
            .filter(|(_, &fp)| fp as usize == p)
            .flat_map(|(t, _)| t.iter().flat_map(|i| i.to_le_bytes()))
            .collect();
        if idx.is_empty() {
            continue;
        }
        let count = idx.len() / 4;
        let v = push_view(&mut bin, &idx, 34963);
        accessors.push(json!({"bufferView": v, "componentType": 5125, "count": count, "type": "SCALAR"}));
        let colour = match piece.kind {
            PieceKind::Curved => [0.32, 0.55, 0.85, 1.0],
            PieceKind::Planar => [0.86, 0.78, 0.6, 1.0],
        };
        materials.push(json!({
            "name": piece.name,
            "doubleSided": true,
            "pbrMetallicRoughness": {"baseColorFactor": colour, "metallicFactor": 0.0, "roughnessFactor": 0.8}
        }));
        primitives.push(json!({
            "attributes": {"POSITION": position, "NORMAL": normal, "TEXCOORD_0": texcoord, GLB_FLAT_ATTRIBUTE: flat},
            "indices": accessors.len() - 1,
            "material": materials.len() - 1,
            "mode": 4
        }));
    }
    while bin.len() % 4 != 0 {
        bin.push(0);
    }
    let doc = json!({
        "asset": {"version": "2.0", "generator": concat!("sheetform ", env!("CARGO_PKG_VERSION"))},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": name}],
        "meshes": [{"name": name, "primitives": primitives, "extras": {"flat_attribute": GLB_FLAT_ATTRIBUTE, "flat_unit": "m", "model_unit": mesh.unit.symbol()}}],
        "materials": materials,
        "buffers": [{"byteLength": bin.len()}],
        "bufferViews": views,
        "accessors": accessors,
    });
    let mut json_bytes = serde_json::to_vec(&doc).expect("glTF JSON serialises");
    while json_bytes.len() % 4 != 0 {
        json_bytes.push(b' ');
    }
    let total = 12 + 8 + json_bytes.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json_bytes.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json_bytes);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    out
}

use serde_json::json;
use sheetform_mesh::{PieceKind, SheetMesh};

/// Name of the application-specific glTF vertex attribute that holds the flat-sheet
/// coordinates at 1:1 scale (in metres, like every glTF length).
pub const GLB_FLAT_ATTRIBUTE: &str = "_FLAT";

/// An image to print on the sheet: PNG or JPEG bytes.
#[derive(Debug, Clone, Copy)]
pub struct Texture<'a> {
    /// The encoded image.
    pub bytes: &'a [u8],
    /// `image/png` or `image/jpeg`.
    pub mime_type: &'static str,
}

impl<'a> Texture<'a> {
    /// Recognises PNG and JPEG by their signatures.
    pub fn from_bytes(bytes: &'a [u8]) -> Option<Self> {
        if bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
            Some(Self {
                bytes,
                mime_type: "image/png",
            })
        } else if bytes.starts_with(&[0xFF, 0xD8, 0xFF]) {
            Some(Self {
                bytes,
                mime_type: "image/jpeg",
            })
        } else {
            None
        }
    }
}

/// glTF 2.0 binary (`.glb`) of the bent sheet.
///
/// Lengths are converted to metres, glTF's unit. One mesh with one primitive per piece
/// (its own material: curved pieces blue, planar pieces sand, double-sided), sharing the
/// vertex attributes `POSITION`, `NORMAL`, `TEXCOORD_0` (the flat pattern's bounding
/// box mapped onto the unit square, for a texture) and [`GLB_FLAT_ATTRIBUTE`] (the flat
/// pattern at 1:1 in metres). With a `texture`, every material shows it.
pub fn glb_bytes(mesh: &SheetMesh, name: &str, texture: Option<Texture<'_>>) -> Vec<u8> {
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
    let size = (fhi - flo).sup(&nalgebra::Vector2::repeat(f64::MIN_POSITIVE));
    let bytes = f32s(
        &mut mesh
            .flat
            .iter()
            .flat_map(|q| [(q.x - flo.x) / size.x, 1.0 - (q.y - flo.y) / size.y]),
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
        let mut pbr = json!({"baseColorFactor": colour, "metallicFactor": 0.0, "roughnessFactor": 0.8});
        if texture.is_some() {
            pbr = json!({"baseColorTexture": {"index": 0}, "metallicFactor": 0.0, "roughnessFactor": 0.8});
        }
        materials.push(json!({"name": piece.name, "doubleSided": true, "pbrMetallicRoughness": pbr}));
        primitives.push(json!({
            "attributes": {"POSITION": position, "NORMAL": normal, "TEXCOORD_0": texcoord, GLB_FLAT_ATTRIBUTE: flat},
            "indices": accessors.len() - 1,
            "material": materials.len() - 1,
            "mode": 4
        }));
    }
    let mut images = Vec::new();
    if let Some(t) = texture {
        while bin.len() % 4 != 0 {
            bin.push(0);
        }
        views.push(json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": t.bytes.len()}));
        bin.extend_from_slice(t.bytes);
        images.push(json!({"bufferView": views.len() - 1, "mimeType": t.mime_type}));
    }
    while bin.len() % 4 != 0 {
        bin.push(0);
    }
    let mut doc = json!({
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
    if !images.is_empty() {
        doc["images"] = json!(images);
        doc["samplers"] = json!([{"magFilter": 9729, "minFilter": 9987, "wrapS": 33071, "wrapT": 33071}]);
        doc["textures"] = json!([{"source": 0, "sampler": 0}]);
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Vector2, Vector3};
    use sheetform_mesh::{Piece, SheetMesh};

    fn square() -> SheetMesh {
        SheetMesh {
            positions: vec![
                Vector3::new(0.0, 0.0, 0.0),
                Vector3::new(2.0, 0.0, 0.0),
                Vector3::new(2.0, 1.0, 0.0),
                Vector3::new(0.0, 1.0, 0.0),
            ],
            flat: vec![
                Vector2::new(0.0, 0.0),
                Vector2::new(2.0, 0.0),
                Vector2::new(2.0, 1.0),
                Vector2::new(0.0, 1.0),
            ],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            face_pieces: vec![0, 0],
            pieces: vec![Piece {
                name: "p".into(),
                kind: PieceKind::Planar,
            }],
            rulings: vec![],
            unit: Default::default(),
        }
    }

    fn json_chunk(glb: &[u8]) -> serde_json::Value {
        let len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
        serde_json::from_slice(&glb[20..20 + len]).unwrap()
    }

    fn floats(glb: &[u8], doc: &serde_json::Value, accessor: usize) -> Vec<f32> {
        let json_len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
        let bin = &glb[20 + json_len + 8..];
        let view = &doc["bufferViews"][doc["accessors"][accessor]["bufferView"].as_u64().unwrap() as usize];
        let (off, len) = (
            view["byteOffset"].as_u64().unwrap() as usize,
            view["byteLength"].as_u64().unwrap() as usize,
        );
        bin[off..off + len]
            .chunks(4)
            .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
            .collect()
    }

    #[test]
    fn texture_is_embedded_and_spans_the_pattern() {
        let png = b"\x89PNG\r\n\x1a\n0000";
        let glb = glb_bytes(&square(), "s", Some(Texture::from_bytes(png).unwrap()));
        let doc = json_chunk(&glb);
        assert_eq!(doc["images"][0]["mimeType"], "image/png");
        assert_eq!(
            doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"],
            0
        );
        let prim = &doc["meshes"][0]["primitives"][0]["attributes"];
        let uv = floats(&glb, &doc, prim["TEXCOORD_0"].as_u64().unwrap() as usize);
        assert_eq!(uv, vec![0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0]);
        // Positions are in metres (the model is in millimetres).
        let pos = floats(&glb, &doc, prim["POSITION"].as_u64().unwrap() as usize);
        assert!((pos[3] - 0.002).abs() < 1e-9);
        assert!(Texture::from_bytes(b"GIF89a").is_none());
    }
}

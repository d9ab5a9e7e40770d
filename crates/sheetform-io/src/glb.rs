use serde_json::json;
use sheetform_mesh::UpAxis;
use sheetform_mesh::{PieceKind, SheetMesh, TriangleMesh};

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

impl Texture<'_> {
    /// Width and height in pixels, read from the PNG `IHDR` chunk or the JPEG
    /// start-of-frame segment; `None` when the header is truncated or malformed.
    pub fn size(&self) -> Option<(u32, u32)> {
        let b = self.bytes;
        if self.mime_type == "image/png" {
            // Signature (8), chunk length (4), "IHDR" (4), width (4), height (4).
            if b.len() < 24 || &b[12..16] != b"IHDR" {
                return None;
            }
            let be = |i: usize| u32::from_be_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]);
            return Some((be(16), be(20)));
        }
        // JPEG: walk the segments to the first start-of-frame (SOF0–SOF15 except DHT,
        // JPG and DAC).
        let mut i = 2;
        while i + 9 < b.len() {
            if b[i] != 0xFF {
                return None;
            }
            let marker = b[i + 1];
            if marker == 0xFF {
                i += 1;
                continue;
            }
            let length = usize::from(u16::from_be_bytes([b[i + 2], b[i + 3]]));
            if (0xC0..=0xCF).contains(&marker) && ![0xC4, 0xC8, 0xCC].contains(&marker) {
                let h = u16::from_be_bytes([b[i + 5], b[i + 6]]);
                let w = u16::from_be_bytes([b[i + 7], b[i + 8]]);
                return Some((u32::from(w), u32::from(h)));
            }
            if length < 2 {
                return None;
            }
            i += 2 + length;
        }
        None
    }
}

/// Buffer, views and accessors of a glTF binary under construction.
#[derive(Default)]
struct GlbBuilder {
    bin: Vec<u8>,
    views: Vec<serde_json::Value>,
    accessors: Vec<serde_json::Value>,
}

impl GlbBuilder {
    fn view(&mut self, bytes: &[u8], target: Option<u32>) -> usize {
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        let mut v = json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len()});
        if let Some(t) = target {
            v["target"] = json!(t);
        }
        self.views.push(v);
        self.bin.extend_from_slice(bytes);
        self.views.len() - 1
    }

    /// A float vertex attribute (`VEC2`, `VEC3`, `VEC4`); `min_max` adds bounds (needed
    /// for `POSITION`).
    fn floats(&mut self, values: &[f32], components: usize, min_max: bool) -> usize {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes, Some(34962));
        let kind = ["", "SCALAR", "VEC2", "VEC3", "VEC4"][components];
        let mut a =
            json!({"bufferView": view, "componentType": 5126, "count": values.len() / components, "type": kind});
        if min_max {
            let mut lo = vec![f32::INFINITY; components];
            let mut hi = vec![f32::NEG_INFINITY; components];
            for chunk in values.chunks(components) {
                for k in 0..components {
                    lo[k] = lo[k].min(chunk[k]);
                    hi[k] = hi[k].max(chunk[k]);
                }
            }
            a["min"] = json!(lo);
            a["max"] = json!(hi);
        }
        self.accessors.push(a);
        self.accessors.len() - 1
    }

    fn indices(&mut self, indices: &[u32]) -> usize {
        let bytes: Vec<u8> = indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        let view = self.view(&bytes, Some(34963));
        self.accessors
            .push(json!({"bufferView": view, "componentType": 5125, "count": indices.len(), "type": "SCALAR"}));
        self.accessors.len() - 1
    }

    /// The `.glb` file: `doc` completed with buffers, views and accessors.
    fn finish(mut self, mut doc: serde_json::Value) -> Vec<u8> {
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        doc["asset"] = json!({"version": "2.0", "generator": concat!("sheetform ", env!("CARGO_PKG_VERSION"))});
        doc["buffers"] = json!([{"byteLength": self.bin.len()}]);
        doc["bufferViews"] = json!(self.views);
        doc["accessors"] = json!(self.accessors);
        let mut json_bytes = serde_json::to_vec(&doc).expect("glTF JSON serialises");
        while json_bytes.len() % 4 != 0 {
            json_bytes.push(b' ');
        }
        let total = 12 + 8 + json_bytes.len() + 8 + self.bin.len();
        let mut out = Vec::with_capacity(total);
        out.extend_from_slice(b"glTF");
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&(total as u32).to_le_bytes());
        out.extend_from_slice(&(json_bytes.len() as u32).to_le_bytes());
        out.extend_from_slice(b"JSON");
        out.extend_from_slice(&json_bytes);
        out.extend_from_slice(&(self.bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&self.bin);
        out
    }
}

fn unit_normals(normals: Vec<nalgebra::Vector3<f64>>) -> Vec<f32> {
    normals
        .into_iter()
        .map(|v| if v.norm() > 0.5 { v } else { nalgebra::Vector3::z() })
        .flat_map(|v| [v.x as f32, v.y as f32, v.z as f32])
        .collect()
}

/// The glTF node of the mesh, rotated to Y-up when needed: a model built `+Z`-up gets a
/// root-node rotation of −90° about `x` (`(x, y, z) ↦ (x, z, −y)`), so that it stands
/// upright in every glTF viewer while its coordinates stay the model's.
fn up_node(up: UpAxis, name: &str) -> serde_json::Value {
    let mut node = json!({"mesh": 0, "name": name});
    if up == UpAxis::Z {
        let h = std::f64::consts::FRAC_1_SQRT_2;
        node["rotation"] = json!([-h, 0.0, 0.0, h]);
    }
    node
}

/// glTF 2.0 binary (`.glb`) of the bent sheet.
///
/// Lengths are converted to metres, glTF's unit. One mesh with one primitive per piece
/// (its own material: curved pieces blue, planar pieces sand, double-sided), sharing the
/// vertex attributes `POSITION`, `NORMAL`, `TEXCOORD_0` (the flat pattern's bounding
/// box mapped onto the unit square, for a texture) and [`GLB_FLAT_ATTRIBUTE`] (the flat
/// pattern at 1:1 in metres). With a `texture`, every material shows it.
pub fn glb_bytes(mesh: &SheetMesh, name: &str, texture: Option<Texture<'_>>, up: UpAxis) -> Vec<u8> {
    glb_with_texcoords(mesh, name, texture, None, up)
}

/// [`glb_bytes`] with the texture mapped by explicit per-vertex coordinates
/// (`TEXCOORD_0`, glTF convention: `[0, 1]²`, `v` down the image) instead of the flat
/// pattern: a photograph projected onto the model (system D). `_FLAT` still holds the
/// pattern.
///
/// # Panics
/// If `texcoords` does not have one entry per vertex.
pub fn glb_bytes_projected(
    mesh: &SheetMesh,
    name: &str,
    texture: Texture<'_>,
    texcoords: &[[f32; 2]],
    up: UpAxis,
) -> Vec<u8> {
    assert_eq!(
        texcoords.len(),
        mesh.positions.len(),
        "one texture coordinate per vertex"
    );
    glb_with_texcoords(mesh, name, Some(texture), Some(texcoords), up)
}

fn glb_with_texcoords(
    mesh: &SheetMesh,
    name: &str,
    texture: Option<Texture<'_>>,
    texcoords: Option<&[[f32; 2]]>,
    up: UpAxis,
) -> Vec<u8> {
    let to_m = mesh.unit.millimetres() / 1000.0;
    let mut b = GlbBuilder::default();
    let pos: Vec<f32> = mesh
        .positions
        .iter()
        .flat_map(|p| [(p.x * to_m) as f32, (p.y * to_m) as f32, (p.z * to_m) as f32])
        .collect();
    let position = b.floats(&pos, 3, true);
    let normal = b.floats(&unit_normals(mesh.vertex_normals()), 3, false);
    let (flo, fhi) = mesh.flat_bounds();
    let size = (fhi - flo).sup(&nalgebra::Vector2::repeat(f64::MIN_POSITIVE));
    let uv: Vec<f32> = match texcoords {
        Some(uv) => uv.iter().flat_map(|t| [t[0], t[1]]).collect(),
        None => mesh
            .flat
            .iter()
            .flat_map(|q| [((q.x - flo.x) / size.x) as f32, (1.0 - (q.y - flo.y) / size.y) as f32])
            .collect(),
    };
    let texcoord = b.floats(&uv, 2, false);
    let flat_m: Vec<f32> = mesh
        .flat
        .iter()
        .flat_map(|q| [(q.x * to_m) as f32, (q.y * to_m) as f32])
        .collect();
    let flat = b.floats(&flat_m, 2, false);
    let mut primitives = Vec::new();
    let mut materials = Vec::new();
    for (p, piece) in mesh.pieces.iter().enumerate() {
        let idx: Vec<u32> = mesh
            .triangles
            .iter()
            .zip(&mesh.face_pieces)
            .filter(|(_, &fp)| fp as usize == p)
            .flat_map(|(t, _)| t.iter().copied())
            .collect();
        if idx.is_empty() {
            continue;
        }
        let indices = b.indices(&idx);
        let colour = match piece.kind {
            PieceKind::Curved => [0.32, 0.55, 0.85, 1.0],
            PieceKind::Planar => [0.86, 0.78, 0.6, 1.0],
            PieceKind::Chart => [0.55, 0.75, 0.55, 1.0],
        };
        let pbr = if texture.is_some() {
            json!({"baseColorTexture": {"index": 0}, "metallicFactor": 0.0, "roughnessFactor": 0.8})
        } else {
            json!({"baseColorFactor": colour, "metallicFactor": 0.0, "roughnessFactor": 0.8})
        };
        materials.push(json!({"name": piece.name, "doubleSided": true, "pbrMetallicRoughness": pbr}));
        primitives.push(json!({
            "attributes": {"POSITION": position, "NORMAL": normal, "TEXCOORD_0": texcoord, GLB_FLAT_ATTRIBUTE: flat},
            "indices": indices,
            "material": materials.len() - 1,
            "mode": 4
        }));
    }
    let mut doc = json!({
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [up_node(up, name)],
        "meshes": [{"name": name, "primitives": primitives, "extras": {"flat_attribute": GLB_FLAT_ATTRIBUTE, "flat_unit": "m", "model_unit": mesh.unit.symbol()}}],
        "materials": materials,
    });
    if let Some(t) = texture {
        let view = b.view(t.bytes, None);
        doc["images"] = json!([{"bufferView": view, "mimeType": t.mime_type}]);
        doc["samplers"] = json!([{"magFilter": 9729, "minFilter": 9987, "wrapS": 33071, "wrapT": 33071}]);
        doc["textures"] = json!([{"source": 0, "sampler": 0}]);
    }
    b.finish(doc)
}

/// glTF 2.0 binary of any triangle mesh with a colour per vertex (`COLOR_0`, linear RGB
/// in [0, 1]), unlit-looking (rough, non-metallic, double-sided): a colour map of a
/// per-vertex measure. `to_metres` converts the mesh's lengths to metres.
pub fn glb_vertex_colours(
    mesh: &TriangleMesh,
    colours: &[[f32; 3]],
    to_metres: f64,
    name: &str,
    up: UpAxis,
) -> Vec<u8> {
    let mut b = GlbBuilder::default();
    let pos: Vec<f32> = mesh
        .positions
        .iter()
        .flat_map(|p| {
            [
                (p.x * to_metres) as f32,
                (p.y * to_metres) as f32,
                (p.z * to_metres) as f32,
            ]
        })
        .collect();
    let position = b.floats(&pos, 3, true);
    let mut normals = vec![nalgebra::Vector3::<f64>::zeros(); mesh.positions.len()];
    for (f, t) in mesh.triangles.iter().enumerate() {
        let n = mesh.face_normal(f) * mesh.face_area(f);
        for &v in t {
            normals[v as usize] += n;
        }
    }
    let normals: Vec<_> = normals
        .into_iter()
        .map(|n| if n.norm() > 0.0 { n.normalize() } else { n })
        .collect();
    let normal = b.floats(&unit_normals(normals), 3, false);
    let cols: Vec<f32> = colours.iter().flat_map(|c| c.iter().copied()).collect();
    let colour = b.floats(&cols, 3, false);
    let idx: Vec<u32> = mesh.triangles.iter().flat_map(|t| t.iter().copied()).collect();
    let indices = b.indices(&idx);
    let doc = json!({
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [up_node(up, name)],
        "meshes": [{"name": name, "primitives": [{"attributes": {"POSITION": position, "NORMAL": normal, "COLOR_0": colour}, "indices": indices, "material": 0, "mode": 4}]}],
        "materials": [{"name": "colour map", "doubleSided": true, "pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 1.0}}],
    });
    b.finish(doc)
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
            smooth_edges: vec![],
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
        let glb = glb_bytes(&square(), "s", Some(Texture::from_bytes(png).unwrap()), UpAxis::Y);
        let doc = json_chunk(&glb);
        assert!(doc["nodes"][0].get("rotation").is_none(), "Y-up needs no rotation");
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

    /// A Z-up model gets the root rotation that stands it upright: the rotation maps the
    /// model's +Z (its up) to glTF's +Y and its +Y to −Z.
    #[test]
    fn a_z_up_model_is_turned_to_y_up() {
        let glb = glb_bytes(&square(), "s", None, UpAxis::Z);
        let doc = json_chunk(&glb);
        let q: Vec<f64> = doc["nodes"][0]["rotation"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        let rotation = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q[3], q[0], q[1], q[2]));
        let up = rotation * Vector3::z();
        assert!((up - Vector3::y()).norm() < 1e-12, "{up}");
        let forward = rotation * Vector3::y();
        assert!((forward + Vector3::z()).norm() < 1e-12, "{forward}");
        let colours = glb_vertex_colours(&square().to_triangle_mesh(), &[[0.0; 3]; 4], 1e-3, "c", UpAxis::Z);
        assert!(json_chunk(&colours)["nodes"][0]["rotation"].is_array());
    }
}

use sheetform_mesh::{SheetMesh, UpAxis};
use std::fmt::Write;

/// Wavefront OBJ text of a model with its flat pattern (a bent sheet, a slit sheet, FFD
/// panels, a flattened mesh).
///
/// - `v x y z`: 3D positions in the model unit;
/// - `vt u v`: the vertex's position on the flat sheet **at 1:1 scale** in the same unit
///   (not normalised to [0, 1]): the pattern to cut;
/// - `vn`: area-weighted vertex normals;
/// - one group `g <piece name>` per piece, faces `f v/vt/vn` (1-based, same index for all
///   three), counter-clockwise seen from the sheet's top side.
///
/// Positions and normals are written `+Y` up, as OBJ readers (Blender, three.js) and the
/// GLB take them: a model built `+Z`-up (`up`) is turned, `(x, y, z) ↦ (x, z, −y)`, and
/// the header says so; `vt` is the pattern either way.
pub fn obj_string(mesh: &SheetMesh, name: &str, up: UpAxis) -> String {
    let mut s = String::with_capacity(mesh.positions.len() * 96 + mesh.triangles.len() * 40);
    let _ = writeln!(
        s,
        "# sheetform model `{}`: the 3D shape and its flat pattern",
        comment(name)
    );
    let _ = writeln!(
        s,
        "# units: {} (3D and flat); vt = flat-sheet coordinates at 1:1 scale",
        mesh.unit.symbol()
    );
    let _ = writeln!(
        s,
        "# up axis: +y{}",
        if up == UpAxis::Z {
            " (the model's +z turned to +y, as in model.glb)"
        } else {
            ""
        }
    );
    let _ = writeln!(s, "o {}", sanitize(name));
    for p in &mesh.positions {
        let p = up.to_y_up(*p);
        let _ = writeln!(s, "v {} {} {}", p.x, p.y, p.z);
    }
    for q in &mesh.flat {
        let _ = writeln!(s, "vt {} {}", q.x, q.y);
    }
    for n in mesh.vertex_normals() {
        let n = up.to_y_up(n);
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

/// A name for a comment line: control characters (line breaks among them, which would
/// end the comment and inject lines into the file) become spaces.
fn comment(name: &str) -> String {
    name.chars().map(|c| if c.is_control() { ' ' } else { c }).collect()
}

fn sanitize(name: &str) -> String {
    let cleaned: String = name
        .chars()
        .map(|c| if c.is_whitespace() || c.is_control() { '_' } else { c })
        .collect();
    if cleaned.is_empty() {
        "sheet".into()
    } else {
        cleaned
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sheetform_mesh::{LengthUnit, Piece, PieceKind};
    type Vec3 = nalgebra::Vector3<f64>;
    type Vec2 = nalgebra::Vector2<f64>;

    fn triangle() -> SheetMesh {
        SheetMesh {
            positions: vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 2.0, 3.0),
            ],
            flat: vec![Vec2::new(0.0, 0.0), Vec2::new(1.0, 0.0), Vec2::new(1.0, 3.6)],
            triangles: vec![[0, 1, 2]],
            face_pieces: vec![0],
            pieces: vec![Piece {
                name: "p".into(),
                kind: PieceKind::Chart,
            }],
            rulings: vec![],
            smooth_edges: vec![],
            unit: LengthUnit::Mm,
        }
    }

    #[test]
    fn a_z_up_model_is_written_y_up_and_a_name_cannot_inject_lines() {
        let mesh = triangle();
        let z = obj_string(&mesh, "sheet", UpAxis::Z);
        assert!(z.contains("\nv 1 3 -2\n"), "{z}");
        assert!(z.contains("# up axis: +y (the model's +z turned to +y"));
        // vt is the pattern either way.
        assert!(z.contains("\nvt 1 3.6\n"));
        let y = obj_string(&mesh, "sheet", UpAxis::Y);
        assert!(y.contains("\nv 1 2 3\n"), "{y}");
        let injected = obj_string(&mesh, "a\nv 9 9 9\nf 1 2 3", UpAxis::Y);
        assert_eq!(injected.lines().filter(|l| l.starts_with("v ")).count(), 3);
        assert_eq!(injected.lines().filter(|l| l.starts_with("f ")).count(), 1);
    }
}

//! Reading triangle meshes: OBJ (with groups and `vt`), PLY, STL, OFF.

use nalgebra::{Vector2, Vector3};
use sheetform_geometry::quoted_token;
use sheetform_mesh::TriangleMesh;
use std::path::Path;
use thiserror::Error;

/// A mesh file that cannot be read, with where and why.
#[derive(Debug, Error)]
pub enum MeshReadError {
    /// The file cannot be opened or read.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The OS error.
        source: std::io::Error,
    },
    /// The content is malformed.
    #[error("{path}{}: {message}", .line.map(|l| format!(":{l}")).unwrap_or_default())]
    Malformed {
        /// The file.
        path: String,
        /// 1-based line, where known.
        line: Option<usize>,
        /// What is wrong.
        message: String,
    },
    /// The extension is not one we read.
    #[error("{path}: unknown mesh format (expected .obj, .ply, .stl or .off)")]
    UnknownFormat {
        /// The file.
        path: String,
    },
}

fn malformed(path: &Path, line: Option<usize>, message: impl Into<String>) -> MeshReadError {
    MeshReadError::Malformed {
        path: path.display().to_string(),
        line,
        message: message.into(),
    }
}

/// Reads a mesh, choosing the format by extension. Polygons are fan-triangulated.
///
/// # Errors
/// Unreadable files; empty meshes; wrong counts; non-numbers, NaN or infinite coordinates;
/// face indices out of range; faces with fewer than three vertices — each with the file
/// and (for text formats) the line.
pub fn read_mesh(path: &Path) -> Result<TriangleMesh, MeshReadError> {
    let bytes = crate::read_bounded(path, crate::MAX_MESH_FILE_BYTES).map_err(|source| MeshReadError::Io {
        path: path.display().to_string(),
        source,
    })?;
    mesh_from_bytes(path, &bytes)
}

/// Parses a mesh file's bytes, choosing the format by the extension of `name` (the
/// file's name, also used in messages). Polygons are fan-triangulated.
///
/// # Errors
/// As [`read_mesh`], without the read errors.
pub fn mesh_from_bytes(name: &Path, bytes: &[u8]) -> Result<TriangleMesh, MeshReadError> {
    // A UTF-8 byte-order mark (Windows editors write one) is not part of the first line:
    // left in, it hid the first `v` statement and shifted every index by one.
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let path = name;
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    let mesh = match ext.as_str() {
        "obj" => parse_obj(path, &String::from_utf8_lossy(bytes))?,
        "off" => parse_off(path, &String::from_utf8_lossy(bytes))?,
        "stl" => parse_stl(path, bytes)?,
        "ply" => parse_ply(path, bytes)?,
        _ => {
            return Err(MeshReadError::UnknownFormat {
                path: path.display().to_string(),
            })
        }
    };
    if mesh.triangles.is_empty() {
        return Err(malformed(path, None, "the mesh has no faces"));
    }
    Ok(mesh)
}

fn number(path: &Path, line: usize, token: Option<&str>, what: &str) -> Result<f64, MeshReadError> {
    let t = token.ok_or_else(|| malformed(path, Some(line), format!("{what}: missing number")))?;
    let v: f64 = t.parse().map_err(|_| {
        malformed(
            path,
            Some(line),
            format!("{what}: `{}` is not a number", quoted_token(t)),
        )
    })?;
    if !v.is_finite() {
        return Err(malformed(
            path,
            Some(line),
            format!("{what}: `{}` is not finite", quoted_token(t)),
        ));
    }
    Ok(v)
}

/// Wavefront OBJ: `v`, `vt`, `f` (with `v`, `v/vt`, `v/vt/vn`, `v//vn`, negative indices),
/// `g`/`o` groups, `l` polylines (kept as seam edges); other statements are ignored. Vertex indices are global across groups
/// (patches sharing vertices stay connected). `vt` are kept per face corner when every
/// face has them.
///
/// Own parser rather than `tobj`, which re-indexes vertices per object/group and reports
/// errors without line numbers.
pub fn parse_obj(path: &Path, text: &str) -> Result<TriangleMesh, MeshReadError> {
    let mut mesh = TriangleMesh::default();
    let mut uvs: Vec<Vector2<f64>> = Vec::new();
    let mut corner_uvs: Vec<[Vector2<f64>; 3]> = Vec::new();
    let mut all_have_uv = true;
    let mut current_group: Option<u32> = None;
    let mut group_index: std::collections::HashMap<String, u32> = std::collections::HashMap::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let content = raw.split('#').next().unwrap_or("");
        let mut it = content.split_whitespace();
        match it.next() {
            Some("v") => {
                let x = number(path, line, it.next(), "vertex x")?;
                let y = number(path, line, it.next(), "vertex y")?;
                let z = number(path, line, it.next(), "vertex z")?;
                mesh.positions.push(Vector3::new(x, y, z));
            }
            Some("vt") => {
                let u = number(path, line, it.next(), "texture u")?;
                let v = number(path, line, it.next(), "texture v")?;
                uvs.push(Vector2::new(u, v));
            }
            Some(kw @ ("g" | "o")) => {
                let name: Vec<&str> = it.collect();
                let name = if name.is_empty() {
                    format!("{kw}-unnamed")
                } else {
                    name.join(" ")
                };
                let next = group_index.len() as u32;
                let g = *group_index.entry(name.clone()).or_insert_with(|| {
                    mesh.groups.push(name);
                    next
                });
                current_group = Some(g);
            }
            Some("l") => {
                // A polyline: its segments are user-given seams.
                let mut previous: Option<u32> = None;
                for token in it {
                    let s = token.split('/').next().unwrap_or("");
                    let k: i64 = s.parse().map_err(|_| {
                        malformed(
                            path,
                            Some(line),
                            format!("line vertex index `{}` is not an integer", quoted_token(s)),
                        )
                    })?;
                    let count = mesh.positions.len();
                    let idx = if k < 0 { count as i64 + k } else { k - 1 };
                    if k == 0 || idx < 0 || idx as usize >= count {
                        return Err(malformed(
                            path,
                            Some(line),
                            format!("line vertex index {k} is out of range (there are {count} so far)"),
                        ));
                    }
                    if let Some(a) = previous {
                        mesh.seam_edges.push([a, idx as u32]);
                    }
                    previous = Some(idx as u32);
                }
            }
            Some("f") => {
                let mut corners: Vec<(u32, Option<usize>)> = Vec::new();
                for token in it {
                    let mut parts = token.split('/');
                    let resolve = |s: &str, count: usize, what: &str| -> Result<usize, MeshReadError> {
                        let k: i64 = s.parse().map_err(|_| {
                            malformed(
                                path,
                                Some(line),
                                format!("face {what} index `{}` is not an integer", quoted_token(s)),
                            )
                        })?;
                        let idx = if k < 0 { count as i64 + k } else { k - 1 };
                        if k == 0 || idx < 0 || idx as usize >= count {
                            return Err(malformed(
                                path,
                                Some(line),
                                format!("face {what} index {k} is out of range (there are {count} so far)"),
                            ));
                        }
                        Ok(idx as usize)
                    };
                    let v = resolve(parts.next().unwrap_or(""), mesh.positions.len(), "vertex")?;
                    let t = match parts.next() {
                        Some(s) if !s.is_empty() => Some(resolve(s, uvs.len(), "texture")?),
                        _ => None,
                    };
                    corners.push((v as u32, t));
                }
                if corners.len() < 3 {
                    return Err(malformed(
                        path,
                        Some(line),
                        format!("a face needs at least 3 vertices, has {}", corners.len()),
                    ));
                }
                let group = match current_group {
                    Some(g) => g,
                    None => {
                        let next = group_index.len() as u32;
                        let g = *group_index.entry("default".into()).or_insert_with(|| {
                            mesh.groups.push("default".into());
                            next
                        });
                        current_group = Some(g);
                        g
                    }
                };
                for k in 1..corners.len() - 1 {
                    let tri = [corners[0], corners[k], corners[k + 1]];
                    mesh.triangles.push(tri.map(|c| c.0));
                    mesh.face_groups.push(group);
                    match (tri[0].1, tri[1].1, tri[2].1) {
                        (Some(a), Some(b), Some(c)) => corner_uvs.push([uvs[a], uvs[b], uvs[c]]),
                        _ => all_have_uv = false,
                    }
                }
            }
            _ => {}
        }
    }
    if mesh.positions.is_empty() {
        return Err(malformed(path, None, "no vertices (`v` lines)"));
    }
    if all_have_uv && !mesh.triangles.is_empty() {
        mesh.corner_uvs = Some(corner_uvs);
    }
    Ok(mesh)
}

/// OFF: `OFF`, counts `V F E`, `V` vertex lines, `F` polygon lines (`n i0 i1 …`).
pub fn parse_off(path: &Path, text: &str) -> Result<TriangleMesh, MeshReadError> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.split('#').next().unwrap_or("").trim()))
        .filter(|(_, l)| !l.is_empty());
    let (first_line, header) = lines.next().ok_or_else(|| malformed(path, None, "empty file"))?;
    let Some(rest) = header.strip_prefix("OFF") else {
        return Err(malformed(path, Some(first_line), "the first line must be `OFF`"));
    };
    let (counts_at, counts_line) = if rest.trim().is_empty() {
        lines
            .next()
            .ok_or_else(|| malformed(path, None, "missing the counts line"))?
    } else {
        (first_line, rest.trim())
    };
    let counts: Vec<usize> = counts_line
        .split_whitespace()
        .map(|t| {
            t.parse()
                .map_err(|_| malformed(path, Some(counts_at), format!("`{}` is not a count", quoted_token(t))))
        })
        .collect::<Result<_, _>>()?;
    if counts.len() < 2 {
        return Err(malformed(path, Some(counts_at), "expected `vertices faces [edges]`"));
    }
    let (nv, nf) = (counts[0], counts[1]);
    let mut mesh = TriangleMesh {
        groups: vec!["default".into()],
        ..Default::default()
    };
    for k in 0..nv {
        let (l, text) = lines
            .next()
            .ok_or_else(|| malformed(path, None, format!("expected {nv} vertices, found {k}")))?;
        let mut it = text.split_whitespace();
        let p = Vector3::new(
            number(path, l, it.next(), "vertex x")?,
            number(path, l, it.next(), "vertex y")?,
            number(path, l, it.next(), "vertex z")?,
        );
        mesh.positions.push(p);
    }
    for k in 0..nf {
        let (l, text) = lines
            .next()
            .ok_or_else(|| malformed(path, None, format!("expected {nf} faces, found {k}")))?;
        let vals: Vec<i64> = text
            .split_whitespace()
            .map(|t| {
                t.parse()
                    .map_err(|_| malformed(path, Some(l), format!("`{}` is not an integer", quoted_token(t))))
            })
            .collect::<Result<_, _>>()?;
        let declared = *vals
            .first()
            .ok_or_else(|| malformed(path, Some(l), "empty face line"))?;
        if declared < 3 || vals.len() as i64 - 1 < declared {
            return Err(malformed(
                path,
                Some(l),
                format!("a face needs at least 3 indices and the count it declares ({declared})"),
            ));
        }
        let n = declared as usize;
        let idx: Vec<u32> = vals[1..=n]
            .iter()
            .map(|&i| {
                if i < 0 || i as usize >= nv {
                    Err(malformed(
                        path,
                        Some(l),
                        format!("vertex index {i} is out of range (0..{nv})"),
                    ))
                } else {
                    Ok(i as u32)
                }
            })
            .collect::<Result<_, _>>()?;
        for j in 1..n - 1 {
            mesh.triangles.push([idx[0], idx[j], idx[j + 1]]);
            mesh.face_groups.push(0);
        }
    }
    Ok(mesh)
}

/// STL (ASCII or binary) through `stl_io`; identical corner positions become one vertex.
pub fn parse_stl(path: &Path, bytes: &[u8]) -> Result<TriangleMesh, MeshReadError> {
    let mut cursor = std::io::Cursor::new(bytes);
    let stl = stl_io::read_stl(&mut cursor).map_err(|e| {
        malformed(
            path,
            None,
            format!("not a valid STL file: {}", quoted_token(&e.to_string())),
        )
    })?;
    let mut mesh = TriangleMesh {
        groups: vec!["default".into()],
        ..Default::default()
    };
    for (i, v) in stl.vertices.iter().enumerate() {
        let p = Vector3::new(v[0] as f64, v[1] as f64, v[2] as f64);
        if !p.iter().all(|c| c.is_finite()) {
            return Err(malformed(path, None, format!("vertex {i} has a non-finite coordinate")));
        }
        mesh.positions.push(p);
    }
    for f in &stl.faces {
        mesh.triangles.push(f.vertices.map(|v| v as u32));
        mesh.face_groups.push(0);
    }
    Ok(mesh)
}

/// PLY (ASCII or binary) through `ply-rs-bw`: `vertex` elements with `x y z`, `face`
/// elements with `vertex_indices` (or `vertex_index`).
pub fn parse_ply(path: &Path, bytes: &[u8]) -> Result<TriangleMesh, MeshReadError> {
    use ply_rs_bw::parser::Parser;
    use ply_rs_bw::ply::{DefaultElement, Property};
    let mut cursor = std::io::Cursor::new(bytes);
    let ply = Parser::<DefaultElement>::new()
        .read_ply(&mut cursor)
        // (ply-rs's message quotes the offending line and its parser's internals.)
        .map_err(|_| {
            malformed(
                path,
                None,
                "not a valid PLY file (a header from `ply` to `end_header` declaring its elements, then the data it declares)",
            )
        })?;
    let scalar = |p: Option<&Property>| -> Option<f64> {
        Some(match p? {
            Property::Float(v) => *v as f64,
            Property::Double(v) => *v,
            Property::Int(v) => *v as f64,
            Property::UInt(v) => *v as f64,
            Property::Short(v) => *v as f64,
            Property::UShort(v) => *v as f64,
            Property::Char(v) => *v as f64,
            Property::UChar(v) => *v as f64,
            _ => return None,
        })
    };
    let mut mesh = TriangleMesh {
        groups: vec!["default".into()],
        ..Default::default()
    };
    let vertices = ply
        .payload
        .get("vertex")
        .ok_or_else(|| malformed(path, None, "no `vertex` element"))?;
    for (i, v) in vertices.iter().enumerate() {
        let get = |k: &str| {
            scalar(v.get(k)).ok_or_else(|| malformed(path, None, format!("vertex {i}: missing or non-numeric `{k}`")))
        };
        let p = Vector3::new(get("x")?, get("y")?, get("z")?);
        if !p.iter().all(|c| c.is_finite()) {
            return Err(malformed(path, None, format!("vertex {i} has a non-finite coordinate")));
        }
        mesh.positions.push(p);
    }
    let nv = mesh.positions.len();
    let faces = ply
        .payload
        .get("face")
        .ok_or_else(|| malformed(path, None, "no `face` element"))?;
    for (i, f) in faces.iter().enumerate() {
        let list: Vec<i64> = match f.get("vertex_indices").or_else(|| f.get("vertex_index")) {
            Some(Property::ListInt(v)) => v.iter().map(|&x| x as i64).collect(),
            Some(Property::ListUInt(v)) => v.iter().map(|&x| x as i64).collect(),
            Some(Property::ListShort(v)) => v.iter().map(|&x| x as i64).collect(),
            Some(Property::ListUShort(v)) => v.iter().map(|&x| x as i64).collect(),
            Some(Property::ListUChar(v)) => v.iter().map(|&x| x as i64).collect(),
            Some(Property::ListChar(v)) => v.iter().map(|&x| x as i64).collect(),
            _ => {
                return Err(malformed(
                    path,
                    None,
                    format!("face {i}: no integer `vertex_indices` list"),
                ))
            }
        };
        if list.len() < 3 {
            return Err(malformed(
                path,
                None,
                format!("face {i} has {} vertices (needs 3)", list.len()),
            ));
        }
        if let Some(bad) = list.iter().find(|&&x| x < 0 || x as usize >= nv) {
            return Err(malformed(
                path,
                None,
                format!("face {i}: vertex index {bad} is out of range (0..{nv})"),
            ));
        }
        for j in 1..list.len() - 1 {
            mesh.triangles
                .push([list[0] as u32, list[j] as u32, list[j + 1] as u32]);
            mesh.face_groups.push(0);
        }
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p() -> &'static Path {
        Path::new("test.obj")
    }

    #[test]
    fn obj_with_groups_uvs_quads_and_negative_indices() {
        let m = parse_obj(p(), "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\ng a\nf 1/1 2/2 3/3 4/4\ng b\nf -4/-4 -2/-2 -1/-1\n").unwrap();
        assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3], [0, 2, 3]]);
        assert_eq!(m.face_groups, vec![0, 0, 1]);
        assert_eq!(m.groups, vec!["a", "b"]);
        assert_eq!(m.corner_uvs.as_ref().unwrap()[1][1], Vector2::new(1.0, 1.0));
    }

    #[test]
    fn obj_errors_name_the_line() {
        let e = parse_obj(p(), "v 0 0 0\nv 1 0 nan\n").unwrap_err().to_string();
        assert!(e.contains("test.obj:2") && e.contains("not finite"), "{e}");
        let e = parse_obj(p(), "v 0 0 0\nv 1 0 0\nf 1 2 5\n").unwrap_err().to_string();
        assert!(e.contains(":3") && e.contains("out of range"), "{e}");
        let e = parse_obj(p(), "v 0 0 0\nv 1 0 0\nf 1 2\n").unwrap_err().to_string();
        assert!(e.contains("at least 3"), "{e}");
        let e = parse_obj(p(), "v 0 x 0\n").unwrap_err().to_string();
        assert!(e.contains("`x` is not a number"), "{e}");
    }

    #[test]
    fn off_counts_are_checked() {
        let m = parse_off(Path::new("t.off"), "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").unwrap();
        assert_eq!(m.triangles.len(), 1);
        let e = parse_off(Path::new("t.off"), "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("expected 4 vertices"), "{e}");
        let e = parse_off(Path::new("t.off"), "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("out of range"), "{e}");
    }

    #[test]
    fn stl_and_ply_round_trip() {
        let stl = b"solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
        assert_eq!(parse_stl(Path::new("t.stl"), stl).unwrap().triangles.len(), 1);
        let ply = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
        let m = parse_ply(Path::new("t.ply"), ply).unwrap();
        assert_eq!(m.triangles, vec![[0, 1, 2]]);
        let bad = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n";
        assert!(parse_ply(Path::new("t.ply"), bad)
            .unwrap_err()
            .to_string()
            .contains("out of range"));
    }
}

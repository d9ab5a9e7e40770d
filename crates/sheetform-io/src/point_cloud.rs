//! Point clouds: `.xyz` text (three numbers per line) or ASCII/binary `.ply` (the
//! `vertex` element's `x y z`), e.g. a scan to fit a design to.

/// The points of a point-cloud file's bytes, told apart by the PLY magic: `.xyz` (three
/// numbers per line; `#` comments and blank lines skipped; extra columns such as normals
/// ignored; commas allowed as separators) or PLY.
///
/// # Errors
/// A message naming the line (text) or the missing property (PLY).
pub fn read_points(bytes: &[u8]) -> Result<Vec<[f64; 3]>, String> {
    if bytes.starts_with(b"ply") {
        read_ply(bytes)
    } else {
        read_xyz(bytes)
    }
}

fn read_xyz(bytes: &[u8]) -> Result<Vec<[f64; 3]>, String> {
    let text = std::str::from_utf8(bytes).map_err(|_| "not UTF-8 text (expected x y z per line)".to_string())?;
    let mut points = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let values: Vec<f64> = line
            .split(|c: char| c.is_whitespace() || c == ',')
            .filter(|s| !s.is_empty())
            .take(3)
            .map(|s| {
                s.parse::<f64>().map_err(|_| {
                    format!(
                        "line {}: `{}` is not a number",
                        n + 1,
                        sheetform_geometry::quoted_token(s)
                    )
                })
            })
            .collect::<Result<_, _>>()?;
        if values.len() < 3 {
            return Err(format!("line {}: expected three coordinates", n + 1));
        }
        points.push([values[0], values[1], values[2]]);
    }
    Ok(points)
}

fn read_ply(bytes: &[u8]) -> Result<Vec<[f64; 3]>, String> {
    use ply_rs_bw::parser::Parser;
    use ply_rs_bw::ply::{DefaultElement, Property};
    let mut reader = std::io::Cursor::new(bytes);
    let ply = Parser::<DefaultElement>::new()
        .read_ply(&mut reader)
        // (ply-rs's message quotes the offending line.)
        .map_err(|_| {
            "not a valid PLY file (a header from `ply` to `end_header`, then the data it declares)".to_string()
        })?;
    let vertices = ply.payload.get("vertex").ok_or("no `vertex` element")?;
    let value = |v: &DefaultElement, key: &str| -> Result<f64, String> {
        match v.get(key) {
            Some(Property::Float(x)) => Ok(f64::from(*x)),
            Some(Property::Double(x)) => Ok(*x),
            Some(Property::Int(x)) => Ok(f64::from(*x)),
            Some(Property::Short(x)) => Ok(f64::from(*x)),
            _ => Err(format!(
                "vertex property `{}` missing or not a number",
                sheetform_geometry::quoted_token(key)
            )),
        }
    };
    vertices
        .iter()
        .map(|v| Ok([value(v, "x")?, value(v, "y")?, value(v, "z")?]))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_xyz_and_ascii_ply_and_names_the_bad_line() {
        let xyz = b"# scan\n1 2 3\n\n4,5,6 0 0 1\n";
        assert_eq!(read_points(xyz).unwrap(), vec![[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]);
        let ply = b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n1.5 2 -3\n";
        assert_eq!(read_points(ply).unwrap(), vec![[0.0, 0.0, 0.0], [1.5, 2.0, -3.0]]);
        let bad = read_points(b"1 2 3\n1 x 3\n").unwrap_err();
        assert!(bad.contains("line 2"), "{bad}");
        assert!(read_points(b"1 2\n").unwrap_err().contains("three coordinates"));
    }
}

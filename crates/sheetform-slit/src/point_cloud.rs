//! Scanned points (§4.1): read from `.xyz` or `.ply`, searched with a k-d tree
//! (the `kiddo` crate) for the nearest point of Eq. 6.

use crate::SlitError;
use kiddo::{ImmutableKdTree, SquaredEuclidean};
use nalgebra::Vector3;

type Vec3 = Vector3<f64>;

/// A point cloud with a nearest-point index.
pub struct ScanCloud {
    points: Vec<[f64; 3]>,
    tree: ImmutableKdTree<f64, 3>,
}

impl std::fmt::Debug for ScanCloud {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ScanCloud").field("points", &self.points.len()).finish()
    }
}

impl ScanCloud {
    /// Indexes points.
    ///
    /// # Errors
    /// No points, or a non-finite coordinate (naming its index).
    pub fn new(points: Vec<[f64; 3]>) -> Result<Self, String> {
        if points.is_empty() {
            return Err("no points".into());
        }
        if let Some(i) = points.iter().position(|p| p.iter().any(|c| !c.is_finite())) {
            return Err(format!("point {i} has a non-finite coordinate"));
        }
        let tree = ImmutableKdTree::new_from_slice(&points).map_err(|e| format!("cannot index the points: {e:?}"))?;
        Ok(Self { points, tree })
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Whether there are no points (never, once built).
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// The scanned point nearest to `q`.
    pub fn nearest(&self, q: &Vec3) -> Vec3 {
        let hit = self
            .tree
            .query(&[q.x, q.y, q.z])
            .nearest_one::<SquaredEuclidean<f64>>()
            .execute();
        let p = self.points[hit.item as usize];
        Vec3::new(p[0], p[1], p[2])
    }

    /// Parses `.xyz` (three numbers per line; `#` comments and blank lines skipped; extra
    /// columns such as normals ignored) or ASCII/binary `.ply` (the `vertex` element's
    /// `x y z`), told apart by the PLY magic. The caller reads the file.
    ///
    /// # Errors
    /// [`SlitError::PointCloud`] naming `name` (the file as the scene names it) and, for
    /// text, the line.
    pub fn from_bytes(bytes: &[u8], name: &str) -> Result<Self, SlitError> {
        let fail = |message: String| SlitError::PointCloud {
            path: name.to_string(),
            message,
        };
        let points = if bytes.starts_with(b"ply") {
            read_ply(bytes).map_err(fail)?
        } else {
            read_xyz(bytes).map_err(fail)?
        };
        Self::new(points).map_err(fail)
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
                s.parse::<f64>()
                    .map_err(|_| format!("line {}: `{s}` is not a number", n + 1))
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
        .map_err(|e| format!("not a valid PLY file: {e}"))?;
    let vertices = ply.payload.get("vertex").ok_or("no `vertex` element")?;
    let value = |v: &DefaultElement, key: &str| -> Result<f64, String> {
        match v.get(key) {
            Some(Property::Float(x)) => Ok(f64::from(*x)),
            Some(Property::Double(x)) => Ok(*x),
            Some(Property::Int(x)) => Ok(f64::from(*x)),
            Some(Property::Short(x)) => Ok(f64::from(*x)),
            _ => Err(format!("vertex property `{key}` missing or not a number")),
        }
    };
    vertices
        .iter()
        .map(|v| Ok([value(v, "x")?, value(v, "y")?, value(v, "z")?]))
        .collect()
}

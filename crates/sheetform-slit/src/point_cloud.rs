//! Scanned points (§4.1), parsed by [`sheetform_io::read_points`] (`.xyz` or `.ply`) and
//! searched with a k-d tree (the `kiddo` crate) for the nearest point of Eq. 6.

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
        Self::new(sheetform_io::read_points(bytes).map_err(fail)?).map_err(fail)
    }
}

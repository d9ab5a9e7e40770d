//! Area-weighted vertex normals.

use nalgebra::Vector3;

type Vec3 = Vector3<f64>;

/// Unit normal of every vertex: the sum of its triangles' cross products
/// `(b − a) × (c − a)` (each twice the triangle's area times its unit normal), normalised;
/// zero for a vertex with no triangle or whose triangles cancel.
///
/// `triangles` may index any point set, e.g. the nodes of linked vertices, so a node
/// shared by several panels gets the normal of all its triangles.
pub fn area_weighted_normals(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<Vec3> {
    let mut normals = vec![Vec3::zeros(); positions.len()];
    for t in triangles {
        let [a, b, c] = t.map(|i| positions[i as usize]);
        let n = (b - a).cross(&(c - a));
        for &i in t {
            normals[i as usize] += n;
        }
    }
    for n in &mut normals {
        let len = n.norm();
        if len > 0.0 {
            *n /= len;
        }
    }
    normals
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A vertex between a horizontal and a vertical triangle of equal area gets the
    /// bisecting normal; an unused vertex gets zero.
    #[test]
    fn normals_are_area_weighted_and_unit() {
        let positions = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(5.0, 5.0, 5.0),
        ];
        let normals = area_weighted_normals(&positions, &[[0, 1, 2], [0, 3, 1]]);
        let expected = Vec3::new(0.0, 1.0, 1.0).normalize();
        assert!((normals[0] - expected).norm() < 1e-15);
        assert!((normals[2] - Vec3::z()).norm() < 1e-15);
        assert_eq!(normals[4], Vec3::zeros());
    }
}

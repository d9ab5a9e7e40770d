//! The largest fold angle of a panel mesh: how sharply the surface bends across an edge.

use nalgebra::Vector3;
use sheetform_mesh::EdgeTable;

type Vec3 = Vector3<f64>;

/// The largest angle between the unit normals of two triangles that share an edge
/// (radians, in `[0, π]`), over the interior edges of `triangles` (those with exactly
/// two triangles in `edges`, the table of `triangles`), with vertex `i` at
/// `position(i)`. Triangles of zero area are left out. On the welded panels
/// ([`crate::PanelAssembly::node_triangles`], as `run_design` reports it) the seams
/// between panels count too; on the panels' own triangles they are boundary edges.
///
/// `θ_e = atan2(|n₁ × n₂|, n₁ · n₂)`, `n₁`, `n₂` the normals of the triangles on edge `e`.
///
/// A smooth surface sampled with edges of length `h` has fold angles of about `κ h`
/// (`κ` its normal curvature across the edge), so a restored mesh should have fold
/// angles close to those of the deformed mesh it started from. A restoration that
/// reaches zero angle defect by folding the mesh into node-scale zig-zags (crinkles)
/// instead shows fold angles several times larger, whatever the resolution: the springs
/// alone (`bending_weight` 0) restore the skirt example with a largest fold angle of
/// 0.56 rad from the deformed mesh's 0.09 (docs/benchmarks.md). Not in the paper; a
/// measure of the result's fairness next to the deviation and the edge-length change,
/// neither of which sees crinkles.
pub fn fold_angle_max(triangles: &[[u32; 3]], edges: &EdgeTable, position: impl Fn(u32) -> Vec3) -> f64 {
    let normals: Vec<Option<Vec3>> = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(&position);
            (b - a).cross(&(c - a)).try_normalize(0.0)
        })
        .collect();
    (0..edges.len())
        .filter_map(|e| match edges.sides(e) {
            // Two triangles running the edge the same way are wound opposite ways (panels
            // sewn with opposite orientations): compare one normal turned round.
            [s, t] => {
                let (n1, n2) = (normals[s.face as usize]?, normals[t.face as usize]?);
                Some((n1, if s.forward == t.forward { -n2 } else { n2 }))
            }
            _ => None,
        })
        .map(|(n1, n2)| n1.cross(&n2).norm().atan2(n1.dot(&n2)))
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two unit right triangles hinged on the x axis, the second lifted by `angle`.
    fn hinge(angle: f64) -> f64 {
        let triangles = [[0, 1, 2], [1, 0, 3]];
        let points = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, -angle.cos(), angle.sin()),
        ];
        let edges = EdgeTable::new(&triangles, 4);
        fold_angle_max(&triangles, &edges, |i| points[i as usize])
    }

    #[test]
    fn a_hinge_folds_by_its_opening() {
        assert!(hinge(0.0).abs() < 1e-15);
        for angle in [0.1, 0.7, 1.5, 2.5] {
            assert!((hinge(angle) - angle).abs() < 1e-12, "{angle}: {}", hinge(angle));
        }
    }

    #[test]
    fn boundary_edges_and_degenerate_triangles_do_not_count() {
        // One triangle: no interior edge.
        let triangles = [[0, 1, 2]];
        let points = [Vec3::zeros(), Vec3::x(), Vec3::y()];
        let edges = EdgeTable::new(&triangles, 3);
        assert_eq!(fold_angle_max(&triangles, &edges, |i| points[i as usize]), 0.0);
        // A zero-area neighbour is left out.
        let triangles = [[0, 1, 2], [1, 0, 3]];
        let points = [Vec3::zeros(), Vec3::x(), Vec3::y(), Vec3::x() * 2.0];
        let edges = EdgeTable::new(&triangles, 4);
        assert_eq!(fold_angle_max(&triangles, &edges, |i| points[i as usize]), 0.0);
    }
}

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
/// 0.56 rad from the deformed mesh's 0.09 (docs/benchmarks-history.md). Not in the paper; a
/// measure of the result's fairness next to the deviation and the edge-length change,
/// neither of which sees crinkles.
pub fn fold_angle_max(triangles: &[[u32; 3]], edges: &EdgeTable, position: impl Fn(u32) -> Vec3) -> f64 {
    signed_fold_angles(triangles, edges, position)
        .into_iter()
        .flatten()
        .map(f64::abs)
        .fold(0.0, f64::max)
}

/// The largest change of the fold angle across one edge between two shapes of the same
/// mesh (radians, in `[0, π]`): `max_e |θ′_e − θ_e|` over the interior edges where both
/// shapes have two non-degenerate triangles, `θ_e` the *signed* fold angle (below), the
/// difference taken round the circle.
///
/// `θ_e = atan2((n₁ × n₂) · ê, n₁ · n₂)`, `ê` the unit edge vector in the direction the
/// first triangle runs it: positive where the surface turns one way across the edge,
/// negative the other, so a crease that flips from valley to mountain counts in full.
///
/// Where [`fold_angle_max`] is dominated by a fold the design has on purpose (the crotch
/// of the trousers example, 2.8 rad, where the four panels meet), this measures what the
/// restoration *added*: a crease where the deformed shape had none shows as a change of
/// tenths of a radian, a fair restoration changes each fold by little more than the
/// deformation's own curvature change across an edge. Not in the paper.
pub fn fold_angle_change_max(
    triangles: &[[u32; 3]],
    edges: &EdgeTable,
    before: impl Fn(u32) -> Vec3,
    after: impl Fn(u32) -> Vec3,
) -> f64 {
    fold_angle_figures(triangles, edges, before, after).change_max
}

/// The fold-angle figures of a restoration, each shape's fold angles computed once.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FoldAngleFigures {
    /// [`fold_angle_max`] of the first shape.
    pub max_before: f64,
    /// [`fold_angle_max`] of the second shape.
    pub max_after: f64,
    /// [`fold_angle_change_max`] from the first shape to the second.
    pub change_max: f64,
}

/// [`fold_angle_max`] of two shapes of the same mesh and [`fold_angle_change_max`]
/// between them (radians).
pub fn fold_angle_figures(
    triangles: &[[u32; 3]],
    edges: &EdgeTable,
    before: impl Fn(u32) -> Vec3,
    after: impl Fn(u32) -> Vec3,
) -> FoldAngleFigures {
    let before = signed_fold_angles(triangles, edges, before);
    let after = signed_fold_angles(triangles, edges, after);
    let largest = |angles: &[Option<f64>]| angles.iter().flatten().map(|a| a.abs()).fold(0.0, f64::max);
    FoldAngleFigures {
        max_before: largest(&before),
        max_after: largest(&after),
        change_max: before
            .iter()
            .zip(&after)
            .filter_map(|(&b, &a)| {
                let change = (a? - b?).rem_euclid(std::f64::consts::TAU);
                Some(change.min(std::f64::consts::TAU - change))
            })
            .fold(0.0, f64::max),
    }
}

/// The signed fold angle of each edge (see [`fold_angle_change_max`]); `None` on
/// boundary and non-manifold edges and where a triangle has zero area.
fn signed_fold_angles(triangles: &[[u32; 3]], edges: &EdgeTable, position: impl Fn(u32) -> Vec3) -> Vec<Option<f64>> {
    let normals: Vec<Option<Vec3>> = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(&position);
            (b - a).cross(&(c - a)).try_normalize(0.0)
        })
        .collect();
    (0..edges.len())
        .map(|e| match edges.sides(e) {
            // Two triangles running the edge the same way are wound opposite ways (panels
            // sewn with opposite orientations): compare one normal turned round.
            [s, t] => {
                let (n1, n2) = (normals[s.face as usize]?, normals[t.face as usize]?);
                let n2 = if s.forward == t.forward { -n2 } else { n2 };
                let [a, b] = edges.edges[e];
                let along = (position(b) - position(a)).try_normalize(0.0)?;
                let along = if s.forward { along } else { -along };
                Some(n1.cross(&n2).dot(&along).atan2(n1.dot(&n2)))
            }
            _ => None,
        })
        .collect()
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
    fn a_fold_that_flips_changes_by_twice_its_angle() {
        let triangles = [[0, 1, 2], [1, 0, 3]];
        let lifted = |angle: f64| {
            [
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
                Vec3::new(0.0, -angle.cos(), angle.sin()),
            ]
        };
        let edges = EdgeTable::new(&triangles, 4);
        let change = |from: f64, to: f64| {
            let (a, b) = (lifted(from), lifted(to));
            fold_angle_change_max(&triangles, &edges, |i| a[i as usize], |i| b[i as usize])
        };
        assert!(change(0.3, 0.3) < 1e-15);
        // The figures of both shapes at once: each shape's largest fold as alone.
        let (a, b) = (lifted(0.3), lifted(-1.2));
        let figures = fold_angle_figures(&triangles, &edges, |i| a[i as usize], |i| b[i as usize]);
        assert_eq!(
            figures.max_before,
            fold_angle_max(&triangles, &edges, |i| a[i as usize])
        );
        assert_eq!(figures.max_after, fold_angle_max(&triangles, &edges, |i| b[i as usize]));
        assert!((figures.change_max - 1.5).abs() < 1e-12);
        assert!((change(0.3, 0.5) - 0.2).abs() < 1e-12);
        // Mountain to valley by the same angle: unsigned it would not change at all.
        assert!((change(0.3, -0.3) - 0.6).abs() < 1e-12, "{}", change(0.3, -0.3));
        // Across ±π the change is the short way round.
        assert!((change(3.1, -3.1) - (std::f64::consts::TAU - 6.2)).abs() < 1e-12);
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

//! Choosing how a mesh becomes a pattern: flattened whole, cut into smooth charts, or
//! unfolded into a net of its facets.

use crate::MAX_CONE_POINTS;
use sheetform_mesh::{vertex_developability, EdgeTable, MeshTopology, TriangleMesh};

/// How a mesh is laid out in the plane.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Layout {
    /// The mesh in one piece as it is (a developable disk).
    Whole,
    /// Smooth charts: cut along sharp creases, user seams and straight seams through cone
    /// points, split until each chart flattens within the distortion bound.
    Charts,
    /// A net: the facets unfolded edge by edge, exact, folded along the kept edges.
    Net,
}

/// The automatic choice and why.
#[derive(Debug, Clone, PartialEq)]
pub struct LayoutChoice {
    /// The layout.
    pub layout: Layout,
    /// Why, in a sentence (for the report).
    pub reason: String,
}

/// An interior vertex whose angle defect exceeds this (radians) is not developable: a cone
/// point of a developable surface or a point of a curved one.
pub const CONE_POINT_DEFECT: f64 = 1e-4;

/// Folds at least this large (degrees) make a mesh faceted: its typical fold is one a
/// maker creases, not the faint bend of a finely meshed smooth surface.
pub const FACETED_FOLD_DEGREES: f64 = 5.0;

/// Picks the layout a maker would expect for `mesh` (what `flatten --charts auto` does):
///
/// 1. **Whole** when the mesh is a disk without user seams whose interior vertices are
///    all developable (angle defect at most [`CONE_POINT_DEFECT`]): it unfolds exactly
///    as it is.
/// 2. **Charts** when it is developable apart from at most [`MAX_CONE_POINTS`] cone points
///    and has no sharp crease (a dihedral angle above `crease_angle_degrees`), or has user
///    seams and no cone point: an open tube or cone, a bent sheet with seams. The charts
///    are opened along straight seams and stay exact.
/// 3. **Net** when it is faceted (and of at most [`crate::MAX_NET_FACES`] faces): the median fold angle over its folded edges (at least
///    1°) is [`FACETED_FOLD_DEGREES`] or more, or it has sharp creases and curved
///    vertices — a box, a low-poly model, an icosphere. Papercraft tools (Pepakura,
///    Blender's Export Paper Model) always unfold such models into nets.
/// 4. **Charts** otherwise: a finely meshed curved surface (a scanned shape, a dome),
///    split until every chart is within the distortion bound.
///
/// `topology` is `mesh`'s ([`sheetform_mesh::mesh_topology`]): the caller has it already.
pub fn choose_layout(mesh: &TriangleMesh, topology: &MeshTopology, crease_angle_degrees: f64) -> LayoutChoice {
    let defects = vertex_developability(mesh, topology).angle_defect;
    let curved = defects.iter().filter(|d| d.abs() > CONE_POINT_DEFECT).count();
    let disk = topology.component_count == 1 && topology.boundary_loop_count == 1 && topology.euler_characteristic == 1;
    let seams = !mesh.seam_edges.is_empty();
    if disk && !seams && curved == 0 {
        return LayoutChoice {
            layout: Layout::Whole,
            reason: "a developable disk: unfolded whole".into(),
        };
    }
    // The folds, only when the mesh is not a developable disk.
    let table = EdgeTable::new(&mesh.triangles, mesh.positions.len());
    let mut folds: Vec<f64> = mesh
        .dihedral_angles(&table)
        .into_iter()
        .map(f64::to_degrees)
        .filter(|&a| a >= 1.0)
        .collect();
    let sharp = folds.iter().any(|&a| a > crease_angle_degrees);
    if (curved <= MAX_CONE_POINTS && !sharp) || (seams && curved == 0) {
        return LayoutChoice {
            layout: Layout::Charts,
            reason: format!(
                "developable apart from {curved} cone point(s), no sharp crease: cut open along straight seams"
            ),
        };
    }
    folds.sort_by(f64::total_cmp);
    let median = folds.get(folds.len() / 2).copied().unwrap_or(0.0);
    let faceted = median >= FACETED_FOLD_DEGREES || (sharp && curved > 0 && median >= 1.0);
    if faceted && mesh.triangles.len() > crate::MAX_NET_FACES {
        return LayoutChoice {
            layout: Layout::Charts,
            reason: format!(
                "faceted (median fold {median:.1}°) but of {} faces, more than a net is made of ({}): split into charts within the distortion bound",
                mesh.triangles.len(),
                crate::MAX_NET_FACES
            ),
        };
    }
    if faceted {
        return LayoutChoice {
            layout: Layout::Net,
            reason: format!(
                "faceted ({curved} curved vertices, median fold {median:.1}°): unfolded into a net of exact facets"
            ),
        };
    }
    LayoutChoice {
        layout: Layout::Charts,
        reason: format!(
            "a finely meshed curved surface ({curved} curved vertices, median fold {median:.1}°): split into charts within the distortion bound"
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sheetform_mesh::primitives;

    #[test]
    fn the_choice_follows_the_shape() {
        let layout = |m: &TriangleMesh| choose_layout(m, &sheetform_mesh::mesh_topology(m), 30.0).layout;
        assert_eq!(
            layout(&TriangleMesh::grid(8, 8, |u, v| [u, v, 0.3 * u * u])),
            Layout::Whole
        );
        assert_eq!(layout(&primitives::cylinder(1.0, 2.0, 32, false)), Layout::Charts);
        assert_eq!(layout(&primitives::cone(1.0, 2.0, 32, false)), Layout::Charts);
        for m in [
            primitives::cuboid([1.0, 2.0, 3.0]),
            primitives::icosphere(1.0, 2),
            primitives::torus(2.0, 0.7, 32, 16),
            primitives::cylinder(1.0, 2.0, 32, true),
            primitives::hemisphere(1.0, 8, 32),
        ] {
            assert_eq!(layout(&m), Layout::Net, "{}", m.groups[0]);
        }
        // A finely meshed dome bends by less than a degree per edge: smooth charts.
        assert_eq!(layout(&primitives::icosphere(1.0, 5)), Layout::Charts);
    }
}

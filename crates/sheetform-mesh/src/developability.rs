use crate::{MeshTopology, TriangleMesh};
use std::f64::consts::TAU;

/// Per-vertex developability of a triangle mesh (Wang & Tang 2004, §2.2).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct VertexDevelopability {
    /// Angle sum `Σ_j θ_j` of the triangle corners at each vertex (radians).
    pub angle_sum: Vec<f64>,
    /// Angle defect `g(q_i) = 2π − Σ_j θ_j` for interior vertices, 0 on the boundary
    /// (Eq. 2-4) (radians).
    pub angle_defect: Vec<f64>,
    /// Discrete Gaussian curvature `κ(q_i) = (2π − Σ_j θ_j) / ((1/3) Σ_j A_j)`
    /// (Eq. 2-1), 0 on the boundary (1/length²).
    pub gaussian_curvature: Vec<f64>,
    /// Vertex area `A_qi = (1/3) Σ_j A_j` (length²).
    pub vertex_area: Vec<f64>,
}

/// Whole-mesh developability figures.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct DevelopabilitySummary {
    /// Interior vertices measured.
    pub interior_vertex_count: usize,
    /// Largest |angle defect| over interior vertices.
    pub angle_defect_max_rad: f64,
    /// Mean |angle defect|.
    pub angle_defect_mean_rad: f64,
    /// Root mean square angle defect.
    pub angle_defect_rms_rad: f64,
    /// Interior vertices whose |angle defect| exceeds the tolerance.
    pub vertices_over_tolerance: usize,
    /// The tolerance used (radians).
    pub tolerance_rad: f64,
    /// Largest |Gaussian curvature| (Eq. 2-1).
    pub gaussian_curvature_max_per_length2: f64,
    /// `D[M] = (1/A) Σ_i δ(2π − θ_sum(q_i)) A_qi` (Definition 2-1), with `δ(t) = 1` for
    /// `|t| ≤ tolerance` (the paper's impulse needs a tolerance in floating point).
    /// 1: every interior vertex developable.
    pub developability_d: f64,
    /// `G[X] = Σ_i g(q_i)²` (Eq. 2-5) (radians²).
    pub developability_g: f64,
}

/// Angle sums, defects, Gaussian curvature and vertex areas (boundary vertices get zero
/// defect and curvature, as in Eq. 2-4).
pub fn vertex_developability(mesh: &TriangleMesh, topology: &MeshTopology) -> VertexDevelopability {
    let n = mesh.positions.len();
    let mut out = VertexDevelopability {
        angle_sum: crate::vertex_angle_sums(&mesh.positions, &mesh.triangles),
        angle_defect: vec![0.0; n],
        gaussian_curvature: vec![0.0; n],
        vertex_area: vec![0.0; n],
    };
    for (f, t) in mesh.triangles.iter().enumerate() {
        let area = mesh.face_area(f);
        for &i in t {
            out.vertex_area[i as usize] += area / 3.0;
        }
    }
    for i in 0..n {
        let used = out.vertex_area[i] > 0.0 || out.angle_sum[i] > 0.0;
        if used && !topology.boundary_vertex[i] {
            out.angle_defect[i] = TAU - out.angle_sum[i];
            if out.vertex_area[i] > 0.0 {
                out.gaussian_curvature[i] = out.angle_defect[i] / out.vertex_area[i];
            }
        }
    }
    out
}

/// Summary statistics over interior vertices; `tolerance` (radians) for the count and for
/// `D[M]`.
pub fn developability_summary(
    mesh: &TriangleMesh,
    topology: &MeshTopology,
    vertices: &VertexDevelopability,
    tolerance: f64,
) -> DevelopabilitySummary {
    let mut s = DevelopabilitySummary {
        tolerance_rad: tolerance,
        ..Default::default()
    };
    let total_area: f64 = (0..mesh.triangles.len()).map(|f| mesh.face_area(f)).sum();
    let mut sum = 0.0;
    let mut sum2 = 0.0;
    let mut developable_area = 0.0;
    for i in 0..mesh.positions.len() {
        if vertices.vertex_area[i] == 0.0 && vertices.angle_sum[i] == 0.0 {
            continue;
        }
        let g = vertices.angle_defect[i];
        if topology.boundary_vertex[i] || g.abs() <= tolerance {
            developable_area += vertices.vertex_area[i];
        }
        if topology.boundary_vertex[i] {
            continue;
        }
        s.interior_vertex_count += 1;
        s.angle_defect_max_rad = s.angle_defect_max_rad.max(g.abs());
        s.gaussian_curvature_max_per_length2 = s
            .gaussian_curvature_max_per_length2
            .max(vertices.gaussian_curvature[i].abs());
        sum += g.abs();
        sum2 += g * g;
        if g.abs() > tolerance {
            s.vertices_over_tolerance += 1;
        }
    }
    if s.interior_vertex_count > 0 {
        s.angle_defect_mean_rad = sum / s.interior_vertex_count as f64;
        s.angle_defect_rms_rad = (sum2 / s.interior_vertex_count as f64).sqrt();
    }
    s.developability_g = sum2;
    s.developability_d = if total_area > 0.0 {
        developable_area / total_area
    } else {
        0.0
    };
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh_topology;

    #[test]
    fn cylinder_is_developable_and_a_dome_is_not() {
        let cylinder = TriangleMesh::grid(20, 20, |u, v| [(2.0 * u).cos(), (2.0 * u).sin(), 3.0 * v]);
        let t = mesh_topology(&cylinder);
        let s = developability_summary(&cylinder, &t, &vertex_developability(&cylinder, &t), 1e-10);
        assert!(s.angle_defect_max_rad < 1e-12, "{s:?}");
        assert!((s.developability_d - 1.0).abs() < 1e-12);
        let dome = TriangleMesh::grid(20, 20, |u, v| {
            let (x, y) = (u - 0.5, v - 0.5);
            [x, y, 1.0 - x * x - y * y]
        });
        let t = mesh_topology(&dome);
        let v = vertex_developability(&dome, &t);
        let s = developability_summary(&dome, &t, &v, 1e-10);
        // Paraboloid z = 1 − r²: Gaussian curvature 4 at the apex (1/length²).
        let centre = 10 * 21 + 10;
        assert!(
            (v.gaussian_curvature[centre] - 4.0).abs() < 0.1,
            "{}",
            v.gaussian_curvature[centre]
        );
        // Every interior vertex is curved; D[M] is then the boundary vertices' area share
        // (θ_sum := 2π there, Definition 2-1).
        assert_eq!(s.vertices_over_tolerance, s.interior_vertex_count);
        assert!(
            s.developability_d > 0.0 && s.developability_d < 0.3 && s.developability_g > 0.0,
            "{s:?}"
        );
    }
}

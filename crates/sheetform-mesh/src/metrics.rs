use crate::SheetMesh;
use nalgebra::Vector3;

/// How far the 3D mesh is from an isometric image of its flat pattern.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct IsometryError {
    /// `max_e | |e_3D| − |e_flat| | / |e_flat|` over all edges.
    pub max_relative: f64,
    /// Mean of the same relative difference.
    pub mean_relative: f64,
    /// The edge where the maximum occurs (vertex indices).
    pub worst_edge: [u32; 2],
    /// Number of edges measured.
    pub edge_count: usize,
}

/// Relative edge-length difference between the 3D mesh and its flat pattern, per edge:
/// `| |x_i − x_j| − |u_i − u_j| | / |u_i − u_j|` (x: 3D, u: flat). Zero for an exact
/// isometry; edges of zero flat length are skipped.
pub fn isometry_error(mesh: &SheetMesh) -> IsometryError {
    let mut out = IsometryError::default();
    let mut sum = 0.0;
    for [a, b] in mesh.edges() {
        let (i, j) = (a as usize, b as usize);
        let flat = (mesh.flat[i] - mesh.flat[j]).norm();
        if flat <= 0.0 {
            continue;
        }
        let space = (mesh.positions[i] - mesh.positions[j]).norm();
        let rel = (space - flat).abs() / flat;
        sum += rel;
        out.edge_count += 1;
        if rel > out.max_relative || out.edge_count == 1 {
            out.max_relative = out.max_relative.max(rel);
            if rel >= out.max_relative {
                out.worst_edge = [a, b];
            }
        }
    }
    if out.edge_count > 0 {
        out.mean_relative = sum / out.edge_count as f64;
    }
    out
}

/// Twist along the rulings: for every ruling, the angle between the surface normals at
/// its two ends, taken on each side of the ruling (the faces that share its first and its
/// last edge on that side). Zero on an exact developable, whose normal is constant along
/// every ruling (Bo & Wang 2007, §3.1).
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct RulingNormalError {
    /// Largest angle (radians) over all rulings.
    pub max_radians: f64,
    /// Mean over the rulings measured.
    pub mean_radians: f64,
    /// Number of rulings measured.
    pub ruling_count: usize,
}

/// See [`RulingNormalError`].
pub fn developability_error(mesh: &SheetMesh) -> RulingNormalError {
    let edges = mesh.edge_table();
    let mut out = RulingNormalError::default();
    let mut sum = 0.0;
    let side_of = |f: u32, a: u32, b: u32| -> f64 {
        // Which side of the directed ruling edge a→b the face's third vertex lies on,
        // in the flat pattern.
        let t = mesh.triangles[f as usize];
        let c = *t
            .iter()
            .find(|&&v| v != a && v != b)
            .expect("triangle has a third vertex");
        let (pa, pb, pc) = (mesh.flat[a as usize], mesh.flat[b as usize], mesh.flat[c as usize]);
        let (u, w) = (pb - pa, pc - pa);
        u.x * w.y - u.y * w.x
    };
    for r in &mesh.rulings {
        if r.vertices.len() < 2 {
            continue;
        }
        let first = [r.vertices[0], r.vertices[1]];
        let last = [r.vertices[r.vertices.len() - 2], r.vertices[r.vertices.len() - 1]];
        let faces_of = |[a, b]: [u32; 2]| edges.faces_of(a, b).collect::<Vec<u32>>();
        let mut worst: Option<f64> = None;
        for side in [1.0, -1.0] {
            let pick = |e: [u32; 2]| faces_of(e).into_iter().find(|&f| side_of(f, e[0], e[1]) * side > 0.0);
            if let (Some(f0), Some(f1)) = (pick(first), pick(last)) {
                let (n0, n1): (Vector3<f64>, Vector3<f64>) =
                    (mesh.face_normal(f0 as usize), mesh.face_normal(f1 as usize));
                let angle = n0.cross(&n1).norm().atan2(n0.dot(&n1));
                worst = Some(worst.map_or(angle, |w: f64| w.max(angle)));
            }
        }
        if let Some(w) = worst {
            out.max_radians = out.max_radians.max(w);
            sum += w;
            out.ruling_count += 1;
        }
    }
    if out.ruling_count > 0 {
        out.mean_radians = sum / out.ruling_count as f64;
    }
    out
}

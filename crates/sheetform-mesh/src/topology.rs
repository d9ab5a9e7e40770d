use crate::TriangleMesh;
use rustc_hash::FxHashMap as HashMap;

/// The combinatorial structure of a triangle mesh and everything wrong with it.
///
/// Nothing here fails: problems are listed so that `check` can report them and the
/// methods that need a clean mesh (flattening) can refuse with a message naming them.
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize)]
pub struct MeshTopology {
    /// Vertices on the boundary (an incident edge with one face).
    #[serde(skip)]
    pub boundary_vertex: Vec<bool>,
    /// Number of boundary edges.
    pub boundary_edge_count: usize,
    /// Number of boundary loops.
    pub boundary_loop_count: usize,
    /// Edges with more than two faces.
    pub non_manifold_edges: Vec<[u32; 2]>,
    /// Vertices whose faces form more than one fan (pinched).
    pub non_manifold_vertices: Vec<u32>,
    /// Vertices used by no face.
    pub isolated_vertices: Vec<u32>,
    /// Faces with a repeated vertex or (numerically) zero area.
    pub degenerate_faces: Vec<u32>,
    /// Whether the faces can be oriented consistently (false for a Möbius strip), and
    /// are: neighbouring faces traverse their shared edge in opposite directions.
    pub orientable: bool,
    /// Whether the orientation as stored is consistent.
    pub consistently_oriented: bool,
    /// Connected components (by shared edges).
    pub component_count: usize,
    /// Euler characteristic `V − E + F` (over used vertices).
    pub euler_characteristic: i64,
}

impl MeshTopology {
    /// Whether the mesh is a clean 2-manifold (with boundary) without degenerate faces.
    pub fn is_clean(&self) -> bool {
        self.non_manifold_edges.is_empty()
            && self.non_manifold_vertices.is_empty()
            && self.degenerate_faces.is_empty()
            && self.orientable
    }
}

/// Analyses the topology of `mesh`. Degenerate faces are those with a repeated vertex or
/// an area below `1e-14 · scale²`.
pub fn mesh_topology(mesh: &TriangleMesh) -> MeshTopology {
    let nv = mesh.positions.len();
    let scale = mesh.scale();
    let mut out = MeshTopology {
        boundary_vertex: vec![false; nv],
        ..Default::default()
    };
    // Directed edge → face, undirected edge → faces.
    let mut edges: HashMap<[u32; 2], Vec<(u32, bool)>> =
        HashMap::with_capacity_and_hasher(mesh.triangles.len() * 2, Default::default());
    let mut used = vec![false; nv];
    for (f, t) in mesh.triangles.iter().enumerate() {
        if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || mesh.face_area(f) <= 1e-14 * scale * scale {
            out.degenerate_faces.push(f as u32);
        }
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            used[a as usize] = true;
            if a == b {
                continue;
            }
            let (key, forward) = if a < b { ([a, b], true) } else { ([b, a], false) };
            edges.entry(key).or_default().push((f as u32, forward));
        }
    }
    let mut vertex_faces: Vec<Vec<u32>> = vec![Vec::new(); nv];
    for (f, t) in mesh.triangles.iter().enumerate() {
        for &v in t {
            if vertex_faces[v as usize].last() != Some(&(f as u32)) {
                vertex_faces[v as usize].push(f as u32);
            }
        }
    }
    out.isolated_vertices = (0..nv as u32).filter(|&v| !used[v as usize]).collect();
    // Face adjacency through manifold edges; orientation by BFS.
    let nf = mesh.triangles.len();
    let mut neighbours: Vec<Vec<(u32, bool)>> = vec![Vec::new(); nf];
    let mut consistent = true;
    let mut boundary_next: HashMap<u32, Vec<u32>> = HashMap::default();
    for (key, faces) in &edges {
        match faces.len() {
            1 => {
                out.boundary_edge_count += 1;
                out.boundary_vertex[key[0] as usize] = true;
                out.boundary_vertex[key[1] as usize] = true;
                boundary_next.entry(key[0]).or_default().push(key[1]);
                boundary_next.entry(key[1]).or_default().push(key[0]);
            }
            2 => {
                let ((f0, d0), (f1, d1)) = (faces[0], faces[1]);
                // Consistent orientation: the two faces use the edge in opposite directions.
                let same = d0 == d1;
                if same {
                    consistent = false;
                }
                neighbours[f0 as usize].push((f1, same));
                neighbours[f1 as usize].push((f0, same));
            }
            _ => out.non_manifold_edges.push(*key),
        }
    }
    out.non_manifold_edges.sort_unstable();
    out.consistently_oriented = consistent;
    // Orientability: 2-colour the "flip" relation.
    let mut flip: Vec<Option<bool>> = vec![None; nf];
    out.orientable = true;
    for start in 0..nf {
        if flip[start].is_some() {
            continue;
        }
        out.component_count += 1;
        flip[start] = Some(false);
        let mut stack = vec![start];
        while let Some(f) = stack.pop() {
            let ff = flip[f].expect("set");
            for &(g, same) in &neighbours[f] {
                let want = ff ^ same;
                match flip[g as usize] {
                    None => {
                        flip[g as usize] = Some(want);
                        stack.push(g as usize);
                    }
                    Some(x) if x != want => out.orientable = false,
                    _ => {}
                }
            }
        }
    }
    // Non-manifold vertices: the faces around a vertex must form one fan (connected
    // through edges at that vertex).
    for (v, faces) in vertex_faces.iter().enumerate() {
        if faces.len() < 2 {
            continue;
        }
        let mut seen = vec![false; faces.len()];
        let mut stack = vec![0usize];
        seen[0] = true;
        while let Some(i) = stack.pop() {
            let ti = mesh.triangles[faces[i] as usize];
            for (j, &g) in faces.iter().enumerate() {
                if !seen[j] {
                    let tj = mesh.triangles[g as usize];
                    let shared = ti.iter().filter(|&&a| a != v as u32 && tj.contains(&a)).count();
                    if shared > 0 {
                        seen[j] = true;
                        stack.push(j);
                    }
                }
            }
        }
        if seen.iter().any(|s| !s) {
            out.non_manifold_vertices.push(v as u32);
        }
    }
    // Boundary loops (count components of the boundary graph).
    let mut visited: std::collections::HashSet<u32> = std::collections::HashSet::new();
    for &v in boundary_next.keys() {
        if visited.insert(v) {
            out.boundary_loop_count += 1;
            let mut stack = vec![v];
            while let Some(x) = stack.pop() {
                for &y in &boundary_next[&x] {
                    if visited.insert(y) {
                        stack.push(y);
                    }
                }
            }
        }
    }
    let used_count = used.iter().filter(|&&u| u).count() as i64;
    out.euler_characteristic = used_count - edges.len() as i64 + nf as i64;
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    fn mesh(positions: Vec<[f64; 3]>, triangles: Vec<[u32; 3]>) -> TriangleMesh {
        let n = triangles.len();
        TriangleMesh {
            positions: positions.into_iter().map(Vector3::from).collect(),
            triangles,
            face_groups: vec![0; n],
            groups: vec!["g".into()],
            corner_uvs: None,
            seam_edges: Vec::new(),
        }
    }

    /// A Möbius strip: a band of `n` quads whose ends are glued with a half twist.
    fn mobius(n: usize) -> TriangleMesh {
        let mut p = Vec::new();
        for i in 0..n {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            for s in [-1.0, 1.0] {
                let (r, z) = (3.0 + s * (a / 2.0).cos(), s * (a / 2.0).sin());
                p.push([r * a.cos(), r * a.sin(), z]);
            }
        }
        let mut t = Vec::new();
        for i in 0..n {
            let (a0, a1) = (2 * i as u32, 2 * i as u32 + 1);
            let (b0, b1) = if i + 1 < n {
                (2 * (i + 1) as u32, 2 * (i + 1) as u32 + 1)
            } else {
                (1, 0)
            };
            t.push([a0, b0, a1]);
            t.push([a1, b0, b1]);
        }
        mesh(p, t)
    }

    #[test]
    fn mobius_strip_is_not_orientable() {
        let m = mobius(24);
        let t = mesh_topology(&m);
        assert!(!t.orientable);
        assert!(!t.is_clean());
        assert_eq!(t.boundary_loop_count, 1);
    }

    #[test]
    fn non_manifold_edge_and_pinched_vertex_are_reported() {
        // Three triangles on one edge.
        let fin = mesh(
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.5, 1.0, 0.0],
                [0.5, -1.0, 0.0],
                [0.5, 0.0, 1.0],
            ],
            vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]],
        );
        assert_eq!(mesh_topology(&fin).non_manifold_edges, vec![[0, 1]]);
        // Two triangles touching at one vertex only.
        let bow = mesh(
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [-1.0, 0.0, 0.0],
                [-1.0, -1.0, 0.0],
            ],
            vec![[0, 1, 2], [0, 3, 4]],
        );
        assert_eq!(mesh_topology(&bow).non_manifold_vertices, vec![0]);
        // A zero-area face.
        let flat = mesh(
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            vec![[0, 1, 2], [0, 1, 3]],
        );
        assert_eq!(mesh_topology(&flat).degenerate_faces, vec![0]);
    }

    #[test]
    fn welding_merges_duplicates_and_drops_collapsed_faces() {
        let mut m = mesh(
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [1.0, 0.0, 1e-9],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
            ],
            vec![[0, 1, 2], [3, 4, 5], [0, 3, 1]],
        );
        assert_eq!(m.weld(1e-6), 2);
        assert_eq!(m.triangles, vec![[0, 1, 2], [1, 3, 2]]);
        assert_eq!(mesh_topology(&m).boundary_loop_count, 1);
    }
}

use crate::EdgeTable;
use crate::TriangleMesh;
use crate::UnionFind;

/// The combinatorial structure of a triangle mesh and everything wrong with it.
///
/// Nothing here fails: problems are listed so that `check` can report them and the
/// methods that need a clean mesh (flattening) can refuse with a message naming them.
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
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

    /// What keeps the mesh from being a clean 2-manifold, one phrase per kind of
    /// problem with the first place (empty for a clean mesh).
    pub fn problems(&self) -> Vec<String> {
        let mut problems = Vec::new();
        if !self.non_manifold_edges.is_empty() {
            problems.push(format!(
                "{} non-manifold edge(s), first {:?}",
                self.non_manifold_edges.len(),
                self.non_manifold_edges[0]
            ));
        }
        if !self.non_manifold_vertices.is_empty() {
            problems.push(format!(
                "{} non-manifold vertex/vertices, first {}",
                self.non_manifold_vertices.len(),
                self.non_manifold_vertices[0]
            ));
        }
        if !self.degenerate_faces.is_empty() {
            problems.push(format!(
                "{} degenerate (zero-area) face(s), first {}",
                self.degenerate_faces.len(),
                self.degenerate_faces[0]
            ));
        }
        if !self.orientable {
            problems.push("the surface is not orientable".into());
        }
        problems
    }
}

/// Analyses the topology of `mesh`. Degenerate faces are those with a repeated vertex or
/// an area below `1e-14 · scale²`.
///
/// Linear in the size of the mesh: the edges come from an [`EdgeTable`] (a counting sort,
/// no hash map), faces around a vertex from a counting sort as well, and boundary loops
/// from a union–find over the boundary edges.
pub fn mesh_topology(mesh: &TriangleMesh) -> MeshTopology {
    mesh_topology_with_edges(mesh).0
}

/// [`mesh_topology`] and the [`EdgeTable`] it was computed from, for callers that need
/// the edges too (exact unfolding), so the table is built once.
pub fn mesh_topology_with_edges(mesh: &TriangleMesh) -> (MeshTopology, EdgeTable) {
    let nv = mesh.positions.len();
    let nf = mesh.triangles.len();
    let scale = mesh.scale();
    let mut out = MeshTopology {
        boundary_vertex: vec![false; nv],
        ..Default::default()
    };
    let table = EdgeTable::new(&mesh.triangles, nv);
    let mut used = vec![false; nv];
    for (f, t) in mesh.triangles.iter().enumerate() {
        if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || mesh.face_area(f) <= 1e-14 * scale * scale {
            out.degenerate_faces.push(f as u32);
        }
        for &v in t {
            used[v as usize] = true;
        }
    }
    out.isolated_vertices = (0..nv as u32).filter(|&v| !used[v as usize]).collect();
    // Face adjacency through manifold edges (at most one neighbour per edge), and whether
    // the two faces on each such edge traverse it in the same direction.
    const NONE: u32 = u32::MAX;
    let mut neighbours = vec![[(NONE, false); 3]; nf];
    let mut consistent = true;
    let mut boundary = UnionFind::new(nv);
    for (e, &[a, b]) in table.edges.iter().enumerate() {
        match table.sides(e) {
            [_] => {
                out.boundary_edge_count += 1;
                out.boundary_vertex[a as usize] = true;
                out.boundary_vertex[b as usize] = true;
                boundary.union(a, b);
            }
            [s0, s1] => {
                // Consistent orientation: the two faces use the edge in opposite directions.
                let same = s0.forward == s1.forward;
                if same {
                    consistent = false;
                }
                for (s, other) in [(s0, s1), (s1, s0)] {
                    let k = (0..3)
                        .find(|&k| table.face_edges[s.face as usize][k] == e as u32)
                        .expect("the face has this edge");
                    neighbours[s.face as usize][k] = (other.face, same);
                }
            }
            _ => out.non_manifold_edges.push([a, b]),
        }
    }
    out.consistently_oriented = consistent;
    // Orientability: 2-colour the "flip" relation.
    let mut flip: Vec<Option<bool>> = vec![None; nf];
    out.orientable = true;
    let mut stack = Vec::new();
    for start in 0..nf {
        if flip[start].is_some() {
            continue;
        }
        out.component_count += 1;
        flip[start] = Some(false);
        stack.push(start);
        while let Some(f) = stack.pop() {
            let ff = flip[f].expect("set");
            for &(g, same) in &neighbours[f] {
                if g == NONE {
                    continue;
                }
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
    // Faces around each vertex (counting sort), each face once per vertex.
    let mut fan_start = vec![0u32; nv + 1];
    for t in &mesh.triangles {
        for (k, &v) in t.iter().enumerate() {
            if !t[..k].contains(&v) {
                fan_start[v as usize + 1] += 1;
            }
        }
    }
    for v in 0..nv {
        fan_start[v + 1] += fan_start[v];
    }
    let mut fan = vec![0u32; fan_start[nv] as usize];
    let mut fill = fan_start.clone();
    for (f, t) in mesh.triangles.iter().enumerate() {
        for (k, &v) in t.iter().enumerate() {
            if !t[..k].contains(&v) {
                fan[fill[v as usize] as usize] = f as u32;
                fill[v as usize] += 1;
            }
        }
    }
    // Non-manifold vertices: the faces around a vertex must form one fan (connected
    // through edges at that vertex). Two faces of the fan share such an edge when they
    // share their other end `a`: sort the (a, face) pairs and join runs of equal `a` in a
    // union-find over the fan, O(k log k) for k faces (comparing every pair was O(k²): a
    // 100k-face fan took 10 s).
    let mut ends: Vec<(u32, u32)> = Vec::new();
    let mut parent: Vec<u32> = Vec::new();
    fn root(parent: &mut [u32], mut i: u32) -> u32 {
        while parent[i as usize] != i {
            parent[i as usize] = parent[parent[i as usize] as usize];
            i = parent[i as usize];
        }
        i
    }
    for v in 0..nv {
        let faces = &fan[fan_start[v] as usize..fan_start[v + 1] as usize];
        if faces.len() < 2 {
            continue;
        }
        ends.clear();
        for (i, &f) in faces.iter().enumerate() {
            for &a in &mesh.triangles[f as usize] {
                if a != v as u32 {
                    ends.push((a, i as u32));
                }
            }
        }
        ends.sort_unstable();
        parent.clear();
        parent.extend(0..faces.len() as u32);
        let mut sets = faces.len();
        for pair in ends.windows(2) {
            if pair[0].0 == pair[1].0 {
                let (x, y) = (root(&mut parent, pair[0].1), root(&mut parent, pair[1].1));
                if x != y {
                    parent[x as usize] = y;
                    sets -= 1;
                }
            }
        }
        if sets > 1 {
            out.non_manifold_vertices.push(v as u32);
        }
    }
    // Boundary loops: components of the boundary graph.
    out.boundary_loop_count = (0..nv as u32)
        .filter(|&v| out.boundary_vertex[v as usize] && boundary.find(v) == v)
        .count();
    let used_count = used.iter().filter(|&&u| u).count() as i64;
    out.euler_characteristic = used_count - table.len() as i64 + nf as i64;
    (out, table)
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
        // Issue 19: a fan of 100 000 faces around one vertex (was O(k²), 10 s), then a
        // second fan at the same vertex (two cones touching at their apex).
        let k = 100_000;
        let mut positions = vec![[0.0, 0.0, 0.0]];
        let mut triangles = Vec::new();
        for i in 0..k {
            let a = std::f64::consts::TAU * i as f64 / k as f64;
            positions.push([a.cos(), a.sin(), 0.0]);
            triangles.push([0, 1 + i as u32, 1 + ((i + 1) % k) as u32]);
        }
        let one = mesh(positions.clone(), triangles.clone());
        assert!(mesh_topology(&one).non_manifold_vertices.is_empty());
        for i in 0..3 {
            let a = std::f64::consts::TAU * i as f64 / 3.0;
            positions.push([a.cos(), a.sin(), 1.0]);
            let n = (k + 1 + i) as u32;
            triangles.push([0, n, (k + 1 + (i + 1) % 3) as u32]);
        }
        let two = mesh(positions, triangles);
        assert_eq!(mesh_topology(&two).non_manifold_vertices, vec![0]);
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

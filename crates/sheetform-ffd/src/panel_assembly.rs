//! Objects made of several developable panels, and their linked vertices.

use crate::FfdError;
use nalgebra::Vector3;
use sheetform_mesh::{coincident_vertices, mesh_topology, EdgeTable, TriangleMesh};

type Vec3 = Vector3<f64>;

/// Relative tolerance (of the model size) within which vertices of different panels are
/// the same point of the object (a linked vertex set).
pub const LINK_TOLERANCE: f64 = 1e-9;

/// One panel (a mesh patch `M_i`, an OBJ group).
#[derive(Debug, Clone, PartialEq)]
pub struct Panel {
    /// The panel's name (OBJ group).
    pub name: String,
    /// Its faces (indices into [`PanelAssembly::mesh`]).
    pub faces: Vec<u32>,
    /// Its vertices (indices into [`PanelAssembly::mesh`]; no other panel uses them).
    pub vertices: Vec<u32>,
}

/// An object `O` of assembled panels (Wang & Tang 2004 §2.1, §3).
///
/// Every panel has its own copy of the vertices it shares with other panels, so that each
/// panel is a mesh of its own (its boundary, where `g = 0` by Eq. 2-4, includes the seams).
/// Coincident vertices form a *linked vertex set*; each set is one **node**, and the
/// deformation stores one parameter triple per node, so linked vertices are evaluated from
/// the same `(u, v, w)` and coincide exactly: no crack can open (the paper instead
/// modifies the gradients of linked vertices so they move alike; sharing the variable is
/// the same constraint, exactly).
#[derive(Debug, Clone, PartialEq)]
pub struct PanelAssembly {
    /// All panels' vertices and faces; `face_groups` / `groups` name the panels.
    pub mesh: TriangleMesh,
    /// The panels.
    pub panels: Vec<Panel>,
    /// Node (linked vertex set) of every mesh vertex.
    pub vertex_node: Vec<u32>,
    /// Number of nodes.
    pub node_count: usize,
    /// Whether each mesh vertex is on its panel's boundary (seams included).
    pub boundary: Vec<bool>,
    /// The edges of `mesh`, in vertex indices: seams are boundary edges here (the panels'
    /// vertices are distinct), so an edge with two triangles is inside one panel.
    pub edges: EdgeTable,
    /// The triangles in node indices: the panels welded at their seams.
    pub node_triangles: Vec<[u32; 3]>,
    /// The edges of `node_triangles`: an edge with two triangles is inside a panel or a
    /// seam where two panels meet.
    pub node_edges: EdgeTable,
}

impl PanelAssembly {
    /// Splits `mesh` into its groups (one panel per non-empty group), gives every panel
    /// its own vertices and links coincident vertices (within `1e-9 ×` the model size).
    ///
    /// # Errors
    /// [`FfdError::Panel`] for an empty mesh or a panel with non-manifold edges or
    /// vertices, degenerate faces or inconsistent orientation (naming the panel and the
    /// first offending element).
    pub fn from_mesh(mesh: &TriangleMesh) -> Result<Self, FfdError> {
        if mesh.triangles.is_empty() {
            return Err(FfdError::Panel {
                panel: "(mesh)".into(),
                message: "the mesh has no faces".into(),
            });
        }
        let group_count = mesh.groups.len().max(1);
        let mut by_group: Vec<Vec<u32>> = vec![Vec::new(); group_count];
        for (f, &g) in mesh.face_groups.iter().enumerate() {
            by_group[g as usize].push(f as u32);
        }
        let mut out = TriangleMesh::default();
        let mut panels = Vec::new();
        let mut boundary = Vec::new();
        let mut local = vec![u32::MAX; mesh.positions.len()];
        for (g, faces) in by_group.iter().enumerate() {
            if faces.is_empty() {
                continue;
            }
            let name = mesh.groups.get(g).cloned().unwrap_or_else(|| format!("panel-{g}"));
            let mut sub = TriangleMesh {
                groups: vec![name.clone()],
                ..Default::default()
            };
            let mut used = Vec::new();
            for &f in faces {
                let t = mesh.triangles[f as usize].map(|v| {
                    if local[v as usize] == u32::MAX {
                        local[v as usize] = used.len() as u32;
                        used.push(v);
                    }
                    local[v as usize]
                });
                sub.triangles.push(t);
                sub.face_groups.push(0);
            }
            sub.positions = used.iter().map(|&v| mesh.positions[v as usize]).collect();
            for &v in &used {
                local[v as usize] = u32::MAX;
            }
            let topology = mesh_topology(&sub);
            let problem = if let Some(e) = topology.non_manifold_edges.first() {
                Some(format!(
                    "non-manifold edge between vertices {} and {} (more than two faces)",
                    used[e[0] as usize], used[e[1] as usize]
                ))
            } else if let Some(&v) = topology.non_manifold_vertices.first() {
                Some(format!("non-manifold vertex {}", used[v as usize]))
            } else if let Some(&f) = topology.degenerate_faces.first() {
                Some(format!("degenerate (zero-area) face {}", faces[f as usize]))
            } else if !topology.orientable {
                Some("the panel is not orientable".into())
            } else {
                None
            };
            if let Some(message) = problem {
                return Err(FfdError::Panel { panel: name, message });
            }
            let offset = out.positions.len() as u32;
            let panel_index = panels.len() as u32;
            out.positions.extend_from_slice(&sub.positions);
            out.triangles
                .extend(sub.triangles.iter().map(|t| t.map(|v| v + offset)));
            out.face_groups.extend(std::iter::repeat_n(panel_index, faces.len()));
            out.groups.push(name.clone());
            boundary.extend_from_slice(&topology.boundary_vertex);
            panels.push(Panel {
                name,
                faces: (out.triangles.len() - faces.len()..out.triangles.len())
                    .map(|f| f as u32)
                    .collect(),
                vertices: (offset..out.positions.len() as u32).collect(),
            });
        }
        let tolerance = LINK_TOLERANCE * out.scale().max(f64::MIN_POSITIVE);
        let vertex_node = coincident_vertices(&out.positions, tolerance);
        let node_count = vertex_node.iter().map(|&n| n as usize + 1).max().unwrap_or(0);
        let edges = EdgeTable::new(&out.triangles, out.positions.len());
        let node_triangles: Vec<[u32; 3]> = out
            .triangles
            .iter()
            .map(|t| t.map(|v| vertex_node[v as usize]))
            .collect();
        let node_edges = EdgeTable::new(&node_triangles, node_count);
        Ok(Self {
            mesh: out,
            panels,
            vertex_node,
            node_count,
            boundary,
            edges,
            node_triangles,
            node_edges,
        })
    }

    /// One position per node (that of its first vertex).
    pub fn node_positions(&self) -> Vec<Vec3> {
        self.node_positions_of(&self.mesh.positions)
    }

    /// One position per node taken from per-vertex positions (that of the node's first
    /// vertex).
    pub fn node_positions_of(&self, vertex_positions: &[Vec3]) -> Vec<Vec3> {
        let mut out = vec![Vec3::zeros(); self.node_count];
        for (v, &n) in self.vertex_node.iter().enumerate().rev() {
            out[n as usize] = vertex_positions[v];
        }
        out
    }

    /// Number of nodes shared by more than one vertex (assembling vertices).
    pub fn linked_node_count(&self) -> usize {
        let mut copies = vec![0u32; self.node_count];
        for &n in &self.vertex_node {
            copies[n as usize] += 1;
        }
        copies.iter().filter(|&&c| c > 1).count()
    }

    /// The mesh with every vertex at its node's position.
    pub fn mesh_at(&self, node_positions: &[Vec3]) -> TriangleMesh {
        let mut mesh = self.mesh.clone();
        for (p, &n) in mesh.positions.iter_mut().zip(&self.vertex_node) {
            *p = node_positions[n as usize];
        }
        mesh
    }

    /// The sub-mesh of one panel (its own vertex numbering, in [`Panel::vertices`] order).
    pub fn panel_mesh(&self, panel: usize, node_positions: &[Vec3]) -> TriangleMesh {
        let p = &self.panels[panel];
        let first = p.vertices[0];
        TriangleMesh {
            positions: p
                .vertices
                .iter()
                .map(|&v| node_positions[self.vertex_node[v as usize] as usize])
                .collect(),
            triangles: p
                .faces
                .iter()
                .map(|&f| self.mesh.triangles[f as usize].map(|v| v - first))
                .collect(),
            face_groups: vec![0; p.faces.len()],
            groups: vec![p.name.clone()],
            ..Default::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shared_and_coincident_vertices_are_linked() {
        // Two squares sharing an edge by index, a third touching by position only.
        let mut mesh = TriangleMesh {
            positions: vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(2.0, 1.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(0.5, 2.0, 0.0),
            ],
            triangles: vec![[0, 1, 2], [0, 2, 3], [1, 4, 5], [1, 5, 2], [6, 7, 8]],
            face_groups: vec![0, 0, 1, 1, 2],
            groups: vec!["a".into(), "b".into(), "c".into()],
            ..Default::default()
        };
        let a = PanelAssembly::from_mesh(&mesh).unwrap();
        assert_eq!(a.panels.len(), 3);
        assert_eq!(a.mesh.positions.len(), 4 + 4 + 3);
        // Nodes: the 6 grid points + the apex = 7; linked: (1,0), (1,1) [a, b, c], (0,1) [a, c].
        assert_eq!(a.node_count, 7);
        assert_eq!(a.linked_node_count(), 3);
        assert!(a.boundary.iter().all(|&b| b));
        // A fan of three faces on one edge is refused with the panel's name.
        mesh.triangles.push([0, 1, 8]);
        mesh.face_groups.push(0);
        mesh.triangles.push([0, 1, 5]);
        mesh.face_groups.push(0);
        let e = PanelAssembly::from_mesh(&mesh).unwrap_err();
        assert!(
            e.to_string().contains("panel `a`") && e.to_string().contains("non-manifold"),
            "{e}"
        );
    }
}

//! The undirected edges of a triangle mesh and the faces on each, built in linear time.

/// One face's use of an edge.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EdgeSide {
    /// The face.
    pub face: u32,
    /// The face traverses the edge from its lower to its higher vertex index.
    pub forward: bool,
}

/// The undirected edges of a triangle mesh, sorted by `(lower, higher)` vertex index, with
/// the faces on each edge and each face's three edges.
///
/// Built by a counting sort of the half-edges on their lower vertex (`O(V + F)`), then a
/// sort of each vertex's few half-edges on the higher vertex (`O(d log d)` per vertex of
/// degree `d`): no hash map, so the cost grows linearly with the mesh and the memory is
/// read in order. Edges `(a, a)` of faces with a repeated vertex are left out (such faces
/// are degenerate; `mesh_topology` lists them).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct EdgeTable {
    /// The edges, `[lower, higher]`, in increasing order.
    pub edges: Vec<[u32; 2]>,
    /// `sides[side_offsets[e]..side_offsets[e + 1]]` are the faces on edge `e`, in face
    /// order (a face with a repeated vertex can be on an edge twice: then in corner order).
    pub side_offsets: Vec<u32>,
    /// The faces on each edge (see `side_offsets`).
    pub sides: Vec<EdgeSide>,
    /// Face `f`'s edge `k` joins corners `k` and `k + 1` (`u32::MAX` where they coincide).
    pub face_edges: Vec<[u32; 3]>,
}

impl EdgeTable {
    /// Builds the table of `triangles` over `vertex_count` vertices (indices must be in
    /// range).
    pub fn new(triangles: &[[u32; 3]], vertex_count: usize) -> Self {
        // Half-edges bucketed by their lower vertex (counting sort).
        let mut start = vec![0u32; vertex_count + 1];
        for t in triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                if a != b {
                    start[a.min(b) as usize + 1] += 1;
                }
            }
        }
        for v in 0..vertex_count {
            start[v + 1] += start[v];
        }
        let total = start[vertex_count] as usize;
        // (higher vertex, face, corner) per half-edge.
        let mut half = vec![(0u32, 0u32, 0u8); total];
        let mut fill = start.clone();
        for (f, t) in triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                if a != b {
                    let slot = &mut fill[a.min(b) as usize];
                    half[*slot as usize] = (a.max(b), f as u32, k as u8);
                    *slot += 1;
                }
            }
        }
        let mut table = Self {
            edges: Vec::with_capacity(total / 2 + 1),
            side_offsets: Vec::with_capacity(total / 2 + 2),
            sides: Vec::with_capacity(total),
            face_edges: vec![[u32::MAX; 3]; triangles.len()],
        };
        table.side_offsets.push(0);
        for lower in 0..vertex_count {
            let bucket = &mut half[start[lower] as usize..start[lower + 1] as usize];
            // Keys are unique: sides come in face order, then corner order.
            bucket.sort_unstable_by_key(|&(higher, face, corner)| (higher, face, corner));
            let mut i = 0;
            while i < bucket.len() {
                let higher = bucket[i].0;
                let edge = table.edges.len() as u32;
                table.edges.push([lower as u32, higher]);
                while i < bucket.len() && bucket[i].0 == higher {
                    let (_, face, k) = bucket[i];
                    let t = triangles[face as usize];
                    table.sides.push(EdgeSide {
                        face,
                        forward: t[k as usize] as usize == lower,
                    });
                    table.face_edges[face as usize][k as usize] = edge;
                    i += 1;
                }
                table.side_offsets.push(table.sides.len() as u32);
            }
        }
        table
    }

    /// Number of edges.
    pub fn len(&self) -> usize {
        self.edges.len()
    }

    /// Whether there are no edges.
    pub fn is_empty(&self) -> bool {
        self.edges.is_empty()
    }

    /// The edge joining vertices `a` and `b` (either order), by binary search.
    pub fn find(&self, a: u32, b: u32) -> Option<usize> {
        self.edges.binary_search(&[a.min(b), a.max(b)]).ok()
    }

    /// The faces on the edge joining `a` and `b` (empty when it is no edge).
    pub fn faces_of(&self, a: u32, b: u32) -> impl Iterator<Item = u32> + '_ {
        self.find(a, b)
            .map_or(&[][..], |e| self.sides(e))
            .iter()
            .map(|s| s.face)
    }

    /// Edges on exactly one face, as that face runs them (`[from, to]`).
    pub fn boundary_edges(&self) -> impl Iterator<Item = [u32; 2]> + '_ {
        (0..self.len()).filter_map(|e| match self.sides(e) {
            [s] => {
                let [lo, hi] = self.edges[e];
                Some(if s.forward { [lo, hi] } else { [hi, lo] })
            }
            _ => None,
        })
    }

    /// The faces on edge `e`.
    pub fn sides(&self, e: usize) -> &[EdgeSide] {
        &self.sides[self.side_offsets[e] as usize..self.side_offsets[e + 1] as usize]
    }

    /// The face across edge `k` of face `f`, if that edge has exactly two faces.
    pub fn opposite(&self, f: usize, k: usize) -> Option<u32> {
        let e = self.face_edges[f][k];
        if e == u32::MAX {
            return None;
        }
        match self.sides(e as usize) {
            [a, b] => Some(if a.face as usize == f { b.face } else { a.face }),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::collections::BTreeMap;

    proptest! {
        #![proptest_config(ProptestConfig { cases: 200, rng_seed: proptest::test_runner::RngSeed::Fixed(7), ..ProptestConfig::default() })]
        /// Any triangle soup (repeated vertices, edges on three faces, unused vertices):
        /// the table equals a map built the obvious way.
        #[test]
        fn matches_a_map_built_the_obvious_way(
            vertex_count in 1usize..12,
            raw in proptest::collection::vec([0u32..12, 0u32..12, 0u32..12], 0..30),
        ) {
            let triangles: Vec<[u32; 3]> = raw.iter().map(|t| t.map(|v| v % vertex_count as u32)).collect();
            let table = EdgeTable::new(&triangles, vertex_count);
            let mut expected: BTreeMap<[u32; 2], Vec<EdgeSide>> = BTreeMap::new();
            for (f, t) in triangles.iter().enumerate() {
                for k in 0..3 {
                    let (a, b) = (t[k], t[(k + 1) % 3]);
                    if a != b {
                        expected.entry([a.min(b), a.max(b)]).or_default().push(EdgeSide { face: f as u32, forward: a < b });
                    }
                }
            }
            prop_assert_eq!(table.edges.clone(), expected.keys().copied().collect::<Vec<_>>());
            for (e, sides) in expected.values().enumerate() {
                prop_assert_eq!(table.sides(e), &sides[..]);
            }
            // Lookups either way round, and the boundary as its one face runs it.
            for (key, sides) in &expected {
                prop_assert_eq!(table.find(key[1], key[0]), table.edges.binary_search(key).ok());
                prop_assert_eq!(table.faces_of(key[1], key[0]).collect::<Vec<_>>(), sides.iter().map(|s| s.face).collect::<Vec<_>>());
            }
            let boundary: Vec<[u32; 2]> = expected
                .iter()
                .filter(|(_, sides)| sides.len() == 1)
                .map(|(k, sides)| if sides[0].forward { *k } else { [k[1], k[0]] })
                .collect();
            prop_assert_eq!(table.boundary_edges().collect::<Vec<_>>(), boundary);
            prop_assert_eq!(table.faces_of(vertex_count as u32, vertex_count as u32 + 1).count(), 0);
        }
    }

    #[test]
    fn edges_faces_and_orientation_of_a_small_mesh() {
        // Two triangles sharing edge (1, 2), a third on edge (0, 1) in the other
        // direction, and a degenerate one.
        let triangles = [[0, 1, 2], [2, 1, 3], [1, 0, 4], [3, 3, 4]];
        let table = EdgeTable::new(&triangles, 5);
        assert_eq!(
            table.edges,
            vec![[0, 1], [0, 2], [0, 4], [1, 2], [1, 3], [1, 4], [2, 3], [3, 4]]
        );
        let at = |a: u32, b: u32| table.edges.iter().position(|&e| e == [a, b]).unwrap();
        assert_eq!(
            table.sides(at(0, 1)),
            &[
                EdgeSide { face: 0, forward: true },
                EdgeSide {
                    face: 2,
                    forward: false
                }
            ]
        );
        assert_eq!(
            table.sides(at(1, 2)),
            &[
                EdgeSide { face: 0, forward: true },
                EdgeSide {
                    face: 1,
                    forward: false
                }
            ]
        );
        assert_eq!(table.sides(at(3, 4)).len(), 2, "the degenerate face's two real edges");
        assert_eq!(table.face_edges[3][0], u32::MAX, "its (3, 3) edge is left out");
        assert_eq!(table.opposite(0, 1), Some(1));
        assert_eq!(table.opposite(1, 0), Some(0));
        assert_eq!(table.opposite(0, 2), None, "boundary edge (2, 0)");
        for (f, t) in triangles.iter().enumerate() {
            for k in 0..3 {
                let e = table.face_edges[f][k];
                if e != u32::MAX {
                    let (a, b) = (t[k], t[(k + 1) % 3]);
                    assert_eq!(table.edges[e as usize], [a.min(b), a.max(b)]);
                    assert!(table.sides(e as usize).iter().any(|s| s.face as usize == f));
                }
            }
        }
    }
}

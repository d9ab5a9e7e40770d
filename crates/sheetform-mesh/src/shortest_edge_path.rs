//! Shortest paths along a mesh's edges (Dijkstra), from a set of vertices to the nearest
//! vertex that passes a test: the seams that open a chart to a disk and the straightened
//! chart borders both follow them.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};

/// The shortest path from any of `sources` to the nearest vertex where `is_target` holds,
/// stepping from a vertex `v` to each `(w, length)` of `steps(v)` (non-negative lengths),
/// shorter than `limit`: its vertices from the target back to its source (equal
/// distances are broken towards the lower vertex index). `None` when no target is
/// reachable within `limit`. Distances are kept for the vertices reached only, so a
/// search over a small part of a large mesh costs that part.
pub fn shortest_edge_path<S: IntoIterator<Item = (u32, f64)>>(
    sources: impl IntoIterator<Item = u32>,
    is_target: impl Fn(u32) -> bool,
    steps: impl Fn(u32) -> S,
    limit: f64,
) -> Option<Vec<u32>> {
    // Per vertex reached: its distance and the vertex it was reached from.
    let mut reached: HashMap<u32, (f64, u32)> = HashMap::new();
    let mut queue = BinaryHeap::new();
    for s in sources {
        reached.insert(s, (0.0, u32::MAX));
        // Non-negative distances order as their bit patterns do.
        queue.push(Reverse((0f64.to_bits(), s)));
    }
    let mut target = None;
    while let Some(Reverse((bits, v))) = queue.pop() {
        let d = f64::from_bits(bits);
        if d > reached[&v].0 {
            continue;
        }
        if is_target(v) {
            target = Some(v);
            break;
        }
        for (w, length) in steps(v) {
            let next = d + length;
            if next < limit && reached.get(&w).is_none_or(|x| next < x.0) {
                reached.insert(w, (next, v));
                queue.push(Reverse((next.to_bits(), w)));
            }
        }
    }
    let mut path = vec![target?];
    while let Some(&(_, from)) = reached.get(path.last().expect("a path has a vertex")) {
        if from == u32::MAX {
            break;
        }
        path.push(from);
    }
    Some(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_target_on_a_weighted_path() {
        // 0 —1— 1 —1— 2, and 0 —5— 2: from 0 to 2 through 1 (length 2), not directly.
        let edges = [(0u32, 1u32, 1.0), (1, 2, 1.0), (0, 2, 5.0)];
        let steps = |v: u32| {
            edges
                .iter()
                .filter_map(move |&(a, b, l)| match v {
                    _ if a == v => Some((b, l)),
                    _ if b == v => Some((a, l)),
                    _ => None,
                })
                .collect::<Vec<_>>()
        };
        assert_eq!(
            shortest_edge_path([0], |v| v == 2, steps, f64::INFINITY),
            Some(vec![2, 1, 0])
        );
        // Nothing shorter than 2 reaches it.
        assert_eq!(shortest_edge_path([0], |v| v == 2, steps, 2.0), None);
        // From either of two sources, the nearer one.
        assert_eq!(
            shortest_edge_path([0, 2], |v| v == 1, steps, f64::INFINITY),
            Some(vec![1, 0])
        );
    }
}

//! A fill-reducing ordering for the KKT system of large meshes: nested dissection by
//! coordinate bisection.

use nalgebra::Vector3;

/// Sets of at most this many unknowns are not split further.
const LEAF_SIZE: usize = 32;

/// A nested-dissection elimination order (George, "Nested dissection of a regular finite
/// element mesh", SIAM J. Numer. Anal. 10(2), 1973) of a sparse symmetric pattern whose
/// unknowns have positions in space: `order[k]` is the unknown eliminated `k`-th.
///
/// `adjacency[i]` lists the unknowns coupled to `i` (symmetric, without `i` itself);
/// `coordinates[i]` is where unknown `i` lives (for the FFD's KKT system: the node of a
/// parameter triple or of a defect constraint).
///
/// Recursively: split the set at the median of its longest bounding-box axis into
/// halves `A` and `B`; the unknowns of `B` coupled to `A` form the separator `S`; order
/// `A`, then `B \ S`, then `S` last, so that eliminating either half never fills the
/// other. Sets of at most 32 unknowns are left in their order (faer's supernodes absorb
/// them).
///
/// Why by hand: faer 0.24 offers AMD or a custom permutation, and no kept crate computes
/// nested dissection (the METIS bindings need a C toolchain). On the FFD's meshes the
/// sheet is a surface, so a plane cut by coordinates gives short separators. Measured
/// (docs/benchmarks-history.md, eighth session): on the 100k-vertex duct the factor `L` has
/// 95.6 M values instead of AMD's 201 M and the numeric factorisation takes 2.0–2.6 s
/// instead of 10–12 s; on a 2 501-vertex duct 1.36 M instead of 2.0 M; on the skirt
/// (1 080 nodes) AMD is 7 % smaller, which is why the KKT system keeps whichever is
/// smaller below 20 000 unknowns.
pub fn nested_dissection(adjacency: &[Vec<usize>], coordinates: &[Vector3<f64>]) -> Vec<usize> {
    debug_assert_eq!(adjacency.len(), coordinates.len());
    let mut order = Vec::with_capacity(adjacency.len());
    // `side[i] == tag` marks the half `A` of the split being made (a fresh tag per split).
    let mut side = vec![0usize; adjacency.len()];
    let mut tag = 0;
    dissect(
        (0..adjacency.len()).collect(),
        adjacency,
        coordinates,
        &mut side,
        &mut tag,
        &mut order,
    );
    order
}

fn dissect(
    mut set: Vec<usize>,
    adjacency: &[Vec<usize>],
    coordinates: &[Vector3<f64>],
    side: &mut [usize],
    tag: &mut usize,
    order: &mut Vec<usize>,
) {
    if set.len() <= LEAF_SIZE {
        order.extend(set);
        return;
    }
    let (mut low, mut high) = (coordinates[set[0]], coordinates[set[0]]);
    for &i in &set {
        low = low.inf(&coordinates[i]);
        high = high.sup(&coordinates[i]);
    }
    let axis = (high - low).imax();
    let half = set.len() / 2;
    set.select_nth_unstable_by(half, |&a, &b| coordinates[a][axis].total_cmp(&coordinates[b][axis]));
    let b_half = set.split_off(half);
    *tag += 1;
    for &i in &set {
        side[i] = *tag;
    }
    let (separator, rest): (Vec<usize>, Vec<usize>) = b_half
        .into_iter()
        .partition(|&i| adjacency[i].iter().any(|&j| side[j] == *tag));
    dissect(set, adjacency, coordinates, side, tag, order);
    dissect(rest, adjacency, coordinates, side, tag, order);
    order.extend(separator);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On an `n × n` grid graph (5-point stencil) the order is a permutation, every
    /// separator really separates (no unknown is coupled to an unknown of the other half
    /// ordered before the separator), and the top separator is one grid line.
    #[test]
    fn orders_a_grid_by_separators() {
        let n = 40;
        let index = |i: usize, j: usize| i + n * j;
        let mut adjacency = vec![Vec::new(); n * n];
        let mut coordinates = Vec::new();
        for j in 0..n {
            for i in 0..n {
                coordinates.push(Vector3::new(i as f64, j as f64, 0.0));
                if i + 1 < n {
                    adjacency[index(i, j)].push(index(i + 1, j));
                    adjacency[index(i + 1, j)].push(index(i, j));
                }
                if j + 1 < n {
                    adjacency[index(i, j)].push(index(i, j + 1));
                    adjacency[index(i, j + 1)].push(index(i, j));
                }
            }
        }
        let order = nested_dissection(&adjacency, &coordinates);
        let mut seen = order.clone();
        seen.sort_unstable();
        assert_eq!(seen, (0..n * n).collect::<Vec<_>>());
        // The last n unknowns are the top separator: one grid line (all the same x or y).
        let top = &order[n * n - n..];
        let xs: Vec<f64> = top.iter().map(|&i| coordinates[i].x).collect();
        let ys: Vec<f64> = top.iter().map(|&i| coordinates[i].y).collect();
        assert!(
            xs.iter().all(|&x| x == xs[0]) || ys.iter().all(|&y| y == ys[0]),
            "{xs:?} {ys:?}"
        );
        // Removing it leaves the half A (the first n²/2 in the order) and the rest of B,
        // with no coupling between them.
        let position: Vec<usize> = {
            let mut p = vec![0; n * n];
            for (k, &i) in order.iter().enumerate() {
                p[i] = k;
            }
            p
        };
        let half = n * n / 2;
        for (i, neighbours) in adjacency.iter().enumerate() {
            for &j in neighbours {
                let (a, b) = (position[i], position[j]);
                if a < n * n - n && b < n * n - n {
                    assert_eq!(a < half, b < half, "{i} and {j} cross the top separator");
                }
            }
        }
    }
}

//! Chart borders moved onto the shortest edge paths between their ends, as a pattern maker
//! draws a seam: splitting a chart along its face graph leaves sawtooth borders on fine
//! meshes; each border between two charts that splitting made (not a crease, a user seam
//! or the cut of an opened chart) is replaced by the shortest path along mesh edges
//! (Dijkstra on the 3D edge lengths) joining the same two ends through the two charts,
//! when both new charts still pass the chart acceptance test.
//!
//! This is the boundary straightening of segmenters such as D-Charts (Julius, Kraevoy and
//! Sheffer 2005, §4.3, "boundary optimisation"), in its simplest form: shortest length
//! only, no smoothness term; the acceptance test (exact unfolding, no overlap, edge
//! distortion within the bound) is the one the charts passed before.

use crate::chart_segmentation::{flatten_chart, submesh, Chart, ChartOptions};
use sheetform_mesh::{EdgeTable, TriangleMesh};
use std::collections::HashSet;

/// Replaces chart borders by shortest edge paths (see the module documentation); returns
/// how many borders moved. `fixed[e]` marks the edges that must stay borders or stay
/// inside their chart (creases and user seams); charts opened along a cut of their own
/// (more vertices than their faces cut along the user's seams have) keep their faces.
pub(crate) fn straighten_chart_borders(
    mesh: &TriangleMesh,
    table: &EdgeTable,
    fixed: &[bool],
    charts: &mut [Chart],
    options: &ChartOptions,
) -> usize {
    let nf = mesh.triangles.len();
    let nv = mesh.positions.len();
    // (A chart cut open along a seam inside it, a slit, has as many vertices as its mesh
    // cut along its seams: it is not "opened" in this sense and may be straightened.)
    let opened: Vec<bool> = charts
        .iter()
        .map(|c| submesh(mesh, &c.faces).1.len() != c.vertices.len())
        .collect();
    let mut face_chart = vec![u32::MAX; nf];
    for (c, chart) in charts.iter().enumerate() {
        for &f in &chart.faces {
            face_chart[f as usize] = c as u32;
        }
    }
    let length = |e: usize| {
        let [a, b] = table.edges[e];
        (mesh.positions[a as usize] - mesh.positions[b as usize]).norm()
    };
    // Edges at each vertex.
    let mut vertex_edges: Vec<Vec<u32>> = vec![Vec::new(); nv];
    for (e, [a, b]) in table.edges.iter().enumerate() {
        vertex_edges[*a as usize].push(e as u32);
        vertex_edges[*b as usize].push(e as u32);
    }
    let movable = |e: usize, face_chart: &[u32]| match table.sides(e) {
        [f, g] => {
            let (cf, cg) = (face_chart[f.face as usize], face_chart[g.face as usize]);
            cf != cg && !fixed[e] && !opened[cf as usize] && !opened[cg as usize]
        }
        _ => false,
    };
    // Chain ends: vertices where the movable border does not simply run on (a third
    // chart, a crease, a seam, the mesh boundary, a branching).
    let end = |v: usize, face_chart: &[u32]| {
        let mut movable_count = 0;
        let mut charts_here: Vec<u32> = Vec::new();
        for &e in &vertex_edges[v] {
            let e = e as usize;
            let sides = table.sides(e);
            if sides.len() != 2 || fixed[e] {
                return true;
            }
            for s in sides {
                let c = face_chart[s.face as usize];
                if !charts_here.contains(&c) {
                    charts_here.push(c);
                }
            }
            if movable(e, face_chart) {
                movable_count += 1;
            } else if face_chart[sides[0].face as usize] != face_chart[sides[1].face as usize] {
                return true;
            }
        }
        movable_count != 2 || charts_here.len() > 2
    };
    // The chains of movable border edges between ends.
    let mut chains: Vec<Vec<u32>> = Vec::new();
    let mut walked = vec![false; table.len()];
    for start in 0..nv {
        if !end(start, &face_chart) {
            continue;
        }
        for &e0 in &vertex_edges[start] {
            if walked[e0 as usize] || !movable(e0 as usize, &face_chart) {
                continue;
            }
            let mut chain = vec![start as u32];
            let (mut e, mut v) = (e0 as usize, start);
            loop {
                walked[e] = true;
                let [a, b] = table.edges[e];
                v = if a as usize == v { b as usize } else { a as usize };
                chain.push(v as u32);
                if end(v, &face_chart) {
                    break;
                }
                let next = vertex_edges[v]
                    .iter()
                    .map(|&x| x as usize)
                    .find(|&x| x != e && !walked[x] && movable(x, &face_chart));
                match next {
                    Some(x) => e = x,
                    None => break,
                }
            }
            if chain.len() > 2 && chain[0] != *chain.last().expect("a chain has ends") {
                chains.push(chain);
            }
        }
    }

    let mut budget = 20 * nf + 10_000;
    let mut moved = 0;
    for chain in chains {
        let edges: Option<Vec<usize>> = chain.windows(2).map(|w| table.find(w[0], w[1])).collect();
        let Some(edges) = edges else { continue };
        // Still a border between the same two charts (an earlier move may have changed it).
        let [f, g] = table.sides(edges[0]) else { continue };
        let (a, b) = (face_chart[f.face as usize], face_chart[g.face as usize]);
        let between = |e: usize| match table.sides(e) {
            [x, y] => {
                let pair = (face_chart[x.face as usize], face_chart[y.face as usize]);
                (pair == (a, b) || pair == (b, a)) && movable(e, &face_chart)
            }
            _ => false,
        };
        if a == b || !edges.iter().all(|&e| between(e)) {
            continue;
        }
        let old_length: f64 = edges.iter().map(|&e| length(e)).sum();
        let in_region = |f: u32| face_chart[f as usize] == a || face_chart[f as usize] == b;
        // Edges inside the region (both faces in it) that the new border may use, through
        // vertices off the region's boundary.
        let inside = |e: usize| match table.sides(e) {
            [x, y] => in_region(x.face) && in_region(y.face) && !fixed[e],
            _ => false,
        };
        let on_region_boundary = |v: usize| {
            vertex_edges[v].iter().any(|&e| {
                let sides = table.sides(e as usize);
                sides.iter().any(|s| in_region(s.face))
                    && !(sides.len() == 2 && sides.iter().all(|s| in_region(s.face)))
            })
        };
        // Work budget: every chain tried costs its two charts' faces (the search), every
        // split tried as much again (the unfoldings).
        let region_size = charts[a as usize].faces.len() + charts[b as usize].faces.len();
        if budget < region_size {
            break;
        }
        budget -= region_size;
        let (source, target) = (chain[0] as usize, *chain.last().expect("ends") as usize);
        // The shortest path through the two charts, off their outer boundary (the ends
        // excepted), shorter than the border it replaces; as edges.
        let steps = |v: u32| {
            let open = v as usize == source || !on_region_boundary(v as usize);
            vertex_edges[v as usize]
                .iter()
                .map(|&e| e as usize)
                .filter(move |&e| open && inside(e))
                .map(|e| {
                    let [x, y] = table.edges[e];
                    (if x == v { y } else { x }, length(e))
                })
                .collect::<Vec<_>>()
        };
        let vertices = sheetform_mesh::shortest_edge_path([source as u32], |v| v as usize == target, steps, old_length);
        let Some(path) =
            vertices.and_then(|p| p.windows(2).map(|w| table.find(w[0], w[1])).collect::<Option<Vec<_>>>())
        else {
            continue;
        };
        let new_length: f64 = path.iter().map(|&e| length(e)).sum();
        if new_length >= old_length * (1.0 - 1e-9) {
            continue;
        }
        // The region's faces on either side of the new border.
        let region: Vec<u32> = charts[a as usize]
            .faces
            .iter()
            .chain(&charts[b as usize].faces)
            .copied()
            .collect();
        let cut: HashSet<usize> = path.iter().copied().collect();
        let Some((side_a, side_b)) = split_along(&region, &cut, table, &face_chart, a) else {
            continue;
        };
        if budget < region.len() {
            break;
        }
        budget -= region.len();
        let Some(chart_a) = accepted_chart(mesh, side_a, options) else {
            continue;
        };
        let Some(chart_b) = accepted_chart(mesh, side_b, options) else {
            continue;
        };
        for &f in &chart_a.faces {
            face_chart[f as usize] = a;
        }
        for &f in &chart_b.faces {
            face_chart[f as usize] = b;
        }
        charts[a as usize] = chart_a;
        charts[b as usize] = chart_b;
        moved += 1;
    }
    moved
}

/// The faces of `region` in the two parts the `cut` edges separate them into (the part
/// holding more faces of chart `a` first); `None` unless there are exactly two.
fn split_along(
    region: &[u32],
    cut: &HashSet<usize>,
    table: &EdgeTable,
    face_chart: &[u32],
    a: u32,
) -> Option<(Vec<u32>, Vec<u32>)> {
    let members: HashSet<u32> = region.iter().copied().collect();
    let mut part: std::collections::HashMap<u32, usize> = std::collections::HashMap::new();
    let mut parts: Vec<Vec<u32>> = Vec::new();
    for &f0 in region {
        if part.contains_key(&f0) {
            continue;
        }
        let id = parts.len();
        part.insert(f0, id);
        let mut faces = vec![f0];
        let mut i = 0;
        while i < faces.len() {
            let f = faces[i] as usize;
            i += 1;
            for k in 0..3 {
                let e = table.face_edges[f][k];
                if e == u32::MAX || cut.contains(&(e as usize)) {
                    continue;
                }
                if let Some(g) = table.opposite(f, k) {
                    if members.contains(&g) && !part.contains_key(&g) {
                        part.insert(g, id);
                        faces.push(g);
                    }
                }
            }
        }
        parts.push(faces);
        if parts.len() > 2 {
            return None;
        }
    }
    let [first, second]: [Vec<u32>; 2] = parts.try_into().ok()?;
    let of_a = |faces: &[u32]| faces.iter().filter(|&&f| face_chart[f as usize] == a).count();
    Some(if of_a(&first) >= of_a(&second) {
        (first, second)
    } else {
        (second, first)
    })
}

/// The chart of `faces` when it unfolds without overlap within the distortion bound.
fn accepted_chart(mesh: &TriangleMesh, mut faces: Vec<u32>, options: &ChartOptions) -> Option<Chart> {
    faces.sort_unstable();
    let (sub, vertices) = submesh(mesh, &faces);
    let (unfolding, distortion) = flatten_chart(&sub)?;
    options.accepts(&distortion).then_some(Chart {
        faces,
        vertices,
        triangles: sub.triangles,
        flat: unfolding.flat,
        distortion,
        solver: unfolding.solver,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    #[test]
    fn a_sawtooth_border_across_a_grid_becomes_straight() {
        // A 10 × 10 grid of unit squares (two triangles each) in two charts: rows 0–4,
        // and rows 5–9, with squares (2, 5), (3, 5), (6, 5), (7, 5) given to the first:
        // a border of length 14 from (0, 5) to (10, 5) with two bumps.
        let n = 10u32;
        let id = |i: u32, j: u32| j * (n + 1) + i;
        let mut positions = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                positions.push(Vector3::new(i as f64, j as f64, 0.0));
            }
        }
        let (mut triangles, mut lower) = (Vec::new(), Vec::new());
        for j in 0..n {
            for i in 0..n {
                triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
                let first = j < 5 || (j == 5 && [2, 3, 6, 7].contains(&i));
                lower.extend([first, first]);
            }
        }
        let mesh = TriangleMesh {
            positions,
            face_groups: vec![0; triangles.len()],
            triangles,
            groups: vec!["grid".into()],
            corner_uvs: None,
            seam_edges: Vec::new(),
        };
        let table = EdgeTable::new(&mesh.triangles, mesh.positions.len());
        let faces = |side: bool| {
            (0..lower.len() as u32)
                .filter(|&f| lower[f as usize] == side)
                .collect::<Vec<_>>()
        };
        let options = ChartOptions::default();
        let mut charts = vec![
            accepted_chart(&mesh, faces(true), &options).unwrap(),
            accepted_chart(&mesh, faces(false), &options).unwrap(),
        ];
        let border_length = |charts: &[Chart]| {
            let mut chart_of = vec![0; mesh.triangles.len()];
            for &f in &charts[1].faces {
                chart_of[f as usize] = 1;
            }
            (0..table.len())
                .filter(|&e| matches!(table.sides(e), [f, g] if chart_of[f.face as usize] != chart_of[g.face as usize]))
                .map(|e| {
                    let [a, b] = table.edges[e];
                    (mesh.positions[a as usize] - mesh.positions[b as usize]).norm()
                })
                .sum::<f64>()
        };
        assert!((border_length(&charts) - 14.0).abs() < 1e-12);
        let fixed = vec![false; table.len()];
        assert_eq!(
            straighten_chart_borders(&mesh, &table, &fixed, &mut charts, &options),
            1
        );
        assert!((border_length(&charts) - 10.0).abs() < 1e-12);
        assert_eq!(charts[0].faces.len(), 100);
        assert!(charts[0].distortion.edge_length_max_relative < 1e-12);
        // A fixed border (a crease or a user seam) stays where it is.
        let mut kept = vec![
            accepted_chart(&mesh, faces(true), &options).unwrap(),
            accepted_chart(&mesh, faces(false), &options).unwrap(),
        ];
        let all_fixed = vec![true; table.len()];
        assert_eq!(
            straighten_chart_borders(&mesh, &table, &all_fixed, &mut kept, &options),
            0
        );
        assert!((border_length(&kept) - 14.0).abs() < 1e-12);
        // A slit drawn inside the first chart (a user seam from its outer edge up to
        // (5, 3), cut open in it): that chart is still straightened, its slit kept.
        let mut slit = mesh.clone();
        slit.seam_edges = (0..3).map(|j| [id(5, j), id(5, j + 1)]).collect();
        let mut fixed = vec![false; table.len()];
        for &[a, b] in &slit.seam_edges {
            fixed[table.find(a, b).unwrap()] = true;
        }
        let mut charts = vec![
            accepted_chart(&slit, faces(true), &options).unwrap(),
            accepted_chart(&slit, faces(false), &options).unwrap(),
        ];
        assert_eq!(
            charts[0].vertices.len(),
            6 * 11 + 6 + 3,
            "the slit's three vertices are doubled"
        );
        assert_eq!(
            straighten_chart_borders(&slit, &table, &fixed, &mut charts, &options),
            1
        );
        assert!((border_length(&charts) - 10.0).abs() < 1e-12);
        assert_eq!(charts[0].vertices.len(), 6 * 11 + 3, "still cut open along the slit");
    }
}

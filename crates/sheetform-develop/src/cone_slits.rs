//! Slits from cone points: a vertex inside a piece that no small move makes flat is cut
//! free along the shortest edge path to its piece's border.

use crate::{mirror_interior, MirrorBoundary, SeamPieces};
use nalgebra::Vector3;
use sheetform_mesh::{vertex_angle_sums, EdgeTable, TriangleMesh};
use std::f64::consts::TAU;

type Vec3 = Vector3<f64>;

/// Cuts a slit from each of `cones` in turn (vertices inside a piece: every edge round
/// them inside the piece) along the shortest edge path, through the piece, to a vertex on
/// a seam, a slit or the mesh's boundary; marks the path's edges in `seam` (one flag per
/// edge of `table`). A cone point already reached by an earlier slit is skipped. Returns
/// the slits cut.
pub(crate) fn cut_slits(mesh: &TriangleMesh, table: &EdgeTable, seam: &mut [bool], cones: &[u32]) -> usize {
    let nv = mesh.positions.len();
    let mut on_border = vec![false; nv];
    // Edges inside a piece, per vertex: (other vertex, edge).
    let mut inner: Vec<Vec<(u32, usize)>> = vec![Vec::new(); nv];
    for (e, &cut) in seam.iter().enumerate() {
        let [a, b] = table.edges[e];
        if cut || table.sides(e).len() != 2 {
            on_border[a as usize] = true;
            on_border[b as usize] = true;
        } else {
            inner[a as usize].push((b, e));
            inner[b as usize].push((a, e));
        }
    }
    let mut slits = 0;
    for &v in cones {
        if on_border[v as usize] || inner[v as usize].is_empty() {
            continue;
        }
        let length = |a: u32, b: u32| (mesh.positions[a as usize] - mesh.positions[b as usize]).norm();
        let steps = |w: u32| {
            inner[w as usize]
                .iter()
                .filter(|&&(_, e)| !seam[e])
                .map(|&(x, _)| (x, length(w, x)))
                .collect::<Vec<_>>()
        };
        let Some(path) = sheetform_mesh::shortest_edge_path([v], |w| on_border[w as usize], steps, f64::INFINITY)
        else {
            continue;
        };
        for pair in path.windows(2) {
            if let Some(e) = table.find(pair[0], pair[1]) {
                seam[e] = true;
            }
            on_border[pair[0] as usize] = true;
            on_border[pair[1] as usize] = true;
        }
        slits += 1;
    }
    slits
}

/// The seams of `pieces` with a slit added from every vertex inside a piece whose angle
/// defect at `positions` (the developed shape) is still above `threshold` radians, the
/// largest first: the cone points the developability solve could not flatten (a sharp
/// tip, a saddle where a handle meets a body). Cutting them frees the solve of those
/// constraints; every other vertex inside a piece stays constrained to be flat.
///
/// On a half target (`mirror`), a vertex on the plane whose angle sum in the whole (twice
/// the half's) stays off 2π by more than the threshold is freed by a seam along one of
/// its edges in the plane: the whole is cut there, between the half and its image.
///
/// `only`: the vertices that may be cut free (the cone points a solve ended early
/// found hopeless, [`crate::Developed::hopeless`]: the others' defects are those of a
/// half-solved state), or `None` for every vertex.
///
/// Returns the seams (vertex pairs, for [`crate::seam_pieces`]) and the slits cut (0:
/// no vertex was above the threshold or none could be reached).
pub fn slit_unflattened_vertices(
    mesh: &TriangleMesh,
    positions: &[Vec3],
    table: &EdgeTable,
    pieces: &SeamPieces,
    mirror: Option<&MirrorBoundary>,
    threshold: f64,
    only: Option<&[u32]>,
) -> (Vec<[u32; 2]>, usize) {
    let angle_sum = vertex_angle_sums(positions, &mesh.triangles);
    let defect = |v: u32| (TAU - angle_sum[v as usize]).abs();
    let candidate = match only {
        Some(list) => {
            let mut flags = vec![false; mesh.positions.len()];
            for &v in list {
                if let Some(flag) = flags.get_mut(v as usize) {
                    *flag = true;
                }
            }
            flags
        }
        None => vec![true; mesh.positions.len()],
    };
    let mut cones: Vec<u32> = (0..mesh.positions.len() as u32)
        .filter(|&v| candidate[v as usize] && pieces.interior[v as usize] && defect(v) > threshold)
        .collect();
    cones.sort_by(|&a, &b| defect(b).total_cmp(&defect(a)));
    let mut seam = vec![false; table.len()];
    for &e in &pieces.seam_edges {
        seam[e] = true;
    }
    let mut plane_cuts = 0;
    if let Some(mirror) = mirror {
        let inside = mirror_interior(table, pieces, mirror.on_plane);
        let on_plane = |v: u32| mirror.on_plane[v as usize];
        let mut on_seam = vec![false; mesh.positions.len()];
        for (e, &[a, b]) in table.edges.iter().enumerate() {
            if seam[e] {
                on_seam[a as usize] = true;
                on_seam[b as usize] = true;
            }
        }
        for (e, &[a, b]) in table.edges.iter().enumerate() {
            let cone = |v: u32| {
                candidate[v as usize] && inside[v as usize] && (TAU - 2.0 * angle_sum[v as usize]).abs() > threshold
            };
            let along_plane = on_plane(a) && on_plane(b) && table.sides(e).len() == 1;
            // One edge along the plane frees the vertex (and its neighbour).
            if along_plane && [a, b].iter().any(|&v| cone(v) && !on_seam[v as usize]) {
                seam[e] = true;
                on_seam[a as usize] = true;
                on_seam[b as usize] = true;
                plane_cuts += 1;
            }
        }
    }
    let slits = cut_slits(mesh, table, &mut seam, &cones) + plane_cuts;
    let seams = (0..table.len()).filter(|&e| seam[e]).map(|e| table.edges[e]).collect();
    (seams, slits)
}

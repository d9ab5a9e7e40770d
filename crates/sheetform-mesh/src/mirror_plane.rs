//! A mesh cut in half by an axis-aligned mirror plane, and a half mirrored back into a
//! whole: the symmetry of `develop` (issue 36), as a modeller's mirror modifier does it.

use crate::{EdgeTable, MeshError, TriangleMesh};
use nalgebra::Vector3;

type Vec3 = Vector3<f64>;

/// A vertex with a neighbour across the plane and closer to it than this fraction of its
/// shortest edge is moved onto it (along the plane's normal) before the cut, so that the cut makes no triangle thinner
/// than a tenth of its neighbours' edges.
pub const MIRROR_SNAP: f64 = 0.1;

/// A vertex on the mesh's boundary closer to the plane than this fraction of its shortest
/// edge is moved onto it too: a half model's cut exported a hair off the plane (float32
/// coordinates, an export's rounding), which would otherwise come back as two halves.
pub const MIRROR_CUT_SNAP: f64 = 1e-3;

/// An axis-aligned mirror plane: the points with `p[axis] = offset` (model units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MirrorPlane {
    /// The plane's normal axis: 0 = x, 1 = y, 2 = z.
    pub axis: usize,
    /// Where the plane crosses that axis (model units).
    pub offset: f64,
}

impl MirrorPlane {
    /// The mirror image of `p`: its `axis` coordinate `c` becomes `2·offset − c`.
    pub fn reflect(&self, p: &Vec3) -> Vec3 {
        let mut q = *p;
        q[self.axis] = 2.0 * self.offset - p[self.axis];
        q
    }

    /// `x = 12.5` for the plane with axis 0 and offset 12.5.
    pub fn describe(&self) -> String {
        format!(
            "{} = {}",
            ["x", "y", "z"][self.axis.min(2)],
            sheetform_geometry::short_number(self.offset)
        )
    }
}

/// One side of a mesh cut along a [`MirrorPlane`].
#[derive(Debug, Clone, PartialEq)]
pub struct MirrorHalf {
    /// The faces on the kept side, the faces the plane crosses cut along it (new
    /// vertices where it crosses an edge). Groups and drawn seams follow (a seam the
    /// plane crosses is cut there); texture coordinates are dropped.
    pub mesh: TriangleMesh,
    /// Whether each vertex of `mesh` lies on the cut: on the plane (its `axis`
    /// coordinate is the plane's offset exactly) and on a boundary edge of the half
    /// along it. A vertex on the plane elsewhere (where the surface touches the plane)
    /// is not flagged.
    pub on_plane: Vec<bool>,
    /// The input vertex each vertex of `mesh` is (`u32::MAX`: new, where the plane
    /// crosses the edge between `crossed_edge`'s two vertices).
    pub source_vertex: Vec<u32>,
    /// For a new vertex, the input edge it lies on (`[u32::MAX; 2]` for the others).
    pub crossed_edge: Vec<[u32; 2]>,
    /// +1 when the side where `p[axis] > offset` is kept, −1 for the other (the side
    /// holding more of the surface's area is kept, + on a tie).
    pub side: f64,
    /// Input vertices moved onto the plane ([`MIRROR_SNAP`]).
    pub snapped_vertex_count: usize,
    /// Area of the input on the side kept and on the other (model units²; a half
    /// model has none on the other).
    pub side_areas: [f64; 2],
}

/// Cuts `mesh` along `plane` and keeps the side holding more of its area: a whole
/// symmetric model gives its half, a half model (all on one side, its cut along the
/// plane) is kept whole. Vertices within [`MIRROR_SNAP`] of their shortest edge from the
/// plane are first moved onto it (those flagged in `keep`, fixed vertices, only by
/// rounding noise: 1e-9 of an edge); each edge the plane then crosses gets a vertex on the
/// plane, and each crossed triangle is clipped to the kept side (Sutherland–Hodgman),
/// a clipped quadrilateral split along its shorter diagonal.
///
/// # Errors
/// [`MeshError::Mirror`] when nothing is left on either side (every face in the plane)
/// or a coordinate is not finite.
pub fn mirror_half(mesh: &TriangleMesh, plane: &MirrorPlane, keep: &[bool]) -> Result<MirrorHalf, MeshError> {
    let axis = plane.axis.min(2);
    let nv = mesh.positions.len();
    if let Some(v) = mesh.positions.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
        return Err(MeshError::NonFinite { vertex: v, which: "3D" });
    }
    // Shortest edge at each vertex, for the snap.
    let table = EdgeTable::new(&mesh.triangles, nv);
    let mut shortest = vec![f64::INFINITY; nv];
    for &[a, b] in &table.edges {
        let length = (mesh.positions[a as usize] - mesh.positions[b as usize]).norm();
        for v in [a, b] {
            shortest[v as usize] = shortest[v as usize].min(length);
        }
    }
    // Only a vertex with a neighbour across the plane is snapped (where the cut would
    // pass close by it); one whose neighbours are all on its side stays.
    let mut crossed = vec![false; nv];
    for &[a, b] in &table.edges {
        let (sa, sb) = (
            mesh.positions[a as usize][axis] - plane.offset,
            mesh.positions[b as usize][axis] - plane.offset,
        );
        if sa * sb < 0.0 {
            crossed[a as usize] = true;
            crossed[b as usize] = true;
        }
    }
    let mut on_boundary = vec![false; nv];
    for [a, b] in table.boundary_edges() {
        on_boundary[a as usize] = true;
        on_boundary[b as usize] = true;
    }
    let mut positions = mesh.positions.clone();
    let mut snapped_vertex_count = 0;
    for (v, p) in positions.iter_mut().enumerate() {
        let distance = (p[axis] - plane.offset).abs();
        let edge = shortest[v];
        let kept = keep.get(v).copied().unwrap_or(false);
        let reach = if kept && (crossed[v] || on_boundary[v]) {
            // A kept vertex moves by rounding noise at most (a cut through it would
            // otherwise leave faces of no area).
            1e-9
        } else if crossed[v] {
            MIRROR_SNAP
        } else if on_boundary[v] {
            MIRROR_CUT_SNAP
        } else {
            0.0
        };
        if distance > 0.0 && edge.is_finite() && distance <= reach * edge {
            p[axis] = plane.offset;
            snapped_vertex_count += 1;
        }
    }
    let signed: Vec<f64> = positions.iter().map(|p| p[axis] - plane.offset).collect();
    // The side with more area (each face's area to the side of its centroid).
    let mut area = [0.0f64; 2];
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|v| positions[v as usize]);
        let centroid = (signed[t[0] as usize] + signed[t[1] as usize] + signed[t[2] as usize]) / 3.0;
        let face = 0.5 * (b - a).cross(&(c - a)).norm();
        if centroid > 0.0 {
            area[0] += face;
        } else if centroid < 0.0 {
            area[1] += face;
        }
    }
    if area[0] <= 0.0 && area[1] <= 0.0 {
        return Err(MeshError::Mirror {
            problem: format!("the mesh lies in the plane {}", plane.describe()),
        });
    }
    let side = if area[0] >= area[1] { 1.0 } else { -1.0 };
    let side_areas = if side > 0.0 { area } else { [area[1], area[0]] };
    let s: Vec<f64> = signed.iter().map(|d| d * side).collect();
    // The kept vertices, then one new vertex per crossed edge.
    let mut index = vec![u32::MAX; nv];
    let mut half = TriangleMesh {
        groups: mesh.groups.clone(),
        ..Default::default()
    };
    let mut on_plane = Vec::new();
    let mut source_vertex = Vec::new();
    let mut crossed_edge = Vec::new();
    for v in 0..nv {
        if s[v] >= 0.0 {
            index[v] = half.positions.len() as u32;
            half.positions.push(positions[v]);
            on_plane.push(s[v] == 0.0);
            source_vertex.push(v as u32);
            crossed_edge.push([u32::MAX; 2]);
        }
    }
    let mut crossing = vec![u32::MAX; table.len()];
    for (e, &[a, b]) in table.edges.iter().enumerate() {
        let (sa, sb) = (s[a as usize], s[b as usize]);
        if sa * sb < 0.0 {
            let t = sa / (sa - sb);
            let mut p = positions[a as usize] + (positions[b as usize] - positions[a as usize]) * t;
            p[axis] = plane.offset;
            crossing[e] = half.positions.len() as u32;
            half.positions.push(p);
            on_plane.push(true);
            source_vertex.push(u32::MAX);
            crossed_edge.push([a, b]);
        }
    }
    let point = |a: u32, b: u32| -> u32 {
        let e = table.find(a, b).expect("a triangle's side is an edge");
        crossing[e]
    };
    let mut used = vec![false; half.positions.len()];
    for (f, t) in mesh.triangles.iter().enumerate() {
        let group = mesh.face_groups.get(f).copied().unwrap_or(0);
        if t.iter().all(|&v| s[v as usize] >= 0.0) {
            if t.iter().all(|&v| s[v as usize] == 0.0) {
                continue; // a face in the plane belongs to neither side
            }
            half.triangles.push(t.map(|v| index[v as usize]));
            half.face_groups.push(group);
            continue;
        }
        // Sutherland–Hodgman: the polygon of the kept side, in the triangle's order.
        let mut polygon: Vec<u32> = Vec::with_capacity(4);
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if s[a as usize] >= 0.0 {
                polygon.push(index[a as usize]);
            }
            if s[a as usize] * s[b as usize] < 0.0 {
                polygon.push(point(a, b));
            }
        }
        let inside = polygon.iter().any(|&v| !on_plane[v as usize]);
        match polygon.len() {
            3 if inside => {
                half.triangles.push([polygon[0], polygon[1], polygon[2]]);
                half.face_groups.push(group);
            }
            4 => {
                let p = |i: usize| half.positions[polygon[i] as usize];
                let split_02 = (p(0) - p(2)).norm() <= (p(1) - p(3)).norm();
                let pair = if split_02 {
                    [[0, 1, 2], [0, 2, 3]]
                } else {
                    [[0, 1, 3], [1, 2, 3]]
                };
                for tri in pair {
                    half.triangles.push(tri.map(|i| polygon[i]));
                    half.face_groups.push(group);
                }
            }
            _ => {}
        }
    }
    for t in &half.triangles {
        for &v in t {
            used[v as usize] = true;
        }
    }
    // Drawn seams: kept on the kept side, cut where the plane crosses them.
    for &[a, b] in &mesh.seam_edges {
        let (sa, sb) = (s[a as usize], s[b as usize]);
        if sa >= 0.0 && sb >= 0.0 {
            half.seam_edges.push([index[a as usize], index[b as usize]]);
        } else if sa * sb < 0.0 {
            if let Some(e) = table.find(a, b) {
                let kept = if sa > 0.0 { a } else { b };
                half.seam_edges.push([index[kept as usize], crossing[e]]);
            }
        }
    }
    // Vertices of the kept side that no kept face uses (on the plane, touching only the
    // other side) are dropped.
    let mut compact = vec![u32::MAX; half.positions.len()];
    let mut next = 0u32;
    for (v, &u) in used.iter().enumerate() {
        if u {
            compact[v] = next;
            next += 1;
        }
    }
    fn retain_used<T>(values: &mut Vec<T>, used: &[bool]) {
        let mut i = 0;
        values.retain(|_| {
            i += 1;
            used[i - 1]
        });
    }
    retain_used(&mut half.positions, &used);
    retain_used(&mut on_plane, &used);
    retain_used(&mut source_vertex, &used);
    retain_used(&mut crossed_edge, &used);
    for t in &mut half.triangles {
        *t = t.map(|v| compact[v as usize]);
    }
    // Only a vertex on the half's cut is shared with the image: one on the plane inside
    // the half (the surface touching the plane without crossing it) would join the two
    // fans into one non-manifold vertex, so it gets an image of its own.
    let half_table = EdgeTable::new(&half.triangles, half.positions.len());
    let mut on_cut = vec![false; half.positions.len()];
    for [a, b] in half_table.boundary_edges() {
        if on_plane[a as usize] && on_plane[b as usize] {
            on_cut[a as usize] = true;
            on_cut[b as usize] = true;
        }
    }
    for (on, cut) in on_plane.iter_mut().zip(on_cut) {
        *on &= cut;
    }
    half.seam_edges
        .retain(|e| e.iter().all(|&v| compact[v as usize] != u32::MAX));
    for e in &mut half.seam_edges {
        *e = e.map(|v| compact[v as usize]);
    }
    Ok(MirrorHalf {
        mesh: half,
        on_plane,
        source_vertex,
        crossed_edge,
        side,
        snapped_vertex_count,
        side_areas,
    })
}

/// A half and its mirror image joined along the plane.
#[derive(Debug, Clone, PartialEq)]
pub struct MirroredWhole {
    /// The whole mesh: the half's vertices first (same indices), then the mirror images
    /// of those off the plane; the half's faces, then their images (orientation
    /// reversed, so the whole is oriented consistently); the half's seams and their
    /// images.
    pub mesh: TriangleMesh,
    /// The half vertex each whole vertex is or mirrors.
    pub half_vertex: Vec<u32>,
}

/// Joins `half` and its mirror image in `plane`, sharing the vertices `on_plane` (each
/// put on the plane exactly). The angle sum of a shared vertex is twice its sum in the
/// half, so it is flat in the whole when its half sum is π.
pub fn mirror_whole(half: &TriangleMesh, on_plane: &[bool], plane: &MirrorPlane) -> MirroredWhole {
    let plane = MirrorPlane {
        axis: plane.axis.min(2),
        ..*plane
    };
    let nv = half.positions.len();
    let mut mesh = half.clone();
    mesh.corner_uvs = None;
    let mut half_vertex: Vec<u32> = (0..nv as u32).collect();
    let mut image = vec![0u32; nv];
    for v in 0..nv {
        if on_plane[v] {
            mesh.positions[v][plane.axis] = plane.offset;
            image[v] = v as u32;
        } else {
            image[v] = mesh.positions.len() as u32;
            mesh.positions.push(plane.reflect(&half.positions[v]));
            half_vertex.push(v as u32);
        }
    }
    let grouped = half.face_groups.len() == half.triangles.len();
    for (f, t) in half.triangles.iter().enumerate() {
        mesh.triangles
            .push([image[t[0] as usize], image[t[2] as usize], image[t[1] as usize]]);
        if grouped {
            mesh.face_groups.push(half.face_groups[f]);
        }
    }
    for &[a, b] in &half.seam_edges {
        let (a, b) = (image[a as usize], image[b as usize]);
        if !(on_plane[half_vertex[a as usize] as usize] && on_plane[half_vertex[b as usize] as usize]) {
            mesh.seam_edges.push([a, b]);
        }
    }
    MirroredWhole { mesh, half_vertex }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{mesh_topology, vertex_angle_sums};
    use std::f64::consts::{PI, TAU};

    /// A cylinder side around the y axis, 16 sections (one vertex every 22.5°, so the
    /// plane x = 0 runs through vertices) or 15 (so it crosses edges).
    fn cylinder(sections: usize) -> TriangleMesh {
        TriangleMesh::grid(sections, 4, |u, v| {
            let t = TAU * u;
            [10.0 * t.cos(), 20.0 * v, 10.0 * t.sin()]
        })
    }

    /// Cut in half and mirrored back, a cylinder side keeps its area and its boundary,
    /// the half lies on one side of the plane, and the whole is a clean manifold whose
    /// plane vertices have angle sum twice the half's.
    #[test]
    fn a_cylinder_cut_in_half_and_mirrored_is_whole_again() {
        for sections in [15, 16, 31] {
            let mesh = cylinder(sections);
            let plane = MirrorPlane { axis: 0, offset: 0.0 };
            let half = mirror_half(&mesh, &plane, &[]).unwrap();
            let area = |m: &TriangleMesh| -> f64 {
                m.triangles
                    .iter()
                    .map(|t| {
                        let [a, b, c] = t.map(|v| m.positions[v as usize]);
                        0.5 * (b - a).cross(&(c - a)).norm()
                    })
                    .sum()
            };
            for (p, &on) in half.mesh.positions.iter().zip(&half.on_plane) {
                assert!(p.x * half.side >= 0.0, "{p:?} on the wrong side");
                assert_eq!(on, p.x == 0.0);
            }
            assert!(
                mesh_topology(&half.mesh).is_clean(),
                "{:?}",
                mesh_topology(&half.mesh).problems()
            );
            let whole = mirror_whole(&half.mesh, &half.on_plane, &plane);
            let topology = mesh_topology(&whole.mesh);
            assert!(topology.is_clean(), "{:?}", topology.problems());
            assert_eq!(topology.boundary_loop_count, 2, "{sections} sections");
            // The seam-free whole has the cylinder's area up to the snap's change (the
            // cylinder is not symmetric in x = 0 for odd section counts: a loose bound).
            let ratio = area(&whole.mesh) / area(&mesh);
            assert!((ratio - 1.0).abs() < 0.02, "{sections}: area ratio {ratio}");
            // Plane vertices: the whole's angle sum is twice the half's.
            let half_sums = vertex_angle_sums(&half.mesh.positions, &half.mesh.triangles);
            let whole_sums = vertex_angle_sums(&whole.mesh.positions, &whole.mesh.triangles);
            for v in 0..half.mesh.positions.len() {
                if half.on_plane[v] {
                    assert!((whole_sums[v] - 2.0 * half_sums[v]).abs() < 1e-12);
                }
            }
            // Every vertex off the plane has its image in the plane's mirror.
            for (w, &h) in whole.half_vertex.iter().enumerate() {
                let expected = if w < half.mesh.positions.len() {
                    half.mesh.positions[h as usize]
                } else {
                    plane.reflect(&half.mesh.positions[h as usize])
                };
                assert_eq!(whole.mesh.positions[w], expected);
            }
            // A plane vertex of a flat interior (the rims excepted) has half sum π.
            let table = EdgeTable::new(&half.mesh.triangles, half.mesh.positions.len());
            let on_rim: Vec<bool> = {
                let mut rim = vec![false; half.mesh.positions.len()];
                for [a, b] in table.boundary_edges() {
                    if !(half.on_plane[a as usize] && half.on_plane[b as usize]) {
                        rim[a as usize] = true;
                        rim[b as usize] = true;
                    }
                }
                rim
            };
            for v in 0..half.mesh.positions.len() {
                if half.on_plane[v] && !on_rim[v] {
                    assert!(
                        (half_sums[v] - PI).abs() < 1e-9,
                        "{sections}: vertex {v} half sum {}",
                        half_sums[v]
                    );
                }
            }
        }
    }

    /// A surface that touches the plane along a line without crossing it keeps that
    /// line's vertices to itself: the whole is two sheets meeting there, each a clean
    /// manifold, not one with vertices where four fans meet.
    #[test]
    fn a_surface_touching_the_plane_is_not_joined_there() {
        let trough = TriangleMesh::grid(8, 6, |u, v| {
            let y = 20.0 * u - 10.0;
            [y * y / 50.0, y, 10.0 * v]
        });
        let plane = MirrorPlane { axis: 0, offset: 0.0 };
        let half = mirror_half(&trough, &plane, &[]).unwrap();
        assert_eq!(half.mesh.triangles.len(), trough.triangles.len());
        assert!(half.mesh.positions.iter().any(|p| p.x == 0.0));
        assert!(half.on_plane.iter().all(|&on| !on));
        let whole = mirror_whole(&half.mesh, &half.on_plane, &plane);
        let topology = mesh_topology(&whole.mesh);
        assert!(topology.is_clean(), "{:?}", topology.problems());
        assert_eq!(whole.mesh.positions.len(), 2 * trough.positions.len());
    }

    /// A half model whose cut was exported a hair off the plane (1e-6 on the kept side) is
    /// snapped onto it: the whole is one sheet with one boundary loop, not two halves;
    /// a vertex flagged to keep is not moved.
    #[test]
    fn a_half_model_a_hair_off_the_plane_is_joined() {
        let mut saddle = TriangleMesh::grid(12, 18, |u, v| {
            let (x, y) = (40.0 * u, 60.0 * v - 30.0);
            [x, y, (x * x - y * y) / 80.0]
        });
        // All on the kept side: no edge crosses the plane, only the boundary rule snaps.
        for p in &mut saddle.positions {
            if p.x == 0.0 {
                p.x = 1e-6;
            }
        }
        let plane = MirrorPlane { axis: 0, offset: 0.0 };
        let half = mirror_half(&saddle, &plane, &[]).unwrap();
        assert_eq!(half.on_plane.iter().filter(|&&on| on).count(), 19);
        assert_eq!(half.side_areas[1], 0.0);
        let whole = mirror_whole(&half.mesh, &half.on_plane, &plane);
        let topology = mesh_topology(&whole.mesh);
        assert!(topology.is_clean() && topology.boundary_loop_count == 1, "{topology:?}");
        let mut keep = vec![false; saddle.positions.len()];
        keep[0] = true;
        let half = mirror_half(&saddle, &plane, &keep).unwrap();
        assert_eq!(half.mesh.positions[0].x, 1e-6);
    }

    /// A half model (everything on one side, its cut on the plane) is kept whole, and
    /// the side with more area is kept when the plane is off centre.
    #[test]
    fn the_side_with_more_area_is_kept() {
        let mesh = cylinder(16);
        let half = mirror_half(&mesh, &MirrorPlane { axis: 0, offset: -12.0 }, &[]).unwrap();
        assert_eq!(half.mesh.triangles.len(), mesh.triangles.len());
        assert_eq!(half.side, 1.0);
        let other = mirror_half(&mesh, &MirrorPlane { axis: 0, offset: 5.0 }, &[]).unwrap();
        assert_eq!(other.side, -1.0);
        assert!(other.mesh.positions.iter().all(|p| p.x <= 5.0));
        let flat = TriangleMesh::grid(2, 2, |u, v| [0.0, u, v]);
        let err = mirror_half(&flat, &MirrorPlane { axis: 0, offset: 0.0 }, &[]).unwrap_err();
        assert!(err.to_string().contains("x = 0"), "{err}");
    }
}

//! Primitive shapes (as `trimesh.creation` makes them): boxes, icospheres, tori,
//! cylinders, cones and hemispheres, every face counter-clockwise seen from outside.
//! The shapes a maker tries first, and the test meshes of flattening and unfolding.

use crate::TriangleMesh;
use nalgebra::Vector3;
use std::collections::HashMap;
use std::f64::consts::{FRAC_PI_2, TAU};

type Vec3 = Vector3<f64>;

fn mesh(name: &str, positions: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> TriangleMesh {
    TriangleMesh {
        positions,
        face_groups: vec![0; triangles.len()],
        triangles,
        groups: vec![name.into()],
        corner_uvs: None,
        seam_edges: Vec::new(),
    }
}

/// An axis-aligned box of `size` centred at the origin: 8 vertices, 12 triangles (two per
/// side, split along a diagonal).
pub fn cuboid(size: [f64; 3]) -> TriangleMesh {
    let h = Vec3::from(size) * 0.5;
    let positions = (0..8)
        .map(|i| {
            Vec3::new(
                if i & 1 == 0 { -h.x } else { h.x },
                if i & 2 == 0 { -h.y } else { h.y },
                if i & 4 == 0 { -h.z } else { h.z },
            )
        })
        .collect();
    // Each side as a counter-clockwise quad seen from outside.
    let quads = [
        [0, 2, 3, 1], // z−
        [4, 5, 7, 6], // z+
        [0, 1, 5, 4], // y−
        [2, 6, 7, 3], // y+
        [0, 4, 6, 2], // x−
        [1, 3, 7, 5], // x+
    ];
    let triangles = quads.iter().flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]]).collect();
    mesh("box", positions, triangles)
}

/// A sphere of `radius` from an icosahedron whose faces are split in four `subdivisions`
/// times, new vertices pushed onto the sphere: `20 · 4^subdivisions` triangles.
pub fn icosphere(radius: f64, subdivisions: u32) -> TriangleMesh {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut positions: Vec<Vec3> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .iter()
    .map(|&p| Vec3::from(p).normalize() * radius)
    .collect();
    let mut triangles: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut middle: HashMap<[u32; 2], u32> = HashMap::new();
        let mut split = |a: u32, b: u32, positions: &mut Vec<Vec3>| {
            *middle.entry([a.min(b), a.max(b)]).or_insert_with(|| {
                let p = (positions[a as usize] + positions[b as usize]).normalize() * radius;
                positions.push(p);
                positions.len() as u32 - 1
            })
        };
        triangles = triangles
            .iter()
            .flat_map(|&[a, b, c]| {
                let ab = split(a, b, &mut positions);
                let bc = split(b, c, &mut positions);
                let ca = split(c, a, &mut positions);
                [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
            })
            .collect();
    }
    mesh("icosphere", positions, triangles)
}

/// A torus around the z axis: tube centre circle of radius `major`, tube radius `minor`,
/// `major_sections × minor_sections` quads split in two.
pub fn torus(major: f64, minor: f64, major_sections: usize, minor_sections: usize) -> TriangleMesh {
    let (n, m) = (major_sections.max(3), minor_sections.max(3));
    let mut positions = Vec::with_capacity(n * m);
    for i in 0..n {
        let u = TAU * i as f64 / n as f64;
        for j in 0..m {
            let v = TAU * j as f64 / m as f64;
            let r = major + minor * v.cos();
            positions.push(Vec3::new(r * u.cos(), r * u.sin(), minor * v.sin()));
        }
    }
    let id = |i: usize, j: usize| ((i % n) * m + j % m) as u32;
    let mut triangles = Vec::with_capacity(2 * n * m);
    for i in 0..n {
        for j in 0..m {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    mesh("torus", positions, triangles)
}

/// Points `0..sections` of a circle of `radius` at height `z`.
fn circle(radius: f64, z: f64, sections: usize) -> impl Iterator<Item = Vec3> {
    (0..sections).map(move |i| {
        let a = TAU * i as f64 / sections as f64;
        Vec3::new(radius * a.cos(), radius * a.sin(), z)
    })
}

/// A fan closing the ring `ring` (vertex indices in counter-clockwise order seen from +z)
/// around a new centre vertex at `centre`; `up`: the fan faces +z.
fn cap(positions: &mut Vec<Vec3>, triangles: &mut Vec<[u32; 3]>, ring: &[u32], centre: Vec3, up: bool) {
    positions.push(centre);
    let c = positions.len() as u32 - 1;
    let n = ring.len();
    for i in 0..n {
        let (a, b) = (ring[i], ring[(i + 1) % n]);
        triangles.push(if up { [c, a, b] } else { [c, b, a] });
    }
}

/// A cylinder of `radius` from z = 0 to `height` around the z axis, `sections` planar
/// rectangles around (each split in two); `capped`: closed by two fans (otherwise an open
/// tube, an annulus).
pub fn cylinder(radius: f64, height: f64, sections: usize, capped: bool) -> TriangleMesh {
    let n = sections.max(3);
    let mut positions: Vec<Vec3> = circle(radius, 0.0, n).chain(circle(radius, height, n)).collect();
    let mut triangles = Vec::with_capacity(4 * n);
    for i in 0..n {
        let (a, b) = (i as u32, ((i + 1) % n) as u32);
        let (c, d) = (b + n as u32, a + n as u32);
        triangles.push([a, b, c]);
        triangles.push([a, c, d]);
    }
    if capped {
        let bottom: Vec<u32> = (0..n as u32).collect();
        let top: Vec<u32> = (n as u32..2 * n as u32).collect();
        cap(&mut positions, &mut triangles, &bottom, Vec3::zeros(), false);
        cap(&mut positions, &mut triangles, &top, Vec3::new(0.0, 0.0, height), true);
    }
    mesh("cylinder", positions, triangles)
}

/// A cone with its base circle of `radius` at z = 0 and its apex at z = `height`,
/// `sections` triangles from the apex (the rulings are mesh edges); `capped`: closed by a
/// fan over the base (otherwise open, a disk whose apex is a cone point).
pub fn cone(radius: f64, height: f64, sections: usize, capped: bool) -> TriangleMesh {
    let n = sections.max(3);
    let mut positions: Vec<Vec3> = circle(radius, 0.0, n).collect();
    positions.push(Vec3::new(0.0, 0.0, height));
    let apex = n as u32;
    let mut triangles: Vec<[u32; 3]> = (0..n).map(|i| [i as u32, ((i + 1) % n) as u32, apex]).collect();
    if capped {
        let ring: Vec<u32> = (0..n as u32).collect();
        cap(&mut positions, &mut triangles, &ring, Vec3::zeros(), false);
    }
    mesh("cone", positions, triangles)
}

/// The upper half of a sphere of `radius` (open at the equator, a disk): `rings` latitude
/// bands of `sections` quads from the equator up, closed by a fan at the pole.
pub fn hemisphere(radius: f64, rings: usize, sections: usize) -> TriangleMesh {
    let (n, r) = (sections.max(3), rings.max(1));
    let mut positions = Vec::with_capacity(n * r + 1);
    for k in 0..r {
        let latitude = FRAC_PI_2 * k as f64 / r as f64;
        positions.extend(circle(radius * latitude.cos(), radius * latitude.sin(), n));
    }
    let id = |k: usize, i: usize| (k * n + i % n) as u32;
    let mut triangles = Vec::with_capacity(2 * n * r);
    for k in 0..r - 1 {
        for i in 0..n {
            let (a, b, c, d) = (id(k, i), id(k, i + 1), id(k + 1, i + 1), id(k + 1, i));
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    let top: Vec<u32> = (0..n).map(|i| id(r - 1, i)).collect();
    cap(&mut positions, &mut triangles, &top, Vec3::new(0.0, 0.0, radius), true);
    mesh("hemisphere", positions, triangles)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh_topology;

    fn volume(m: &TriangleMesh) -> f64 {
        m.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| m.positions[i as usize]);
                a.dot(&b.cross(&c)) / 6.0
            })
            .sum()
    }

    #[test]
    fn closed_primitives_are_clean_outward_surfaces_of_the_right_genus_and_volume() {
        let cases = [
            (cuboid([1.0, 2.0, 3.0]), 2, 6.0),
            (icosphere(1.0, 3), 2, 4.0 / 3.0 * std::f64::consts::PI),
            (
                torus(2.0, 0.5, 48, 24),
                0,
                2.0 * std::f64::consts::PI.powi(2) * 2.0 * 0.25,
            ),
            (cylinder(1.0, 2.0, 64, true), 2, std::f64::consts::PI * 2.0),
            (cone(1.0, 2.0, 64, true), 2, std::f64::consts::PI * 2.0 / 3.0),
        ];
        for (m, euler, v) in cases {
            let t = mesh_topology(&m);
            assert!(t.is_clean() && t.consistently_oriented, "{}: {t:?}", m.groups[0]);
            assert_eq!(
                (t.euler_characteristic, t.boundary_loop_count),
                (euler, 0),
                "{}",
                m.groups[0]
            );
            // Outward: positive volume within the discretisation error.
            let rel = (volume(&m) - v) / v;
            assert!(rel < 1e-12 && rel > -0.02, "{}: {} vs {v}", m.groups[0], volume(&m));
        }
    }

    #[test]
    fn open_primitives_have_the_expected_boundaries() {
        let tube = mesh_topology(&cylinder(1.0, 2.0, 16, false));
        assert_eq!((tube.euler_characteristic, tube.boundary_loop_count), (0, 2));
        let cone = mesh_topology(&cone(1.0, 2.0, 16, false));
        assert_eq!((cone.euler_characteristic, cone.boundary_loop_count), (1, 1));
        let dome = mesh_topology(&hemisphere(1.0, 6, 16));
        assert_eq!((dome.euler_characteristic, dome.boundary_loop_count), (1, 1));
        assert!(dome.consistently_oriented && dome.is_clean());
    }
}

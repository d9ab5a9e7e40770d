//! `develop_pieces` on shapes with known answers: a developable target stays put, a
//! perturbed cylinder becomes exactly developable again near where it was, a sphere cut
//! into gores becomes gores within the globe-gore bound.

use nalgebra::Vector3;
use sheetform_develop::{develop_pieces, mirror_interior, seam_pieces, DevelopOptions, MirrorBoundary};
use sheetform_mesh::{vertex_developability, EdgeTable, MeshTopology, TriangleMesh};

/// A grid over `(u, v)` in `[0, 1]²` ([`TriangleMesh::grid`]).
fn grid(nu: usize, nv: usize, surface: impl Fn(f64, f64) -> Vector3<f64>) -> TriangleMesh {
    TriangleMesh::grid(nu, nv, |u, v| surface(u, v).into())
}

/// Half a cylinder of radius 30, height 50 (exactly developable), `nu × nv` cells.
fn half_cylinder(nu: usize, nv: usize) -> TriangleMesh {
    grid(nu, nv, |u, v| {
        let t = std::f64::consts::PI * u;
        Vector3::new(30.0 * t.cos(), 30.0 * t.sin(), 50.0 * v)
    })
}

/// A pseudo-random number in `[-0.5, 0.5)` (fixed seed).
fn random(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6_364_136_223_846_793_005)
        .wrapping_add(1_442_695_040_888_963_407);
    (*seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
}

/// The largest angle defect over the vertices `interior` marks (radians).
fn max_interior_defect(mesh: &TriangleMesh, interior: &[bool]) -> f64 {
    let topology: MeshTopology = sheetform_mesh::mesh_topology(mesh);
    let defects = vertex_developability(mesh, &topology).angle_defect;
    defects
        .iter()
        .zip(interior)
        .filter(|(_, inside)| **inside)
        .fold(0.0, |m, (d, _)| m.max(d.abs()))
}

#[test]
fn a_developable_target_comes_back_unchanged() {
    let mesh = half_cylinder(24, 10);
    let table = EdgeTable::new(&mesh.triangles, mesh.positions.len());
    let pieces = seam_pieces(&mesh, &table, &[]).unwrap();
    let developed = develop_pieces(&mesh, &table, &pieces, &[], None, &DevelopOptions::default(), None).unwrap();
    assert!(developed.converged && developed.max_defect <= 1e-10, "{developed:?}");
    assert!(
        developed.displacement_max <= 1e-6,
        "moved {}",
        developed.displacement_max
    );
}

#[test]
fn a_perturbed_cylinder_becomes_exactly_developable_near_the_target() {
    let mut seed = 17;
    let mut mesh = half_cylinder(24, 12);
    for p in &mut mesh.positions {
        *p += Vector3::new(random(&mut seed), random(&mut seed), random(&mut seed)) * 0.4;
    }
    let table = EdgeTable::new(&mesh.triangles, mesh.positions.len());
    let pieces = seam_pieces(&mesh, &table, &[]).unwrap();
    let before = max_interior_defect(&mesh, &pieces.interior);
    assert!(before > 1e-2, "{before}");
    let developed = develop_pieces(&mesh, &table, &pieces, &[], None, &DevelopOptions::default(), None).unwrap();
    let mut result = mesh.clone();
    result.positions = developed.positions.clone();
    // Checked on the result's own angles, not the solver's figure.
    let after = max_interior_defect(&result, &pieces.interior);
    assert!(developed.converged && after <= 1e-9, "{after} {developed:?}");
    // No farther than the noise put it (0.35 mm at most per coordinate).
    assert!(developed.displacement_max <= 1.0, "{developed:?}");
}

#[test]
fn a_sphere_cut_into_twelve_gores_becomes_gores_within_the_globe_bound() {
    let (radius, rings, sections) = (50.0, 24usize, 48usize);
    // A UV sphere without pole caps' duplicate vertices: rings of `sections` vertices and
    // two poles.
    let mut mesh = TriangleMesh::default();
    mesh.positions.push(Vector3::new(0.0, 0.0, -radius));
    for r in 1..rings {
        let phi = std::f64::consts::PI * r as f64 / rings as f64 - std::f64::consts::FRAC_PI_2;
        for s in 0..sections {
            let t = std::f64::consts::TAU * s as f64 / sections as f64;
            mesh.positions.push(Vector3::new(
                radius * phi.cos() * t.cos(),
                radius * phi.cos() * t.sin(),
                radius * phi.sin(),
            ));
        }
    }
    mesh.positions.push(Vector3::new(0.0, 0.0, radius));
    let north = (mesh.positions.len() - 1) as u32;
    let at = |r: usize, s: usize| (1 + (r - 1) * sections + s % sections) as u32;
    for s in 0..sections {
        mesh.triangles.push([0, at(1, s + 1), at(1, s)]);
        mesh.triangles.push([north, at(rings - 1, s), at(rings - 1, s + 1)]);
    }
    for r in 1..rings - 1 {
        for s in 0..sections {
            mesh.triangles.push([at(r, s), at(r, s + 1), at(r + 1, s + 1)]);
            mesh.triangles.push([at(r, s), at(r + 1, s + 1), at(r + 1, s)]);
        }
    }
    // Seams along 12 meridians, pole to pole.
    let mut seams = Vec::new();
    for g in 0..12 {
        let s = g * sections / 12;
        seams.push([0, at(1, s)]);
        for r in 1..rings - 1 {
            seams.push([at(r, s), at(r + 1, s)]);
        }
        seams.push([at(rings - 1, s), north]);
    }
    let table = EdgeTable::new(&mesh.triangles, mesh.positions.len());
    let pieces = seam_pieces(&mesh, &table, &seams).unwrap();
    assert_eq!(pieces.piece_count, 12);
    let developed = develop_pieces(&mesh, &table, &pieces, &[], None, &DevelopOptions::default(), None).unwrap();
    let mut result = mesh.clone();
    result.positions = developed.positions.clone();
    let after = max_interior_defect(&result, &pieces.interior);
    assert!(developed.converged && after <= 1e-9, "{after} {developed:?}");
    // Globe gores of 30° keep within R (1 − cos 15°) of the sphere.
    let bound = radius * (1.0 - 15f64.to_radians().cos());
    let off_sphere = result
        .positions
        .iter()
        .map(|p| (p.norm() - radius).abs())
        .fold(0.0, f64::max);
    eprintln!(
        "gores: {} steps, defect {:.1e} -> {:.1e} rad, off the sphere {off_sphere:.3} mm (bound {bound:.3}), moved max {:.3} mean {:.3} mm",
        developed.iterations, developed.max_defect_before, after, developed.displacement_max, developed.displacement_mean
    );
    assert!(off_sphere <= bound, "{off_sphere} > {bound}; {developed:?}");
}

/// Fixed vertices do not move at all while the rest of the perturbed cylinder is made
/// developable; a fixed patch that is not developable itself (its vertices inside
/// perturbed, their whole stars fixed) cannot be flattened and is reported out of
/// tolerance rather than hidden.
#[test]
fn fixed_vertices_stay_exactly_where_they_are() {
    let mut seed = 5;
    let mut mesh = half_cylinder(24, 12);
    let target = mesh.positions.clone();
    // The strip u ≤ 1/4 is fixed (developable: still on the cylinder).
    let fixed: Vec<bool> = target
        .iter()
        .map(|p| p.x >= 30.0 * (std::f64::consts::PI / 4.0).cos() - 1e-9 && p.y >= 0.0)
        .collect();
    for (p, &f) in mesh.positions.iter_mut().zip(&fixed) {
        if !f {
            *p += Vector3::new(random(&mut seed), random(&mut seed), random(&mut seed)) * 0.4;
        }
    }
    let table = EdgeTable::new(&mesh.triangles, mesh.positions.len());
    let pieces = seam_pieces(&mesh, &table, &[]).unwrap();
    assert!(fixed.iter().filter(|&&f| f).count() > 20);
    // Both step systems: the metric's diagonal (light smoothness) and the full metric.
    for smoothness in [0.1, 1.0] {
        let options = DevelopOptions {
            smoothness,
            ..Default::default()
        };
        let developed = develop_pieces(&mesh, &table, &pieces, &fixed, None, &options, None).unwrap();
        let mut result = mesh.clone();
        result.positions = developed.positions.clone();
        assert!(
            developed.converged && max_interior_defect(&result, &pieces.interior) <= 1e-9,
            "smoothness {smoothness}: {developed:?}"
        );
        for ((p, q), &f) in developed.positions.iter().zip(&mesh.positions).zip(&fixed) {
            if f {
                assert_eq!(p, q, "smoothness {smoothness}");
            }
        }
    }
    // The same strip bent out of developability (a bump in the middle of it): pinned.
    let mut bumped = mesh.clone();
    let middle = (0..bumped.positions.len())
        .filter(|&v| fixed[v] && pieces.interior[v])
        .max_by(|&a, &b| {
            (target[a].z - 25.0)
                .abs()
                .total_cmp(&(target[b].z - 25.0).abs())
                .reverse()
        })
        .unwrap();
    bumped.positions[middle] += Vector3::new(2.0, 0.0, 0.0);
    let developed = develop_pieces(&bumped, &table, &pieces, &fixed, None, &DevelopOptions::default(), None).unwrap();
    assert!(!developed.converged && developed.max_defect > 1e-3, "{developed:?}");
    assert_eq!(developed.positions[middle], bumped.positions[middle]);
}

/// A perturbed half cylinder cut at x = 0 by its mirror plane, developed as a half: the
/// plane vertices keep their x exactly, those inside the whole get half angle sum π, and
/// the half joined with its mirror image is flat at every interior vertex (2π there,
/// twice the half's sum), checked on the joined mesh's own angles.
#[test]
fn a_half_developed_against_its_mirror_plane_is_flat_when_joined() {
    let mut seed = 5;
    // The quarter x ≥ 0 of the half cylinder: u in [0, 1/2], its edge u = 1/2 on x = 0.
    let mut mesh = grid(12, 10, |u, v| {
        let t = std::f64::consts::FRAC_PI_2 * u;
        Vector3::new(30.0 * t.cos(), 30.0 * t.sin(), 50.0 * v)
    });
    let on_plane: Vec<bool> = mesh.positions.iter().map(|p| p.x.abs() < 1e-9).collect();
    for (p, &on) in mesh.positions.iter_mut().zip(&on_plane) {
        *p += Vector3::new(random(&mut seed), random(&mut seed), random(&mut seed)) * 0.4;
        if on {
            p.x = 0.0;
        }
    }
    assert_eq!(on_plane.iter().filter(|&&on| on).count(), 11);
    let table = EdgeTable::new(&mesh.triangles, mesh.positions.len());
    let pieces = seam_pieces(&mesh, &table, &[]).unwrap();
    let inside = mirror_interior(&table, &pieces, &on_plane);
    // The plane's rim ends are on the target's boundary: 9 of the 11 are inside.
    assert_eq!(inside.iter().filter(|&&i| i).count(), 9);
    let mirror = MirrorBoundary {
        axis: 0,
        on_plane: &on_plane,
    };
    let mut whole_pieces = None;
    // Both step systems: the metric's diagonal (light smoothness) and the full metric.
    for smoothness in [0.1, 1.0] {
        let options = DevelopOptions {
            smoothness,
            ..Default::default()
        };
        let developed = develop_pieces(&mesh, &table, &pieces, &[], Some(&mirror), &options, None).unwrap();
        assert!(developed.converged, "smoothness {smoothness}: {developed:?}");
        for (v, p) in developed.positions.iter().enumerate() {
            if on_plane[v] {
                assert_eq!(p.x, 0.0, "smoothness {smoothness}: plane vertex {v} left the plane");
            }
        }
        let half = TriangleMesh {
            positions: developed.positions.clone(),
            ..mesh.clone()
        };
        let whole =
            sheetform_mesh::mirror_whole(&half, &on_plane, &sheetform_mesh::MirrorPlane { axis: 0, offset: 0.0 });
        let whole_table = EdgeTable::new(&whole.mesh.triangles, whole.mesh.positions.len());
        let pieces_of_whole = seam_pieces(&whole.mesh, &whole_table, &[]).unwrap();
        let worst = max_interior_defect(&whole.mesh, &pieces_of_whole.interior);
        assert!(
            worst <= 1e-9,
            "smoothness {smoothness}: the joined mesh has a defect of {worst} rad"
        );
        whole_pieces = Some(pieces_of_whole);
    }
    let whole_pieces = whole_pieces.unwrap();
    // Without the mirror constraint the joined mesh is not flat on the plane.
    let free = develop_pieces(&mesh, &table, &pieces, &[], None, &DevelopOptions::default(), None).unwrap();
    let half = TriangleMesh {
        positions: free.positions,
        ..mesh.clone()
    };
    let whole = sheetform_mesh::mirror_whole(&half, &on_plane, &sheetform_mesh::MirrorPlane { axis: 0, offset: 0.0 });
    assert!(max_interior_defect(&whole.mesh, &whole_pieces.interior) > 1e-3);
}

/// A flat 12 × 12 sheet (unit cells) with one vertex raised 10 cells into a spike (angle
/// defect about 5.5 rad): steps that move no vertex more than half a cell cannot flatten
/// it within `HOPELESS_STEPS`, and flattening it at all means pressing the spike down
/// by most of its height. Asked to, the solve ends once the spike has stayed far from
/// flat for `HOPELESS_STEPS` steps, naming it; cut free along a slit, the pieces solve
/// exactly and the spike stays close to where it was. Without the flag the solve runs
/// its course.
#[test]
fn a_spike_the_solve_cannot_flatten_is_found_hopeless_early_and_cut_free() {
    use sheetform_develop::{slit_unflattened_vertices, HOPELESS_DEFECT, HOPELESS_STEPS};
    let n = 12;
    let apex = (n / 2) * (n + 1) + n / 2;
    let mut mesh = grid(n, n, |u, v| Vector3::new(12.0 * u, 12.0 * v, 0.0));
    mesh.positions[apex].z = 10.0;
    let table = EdgeTable::new(&mesh.triangles, mesh.positions.len());
    let pieces = seam_pieces(&mesh, &table, &[]).unwrap();
    assert!(pieces.interior[apex]);
    let before = max_interior_defect(&mesh, &pieces.interior);
    assert!(before > 2.0 * HOPELESS_DEFECT, "{before}");
    let early = DevelopOptions {
        end_at_hopeless_cone_points: true,
        ..Default::default()
    };
    let ended = develop_pieces(&mesh, &table, &pieces, &[], None, &early, None).unwrap();
    assert!(!ended.converged, "{}", ended.max_defect);
    assert!(ended.hopeless.contains(&(apex as u32)), "{:?}", ended.hopeless);
    assert!(
        ended.iterations == HOPELESS_STEPS,
        "ended after {} steps",
        ended.iterations
    );
    // Every vertex named is far from flat where the solve ended.
    let mut ended_mesh = mesh.clone();
    ended_mesh.positions = ended.positions.clone();
    let topology = sheetform_mesh::mesh_topology(&ended_mesh);
    let defects = vertex_developability(&ended_mesh, &topology).angle_defect;
    for &v in &ended.hopeless {
        assert!(
            defects[v as usize].abs() > HOPELESS_DEFECT,
            "{v}: {}",
            defects[v as usize]
        );
    }
    // Cut free (only the named vertices, one slit each at most), the pieces solve exactly.
    let (seams, slits) = slit_unflattened_vertices(
        &mesh,
        &ended.positions,
        &table,
        &pieces,
        None,
        1e-10,
        Some(&ended.hopeless),
    );
    assert!(slits >= 1 && slits <= ended.hopeless.len(), "{slits}");
    let cut = seam_pieces(&mesh, &table, &seams).unwrap();
    assert!(!cut.interior[apex]);
    let solved = develop_pieces(&mesh, &table, &cut, &[], None, &DevelopOptions::default(), None).unwrap();
    let mut result = mesh.clone();
    result.positions = solved.positions.clone();
    assert!(
        solved.converged && max_interior_defect(&result, &cut.interior) <= 1e-9,
        "{} {}",
        solved.max_defect,
        solved.iterations
    );
    assert!(solved.hopeless.is_empty());
    let spike_moved = (solved.positions[apex] - mesh.positions[apex]).norm();
    // Without the flag the same solve is not ended early.
    let full = develop_pieces(&mesh, &table, &pieces, &[], None, &DevelopOptions::default(), None).unwrap();
    assert!(
        full.hopeless.is_empty() && full.iterations > HOPELESS_STEPS,
        "{} steps, hopeless {:?}",
        full.iterations,
        full.hopeless
    );
    let pressed = (full.positions[apex] - mesh.positions[apex]).norm();
    assert!(
        spike_moved < 0.5 * pressed,
        "cut free: moved {spike_moved}; whole: {pressed}"
    );
}

//! Embedding: the parameters `(u, v, w)` of points in the undeformed volume.

use crate::{FfdError, NurbsVolume};
use kiddo::{ImmutableKdTree, SquaredEuclidean};
use nalgebra::Vector3;
use rayon::prelude::*;
use std::num::NonZero;

type Vec3 = Vector3<f64>;

/// Relative tolerance (of the lattice size) within which a point counts as inside the
/// volume and an inversion as converged.
pub const EMBEDDING_TOLERANCE: f64 = 1e-9;

/// Finds `x = (u, v, w)` with `Q(x) = p` for every point (Wang & Tang 2004 §2.1).
///
/// - **Parallelepiped lattice** (see [`NurbsVolume::affine_map`]): `x = M⁻¹ (p − o)`, one
///   3×3 solve per point.
/// - **General lattice**: Newton's method `x ← clamp(x − J_Q(x)⁻¹ (Q(x) − p))` on the
///   domain box, started from the nearest of a grid of volume samples (four per knot
///   span and direction, found with a k-d tree), then from the next nearest ones if that
///   fails.
///
/// A point counts as inside when `|Q(x) − p| ≤ 1e-9 ×` lattice size.
///
/// # Errors
/// [`FfdError::OutsideVolume`] for the first point outside the volume (or where the
/// inversion does not converge, which for a volume without fold-overs means the same).
pub fn embed_points(volume: &NurbsVolume, points: &[Vec3]) -> Result<Vec<Vec3>, FfdError> {
    let size = lattice_size(volume);
    let tolerance = EMBEDDING_TOLERANCE * size;
    let dom = volume.domain();
    let results: Vec<Result<Vec3, (usize, f64)>> = if let Some((origin, m)) = volume.affine_map() {
        let inverse = m
            .try_inverse()
            .ok_or_else(|| FfdError::Solver("lattice map is singular".into()))?;
        points
            .par_iter()
            .enumerate()
            .map(|(n, p)| {
                let x = inverse * (p - origin);
                let clamped = volume.clamp(x);
                let distance = (m * clamped + origin - p).norm();
                if distance <= tolerance {
                    Ok(clamped)
                } else {
                    Err((n, distance))
                }
            })
            .collect()
    } else {
        let samples_per = |d: usize| {
            let b = volume.basis(d);
            (4 * (b.count() - b.degree())).clamp(4, 48)
        };
        let counts = [samples_per(0), samples_per(1), samples_per(2)];
        let mut parameters = Vec::with_capacity(counts.iter().map(|c| c + 1).product());
        for k in 0..=counts[2] {
            for j in 0..=counts[1] {
                for i in 0..=counts[0] {
                    let t = [
                        i as f64 / counts[0] as f64,
                        j as f64 / counts[1] as f64,
                        k as f64 / counts[2] as f64,
                    ];
                    parameters.push(Vec3::new(
                        dom[0].0 + t[0] * (dom[0].1 - dom[0].0),
                        dom[1].0 + t[1] * (dom[1].1 - dom[1].0),
                        dom[2].0 + t[2] * (dom[2].1 - dom[2].0),
                    ));
                }
            }
        }
        let samples: Vec<[f64; 3]> = parameters
            .par_iter()
            .map(|&x| {
                let q = volume.point(x);
                [q.x, q.y, q.z]
            })
            .collect();
        let tree: ImmutableKdTree<f64, 3> = ImmutableKdTree::new_from_slice(&samples).map_err(|_| {
            // kiddo fails only past 2^32 items or when too many share a coordinate;
            // its Debug output names its variants, so say it in words.
            FfdError::Solver(format!(
                "cannot index the {} volume samples for the embedding: too many, or too many at one coordinate",
                samples.len()
            ))
        })?;
        points
            .par_iter()
            .enumerate()
            .map(|(n, p)| {
                let nearest = tree
                    .query(&[p.x, p.y, p.z])
                    .nearest_n::<SquaredEuclidean<f64>>(NonZero::new(4).expect("4 > 0"))
                    .execute();
                let mut best = f64::INFINITY;
                for start in nearest {
                    let (x, distance) = newton_inversion(volume, *p, parameters[start.item as usize], tolerance);
                    if distance <= tolerance {
                        return Ok(x);
                    }
                    best = best.min(distance);
                }
                Err((n, best))
            })
            .collect()
    };
    results
        .into_iter()
        .map(|r| {
            r.map_err(|(n, distance)| FfdError::OutsideVolume {
                vertex: n,
                x: points[n].x,
                y: points[n].y,
                z: points[n].z,
                distance,
            })
        })
        .collect()
}

/// Largest distance between two corners of the lattice's bounding box.
pub fn lattice_size(volume: &NurbsVolume) -> f64 {
    let mut lo = Vec3::repeat(f64::INFINITY);
    let mut hi = Vec3::repeat(f64::NEG_INFINITY);
    for p in volume.control_points() {
        lo = lo.inf(p);
        hi = hi.sup(p);
    }
    (hi - lo).norm()
}

/// Newton's method for `Q(x) = p` from `start`, clamped to the domain; returns the last
/// iterate and its distance `|Q(x) − p|`.
pub fn newton_inversion(volume: &NurbsVolume, p: Vec3, start: Vec3, tolerance: f64) -> (Vec3, f64) {
    let mut x = start;
    let mut best = (x, f64::INFINITY);
    for _ in 0..40 {
        let (q, j) = volume.point_and_jacobian(x);
        let r = q - p;
        let distance = r.norm();
        if distance < best.1 {
            best = (x, distance);
        }
        if distance <= 0.01 * tolerance {
            break;
        }
        let Some(step) = j.lu().solve(&r) else {
            break;
        };
        let next = volume.clamp(x - step);
        if (next - x).norm() < 1e-15 {
            break;
        }
        x = next;
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverts_affine_and_curved_lattices_and_refuses_outside_points() {
        let box_volume = NurbsVolume::parallelepiped(
            Vec3::new(-1.0, 0.0, 0.0),
            [
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(0.0, 3.0, 0.0),
                Vec3::new(0.5, 0.0, 1.0),
            ],
            [3, 3, 2],
            [5, 5, 3],
            None,
        )
        .unwrap();
        let params = [
            Vec3::new(0.2, 0.3, 0.4),
            Vec3::new(0.95, 0.01, 0.5),
            Vec3::new(0.5, 0.5, 1.0),
        ];
        let mut curved_points = box_volume.control_points().to_vec();
        for (n, p) in curved_points.iter_mut().enumerate() {
            p.y += 0.2 * (n as f64 * 0.9).sin();
        }
        let curved = box_volume
            .with_control_net(curved_points, (0..75).map(|n| 1.0 + 0.3 * (n % 3) as f64).collect())
            .unwrap();
        for volume in [&box_volume, &curved] {
            let points: Vec<Vec3> = params.iter().map(|&x| volume.point(x)).collect();
            let found = embed_points(volume, &points).unwrap();
            for (x, y) in params.iter().zip(&found) {
                assert!((x - y).norm() < 1e-8, "{x} vs {y}");
            }
        }
        let e = embed_points(&curved, &[Vec3::new(0.0, 1.0, 5.0)]).unwrap_err();
        assert!(matches!(e, FfdError::OutsideVolume { vertex: 0, .. }), "{e}");
        assert!(embed_points(&box_volume, &[Vec3::new(9.0, 0.0, 0.0)]).is_err());
    }
}

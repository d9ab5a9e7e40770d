//! The whole object from its visible side: ruled bands closed around a common axis as
//! surfaces of revolution (issue 37's "whole objects"; beyond the paper, whose §9 names
//! completing the hidden side as its limit).
//!
//! A photo shows the front of a cup, a lamp shade or a vase; the reconstruction (§6–§7)
//! gives that front only. When the annotation says `"back_side": "revolve"`, every ruled
//! patch is taken as part of a developable surface of revolution (a cylinder or a cone:
//! the only developable surfaces of revolution besides the plane), all about one axis,
//! and is closed around it:
//!
//! 1. **The axis** (Pottmann & Randrup 1998, "Rotational and helical surface
//!    approximation for reverse engineering", §3): the normals of a surface of revolution
//!    all meet its axis, so their Plücker coordinates `(n, p × n)` lie in the linear line
//!    complex `C = (c, c̄)` with `(p × n)·c + n·c̄ = 0`. The complex minimising
//!    `Σ w (p×n·c + n·c̄)²` (one term per band vertex, `n` its area-weighted normal,
//!    `w = 1`) under `|c| = 1` is
//!    found in closed form: `c̄ = −E⁺Bᵀc` with `A = Σ w (p×n)(p×n)ᵀ`, `B = Σ w (p×n)nᵀ`,
//!    `E = Σ w nnᵀ`, and `c` the eigenvector of the least eigenvalue of
//!    `S = A − B E⁺ Bᵀ`. The axis runs along `c` through `c × c̄`. (The pitch `c·c̄`, which
//!    is 0 for a surface of revolution, is not needed: the cross product drops it. For a
//!    cylinder `E` is singular along the axis and the pseudo-inverse picks pitch 0.)
//!    The normals are the vertices' (area-weighted over their triangles): a coarse
//!    strip's face normals, taken at the faces' centroids, miss the axis by a fraction of
//!    the strip's width and tilted the cone's axis by 6.6° on `cone-ortho`.
//! 2. **Each band's cone**, and the axis again: every vertex's radius `r` and height `z`
//!    about the axis should lie on its band's line `r = α_b + β_b z`. The axis (4
//!    degrees of freedom: its direction turned by `(e₁, e₂)` and its point moved by
//!    `(s₁, s₂)` across it) and the lines minimise `Σ (r − α_b − β_b z)²` by Gauss–Newton
//!    from step 1's axis, with the exact Jacobian: for `w = p − q`, `z = w·d`,
//!    `ρ̂ = (w − z d)/r` and `u` a direction across the axis, `∂r/∂e = −z ρ̂·u`,
//!    `∂z/∂e = w·u`, `∂r/∂s = −ρ̂·u`, `∂z/∂s = 0`. (On `cone-ortho` this finds the true
//!    axis to 0.02°; step 1 alone was 1.1° off.) The relative RMS of each band's line
//!    says how far the band is from a surface of revolution ([`REVOLUTION_FIT_BOUND`]).
//!    The band runs between the medians of its rulings' lower and upper ends' heights.
//! 3. **Rings**: band ends within 2 % of the object's height of each other are one ring
//!    (a cylinder on a cone share the circle between them), each a circle perpendicular
//!    to the axis whose radius is the mean of its bands' lines there, so that bands meet
//!    exactly.
//! 4. **The mesh**: `N` rulings round each band (planar quads between consecutive
//!    rulings of a cone or cylinder: exactly developable, no interior vertex), cut open
//!    along one ruling, the seam, placed in the symmetry plane on the side away from the
//!    camera (the pattern is then symmetric about its middle ruling, and the seam is at
//!    the back).
//!
//! Lengths are in the mesh's unit (the annotation's `units`); the camera works in
//! pixels (`unit_per_pixel` converts).

use crate::camera::Camera;
use crate::patch_mesh::{PatchMesh, PatchSurface};
use crate::symmetry_plane::SymmetryPlane;
use crate::PhotoError;
use nalgebra::{Matrix3, SymmetricEigen, Vector2, Vector3};
use serde::{Deserialize, Serialize};
use std::collections::HashMap;

type Vec3 = Vector3<f64>;

/// Largest relative RMS of a band's radius about the fitted axis: above it the band is
/// not a surface of revolution and is refused (a reconstruction 1–2 % off a cone is
/// 1–3 % here).
pub const REVOLUTION_FIT_BOUND: f64 = 0.1;
/// Relative RMS of a band's radius above which the report warns that the closed band is a
/// fit rather than what the photo shows (2 %: the synthetic views with 1 px of noise are
/// 0.7–1.6 %, exact ones below 0.2 %).
pub const REVOLUTION_FIT_WARNING: f64 = 0.02;
/// Largest angle between the fitted cone and the camera's rays at the visible band's
/// sides (degrees): above it the band is refused (see [`RevolvedBand::silhouette_angle_degrees`]).
pub const REVOLUTION_SILHOUETTE_BOUND_DEGREES: f64 = 10.0;
/// Angle between the fitted cone and the camera's rays at a band's silhouettes above which
/// the report warns that the symmetry marks may be off (degrees): exact views are within
/// 0.9°; the synthetic views with a frame point or a mirror point moved 3 px are at
/// 1.2–3.5° (in an orthographic view such a mark only shears the model, which nothing
/// else in the drawing shows).
pub const REVOLUTION_SILHOUETTE_WARNING_DEGREES: f64 = 1.5;
/// Fewest rulings round a closed band.
pub const MIN_REVOLUTION_RULINGS: usize = 24;
/// Most mesh edges along the axis round a closed band (one every half degree).
pub const MAX_REVOLUTION_SEGMENTS: usize = 720;

/// One band closed around the axis (the `photo.revolution.bands` entries of report.json).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct RevolvedBand {
    /// The patch (1-based, as errors name them).
    pub patch: usize,
    /// Heights of its lower and upper rings along the axis (model units, from the axis
    /// point).
    pub heights: [f64; 2],
    /// Radii of its lower and upper rings (model units).
    pub radii: [f64; 2],
    /// Relative RMS of the visible band's radius about its fitted cone (0: exactly a
    /// surface of revolution).
    pub fit_rms_relative: f64,
    /// Largest angle between the fitted cone and the camera's rays where the visible band
    /// ends (degrees; 0: its sides are the cone's silhouettes, as they should be).
    pub silhouette_angle_degrees: f64,
}

/// What closing the bands did (the `photo.revolution` section of report.json).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Revolution {
    /// A point of the fitted axis (model frame, model units).
    pub axis_point: [f64; 3],
    /// The axis' unit direction (model frame: x right, y up, z towards the camera).
    pub axis_direction: [f64; 3],
    /// Angle between the axis and the symmetry plane (degrees; 0 when the plane holds
    /// the axis, as a surface of revolution's mirror plane does).
    pub axis_off_symmetry_plane_degrees: f64,
    /// Rulings round each band (the pattern's bending guides).
    pub ruling_count: usize,
    /// Mesh edges along the axis round each band (rulings and smooth bends between).
    pub segment_count: usize,
    /// The bands, from the lowest.
    pub bands: Vec<RevolvedBand>,
    /// Mesh edges of the seam each band is cut open along (in the closed mesh's
    /// numbering).
    #[serde(skip)]
    #[schemars(skip)]
    pub seam_edges: Vec<[u32; 2]>,
}

/// The axis of the surface of revolution whose normals best meet it (step 1 of the
/// module's method): `(point, unit direction)`, or `None` when the normals do not fix one
/// (fewer than two directions, all parallel).
///
/// `samples` are `(point, unit normal, weight)`.
pub fn fit_revolution_axis(samples: &[(Vec3, Vec3, f64)]) -> Option<(Vec3, Vec3)> {
    let total: f64 = samples.iter().map(|s| s.2).sum();
    if samples.len() < 3 || total.is_nan() || total <= 0.0 {
        return None;
    }
    // Centred and scaled, for conditioning: p' = (p − centre) / size.
    let centre = samples.iter().map(|(p, _, w)| p * *w).sum::<Vec3>() / total;
    let size = samples
        .iter()
        .map(|(p, _, w)| w * (p - centre).norm_squared())
        .sum::<f64>()
        / total;
    let size = size.sqrt().max(f64::MIN_POSITIVE);
    let (mut a, mut b, mut e) = (Matrix3::zeros(), Matrix3::zeros(), Matrix3::zeros());
    for (p, n, w) in samples {
        let m = ((p - centre) / size).cross(n);
        a += m * m.transpose() * *w;
        b += m * n.transpose() * *w;
        e += n * n.transpose() * *w;
    }
    let eigen = SymmetricEigen::new(e);
    let largest = eigen.eigenvalues.max();
    if largest.is_nan() || largest <= 0.0 {
        return None;
    }
    let mut inverse = Matrix3::zeros();
    let mut rank = 0;
    for k in 0..3 {
        let lambda = eigen.eigenvalues[k];
        if lambda > 1e-9 * largest {
            let v = eigen.eigenvectors.column(k);
            inverse += v * v.transpose() / lambda;
            rank += 1;
        }
    }
    if rank < 2 {
        return None;
    }
    let s = a - b * inverse * b.transpose();
    let s = (s + s.transpose()) * 0.5;
    let eigen = SymmetricEigen::new(s);
    let k = eigen.eigenvalues.imin();
    let c: Vec3 = eigen.eigenvectors.column(k).into_owned().normalize();
    let c_bar = -(inverse * b.transpose() * c);
    let point = c.cross(&c_bar) * size + centre;
    (point.iter().all(|v| v.is_finite()) && c.iter().all(|v| v.is_finite())).then_some((point, c))
}

/// Step 2 of the module's method: the axis `(point, direction)` and, per band (its
/// points), the line `r = α + βz` with its RMS, by Gauss–Newton from `(point, axis)`.
pub fn fit_cones(bands: &[Vec<Vec3>], point: Vec3, axis: Vec3) -> (Vec3, Vec3, Vec<(f64, f64, f64)>) {
    let lines_of = |point: Vec3, axis: Vec3| -> (Vec<(f64, f64, f64)>, f64) {
        let mut total = 0.0;
        let lines = bands
            .iter()
            .map(|points| {
                let n = points.len() as f64;
                let (mut sz, mut sr, mut szz, mut szr) = (0.0, 0.0, 0.0, 0.0);
                let zr: Vec<(f64, f64)> = points
                    .iter()
                    .map(|p| {
                        let w = p - point;
                        let z = w.dot(&axis);
                        (z, (w - axis * z).norm())
                    })
                    .collect();
                for &(z, r) in &zr {
                    sz += z;
                    sr += r;
                    szz += z * z;
                    szr += z * r;
                }
                let var = szz / n - (sz / n).powi(2);
                let slope = if var > 0.0 {
                    (szr / n - sz / n * sr / n) / var
                } else {
                    0.0
                };
                let intercept = sr / n - slope * sz / n;
                let sum: f64 = zr.iter().map(|&(z, r)| (r - intercept - slope * z).powi(2)).sum();
                total += sum;
                (intercept, slope, (sum / n).sqrt())
            })
            .collect();
        (lines, total)
    };
    let (mut point, mut axis) = (point, axis.normalize());
    let (mut lines, mut cost) = lines_of(point, axis);
    let unknowns = 4 + 2 * bands.len();
    for _ in 0..50 {
        let other = if axis.x.abs() < 0.9 { Vec3::x() } else { Vec3::y() };
        let u = axis.cross(&other).normalize();
        let v = axis.cross(&u);
        let mut normal = nalgebra::DMatrix::<f64>::zeros(unknowns, unknowns);
        let mut gradient = nalgebra::DVector::<f64>::zeros(unknowns);
        let mut row = nalgebra::DVector::<f64>::zeros(unknowns);
        for (b, points) in bands.iter().enumerate() {
            let (alpha, beta, _) = lines[b];
            for p in points {
                let w = p - point;
                let z = w.dot(&axis);
                let rho = w - axis * z;
                let r = rho.norm();
                if r <= 0.0 {
                    continue;
                }
                let rho = rho / r;
                row.fill(0.0);
                for (k, dir) in [u, v].iter().enumerate() {
                    row[k] = -z * rho.dot(dir) - beta * w.dot(dir);
                    row[2 + k] = -rho.dot(dir);
                }
                row[4 + 2 * b] = -1.0;
                row[5 + 2 * b] = -z;
                let residual = r - alpha - beta * z;
                normal.ger(1.0, &row, &row, 1.0);
                gradient.axpy(residual, &row, 1.0);
            }
        }
        for k in 0..unknowns {
            normal[(k, k)] *= 1.0 + 1e-9;
            normal[(k, k)] += 1e-30;
        }
        let Some(step) = normal.cholesky().map(|c| -c.solve(&gradient)) else {
            break;
        };
        let mut scale = 1.0;
        let mut improved = false;
        for _ in 0..20 {
            let axis_new = (axis + (u * step[0] + v * step[1]) * scale).normalize();
            let point_new = point + (u * step[2] + v * step[3]) * scale;
            let (lines_new, cost_new) = lines_of(point_new, axis_new);
            if cost_new.is_finite() && cost_new < cost {
                let gain = cost - cost_new;
                (point, axis, lines, cost) = (point_new, axis_new, lines_new, cost_new);
                improved = gain > 1e-14 * cost.max(f64::MIN_POSITIVE);
                break;
            }
            scale *= 0.5;
        }
        if !improved {
            break;
        }
    }
    (point, axis, lines)
}

/// A band of the visible model before closing.
struct Band {
    patch: usize,
    ends: [f64; 2],
    line: (f64, f64),
    fit_rms_relative: f64,
    silhouette_angle: f64,
}

/// Closes every ruled band of `mesh` around one axis (the module's method), with rulings
/// about `ruling_spacing` apart round the largest ring and mesh edges about
/// `sample_spacing` (both in model units): a new mesh
/// with the same patches, each band a whole cone or cylinder cut open along its seam
/// ([`Revolution::seam_edges`]), and what was fitted.
///
/// # Errors
/// [`PhotoError::Field`] on `back_side` when there is no ruled band or the bands fix no
/// axis; [`PhotoError::Patch`] naming a patch that is filled rather than ruled, is not a
/// surface of revolution about the axis ([`REVOLUTION_FIT_BOUND`]), has no height along
/// it, narrows to a point, or lies over the same stretch of the axis as another band.
pub fn revolve_bands(
    mesh: &PatchMesh,
    plane: &SymmetryPlane,
    camera: &Camera,
    unit_per_pixel: f64,
    sample_spacing: f64,
    ruling_spacing: f64,
) -> Result<(PatchMesh, Revolution), PhotoError> {
    let patch_error = |patch: usize, message: String| PhotoError::Patch {
        patch: format!("{}", patch + 1),
        message,
    };
    let mut faces_of: Vec<Vec<usize>> = vec![Vec::new(); mesh.patch_kind.len()];
    for (f, &p) in mesh.face_patch.iter().enumerate() {
        faces_of[p as usize].push(f);
    }
    let mut band_patches = Vec::new();
    for (p, faces) in faces_of.iter().enumerate() {
        match mesh.patch_kind[p] {
            _ if faces.is_empty() => {}
            PatchSurface::Opening => {}
            PatchSurface::Ruled => band_patches.push(p),
            PatchSurface::Filled => {
                return Err(patch_error(
                    p,
                    "is not a ruled band, so it cannot be closed around an axis (`back_side: revolve` closes bands \
                     bounded by two silhouettes); mark it as an opening, or draw the object without it"
                        .into(),
                ))
            }
        }
    }
    if band_patches.is_empty() {
        return Err(PhotoError::field(
            "back_side",
            "there is no ruled band to close around an axis (a band lies between two silhouettes)",
        ));
    }
    // 1. The axis, from the bands' vertex normals.
    let corner = |t: [u32; 3]| t.map(|v| mesh.positions[v as usize]);
    let mut vertex_normal = vec![Vec3::zeros(); mesh.positions.len()];
    let mut band_vertices: Vec<Vec<u32>> = Vec::with_capacity(band_patches.len());
    for &p in &band_patches {
        for &f in &faces_of[p] {
            let [a, b, c] = corner(mesh.triangles[f]);
            let n = (b - a).cross(&(c - a));
            for v in mesh.triangles[f] {
                vertex_normal[v as usize] += n;
            }
        }
        let mut vertices: Vec<u32> = faces_of[p].iter().flat_map(|&f| mesh.triangles[f]).collect();
        vertices.sort_unstable();
        vertices.dedup();
        band_vertices.push(vertices);
    }
    let samples: Vec<(Vec3, Vec3, f64)> = band_vertices
        .iter()
        .flatten()
        .filter(|&&v| vertex_normal[v as usize].norm() > 0.0)
        .map(|&v| (mesh.positions[v as usize], vertex_normal[v as usize].normalize(), 1.0))
        .collect();
    let (axis_point, axis) = fit_revolution_axis(&samples).ok_or_else(|| {
        PhotoError::field(
            "back_side",
            "the bands' surface normals fix no axis of revolution (the bands are flat or degenerate)",
        )
    })?;
    // 2. The axis and the bands' cones by least squares on the radius.
    let points: Vec<Vec<Vec3>> = band_vertices
        .iter()
        .map(|vs| vs.iter().map(|&v| mesh.positions[v as usize]).collect())
        .collect();
    let (axis_point, axis, lines) = fit_cones(&points, axis_point, axis);
    let height = |p: &Vec3| (p - axis_point).dot(&axis);
    let radius = |p: &Vec3| {
        let d = p - axis_point;
        (d - axis * d.dot(&axis)).norm()
    };
    // 2. Each band's cone and ends.
    let mut edge_patch: HashMap<(u32, u32), usize> = HashMap::new();
    for (f, t) in mesh.triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            edge_patch.insert((a.min(b), a.max(b)), mesh.face_patch[f] as usize);
        }
    }
    let pixel = |q: Vec3| q / unit_per_pixel;
    let mut bands = Vec::new();
    for (b, &p) in band_patches.iter().enumerate() {
        let vertices = &band_vertices[b];
        let (intercept, slope, rms) = lines[b];
        let mean_radius = points[b].iter().map(radius).sum::<f64>() / points[b].len() as f64;
        let fit_rms_relative = if mean_radius > 0.0 {
            rms / mean_radius
        } else {
            f64::INFINITY
        };
        // The band's sides are silhouettes: there the fitted surface must turn edge-on to
        // the camera (its normal across the ray). Half an ellipse fits a wider circle to
        // 2 % but meets the camera's rays at 38° where it ends.
        let front = points[b]
            .iter()
            .map(|q| {
                let d = q - axis_point;
                d - axis * d.dot(&axis)
            })
            .sum::<Vec3>();
        let front = front.try_normalize(0.0).unwrap_or_else(Vec3::z);
        let side = axis.cross(&front);
        let azimuth = |q: &Vec3| {
            let d = q - axis_point;
            d.dot(&side).atan2(d.dot(&front))
        };
        let azimuths: Vec<f64> = points[b].iter().map(azimuth).collect();
        let (least, most) = azimuths
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &t| {
                (lo.min(t), hi.max(t))
            });
        let silhouette_angle = points[b]
            .iter()
            .zip(&azimuths)
            .filter(|(_, &t)| t - least < 0.02 || most - t < 0.02)
            .map(|(q, _)| {
                let d = q - axis_point;
                let radial = (d - axis * d.dot(&axis)).normalize();
                let normal = (radial - axis * slope).normalize();
                let ray = match camera.focal_length_px {
                    Some(f) => pixel(*q) - Vec3::new(camera.principal_point.x, camera.principal_point.y, f),
                    None => Vec3::z(),
                }
                .normalize();
                normal.dot(&ray).abs().min(1.0).asin().to_degrees()
            })
            // (NaN kept: a degenerate radius is refused below, not read as 0°.)
            .fold(0.0, |most: f64, angle| {
                if most.is_nan() || angle.is_nan() {
                    f64::NAN
                } else {
                    most.max(angle)
                }
            });
        if fit_rms_relative.is_nan() || fit_rms_relative > REVOLUTION_FIT_BOUND {
            return Err(patch_error(
                p,
                format!(
                    "is not a surface of revolution about the axis fitted to the bands: its radius is {:.1} % off a \
                     cone round it (at most {:.0} %); close only cups, lamp shades and vases whose bands are cones \
                     or cylinders about one axis",
                    100.0 * fit_rms_relative,
                    100.0 * REVOLUTION_FIT_BOUND
                ),
            ));
        }
        // Its ends: the medians of its rulings' lower and upper ends (all its vertices'
        // extremes when it has no ruling edge).
        let (mut lows, mut highs) = (Vec::new(), Vec::new());
        for &[a, b] in &mesh.ruling_edges {
            if edge_patch.get(&(a.min(b), a.max(b))) == Some(&p) {
                let (za, zb) = (height(&mesh.positions[a as usize]), height(&mesh.positions[b as usize]));
                lows.push(za.min(zb));
                highs.push(za.max(zb));
            }
        }
        if lows.is_empty() {
            for &v in vertices {
                let z = height(&mesh.positions[v as usize]);
                lows.push(z);
                highs.push(z);
            }
            lows = vec![lows.iter().copied().fold(f64::INFINITY, f64::min)];
            highs = vec![highs.iter().copied().fold(f64::NEG_INFINITY, f64::max)];
        }
        let median = |values: &mut Vec<f64>| {
            values.sort_by(f64::total_cmp);
            values[values.len() / 2]
        };
        bands.push(Band {
            patch: p,
            ends: [median(&mut lows), median(&mut highs)],
            line: (intercept, slope),
            fit_rms_relative,
            silhouette_angle,
        });
    }
    // 3. Rings: band ends within 2 % of the whole height are one.
    let lowest = bands.iter().map(|b| b.ends[0]).fold(f64::INFINITY, f64::min);
    let highest = bands.iter().map(|b| b.ends[1]).fold(f64::NEG_INFINITY, f64::max);
    let tolerance = 0.02 * (highest - lowest);
    let mut ends: Vec<(f64, usize, usize)> = bands
        .iter()
        .enumerate()
        .flat_map(|(b, band)| [(band.ends[0], b, 0), (band.ends[1], b, 1)])
        .collect();
    ends.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut ring_of = vec![[usize::MAX; 2]; bands.len()];
    let mut rings: Vec<(f64, f64)> = Vec::new(); // (height, radius)
    let mut k = 0;
    while k < ends.len() {
        let mut group = vec![ends[k]];
        while k + 1 < ends.len() && ends[k + 1].0 - group[0].0 <= tolerance {
            k += 1;
            group.push(ends[k]);
        }
        k += 1;
        let z = group.iter().map(|g| g.0).sum::<f64>() / group.len() as f64;
        let r = group
            .iter()
            .map(|&(_, b, _)| bands[b].line.0 + bands[b].line.1 * z)
            .sum::<f64>()
            / group.len() as f64;
        for &(_, b, end) in &group {
            ring_of[b][end] = rings.len();
        }
        rings.push((z, r));
    }
    let largest_radius = rings.iter().map(|r| r.1).fold(0.0, f64::max);
    for (b, band) in bands.iter().enumerate() {
        let [lo, hi] = ring_of[b];
        if lo == hi {
            return Err(patch_error(
                band.patch,
                "has no height along the axis fitted to the bands (its ends are one ring), so it cannot be closed \
                 around it"
                    .into(),
            ));
        }
        for ring in [lo, hi] {
            if rings[ring].1.is_nan() || rings[ring].1 <= 1e-3 * largest_radius {
                return Err(patch_error(
                    band.patch,
                    "narrows to a point (or past it) on the axis fitted to the bands; close it only when both of its \
                     ends are circles"
                        .into(),
                ));
            }
        }
    }
    // Two bands over the same stretch of the axis would both become whole cones there.
    for a in 0..bands.len() {
        for b in a + 1..bands.len() {
            let ([a0, a1], [b0, b1]) = (ring_of[a], ring_of[b]);
            if a0.max(b0) < a1.min(b1) {
                let (first, second) = (bands[a].patch.min(bands[b].patch), bands[a].patch.max(bands[b].patch));
                return Err(patch_error(
                    first,
                    format!(
                        "and patch {} lie over the same stretch of the axis fitted to the bands, so both would close \
                         into the same cone; draw that band as one patch (without a curve between them), or keep \
                         the visible side only (`back_side: visible`)",
                        second + 1
                    ),
                ));
            }
        }
    }
    // Each band's sides are silhouettes (checked once no two bands share a stretch of the
    // axis: a band split by a curve has a side that is not).
    for band in &bands {
        let (p, silhouette_angle) = (band.patch, band.silhouette_angle);
        if silhouette_angle.is_nan() || silhouette_angle > REVOLUTION_SILHOUETTE_BOUND_DEGREES {
            return Err(patch_error(
                p,
                format!(
                    "is not a surface of revolution about the axis fitted to the bands: where it ends at its \
                     silhouettes, the cone fitted round that axis meets the camera's rays at {silhouette_angle:.0}° \
                     instead of grazing them (at most {REVOLUTION_SILHOUETTE_BOUND_DEGREES}°); an elliptic or \
                     flattened band cannot be closed round an axis"
                ),
            ));
        }
    }
    // 4. The seam: the ruling in the symmetry plane away from the camera.
    let middle = axis_point + axis * 0.5 * (lowest + highest);
    let mean_radius = rings.iter().map(|r| r.1).sum::<f64>() / rings.len() as f64;
    let mut seam_direction = plane.normal.cross(&axis);
    if seam_direction.norm() < 0.1 {
        // The plane does not hold the axis: the direction away from the camera.
        let toward_camera = match camera.focal_length_px {
            Some(f) => Vec3::new(camera.principal_point.x, camera.principal_point.y, f) * unit_per_pixel - middle,
            None => Vec3::z(),
        };
        seam_direction = toward_camera - axis * toward_camera.dot(&axis);
        if seam_direction.norm() < 1e-9 * toward_camera.norm() {
            seam_direction = axis.cross(&Vec3::x());
            if seam_direction.norm() < 0.1 {
                seam_direction = axis.cross(&Vec3::y());
            }
        }
    }
    let mut seam_direction = seam_direction.normalize();
    let distance_from_camera = |q: Vec3| match camera.focal_length_px {
        Some(f) => (pixel(q) - Vec3::new(camera.principal_point.x, camera.principal_point.y, f)).norm(),
        None => -pixel(q).z,
    };
    if distance_from_camera(middle - seam_direction * mean_radius)
        > distance_from_camera(middle + seam_direction * mean_radius)
    {
        seam_direction = -seam_direction;
    }
    let across = axis.cross(&seam_direction);
    // Rulings round the largest ring about `ruling_spacing` apart (an even count, so that
    // the ruling opposite the seam is one: the pattern's middle), each span divided in
    // `k` about `sample_spacing` apart (the edges between are smooth bends, drawn neither
    // as folds nor as guides).
    let circumference = std::f64::consts::TAU * largest_radius;
    let rulings_round = (circumference / ruling_spacing).round();
    let rulings_round = if rulings_round.is_finite() {
        rulings_round as usize
    } else {
        MAX_REVOLUTION_SEGMENTS
    };
    let rulings_round = (rulings_round.clamp(MIN_REVOLUTION_RULINGS, MAX_REVOLUTION_SEGMENTS) + 1) & !1;
    let divisions = (ruling_spacing / sample_spacing).round();
    let divisions = if divisions.is_finite() {
        divisions.max(1.0) as usize
    } else {
        1
    };
    let divisions = divisions.min(MAX_REVOLUTION_SEGMENTS / rulings_round).max(1);
    let segments = rulings_round * divisions;
    // The front's orientation: its triangles' normals outward (or inward), kept.
    let outward: f64 = samples
        .iter()
        .map(|(q, n, w)| {
            let d = q - axis_point;
            w * n.dot(&(d - axis * d.dot(&axis)))
        })
        .sum();
    let mut closed = PatchMesh {
        patch_kind: mesh.patch_kind.clone(),
        ..PatchMesh::default()
    };
    for &(z, r) in &rings {
        for j in 0..segments {
            let theta = std::f64::consts::TAU * j as f64 / segments as f64;
            let q = axis_point + axis * z + (seam_direction * theta.cos() + across * theta.sin()) * r;
            closed.positions.push(q);
            let image = camera.project(pixel(q));
            closed.image.push(Vector2::new(image.x, image.y));
        }
    }
    let vertex = |ring: usize, j: usize| (ring * segments + j % segments) as u32;
    let mut seam_edges = Vec::new();
    let mut revolved = Vec::new();
    let mut order: Vec<usize> = (0..bands.len()).collect();
    order.sort_by(|&x, &y| rings[ring_of[x][0]].0.total_cmp(&rings[ring_of[y][0]].0));
    for b in order {
        let band = &bands[b];
        let [lo, hi] = ring_of[b];
        for j in 0..segments {
            let (a, b1, c, d) = (vertex(lo, j), vertex(lo, j + 1), vertex(hi, j + 1), vertex(hi, j));
            // Counter-clockwise seen from outside when the axis runs from `lo` to `hi`.
            let mut triangles = [[a, b1, c], [a, c, d]];
            let [p0, p1, p2] = triangles[0].map(|v| closed.positions[v as usize]);
            let d0 = p0 - axis_point;
            let facing = (p1 - p0).cross(&(p2 - p0)).dot(&(d0 - axis * d0.dot(&axis)));
            if (facing > 0.0) != (outward >= 0.0) {
                for t in &mut triangles {
                    t.swap(1, 2);
                }
            }
            for t in triangles {
                closed.triangles.push(t);
                closed.face_patch.push(band.patch as u32);
            }
            if j == 0 {
                seam_edges.push([a, d]);
            } else if j % divisions == 0 {
                closed.ruling_edges.push([a, d]);
            } else {
                closed.bending_edges.push([a, d]);
            }
            closed.bending_edges.push([a, c]);
        }
        revolved.push(RevolvedBand {
            patch: band.patch + 1,
            heights: [rings[lo].0, rings[hi].0],
            radii: [rings[lo].1, rings[hi].1],
            fit_rms_relative: band.fit_rms_relative,
            silhouette_angle_degrees: band.silhouette_angle,
        });
    }
    let off_plane = plane.normal.dot(&axis).abs().clamp(0.0, 1.0).asin().to_degrees();
    tracing::debug!(
        "photo: {} bands closed round an axis {off_plane:.2}° off the symmetry plane, {segments} rulings round",
        revolved.len()
    );
    Ok((
        closed,
        Revolution {
            axis_point: axis_point.into(),
            axis_direction: axis.into(),
            axis_off_symmetry_plane_degrees: off_plane,
            ruling_count: rulings_round,
            segment_count: segments,
            bands: revolved,
            seam_edges,
        },
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Samples of a frustum about `axis` through `point` between azimuths `from` and
    /// `to`: points with their exact normals, equal weights.
    fn frustum_samples(
        point: Vec3,
        axis: Vec3,
        radii: [f64; 2],
        height: f64,
        from: f64,
        to: f64,
    ) -> Vec<(Vec3, Vec3, f64)> {
        let axis = axis.normalize();
        let u = axis.cross(&Vec3::new(0.3, 0.5, 0.8)).normalize();
        let v = axis.cross(&u);
        let mut samples = Vec::new();
        let (n, m) = (40, 6);
        for i in 0..=n {
            for k in 0..=m {
                let t = from + (to - from) * i as f64 / n as f64;
                let s = k as f64 / m as f64;
                let r = radii[0] + (radii[1] - radii[0]) * s;
                let radial = u * t.cos() + v * t.sin();
                let along_t = (v * t.cos() - u * t.sin()) * r;
                let along_s = axis * height + radial * (radii[1] - radii[0]);
                let normal = along_t.cross(&along_s).normalize();
                samples.push((point + axis * (height * s) + radial * r, normal, 1.0));
            }
        }
        samples
    }

    fn distance_to_line(q: Vec3, point: Vec3, direction: Vec3) -> f64 {
        let d = q - point;
        (d - direction * d.dot(&direction)).norm()
    }

    #[test]
    fn the_axis_of_a_half_cone_and_a_half_cylinder_is_found() {
        let point = Vec3::new(12.0, -40.0, 7.0);
        let axis = Vec3::new(0.2, 0.9, 0.4).normalize();
        for radii in [[30.0, 18.0], [25.0, 25.0]] {
            // The visible half only (a 180° band).
            let samples = frustum_samples(point, axis, radii, 60.0, -0.3, 2.8);
            let (q, a) = fit_revolution_axis(&samples).expect("an axis");
            assert!(a.dot(&axis).abs() > 1.0 - 1e-9, "{radii:?}: direction {a:?}");
            for s in [0.0, 60.0] {
                let on_axis = point + axis * s;
                assert!(distance_to_line(on_axis, q, a) < 1e-6, "{radii:?}: point {q:?}");
            }
        }
    }

    /// The visible half of an elliptic cylinder (semi-axes `a` along x, `b` towards the
    /// camera, axis along y), rulings along y: one ruled patch.
    fn half_elliptic_cylinder(a: f64, b: f64) -> PatchMesh {
        let n = 40;
        let mut mesh = PatchMesh {
            patch_kind: vec![PatchSurface::Ruled],
            ..PatchMesh::default()
        };
        for i in 0..=n {
            let t = std::f64::consts::PI * i as f64 / n as f64;
            for y in [0.0, 60.0] {
                let p = Vec3::new(a * t.cos(), y, b * t.sin());
                mesh.positions.push(p);
                mesh.image.push(Vector2::new(p.x, p.y));
            }
        }
        for i in 0..n as u32 {
            let (p, q) = (2 * i, 2 * i + 2);
            mesh.triangles.push([p, q, q + 1]);
            mesh.triangles.push([p, q + 1, p + 1]);
            mesh.face_patch.extend([0, 0]);
            mesh.ruling_edges.push([p, p + 1]);
            mesh.bending_edges.push([p, q + 1]);
        }
        mesh
    }

    fn plane() -> SymmetryPlane {
        SymmetryPlane {
            normal: Vec3::x(),
            point: Vec3::zeros(),
            camera: Camera::orthographic(),
        }
    }

    #[test]
    fn a_half_cylinder_closes_into_a_whole_one_and_an_ellipse_is_refused() {
        let (closed, revolution) = revolve_bands(
            &half_elliptic_cylinder(30.0, 30.0),
            &plane(),
            &Camera::orthographic(),
            1.0,
            1.0,
            4.0,
        )
        .expect("a circular cylinder closes");
        assert_eq!(revolution.bands.len(), 1);
        let band = &revolution.bands[0];
        assert!(
            (band.radii[0] - 30.0).abs() < 1e-6 && (band.radii[1] - 30.0).abs() < 1e-6,
            "{band:?}"
        );
        assert!((band.heights[1] - band.heights[0] - 60.0).abs() < 1e-6, "{band:?}");
        // The seam in the symmetry plane (x = 0), at the back (z < 0).
        let [a, b] = revolution.seam_edges[0];
        for v in [a, b] {
            let p = closed.positions[v as usize];
            assert!(p.x.abs() < 1e-6 && p.z < -29.0, "{p:?}");
        }
        // Rulings about 4 apart round 188.5, an even count; mesh edges about 1 apart.
        assert_eq!(revolution.ruling_count, 48);
        assert_eq!(revolution.segment_count, 48 * 4);
        assert_eq!(closed.ruling_edges.len() + 1, revolution.ruling_count);
        let error = revolve_bands(
            &half_elliptic_cylinder(40.0, 20.0),
            &plane(),
            &Camera::orthographic(),
            1.0,
            1.0,
            4.0,
        )
        .expect_err("an elliptic cylinder is no surface of revolution");
        assert!(error.to_string().contains("not a surface of revolution"), "{error}");
        // The band split in two patches by a curve between its silhouettes: both would
        // close into the same cylinder.
        let mut split = half_elliptic_cylinder(30.0, 30.0);
        split.patch_kind.push(PatchSurface::Ruled);
        let half = split.face_patch.len() / 2;
        for p in &mut split.face_patch[half..] {
            *p = 1;
        }
        let error = revolve_bands(&split, &plane(), &Camera::orthographic(), 1.0, 1.0, 4.0)
            .expect_err("two patches over one band");
        assert!(error.to_string().contains("same stretch of the axis"), "{error}");
        let mut filled = half_elliptic_cylinder(30.0, 30.0);
        filled.patch_kind[0] = PatchSurface::Filled;
        let error = revolve_bands(&filled, &plane(), &Camera::orthographic(), 1.0, 1.0, 4.0)
            .expect_err("a filled patch is no band");
        assert!(error.to_string().contains("not a ruled band"), "{error}");
    }

    #[test]
    fn a_plane_fixes_no_axis() {
        let samples: Vec<_> = (0..20)
            .map(|i| (Vec3::new(i as f64, (i * 7 % 5) as f64, 0.0), Vec3::z(), 1.0))
            .collect();
        assert!(fit_revolution_axis(&samples).is_none());
    }
}

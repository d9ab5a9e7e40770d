//! The whole method of Fondevilla et al. on one annotation: analysis (§5), lifting (§6),
//! refinement (beyond the paper), meshing (§7) and the true size.

use crate::annotation::{image_to_model, BackSide, PhotoAnnotation};
use crate::camera::Camera;
use crate::curve_lifting::{assemble_energy, image_prior, solve_energy, Energy};
use crate::curve_network::{build_curve_network, CurveNetwork};
use crate::curve_samples::{sample_curves, CurvePoint, CurveSamples};
use crate::developability_refinement::{refine_developability, ruling_errors, RefinementInfo};
use crate::focal_length_estimate::{estimate_focal_length, FocalLengthEstimate};
use crate::patch_cycles::{find_patches, Patch};
use crate::patch_mesh::{mesh_patches, PatchMesh};
use crate::revolved_bands::{revolve_bands, Revolution};
use crate::ruling_alignment::{align_rulings, align_rulings_in_perspective, move_ruling_ends};
use crate::ruling_propagation::{propagate_rulings, PropagationCounts, PropagationOptions, RuledStrip};
use crate::symmetric_correspondences::{symmetric_pairs_of_curves, SymmetricPair};
use crate::symmetrization::{split_at_mirror_nodes, symmetrize, MirrorMap, SymmetrizationInfo};
use crate::symmetry_plane::SymmetryPlane;
use crate::{cubic, PhotoError};
use nalgebra::{Vector2, Vector3};
use std::time::Instant;

type Vec2 = Vector2<f64>;
type Vec3 = Vector3<f64>;

/// Largest depth sensitivity (see [`PhotoReconstruction::depth_sensitivity`]) of a curve
/// whose depth counts as fixed by the drawing: 1 % of a shift of the prior.
pub const DEPTH_SENSITIVITY_BOUND: f64 = 0.01;

/// Most linear solves of a perspective drawing: each takes the perspective divisors of
/// the one before for its barycentric coordinates ([`assemble_energy`]); they settle to
/// 1e-9 in three to five on the synthetic views.
const PERSPECTIVE_SOLVES: usize = 8;

/// The depths `Z` of a solution's points (`3 × point + 2`).
fn depths_of(x: &[f64]) -> Vec<f64> {
    x.iter().skip(2).step_by(3).copied().collect()
}

/// Milliseconds spent in each stage.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct StageTimes {
    /// Intersections, splitting, patches, samples (§5.1).
    pub network_ms: f64,
    /// Ruling propagation (§5.2).
    pub rulings_ms: f64,
    /// Symmetry plane and correspondences (§5.3, §6.1).
    pub symmetry_ms: f64,
    /// Energy assembly and linear solve (§6).
    pub linear_solve_ms: f64,
    /// Developability refinement.
    pub refinement_ms: f64,
    /// Symmetrisation (§7).
    pub symmetrization_ms: f64,
    /// Meshing (§7).
    pub meshing_ms: f64,
    /// The focal length estimated from the drawing (its 25 linear solves; 0 when the
    /// camera gave one).
    #[serde(default)]
    pub focal_length_estimate_ms: f64,
}

/// Summary of a set of angles (degrees, as the paper's Table 1).
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct AngleSummary {
    /// Mean (degrees).
    pub mean_deg: f64,
    /// Maximum (degrees).
    pub max_deg: f64,
    /// How many angles.
    pub count: usize,
}

impl AngleSummary {
    /// Of angles in radians.
    pub fn of(radians: &[f64]) -> Self {
        let count = radians.len();
        if count == 0 {
            return Self::default();
        }
        Self {
            mean_deg: radians.iter().sum::<f64>() / count as f64 * 180.0 / std::f64::consts::PI,
            max_deg: radians.iter().copied().fold(0.0, f64::max) * 180.0 / std::f64::consts::PI,
            count,
        }
    }
}

/// Everything the reconstruction made.
#[derive(Debug, Clone)]
pub struct PhotoReconstruction {
    /// The curve network (2D).
    pub network: CurveNetwork,
    /// Samples along it.
    pub samples: CurveSamples,
    /// Patches (minimal cycles).
    pub patches: Vec<Patch>,
    /// Ruled strips.
    pub strips: Vec<RuledStrip>,
    /// Ruling candidates and rejections.
    pub propagation: PropagationCounts,
    /// Ruling ends moved onto the point of parallel tangents.
    pub aligned_ruling_count: usize,
    /// The symmetry plane (model frame, pixels).
    pub plane: SymmetryPlane,
    /// Mirror pairs.
    pub pairs: Vec<SymmetricPair>,
    /// The energy of §6.
    pub energy: Energy,
    /// 3D control points after the linear solve (pixels; `3 × point + axis`).
    pub linear: Vec<f64>,
    /// 3D control points after the refinement (the linear ones without it).
    pub refined: Vec<f64>,
    /// The refinement's report, when it ran.
    pub refinement: Option<RefinementInfo>,
    /// The final 3D control points: the refined ones symmetrised (§7), or the refined
    /// ones when the symmetrisation is off. The mesh, the overlay and the true size use
    /// these.
    pub points3d: Vec<f64>,
    /// The symmetrisation's report, when it ran.
    pub symmetrization: Option<SymmetrizationInfo>,
    /// Per network curve, how much its depth follows an arbitrary prior instead of the
    /// drawing (0: fixed by mirror pairs, rulings and joins; 1: free, e.g. a circle no
    /// mirror pair reaches). Above [`DEPTH_SENSITIVITY_BOUND`] the curve's depth is
    /// undetermined.
    pub depth_sensitivity: Vec<f64>,
    /// The rulings of the linear solve in the image (patch, ends), before the refinement
    /// slid their ends.
    pub rulings_linear: Vec<(usize, [Vec2; 2])>,
    /// Developability error per ruling after the linear solve (radians).
    pub ruling_errors_linear: Vec<f64>,
    /// The same after the refinement.
    pub ruling_errors_refined: Vec<f64>,
    /// The same on the final model (after the symmetrisation).
    pub ruling_errors_final: Vec<f64>,
    /// Mean and largest distance between the solved curves' projections and the traced
    /// curves, over the samples (pixels).
    pub reprojection_error_px: (f64, f64),
    /// The mesh, in the annotation's unit (scaled by `unit_per_pixel`).
    pub mesh: PatchMesh,
    /// Model units per pixel (from the true size).
    pub unit_per_pixel: f64,
    /// The bands closed around their axis (`back_side: revolve`): `mesh` is then the
    /// whole object, each band cut open along the seam these list.
    pub revolution: Option<Revolution>,
    /// The focal length estimated from the drawing, when the camera is perspective and
    /// neither the annotation nor the photo's EXIF gave one (the camera of `plane` is
    /// then the estimate's).
    pub focal_length_estimate: Option<FocalLengthEstimate>,
    /// Time per stage.
    pub times: StageTimes,
}

fn milliseconds(since: Instant) -> f64 {
    since.elapsed().as_secs_f64() * 1e3
}

/// Nearest place on the network to an image point, and its distance (pixels).
fn nearest_place(network: &CurveNetwork, p: Vec2) -> (CurvePoint, f64) {
    (0..network.segments.len())
        .map(|s| {
            let (t, d) = cubic::nearest_parameter(&network.control_points(s), p);
            (CurvePoint { segment: s as u32, t }, d)
        })
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .expect("a network has segments")
}

/// The 3D point of a place for unknowns `x`.
pub fn place_point(network: &CurveNetwork, x: &[f64], place: CurvePoint) -> Vec3 {
    crate::curve_lifting::combine3(network, x, place.segment, cubic::bernstein(place.t))
}

/// The network curve named `name` (validated to exist).
fn curve_index(network: &CurveNetwork, name: &str) -> usize {
    network
        .curves
        .iter()
        .position(|c| c.name == name)
        .expect("validated name")
}

/// The annotation's symmetric curve pairs, then its self-symmetric curves (`[c, c]`), as
/// network curve indices.
fn annotated_curve_pairs(annotation: &PhotoAnnotation, network: &CurveNetwork) -> Vec<[usize; 2]> {
    annotation
        .symmetric_curves
        .iter()
        .map(|[a, b]| [curve_index(network, a), curve_index(network, b)])
        .chain(
            annotation
                .self_symmetric_curves
                .iter()
                .map(|a| [curve_index(network, a); 2]),
        )
        .collect()
}

/// The 2D analysis of a network (§5).
#[derive(Clone)]
struct Analysis {
    patches: Vec<Patch>,
    samples: CurveSamples,
    strips: Vec<RuledStrip>,
    propagation: PropagationCounts,
    aligned_ruling_count: usize,
    pairs: Vec<SymmetricPair>,
}

/// Patches, samples and rulings (§5.1, §5.2), mirror pairs (§5.3); the time of each
/// stage goes to `times` (the network's from `start`).
fn analyse(
    annotation: &PhotoAnnotation,
    network: &CurveNetwork,
    plane: &SymmetryPlane,
    times: &mut StageTimes,
    start: Instant,
) -> Result<Analysis, PhotoError> {
    let lengths = annotation.lengths();
    let patches = find_patches(network, annotation)?;
    let mut samples = sample_curves(network, lengths.sample);
    times.network_ms = milliseconds(start);
    let start = Instant::now();
    let (mut strips, propagation) = propagate_rulings(
        network,
        &samples,
        &patches,
        &PropagationOptions {
            ruling_spacing: lengths.ruling,
            smoothness_weight: annotation.analysis.dtw_smoothness_weight,
        },
    )?;
    let aligned_ruling_count = align_rulings(network, &mut samples, &mut strips);
    times.rulings_ms = milliseconds(start);
    let start = Instant::now();
    let pairs = symmetric_pairs_of_curves(network, &samples, &annotated_curve_pairs(annotation, network), plane)?;
    times.symmetry_ms = milliseconds(start);
    Ok(Analysis {
        patches,
        samples,
        strips,
        propagation,
        aligned_ruling_count,
        pairs,
    })
}

/// A network, its analysis and energy, and 3D control points for it.
struct Solved {
    network: CurveNetwork,
    analysis: Analysis,
    energy: Energy,
    points: Vec<f64>,
}

/// The model after the symmetrisation and the refinement.
struct Finished {
    network: CurveNetwork,
    /// The linear solution on this network (split exactly where it was split).
    linear: Vec<f64>,
    analysis: Analysis,
    energy: Energy,
    refined: Vec<f64>,
    refinement: Option<RefinementInfo>,
    points3d: Vec<f64>,
    symmetrization: Option<SymmetrizationInfo>,
    ruling_errors_refined: Vec<f64>,
}

/// Symmetrisation (§7) and refinement of the linear solution. With `symmetric`, the
/// curves are first split where their partners' nodes mirror (exactly: the solved model
/// does not change) and the analysis is redone on the split network, so that segments
/// mirror onto segments; the linear solution is symmetrised, so that the refinement
/// starts from a symmetric model and keeps it symmetric (its steps are taken in the free
/// coordinates of the mirror map); after it, the rulings are mirrored again from their
/// refined positive halves.
fn finish_model(
    annotation: &PhotoAnnotation,
    plane: &SymmetryPlane,
    base: &Solved,
    curve_pairs: &[[usize; 2]],
    symmetric: bool,
    times: &mut StageTimes,
) -> Result<Finished, PhotoError> {
    let start = Instant::now();
    let mut network = base.network.clone();
    let mut x = base.points.clone();
    let split_count = if symmetric {
        split_at_mirror_nodes(&mut network, &mut x, plane, curve_pairs, annotation.lengths().sample)?
    } else {
        0
    };
    let (mut analysis, energy) = if split_count > 0 {
        let mut ignored = StageTimes::default();
        let mut again = analyse(annotation, &network, plane, &mut ignored, Instant::now())?;
        if !plane.camera.is_orthographic() {
            align_rulings_in_perspective(&network, &mut again.samples, &mut again.strips, &plane.camera, &x);
        }
        let energy = assemble_energy(
            &network,
            &again.strips,
            &again.pairs,
            plane,
            &annotation.analysis.weights,
            &depths_of(&x),
        );
        (again, energy)
    } else {
        (base.analysis.clone(), base.energy.clone())
    };
    let (start_points, symmetrization, map) = if symmetric {
        let (y, mut info, map) = symmetrize(
            &network,
            &mut analysis.samples,
            &mut analysis.strips,
            plane,
            curve_pairs,
            &x,
        )?;
        if info.mirrored_segment_count == 0 {
            // Nothing mirrors: the model is the plain one (without the splits made for it).
            times.symmetrization_ms += milliseconds(start);
            let mut plain = finish_model(annotation, plane, base, curve_pairs, false, times)?;
            plain.symmetrization = Some(info);
            return Ok(plain);
        }
        info.split_segment_count = split_count;
        (y, Some(info), map)
    } else {
        (x.clone(), None, MirrorMap::identity(x.len()))
    };
    times.symmetrization_ms += milliseconds(start);
    let start = Instant::now();
    let (refined, refinement) = if annotation.analysis.refine {
        let (x, ends, info) = refine_developability(
            &network,
            &energy,
            &analysis.strips,
            &start_points,
            annotation.analysis.weights.projection,
            &map,
        )?;
        move_ruling_ends(&network, &mut analysis.samples, &mut analysis.strips, &ends);
        (x, Some(info))
    } else {
        (start_points, None)
    };
    let ruling_errors_refined = ruling_errors(&network, &refined, &analysis.strips);
    let points3d = if symmetric && annotation.analysis.refine {
        symmetrize(
            &network,
            &mut analysis.samples,
            &mut analysis.strips,
            plane,
            curve_pairs,
            &refined,
        )?
        .0
    } else {
        refined.clone()
    };
    times.refinement_ms += milliseconds(start);
    Ok(Finished {
        network,
        linear: x,
        analysis,
        energy,
        refined,
        refinement,
        points3d,
        symmetrization,
        ruling_errors_refined,
    })
}

/// The drawing analysed and lifted by the linear solve of §6, for one camera.
struct LinearStage {
    plane: SymmetryPlane,
    network: CurveNetwork,
    analysis: Analysis,
    energy: Energy,
    /// The solution for the image prior at depth 0.
    linear: Vec<f64>,
    /// The solution for the prior moved by `shift` along the rays.
    probe: Vec<f64>,
    /// How far the probe's prior was moved: a tenth of the diagonal.
    shift: f64,
}

/// The analysis (§5) and the linear solve (§6) of `annotation` through `camera`.
fn linear_stage(
    annotation: &PhotoAnnotation,
    camera: Camera,
    times: &mut StageTimes,
    start: Instant,
) -> Result<LinearStage, PhotoError> {
    let plane = SymmetryPlane::from_annotation(&annotation.symmetry, &camera)?;
    let network = build_curve_network(annotation)?;
    let mut analysis = analyse(annotation, &network, &plane, times, start)?;
    let start = Instant::now();
    let prior = image_prior(&network, &camera, 0.0);
    // Which depths the drawing fixes: solve again with the prior's depth moved by
    // `D` (a tenth of the diagonal) along the rays. A point the energy pins stays; a
    // point in the energy's null space (a circle no mirror pair reaches slides along the
    // view) follows the prior. The ratio of its move to `D` is its depth's sensitivity.
    // Same matrix, one factorisation.
    let shift = 0.1 * annotation.diagonal();
    let shifted = image_prior(&network, &camera, shift);
    // Under perspective the barycentric coordinates and the rulings' ends depend on the
    // depths: solve again with those of the last solution until its divisors settle.
    let mut depths: Vec<f64> = Vec::new();
    let mut solves = 0;
    let mut last: Option<Vec<f64>> = None;
    let (energy, linear, probe) = loop {
        if let Some(x) = &last {
            align_rulings_in_perspective(&network, &mut analysis.samples, &mut analysis.strips, &camera, x);
        }
        let energy = assemble_energy(
            &network,
            &analysis.strips,
            &analysis.pairs,
            &plane,
            &annotation.analysis.weights,
            &depths,
        );
        let mut solutions = solve_energy(&energy, &[&prior, &shifted])?;
        let probe = solutions.pop().expect("two priors");
        let linear = solutions.pop().expect("two priors");
        solves += 1;
        let new_depths = depths_of(&linear);
        let change = new_depths
            .iter()
            .enumerate()
            .map(|(k, &z)| (camera.divisor(z) - camera.divisor(depths.get(k).copied().unwrap_or(0.0))).abs())
            .fold(0.0, f64::max);
        depths = new_depths;
        if camera.is_orthographic() || change < 1e-9 || solves == PERSPECTIVE_SOLVES {
            tracing::debug!("photo: {solves} linear solves, last change of a divisor {change:.1e}");
            break (energy, linear, probe);
        }
        last = Some(linear);
    };
    times.linear_solve_ms = milliseconds(start);
    Ok(LinearStage {
        plane,
        network,
        analysis,
        energy,
        linear,
        probe,
        shift,
    })
}

/// Runs the method on a validated annotation.
///
/// # Errors
/// Curves that cross themselves, have zero length or close no cycle; a degenerate
/// symmetry annotation; true-size points far from every curve; solver failures; a
/// drawing whose analysis, symmetrisation, refinement or meshing would pass one of the
/// work bounds (each error names the field to change and the bound).
pub fn reconstruct(annotation: &PhotoAnnotation) -> Result<PhotoReconstruction, PhotoError> {
    annotation.validate()?;
    let lengths = annotation.lengths();
    let mut times = StageTimes::default();
    let (width, height) = (annotation.image.width, annotation.image.height);
    let centre = annotation.camera.principal_point_or_centre(width, height);
    // Neither the annotation nor the photo's EXIF gives a focal length: the one whose
    // linear solve leaves the rulings most nearly developable.
    let estimating = Instant::now();
    let focal_length_estimate = if annotation.camera.focal_length_missing() {
        Some(estimate_focal_length(annotation.diagonal(), |f| {
            let stage = linear_stage(
                annotation,
                Camera::perspective(f, centre),
                &mut StageTimes::default(),
                Instant::now(),
            )?;
            let errors = ruling_errors(&stage.network, &stage.linear, &stage.analysis.strips);
            if errors.is_empty() {
                return Err(PhotoError::field(
                    "camera",
                    "a perspective camera needs its focal length, and neither the annotation nor the photo's \
                     EXIF gives one; a drawing without ruled patches cannot tell it: give focal_length_35mm \
                     (about 26 mm for a phone's main camera) or focal_length_px",
                ));
            }
            Ok(errors.iter().sum::<f64>() / errors.len() as f64)
        })?)
    } else {
        None
    };
    times.focal_length_estimate_ms = milliseconds(estimating);
    let camera = match &focal_length_estimate {
        Some(estimate) => Camera::perspective(estimate.focal_length_px, centre),
        None => Camera::from_spec(&annotation.camera, width, height)?,
    };
    let start = Instant::now();
    let LinearStage {
        plane,
        network,
        analysis,
        energy,
        linear,
        probe,
        shift,
    } = linear_stage(annotation, camera, &mut times, start)?;
    let depth_sensitivity: Vec<f64> = network
        .curves
        .iter()
        .map(|c| {
            c.segments
                .iter()
                .flat_map(|&s| network.segments[s as usize].points)
                .map(|p| {
                    let k = 3 * p as usize;
                    Vec3::new(
                        probe[k] - linear[k],
                        probe[k + 1] - linear[k + 1],
                        probe[k + 2] - linear[k + 2],
                    )
                    .norm()
                        / shift
                })
                .fold(0.0, f64::max)
        })
        .collect();
    let ruling_errors_linear = ruling_errors(&network, &linear, &analysis.strips);
    let rulings_linear: Vec<(usize, [Vec2; 2])> = analysis
        .strips
        .iter()
        .flat_map(|s| (0..s.rulings.len()).map(move |i| (s.patch, s.segment(i))))
        .collect();
    let curve_pairs = annotated_curve_pairs(annotation, &network);
    let base = Solved {
        network,
        analysis,
        energy,
        points: linear.clone(),
    };
    let symmetric = annotation.analysis.symmetrize;
    let mut finished = finish_model(annotation, &plane, &base, &curve_pairs, symmetric, &mut times)?;
    if symmetric && finished.refinement.is_some_and(|r| !r.converged) {
        // The mirror-symmetric model cannot be made developable (a perspective or
        // inconsistent drawing): the model is left as solved, and the report says so.
        let mut plain = finish_model(annotation, &plane, &base, &curve_pairs, false, &mut times)?;
        if plain.refinement.is_some_and(|r| r.converged) {
            plain.symmetrization = finished.symmetrization.take().map(|info| SymmetrizationInfo {
                abandoned: true,
                ..info
            });
            finished = plain;
        }
    }
    let Finished {
        network,
        linear,
        analysis:
            Analysis {
                patches,
                samples,
                strips,
                propagation,
                aligned_ruling_count,
                pairs,
            },
        energy,
        refined,
        refinement,
        points3d,
        symmetrization,
        ruling_errors_refined,
    } = finished;
    let ruling_errors_final = ruling_errors(&network, &points3d, &strips);
    // Reprojection: solved curves against traced curves at every sample.
    let (mut sum, mut max, mut count) = (0.0, 0.0f64, 0usize);
    for (s, params) in samples.parameters.iter().enumerate() {
        for &t in params {
            let place = CurvePoint { segment: s as u32, t };
            let p = place_point(&network, &points3d, place);
            let q = cubic::point(&network.control_points(s), t);
            let d = (camera.project(p) - q).norm();
            sum += d;
            max = max.max(d);
            count += 1;
        }
    }
    let reprojection_error_px = (sum / count.max(1) as f64, max);
    // True size.
    let size = &annotation.true_size;
    let tolerance = 3.0 * lengths.snap + annotation.diagonal() / 100.0;
    let mut ends = Vec::new();
    for (field, point) in [("true_size.from", size.from), ("true_size.to", size.to)] {
        let (place, distance) = nearest_place(&network, image_to_model(point));
        if distance > tolerance {
            return Err(PhotoError::field(
                field,
                format!(
                    "[{}, {}] is {} px from the nearest curve (at most {})",
                    sheetform_geometry::short_number(point[0]),
                    sheetform_geometry::short_number(point[1]),
                    sheetform_geometry::numbers_apart(distance, tolerance)[0],
                    sheetform_geometry::numbers_apart(distance, tolerance)[1]
                ),
            ));
        }
        ends.push(place_point(&network, &points3d, place));
    }
    let measured = (ends[1] - ends[0]).norm();
    if measured.is_nan() || measured <= 1e-6 {
        return Err(PhotoError::field(
            "true_size",
            "the two points coincide on the reconstructed model: the distance fixes no scale",
        ));
    }
    let unit_per_pixel = size.length / measured;
    let start = Instant::now();
    let mut mesh = mesh_patches(&network, &samples, &patches, &strips, &points3d, lengths.sample)?;
    for p in &mut mesh.positions {
        *p *= unit_per_pixel;
    }
    let revolution = match annotation.back_side {
        BackSide::Visible => None,
        BackSide::Revolve => {
            let (closed, revolution) = revolve_bands(
                &mesh,
                &plane,
                &camera,
                unit_per_pixel,
                lengths.sample * unit_per_pixel,
                lengths.ruling * unit_per_pixel,
            )?;
            mesh = closed;
            Some(revolution)
        }
    };
    times.meshing_ms = milliseconds(start);
    if mesh.positions.iter().any(|p| !p.iter().all(|v| v.is_finite())) {
        return Err(PhotoError::Solver(
            "the reconstructed surface has points at no finite place (control points or weights far out of \
             scale?)"
                .into(),
        ));
    }
    Ok(PhotoReconstruction {
        network,
        samples,
        patches,
        strips,
        propagation,
        aligned_ruling_count,
        plane,
        pairs,
        energy,
        linear,
        refined,
        refinement,
        points3d,
        symmetrization,
        depth_sensitivity,
        rulings_linear,
        ruling_errors_linear,
        ruling_errors_refined,
        ruling_errors_final,
        reprojection_error_px,
        mesh,
        unit_per_pixel,
        revolution,
        focal_length_estimate,
        times,
    })
}

impl PhotoReconstruction {
    /// Names of the curves whose depth the drawing does not fix.
    pub fn depth_undetermined_curves(&self) -> Vec<String> {
        self.network
            .curves
            .iter()
            .zip(&self.depth_sensitivity)
            .filter(|(_, &s)| s > DEPTH_SENSITIVITY_BOUND)
            .map(|(c, _)| c.name.clone())
            .collect()
    }

    /// Rulings over all strips.
    pub fn ruling_count(&self) -> usize {
        self.strips.iter().map(|s| s.rulings.len()).sum()
    }

    /// The 3D point (model units) of a place on the final model.
    pub fn point(&self, place: CurvePoint) -> Vec3 {
        place_point(&self.network, &self.points3d, place) * self.unit_per_pixel
    }
}

//! `sheetform develop`: a target mesh → the nearest surface made of exactly developable
//! pieces (cut along the user's seams), unfolded exactly, with the patterns of `flatten`
//! (issue 36: automatic seams, or the user's only).

use super::check::mesh_name;
use super::context::{no_progress, RunContext};
use super::error::{Outcome, PipelineError};
use super::flatten::{run_flatten, ChartMode, FlattenOptions, FlattenRun};
use super::outputs::output_names;
use crate::report::{Command, DevelopReport, Status};
use sheetform_develop::{
    develop_pieces, seam_pieces, segment_developable, slit_unflattened_vertices, smooth_seams, DevelopError,
    MirrorBoundary,
};
pub use sheetform_develop::{DevelopOptions, Developed, SeamSmoothingOptions, SegmentationOptions};
use sheetform_flatten::ChartOptions;
use sheetform_io::{colour_ramp, glb_vertex_colours, ply_vertex_colours, UpAxis};
use sheetform_mesh::{
    mesh_topology_with_edges, mirror_half, mirror_whole, remesh_isotropic, surface_distance, vertex_angle_sums,
    vertex_distances, EdgeTable, MirrorPlane, RemeshOptions, SurfaceDistanceOptions, SurfaceIndex, TriangleMesh,
};
use sheetform_pattern::PatternError;
use std::borrow::Cow;

/// Where `develop` cuts the target.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum SeamSource {
    /// Seams found by [`sheetform_develop::segment_developable`], as many pieces as the
    /// budget allows until each is close to a developable; the drawn seams (OBJ `l`) are
    /// always among them.
    #[default]
    Automatic,
    /// Only the drawn seams.
    Drawn,
}

/// How far the developed surface may be from the target (two-sided Hausdorff distance).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum DistanceBound {
    /// A fraction of the target's bounding-box diagonal (0.01 = 1 %).
    Relative(f64),
    /// A length in the mesh's units.
    Absolute(f64),
}

impl std::str::FromStr for DistanceBound {
    type Err = String;

    /// `0.5%` (a percentage of the bounding-box diagonal) or `2` (a length in the mesh's
    /// units), as `--max-distance` and the Python binding's `max_distance` spell it.
    fn from_str(text: &str) -> Result<Self, String> {
        let (number, relative) = match text.trim().strip_suffix('%') {
            Some(percent) => (percent.trim(), true),
            None => (text.trim(), false),
        };
        let value: f64 = number.parse().map_err(|_| {
            format!(
                "`{}` is not a distance: give a length in the mesh's units (2) or a percentage of its size (0.5%)",
                sheetform_geometry::shortened_message(text)
            )
        })?;
        Ok(if relative {
            Self::Relative(value / 100.0)
        } else {
            Self::Absolute(value)
        })
    }
}

impl DistanceBound {
    /// The bound in the mesh's units, for a target of bounding-box `diagonal`.
    pub fn in_model_units(&self, diagonal: f64) -> f64 {
        match *self {
            Self::Relative(fraction) => fraction * diagonal,
            Self::Absolute(length) => length,
        }
    }

    fn validate(&self) -> Result<(), DevelopError> {
        let (value, ok) = match *self {
            Self::Relative(f) => (f, f.is_finite() && f > 0.0 && f <= 1.0),
            Self::Absolute(l) => (l, l.is_finite() && l > 0.0 && l <= 1e12),
        };
        if ok {
            Ok(())
        } else {
            Err(DevelopError::Option {
                option: "max_distance",
                message: format!(
                    "must be a positive length, or a fraction of the size up to 100 %, got {}",
                    sheetform_geometry::short_number(value)
                ),
            })
        }
    }
}

/// A mirror plane `develop` keeps (`--mirror x`, `--mirror x=0`): perpendicular to a
/// coordinate axis, through the target's bounding-box centre unless placed.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct Mirror {
    /// The plane's normal axis: 0 = x, 1 = y, 2 = z.
    pub axis: usize,
    /// Where the plane crosses the axis (the mesh's units); `None`: the middle of the
    /// target's bounding box along it.
    pub offset: Option<f64>,
}

impl std::str::FromStr for Mirror {
    type Err = String;

    /// `x`, `y` or `z` (the plane through the bounding box's middle), or `x=0` (placed).
    fn from_str(text: &str) -> Result<Self, String> {
        let text = text.trim();
        let (name, offset) = match text.split_once('=') {
            Some((name, value)) => (name.trim(), Some(value.trim())),
            None => (text, None),
        };
        let axis = match name.to_ascii_lowercase().as_str() {
            "x" => 0,
            "y" => 1,
            "z" => 2,
            _ => {
                return Err(format!(
                    "`{}` is not a mirror plane: give its normal axis (x, y or z), placed with = (x=0) or through the middle of the mesh (x)",
                    sheetform_geometry::shortened_message(text)
                ))
            }
        };
        let offset = match offset {
            None => None,
            Some(value) => match value.parse::<f64>() {
                Ok(v) if v.is_finite() && v.abs() <= 1e12 => Some(v),
                _ => {
                    return Err(format!(
                        "`{}` is not a position on the {name} axis: give a number in the mesh's units",
                        sheetform_geometry::shortened_message(value)
                    ))
                }
            },
        };
        Ok(Self { axis, offset })
    }
}

/// Knobs of `sheetform develop`.
#[derive(Debug, Clone, Default)]
pub struct DevelopRunOptions {
    /// Where the target is cut.
    pub seams: SeamSource,
    /// The largest distance to the target accepted. With automatic seams, pieces are
    /// added (up to the budget) until it holds; a result still farther is `out of
    /// tolerance` (exit 5), the closest one written. `None`: no bound.
    pub max_distance: Option<DistanceBound>,
    /// How automatic seams are found (the piece budget, the fit).
    pub segmentation: SegmentationOptions,
    /// How automatic seams are slid over the developed surface onto smooth curves before
    /// the pieces are developed again ([`sheetform_develop::smooth_seams`];
    /// `iterations: 0`: along the mesh's edges as found). Drawn seams, fixed vertices and
    /// a mirror plane's vertices never move.
    pub seam_smoothing: SeamSmoothingOptions,
    /// How the pieces are made developable.
    pub develop: DevelopOptions,
    /// Regions kept where they are: the faces of these mesh groups (OBJ `g` names) do
    /// not move, nor do their vertices.
    pub fixed_groups: Vec<String>,
    /// Vertices kept where they are (0-based indices), besides `fixed_groups`'.
    pub fixed_vertices: Vec<u32>,
    /// Most faces develop works on: a target of more is remeshed first into about this
    /// many well-shaped triangles ([`sheetform_mesh::remesh_isotropic`]; its boundary,
    /// drawn seams and fixed regions kept vertex for vertex), and the result has them.
    /// `None`: [`DEFAULT_WORK_FACES`].
    pub work_faces: Option<usize>,
    /// A mirror plane the result keeps: the half of the target on the side holding more
    /// of its area is developed (a half model is kept whole) and joined with its mirror
    /// image along the plane, with no seam there unless one is needed. The pieces come
    /// in mirrored pairs, a piece across the plane is symmetric, and the piece budget
    /// counts the whole (the half gets half of it). `None`: no symmetry.
    pub mirror: Option<Mirror>,
    /// How the developed pieces are unfolded and drawn: `flatten`'s options (the unit,
    /// the pattern, the name, the size). The layout is always exact charts cut along the
    /// seams only (`charts` and the chart options are set by `develop`).
    pub flatten: FlattenOptions,
}

/// Most faces develop works on unless told otherwise (`--work-faces`). Measured
/// (docs/benchmarks-history.md, session 26) on a 100k-face koala scan: worked on at 3.6k, 9.2k
/// and 18k faces it develops in 2.9, 4.4 and 27 s into 12, 15 and 50 pieces, 2.6 %,
/// 2.9 % and 1.9 % of the diagonal from the scan: the solve's time grows much faster than
/// the faces, and a finer working mesh is closer only with many more pieces.
pub const DEFAULT_WORK_FACES: usize = 10_000;

/// Fewest faces `--work-faces` accepts.
pub const MIN_WORK_FACES: usize = 100;

/// Pieces of the first attempt under a distance bound.
const FIRST_PIECE_COUNT: usize = 4;

/// Without a distance bound, the result with its seams smoothed is kept when its
/// Hausdorff distance to the target is at most this fraction above the unsmoothed one's
/// (measured, docs/benchmarks-history.md session 32: smoothing moved it by −1 % to +7 % on the
/// develop targets).
pub const SMOOTHED_DISTANCE_SLACK: f64 = 0.1;

/// With automatic seams, a solve that leaves defects above the tolerance is tried again
/// at most this many times, each time with slits from the vertices it could not flatten
/// (those within a tenth of the largest defect left).
pub const SLIT_ROUNDS: usize = 3;

/// A mirror plane the target is farther than this fraction of its bounding-box diagonal
/// from being symmetric in (two-sided Hausdorff distance to its mirror image) gets a
/// warning in the report: the result repeats one half.
pub const MIRROR_ASYMMETRY_WARNING: f64 = 0.01;

/// With a mirror plane and no distance bound, the half's piece budget is raised at most
/// this many times towards the whole's (see [`DevelopRunOptions::mirror`]).
pub const MIRROR_BUDGET_ROUNDS: usize = 3;

/// One segmentation and development of the target.
struct Attempt {
    /// The developed mesh (with a mirror plane, the half joined with its image).
    result: TriangleMesh,
    /// With a mirror plane, the half vertex each vertex of `result` is or mirrors.
    half_vertex: Option<Vec<u32>>,
    /// The edges of `result`.
    result_table: EdgeTable,
    /// The pieces of `result` (with a mirror plane, a piece across it counts once).
    whole_pieces: sheetform_develop::SeamPieces,
    segmentation: Option<sheetform_develop::Segmentation>,
    pieces: sheetform_develop::SeamPieces,
    developed: Developed,
    distance: sheetform_mesh::SurfaceDistance,
    /// Slits cut after a solve left cone points unflattened.
    late_slit_count: usize,
    /// Seam vertices smoothing moved in the result kept.
    smoothed_count: usize,
}

/// A finished `develop`.
#[derive(Debug)]
pub struct DevelopRun {
    /// The developed mesh with its pattern, files and report (command `develop`, with
    /// its `develop` section).
    pub run: FlattenRun,
    /// What the developability solve did.
    pub developed: Developed,
}

/// Cuts `target` into pieces (automatic seams by
/// [`sheetform_develop::segment_developable`], the drawn ones among them; or the drawn
/// seams only, `target.seam_edges`: OBJ `l` polylines), makes every piece exactly
/// developable by moving its vertices as little as possible
/// ([`sheetform_develop::develop_pieces`]; the fixed groups and vertices do not move),
/// then unfolds each piece exactly and renders the model and the patterns as `flatten`
/// does ([`run_flatten`], charts cut along the seams only; a developed piece that would
/// overlap itself in the plane is cut again, and the printed pieces are what the report
/// counts). With automatic seams, a solve that leaves a defect above the tolerance is
/// run again after slits from the vertices it could not flatten
/// ([`sheetform_develop::slit_unflattened_vertices`], at most [`SLIT_ROUNDS`] times; a
/// solve with a vertex stuck far from flat is ended early there,
/// [`sheetform_develop::HOPELESS_DEFECT`], and its stuck vertices are cut free);
/// then its seams, which run along mesh edges in steps, are slid over the developed
/// surface onto smooth curves ([`sheetform_develop::smooth_seams`],
/// [`DevelopRunOptions::seam_smoothing`]) and the pieces developed again from there, the
/// smoother result kept when it is developable and within the distance bound (without
/// one, within [`SMOOTHED_DISTANCE_SLACK`] of the unsmoothed distance).
/// With a mirror plane ([`DevelopRunOptions::mirror`]) the half of the target cut by
/// [`sheetform_mesh::mirror_half`] is developed, in two layouts (pieces across the plane,
/// flat on it in the whole; or a centre seam; searched at once on two threads, the
/// second reporting no progress) of which the better is kept, and joined
/// with its image ([`sheetform_mesh::mirror_whole`]) before the unfolding. The
/// report's `develop` section gives the seams, the defects before and after and the
/// two-sided distance to the target ([`sheetform_mesh::surface_distance`]); its status
/// is `out of tolerance` (exit 5, everything written) when a defect inside a piece stays
/// above the tolerance.
///
/// # Errors
/// A mesh that is not a clean manifold or has no faces; a closed mesh without drawn
/// seams when only those are asked for; a seam off the mesh's edges; a fixed group the
/// mesh does not have or a fixed vertex out of range; options out of range; a mirror
/// plane whose half of the mesh is not a clean manifold or that holds the whole mesh;
/// [`PipelineError::Cancelled`].
pub fn run_develop(
    target: TriangleMesh,
    options: &DevelopRunOptions,
    context: &RunContext,
) -> Result<DevelopRun, PipelineError> {
    let started = std::time::Instant::now();
    options.develop.validate()?;
    options.segmentation.validate()?;
    options.seam_smoothing.validate()?;
    if let Some(bound) = &options.max_distance {
        bound.validate()?;
    }
    let unit = options.flatten.unit.millimetres();
    if target.triangles.is_empty() {
        return Err(DevelopError::Topology {
            problem: "the mesh has no faces".into(),
        }
        .into());
    }
    let (topology, table) = mesh_topology_with_edges(&target);
    let problems = topology.problems();
    if !problems.is_empty() {
        return Err(DevelopError::Topology {
            problem: problems.join("; "),
        }
        .into());
    }
    let (low, high) = target.positions.iter().fold(
        (
            nalgebra::Vector3::repeat(f64::INFINITY),
            nalgebra::Vector3::repeat(f64::NEG_INFINITY),
        ),
        |(low, high), p| (low.inf(p), high.sup(p)),
    );
    let diagonal = (high - low).norm();
    let bound = options.max_distance.map(|b| b.in_model_units(diagonal));
    let fixed = fixed_vertices(&target, &options.fixed_groups, &options.fixed_vertices)?;
    // A target finer than the working size is remeshed first; the distances are to the
    // target as read (`full`).
    let work_faces = options.work_faces.unwrap_or(DEFAULT_WORK_FACES);
    if work_faces < MIN_WORK_FACES {
        return Err(PipelineError::Option {
            option: "work_faces",
            message: format!("must be at least {MIN_WORK_FACES} faces, got {work_faces}"),
        });
    }
    let full = target;
    // With a remeshed target, the target vertex each working vertex is (`u32::MAX` for
    // a new one).
    let mut target_vertex_of_work: Option<Vec<u32>> = None;
    let (target, table, fixed) = if full.triangles.len() > work_faces {
        // The drawn seams are checked on the target as read, so that a seam off its
        // edges is named by the user's vertex numbers.
        seam_pieces(&full, &table, &full.seam_edges)?;
        context.progress("remeshing the target", 0.01);
        let remeshed = remesh_isotropic(
            &full,
            &fixed,
            &RemeshOptions {
                face_count: work_faces,
                ..Default::default()
            },
        );
        let mut origin = vec![u32::MAX; remeshed.mesh.positions.len()];
        for (v, &k) in remeshed.kept.iter().enumerate() {
            if k != u32::MAX {
                origin[k as usize] = v as u32;
            }
        }
        // Fixed vertices are kept by the remeshing: their flags follow them.
        let work_fixed: Vec<bool> = if fixed.is_empty() {
            Vec::new()
        } else {
            origin.iter().map(|&v| v != u32::MAX && fixed[v as usize]).collect()
        };
        target_vertex_of_work = Some(origin);
        tracing::info!(
            faces = full.triangles.len(),
            work_faces = remeshed.mesh.triangles.len(),
            edge_length = remeshed.edge_length,
            "develop: the target remeshed to the working size"
        );
        let (_, table) = mesh_topology_with_edges(&remeshed.mesh);
        (Cow::Owned(remeshed.mesh), table, work_fixed)
    } else {
        (Cow::Borrowed(&full), table, fixed)
    };
    // With a mirror plane, the half on the side with more area is worked on; the
    // result is it joined with its mirror image.
    let mirror = match options.mirror {
        None => None,
        Some(spec) => {
            // Drawn seams are checked on the target (named by its vertex numbers) before
            // the cut.
            seam_pieces(&target, &table, &target.seam_edges)?;
            Some(MirrorWork::new(&target, &fixed, &full, spec, low, high)?)
        }
    };
    let (work, work_table, work_fixed): (&TriangleMesh, &EdgeTable, &[bool]) = match &mirror {
        Some(m) => (&m.half.mesh, &m.table, &m.fixed),
        None => (target.as_ref(), &table, &fixed),
    };
    // What distances are measured to: the target as read (a half model with its image).
    let reference: &TriangleMesh = mirror.as_ref().and_then(|m| m.reference.as_ref()).unwrap_or(&full);
    let mirror_boundary = mirror.as_ref().map(|m| MirrorBoundary {
        axis: m.plane.axis,
        on_plane: &m.half.on_plane,
    });
    // The budget counts the whole's pieces: the half starts with half of it, and may
    // have up to all of it (when each of its pieces crosses the plane), an attempt whose
    // whole has more than the budget not taken.
    let whole_limit = options.segmentation.max_pieces;
    let budget = if mirror.is_some() {
        (whole_limit / 2).max(1)
    } else {
        whole_limit
    };
    let segmentation_options = SegmentationOptions {
        max_pieces: budget,
        ..options.segmentation
    };
    // The drawn seams are checked (and named when off the mesh) as seams of their own.
    let drawn = seam_pieces(work, work_table, &work.seam_edges)?;
    let mut hard = vec![false; work_table.len()];
    for &e in &drawn.seam_edges {
        hard[e] = true;
    }
    if options.seams == SeamSource::Drawn
        && target.seam_edges.is_empty()
        && topology.boundary_loop_count == 0
        && options.mirror.is_none()
    {
        return Err(DevelopError::Topology {
            problem: "a closed surface cannot be developed without cuts: draw its seams as OBJ `l` polylines along mesh edges, or let develop find them (--seams automatic)".into(),
        }
        .into());
    }
    // What seam smoothing never moves: the drawn seams, the fixed vertices and the
    // mirror plane's (a centre seam runs on the plane).
    let mut seam_locked = vec![false; work.positions.len()];
    for (e, &[a, b]) in work_table.edges.iter().enumerate() {
        if hard[e] {
            seam_locked[a as usize] = true;
            seam_locked[b as usize] = true;
        }
    }
    for (flag, &fixed) in seam_locked.iter_mut().zip(work_fixed) {
        *flag |= fixed;
    }
    if let Some(m) = &mirror {
        for (flag, &on) in seam_locked.iter_mut().zip(&m.half.on_plane) {
            *flag |= on;
        }
    }
    // With a mirror plane, `centre_seam` cuts the whole along the plane (the half's cut
    // is a seam); without, pieces run across it where they can.
    // An attempt reports its progress through `report` and reads the cancel flag alone
    // (not the context), so that the two mirror layouts can be searched on two threads.
    let cancel = context.cancel;
    // Set when one of the two mirror layouts' searches fails: the other stops at its
    // next attempt or slit round (the run fails either way).
    let abandoned = std::sync::atomic::AtomicBool::new(false);
    let check_cancelled = || {
        let relaxed = std::sync::atomic::Ordering::Relaxed;
        if cancel.is_some_and(|flag| flag.load(relaxed)) || abandoned.load(relaxed) {
            Err(PipelineError::Cancelled)
        } else {
            Ok(())
        }
    };
    let attempt_with = |segmentation: &SegmentationOptions,
                        emphasis: &[f64],
                        progress: f64,
                        centre_seam: bool,
                        report: &dyn Fn(&str, f64)|
     -> Result<Attempt, PipelineError> {
        check_cancelled()?;
        report("finding the seams", progress);
        let centre: &[[u32; 2]] = match &mirror {
            Some(m) if centre_seam => &m.plane_edges,
            _ => &[],
        };
        let (seams, segmentation) = match options.seams {
            SeamSource::Drawn => (work.seam_edges.iter().chain(centre).copied().collect(), None),
            SeamSource::Automatic => {
                let mut hard = hard.clone();
                for &[a, b] in centre {
                    if let Some(e) = work_table.find(a, b) {
                        hard[e] = true;
                    }
                }
                let found = segment_developable(work, work_table, &hard, emphasis, segmentation, cancel)?;
                (found.seams.clone(), Some(found))
            }
        };
        report("making the pieces developable", progress + 0.02);
        let solve = |pieces: &sheetform_develop::SeamPieces, end_at_hopeless_cone_points: bool| {
            develop_pieces(
                work,
                work_table,
                pieces,
                work_fixed,
                mirror_boundary.as_ref(),
                &DevelopOptions {
                    end_at_hopeless_cone_points,
                    ..options.develop
                },
                cancel,
            )
        };
        let automatic = options.seams == SeamSource::Automatic;
        let mut pieces = seam_pieces(work, work_table, &seams)?;
        let mut developed = solve(&pieces, automatic && SLIT_ROUNDS > 0)?;
        check_cancelled()?;
        // Cone points the solve could not flatten (a saddle where a handle meets a body,
        // a tip below the cone angle) get slits, and the pieces are solved again.
        let mut seams = seams;
        let mut late_slit_count = 0;
        let mut steps = developed.iterations;
        for round in 0..SLIT_ROUNDS {
            if developed.converged || !automatic {
                break;
            }
            // A solve ended early names its hopeless cone points (each above
            // HOPELESS_DEFECT); one that ran its course, those within a tenth of its
            // largest defect.
            let threshold = if developed.hopeless.is_empty() {
                (0.1 * developed.max_defect).max(options.develop.defect_tolerance)
            } else {
                options.develop.defect_tolerance
            };
            let (more, slits) = slit_unflattened_vertices(
                work,
                &developed.positions,
                work_table,
                &pieces,
                mirror_boundary.as_ref(),
                threshold,
                (!developed.hopeless.is_empty()).then_some(developed.hopeless.as_slice()),
            );
            if slits == 0 {
                if developed.hopeless.is_empty() {
                    break;
                }
                // Ended early at cone points no slit could reach: the solve runs its
                // course, and the next round slits what it leaves.
                developed = solve(&pieces, false)?;
                check_cancelled()?;
                steps += developed.iterations;
                continue;
            }
            tracing::debug!(
                slits,
                max_defect = developed.max_defect,
                "develop: slits from cone points left"
            );
            late_slit_count += slits;
            seams = more;
            pieces = seam_pieces(work, work_table, &seams)?;
            developed = solve(&pieces, round + 1 < SLIT_ROUNDS)?;
            check_cancelled()?;
            steps += developed.iterations;
        }
        if !developed.hopeless.is_empty() {
            // Defensive: the last round's solve and the one after a round that cut no
            // slit run their course, so no solve ended early reaches the result.
            developed = solve(&pieces, false)?;
            check_cancelled()?;
            steps += developed.iterations;
        }
        developed.iterations = steps;
        // The developed half joined with its mirror image (with a plane), and its
        // distance to the target.
        let built = |positions: &[nalgebra::Vector3<f64>]| -> Result<_, PipelineError> {
            let mut result = work.clone();
            result.positions = positions.to_vec();
            result.seam_edges.clone_from(&seams);
            let half_vertex = match &mirror {
                Some(m) => {
                    let whole = mirror_whole(&result, &m.half.on_plane, &m.plane);
                    let problems = sheetform_mesh::mesh_topology(&whole.mesh).problems();
                    if !problems.is_empty() {
                        return Err(DevelopError::Topology {
                            problem: format!(
                                "joined with its mirror image in {}, the developed half is not a clean manifold ({}): place the plane where the mesh crosses it cleanly",
                                m.plane.describe(),
                                problems.join("; ")
                            ),
                        }
                        .into());
                    }
                    result = whole.mesh;
                    Some(whole.half_vertex)
                }
                None => None,
            };
            let distance = surface_distance(&result, reference, &SurfaceDistanceOptions::default());
            Ok((result, half_vertex, distance))
        };
        let (mut result, mut half_vertex, mut distance) = built(&developed.positions)?;
        let mut smoothed_count = 0;
        // The seams found run along mesh edges, in steps: on the developed surface they
        // are slid onto smooth curves and the pieces made developable again from there,
        // kept when that converges and stays within the distance bound (a result already
        // farther than the bound: no farther), or without a bound within
        // SMOOTHED_DISTANCE_SLACK of the unsmoothed distance. A second solve that fails
        // leaves the first result (smoothing the target's seams before the first solve
        // was measured to leave the solve unconverged and cut many more slits:
        // docs/benchmarks-history.md, session 32).
        if options.seams == SeamSource::Automatic && developed.converged && options.seam_smoothing.iterations > 0 {
            let surface = TriangleMesh {
                positions: developed.positions.clone(),
                ..work.clone()
            };
            let smoothed = smooth_seams(&surface, work_table, &seams, &seam_locked, &options.seam_smoothing);
            if smoothed.moved_count > 0 {
                let surface = TriangleMesh {
                    positions: smoothed.positions,
                    ..surface
                };
                let again = match develop_pieces(
                    &surface,
                    work_table,
                    &pieces,
                    work_fixed,
                    mirror_boundary.as_ref(),
                    &DevelopOptions {
                        end_at_hopeless_cone_points: false,
                        ..options.develop
                    },
                    cancel,
                ) {
                    Ok(again) => Some(again),
                    Err(DevelopError::Cancelled) => return Err(PipelineError::Cancelled),
                    Err(error) => {
                        tracing::debug!(%error, "develop: the smoothed seams' solve failed; the seams kept as found");
                        None
                    }
                };
                check_cancelled()?;
                if let Some(again) = again {
                    developed.iterations += again.iterations;
                    let smooth = if again.converged {
                        built(&again.positions)
                            .inspect_err(|error| tracing::debug!(%error, "develop: the smoothed result not kept"))
                            .ok()
                    } else {
                        None
                    };
                    let allowed = match bound {
                        Some(b) if distance.hausdorff <= b => b,
                        Some(_) => distance.hausdorff,
                        None => (1.0 + SMOOTHED_DISTANCE_SLACK) * distance.hausdorff,
                    };
                    let kept = smooth.filter(|(_, _, d)| d.hausdorff <= allowed);
                    tracing::debug!(
                        converged = again.converged,
                        iterations = again.iterations,
                        moved = smoothed.moved_count,
                        kept = kept.is_some(),
                        "develop: seams smoothed, the pieces developed again"
                    );
                    if let Some(smooth) = kept {
                        let moves: Vec<f64> = again
                            .positions
                            .iter()
                            .zip(&work.positions)
                            .map(|(p, q)| (p - q).norm())
                            .collect();
                        developed = Developed {
                            iterations: developed.iterations,
                            max_defect_before: developed.max_defect_before,
                            displacement_max: moves.iter().copied().fold(0.0, f64::max),
                            displacement_mean: moves.iter().sum::<f64>() / moves.len().max(1) as f64,
                            ..again
                        };
                        (result, half_vertex, distance) = smooth;
                        smoothed_count = smoothed.moved_count;
                    }
                }
            }
        }
        let result_table = EdgeTable::new(&result.triangles, result.positions.len());
        let whole_pieces = seam_pieces(&result, &result_table, &result.seam_edges)?;
        Ok(Attempt {
            result,
            result_table,
            whole_pieces,
            half_vertex,
            segmentation,
            pieces,
            developed,
            distance,
            late_slit_count,
            smoothed_count,
        })
    };
    // With a distance bound and automatic seams: from a few pieces (at most 4, fewer when
    // the pieces fit cones within the normal tolerance), more pieces (half as many again
    // each time, the normal tolerance lifted so the count is used; each count tried
    // again with its pieces drawn to where it was far, `distance_emphasis`) until the
    // bound holds or the budget is spent; the closest developed attempt is kept. Without a bound:
    // one attempt, the budget used until the normal tolerance holds.
    let first = match (bound, options.seams) {
        (Some(_), SeamSource::Automatic) => SegmentationOptions {
            max_pieces: budget.min(FIRST_PIECE_COUNT),
            ..segmentation_options
        },
        _ => segmentation_options,
    };
    let half_limit = if mirror.is_some() { whole_limit } else { budget };
    let attempts = std::sync::atomic::AtomicUsize::new(0);
    let count_attempt = || attempts.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let progress_now = || (0.02 + 0.1 * attempts.load(std::sync::atomic::Ordering::Relaxed) as f64).min(0.5);
    // The first attempt, then more pieces while the distance bound does not hold, or
    // (mirror plane, no bound) while the whole keeps within the budget.
    let search = |centre_seam: bool, report: &dyn Fn(&str, f64)| -> Result<Attempt, PipelineError> {
        let mut best = attempt_with(&first, &[], progress_now(), centre_seam, report)?;
        count_attempt();
        if let (Some(bound), SeamSource::Automatic) = (bound, options.seams) {
            let mut count = best.pieces.piece_count;
            while best.distance.hausdorff > bound && count < half_limit {
                count = (count + count.div_ceil(2)).min(half_limit);
                let segmentation = SegmentationOptions {
                    max_pieces: count,
                    normal_tolerance_degrees: 0.0,
                    ..segmentation_options
                };
                let mut next = attempt_with(&segmentation, &[], progress_now(), centre_seam, report)?;
                count_attempt();
                // The most pieces either try used: the search goes on while that grows.
                let mut tried_pieces = next.pieces.piece_count;
                if next.distance.hausdorff > bound {
                    // The same count again, the pieces drawn to where this attempt was
                    // farthest from the target (see `distance_emphasis`); the better
                    // kept (`better_attempt`).
                    let emphasis = distance_emphasis(work, &next.developed.positions, reference, bound);
                    let tried = attempt_with(&segmentation, &emphasis, progress_now(), centre_seam, report);
                    count_attempt();
                    match tried {
                        Ok(emphasised) => {
                            tracing::debug!(
                                centre_seam,
                                pieces = emphasised.pieces.piece_count,
                                hausdorff = emphasised.distance.hausdorff,
                                converged = emphasised.developed.converged,
                                plain = next.distance.hausdorff,
                                "develop: the same count with the pieces drawn to where it was far"
                            );
                            if emphasised.whole_pieces.piece_count <= whole_limit {
                                tried_pieces = tried_pieces.max(emphasised.pieces.piece_count);
                                // Within the budget it beats a plain try that is not.
                                if next.whole_pieces.piece_count > whole_limit || better_attempt(&emphasised, &next) {
                                    next = emphasised;
                                }
                            }
                        }
                        Err(error) if error.kind() == crate::pipeline::ErrorKind::Cancelled => {
                            return Err(PipelineError::Cancelled)
                        }
                        // An extra try that fails (a singular step, a mirror join that is
                        // not clean) leaves the plain one.
                        Err(error) => tracing::debug!(%error, "develop: the try drawn to where it was far failed"),
                    }
                }
                tracing::debug!(
                    centre_seam,
                    pieces = next.pieces.piece_count,
                    hausdorff = next.distance.hausdorff,
                    converged = next.developed.converged,
                    "develop: an attempt with more pieces"
                );
                if next.whole_pieces.piece_count > whole_limit {
                    break;
                }
                let grew = tried_pieces > best.pieces.piece_count;
                if better_attempt(&next, &best) {
                    best = next;
                }
                if !grew {
                    break;
                }
            }
        }
        // With a mirror plane and no distance bound, the half's budget is raised while
        // the whole keeps within the piece budget and the half used all it was given
        // (its pieces are still farther than the normal tolerance from cones).
        if mirror.is_some() && bound.is_none() && options.seams == SeamSource::Automatic {
            let mut given = first.max_pieces;
            for _ in 0..MIRROR_BUDGET_ROUNDS {
                let count = best.pieces.piece_count;
                if count < given || best.whole_pieces.piece_count >= whole_limit {
                    break;
                }
                given = count + ((whole_limit - best.whole_pieces.piece_count) / 2).max(1);
                let segmentation = SegmentationOptions {
                    max_pieces: given,
                    ..segmentation_options
                };
                let next = attempt_with(&segmentation, &[], progress_now(), centre_seam, report)?;
                count_attempt();
                tracing::debug!(
                    centre_seam,
                    pieces = next.pieces.piece_count,
                    whole_pieces = next.whole_pieces.piece_count,
                    hausdorff = next.distance.hausdorff,
                    "develop: a mirrored attempt with more pieces"
                );
                if next.whole_pieces.piece_count > whole_limit || next.pieces.piece_count <= count {
                    break;
                }
                // A developed attempt beats one left out of tolerance; among developed
                // ones the closer is kept.
                let better = (next.developed.converged && !best.developed.converged)
                    || (next.developed.converged == best.developed.converged
                        && next.distance.hausdorff <= best.distance.hausdorff);
                if better {
                    best = next;
                } else if best.developed.converged {
                    break;
                }
            }
        }
        Ok(best)
    };
    // With a mirror plane, pieces across the plane must be flat on it, a
    // strong condition on organic shapes (measured, benchmarks-history.md: Spot needed 79 late
    // slits, printed in 63 pieces, and the koala stayed out of tolerance); the whole cut
    // along the plane is tried too, and the better kept: developed, then within the
    // distance bound, then fewer late slits
    // (each may open a wedge the unfolding cuts again: measured, the cup under a 1 % bound
    // printed 60 pieces from 4 with 100 slits across the plane, 16 with a centre seam),
    // then closer. The two are searched at once, the centre seam on a thread of its own
    // (its progress not reported).
    let searched = |centre_seam: bool, report: &dyn Fn(&str, f64)| {
        let found = search(centre_seam, report);
        if found.is_err() {
            abandoned.store(true, std::sync::atomic::Ordering::Relaxed);
        }
        found
    };
    let (joined, seamed) = if mirror.is_some() {
        std::thread::scope(|scope| {
            let seamed = scope.spawn(|| searched(true, &no_progress));
            let joined = searched(false, context.progress);
            let seamed = seamed.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic));
            (joined, Some(seamed))
        })
    } else {
        (search(false, context.progress), None)
    };
    // A failed search's own error, not the other's abandonment.
    let (mut best, seamed) = match (joined, seamed) {
        (Ok(joined), Some(Ok(seamed))) => (joined, Some(seamed)),
        (Ok(joined), None) => (joined, None),
        (Err(PipelineError::Cancelled), Some(Err(error))) | (Err(error), _) | (Ok(_), Some(Err(error))) => {
            return Err(error)
        }
    };
    let mut centre_seam = false;
    if let Some(seamed) = seamed {
        let rank = |a: &Attempt| {
            (
                !a.developed.converged,
                bound.is_some_and(|b| a.distance.hausdorff > b),
                a.late_slit_count,
                a.distance.hausdorff,
            )
        };
        tracing::debug!(
            joined = ?rank(&best),
            seamed = ?rank(&seamed),
            "develop: the mirror plane, pieces across it or a seam along it"
        );
        if rank(&seamed) < rank(&best) {
            best = seamed;
            centre_seam = true;
        }
    }
    let mut attempts = attempts.into_inner();
    context.progress("unfolding the pieces", 0.6);
    let developing_ms = started.elapsed().as_secs_f64() * 1e3;
    // The developed pieces unfold exactly: charts cut along the seams only (no crease
    // splits them), each edge within 1e-9 of its length.
    // The pieces are glued along their seams: they get the tabs a net gets (one side of
    // every seam) unless the pattern options ask for others, none, a seam allowance or a
    // sheet thickness.
    let pattern = options.flatten.pattern.glued_with(options.flatten.net_tabs);
    let flatten_options = FlattenOptions {
        pattern,
        charts: ChartMode::Smooth,
        chart_options: ChartOptions {
            crease_angle_degrees: 180.0,
            // The bound on an exact piece's edges: a chart holding a vertex the
            // solve left free (a seam vertex the cut does not open) is split rather than
            // printed with up to 1e-6 of stretch and reported ok (measured: 9e-7 on a
            // bump with fixed wings while trying seam smoothing, session 25).
            max_edge_distortion: 1e-9,
            ..Default::default()
        },
        ..options.flatten.clone()
    };
    // With a sheet (`--sheet`) and automatic seams, a piece too large for it asks for
    // more pieces (half as many again each time, up to the budget), as a maker cuts a
    // large panel in two.
    let unpacked = |result: &TriangleMesh| {
        let mut options = flatten_options.clone();
        options.pattern.sheet = None;
        run_flatten(result.clone(), &options, context)
    };
    let (fits_sheet, mut run) = loop {
        match run_flatten(best.result.clone(), &flatten_options, context) {
            Err(PipelineError::Pattern(PatternError::PieceTooLarge { .. }))
                if options.seams == SeamSource::Automatic
                    && best.pieces.piece_count < half_limit
                    && best.whole_pieces.piece_count < whole_limit =>
            {
                let count = best.pieces.piece_count;
                let segmentation = SegmentationOptions {
                    max_pieces: (count + count.div_ceil(2)).min(half_limit),
                    normal_tolerance_degrees: 0.0,
                    ..segmentation_options
                };
                let next = attempt_with(&segmentation, &[], 0.5, centre_seam, context.progress)?;
                attempts += 1;
                tracing::debug!(
                    pieces = next.pieces.piece_count,
                    "develop: more pieces to fit the sheet"
                );
                if next.pieces.piece_count <= count || next.whole_pieces.piece_count > whole_limit {
                    break (false, unpacked(&best.result)?);
                }
                best = next;
            }
            // No budget left: the pattern without the sheets, out of tolerance.
            Err(PipelineError::Pattern(PatternError::PieceTooLarge { .. })) => break (false, unpacked(&best.result)?),
            other => break (true, other?),
        }
    };
    let Attempt {
        result,
        half_vertex,
        segmentation,
        pieces: _,
        result_table,
        whole_pieces: pieces,
        developed,
        distance,
        late_slit_count,
        smoothed_count,
    } = best;
    // Each printed vertex's vertex of the target as read: through its half vertex and
    // the cut (mirror), then the remeshing.
    if let (Some(m), Some(half_vertex)) = (&mirror, &half_vertex) {
        for v in &mut run.source_vertices {
            // A mirror image copies no vertex of the target: -1 (u32::MAX).
            let image = *v as usize >= m.half.mesh.positions.len();
            *v = half_vertex
                .get(*v as usize)
                .filter(|_| !image)
                .and_then(|&h| m.half.source_vertex.get(h as usize))
                .copied()
                .unwrap_or(u32::MAX);
        }
    }
    if let Some(origin) = &target_vertex_of_work {
        for v in &mut run.source_vertices {
            *v = origin.get(*v as usize).copied().unwrap_or(u32::MAX);
        }
    }
    // The defects of what was built (with a mirror, the whole).
    let sums = vertex_angle_sums(&result.positions, &result.triangles);
    let built_defect = (0..result.positions.len())
        .filter(|&v| pieces.interior[v])
        .map(|v| (std::f64::consts::TAU - sums[v]).abs())
        .fold(0.0, f64::max);
    let max_defect = developed.max_defect.max(built_defect);
    // The distance colour map: each developed vertex's distance to the target, blue at
    // none, red at the largest (PLY with the value in mm per vertex, and GLB).
    let distances = vertex_distances(&result, &SurfaceIndex::new(reference));
    let top = distances.iter().copied().filter(|d| d.is_finite()).fold(0.0, f64::max);
    let colours: Vec<[f32; 3]> = distances
        .iter()
        .map(|d| colour_ramp(if top > 0.0 { d / top } else { 0.0 }))
        .collect();
    let name = mesh_name(options.flatten.name.as_deref(), options.flatten.input.as_deref());
    if context.renders_all() {
        let millimetres: Vec<f64> = distances.iter().map(|d| d * unit).collect();
        run.files.push((
            "distance.ply".to_string(),
            ply_vertex_colours(&result, &colours, &millimetres, "distance_mm").into_bytes(),
        ));
    }
    run.files.push((
        "distance.glb".to_string(),
        glb_vertex_colours(&result, &colours, unit / 1000.0, &name, UpAxis::Y),
    ));
    run.report.outputs = output_names(&run.files);
    let report = &mut run.report;
    report.command = Command::Develop;
    // The cuts a maker glues, read from the printed pattern: a cut edge is two border
    // edges of the pattern and none of the model's own border.
    let border = |positions: &[nalgebra::Vector3<f64>], table: &EdgeTable| {
        table
            .boundary_edges()
            .fold((0usize, 0.0f64), |(count, length), [a, b]| {
                (
                    count + 1,
                    length + (positions[a as usize] - positions[b as usize]).norm(),
                )
            })
    };
    let (pattern_border_count, pattern_border_length) = border(
        &run.sheet.positions,
        &EdgeTable::new(&run.sheet.triangles, run.sheet.positions.len()),
    );
    let (model_border_count, model_border_length) = border(&result.positions, &result_table);
    let seam_edge_count = pattern_border_count.saturating_sub(model_border_count) / 2;
    // (The model's border edges are the pattern's too, so the difference is the cut
    // edges' twice; with no cut edge, rounding leaves no length.)
    let seam_length = if seam_edge_count == 0 {
        0.0
    } else {
        ((pattern_border_length - model_border_length) / 2.0).max(0.0)
    };
    // The solve's time is develop's as much as the unfolding's.
    report.timings.solve_ms += developing_ms;
    report.timings.total_ms = started.elapsed().as_secs_f64() * 1e3;
    report.timings.export_ms = (report.timings.total_ms - report.timings.parse_ms - report.timings.solve_ms).max(0.0);
    let pattern_piece_count = run.sheet.pieces.len();
    report.develop = Some(DevelopReport {
        seams: options.seams,
        piece_count: pattern_piece_count,
        seam_piece_count: pieces.piece_count,
        overlap_split_count: pattern_piece_count.saturating_sub(pieces.piece_count),
        seam_edge_count,
        seam_length_mm: seam_length * unit,
        seam_length_relative: seam_length / diagonal,
        normal_deviation_rms_deg: segmentation.as_ref().map(|s| s.normal_deviation_rms.to_degrees()),
        slit_count: segmentation.as_ref().map_or(0, |s| s.slit_count) + late_slit_count,
        seam_smoothed_vertex_count: smoothed_count,
        constrained_vertex_count: pieces.interior.iter().filter(|&&i| i).count(),
        angle_defect_max_before_rad: developed.max_defect_before,
        angle_defect_max_rad: max_defect,
        angle_defect_tolerance_rad: options.develop.defect_tolerance,
        iterations: developed.iterations,
        hausdorff_mm: distance.hausdorff * unit,
        hausdorff_relative: distance.hausdorff / diagonal,
        distance_mean_mm: distance.mean * unit,
        distance_mean_relative: distance.mean / diagonal,
        bounding_box_diagonal_mm: diagonal * unit,
        displacement_max_mm: developed.displacement_max * unit,
        max_distance_mm: bound.map(|b| b * unit),
        attempt_count: attempts,
        fixed_vertex_count: fixed.iter().filter(|&&f| f).count(),
        target_face_count: full.triangles.len(),
        work_face_count: result.triangles.len(),
        pieces_fit_sheet: options.flatten.pattern.sheet.map(|_| fits_sheet),
        mirror_plane: mirror.as_ref().map(|m| m.plane.describe()),
        mirror_seam: mirror.as_ref().map(|_| centre_seam),
        mirror_asymmetry_relative: mirror.as_ref().map(|m| m.asymmetry / diagonal),
    });
    if let Some(m) = mirror
        .as_ref()
        .filter(|m| m.asymmetry > MIRROR_ASYMMETRY_WARNING * diagonal)
    {
        report.warnings.push(format!(
            "the target is {:.1} % of its size from symmetric in the plane {}: the result repeats one half of it; place the plane where the target is symmetric (--mirror x=VALUE) or choose another axis",
            100.0 * m.asymmetry / diagonal,
            m.plane.describe()
        ));
    }
    // The budget counts the pieces the seams cut; the unfolding cuts again a developed
    // piece that would overlap itself flat, which can print more.
    if options.seams == SeamSource::Automatic && pattern_piece_count > whole_limit {
        report.warnings.push(format!(
            "the pattern has {pattern_piece_count} pieces, more than the {whole_limit} of --max-pieces, which counts the pieces the seams cut ({}): the unfolding cut {} more where a developed piece would overlap itself flat",
            pieces.piece_count,
            pattern_piece_count - pieces.piece_count
        ));
    }
    let too_far = bound.is_some_and(|b| distance.hausdorff > b);
    let converged = max_defect <= options.develop.defect_tolerance;
    if (!converged || too_far || !fits_sheet) && run.outcome == Outcome::Ok {
        run.outcome = Outcome::OutOfTolerance;
        report.status = Status::OutOfTolerance;
    }
    Ok(DevelopRun { run, developed })
}

/// The half of the working target that `develop --mirror` develops.
struct MirrorWork {
    plane: MirrorPlane,
    half: sheetform_mesh::MirrorHalf,
    table: EdgeTable,
    /// The half's edges along the plane (its cut).
    plane_edges: Vec<[u32; 2]>,
    /// The half's fixed vertices (a new vertex on the plane is fixed when both ends of
    /// the edge it cuts are; empty: none).
    fixed: Vec<bool>,
    /// Two-sided Hausdorff distance between the target as read and its mirror image (0
    /// for a half model).
    asymmetry: f64,
    /// A half model joined with its image: what distances are measured to (`None`: the
    /// target as read).
    reference: Option<TriangleMesh>,
}

impl MirrorWork {
    /// Cuts `work` (the working target, `fixed` its flags) in `spec`'s plane (through
    /// the middle of `low`–`high`, the bounding box of `full`, the target as read, when
    /// not placed).
    fn new(
        work: &TriangleMesh,
        fixed: &[bool],
        full: &TriangleMesh,
        spec: Mirror,
        low: nalgebra::Vector3<f64>,
        high: nalgebra::Vector3<f64>,
    ) -> Result<Self, PipelineError> {
        if spec.axis > 2 {
            return Err(PipelineError::Option {
                option: "mirror",
                message: format!("the plane's axis must be 0 (x), 1 (y) or 2 (z), got {}", spec.axis),
            });
        }
        let axis = spec.axis;
        let plane = MirrorPlane {
            axis,
            offset: spec.offset.unwrap_or(0.5 * (low[axis] + high[axis])),
        };
        // Fixed vertices are not snapped onto the plane.
        let half = mirror_half(work, &plane, fixed).map_err(|e| DevelopError::Topology { problem: e.to_string() })?;
        let (topology, table) = mesh_topology_with_edges(&half.mesh);
        let plane_edges = table
            .boundary_edges()
            .filter(|&[a, b]| half.on_plane[a as usize] && half.on_plane[b as usize])
            .collect();
        let problems = topology.problems();
        if !problems.is_empty() {
            return Err(DevelopError::Topology {
                problem: format!(
                    "its half on one side of the mirror plane {} is not a clean manifold ({}): place the plane where the mesh crosses it cleanly",
                    plane.describe(),
                    problems.join("; ")
                ),
            }
            .into());
        }
        let half_fixed = if fixed.is_empty() {
            Vec::new()
        } else {
            half.source_vertex
                .iter()
                .zip(&half.crossed_edge)
                .map(|(&v, &[a, b])| {
                    if v != u32::MAX {
                        fixed[v as usize]
                    } else {
                        fixed[a as usize] && fixed[b as usize]
                    }
                })
                .collect()
        };
        // A fixed vertex on the side replaced by the image must be the image of a fixed
        // vertex kept (a region fixed symmetrically), or it could not stay in place.
        if !fixed.is_empty() {
            let mut kept = vec![false; work.positions.len()];
            for &v in half.source_vertex.iter().filter(|&&v| v != u32::MAX) {
                kept[v as usize] = true;
            }
            let anchors: Vec<nalgebra::Vector3<f64>> = (0..work.positions.len())
                .filter(|&v| fixed[v] && kept[v])
                .map(|v| work.positions[v])
                .collect();
            let tolerance = 1e-6 * (high - low).norm();
            for v in (0..work.positions.len()).filter(|&v| fixed[v] && !kept[v]) {
                let image = plane.reflect(&work.positions[v]);
                if !anchors.iter().any(|a| (a - image).norm() <= tolerance) {
                    let p = work.positions[v];
                    return Err(PipelineError::Option {
                        option: "fixed",
                        message: format!(
                            "a fixed vertex at ({}, {}, {}) is on the side of the mirror plane {} that the mirror image of the other replaces, and no fixed vertex mirrors it: fix a region symmetric in the plane, or one on the side kept",
                            sheetform_geometry::short_number(p.x),
                            sheetform_geometry::short_number(p.y),
                            sheetform_geometry::short_number(p.z),
                            plane.describe()
                        ),
                    });
                }
            }
        }
        // A half model (nothing on the other side) is completed by its image: distances
        // are to both, and it is symmetric by construction.
        let half_model = half.side_areas[1] <= 1e-9 * half.side_areas[0];
        let (reference, asymmetry) = if half_model {
            let apart = vec![false; full.positions.len()];
            (Some(mirror_whole(full, &apart, &plane).mesh), 0.0)
        } else {
            let mut image = full.clone();
            for p in &mut image.positions {
                *p = plane.reflect(p);
            }
            (
                None,
                surface_distance(&image, full, &SurfaceDistanceOptions::default()).hausdorff,
            )
        };
        tracing::info!(
            plane = %plane.describe(),
            half_faces = half.mesh.triangles.len(),
            snapped = half.snapped_vertex_count,
            asymmetry,
            "develop: the target cut in half by its mirror plane"
        );
        Ok(Self {
            plane,
            half,
            table,
            plane_edges,
            fixed: half_fixed,
            asymmetry,
            reference,
        })
    }
}

/// One flag per vertex of `mesh`: on a face of one of `groups`, or listed in `vertices`
/// (none: an empty vector).
///
/// # Errors
/// A group the mesh does not have (the ones it has named), a vertex out of range.
fn fixed_vertices(mesh: &TriangleMesh, groups: &[String], vertices: &[u32]) -> Result<Vec<bool>, PipelineError> {
    if groups.is_empty() && vertices.is_empty() {
        return Ok(Vec::new());
    }
    let mut fixed = vec![false; mesh.positions.len()];
    for name in groups {
        let Some(group) = mesh.groups.iter().position(|g| g == name) else {
            let known: Vec<String> = mesh.groups.iter().map(|g| format!("`{g}`")).collect();
            return Err(PipelineError::Option {
                option: "fixed",
                message: format!(
                    "the mesh has no group `{}` (its groups: {})",
                    sheetform_geometry::shortened_message(name),
                    known.join(", ")
                ),
            });
        };
        for (t, &g) in mesh.triangles.iter().zip(&mesh.face_groups) {
            if g as usize == group {
                for &v in t {
                    fixed[v as usize] = true;
                }
            }
        }
    }
    for &v in vertices {
        let Some(flag) = fixed.get_mut(v as usize) else {
            return Err(PipelineError::Option {
                option: "fixed",
                message: format!("vertex {v} is out of range (the mesh has {})", mesh.positions.len()),
            });
        };
        *flag = true;
    }
    Ok(fixed)
}

/// Whether attempt `a` is better than `b` in the distance search: developed (every
/// defect within the tolerance) before not, then the closer to the target.
fn better_attempt(a: &Attempt, b: &Attempt) -> bool {
    (a.developed.converged && !b.developed.converged)
        || (a.developed.converged == b.developed.converged && a.distance.hausdorff < b.distance.hausdorff)
}

/// Per-face weights for a segmentation that draws its pieces to where an attempt was
/// far from the target: `w_f = 1 + (d_f / D)²`, `d_f` the largest distance of face `f`'s
/// vertices (at `positions`, the developed work mesh) to `reference` and `D` the distance
/// bound (model units). A face at the bound weighs twice, one at twice the bound five
/// times: [`segment_developable`] multiplies each face's area by its weight, so its cone
/// fits, the piece it splits next and the pieces it keeps from merging follow where the
/// distance is (error-driven refinement, as adaptive meshing places elements where the
/// error estimate is large). The distance is one-sided (the developed vertices' to the
/// target), where the Hausdorff distance the bound is checked on is two-sided.
/// Measured (docs/benchmarks-history.md, session 34): the coffee cup under
/// `--max-distance 0.5% --max-pieces 25` comes out at 0.12 % in 13 pieces, where the
/// pieces placed by their cone fits alone stayed out of tolerance at 1.13 % in 18
/// printed pieces; the exponent 4 instead of 2 left the cup out of tolerance at a
/// budget of 40 (1.44 %).
fn distance_emphasis(
    work: &TriangleMesh,
    positions: &[nalgebra::Vector3<f64>],
    reference: &TriangleMesh,
    bound: f64,
) -> Vec<f64> {
    let mut developed = work.clone();
    developed.positions = positions.to_vec();
    let distances = vertex_distances(&developed, &SurfaceIndex::new(reference));
    work.triangles
        .iter()
        .map(|t| {
            let d = t.iter().map(|&v| distances[v as usize]).fold(0.0, f64::max);
            // At most 1e3 (a weight of 1e6): finite sums of weighted areas.
            let ratio = if d.is_finite() {
                (d / bound.max(f64::MIN_POSITIVE)).min(1e3)
            } else {
                0.0
            };
            1.0 + ratio * ratio
        })
        .collect()
}

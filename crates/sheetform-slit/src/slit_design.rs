//! Scene → validated model → solved design, and the edits of §3.2: anchors added and
//! removed (only the affected strip is solved again, from its current state) and
//! subdivision (Fig. 13).

use crate::point_cloud::ScanCloud;
use crate::sheet_layout::MAX_LENGTH;
use crate::strip_folding::{fold_strip, FoldedStrip, RidgeEnd, StripStart, StripState};
use crate::strip_penalty::{StripTerms, VertexAnchor};
use crate::strip_solver::{solve_gap_constrained, solve_strip_until, JointProblem, StripSolveInfo, StripSolveOptions};
use crate::{
    AnchorSpec, MouldSpec, SeatCurve, SheetLayout, SidePanel, SlitError, SlitScene, SolveMode, SolverSpec, StripSide,
    WeightsSpec,
};
use nalgebra::{DVector, Vector2, Vector3};
use rayon::prelude::*;
use sheetform_geometry::{numbers_apart, refused_number, short_number, Bezier2};
use sheetform_mesh::LengthUnit;
use std::sync::atomic::AtomicBool;

type Vec3 = Vector3<f64>;

/// Segments of the seat-curve polyline.
const SEAT_SEGMENTS: usize = 256;

/// Most quads solved together: one strip's (`quads_per_strip × 2^subdivisions`), or all
/// strips' in joint mode. The solve's time grows with the cube of its unknowns: 256
/// quads take about 3 s on one core, 512 took 26 s.
pub const MAX_QUADS_SOLVED_TOGETHER: usize = 256;
/// Most quads of the whole sheet (`strip_count × quads_per_strip × 2^subdivisions`):
/// eight strips at the largest size, about 25 s.
pub const MAX_QUADS: usize = 2048;
/// Most strips (`sheet.strip_count`).
pub const MAX_STRIPS: usize = 256;
/// Most Levenberg–Marquardt iterations per strip (`solver.max_iterations`).
pub const MAX_ITERATIONS: usize = 10_000;

/// A validated slit-sheet model: the flat sheet, the two design curves, the anchors, the
/// weights and the solver settings.
#[derive(Debug, Clone)]
pub struct SlitModel {
    /// Name from the scene.
    pub name: Option<String>,
    /// Length unit.
    pub unit: LengthUnit,
    /// The flat sheet.
    pub layout: SheetLayout,
    /// The side panel (leg).
    pub panel: SidePanel,
    /// The seat curve on the symmetry plane.
    pub seat: Option<SeatCurve>,
    /// Position anchors (ridge indices before subdivision).
    pub anchors: Vec<AnchorSpec>,
    /// Penalty weights.
    pub weights: WeightsSpec,
    /// Solver settings.
    pub solver: SolverSpec,
    /// Scanned points to fit.
    pub scan: Option<std::sync::Arc<ScanCloud>>,
    /// Mould settings.
    pub mould: MouldSpec,
}

fn planar_bezier(field: &str, points: &[[f64; 2]]) -> Result<Bezier2, SlitError> {
    if points.len() < 2 {
        return Err(SlitError::field(
            format!("{field}.control_points"),
            format!("needs at least two points, got {}", points.len()),
        ));
    }
    if let Some(i) = points.iter().position(|p| p.iter().any(|c| !c.is_finite())) {
        return Err(SlitError::field(
            format!("{field}.control_points[{i}]"),
            "not a finite number",
        ));
    }
    if let Some(i) = points.iter().position(|p| p.iter().any(|c| c.abs() > MAX_LENGTH)) {
        return Err(SlitError::field(
            format!("{field}.control_points[{i}]"),
            format!("coordinates up to {} model units", short_number(MAX_LENGTH)),
        ));
    }
    Bezier2::new(points.iter().map(|p| Vector2::new(p[0], p[1])).collect())
        .map_err(|e| SlitError::field(format!("{field}.control_points"), e.to_string()))
}

impl SlitModel {
    /// Validates a scene. `scan` holds the bytes of the scan file the scene names
    /// (`scan.points`; the caller reads it), `None` without a scan.
    ///
    /// # Errors
    /// [`SlitError::Field`] naming the first invalid field: lengths ≤ 0, no strips, slits
    /// wider than the sheet, a leg curve shorter than the panel or whose strips cannot
    /// reach the symmetry plane, a seat curve that does not span the strips or that they
    /// cannot reach, anchors on strips or ridge lines that do not exist, bad weights.
    /// [`SlitError::PointCloud`] for an unreadable scan, [`SlitError::Field`] on
    /// `scan.points` when the scene names a scan and no bytes are given.
    pub fn from_scene(scene: &SlitScene, scan: Option<&[u8]>) -> Result<Self, SlitError> {
        if scene.sheet.strip_count > MAX_STRIPS {
            return Err(SlitError::field(
                "sheet.strip_count",
                format!("at most {MAX_STRIPS}, got {}", scene.sheet.strip_count),
            ));
        }
        let layout = SheetLayout::new(&scene.sheet)?;
        let solver = scene.solver;
        if !(solver.gap_tolerance.is_finite() && solver.gap_tolerance > 0.0) {
            return Err(SlitError::field("solver.gap_tolerance", "must be a positive number"));
        }
        if !(1..=MAX_ITERATIONS).contains(&solver.max_iterations) {
            return Err(SlitError::field(
                "solver.max_iterations",
                format!("must be 1 to {MAX_ITERATIONS}, got {}", solver.max_iterations),
            ));
        }
        if solver.subdivisions > 6 {
            return Err(SlitError::field(
                "solver.subdivisions",
                format!("at most 6 (each doubles the quads), got {}", solver.subdivisions),
            ));
        }
        // The solve's cost grows with the cube of the unknowns it solves together (a
        // strip's; all strips' in joint mode): one strip of 256 quads takes about 3 s,
        // 512 quads 26 s; 20 strips of 10 quads in joint mode 3.6 s, 30 strips 13.5 s.
        let quads = layout.quads_per_strip << solver.subdivisions;
        let (together, limit, what) = match solver.mode {
            SolveMode::Joint => (
                quads.saturating_mul(layout.strip_count),
                MAX_QUADS_SOLVED_TOGETHER,
                "strip_count × quads_per_strip × 2^subdivisions (joint mode solves all strips together)",
            ),
            SolveMode::Independent => (quads, MAX_QUADS_SOLVED_TOGETHER, "quads_per_strip × 2^subdivisions"),
        };
        if together > limit {
            return Err(SlitError::field(
                if solver.subdivisions > 0 {
                    "solver.subdivisions"
                } else {
                    "sheet.quads_per_strip"
                },
                format!("{what} is {together}, more than {limit} (the solve's time grows with its cube)"),
            ));
        }
        if quads.saturating_mul(layout.strip_count) > MAX_QUADS {
            return Err(SlitError::field(
                "sheet.strip_count",
                format!(
                    "strip_count × quads_per_strip × 2^subdivisions is {}, more than {MAX_QUADS}",
                    quads.saturating_mul(layout.strip_count)
                ),
            ));
        }
        if !(1..=1000).contains(&solver.leg_segments) {
            return Err(SlitError::field("solver.leg_segments", "must be between 1 and 1000"));
        }
        let w = scene.weights;
        for (name, value) in [
            ("weights.no_gap", w.no_gap),
            ("weights.smooth", w.smooth),
            ("weights.fair", w.fair),
            ("weights.user_control", w.user_control),
            ("weights.scan", w.scan),
            ("weights.neighbour", w.neighbour),
        ] {
            // (Bounded: a weight whose square overflows made the strip solve loop on a
            // matrix of infinities.)
            if !(value.is_finite() && (0.0..=crate::MAX_WEIGHT).contains(&value)) {
                return Err(SlitError::field(
                    name,
                    format!(
                        "must be a number from 0 to {}, got {}",
                        short_number(crate::MAX_WEIGHT),
                        refused_number(value, &[0.0, crate::MAX_WEIGHT])
                    ),
                ));
            }
        }
        if w.no_gap <= 0.0 {
            return Err(SlitError::field(
                "weights.no_gap",
                "must be positive (it closes the strips)",
            ));
        }
        if w.fair <= 0.0 {
            return Err(SlitError::field(
                "weights.fair",
                "must be positive (it keeps quads from collapsing)",
            ));
        }
        let panel = match &scene.leg_curve {
            Some(spec) => SidePanel::new(
                &planar_bezier("leg_curve", &spec.control_points)?,
                layout.panel_length,
                solver.leg_segments,
            )?,
            None => SidePanel::vertical(layout.strip_length, layout.panel_length, solver.leg_segments),
        };
        let top = panel.top();
        if top.x > layout.strip_length * (1.0 + 1e-12) {
            return Err(SlitError::field(
                "leg_curve",
                format!(
                    "unreachable: the strips start at x = {} from the symmetry plane but are only \
                     l3_strip_length = {} long, so they cannot reach it",
                    numbers_apart(top.x, layout.strip_length)[0],
                    numbers_apart(top.x, layout.strip_length)[1]
                ),
            ));
        }
        let seat = match &scene.seat_curve {
            Some(spec) => {
                let curve = SeatCurve::from_bezier(&planar_bezier("seat_curve", &spec.control_points)?, SEAT_SEGMENTS);
                let (lo, hi) = curve.z_range();
                let slack = 1e-9 * layout.width;
                if lo > slack || hi < layout.width - slack {
                    return Err(SlitError::field(
                        "seat_curve",
                        format!(
                            "misses strips: it spans z = {} .. {} on the symmetry plane but the strips' ends \
                             span z = 0 .. {} (l1_width); give it control points from z = 0 to z = {}",
                            refused_number(lo, &[0.0]),
                            numbers_apart(hi, layout.width)[0],
                            short_number(layout.width),
                            short_number(layout.width)
                        ),
                    ));
                }
                for k in 0..layout.strip_count {
                    for z in [
                        layout.strip_left_edge(k),
                        layout.strip_left_edge(k) + layout.strip_width,
                    ] {
                        let Some(y) = curve.height_at(z) else { continue };
                        let reach = Vector2::new(top.x, y - top.y).norm();
                        if reach > layout.strip_length * (1.0 + 1e-9) {
                            return Err(SlitError::field(
                                "seat_curve",
                                format!(
                                    "unreachable: at z = {} it is at height {}, {} away from where strip \
                                     {k} starts ({}, {}), but the strip is only l3_strip_length = {} long",
                                    short_number(z),
                                    short_number(y),
                                    numbers_apart(reach, layout.strip_length)[0],
                                    short_number(top.x),
                                    short_number(top.y),
                                    numbers_apart(reach, layout.strip_length)[1]
                                ),
                            ));
                        }
                    }
                }
                Some(curve)
            }
            None => None,
        };
        // Within the sheet's scale, as its lengths (a base of 1e308 or 1e-320 reached the
        // mould's triangulation, which cannot take such coordinates).
        let base = scene.mould.base_thickness;
        let largest = layout.width.max(layout.panel_length).max(layout.strip_length);
        if !(base.is_finite() && base >= 1e-6 * largest && base <= MAX_LENGTH) {
            return Err(SlitError::field(
                "mould.base_thickness",
                format!(
                    "must be a positive length from a millionth of the sheet's largest length ({}) to {}, got {}",
                    short_number(1e-6 * largest),
                    short_number(MAX_LENGTH),
                    refused_number(base, &[1e-6 * largest, MAX_LENGTH])
                ),
            ));
        }
        // 0 (a sheet of no thickness), or within the sheet's scale as the base: a
        // thickness of 1e-320 reached the mould's triangulation, which refused its
        // coordinates without naming the field.
        let thickest = 0.5 * layout.strip_width;
        let thinnest = 1e-6 * largest;
        let sheet = scene.mould.sheet_thickness;
        if !(sheet.is_finite() && (sheet == 0.0 || (thinnest..=thickest).contains(&sheet))) {
            let [shown, bound] = if sheet > thickest {
                numbers_apart(sheet, thickest)
            } else {
                numbers_apart(sheet, thinnest)
            };
            let (thinnest, thickest) = if sheet > thickest {
                (short_number(thinnest).to_string(), bound)
            } else {
                (bound, short_number(thickest).to_string())
            };
            return Err(SlitError::field(
                "mould.sheet_thickness",
                format!(
                    "must be 0 (a sheet of no thickness) or from a millionth of the sheet's largest length ({thinnest}) \
                     to half the strip width ({thickest}), got {shown}"
                ),
            ));
        }
        let mut model = Self {
            name: scene.name.clone(),
            unit: scene.units,
            layout,
            panel,
            seat,
            anchors: Vec::new(),
            weights: w,
            solver,
            scan: match &scene.scan {
                Some(spec) => {
                    let bytes = scan.ok_or_else(|| SlitError::field("scan.points", "the scan file was not read"))?;
                    Some(std::sync::Arc::new(ScanCloud::from_bytes(bytes, &spec.points)?))
                }
                None => None,
            },
            mould: scene.mould,
        };
        for (i, a) in scene.anchors.iter().enumerate() {
            model.add_anchor(*a).map_err(|e| match e {
                SlitError::Field { field, message } => SlitError::field(format!("anchors[{i}]{field}"), message),
                other => other,
            })?;
        }
        Ok(model)
    }

    /// Adds a position anchor (Fig. 12).
    ///
    /// # Errors
    /// A strip or ridge line that does not exist, E0 (fixed), a non-finite position, or
    /// a position the ridge line's end cannot reach; the field is relative (`.strip`).
    pub fn add_anchor(&mut self, anchor: AnchorSpec) -> Result<(), SlitError> {
        let l = &self.layout;
        if anchor.strip >= l.strip_count {
            return Err(SlitError::field(
                ".strip",
                format!(
                    "strip {} does not exist (the sheet has strips 0..{})",
                    anchor.strip,
                    l.strip_count - 1
                ),
            ));
        }
        if anchor.ridge == 0 {
            return Err(SlitError::field(
                ".ridge",
                "ridge line 0 (E0) is fixed by the leg curve; anchors go on ridge lines 1..quads_per_strip",
            ));
        }
        if anchor.ridge > l.quads_per_strip {
            return Err(SlitError::field(
                ".ridge",
                format!(
                    "ridge line {} does not exist (the strips have ridge lines 0..{})",
                    anchor.ridge, l.quads_per_strip
                ),
            ));
        }
        if anchor.position.iter().any(|c| !c.is_finite()) {
            return Err(SlitError::field(".position", "not a finite number"));
        }
        let start = self.strip_start(anchor.strip);
        let p = Vec3::from(anchor.position);
        let base = match anchor.side {
            StripSide::Left => start.origin,
            StripSide::Right => start.origin + start.across * start.width,
        };
        let reach = (l.strip_length * l.strip_length + l.strip_width * l.strip_width).sqrt();
        if (p - base).norm() > reach * (1.0 + 1e-9) {
            return Err(SlitError::field(
                ".position",
                format!(
                    "unreachable: it is {} from where the strip starts but no point of the strip is farther than {}",
                    numbers_apart((p - base).norm(), reach)[0],
                    numbers_apart((p - base).norm(), reach)[1]
                ),
            ));
        }
        self.anchors.push(anchor);
        Ok(())
    }

    /// Removes anchor `index` and returns it.
    pub fn remove_anchor(&mut self, index: usize) -> Option<AnchorSpec> {
        (index < self.anchors.len()).then(|| self.anchors.remove(index))
    }

    /// Where strip `k` starts: E0 on the top of the side panel.
    pub fn strip_start(&self, strip: usize) -> StripStart {
        let top = self.panel.top();
        StripStart {
            origin: Vec3::new(top.x, top.y, self.layout.strip_left_edge(strip)),
            along: self.panel.top_direction(),
            across: Vec3::z(),
            width: self.layout.strip_width,
            length: self.layout.strip_length,
        }
    }

    /// The penalty terms of strip `k` whose quads have been subdivided `level` times.
    pub fn strip_terms(&self, strip: usize, level: usize) -> StripTerms<'_> {
        let factor = 1usize << level;
        StripTerms {
            start: self.strip_start(strip),
            quads: self.layout.quads_per_strip * factor,
            weights: self.weights,
            anchors: self
                .anchors
                .iter()
                .filter(|a| a.strip == strip)
                .map(|a| VertexAnchor {
                    ridge: a.ridge * factor,
                    end: match a.side {
                        StripSide::Left => RidgeEnd::Left,
                        StripSide::Right => RidgeEnd::Right,
                    },
                    position: Vec3::from(a.position),
                })
                .collect(),
            seat: self.seat.as_ref(),
            scan: self.scan.as_deref(),
            length_scale: self.layout.half_length(),
            gap_weight: self.weights.no_gap,
            gap_shift: [0.0; 2],
        }
    }

    /// The strip solver's knobs from the scene's `solver` section.
    pub fn solve_options(&self) -> StripSolveOptions {
        StripSolveOptions {
            gap: self.solver.gap,
            gap_tolerance: self.solver.gap_tolerance,
            max_iterations: self.solver.max_iterations,
        }
    }
}

/// A solved design: every strip's ridge lines and what the solver did.
#[derive(Debug, Clone)]
pub struct SlitDesign {
    /// Ridge-line parameters per strip.
    pub states: Vec<StripState>,
    /// Times the quads have been subdivided.
    pub level: usize,
    /// Solver info per strip (iterations and time summed over the subdivision levels).
    pub strips: Vec<StripSolveInfo>,
    /// `E = G / (L2 + L3)` with `G` the largest gap over all strips (§4).
    pub normalised_error: f64,
    /// `G`, in the model's unit.
    pub gap: f64,
}

impl SlitDesign {
    /// The paper's starting state (Fig. 9) for every strip, not yet solved.
    pub fn initial(model: &SlitModel) -> Self {
        let l = &model.layout;
        let states = vec![StripState::initial(l.quads_per_strip, l.strip_length); l.strip_count];
        let mut design = Self {
            strips: (0..l.strip_count)
                .map(|k| StripSolveInfo {
                    strip: k,
                    quads: l.quads_per_strip,
                    initial_penalty: model.strip_terms(k, 0).penalty(&states[k].to_vector()).total,
                    ..Default::default()
                })
                .collect(),
            states,
            level: 0,
            normalised_error: 0.0,
            gap: 0.0,
        };
        design.measure(model);
        design
    }

    /// Where each ridge line an anchor can hold ends, in the model frame: ridge lines
    /// `1..=quads_per_strip` of every strip (numbered before subdivision, as
    /// [`AnchorSpec::ridge`]; E0 is fixed by the leg curve), both ends, strip by strip.
    /// An editor shows these to be anchored (Fig. 12).
    pub fn anchorable_points(&self, model: &SlitModel) -> Vec<AnchorSpec> {
        let factor = 1usize << self.level;
        self.folded(model)
            .iter()
            .enumerate()
            .flat_map(|(strip, folded)| {
                (1..=model.layout.quads_per_strip).flat_map(move |ridge| {
                    [
                        (StripSide::Left, folded.left[ridge * factor]),
                        (StripSide::Right, folded.right[ridge * factor]),
                    ]
                    .map(|(side, p)| AnchorSpec {
                        strip,
                        ridge,
                        side,
                        position: p.into(),
                    })
                })
            })
            .collect()
    }

    /// Each strip folded.
    pub fn folded(&self, model: &SlitModel) -> Vec<FoldedStrip> {
        self.states
            .iter()
            .enumerate()
            .map(|(k, s)| fold_strip(&model.strip_start(k), s))
            .collect()
    }

    fn measure(&mut self, model: &SlitModel) {
        let scale = model.layout.half_length();
        self.gap = self
            .folded(model)
            .iter()
            .map(|f| {
                let m = f.quads();
                f.left[m].x.abs().max(f.right[m].x.abs())
            })
            .fold(0.0, f64::max);
        self.normalised_error = self.gap / scale;
    }

    /// Solves the given strips again from their current state (after an anchor edit, only
    /// the affected strip), one by one in parallel, or all strips jointly when the model
    /// says so.
    pub fn solve(&mut self, model: &SlitModel, strips: &[usize]) {
        self.solve_until(model, strips, None);
    }

    /// [`SlitDesign::solve`] that stops where it is once `stop` is set (from another
    /// thread: a cancelled run); the design is then not converged.
    pub fn solve_until(&mut self, model: &SlitModel, strips: &[usize], stop: Option<&AtomicBool>) {
        let options = model.solve_options();
        let level = self.level;
        if model.solver.mode == SolveMode::Joint && model.layout.strip_count > 1 {
            let started = std::time::Instant::now();
            let mut problem = JointProblem {
                strips: (0..model.layout.strip_count)
                    .map(|k| model.strip_terms(k, level))
                    .collect(),
                neighbour_weight: model.weights.neighbour,
                stop,
            };
            let x0: Vec<f64> = self.states.iter().flat_map(StripState::to_vector).collect();
            let (x, info, _) = solve_gap_constrained(&mut problem, DVector::from_vec(x0), &options);
            let mut at = 0;
            let time_ms = started.elapsed().as_secs_f64() * 1e3;
            for (k, state) in self.states.iter_mut().enumerate() {
                let n = state.variable_count();
                state.set_vector(&x.as_slice()[at..at + n]);
                let terms = &problem.strips[k];
                let gaps = terms.gaps(&x.as_slice()[at..at + n]);
                let e = gaps[0].abs().max(gaps[1].abs());
                self.strips[k] = accumulate(
                    self.strips[k],
                    StripSolveInfo {
                        strip: k,
                        quads: state.quads(),
                        iterations: info.iterations,
                        initial_penalty: self.strips[k].initial_penalty,
                        penalty: terms.penalty(&x.as_slice()[at..at + n]),
                        gap: e * terms.length_scale,
                        normalised_error: e,
                        gradient_norm: info.gradient_norm,
                        converged: info.converged,
                        time_ms,
                    },
                );
                at += n;
            }
        } else {
            let results: Vec<(usize, StripState, StripSolveInfo)> = strips
                .par_iter()
                .map(|&k| {
                    let mut state = self.states[k].clone();
                    let info = solve_strip_until(model.strip_terms(k, level), k, &mut state, &options, stop);
                    (k, state, info)
                })
                .collect();
            for (k, state, info) in results {
                self.states[k] = state;
                self.strips[k] = accumulate(self.strips[k], info);
            }
        }
        self.measure(model);
    }

    /// How close the strips are to the scanned points (§4.1, Eq. 6), if the model has a
    /// scan: the distance from every ridge-line end point `v_·,i` (`i ≥ 1`, the points the
    /// fitting term pulls) to its nearest scanned point, in the model's unit.
    pub fn scan_fit(&self, model: &SlitModel) -> Option<ScanFit> {
        let scan = model.scan.as_ref()?;
        let distances: Vec<f64> = self
            .folded(model)
            .iter()
            .flat_map(|f| {
                f.left[1..]
                    .iter()
                    .chain(&f.right[1..])
                    .map(|v| (v - scan.nearest(v)).norm())
                    .collect::<Vec<_>>()
            })
            .collect();
        let count = distances.len().max(1) as f64;
        Some(ScanFit {
            scanned_point_count: scan.len(),
            fitted_point_count: distances.len(),
            distance_mean: distances.iter().sum::<f64>() / count,
            distance_rms: (distances.iter().map(|d| d * d).sum::<f64>() / count).sqrt(),
            distance_max: distances.iter().copied().fold(0.0, f64::max),
        })
    }

    /// Splits every quad in two (new ridge lines with zero angle, Fig. 13); the shape is
    /// unchanged until the next [`SlitDesign::solve`].
    pub fn subdivide(&mut self) {
        for s in &mut self.states {
            *s = s.subdivided();
        }
        self.level += 1;
    }
}

/// How close a design is to its scanned points ([`SlitDesign::scan_fit`]); lengths in the
/// model's unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScanFit {
    /// Points in the scan.
    pub scanned_point_count: usize,
    /// Ridge-line end points measured.
    pub fitted_point_count: usize,
    /// Mean distance to the nearest scanned point.
    pub distance_mean: f64,
    /// Root-mean-square distance.
    pub distance_rms: f64,
    /// Largest distance.
    pub distance_max: f64,
}

/// A strip's info after one more solve: iterations and time add up over solves, the
/// initial penalty stays the one of the paper's initial state.
fn accumulate(previous: StripSolveInfo, latest: StripSolveInfo) -> StripSolveInfo {
    StripSolveInfo {
        iterations: previous.iterations + latest.iterations,
        time_ms: previous.time_ms + latest.time_ms,
        initial_penalty: previous.initial_penalty,
        ..latest
    }
}

/// Solves a model from the paper's initial state, with the subdivisions its solver
/// settings ask for (solve, split, solve again from the current state, …). With a scan,
/// the first solve is from the design curves alone and the fit starts from its result.
pub fn solve_design(model: &SlitModel) -> SlitDesign {
    solve_design_until(model, None).expect("nothing stops a solve without a stop flag")
}

/// [`solve_design`] that stops once `stop` is set (from another thread: Ctrl-C, an
/// abandoned editor request), at its next iteration of any strip's solve.
///
/// # Errors
/// [`SlitError::Cancelled`] when stopped.
pub fn solve_design_until(model: &SlitModel, stop: Option<&AtomicBool>) -> Result<SlitDesign, SlitError> {
    let stopped = || stop.is_some_and(|s| s.load(std::sync::atomic::Ordering::Relaxed));
    let mut design = SlitDesign::initial(model);
    let all: Vec<usize> = (0..model.layout.strip_count).collect();
    if model.scan.is_some() && model.weights.scan > 0.0 {
        // Fitting to a scan is a nearest-point (ICP-like) problem with many local minima:
        // from the flat initial state, ridge-line ends lock onto the wrong parts of the
        // cloud (the chair example: mean 5.8 mm, max 45 mm from the scan). So the strips
        // are first solved from the design curves alone, then fitted from there
        // (mean 3.2 mm, max 4.4 mm; `examples/scan_fitted_chair.rs` of the facade).
        let mut curves_only = model.clone();
        curves_only.scan = None;
        design.solve_until(&curves_only, &all, stop);
    }
    design.solve_until(model, &all, stop);
    for _ in 0..model.solver.subdivisions {
        if stopped() {
            return Err(SlitError::Cancelled);
        }
        design.subdivide();
        design.solve_until(model, &all, stop);
    }
    if stopped() {
        return Err(SlitError::Cancelled);
    }
    Ok(design)
}

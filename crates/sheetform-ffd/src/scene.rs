//! The FFD scene file (`sheetform ffd SCENE.json`).

use crate::nurbs_volume::NO_VOLUME_FIELD;
use crate::procedural_panels::ProceduralModel;
use crate::{FfdError, LatticeEdit, NurbsVolume};
use nalgebra::Vector3;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

type Vec3 = Vector3<f64>;

/// A developability-preserving FFD scene: panels, a lattice, and a list of
/// deformations applied one after the other.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FfdScene {
    /// Name of the design (output file names).
    #[serde(default = "default_name")]
    pub name: String,
    /// Length unit of the model and of every length in the file (`mm`, `cm`, `m` or
    /// `in`; default `mm`).
    #[serde(default)]
    #[schemars(with = "String")]
    pub units: sheetform_mesh::LengthUnit,
    /// The panels.
    pub model: ModelSource,
    /// The FFD lattice around the undeformed model.
    #[serde(default)]
    pub lattice: LatticeSpec,
    /// Deformations, applied in order, each to the lattice the previous one left and to
    /// the parameters its restoration found.
    pub deformations: Vec<Deformation>,
    /// How developability is restored.
    #[serde(default)]
    pub solver: SolverSpec,
    /// Which axis of the model points up: `"z"` (the default, as the procedural garments
    /// are built) or `"y"` (as most mesh files are written). The GLB and OBJ are written
    /// `+Y` up, a `+Z`-up model turned.
    #[serde(default = "z_up")]
    pub up_axis: sheetform_mesh::UpAxis,
}

fn z_up() -> sheetform_mesh::UpAxis {
    sheetform_mesh::UpAxis::Z
}

fn default_name() -> String {
    "ffd".into()
}

/// Where the panels come from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum ModelSource {
    /// A mesh file (OBJ with one group or object per panel, PLY, STL, OFF), relative to
    /// the scene file.
    Mesh(String),
    /// A panel assembly built by sheetform.
    Procedural(ProceduralModel),
}

/// The lattice. Without `control_points` it is a box (`box_min`/`box_max`, default the
/// model's bounding box grown by `margin`) with control points at the Greville abscissae,
/// so the undeformed volume is the identity on the box and the embedding is linear.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LatticeSpec {
    /// Degrees in u, v, w.
    #[serde(default = "default_degrees")]
    pub degrees: [usize; 3],
    /// Control points in u, v, w.
    #[serde(default = "default_counts")]
    pub counts: [usize; 3],
    /// Fraction of the model's size added on every side of the automatic box (at least
    /// [`MIN_LATTICE_MARGIN`]; unused with `box_min`/`box_max` or `control_points`, which
    /// should then enclose the model with room to spare). The restoration moves vertices
    /// in the lattice's parameters, which end at its boundary, so a vertex there could not
    /// move outwards;
    /// with no margin the two panels stall at 6.2e-3 rad).
    #[serde(default = "default_margin")]
    pub margin: f64,
    /// Lower corner of the box (model units).
    #[serde(default)]
    pub box_min: Option<[f64; 3]>,
    /// Upper corner of the box (model units).
    #[serde(default)]
    pub box_max: Option<[f64; 3]>,
    /// Full knot vectors per direction (default: clamped, uniform).
    #[serde(default)]
    pub knots: Option<[Vec<f64>; 3]>,
    /// A general lattice: `n_u n_v n_w` control points, `i` fastest (the embedding is
    /// then found by Newton's method).
    #[serde(default)]
    pub control_points: Option<Vec<[f64; 3]>>,
    /// Weights, one per control point (positive, at most 1e6; default 1).
    #[serde(default)]
    pub weights: Option<Vec<f64>>,
}

fn default_degrees() -> [usize; 3] {
    [3, 3, 3]
}
fn default_counts() -> [usize; 3] {
    [4, 4, 4]
}
/// Smallest `lattice.margin` accepted.
pub const MIN_LATTICE_MARGIN: f64 = 0.01;

/// Most control points per lattice direction (`lattice.counts`): the paper's lattices
/// have 4 to 6; 64³ points is a quarter of a million (1000³ asked for 24 GB and aborted).
pub const MAX_LATTICE_COUNT: usize = 64;

/// Largest `lattice.margin` accepted (ten times the model's size on every side).
pub const MAX_LATTICE_MARGIN: f64 = 10.0;

fn default_margin() -> f64 {
    0.05
}

impl Default for LatticeSpec {
    fn default() -> Self {
        Self {
            degrees: default_degrees(),
            counts: default_counts(),
            margin: default_margin(),
            box_min: None,
            box_max: None,
            knots: None,
            control_points: None,
            weights: None,
        }
    }
}

/// One deformation: lattice edits, then developability restoration.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Deformation {
    /// Name (report).
    #[serde(default)]
    pub name: Option<String>,
    /// The edits, in order.
    pub edits: Vec<LatticeEdit>,
}

/// Which solver restores developability, and its knobs.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SolverSpec {
    /// `constrained` (default: constrained Gauss–Newton, exact gradients, sparse LDLᵀ) or
    /// `paper` (the paper's penalty + conjugate gradients), or `none` (plain FFD).
    #[serde(default)]
    pub method: SolverMethod,
    /// Largest angle defect accepted by the constrained solver (radians).
    #[serde(default = "default_tolerance")]
    pub tolerance_rad: f64,
    /// `λ` of the selective set (radians): vertices whose defect exceeds it are optimised
    /// with their neighbours. The constrained solver uses at most `tolerance_rad`, so that
    /// every defect over its tolerance is in the set.
    #[serde(default = "default_selection")]
    pub selection_threshold_rad: f64,
    /// Weight of the proximity term of the constrained solver (0 to 1e6, default 0.01).
    #[serde(default = "default_position_weight")]
    pub position_weight: f64,
    /// Most iterations (constrained) or penalty updates (paper, `N_max`).
    #[serde(default)]
    pub max_iterations: Option<usize>,
    /// Refinement iterations of the constrained solver once the defects are within
    /// tolerance (they lower the edge-length change and the deviation; 0: restore only).
    #[serde(default = "default_refine")]
    pub refine_iterations: usize,
    /// Weight `γ` of the constrained solver's bending term in its step metric, scaled by
    /// the panels' area over their squared mean edge length so that it means the same
    /// at every resolution (default 3e-3: smooth results in 3–9 full steps; 0: springs
    /// alone, as in the paper, which fold the panels into node-scale zig-zags and need
    /// several times more iterations; see `fold_angle_max_after_rad` in the report; at
    /// most 1e6).
    #[serde(default = "default_bending_weight")]
    pub bending_weight: f64,
    /// Memory of the constrained solver's non-monotone line search: a step is accepted
    /// when the largest defect falls below the largest of the last this many iterates'
    /// (1: a monotone search; default 12: skirt 27 instead of 38 iterations, trousers 25
    /// instead of 32, with the same result quality).
    #[serde(default = "default_line_search_memory")]
    #[schemars(range(min = 1))]
    pub line_search_memory: usize,
    /// Bending weight the constrained solver switches on when the restoration stalls
    /// (five steps in a row cut to 1/64 or less) with `bending_weight` 0; 0: never
    /// (default 3e-3, at most 1e6). Fine meshes restored with the springs alone need it;
    /// the report's steps say when it happened (`bending_fallback_iteration`). A stall
    /// with nothing left to switch on ends the restoration, not converged.
    #[serde(default = "default_stall_bending_weight")]
    pub stall_bending_weight: f64,
    /// Restore along the deformation's path in adaptive sub-steps (continuation, the
    /// constrained solver only; absent: the whole deformation at once). For large
    /// deformations, whose one-shot restoration cuts its steps and crumples the panels.
    #[serde(default)]
    pub continuation: Option<ContinuationSpec>,
    /// The constrained solver's step unknowns: `parameters` (default: each node's three
    /// lattice parameters) or `normal` (one per node, along the surface normal: about a
    /// third of the time on large meshes, larger edge-length changes on small ones; see
    /// docs/benchmarks-history.md).
    #[serde(default)]
    pub step_unknowns: crate::StepUnknowns,
    /// Most chord steps of the constrained solver after each full step: projections that
    /// reuse the step's factorisation, taken while each is at most half as long as the
    /// one before and halves the largest defect (0: none, every step factorised; default
    /// 8; not used with `continuation`). They cost about a tenth of a factorisation:
    /// 100k-vertex duct 5 factorisations instead of 7, skirt 2 instead of 4, with the same
    /// edge-length change.
    #[serde(default = "default_chord_steps")]
    #[schemars(range(max = 100))]
    pub chord_steps: usize,
}

/// Most iterations `solver.max_iterations` and `solver.refine_iterations` may ask for
/// (each is one sparse factorisation: seconds at the largest models).
pub const MAX_SOLVER_ITERATIONS: usize = 10_000;
/// Largest `solver.line_search_memory` (beyond it the stall detection has no effect).
pub const MAX_LINE_SEARCH_MEMORY: usize = 100;
/// Most `solver.chord_steps` after one full step.
pub const MAX_CHORD_STEPS: usize = 100;
/// Smallest `solver.tolerance_rad`: angle sums are exact to about 4e-15 rad, so a
/// smaller tolerance could never be reached.
pub const MIN_TOLERANCE_RAD: f64 = 1e-14;
/// Most deformations in one scene (each is one restoration).
pub const MAX_DEFORMATIONS: usize = 1_000;

/// The largest weight a scene may set, as the slit and photo systems' weights: the
/// solver's (`solver.position_weight`, `solver.bending_weight`,
/// `solver.stall_bending_weight`), the lattice's (`lattice.weights`) and a `weight`
/// edit's `value`. Larger ones overflow when squared or summed in the restoration (a
/// bending weight of 1e300 was reported as a singular system, a lattice weight of 1e300
/// as collapsed panels, a position weight of 1e300 ended `ok` with nothing restored).
pub const MAX_WEIGHT: f64 = 1e6;

/// Which weights [`check_weight`] accepts at the low end.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum WeightSign {
    /// 0 switches the term off.
    ZeroOrPositive,
    /// A NURBS weight: 0 would take the control point out of the volume.
    Positive,
}

/// A weight within `0 ..= MAX_WEIGHT` (above 0 when `sign` is [`WeightSign::Positive`]),
/// or a field error naming `field`, the value and the bounds.
pub(crate) fn check_weight(field: &str, value: f64, sign: WeightSign) -> Result<(), FfdError> {
    let low_ok = match sign {
        WeightSign::ZeroOrPositive => value >= 0.0,
        WeightSign::Positive => value > 0.0,
    };
    if value.is_finite() && low_ok && value <= MAX_WEIGHT {
        return Ok(());
    }
    let range = match sign {
        WeightSign::ZeroOrPositive => "a number from 0 to",
        WeightSign::Positive => "a positive number up to",
    };
    Err(FfdError::field(
        field,
        format!(
            "must be {range} {}, got {}",
            sheetform_geometry::short_number(MAX_WEIGHT),
            sheetform_geometry::refused_number(value, &[0.0, MAX_WEIGHT])
        ),
    ))
}

/// Continuation along the deformation (`solver.continuation`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ContinuationSpec {
    /// Largest curvature a sub-step may create before it is restored: the largest angle
    /// defect of the sub-step's plain FFD times the panels' area over their squared mean
    /// edge length (about the largest Gaussian curvature times the panels' area, the same
    /// at every mesh resolution; default 0.5). Smaller: more, shorter sub-steps.
    #[serde(default = "default_sub_step_curvature")]
    pub sub_step_curvature: f64,
    /// Most sub-steps per deformation (1 to 1024, default 64); the shortest sub-step is
    /// this fraction of the deformation.
    #[serde(default = "default_max_sub_steps")]
    #[schemars(range(min = 1, max = 1024))]
    pub max_sub_steps: usize,
}

impl Default for ContinuationSpec {
    fn default() -> Self {
        let o = crate::ContinuationOptions::default();
        Self {
            sub_step_curvature: o.sub_step_curvature,
            max_sub_steps: o.max_sub_steps,
        }
    }
}

impl ContinuationSpec {
    /// The options of [`crate::restore_along_path`].
    pub fn options(&self) -> crate::ContinuationOptions {
        crate::ContinuationOptions {
            sub_step_curvature: self.sub_step_curvature,
            max_sub_steps: self.max_sub_steps,
        }
    }
}

/// Most sub-steps `solver.continuation.max_sub_steps` may ask for (each a restoration).
pub const MAX_SUB_STEPS: usize = 1024;

fn default_sub_step_curvature() -> f64 {
    crate::ContinuationOptions::default().sub_step_curvature
}
fn default_max_sub_steps() -> usize {
    crate::ContinuationOptions::default().max_sub_steps
}

/// The restoration method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum SolverMethod {
    /// Constrained Gauss–Newton (default).
    #[default]
    Constrained,
    /// The paper's penalty method with conjugate gradients.
    Paper,
    /// No restoration (plain FFD).
    None,
}

impl std::fmt::Display for SolverMethod {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Constrained => "constrained",
            Self::Paper => "paper",
            Self::None => "none",
        })
    }
}

fn default_tolerance() -> f64 {
    1e-10
}
fn default_selection() -> f64 {
    1e-8
}
fn default_refine() -> usize {
    0
}
fn default_position_weight() -> f64 {
    0.01
}
fn default_bending_weight() -> f64 {
    crate::ConstrainedOptions::default().bending_weight
}
fn default_stall_bending_weight() -> f64 {
    crate::ConstrainedOptions::default().stall_bending_weight
}
fn default_chord_steps() -> usize {
    crate::ConstrainedOptions::default().chord_steps
}
fn default_line_search_memory() -> usize {
    crate::ConstrainedOptions::default().line_search_memory
}

impl Default for SolverSpec {
    fn default() -> Self {
        Self {
            method: SolverMethod::default(),
            tolerance_rad: default_tolerance(),
            selection_threshold_rad: default_selection(),
            position_weight: default_position_weight(),
            max_iterations: None,
            refine_iterations: default_refine(),
            bending_weight: default_bending_weight(),
            stall_bending_weight: default_stall_bending_weight(),
            line_search_memory: default_line_search_memory(),
            continuation: None,
            step_unknowns: crate::StepUnknowns::default(),
            chord_steps: default_chord_steps(),
        }
    }
}

impl SolverSpec {
    /// The restoration problem's options: the selective set's `λ`, at most the
    /// tolerance for the constrained solver (every defect over the tolerance is
    /// optimised; with `λ` = 1e-8 against the 1e-10 tolerance, a 5 mm drag on the
    /// restored skirt crawled to 100 iterations at 1.9e-10 rad, with `λ` at the tolerance
    /// it takes 2 iterations, 9 ms).
    pub fn problem_options(&self) -> crate::ProblemOptions {
        crate::ProblemOptions {
            selection_threshold: match self.method {
                SolverMethod::Constrained => self.selection_threshold_rad.min(self.tolerance_rad),
                _ => self.selection_threshold_rad,
            },
        }
    }

    /// The constrained solver's options.
    pub fn constrained_options(&self) -> crate::ConstrainedOptions {
        let mut options = crate::ConstrainedOptions {
            tolerance: self.tolerance_rad,
            position_weight: self.position_weight,
            refine_iterations: self.refine_iterations,
            bending_weight: self.bending_weight,
            line_search_memory: self.line_search_memory,
            stall_bending_weight: self.stall_bending_weight,
            step_unknowns: self.step_unknowns,
            chord_steps: self.chord_steps,
            ..Default::default()
        };
        if let Some(m) = self.max_iterations {
            options.max_iterations = m;
        }
        options
    }
}

impl FfdScene {
    /// The JSON Schema of the scene format (`sheetform schema ffd`).
    pub fn json_schema() -> serde_json::Value {
        serde_json::to_value(schemars::schema_for!(FfdScene)).expect("schema serialises")
    }

    /// Parses a scene.
    ///
    /// # Errors
    /// [`FfdError::Field`] for malformed JSON, unknown, missing or mistyped fields: naming
    /// the field path, what is accepted, then the line and column.
    pub fn from_json(text: &str) -> Result<Self, FfdError> {
        sheetform_geometry::json_from_text(text).map_err(|e| FfdError::field(e.field, e.message))
    }

    /// Checks the numbers that serde cannot.
    ///
    /// # Errors
    /// A field error naming the field.
    pub fn validate(&self) -> Result<(), FfdError> {
        let s = &self.solver;
        for (field, v) in [
            ("solver.tolerance_rad", s.tolerance_rad),
            ("solver.selection_threshold_rad", s.selection_threshold_rad),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(FfdError::field(
                    field,
                    format!(
                        "must be positive, got {}",
                        sheetform_geometry::refused_number(v, &[0.0])
                    ),
                ));
            }
        }
        for (field, value) in [
            ("solver.position_weight", s.position_weight),
            ("solver.bending_weight", s.bending_weight),
            ("solver.stall_bending_weight", s.stall_bending_weight),
        ] {
            check_weight(field, value, WeightSign::ZeroOrPositive)?;
        }
        if let Some(weights) = &self.lattice.weights {
            for (n, &value) in weights.iter().enumerate() {
                check_weight(&format!("lattice.weights[{n}]"), value, WeightSign::Positive)?;
            }
        }
        if s.chord_steps > MAX_CHORD_STEPS {
            return Err(FfdError::field(
                "solver.chord_steps",
                format!("must be 0 to {MAX_CHORD_STEPS}, got {}", s.chord_steps),
            ));
        }
        if !(1..=MAX_LINE_SEARCH_MEMORY).contains(&s.line_search_memory) {
            return Err(FfdError::field(
                "solver.line_search_memory",
                format!(
                    "must be 1 (monotone) to {MAX_LINE_SEARCH_MEMORY}, got {}",
                    s.line_search_memory
                ),
            ));
        }
        if s.tolerance_rad < MIN_TOLERANCE_RAD {
            return Err(FfdError::field(
                "solver.tolerance_rad",
                format!(
                    "at least {MIN_TOLERANCE_RAD:e} (angle sums are exact only to about 4e-15 rad), got {}",
                    sheetform_geometry::refused_number(s.tolerance_rad, &[MIN_TOLERANCE_RAD])
                ),
            ));
        }
        for (field, value) in [
            ("solver.max_iterations", s.max_iterations.unwrap_or(0)),
            ("solver.refine_iterations", s.refine_iterations),
        ] {
            if value > MAX_SOLVER_ITERATIONS {
                return Err(FfdError::field(
                    field,
                    format!("at most {MAX_SOLVER_ITERATIONS}, got {value}"),
                ));
            }
        }
        if self.deformations.len() > MAX_DEFORMATIONS {
            return Err(FfdError::field(
                "deformations",
                format!(
                    "at most {MAX_DEFORMATIONS} deformations (each is a restoration), got {}",
                    self.deformations.len()
                ),
            ));
        }
        if let Some(c) = &s.continuation {
            if s.method != SolverMethod::Constrained {
                return Err(FfdError::field(
                    "solver.continuation",
                    format!("needs the constrained solver (method is `{}`)", s.method),
                ));
            }
            if !(c.sub_step_curvature.is_finite() && c.sub_step_curvature > 0.0) {
                return Err(FfdError::field(
                    "solver.continuation.sub_step_curvature",
                    format!(
                        "must be positive, got {}",
                        sheetform_geometry::refused_number(c.sub_step_curvature, &[0.0])
                    ),
                ));
            }
            if !(1..=MAX_SUB_STEPS).contains(&c.max_sub_steps) {
                return Err(FfdError::field(
                    "solver.continuation.max_sub_steps",
                    format!("must be between 1 and {MAX_SUB_STEPS}, got {}", c.max_sub_steps),
                ));
            }
        }
        if let ModelSource::Procedural(model) = &self.model {
            model.validate()?;
        }
        for d in 0..3 {
            let (degree, count) = (self.lattice.degrees[d], self.lattice.counts[d]);
            if !(1..=sheetform_geometry::MAX_BSPLINE_DEGREE).contains(&degree) {
                return Err(FfdError::field(
                    format!("lattice.degrees[{d}]"),
                    format!("must be 1 to {}, got {degree}", sheetform_geometry::MAX_BSPLINE_DEGREE),
                ));
            }
            if !(degree + 1..=MAX_LATTICE_COUNT).contains(&count) {
                return Err(FfdError::field(
                    format!("lattice.counts[{d}]"),
                    format!(
                        "must be {} (degree + 1) to {MAX_LATTICE_COUNT}, got {count}",
                        degree + 1
                    ),
                ));
            }
        }
        let automatic_box = self.lattice.box_min.is_none() && self.lattice.control_points.is_none();
        if automatic_box
            && !(self.lattice.margin.is_finite()
                && (MIN_LATTICE_MARGIN..=MAX_LATTICE_MARGIN).contains(&self.lattice.margin))
        {
            return Err(FfdError::field(
                "lattice.margin",
                format!(
                    "must be between {MIN_LATTICE_MARGIN} and {MAX_LATTICE_MARGIN} (the model's vertices on the lattice's boundary could not move outwards), got {}",
                    sheetform_geometry::refused_number(self.lattice.margin, &[MIN_LATTICE_MARGIN, MAX_LATTICE_MARGIN])
                ),
            ));
        }
        if self.deformations.is_empty() {
            return Err(FfdError::field("deformations", "give at least one deformation"));
        }
        Ok(())
    }

    /// The undeformed lattice around points `positions` (the model).
    ///
    /// # Errors
    /// Bad degrees, counts, knots, weights or control points, or a box without volume,
    /// named by field.
    pub fn lattice(&self, positions: &[Vec3]) -> Result<NurbsVolume, FfdError> {
        let l = &self.lattice;
        if let Some(points) = &l.control_points {
            let total: usize = l.counts.iter().product();
            let knots = match &l.knots {
                Some(k) => k.clone(),
                None => {
                    let mut out: [Vec<f64>; 3] = Default::default();
                    for (d, slot) in out.iter_mut().enumerate() {
                        *slot = sheetform_geometry::BSplineBasis::clamped_uniform(l.degrees[d], l.counts[d])
                            .map_err(|e| FfdError::field(format!("lattice.counts[{d}]"), e.to_string()))?
                            .knots()
                            .to_vec();
                    }
                    out
                }
            };
            return NurbsVolume::new(
                l.degrees,
                knots,
                l.counts,
                points.iter().map(|p| Vec3::from(*p)).collect(),
                l.weights.clone().unwrap_or_else(|| vec![1.0; total]),
            );
        }
        // A problem with the box is named by the fields that made it: the scene's box, or
        // (no box given) the model, whose extent grown by the margin is the box.
        let explicit_box = l.box_min.is_some() || l.box_max.is_some();
        let (lo, hi) = match (l.box_min, l.box_max) {
            (Some(a), Some(b)) => (Vec3::from(a), Vec3::from(b)),
            (None, None) => {
                let mut lo = Vec3::repeat(f64::INFINITY);
                let mut hi = Vec3::repeat(f64::NEG_INFINITY);
                for p in positions {
                    lo = lo.inf(p);
                    hi = hi.sup(p);
                }
                let grow = (hi - lo).norm() * l.margin;
                (lo - Vec3::repeat(grow), hi + Vec3::repeat(grow))
            }
            (given, _) => {
                return Err(FfdError::field(
                    if given.is_some() {
                        "lattice.box_min"
                    } else {
                        "lattice.box_max"
                    },
                    "give both box_min and box_max, or neither",
                ))
            }
        };
        if (0..3).any(|d| hi[d] <= lo[d] || !(hi[d] - lo[d]).is_finite()) {
            return Err(if explicit_box {
                FfdError::field(
                    "lattice.box_max",
                    "the box must be larger than box_min in every direction (by a finite length)",
                )
            } else {
                FfdError::field(
                    "model",
                    "has no extent to put a lattice around (no vertices, or coordinates too large to measure)",
                )
            });
        }
        let size = hi - lo;
        let volume = NurbsVolume::parallelepiped(
            lo,
            [Vec3::x() * size.x, Vec3::y() * size.y, Vec3::z() * size.z],
            l.degrees,
            l.counts,
            l.knots.clone(),
        )
        .map_err(|e| match e {
            // The box's volume under- or overflows (sides of 1e-120 or 1e120).
            FfdError::Field { field, .. } if field == NO_VOLUME_FIELD => {
                let message = "the lattice box is too small or too large: its volume is not a finite positive number";
                if explicit_box {
                    FfdError::field("lattice.box_max", message)
                } else {
                    FfdError::field(
                        "model",
                        format!("{message} (the box is the model's extent grown by lattice.margin): scale the model"),
                    )
                }
            }
            other => other,
        })?;
        match &l.weights {
            Some(w) => volume.with_control_net(volume.control_points().to_vec(), w.clone()),
            None => Ok(volume),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn duct() -> FfdScene {
        let path = format!("{}/../../examples/ffd/duct.json", env!("CARGO_MANIFEST_DIR"));
        FfdScene::from_json(&std::fs::read_to_string(path).unwrap()).unwrap()
    }

    /// Issue 35: the FFD's weights had no upper bound (a bending weight of 1e300 was
    /// reported as a singular system, a position weight of 1e300 ended `ok`); every weight
    /// a scene sets is bounded at `MAX_WEIGHT`, as the slit and photo weights are, and
    /// refused naming the field, its value and the bounds. The bounds themselves pass.
    #[test]
    fn every_weight_is_bounded_and_refused_naming_field_value_and_bounds() {
        type Set = fn(&mut FfdScene, f64);
        let fields: [(&str, Set, f64); 4] = [
            ("solver.position_weight", |s, v| s.solver.position_weight = v, 0.0),
            ("solver.bending_weight", |s, v| s.solver.bending_weight = v, 0.0),
            (
                "solver.stall_bending_weight",
                |s, v| s.solver.stall_bending_weight = v,
                0.0,
            ),
            (
                "lattice.weights[5]",
                |s, v| {
                    let mut w = vec![1.0; 64];
                    w[5] = v;
                    s.lattice.weights = Some(w);
                },
                1e-300,
            ),
        ];
        for (field, set, lowest) in fields {
            for fine in [lowest, MAX_WEIGHT] {
                let mut scene = duct();
                set(&mut scene, fine);
                assert_eq!(scene.validate(), Ok(()), "{field} = {fine:e}");
            }
            for (bad, shown) in [
                (1e300, "got 1e300"),
                (1_000_000.5, "got 1.0000005e6"),
                (f64::INFINITY, "got inf"),
                (-1.0, "got -1"),
            ] {
                let mut scene = duct();
                set(&mut scene, bad);
                let e = scene.validate().unwrap_err().to_string();
                assert!(e.starts_with(&format!("scene field `{field}`: must be ")), "{e}");
                assert!(e.contains("to 1e6, got") && e.ends_with(shown), "{e}");
            }
        }
        // A lattice weight of 0 takes its control point out of the volume.
        let mut scene = duct();
        scene.lattice.weights = Some(vec![0.0; 64]);
        let e = scene.validate().unwrap_err().to_string();
        assert!(
            e.contains("`lattice.weights[0]`: must be a positive number up to 1e6, got 0"),
            "{e}"
        );
    }

    /// Issue 35: a lattice made from the model (no box in the scene) that cannot be built
    /// named `lattice.box` (no such field) or `lattice.box_max` (not in the scene): the
    /// model is named, and a box given in part names the part given.
    #[test]
    fn a_box_problem_names_the_fields_the_scene_has() {
        let scene = duct();
        for positions in [
            vec![Vec3::new(-1e308, 0.0, 0.0), Vec3::new(1e308, 1.0, 1.0)],
            vec![Vec3::zeros(), Vec3::repeat(1e-110)],
            vec![],
        ] {
            let e = scene.lattice(&positions).unwrap_err().to_string();
            assert!(e.starts_with("scene field `model`"), "{e}");
        }
        let points = [Vec3::zeros(), Vec3::repeat(1.0)];
        let mut scene = duct();
        scene.lattice.box_max = Some([2.0; 3]);
        let e = scene.lattice(&points).unwrap_err().to_string();
        assert!(e.contains("`lattice.box_max`") && e.contains("give both"), "{e}");
        scene.lattice.box_min = Some([0.0; 3]);
        scene.lattice.box_max = Some([1e-120; 3]);
        let e = scene.lattice(&points).unwrap_err().to_string();
        assert!(
            e.contains("`lattice.box_max`") && e.contains("too small or too large"),
            "{e}"
        );
    }
}

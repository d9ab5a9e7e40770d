//! The slit scene file (JSON): what the user writes. [`SlitScene`] is its serde form; the
//! JSON Schema in `docs/schema/slit-scene.schema.json` is generated from these types.
//!
//! Coordinates (the paper's, §3.1): `y` is up, the ground is the `xz` plane, the symmetry
//! plane is `x = 0` and the modelled half lies at `x > 0`. The sheet's width runs along `z`.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use sheetform_mesh::LengthUnit;

/// A rectangular sheet with parallel slits bent into a symmetric shape (system B,
/// Tsuruta et al.).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SlitScene {
    /// Optional name shown in reports and pattern labels.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Length unit of every length and coordinate in the file. Default `mm`.
    #[serde(default)]
    #[schemars(with = "String")]
    pub units: LengthUnit,
    /// The flat sheet (Fig. 2).
    pub sheet: SheetSpec,
    /// The leg curve (Fig. 11): the side panel seen from the front, as a 2D Bézier in the
    /// `xy` plane (`[x, y]`: distance from the symmetry plane, height), from the foot
    /// upwards. The side panel is this curve swept along `z`; the strips start (ridge
    /// line E0) where the curve has run the panel length `l2_panel_length`. Default: a
    /// vertical panel at `x = l3_strip_length` standing on the ground, as in the paper's
    /// initial state (Fig. 9).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub leg_curve: Option<PlanarCurveSpec>,
    /// The seat curve (Fig. 11): the cross-section the strips' ends should meet on the
    /// symmetry plane, as a 2D Bézier in that plane (`[z, y]`: depth across the sheet,
    /// height). It must span every strip's `z` range. Optional: without it only the other
    /// terms shape the strips.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seat_curve: Option<PlanarCurveSpec>,
    /// Position anchors (Fig. 12): a ridge-line end point pulled towards a 3D position.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub anchors: Vec<AnchorSpec>,
    /// Weights of the penalty terms (Eq. 1). Defaults are the paper's.
    #[serde(default)]
    pub weights: WeightsSpec,
    /// How the strips are solved.
    #[serde(default)]
    pub solver: SolverSpec,
    /// Fit the strips to scanned points (§4.1, Eq. 6).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scan: Option<ScanSpec>,
    /// The 3D-printable mould under the strips (§4.2).
    #[serde(default)]
    pub mould: MouldSpec,
}

/// The flat sheet: a rectangle, symmetric about its middle line, with `strip_count`
/// strips separated by `strip_count − 1` slits of equal length (Fig. 2).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SheetSpec {
    /// L1: the sheet's width, across the slits (along `z`).
    pub l1_width: f64,
    /// L2: length of each side panel, from the sheet's end to where the slits begin.
    pub l2_panel_length: f64,
    /// L3: length of each half strip, from where the slits begin to the middle line (half
    /// the slit length). The sheet's length is `2 (l2 + l3)`.
    pub l3_strip_length: f64,
    /// L4: width of each slit (the material cut away between two strips).
    pub l4_slit_width: f64,
    /// N: number of strips.
    pub strip_count: usize,
    /// M: quads per half strip (ridge lines E0..EM). Default 10.
    #[serde(default = "default_quads")]
    pub quads_per_strip: usize,
}

fn default_quads() -> usize {
    10
}

/// A planar Bézier curve given by its control points.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PlanarCurveSpec {
    /// Control points (at least two; degree = count − 1).
    pub control_points: Vec<[f64; 2]>,
}

/// Which long edge of a strip.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum StripSide {
    /// The edge at the smaller `z` (end points `v_L,i`).
    Left,
    /// The edge at the larger `z` (end points `v_R,i`).
    Right,
}

/// A position anchor: the end point `v_side,ridge` of one ridge line is pulled towards
/// `position` (Eq. 5, first sum).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AnchorSpec {
    /// Strip index, 0 = the strip at `z = 0`.
    pub strip: usize,
    /// Ridge line index, 1..=quads_per_strip (E0 is fixed by the leg curve; EM lies on
    /// the symmetry plane). Refers to the ridge lines before any subdivision.
    pub ridge: usize,
    /// Which end of the ridge line.
    pub side: StripSide,
    /// Target position `[x, y, z]`.
    pub position: [f64; 3],
}

/// The largest weight of [`WeightsSpec`] (as the photo reconstruction's energy weights):
/// larger ones overflow when squared in the solve.
pub const MAX_WEIGHT: f64 = 1e6;

/// Weights `w1..w4` of Eq. 1 and of the extensions, each from 0 to [`MAX_WEIGHT`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct WeightsSpec {
    /// w1, the gap at the symmetry plane (Eq. 2). Default 0.1.
    pub no_gap: f64,
    /// w2, smoothness and the end angle (Eq. 3). Default 0.04.
    pub smooth: f64,
    /// w3, fairness of the quads (Eq. 4). Default 0.01.
    pub fair: f64,
    /// w4, user control: anchors and the seat curve (Eq. 5). Default 0.03.
    pub user_control: f64,
    /// Closeness to the scanned points (Eq. 6). Default 0.03.
    pub scan: f64,
    /// Joint solve only: neighbouring strips' ridge angles kept close (the paper's
    /// future work). Default 0.01.
    pub neighbour: f64,
}

impl Default for WeightsSpec {
    fn default() -> Self {
        Self {
            no_gap: 0.1,
            smooth: 0.04,
            fair: 0.01,
            user_control: 0.03,
            scan: 0.03,
            neighbour: 0.01,
        }
    }
}

/// Strips one by one, or all together.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum SolveMode {
    /// Each strip on its own (in parallel), as in the paper.
    #[default]
    Independent,
    /// All strips in one problem with the neighbour term.
    Joint,
}

/// How the no-gap condition is enforced.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum GapHandling {
    /// As an equality constraint (augmented Lagrangian around the penalty): the gap goes
    /// to `gap_tolerance`.
    #[default]
    Exact,
    /// As the paper: a fixed penalty weight `w1`; some gap remains.
    Penalty,
}

/// Solver settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct SolverSpec {
    /// Strips one by one or jointly. Default `independent`.
    pub mode: SolveMode,
    /// Gap as a constraint or a penalty. Default `exact`.
    pub gap: GapHandling,
    /// Target of the normalised error `E = G / (L2 + L3)` with `gap: exact`. Default 1e-8.
    pub gap_tolerance: f64,
    /// Most Levenberg–Marquardt iterations per strip (all rounds together). Default 500.
    pub max_iterations: usize,
    /// Times every quad is split in two after solving, then solved again from the current
    /// state (Fig. 13). Default 0.
    pub subdivisions: usize,
    /// Segments of the side panel along the leg curve. Default 24.
    pub leg_segments: usize,
}

impl Default for SolverSpec {
    fn default() -> Self {
        Self {
            mode: SolveMode::Independent,
            gap: GapHandling::Exact,
            gap_tolerance: 1e-8,
            max_iterations: 500,
            subdivisions: 0,
            leg_segments: 24,
        }
    }
}

/// Scanned points to fit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ScanSpec {
    /// A point cloud file, `.ply` (vertices) or `.xyz` (`x y z` per line), relative to the
    /// scene file, in the scene's units.
    pub points: String,
}

/// The mould (§4.2).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct MouldSpec {
    /// Write `mould.stl`. Default true.
    pub enabled: bool,
    /// Thickness of the base plate under the lowest point of the shape (from a millionth
    /// of the sheet's largest length to 1e6). Default 5.
    pub base_thickness: f64,
    /// Thickness of the sheet pressed onto the mould (0: a sheet of no thickness; else from
    /// a millionth of the sheet's largest length to half the strip width). The
    /// model is the sheet's mid-surface, which keeps its length when the sheet bends, so
    /// the pattern is exact there; the mould's top lies half this much below it, where
    /// the sheet's underside rests (the paper's §4.2 found its pattern short for not
    /// doing so). Default 0.
    pub sheet_thickness: f64,
}

impl Default for MouldSpec {
    fn default() -> Self {
        Self {
            enabled: true,
            base_thickness: 5.0,
            sheet_thickness: 0.0,
        }
    }
}

impl SlitScene {
    /// Parses a scene from JSON text.
    ///
    /// # Errors
    /// [`crate::SlitError::Field`] naming the field path of the first problem, what is
    /// accepted, then the line and column.
    pub fn from_json(text: &str) -> Result<Self, crate::SlitError> {
        sheetform_geometry::json_from_text(text).map_err(|e| crate::SlitError::field(e.field, e.message))
    }

    /// The JSON Schema of the scene format.
    pub fn json_schema() -> serde_json::Value {
        serde_json::to_value(schemars::schema_for!(SlitScene)).expect("schema serialises")
    }
}

//! The bend scene file (JSON): what the user writes. [`BendScene`] is its serde form; the
//! JSON Schema in `docs/schema/bend-scene.schema.json` is generated from these types.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use sheetform_mesh::LengthUnit;

/// A sheet bent by one or more 3D control curves (system A, Bo & Wang 2007).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BendScene {
    /// Optional name shown in reports and pattern labels.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Length unit of every coordinate in the file (flat and 3D). Default `mm`.
    #[serde(default)]
    #[schemars(with = "String")]
    pub units: LengthUnit,
    /// The flat sheet's outline: a simple polygon, `[x, y]` per vertex, either orientation,
    /// concave allowed, not closed (the last vertex joins the first).
    pub outline: Vec<[f64; 2]>,
    /// Holes in the sheet, each a simple polygon inside the outline.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub holes: Vec<Vec<[f64; 2]>>,
    /// Curved regions. Region 0 is placed in world coordinates as its curve says; every
    /// other region, and every planar piece, is attached rigidly to its neighbour (§4.2),
    /// so only the *shape* of their curves matters, not where they are drawn.
    pub regions: Vec<CurvedRegionSpec>,
    /// How finely the bent sheet is cut into planar strips.
    #[serde(default)]
    pub tessellation: TessellationOptions,
    /// A picture printed on the sheet (PNG or JPEG, path relative to the scene file),
    /// stretched over the flat pattern's bounding box. The flat sheet is the texture
    /// domain, so the bent sheet shows it without distortion (Fig. 6). Embedded in the GLB.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub texture: Option<String>,
    /// Which axis of the 3D coordinates (the control curves) points up: `"z"` (the
    /// default: the flat sheet lies in the `xy` plane) or `"y"`. The GLB and OBJ are
    /// written `+Y` up, a `+Z`-up scene turned.
    #[serde(default = "z_up")]
    pub up_axis: sheetform_mesh::UpAxis,
}

fn z_up() -> sheetform_mesh::UpAxis {
    sheetform_mesh::UpAxis::Z
}

/// One curved region: a straight segment on the flat sheet and the 3D control curve it
/// is bent into. The curve is a geodesic of the bent sheet.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CurvedRegionSpec {
    /// Optional name (default `curved-K`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Start of the flat geodesic segment (where arc length 0 of the curve lands). Not used
    /// with a Bézier or B-spline `flat_curve`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flat_start: Option<[f64; 2]>,
    /// End of the flat geodesic segment. Its distance from `flat_start` must equal the
    /// curve's length (see `tessellation.length_tolerance`). Give this or `flat_direction`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flat_end: Option<[f64; 2]>,
    /// Direction of the flat geodesic segment; its length is then the curve's length.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flat_direction: Option<[f64; 2]>,
    /// The 3D control curve.
    pub curve: CurveSpec,
    /// The control curve's image on the flat sheet when it is not a straight segment
    /// (§5, non-geodesic control curves): the bent curve keeps this curve's curvature as
    /// its geodesic curvature. Needs `|p''|` larger than that curvature everywhere.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flat_curve: Option<FlatCurveSpec>,
    /// Which way the sheet's top face (the side facing +z in the flat pattern) should face
    /// at the start of the curve: of the two possible sheets, the one whose top normal
    /// points more along `up`. Default `[0, 0, 1]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub up: Option<[f64; 3]>,
    /// The curve is closed and the sheet's two end rulings are glued (closed strip, tube).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub closed: bool,
}

/// A 3D control curve.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum CurveSpec {
    /// Bézier curve of degree `n = control_points.len() − 1 ≥ 2`.
    Bezier {
        /// Control points `[x, y, z]`.
        control_points: Vec<[f64; 3]>,
    },
    /// B-spline curve (cubic by default). Without `knots`: clamped and uniform, or, with
    /// `periodic`, closed and uniform (the first `degree` points are wrapped around).
    Bspline {
        /// Degree (default 3).
        #[serde(default = "default_degree")]
        degree: usize,
        /// Control points `[x, y, z]`.
        control_points: Vec<[f64; 3]>,
        /// Full knot vector (`control_points.len() + degree + 1` non-decreasing values).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        knots: Option<Vec<f64>>,
        /// Closed curve with uniform knots.
        #[serde(default, skip_serializing_if = "std::ops::Not::not")]
        periodic: bool,
    },
    /// Exact circular helix about the z axis through `center`:
    /// `center + (r cos θ, r sin θ, c θ)`, `θ` from `start_angle` to `end_angle` (radians).
    /// `rise_per_radian = 0` gives a circle (a tube's geodesic, Fig. 14).
    Helix {
        /// Radius `r`.
        radius: f64,
        /// Rise along z per radian `c`.
        #[serde(default)]
        rise_per_radian: f64,
        /// Start angle (radians).
        #[serde(default)]
        start_angle: f64,
        /// End angle (radians).
        end_angle: f64,
        /// Point on the axis (default origin).
        #[serde(default)]
        center: [f64; 3],
    },
}

/// A planar curve on the flat sheet (§5).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum FlatCurveSpec {
    /// A circular arc from `flat_start` leaving along `flat_direction`; its length is the
    /// control curve's.
    Arc {
        /// Radius (model units).
        radius: f64,
        /// `left` (counter-clockwise) or `right`.
        turn: String,
    },
    /// A planar Bézier curve; its length must equal the control curve's.
    Bezier {
        /// Control points `[x, y]`.
        control_points: Vec<[f64; 2]>,
    },
    /// A planar B-spline (clamped uniform knots unless given); its length must equal the
    /// control curve's.
    Bspline {
        /// Degree (default 3).
        #[serde(default = "default_degree")]
        degree: usize,
        /// Control points `[x, y]`.
        control_points: Vec<[f64; 2]>,
        /// Full knot vector.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        knots: Option<Vec<f64>>,
    },
}

fn default_degree() -> usize {
    3
}

/// How finely the bent sheet is cut into planar strips between rulings.
///
/// The mesh is exactly isometric at every setting; finer settings bring it closer to the
/// smooth developable (the distance shrinks with the square of the fold angle).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct TessellationOptions {
    /// Largest angle (degrees) between the planes of two neighbouring strips.
    pub max_fold_angle_degrees: f64,
    /// Fewest rulings per curved region.
    pub min_rulings: usize,
    /// Most rulings per curved region.
    pub max_rulings: usize,
    /// Exact ruling count per curved region (overrides the three above).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rulings: Option<usize>,
    /// Allowed relative difference between a curve's length and its flat segment's.
    pub length_tolerance: f64,
}

impl Default for TessellationOptions {
    fn default() -> Self {
        Self {
            max_fold_angle_degrees: 1.0,
            min_rulings: 24,
            max_rulings: 200_000,
            rulings: None,
            length_tolerance: 1e-6,
        }
    }
}

impl BendScene {
    /// Parses a scene from JSON text.
    ///
    /// # Errors
    /// [`crate::BendError::Field`] for malformed JSON, unknown, missing or mistyped fields:
    /// naming the field path (`regions[0].curve.type`), what is accepted, then the line
    /// and column.
    pub fn from_json(text: &str) -> Result<Self, crate::BendError> {
        sheetform_geometry::json_from_text(text).map_err(|e| crate::BendError::Field {
            field: e.field,
            message: e.message,
        })
    }

    /// The JSON Schema of the scene format.
    pub fn json_schema() -> serde_json::Value {
        serde_json::to_value(schemars::schema_for!(BendScene)).expect("schema serialises")
    }
}

//! The photo annotation file (JSON): the curves a user traced over one photograph and the
//! symmetry and size marks of Fondevilla et al. §4 (Fig. 3). [`PhotoAnnotation`] is its
//! serde form; `docs/schema/photo-annotation.schema.json` is generated from these types.
//!
//! Coordinates are image pixels: `x` to the right, `y` down, origin at the top-left
//! corner (as every image editor shows them). The reconstruction works in the *model
//! frame* `X = x`, `Y = −y`, `Z` towards the viewer (right-handed, orthographic
//! projection drops `Z`), see [`image_to_model`].

use crate::PhotoError;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use sheetform_geometry::{numbers_apart, refused_number, short_number};
use sheetform_mesh::LengthUnit;

/// A 2D point in image pixels, `[x, y]`, `y` down.
pub type ImagePoint = [f64; 2];

/// Most curves in one annotation.
pub const MAX_CURVES: usize = 2_000;
/// Most control points over all curves.
pub const MAX_CONTROL_POINTS: usize = 30_000;
/// Largest image side (pixels).
pub const MAX_IMAGE_SIDE: u32 = 40_000;
/// Most pixels of the image (100 MP): the overlay decodes it whole, about 12 bytes per
/// pixel.
pub const MAX_IMAGE_PIXELS: u64 = 100_000_000;
/// Most entries in each of `occlusions` and `openings`.
pub const MAX_MARKERS: usize = 1_000;

/// Curves traced over a photograph of a piecewise-developable, mirror-symmetric object
/// (system D, Fondevilla et al. 2017).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PhotoAnnotation {
    /// Optional name shown in reports and pattern labels.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// The photograph the curves were traced over.
    pub image: ImageSpec,
    /// The camera that took it. Default: orthographic (the paper's assumption); a phone
    /// or camera photo is a perspective view.
    #[serde(default, skip_serializing_if = "CameraSpec::is_default")]
    pub camera: CameraSpec,
    /// Unit of `true_size.length` and of every output length. Default `mm`.
    #[serde(default)]
    #[schemars(with = "String")]
    pub units: LengthUnit,
    /// The traced curves: C¹ piecewise cubic Béziers (at least one).
    pub curves: Vec<CurveSpec>,
    /// The mirror-symmetry plane (§6.1): without it the drawing has no depth.
    pub symmetry: SymmetrySpec,
    /// Pairs of curves (by name) that are mirror images of each other (§5.3).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub symmetric_curves: Vec<[String; 2]>,
    /// Curves (by name) that are their own mirror image (§5.3).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub self_symmetric_curves: Vec<String>,
    /// Crossings of curves near these points (pixels) are not joined in 3D: one curve
    /// passes in front of the other (§4, the purple disks of Fig. 3).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub occlusions: Vec<ImagePoint>,
    /// One point inside each region of the drawing that is not material (the mouth of a
    /// cup): that region gets no surface.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub openings: Vec<ImagePoint>,
    /// What to make of the side the photo does not show. Default `visible`: the model
    /// and its pattern are what the drawing shows; `revolve` closes every ruled band
    /// around one axis (a cup, a lamp shade, a vase made of cones and cylinders), so that
    /// the pattern is the whole product.
    #[serde(default, skip_serializing_if = "BackSide::is_visible")]
    pub back_side: BackSide,
    /// A known true distance between two points on the curves: the model and its
    /// patterns are scaled to it.
    pub true_size: TrueSizeSpec,
    /// Knobs of the analysis and the solve; every one has a default.
    #[serde(default)]
    pub analysis: AnalysisSpec,
}

/// The photograph.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ImageSpec {
    /// PNG or JPEG file, relative to the annotation file.
    pub path: String,
    /// Width in pixels (must match the file).
    pub width: u32,
    /// Height in pixels (must match the file).
    pub height: u32,
}

/// How the photograph projects the object.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Projection {
    /// Parallel projection (a telephoto view from far away; the paper's assumption).
    #[default]
    Orthographic,
    /// A pinhole camera: a phone or camera photo.
    Perspective,
}

/// Smallest focal length, in image diagonals (a diagonal field of view of 157°).
pub const MIN_FOCAL_LENGTH_DIAGONALS: f64 = 0.1;
/// Largest focal length, in image diagonals (a diagonal field of view of 0.57°: beyond it
/// the view is orthographic to a thousandth).
pub const MAX_FOCAL_LENGTH_DIAGONALS: f64 = 100.0;

/// The camera of the photograph. A perspective camera takes its focal length in pixels
/// or as the 35 mm equivalent a phone writes in the photo's EXIF
/// (`FocalLengthIn35mmFilm`, e.g. 26 mm for a phone's main camera); without either, the
/// pipeline reads it from the photo's EXIF, and without it there the reconstruction
/// estimates it from the drawing (0.2-16 % off on the synthetic views; a warning says so).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CameraSpec {
    /// `orthographic` (default) or `perspective`.
    #[serde(default)]
    pub projection: Projection,
    /// Focal length in pixels of this image (perspective only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub focal_length_px: Option<f64>,
    /// Focal length in mm, 35 mm film equivalent (perspective only): the image's
    /// diagonal is seen as a 43.27 mm film diagonal. Without this and `focal_length_px`,
    /// taken from the photo's EXIF (`FocalLengthIn35mmFilm`), or else estimated from the
    /// drawing; a cropped photo's EXIF value is the uncropped one's, give
    /// `focal_length_px` then.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub focal_length_35mm: Option<f64>,
    /// Where the optical axis meets the image (pixels). Default: the image's centre
    /// (right for any uncropped photo).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub principal_point: Option<ImagePoint>,
}

impl CameraSpec {
    /// Whether every field has its default (the orthographic camera).
    pub fn is_default(&self) -> bool {
        *self == Self::default()
    }

    /// The principal point (image pixels): the one given, or the image's centre.
    pub fn principal_point_or_centre(&self, width: u32, height: u32) -> ImagePoint {
        self.principal_point
            .unwrap_or([0.5 * f64::from(width), 0.5 * f64::from(height)])
    }

    /// A perspective camera whose focal length is given neither in pixels nor in 35 mm
    /// terms (the reconstruction estimates it from the drawing).
    pub fn focal_length_missing(&self) -> bool {
        self.projection == Projection::Perspective && self.focal_length_px.is_none() && self.focal_length_35mm.is_none()
    }

    /// The focal length in pixels for a `width × height` image (`None` for an
    /// orthographic camera or when none is given).
    pub fn focal_length(&self, width: u32, height: u32) -> Option<f64> {
        let diagonal = f64::from(width).hypot(f64::from(height));
        self.focal_length_px.or(self
            .focal_length_35mm
            .map(|f| f * diagonal / crate::camera::FILM_35MM_DIAGONAL_MM))
    }
}

/// What a traced curve is (§4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum CurveKind {
    /// A smooth contour where the surface turns away from the viewer. On a developable
    /// surface it is a straight segment along a ruling (§3): rulings are propagated from
    /// it into the patch it bounds.
    Silhouette,
    /// A sharp edge, cut edge or seam between patches.
    Boundary,
}

/// One traced curve: a C¹ piecewise cubic Bézier in image pixels.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CurveSpec {
    /// Unique name (errors, symmetric pairs and reports refer to it).
    pub name: String,
    /// Silhouette or boundary.
    pub kind: CurveKind,
    /// `3k + 1` control points (`k ≥ 1` cubic segments; segment `j` uses points `3j …
    /// 3j+3`). Points `3j−1, 3j, 3j+1` should be collinear (C¹ joins).
    pub control_points: Vec<ImagePoint>,
    /// A closed curve ends where it starts (the last control point equals the first).
    #[serde(default)]
    pub closed: bool,
}

/// The symmetry annotation of §6.1 (the cyan frame and red squares of Fig. 3).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SymmetrySpec {
    /// Two segments `[[start], [end]]` that lie in the symmetry plane and are
    /// perpendicular to each other in 3D. Their images must be neither parallel nor
    /// perpendicular.
    pub frame: [[ImagePoint; 2]; 2],
    /// A pair of mirror-symmetric points: the segment between them is along the plane's
    /// normal in 3D.
    pub points: [ImagePoint; 2],
    /// Take the other of the two depth interpretations (a single orthographic view
    /// cannot tell which side of the plane is nearer the camera). Default `false`: the
    /// second of `points` is nearer.
    #[serde(default)]
    pub flip_depth: bool,
}

/// A known distance that fixes the model's size.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TrueSizeSpec {
    /// First point (pixels), on or next to a traced curve.
    pub from: ImagePoint,
    /// Second point (pixels), on or next to a traced curve.
    pub to: ImagePoint,
    /// Their true 3D distance, in the annotation's `units` (from 1e-6 to below 1e9).
    pub length: f64,
}

/// Knobs of the analysis (§5) and the solve (§6). Lengths are in image pixels; a missing
/// length is set from the image's diagonal `d`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AnalysisSpec {
    /// A curve end this close to another curve is joined to it (default `d/600`, at
    /// least 1 px).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub snap_distance_px: Option<f64>,
    /// Spacing of the samples along the curves: mesh boundary, DTW and symmetric
    /// correspondences (default `d/250`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sample_spacing_px: Option<f64>,
    /// Spacing of the kept rulings (default `d/90`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ruling_spacing_px: Option<f64>,
    /// The weight `λ` of the ruling-smoothness term of the DTW cost (Eq. 2). Default 1.
    #[serde(default = "default_dtw_weight")]
    pub dtw_smoothness_weight: f64,
    /// The energy's weights (§6.2). Defaults are the paper's.
    #[serde(default)]
    pub weights: EnergyWeights,
    /// Make every ruled patch exactly developable after the linear solve (beyond the
    /// paper; default `true`).
    #[serde(default = "default_true")]
    pub refine: bool,
    /// Make the model exactly mirror-symmetric (§7; default `true`): the curves and
    /// rulings on the far side of the symmetry plane become the mirror image of those on
    /// the near side, wherever the drawing shows both (the report lists the curves left
    /// as solved). Switch it off for objects that are not quite symmetric.
    #[serde(default = "default_true")]
    pub symmetrize: bool,
}

fn default_dtw_weight() -> f64 {
    1.0
}

fn default_true() -> bool {
    true
}

impl Default for AnalysisSpec {
    fn default() -> Self {
        Self {
            snap_distance_px: None,
            sample_spacing_px: None,
            ruling_spacing_px: None,
            dtw_smoothness_weight: default_dtw_weight(),
            weights: EnergyWeights::default(),
            refine: true,
            symmetrize: true,
        }
    }
}

/// What to make of the side of the object the photo does not show.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum BackSide {
    /// Only what the drawing shows (the paper's result).
    #[default]
    Visible,
    /// Every ruled band closed around one axis as a cone or cylinder, cut open along a
    /// seam at the back (`revolved_bands.rs`).
    Revolve,
}

impl BackSide {
    /// Whether this is the default, [`BackSide::Visible`].
    pub fn is_visible(&self) -> bool {
        *self == Self::Visible
    }
}

/// The weights `ω1 … ω6` of the energy (§6.2).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct EnergyWeights {
    /// `ω1`, projection accuracy (default 1).
    #[serde(default = "one")]
    pub projection: f64,
    /// `ω2`, minimal variation (default 0.1).
    #[serde(default = "tenth")]
    pub minimal_variation: f64,
    /// `ω3`, collinearity of C¹ joins (default 1).
    #[serde(default = "one")]
    pub collinearity: f64,
    /// `ω4`, foreshortening (default 1e-8).
    #[serde(default = "tiny")]
    pub foreshortening: f64,
    /// `ω5`, symmetry (default 1).
    #[serde(default = "one")]
    pub symmetry: f64,
    /// `ω6`, developability (default 1).
    #[serde(default = "one")]
    pub developability: f64,
}

fn one() -> f64 {
    1.0
}
fn tenth() -> f64 {
    0.1
}
fn tiny() -> f64 {
    1e-8
}

impl Default for EnergyWeights {
    fn default() -> Self {
        Self {
            projection: 1.0,
            minimal_variation: 0.1,
            collinearity: 1.0,
            foreshortening: 1e-8,
            symmetry: 1.0,
            developability: 1.0,
        }
    }
}

/// The model frame's point for an image point: `(x, −y)`.
pub fn image_to_model(p: ImagePoint) -> nalgebra::Vector2<f64> {
    nalgebra::Vector2::new(p[0], -p[1])
}

/// The image point of a model-frame point.
pub fn model_to_image(p: nalgebra::Vector2<f64>) -> ImagePoint {
    [p.x, -p.y]
}

/// Resolved analysis lengths (pixels).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AnalysisLengths {
    /// Snap distance.
    pub snap: f64,
    /// Sample spacing.
    pub sample: f64,
    /// Ruling spacing.
    pub ruling: f64,
}

impl PhotoAnnotation {
    /// Checks `camera` for an image of diagonal `d` pixels.
    fn validate_camera(&self, d: f64) -> Result<(), PhotoError> {
        let c = &self.camera;
        match c.projection {
            Projection::Orthographic => {
                for (field, given) in [
                    ("camera.focal_length_px", c.focal_length_px.is_some()),
                    ("camera.focal_length_35mm", c.focal_length_35mm.is_some()),
                    ("camera.principal_point", c.principal_point.is_some()),
                ] {
                    if given {
                        return Err(PhotoError::field(
                            field,
                            "is for a perspective camera: set camera.projection to \"perspective\"",
                        ));
                    }
                }
            }
            Projection::Perspective => {
                if c.focal_length_px.is_some() && c.focal_length_35mm.is_some() {
                    return Err(PhotoError::field(
                        "camera",
                        "give the focal length once: focal_length_px or focal_length_35mm",
                    ));
                }
                let (lo, hi) = (MIN_FOCAL_LENGTH_DIAGONALS * d, MAX_FOCAL_LENGTH_DIAGONALS * d);
                let mm = |px: f64| px / d * crate::camera::FILM_35MM_DIAGONAL_MM;
                let (field, value, bounds, unit) = match (c.focal_length_px, c.focal_length_35mm) {
                    (Some(f), _) => ("camera.focal_length_px", f, [lo, hi], "px for this image"),
                    (None, Some(f)) => ("camera.focal_length_35mm", f, [mm(lo), mm(hi)], "mm"),
                    // Read from the photo's EXIF by the caller, or refused by `reconstruct`.
                    (None, None) => return Ok(()),
                };
                if !(value.is_finite() && value >= bounds[0] && value <= bounds[1]) {
                    return Err(PhotoError::field(
                        field,
                        format!(
                            "must be within {} … {} {unit} (got {})",
                            short_number(bounds[0]),
                            short_number(bounds[1]),
                            refused_number(value, &bounds)
                        ),
                    ));
                }
                if let Some(p) = c.principal_point {
                    let (w, h) = (f64::from(self.image.width), f64::from(self.image.height));
                    if !(p[0].is_finite() && p[1].is_finite() && (0.0..=w).contains(&p[0]) && (0.0..=h).contains(&p[1]))
                    {
                        return Err(PhotoError::field(
                            "camera.principal_point",
                            format!(
                                "must lie in the {w} × {h} image (got [{}, {}])",
                                short_number(p[0]),
                                short_number(p[1])
                            ),
                        ));
                    }
                }
            }
        }
        Ok(())
    }

    /// Parses an annotation from JSON text and validates it ([`PhotoAnnotation::validate`]).
    ///
    /// # Errors
    /// [`PhotoError::Field`] naming the field path of the first problem (with what is
    /// accepted, then the line and column, for one serde finds).
    pub fn from_json(text: &str) -> Result<Self, PhotoError> {
        let annotation: Self =
            sheetform_geometry::json_from_text(text).map_err(|e| PhotoError::field(e.field, e.message))?;
        annotation.validate()?;
        Ok(annotation)
    }

    /// The JSON Schema of the annotation format.
    pub fn json_schema() -> serde_json::Value {
        serde_json::to_value(schemars::schema_for!(PhotoAnnotation)).expect("schema serialises")
    }

    /// The image diagonal (pixels).
    pub fn diagonal(&self) -> f64 {
        f64::from(self.image.width).hypot(f64::from(self.image.height))
    }

    /// The analysis lengths with defaults filled in from the image diagonal.
    pub fn lengths(&self) -> AnalysisLengths {
        let d = self.diagonal();
        AnalysisLengths {
            snap: self.analysis.snap_distance_px.unwrap_or((d / 600.0).max(1.0)),
            sample: self.analysis.sample_spacing_px.unwrap_or(d / 250.0),
            ruling: self.analysis.ruling_spacing_px.unwrap_or(d / 90.0),
        }
    }

    /// Checks every field's range (counts, finiteness, sizes, names, the symmetry
    /// annotation). Geometric problems of the curves (self-crossings, no cycle) are found
    /// by the analysis.
    ///
    /// # Errors
    /// [`PhotoError::Field`] naming the first bad field.
    pub fn validate(&self) -> Result<(), PhotoError> {
        let (w, h) = (self.image.width, self.image.height);
        if w == 0 || h == 0 || w > MAX_IMAGE_SIDE || h > MAX_IMAGE_SIDE {
            return Err(PhotoError::field(
                "image",
                format!("width and height must be 1 … {MAX_IMAGE_SIDE} px (got {w} × {h})"),
            ));
        }
        if u64::from(w) * u64::from(h) > MAX_IMAGE_PIXELS {
            return Err(PhotoError::field(
                "image",
                format!(
                    "{w} × {h} px is over {} megapixels; scale the photo and the curves down",
                    MAX_IMAGE_PIXELS / 1_000_000
                ),
            ));
        }
        if self.image.path.trim().is_empty() {
            return Err(PhotoError::field("image.path", "empty"));
        }
        for (field, count, limit) in [
            ("symmetric_curves", self.symmetric_curves.len(), MAX_CURVES),
            ("self_symmetric_curves", self.self_symmetric_curves.len(), MAX_CURVES),
            ("occlusions", self.occlusions.len(), MAX_MARKERS),
            ("openings", self.openings.len(), MAX_MARKERS),
        ] {
            if count > limit {
                return Err(PhotoError::field(field, format!("{count} entries (at most {limit})")));
            }
        }
        let mut pairs = std::collections::HashSet::new();
        for (i, [a, b]) in self.symmetric_curves.iter().enumerate() {
            let key = if a <= b { (a, b) } else { (b, a) };
            if !pairs.insert(key) {
                return Err(PhotoError::field(
                    format!("symmetric_curves[{i}]"),
                    format!("the pair `{a}`, `{b}` is given twice"),
                ));
            }
        }
        let mut singles = std::collections::HashSet::new();
        for (i, name) in self.self_symmetric_curves.iter().enumerate() {
            if !singles.insert(name) {
                return Err(PhotoError::field(
                    format!("self_symmetric_curves[{i}]"),
                    format!("`{name}` is given twice"),
                ));
            }
        }
        let d = self.diagonal();
        // Points may lie a little outside the image (a curve traced to the border), not
        // far away.
        let check_point = |field: String, p: ImagePoint| -> Result<(), PhotoError> {
            if !p[0].is_finite() || !p[1].is_finite() {
                return Err(PhotoError::field(field, "not a finite number"));
            }
            if p[0] < -d || p[1] < -d || p[0] > f64::from(w) + d || p[1] > f64::from(h) + d {
                return Err(PhotoError::field(
                    field,
                    format!(
                        "[{}, {}] is far outside the {w} × {h} image",
                        short_number(p[0]),
                        short_number(p[1])
                    ),
                ));
            }
            Ok(())
        };
        if self.curves.is_empty() {
            return Err(PhotoError::field("curves", "no curve"));
        }
        if self.curves.len() > MAX_CURVES {
            return Err(PhotoError::field(
                "curves",
                format!("{} curves (at most {MAX_CURVES})", self.curves.len()),
            ));
        }
        let total: usize = self.curves.iter().map(|c| c.control_points.len()).sum();
        if total > MAX_CONTROL_POINTS {
            return Err(PhotoError::field(
                "curves",
                format!("{total} control points in all (at most {MAX_CONTROL_POINTS})"),
            ));
        }
        let mut names = std::collections::HashSet::new();
        for (i, c) in self.curves.iter().enumerate() {
            let field = format!("curves[{i}] ({})", c.name);
            if c.name.trim().is_empty() {
                return Err(PhotoError::field(format!("curves[{i}].name"), "empty"));
            }
            if !names.insert(c.name.as_str()) {
                return Err(PhotoError::field(
                    format!("curves[{i}].name"),
                    format!("`{}` is used twice", c.name),
                ));
            }
            let n = c.control_points.len();
            if n < 4 || (n - 1) % 3 != 0 {
                return Err(PhotoError::field(
                    format!("{field}.control_points"),
                    format!("{n} points; a piecewise cubic Bézier has 3k + 1 (4, 7, 10, …)"),
                ));
            }
            for (k, &p) in c.control_points.iter().enumerate() {
                check_point(format!("{field}.control_points[{k}]"), p)?;
            }
            let first = c.control_points[0];
            let last = c.control_points[n - 1];
            let gap = (first[0] - last[0]).hypot(first[1] - last[1]);
            if c.closed && gap > 1e-9 * d {
                return Err(PhotoError::field(
                    format!("{field}.closed"),
                    format!(
                        "a closed curve must end where it starts (ends are {} px apart)",
                        short_number(gap)
                    ),
                ));
            }
            if c.closed && n == 4 {
                return Err(PhotoError::field(
                    format!("{field}.control_points"),
                    "a closed curve needs at least two cubic segments",
                ));
            }
        }
        let known = |name: &str| names.contains(name);
        for (i, [a, b]) in self.symmetric_curves.iter().enumerate() {
            for name in [a, b] {
                if !known(name) {
                    return Err(PhotoError::field(
                        format!("symmetric_curves[{i}]"),
                        format!("no curve `{name}`"),
                    ));
                }
            }
            if a == b {
                return Err(PhotoError::field(
                    format!("symmetric_curves[{i}]"),
                    format!("`{a}` paired with itself: list it in self_symmetric_curves"),
                ));
            }
        }
        for (i, name) in self.self_symmetric_curves.iter().enumerate() {
            if !known(name) {
                return Err(PhotoError::field(
                    format!("self_symmetric_curves[{i}]"),
                    format!("no curve `{name}`"),
                ));
            }
        }
        for (i, &p) in self.occlusions.iter().enumerate() {
            check_point(format!("occlusions[{i}]"), p)?;
        }
        for (i, &p) in self.openings.iter().enumerate() {
            check_point(format!("openings[{i}]"), p)?;
        }
        for (k, seg) in self.symmetry.frame.iter().enumerate() {
            for (e, &p) in seg.iter().enumerate() {
                check_point(format!("symmetry.frame[{k}][{e}]"), p)?;
            }
        }
        for (e, &p) in self.symmetry.points.iter().enumerate() {
            check_point(format!("symmetry.points[{e}]"), p)?;
        }
        self.validate_camera(d)?;
        check_point("true_size.from".into(), self.true_size.from)?;
        check_point("true_size.to".into(), self.true_size.to)?;
        let t = &self.true_size;
        // (A length of 1e-320 scaled the whole model to subnormal numbers, whose faces
        // then had no area.)
        if !(t.length.is_finite() && t.length >= 1e-6 && t.length < 1e9) {
            return Err(PhotoError::field(
                "true_size.length",
                format!(
                    "must be a length from 1e-6 to below 1e9 (got {})",
                    refused_number(t.length, &[1e-6, 1e9])
                ),
            ));
        }
        if (t.from[0] - t.to[0]).hypot(t.from[1] - t.to[1]) < 1.0 {
            return Err(PhotoError::field(
                "true_size",
                "`from` and `to` are less than a pixel apart: the distance fixes no scale",
            ));
        }
        let a = &self.analysis;
        let positive_length = |field: &str, v: Option<f64>, lo: f64, hi: f64| -> Result<(), PhotoError> {
            match v {
                Some(x) if !(x.is_finite() && x >= lo && x <= hi) => {
                    // The bound crossed and the value in the digits that tell them apart.
                    let ([got, lo_text], [_, hi_text]) = if x < lo {
                        (numbers_apart(x, lo), numbers_apart(x, hi))
                    } else {
                        let [got, hi_text] = numbers_apart(x, hi);
                        ([got, short_number(lo).to_string()], [String::new(), hi_text])
                    };
                    Err(PhotoError::field(
                        format!("analysis.{field}"),
                        format!("must be within {lo_text} … {hi_text} px for this image (got {got})"),
                    ))
                }
                _ => Ok(()),
            }
        };
        positive_length("snap_distance_px", a.snap_distance_px, 0.0, d / 20.0)?;
        // At most ~100 000 samples along the curves and rulings no finer than them.
        positive_length("sample_spacing_px", a.sample_spacing_px, d / 2_000.0, d / 10.0)?;
        positive_length("ruling_spacing_px", a.ruling_spacing_px, d / 2_000.0, d / 3.0)?;
        let lengths = self.lengths();
        if lengths.ruling < lengths.sample {
            let [ruling, sample] = numbers_apart(lengths.ruling, lengths.sample);
            return Err(PhotoError::field(
                "analysis.ruling_spacing_px",
                format!("{ruling} px is finer than the sample spacing {sample} px"),
            ));
        }
        if !(a.dtw_smoothness_weight.is_finite() && (0.0..=1e3).contains(&a.dtw_smoothness_weight)) {
            return Err(PhotoError::field(
                "analysis.dtw_smoothness_weight",
                format!(
                    "must be within 0 … 1000, got {}",
                    refused_number(a.dtw_smoothness_weight, &[0.0, 1e3])
                ),
            ));
        }
        let wts = &a.weights;
        for (name, v) in [
            ("projection", wts.projection),
            ("minimal_variation", wts.minimal_variation),
            ("collinearity", wts.collinearity),
            ("foreshortening", wts.foreshortening),
            ("symmetry", wts.symmetry),
            ("developability", wts.developability),
        ] {
            if !(v.is_finite() && (0.0..=1e6).contains(&v)) {
                return Err(PhotoError::field(
                    format!("analysis.weights.{name}"),
                    format!("must be within 0 … 1e6, got {}", refused_number(v, &[0.0, 1e6])),
                ));
            }
        }
        if wts.projection <= 0.0 {
            return Err(PhotoError::field(
                "analysis.weights.projection",
                "must be positive: without it nothing ties the model to the drawing",
            ));
        }
        Ok(())
    }
}

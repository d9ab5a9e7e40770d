use sheetform_geometry::GeometryError;
use thiserror::Error;

/// Why a bend model could not be built or meshed.
///
/// Input problems name the scene field; shape problems name the region and the place.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum BendError {
    /// A scene field is missing, malformed or out of range.
    #[error("scene field `{field}`: {message}")]
    Field {
        /// JSON path of the field (e.g. `regions[1].curve.control_points[3]`).
        field: String,
        /// What is wrong with it.
        message: String,
    },
    /// A geometric object in the scene is invalid.
    #[error("scene field `{field}`: {source}")]
    Geometry {
        /// JSON path of the field.
        field: String,
        /// The geometric problem.
        source: GeometryError,
    },
    /// The control curve's length differs from its flat geodesic segment's.
    #[error(
        "region {region} (`{name}`): the control curve is {} long but its flat geodesic \
         segment is {} long (relative difference {relative:.2e} > tolerance {tolerance:.1e}); \
         bending cannot stretch the sheet. Fix the curve, move `flat_end`, or give `flat_direction` instead \
         of `flat_end` to take the length from the curve",
        sheetform_geometry::refused_number(*.curve_length, &[*.flat_length]),
        sheetform_geometry::refused_number(*.flat_length, &[*.curve_length])
    )]
    LengthMismatch {
        /// Region index.
        region: usize,
        /// Region name.
        name: String,
        /// Arc length of the 3D curve.
        curve_length: f64,
        /// Length of the flat segment.
        flat_length: f64,
        /// Relative difference.
        relative: f64,
        /// Allowed relative difference.
        tolerance: f64,
    },
    /// The flat geodesic segment leaves the sheet (crosses the outline or a hole): told in
    /// the user's terms, the curve's length against the sheet ahead of its start.
    #[error(
        "region {region} (`{name}`): the curve is {} long, but its flat segment leaves the sheet {} from its \
         start, near ({}, {}): shorten the curve by {} or more, or move the segment's start or turn its \
         direction so that the curve's length of sheet lies ahead of it",
        sheetform_geometry::short_number(*.curve_length),
        sheetform_geometry::short_number(*.on_sheet_length),
        sheetform_geometry::short_number(*.x),
        sheetform_geometry::short_number(*.y),
        sheetform_geometry::short_number(*.curve_length - *.on_sheet_length)
    )]
    GeodesicLeavesSheet {
        /// Region index.
        region: usize,
        /// Region name.
        name: String,
        /// Length of the control curve (= of its flat segment).
        curve_length: f64,
        /// Length of the flat segment from its start to where it leaves the sheet.
        on_sheet_length: f64,
        /// Flat x where it leaves.
        x: f64,
        /// Flat y where it leaves.
        y: f64,
    },
    /// The control curve cannot define a developable (straight everywhere, cusp, …).
    #[error("region {region} (`{name}`): {reason}")]
    DegenerateCurve {
        /// Region index.
        region: usize,
        /// Region name.
        name: String,
        /// What is wrong, with the parameter range.
        reason: String,
    },
    /// The shape is not admissible: the curve of regression enters the sheet, or rulings
    /// cross inside it (Bo & Wang 2007, Eq. 6 and §4.3).
    #[error("inadmissible shape: {}", .0.message)]
    Inadmissible(Box<InadmissibleDetail>),
    /// Pieces of a composite sheet cannot be placed consistently.
    #[error("composite sheet: {message}")]
    Composite {
        /// What is inconsistent, and where.
        message: String,
    },
    /// The edit asked for cannot be done.
    #[error("edit: {message}")]
    Edit {
        /// What is wrong with the edit.
        message: String,
    },
}

/// Where a shape stops being admissible.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct InadmissibleDetail {
    /// Human-readable summary.
    pub message: String,
    /// Region whose rulings are at fault.
    pub region: usize,
    /// Arc-length range along the control curve where the test fails.
    pub arc_length_range: [f64; 2],
    /// Flat-sheet point where the curve of regression (or the crossing) enters the sheet.
    pub flat_point: [f64; 2],
    /// The same point on the bent sheet (on the ruling), if defined.
    pub point: Option<[f64; 3]>,
}

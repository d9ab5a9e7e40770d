use sheetform_geometry::short_number;
use thiserror::Error;

/// Why a pattern file could not be made.
#[derive(Debug, Error)]
pub enum PatternError {
    /// The DXF writer failed.
    #[error("writing DXF: {0}")]
    Dxf(String),
    /// An option is out of range.
    #[error("pattern option `{option}`: {message}")]
    Option {
        /// Which option.
        option: &'static str,
        /// What is wrong.
        message: String,
    },
    /// A piece does not fit on the sheet in any orientation.
    #[error(
        "piece `{piece}` measures {} × {} mm (smallest bounding rectangle) and does not fit on the {} × {} mm sheet with its {} mm margin",
        short_number(*.width_mm),
        short_number(*.height_mm),
        short_number(*.sheet_width_mm),
        short_number(*.sheet_height_mm),
        short_number(*.gap_mm)
    )]
    PieceTooLarge {
        /// The piece's name.
        piece: String,
        /// Its width (mm).
        width_mm: f64,
        /// Its height (mm).
        height_mm: f64,
        /// Sheet width (mm).
        sheet_width_mm: f64,
        /// Sheet height (mm).
        sheet_height_mm: f64,
        /// Gap kept around and between pieces (mm).
        gap_mm: f64,
    },
    /// Folds close a loop of flat panels around a point: with a thickness, the panels
    /// cannot all keep their bend allowances.
    #[error(
        "piece `{piece}`: the folds near ({}, {}) mm on the pattern close a loop of flat panels (round an inner vertex, or strips between two rigid panels), whose bend allowances do not add up, so a sheet with thickness cannot be cut flat for them; cut the model open there (a seam) or leave out the thickness",
        short_number(*.x_mm),
        short_number(*.y_mm)
    )]
    BendLoop {
        /// The piece's name.
        piece: String,
        /// Where on the pattern (mm).
        x_mm: f64,
        /// See `x_mm`.
        y_mm: f64,
    },
}

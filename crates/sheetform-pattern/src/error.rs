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
        "piece `{piece}` measures {width_mm:.1} × {height_mm:.1} mm (smallest bounding rectangle) and does not fit on the {sheet_width_mm:.1} × {sheet_height_mm:.1} mm sheet with its {gap_mm:.1} mm margin"
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
}

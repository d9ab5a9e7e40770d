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
}

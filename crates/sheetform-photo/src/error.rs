use thiserror::Error;

/// Why a photo annotation could not be reconstructed.
///
/// Input problems name the annotation field (a JSON path such as `curves[2]`) or the
/// curve by its name.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum PhotoError {
    /// An annotation field is missing, malformed or out of range.
    #[error("annotation field `{field}`: {message}")]
    Field {
        /// JSON path of the field (with the curve's name where there is one).
        field: String,
        /// What is wrong with it.
        message: String,
    },
    /// A traced curve cannot be used (zero length, self-intersecting, closes no cycle).
    #[error("curve `{curve}`: {message}")]
    Curve {
        /// The curve's name.
        curve: String,
        /// What is wrong with it.
        message: String,
    },
    /// The curves close no surface patch at all.
    #[error("the curves close no surface patch: {0}")]
    NoPatch(String),
    /// A surface patch the curves close cannot be meshed or unfolded.
    #[error("patch `{patch}`: {message}")]
    Patch {
        /// The patch, as the outputs name it (`patch-03`, or its number in the curve
        /// network).
        patch: String,
        /// What is wrong, and what to change in the drawing.
        message: String,
    },
    /// A linear solve failed (should not happen for a valid annotation).
    #[error("solver: {0}")]
    Solver(String),
}

impl PhotoError {
    /// A [`PhotoError::Field`].
    pub fn field(field: impl Into<String>, message: impl Into<String>) -> Self {
        Self::Field {
            field: field.into(),
            message: message.into(),
        }
    }

    /// A [`PhotoError::Curve`].
    pub fn curve(curve: impl Into<String>, message: impl Into<String>) -> Self {
        Self::Curve {
            curve: curve.into(),
            message: message.into(),
        }
    }
}

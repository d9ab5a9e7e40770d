use thiserror::Error;

/// Why a slit-sheet design could not be built or solved.
///
/// Input problems name the scene field (a JSON path such as `anchors[2].ridge`).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SlitError {
    /// A scene field is missing, malformed or out of range.
    #[error("scene field `{field}`: {message}")]
    Field {
        /// JSON path of the field.
        field: String,
        /// What is wrong with it.
        message: String,
    },
    /// The scanned point cloud cannot be read.
    #[error("point cloud {path}: {message}")]
    PointCloud {
        /// The file.
        path: String,
        /// What is wrong.
        message: String,
    },
    /// No mould can be made from the shape.
    #[error("mould: {0}")]
    Mould(String),
    /// The solve was stopped from outside (Ctrl-C, an abandoned editor request).
    #[error("cancelled")]
    Cancelled,
}

impl SlitError {
    /// A [`SlitError::Field`].
    pub fn field(field: impl Into<String>, message: impl Into<String>) -> Self {
        Self::Field {
            field: field.into(),
            message: message.into(),
        }
    }
}

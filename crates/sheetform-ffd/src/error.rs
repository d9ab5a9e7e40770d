use thiserror::Error;

/// Why a free-form deformation could not be set up or solved.
///
/// Input problems name the scene field (a JSON path such as `lattice.knots[1]`) or the
/// mesh element.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FfdError {
    /// A scene field is missing, malformed or out of range.
    #[error("scene field `{field}`: {message}")]
    Field {
        /// JSON path of the field.
        field: String,
        /// What is wrong with it.
        message: String,
    },
    /// A mesh vertex lies outside the deformation volume.
    #[error(
        "vertex {vertex} at ({}, {}, {}) is outside the lattice volume (closest point {} away); enlarge the lattice or give a margin",
        sheetform_geometry::short_number(*.x),
        sheetform_geometry::short_number(*.y),
        sheetform_geometry::short_number(*.z),
        sheetform_geometry::short_number(*.distance)
    )]
    OutsideVolume {
        /// Vertex index in the input mesh.
        vertex: usize,
        /// Its coordinates.
        x: f64,
        /// Its coordinates.
        y: f64,
        /// Its coordinates.
        z: f64,
        /// Distance to the nearest point found in the volume.
        distance: f64,
    },
    /// A panel (mesh patch) cannot be used.
    #[error("panel `{panel}`: {message}")]
    Panel {
        /// Panel (OBJ group) name.
        panel: String,
        /// What is wrong with it.
        message: String,
    },
    /// The linear algebra failed.
    #[error("solver: {0}")]
    Solver(String),
    /// The run was cancelled (the problem's cancel flag).
    #[error("cancelled")]
    Cancelled,
}

impl FfdError {
    /// A [`FfdError::Field`].
    pub fn field(field: impl Into<String>, message: impl Into<String>) -> Self {
        Self::Field {
            field: field.into(),
            message: message.into(),
        }
    }
}

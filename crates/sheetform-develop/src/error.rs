//! Why a target cannot be developed.

use thiserror::Error;

/// Why [`crate::develop_pieces`] cannot make a target's pieces developable.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum DevelopError {
    /// The mesh is not a clean 2-manifold (or has no faces).
    #[error("the target mesh cannot be developed as it is: {problem}")]
    Topology {
        /// What is wrong, with the first place.
        problem: String,
    },
    /// A seam polyline's segment is not an edge of the mesh.
    #[error("seam segment {index} (vertices {a} and {b}, 1-based as in the file) is not an edge of the mesh: seams must run along mesh edges")]
    SeamOffMesh {
        /// The segment's index among the seam edges (1-based).
        index: usize,
        /// Its first vertex (1-based).
        a: u32,
        /// Its second vertex (1-based).
        b: u32,
    },
    /// An option out of its range.
    #[error("develop option `{option}`: {message}")]
    Option {
        /// The option.
        option: &'static str,
        /// What is wrong.
        message: String,
    },
    /// The linear system of a step is too large, or its factorisation failed.
    #[error("the developability solve failed: {message}")]
    Solver {
        /// What failed, in the user's terms.
        message: String,
    },
    /// Stopped from outside (Ctrl-C, an abandoned editor request).
    #[error("cancelled")]
    Cancelled,
}

use thiserror::Error;

/// Why a mesh cannot be flattened.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FlattenError {
    /// The mesh is not a clean 2-manifold.
    #[error("the mesh cannot be flattened as it is: {problem}")]
    Topology {
        /// What is wrong (non-manifold edges, degenerate faces, non-orientable, …).
        problem: String,
    },
    /// The mesh is not a topological disk (one piece, one boundary loop, no handles).
    #[error(
        "exact unfolding needs a disk-like piece (one connected piece with one boundary loop and no handles); this mesh has {components} piece(s), {boundary_loops} boundary loop(s) and Euler characteristic {euler} — cut it into charts first"
    )]
    NotADisk {
        /// Connected components.
        components: usize,
        /// Boundary loops.
        boundary_loops: usize,
        /// Euler characteristic.
        euler: i64,
    },
    /// The sparse solver failed.
    #[error("the layout solver failed: {message}")]
    Solver {
        /// The solver's message.
        message: String,
    },
    /// Stopped from outside (Ctrl-C, an abandoned editor request).
    #[error("cancelled")]
    Cancelled,
}

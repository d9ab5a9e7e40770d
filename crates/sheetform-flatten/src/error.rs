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
    /// The layout could not be computed (its linear system has no unique solution).
    #[error("{message}")]
    Solver {
        /// Why, in the mesh's terms where they are known (a needle-thin triangle), else
        /// the solver's.
        message: String,
    },
    /// The pattern would have more pieces than a pattern may have, or the mesh has more
    /// faces than a net is made of: refused before the work is done.
    #[error(
        "{what} ({count}, more than the {bound} a pattern may have): the mesh is likely noisy or too finely faceted for this; {advice}"
    )]
    TooManyPieces {
        /// What is counted.
        what: String,
        /// How many.
        count: usize,
        /// The bound.
        bound: usize,
        /// What the user can do.
        advice: String,
    },
    /// Stopped from outside (Ctrl-C, an abandoned editor request).
    #[error("cancelled")]
    Cancelled,
}

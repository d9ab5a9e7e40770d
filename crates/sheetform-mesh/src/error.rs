use thiserror::Error;

/// An inconsistent [`crate::SheetMesh`].
#[derive(Debug, Clone, PartialEq, Error)]
pub enum MeshError {
    /// The per-vertex or per-face arrays have different lengths.
    #[error("{what}: expected {expected} entries, found {found}")]
    LengthMismatch {
        /// Which array.
        what: &'static str,
        /// Expected count.
        expected: usize,
        /// Actual count.
        found: usize,
    },
    /// A face refers to a vertex that does not exist.
    #[error("face {face} refers to vertex {vertex}, but there are only {vertex_count} vertices")]
    IndexOutOfRange {
        /// Face index.
        face: usize,
        /// Offending vertex index.
        vertex: u32,
        /// Number of vertices.
        vertex_count: usize,
    },
    /// A face has a repeated vertex.
    #[error("face {face} repeats a vertex")]
    DegenerateFace {
        /// Face index.
        face: usize,
    },
    /// A coordinate is not finite.
    #[error("vertex {vertex} has a non-finite {which} coordinate")]
    NonFinite {
        /// Vertex index.
        vertex: usize,
        /// "3D" or "flat".
        which: &'static str,
    },
    /// A face label refers to a piece that does not exist.
    #[error("face {face} is labelled with piece {piece}, but there are only {piece_count} pieces")]
    PieceOutOfRange {
        /// Face index.
        face: usize,
        /// Offending piece index.
        piece: u32,
        /// Number of pieces.
        piece_count: usize,
    },
    /// A mesh that a mirror plane cannot cut in half.
    #[error("cannot mirror the mesh: {problem}")]
    Mirror {
        /// What is wrong.
        problem: String,
    },
}

use std::path::PathBuf;
use thiserror::Error;

/// A file could not be read or written.
#[derive(Debug, Error)]
pub enum IoError {
    /// The operating system refused.
    #[error("{path}: {source}")]
    Os {
        /// The file.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
}

//! Reading a scene file (JSON scene, photo annotation or drawing): the same bound and the
//! same errors for every front end that takes a path.

use super::error::PipelineError;
use std::path::{Path, PathBuf};

/// The text of the scene file at `path`, at most [`sheetform_io::MAX_SCENE_FILE_BYTES`].
///
/// # Errors
/// [`PipelineError::Read`] naming the file: missing, unreadable, too large, not UTF-8.
pub fn read_scene_file(path: &Path) -> Result<String, PipelineError> {
    let bytes =
        sheetform_io::read_bounded(path, sheetform_io::MAX_SCENE_FILE_BYTES).map_err(|source| PipelineError::Read {
            path: path.display().to_string(),
            source,
        })?;
    String::from_utf8(bytes).map_err(|_| PipelineError::Read {
        path: path.display().to_string(),
        source: std::io::Error::new(std::io::ErrorKind::InvalidData, "not UTF-8 text"),
    })
}

/// The directory a scene file's assets are read from: its own (`.` for a bare name).
pub fn scene_directory(path: &Path) -> PathBuf {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

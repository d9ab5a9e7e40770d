use crate::IoError;
use std::io::Write;
use std::path::Path;

/// Writes `bytes` to `path` atomically: into a temporary file in the same directory
/// (created exclusively under an unpredictable name, so no other process's file or
/// symbolic link is followed), flushed to disk, then renamed over `path`. Either the old
/// file or the complete new one is there afterwards, never a partial one.
///
/// # Errors
/// Any OS error, naming the path.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), IoError> {
    let os = |source| IoError::Os {
        path: path.to_path_buf(),
        source,
    };
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut file = tempfile::Builder::new()
        .prefix(&format!(".{name}."))
        .suffix(".tmp")
        .tempfile_in(dir)
        .map_err(os)?;
    file.write_all(bytes).map_err(os)?;
    file.as_file().sync_all().map_err(os)?;
    // On failure the temporary file is removed when dropped.
    file.persist(path).map_err(|e| os(e.error))?;
    Ok(())
}

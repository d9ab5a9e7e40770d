//! Reading an input file within a size bound: regular files only.

use std::io::{self, Read};
use std::path::Path;

/// Most bytes of a mesh file (`check`, `flatten`, an FFD model): 1 GiB, about 15 million
/// triangles as OBJ text.
pub const MAX_MESH_FILE_BYTES: u64 = 1 << 30;

/// Most bytes of a scene or annotation file (JSON): 64 MiB.
pub const MAX_SCENE_FILE_BYTES: u64 = 64 << 20;

/// The bytes of the file at `path`, refused (an [`io::ErrorKind::InvalidInput`] error
/// saying why) unless it is a regular file of at most `max_bytes`: a FIFO would block
/// the read forever and `/dev/zero` never ends, a directory is not an input.
///
/// # Errors
/// Not a regular file, too large (also when it grew past the bound while read), or the
/// operating system's error.
pub fn read_bounded(path: &Path, max_bytes: u64) -> io::Result<Vec<u8>> {
    // `metadata` does not open the file, so a FIFO is refused before it can block.
    let metadata = std::fs::metadata(path)?;
    if !metadata.is_file() {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            if metadata.is_dir() {
                "a directory, not a file"
            } else {
                "not a regular file (a device, a pipe or a socket)"
            },
        ));
    }
    let too_large = || {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("larger than the {max_bytes} bytes an input file may have"),
        )
    };
    if metadata.len() > max_bytes {
        return Err(too_large());
    }
    let mut bytes = Vec::with_capacity(metadata.len() as usize);
    std::fs::File::open(path)?.take(max_bytes + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > max_bytes {
        return Err(too_large());
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_regular_files_within_the_bound_are_read() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("a.obj");
        std::fs::write(&file, b"v 0 0 0\n").unwrap();
        assert_eq!(read_bounded(&file, 100).unwrap(), b"v 0 0 0\n");
        let error = read_bounded(&file, 4).unwrap_err();
        assert!(error.to_string().contains("larger than the 4 bytes"), "{error}");
        let error = read_bounded(dir.path(), 100).unwrap_err();
        assert!(error.to_string().contains("a directory"), "{error}");
        #[cfg(unix)]
        {
            let error = read_bounded(Path::new("/dev/zero"), 100).unwrap_err();
            assert!(error.to_string().contains("not a regular file"), "{error}");
            let fifo = dir.path().join("fifo.obj");
            let made = std::process::Command::new("mkfifo").arg(&fifo).status();
            if made.is_ok_and(|s| s.success()) {
                let error = read_bounded(&fifo, 100).unwrap_err();
                assert!(error.to_string().contains("not a regular file"), "{error}");
            }
        }
    }
}

//! Replacing the set of files a run writes into a directory, as one unit.

use crate::IoError;
use std::collections::HashSet;
use std::path::{Component, Path, PathBuf};

/// Replaces the output set in `dir` (created if missing) with `files` — `(path relative
/// to dir, bytes)` — as one unit.
///
/// `previous` names the files of the previous set (from its manifest); they are removed
/// unless this set writes them again. Everything else in `dir` (files a user put there)
/// is kept.
///
/// On Linux the new set is built in a fresh sibling directory (created exclusively
/// under an unpredictable name: `.NAME.sheetform-PID-XXXXXX`), the user's files are
/// hard-linked into it, and it is exchanged with `dir` in one `renameat2(RENAME_EXCHANGE)`
/// call; the old set is then deleted. At every instant `dir` holds either the complete
/// previous set or the complete new one: a write that fails (a full disk, a file size
/// limit) or a process killed before the exchange leaves the previous set exactly as it
/// was. A sibling left by a killed process is removed by the next call for the same
/// directory once that process is gone.
///
/// Where that cannot be done (another platform, a parent directory that is not
/// writable, a file system without the exchange or without hard links, `dir` a mount
/// point) the files are staged inside `dir` and renamed into place one by one: a failed
/// write still leaves the previous set untouched, but a kill during the renames leaves a
/// mixed set.
///
/// # Errors
/// A write or rename the operating system refuses, naming the path.
pub fn replace_file_set(dir: &Path, files: &[(&str, &[u8])], previous: &[String]) -> Result<(), IoError> {
    let os = |path: &Path| {
        let path = path.to_path_buf();
        move |source| IoError::Os { path, source }
    };
    for (name, _) in files {
        if !is_plain_relative(name) {
            return Err(IoError::Os {
                path: dir.join(name),
                source: std::io::Error::new(std::io::ErrorKind::InvalidInput, "not a plain relative path"),
            });
        }
    }
    std::fs::create_dir_all(dir).map_err(os(dir))?;
    #[cfg(target_os = "linux")]
    if exchange::replace(dir, files, previous)? {
        return Ok(());
    }
    replace_in_place(dir, files, previous)
}

/// True for a non-empty path made of normal components only (no `..`, no `.`, no root):
/// a path that stays inside whatever directory it is joined to.
pub fn is_plain_relative(name: &str) -> bool {
    !name.is_empty() && Path::new(name).components().all(|c| matches!(c, Component::Normal(_)))
}

/// Writes `files` into `root` (which exists), creating sub-directories.
fn write_all_into(root: &Path, dir: &Path, files: &[(&str, &[u8])]) -> Result<(), IoError> {
    for (name, bytes) in files {
        let path = root.join(name);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).map_err(|source| IoError::Os {
                path: dir.join(name),
                source,
            })?;
        }
        std::fs::write(&path, bytes).map_err(|source| IoError::Os {
            path: dir.join(name),
            source,
        })?;
    }
    Ok(())
}

/// The fallback: stage inside `dir`, rename file by file, remove the stale files.
fn replace_in_place(dir: &Path, files: &[(&str, &[u8])], previous: &[String]) -> Result<(), IoError> {
    let os = |path: &Path| {
        let path = path.to_path_buf();
        move |source| IoError::Os { path, source }
    };
    let staging = tempfile::Builder::new()
        .prefix(".sheetform-staging-")
        .tempdir_in(dir)
        .map_err(os(dir))?;
    write_all_into(staging.path(), dir, files)?;
    for (name, _) in files {
        let path = dir.join(name);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).map_err(os(parent))?;
        }
        std::fs::rename(staging.path().join(name), &path).map_err(os(&path))?;
    }
    let written: HashSet<&str> = files.iter().map(|(n, _)| *n).collect();
    for stale in previous
        .iter()
        .filter(|n| is_plain_relative(n) && !written.contains(n.as_str()))
    {
        let path = dir.join(stale);
        match std::fs::remove_file(&path) {
            Ok(()) => {
                // Sub-directories of outputs (frames/, sheets/) go when left empty.
                if let Some(parent) = path.parent().filter(|p| *p != dir) {
                    let _ = std::fs::remove_dir(parent);
                }
            }
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => return Err(os(&path)(e)),
        }
    }
    Ok(())
}

/// Every path below `root` (relative, directories before their contents), without
/// following symbolic links.
fn relative_tree(root: &Path) -> std::io::Result<Vec<(PathBuf, bool)>> {
    let mut entries = Vec::new();
    let mut pending = vec![PathBuf::new()];
    while let Some(relative) = pending.pop() {
        for entry in std::fs::read_dir(root.join(&relative))? {
            let entry = entry?;
            let path = relative.join(entry.file_name());
            let is_dir = entry.file_type()?.is_dir();
            if is_dir {
                pending.push(path.clone());
            }
            entries.push((path, is_dir));
        }
    }
    Ok(entries)
}

#[cfg(target_os = "linux")]
mod exchange {
    use super::*;

    /// The exchange path of [`replace_file_set`]: `Ok(false)` when it cannot be taken
    /// here (nothing changed in `dir`), `Err` when a write of the new set failed.
    pub(super) fn replace(dir: &Path, files: &[(&str, &[u8])], previous: &[String]) -> Result<bool, IoError> {
        let Ok(real) = dir.canonicalize() else {
            return Ok(false);
        };
        let (Some(parent), Some(name)) = (real.parent(), real.file_name()) else {
            return Ok(false);
        };
        let prefix = format!(".{}.sheetform-", name.to_string_lossy());
        remove_abandoned(parent, &prefix);
        let Ok(staging) = tempfile::Builder::new()
            .prefix(&format!("{prefix}{}-", std::process::id()))
            .tempdir_in(parent)
        else {
            return Ok(false);
        };
        write_all_into(staging.path(), dir, files)?;
        // Carry over everything that is neither written now nor a stale output.
        let written: HashSet<&Path> = files.iter().map(|(n, _)| Path::new(*n)).collect();
        let stale: HashSet<&Path> = previous.iter().map(Path::new).collect();
        let Ok(tree) = relative_tree(&real) else {
            return Ok(false);
        };
        for (relative, is_dir) in tree {
            if written.contains(relative.as_path()) || stale.contains(relative.as_path()) {
                continue;
            }
            let target = staging.path().join(&relative);
            let carried = if is_dir {
                std::fs::create_dir_all(&target)
            } else {
                std::fs::hard_link(real.join(&relative), &target)
            };
            match carried {
                Ok(()) => {}
                // A user's file where this set writes a directory: the set wins.
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
                Err(_) => return Ok(false),
            }
        }
        // Remove directories the stale outputs leave empty (frames/, sheets/), but not
        // an empty directory the user made.
        let mut emptied: Vec<&Path> = previous
            .iter()
            .filter_map(|n| Path::new(n).parent())
            .filter(|p| !p.as_os_str().is_empty())
            .collect();
        emptied.sort_by_key(|p| std::cmp::Reverse(p.components().count()));
        for relative in emptied {
            let _ = std::fs::remove_dir(staging.path().join(relative));
        }
        if let Ok(metadata) = std::fs::metadata(&real) {
            let _ = std::fs::set_permissions(staging.path(), metadata.permissions());
        }
        let exchanged = rustix::fs::renameat_with(
            rustix::fs::CWD,
            staging.path(),
            rustix::fs::CWD,
            &real,
            rustix::fs::RenameFlags::EXCHANGE,
        );
        // Either way the staging path now holds what is to be deleted: the new set when
        // the exchange failed, the previous set when it succeeded.
        drop(staging);
        Ok(exchanged.is_ok())
    }

    /// Removes siblings `PREFIX<pid>-*` whose process no longer runs (left by a killed
    /// run).
    fn remove_abandoned(parent: &Path, prefix: &str) {
        let Ok(entries) = std::fs::read_dir(parent) else {
            return;
        };
        for entry in entries.flatten() {
            let file_name = entry.file_name();
            let Some(rest) = file_name.to_str().and_then(|n| n.strip_prefix(prefix)) else {
                continue;
            };
            let Some(pid) = rest.split('-').next().and_then(|p| p.parse::<u32>().ok()) else {
                continue;
            };
            let running = pid == std::process::id() || Path::new("/proc").join(pid.to_string()).exists();
            if !running && entry.file_type().is_ok_and(|t| t.is_dir()) {
                let _ = std::fs::remove_dir_all(entry.path());
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tree(dir: &Path) -> Vec<(String, Vec<u8>)> {
        let mut files: Vec<(String, Vec<u8>)> = relative_tree(dir)
            .unwrap()
            .into_iter()
            .filter(|(_, is_dir)| !is_dir)
            .map(|(p, _)| (p.to_string_lossy().into_owned(), std::fs::read(dir.join(&p)).unwrap()))
            .collect();
        files.sort();
        files
    }

    fn siblings(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(dir.parent().unwrap())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn a_new_set_replaces_the_listed_files_and_keeps_the_users() {
        let root = tempfile::tempdir().unwrap();
        let dir = root.path().join("out");
        replace_file_set(
            &dir,
            &[("a.txt", b"1"), ("frames/f1", b"f1"), ("frames/f2", b"f2")],
            &[],
        )
        .unwrap();
        std::fs::write(dir.join("mine.txt"), "mine").unwrap();
        std::fs::create_dir(dir.join("empty")).unwrap();
        let previous: Vec<String> = ["a.txt", "frames/f1", "frames/f2"].map(String::from).to_vec();
        replace_file_set(&dir, &[("a.txt", b"2"), ("b.txt", b"3")], &previous).unwrap();
        assert_eq!(
            tree(&dir),
            vec![
                ("a.txt".into(), b"2".to_vec()),
                ("b.txt".into(), b"3".to_vec()),
                ("mine.txt".into(), b"mine".to_vec())
            ]
        );
        assert!(dir.join("empty").is_dir(), "the user's empty directory went");
        assert!(!dir.join("frames").exists(), "the emptied frames/ stayed");
        assert_eq!(siblings(&dir), vec!["out".to_string()]);
    }

    #[test]
    fn paths_outside_the_directory_are_refused() {
        let root = tempfile::tempdir().unwrap();
        let dir = root.path().join("out");
        for name in ["../x", "/tmp/x", ""] {
            assert!(replace_file_set(&dir, &[(name, b"1")], &[]).is_err(), "{name}");
        }
        assert!(!root.path().join("x").exists());
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn a_staging_directory_of_a_dead_process_is_removed() {
        let root = tempfile::tempdir().unwrap();
        let dir = root.path().join("out");
        // Process ids are below 2^22 on Linux: this one cannot be running.
        let abandoned = root.path().join(".out.sheetform-4294967295-abcdef");
        std::fs::create_dir_all(abandoned.join("frames")).unwrap();
        let alive = root
            .path()
            .join(format!(".out.sheetform-{}-abcdef", std::process::id()));
        std::fs::create_dir(&alive).unwrap();
        replace_file_set(&dir, &[("a.txt", b"1")], &[]).unwrap();
        assert!(!abandoned.exists());
        assert!(alive.exists(), "a running process's staging directory was removed");
    }
}

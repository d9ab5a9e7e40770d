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
    refuse_read_only(dir)?;
    std::fs::create_dir_all(dir).map_err(os(dir))?;
    #[cfg(target_os = "linux")]
    if exchange::replace(dir, files, previous)? {
        return Ok(());
    }
    replace_in_place(dir, files, previous)
}

/// Refuses an existing `dir` that is read-only (no write bit in its mode, or not
/// writable by this process): a user who made it read-only does not want it replaced.
fn refuse_read_only(dir: &Path) -> Result<(), IoError> {
    let Ok(metadata) = std::fs::metadata(dir) else {
        return Ok(());
    };
    if !metadata.is_dir() {
        return Ok(());
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = metadata.permissions().mode() & 0o7777;
        let writable = mode & 0o222 != 0 && rustix::fs::access(dir, rustix::fs::Access::WRITE_OK).is_ok();
        if !writable {
            return Err(IoError::Os {
                path: dir.to_path_buf(),
                source: std::io::Error::new(
                    std::io::ErrorKind::PermissionDenied,
                    format!(
                        "the output directory is read-only (mode {mode:o}): nothing was written; \
                         make it writable (chmod u+w) or choose another output directory"
                    ),
                ),
            });
        }
    }
    #[cfg(not(unix))]
    if metadata.permissions().readonly() {
        return Err(IoError::Os {
            path: dir.to_path_buf(),
            source: std::io::Error::new(
                std::io::ErrorKind::PermissionDenied,
                "the output directory is read-only: nothing was written",
            ),
        });
    }
    Ok(())
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
/// following symbolic links; directories come with their metadata, read before they
/// are listed (listing one updates its access time).
fn relative_tree(root: &Path) -> std::io::Result<Vec<(PathBuf, Option<std::fs::Metadata>)>> {
    let mut entries = Vec::new();
    let mut pending = vec![PathBuf::new()];
    while let Some(relative) = pending.pop() {
        for entry in std::fs::read_dir(root.join(&relative))? {
            let entry = entry?;
            let path = relative.join(entry.file_name());
            let metadata = entry.metadata()?;
            if metadata.is_dir() {
                pending.push(path.clone());
                entries.push((path, Some(metadata)));
            } else {
                entries.push((path, None));
            }
        }
    }
    Ok(entries)
}

#[cfg(target_os = "linux")]
mod exchange {
    use super::*;
    use std::os::unix::fs::{MetadataExt, PermissionsExt};

    /// The exchange path of [`replace_file_set`]: `Ok(false)` when it cannot be taken
    /// here (nothing changed in `dir`), `Err` when a write of the new set failed.
    ///
    /// The new directory replaces `dir`'s inode, so everything carried over must look
    /// as before: files are hard links (the same inodes); carried directories get their
    /// owner, mode (with setgid and sticky bits) and, when nothing inside them changed,
    /// their access and modification times back. What cannot be carried (extended
    /// attributes or ACLs on `dir` or a directory in it, an owner this process cannot
    /// give, a process whose working directory is inside `dir`, which would be left in
    /// a deleted directory) sends the call to the in-place path.
    pub(super) fn replace(dir: &Path, files: &[(&str, &[u8])], previous: &[String]) -> Result<bool, IoError> {
        let Ok(real) = dir.canonicalize() else {
            return Ok(false);
        };
        let (Some(parent), Some(name)) = (real.parent(), real.file_name()) else {
            return Ok(false);
        };
        let Ok(dir_metadata) = std::fs::metadata(&real) else {
            return Ok(false);
        };
        if has_extended_attributes(&real) || is_a_working_directory(&real) {
            return Ok(false);
        }
        let prefix = format!(".{}.sheetform-", name.to_string_lossy());
        remove_abandoned(parent, &prefix);
        let Ok(staging) = tempfile::Builder::new()
            .prefix(&format!("{prefix}{}-", std::process::id()))
            .tempdir_in(parent)
        else {
            return Ok(false);
        };
        let staging = Staging(Some(staging.keep()));
        let staged = staging.path();
        if !give_owner(staged, &dir_metadata) {
            return Ok(false);
        }
        write_all_into(staged, dir, files)?;
        // Carry over everything that is neither written now nor a stale output.
        let written: HashSet<&Path> = files.iter().map(|(n, _)| Path::new(*n)).collect();
        let stale: HashSet<&Path> = previous.iter().map(Path::new).collect();
        let Ok(tree) = relative_tree(&real) else {
            return Ok(false);
        };
        // Listing a directory updated its access time: a call that gives up after this
        // point (for the in-place path, which does not read the user's directories)
        // sets those back.
        let listed: Vec<(PathBuf, std::fs::Metadata)> = tree
            .iter()
            .filter_map(|(relative, directory)| Some((real.join(relative), directory.clone()?)))
            .collect();
        let give_up = || {
            for (path, metadata) in &listed {
                set_times(path, metadata);
            }
            Ok(false)
        };
        let mut carried_directories = Vec::new();
        for (relative, directory) in tree {
            if written.contains(relative.as_path()) || stale.contains(relative.as_path()) {
                continue;
            }
            let target = staged.join(&relative);
            let carried = if directory.is_some() {
                std::fs::create_dir_all(&target)
            } else {
                std::fs::hard_link(real.join(&relative), &target)
            };
            match carried {
                Ok(()) => {}
                // A user's file where this set writes a directory: the set wins.
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
                Err(_) => return give_up(),
            }
            if let Some(metadata) = directory {
                let original = real.join(&relative);
                if has_extended_attributes(&original) || !give_owner(&target, &metadata) {
                    return give_up();
                }
                carried_directories.push((relative, metadata));
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
            let _ = std::fs::remove_dir(staged.join(relative));
        }
        // Modes last but one (a read-only directory takes no more links), deepest
        // first; then the times of directories whose contents this run did not touch.
        carried_directories.sort_by_key(|(p, _)| std::cmp::Reverse(p.components().count()));
        let touched = |relative: &Path| {
            written
                .iter()
                .chain(stale.iter())
                .any(|output| output.starts_with(relative))
        };
        for (relative, metadata) in &carried_directories {
            let target = staged.join(relative);
            if !target.is_dir() {
                continue;
            }
            if std::fs::set_permissions(&target, metadata.permissions()).is_err() {
                return give_up();
            }
            if !touched(relative) {
                set_times(&target, metadata);
            }
        }
        if std::fs::set_permissions(staged, dir_metadata.permissions()).is_err() {
            return give_up();
        }
        let exchanged = rustix::fs::renameat_with(
            rustix::fs::CWD,
            staged,
            rustix::fs::CWD,
            &real,
            rustix::fs::RenameFlags::EXCHANGE,
        );
        // Either way the staging path now holds what is to be deleted: the new set when
        // the exchange failed, the previous set when it succeeded (dropping `staging`
        // removes it).
        if exchanged.is_err() {
            return give_up();
        }
        Ok(true)
    }

    /// Sets the access and modification times of `path` (not following a symbolic
    /// link) to those in `metadata`.
    fn set_times(path: &Path, metadata: &std::fs::Metadata) {
        let timestamps = rustix::fs::Timestamps {
            last_access: rustix::fs::Timespec {
                tv_sec: metadata.atime(),
                tv_nsec: metadata.atime_nsec() as _,
            },
            last_modification: rustix::fs::Timespec {
                tv_sec: metadata.mtime(),
                tv_nsec: metadata.mtime_nsec() as _,
            },
        };
        let _ = rustix::fs::utimensat(
            rustix::fs::CWD,
            path,
            &timestamps,
            rustix::fs::AtFlags::SYMLINK_NOFOLLOW,
        );
    }

    /// A staging directory, removed with everything in it (read-only directories
    /// included) when dropped.
    struct Staging(Option<PathBuf>);

    impl Staging {
        fn path(&self) -> &Path {
            self.0.as_deref().expect("a staging path until dropped")
        }
    }

    impl Drop for Staging {
        fn drop(&mut self) {
            if let Some(path) = self.0.take() {
                remove_tree(&path);
            }
        }
    }

    /// Removes `path` and everything below it, first giving its owner write and search
    /// permission on each directory (a read-only directory would keep its entries).
    fn remove_tree(path: &Path) {
        if let Ok(tree) = relative_tree(path) {
            for relative in std::iter::once(PathBuf::new()).chain(
                tree.into_iter()
                    .filter(|(_, directory)| directory.is_some())
                    .map(|(relative, _)| relative),
            ) {
                let directory = path.join(relative);
                if let Ok(metadata) = std::fs::symlink_metadata(&directory) {
                    let mode = metadata.permissions().mode();
                    if mode & 0o700 != 0o700 {
                        let _ = std::fs::set_permissions(&directory, std::fs::Permissions::from_mode(mode | 0o700));
                    }
                }
            }
        }
        let _ = std::fs::remove_dir_all(path);
    }

    /// Gives `path` (made by this process) the owner and group of `original`; false
    /// when this process may not.
    fn give_owner(path: &Path, original: &std::fs::Metadata) -> bool {
        let Ok(metadata) = std::fs::symlink_metadata(path) else {
            return false;
        };
        if metadata.uid() == original.uid() && metadata.gid() == original.gid() {
            return true;
        }
        // SAFETY of the raw ids: they come from the file system's own metadata.
        let owner = rustix::fs::Uid::from_raw(original.uid());
        let group = rustix::fs::Gid::from_raw(original.gid());
        rustix::fs::chown(path, Some(owner), Some(group)).is_ok()
    }

    /// True when `path` carries extended attributes (ACLs, SELinux labels, a user's
    /// tags), which a directory made anew would not have.
    fn has_extended_attributes(path: &Path) -> bool {
        let mut names = [0u8; 256];
        match rustix::fs::llistxattr(path, &mut names[..]) {
            Ok(length) => length > 0,
            // More names than the buffer holds.
            Err(rustix::io::Errno::RANGE) => true,
            Err(_) => false,
        }
    }

    /// True when this process, its parent (the shell that ran `-o .`) or any other
    /// process this user can see has its working directory at or below `real`.
    fn is_a_working_directory(real: &Path) -> bool {
        if std::env::current_dir().is_ok_and(|cwd| cwd.starts_with(real)) {
            return true;
        }
        let Ok(processes) = std::fs::read_dir("/proc") else {
            return false;
        };
        processes.flatten().any(|entry| {
            entry
                .file_name()
                .to_str()
                .is_some_and(|n| n.bytes().all(|b| b.is_ascii_digit()))
                && std::fs::read_link(entry.path().join("cwd")).is_ok_and(|cwd| cwd.starts_with(real))
        })
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
                remove_tree(&entry.path());
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
            .filter(|(_, directory)| directory.is_none())
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
    /// Issue 35: everything sheetform did not write keeps what it had: a user's
    /// directories their mode (setgid and sticky bits too), owner, times and extended
    /// attributes, whichever path the replacement takes.
    #[cfg(target_os = "linux")]
    #[test]
    fn a_users_directories_keep_their_mode_owner_times_and_attributes() {
        // Without extended attributes the set is exchanged, with them written in place.
        for tag in [false, true] {
            users_directories_are_kept(tag);
        }
    }

    #[cfg(target_os = "linux")]
    fn users_directories_are_kept(tag: bool) {
        use std::os::unix::fs::{MetadataExt, PermissionsExt};
        let root = tempfile::tempdir().unwrap();
        let dir = root.path().join("out");
        replace_file_set(&dir, &[("a.txt", b"1")], &[]).unwrap();
        let mine = dir.join("mine/deeper");
        std::fs::create_dir_all(&mine).unwrap();
        std::fs::write(mine.join("notes.txt"), "notes").unwrap();
        std::fs::set_permissions(dir.join("mine"), std::fs::Permissions::from_mode(0o3750)).unwrap();
        std::fs::set_permissions(&mine, std::fs::Permissions::from_mode(0o555)).unwrap();
        // A chown works only for root; an owner change is checked where it could happen.
        let chowned = rustix::fs::chown(
            dir.join("mine"),
            Some(rustix::fs::Uid::from_raw(4321)),
            Some(rustix::fs::Gid::from_raw(4321)),
        )
        .is_ok();
        let tagged =
            tag && rustix::fs::setxattr(&mine, "user.sheetform-test", b"kept", rustix::fs::XattrFlags::empty()).is_ok();
        let old = rustix::fs::Timestamps {
            last_access: rustix::fs::Timespec {
                tv_sec: 1_000_000_000,
                tv_nsec: 5,
            },
            last_modification: rustix::fs::Timespec {
                tv_sec: 1_100_000_000,
                tv_nsec: 7,
            },
        };
        for path in [dir.join("mine"), mine.clone()] {
            rustix::fs::utimensat(rustix::fs::CWD, &path, &old, rustix::fs::AtFlags::empty()).unwrap();
        }
        let before: Vec<std::fs::Metadata> = [dir.join("mine"), mine.clone()]
            .iter()
            .map(|p| std::fs::metadata(p).unwrap())
            .collect();
        let inode = std::fs::metadata(&dir).unwrap().ino();
        replace_file_set(&dir, &[("a.txt", b"2")], &["a.txt".to_string()]).unwrap();
        // (Where the file system has the exchange, it is taken without attributes.)
        let _exchanged = std::fs::metadata(&dir).unwrap().ino() != inode;
        for (path, before) in [dir.join("mine"), mine.clone()].iter().zip(&before) {
            let after = std::fs::metadata(path).unwrap();
            assert_eq!(
                after.permissions().mode() & 0o7777,
                before.permissions().mode() & 0o7777,
                "{path:?}"
            );
            assert_eq!((after.uid(), after.gid()), (before.uid(), before.gid()), "{path:?}");
            assert_eq!((after.mtime(), after.mtime_nsec()), (1_100_000_000, 7), "{path:?}");
            assert_eq!((after.atime(), after.atime_nsec()), (1_000_000_000, 5), "{path:?}");
        }
        if chowned {
            assert_eq!(std::fs::metadata(dir.join("mine")).unwrap().uid(), 4321);
        }
        if tagged {
            let mut value = [0u8; 16];
            let length = rustix::fs::getxattr(&mine, "user.sheetform-test", &mut value[..]).unwrap();
            assert_eq!(&value[..length], b"kept");
        }
        assert_eq!(std::fs::read_to_string(mine.join("notes.txt")).unwrap(), "notes");
        assert_eq!(std::fs::read(dir.join("a.txt")).unwrap(), b"2");
        assert_eq!(siblings(&dir), vec!["out".to_string()]);
        std::fs::set_permissions(&mine, std::fs::Permissions::from_mode(0o755)).unwrap();
    }

    /// Issue 35: a read-only output directory is refused naming it, nothing in it
    /// changes and no copy is left beside it.
    #[cfg(unix)]
    #[test]
    fn a_read_only_output_directory_is_refused() {
        use std::os::unix::fs::PermissionsExt;
        let root = tempfile::tempdir().unwrap();
        let dir = root.path().join("out");
        replace_file_set(&dir, &[("a.txt", b"1")], &[]).unwrap();
        std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o555)).unwrap();
        let error = replace_file_set(&dir, &[("a.txt", b"2")], &["a.txt".to_string()]).unwrap_err();
        let message = error.to_string();
        assert!(message.contains("out") && message.contains("read-only"), "{message}");
        std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o755)).unwrap();
        assert_eq!(tree(&dir), vec![("a.txt".into(), b"1".to_vec())]);
        assert_eq!(siblings(&dir), vec!["out".to_string()]);
    }

    /// Issue 35: `-o .` from a shell: a process whose working directory is inside the
    /// output directory keeps a live directory (the set is written in place, the
    /// directory's inode stays).
    #[cfg(target_os = "linux")]
    #[test]
    fn a_working_directory_inside_the_output_stays_live() {
        use std::os::unix::fs::MetadataExt;
        let root = tempfile::tempdir().unwrap();
        let dir = root.path().join("out");
        replace_file_set(&dir, &[("a.txt", b"1")], &[]).unwrap();
        std::fs::create_dir(dir.join("sub")).unwrap();
        let inode = std::fs::metadata(&dir).unwrap().ino();
        let mut shell = std::process::Command::new("sleep")
            .arg("30")
            .current_dir(dir.join("sub"))
            .spawn()
            .unwrap();
        let result = replace_file_set(&dir, &[("a.txt", b"2")], &["a.txt".to_string()]);
        let cwd = std::fs::read_link(format!("/proc/{}/cwd", shell.id())).unwrap();
        let _ = shell.kill();
        let _ = shell.wait();
        result.unwrap();
        assert_eq!(
            std::fs::metadata(&dir).unwrap().ino(),
            inode,
            "the directory was replaced"
        );
        assert!(!cwd.to_string_lossy().ends_with("(deleted)"), "{cwd:?}");
        assert_eq!(std::fs::read(dir.join("a.txt")).unwrap(), b"2");
    }
}

//! What a run may touch besides its typed scene: the files the scene names (confined to a
//! root), progress reporting, cancellation and which outputs to render. Every front end
//! builds one: the CLI from the scene file's directory, the web server from its project
//! directory, the Python binding from its caller.

use super::error::PipelineError;
use std::io::Read;
use std::path::{Component, Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

/// Largest file a scene may make a run read (1 GiB): a texture, a scan, a mesh.
pub const MAX_ASSET_BYTES: u64 = 1 << 30;

/// The files a scene may read: paths relative to a root directory, inside it.
///
/// A scene names its assets (a bend texture, a slit scan, an FFD mesh, a photo) by paths
/// relative to its own file. The resolver refuses absolute paths, paths that leave the
/// root (also through a symbolic link), anything but a regular file (a FIFO or a device
/// would block or never end) and files over its size bound, each with an error naming
/// the scene field. Only when the user widens it explicitly
/// ([`Self::with_confinement`], the CLI's `--assets-within DIR`) may a scene name
/// absolute paths and paths that leave its directory, and then only inside that
/// directory.
#[derive(Debug, Clone)]
pub struct AssetResolver {
    root: PathBuf,
    confinement: Option<PathBuf>,
    max_bytes: u64,
}

impl AssetResolver {
    /// Files under `root` (usually the scene file's directory), at most
    /// [`MAX_ASSET_BYTES`] each.
    pub fn new(root: impl Into<PathBuf>) -> Self {
        Self {
            root: root.into(),
            confinement: None,
            max_bytes: MAX_ASSET_BYTES,
        }
    }

    /// The same, letting a scene also name absolute paths and paths that leave `root`,
    /// as long as they lie inside `confinement` (an explicit choice of the user).
    pub fn with_confinement(mut self, confinement: impl Into<PathBuf>) -> Self {
        self.confinement = Some(confinement.into());
        self
    }

    /// The same with another size bound (bytes).
    pub fn with_max_bytes(mut self, max_bytes: u64) -> Self {
        self.max_bytes = max_bytes;
        self
    }

    /// The root directory.
    pub fn root(&self) -> &Path {
        &self.root
    }

    /// The file a scene's `field` names by `relative`, checked to lie inside the root.
    ///
    /// # Errors
    /// [`PipelineError::Asset`] for an empty, absolute or escaping path, a missing file
    /// or one that is not a regular file.
    pub fn resolve(&self, relative: &str, field: &str) -> Result<PathBuf, PipelineError> {
        let fail = |message: String| PipelineError::Asset {
            field: field.to_string(),
            path: relative.to_string(),
            message,
        };
        let path = Path::new(relative);
        if relative.is_empty() {
            return Err(fail("the path is empty".into()));
        }
        let absolute = path.is_absolute()
            || path
                .components()
                .any(|c| matches!(c, Component::Prefix(_) | Component::RootDir));
        if absolute && self.confinement.is_none() {
            return Err(fail(
                "an absolute path; assets are named relative to the scene file (or allow a directory with \
                 --assets-within)"
                    .into(),
            ));
        }
        let root = self
            .root
            .canonicalize()
            .map_err(|e| fail(format!("the scene's directory {}: {e}", self.root.display())))?;
        let full = root
            .join(path)
            .canonicalize()
            .map_err(|e| fail(format!("cannot open it: {e}")))?;
        match &self.confinement {
            None if !full.starts_with(&root) => {
                return Err(fail(format!(
                    "it lies outside the scene's directory {} (assets must be inside it, or in a directory \
                     allowed with --assets-within)",
                    root.display()
                )));
            }
            Some(confinement) => {
                let allowed = confinement
                    .canonicalize()
                    .map_err(|e| fail(format!("the allowed directory {}: {e}", confinement.display())))?;
                if !full.starts_with(&allowed) {
                    return Err(fail(format!(
                        "it lies outside the allowed directory {}",
                        allowed.display()
                    )));
                }
            }
            None => {}
        }
        let metadata = std::fs::metadata(&full).map_err(|e| fail(format!("cannot open it: {e}")))?;
        if !metadata.is_file() {
            return Err(fail("not a regular file".into()));
        }
        if metadata.len() > self.max_bytes {
            return Err(fail(format!(
                "{} bytes, more than the {} bytes a scene may read",
                metadata.len(),
                self.max_bytes
            )));
        }
        Ok(full)
    }

    /// Where a front end may write the file a user names by `relative` (the editor's
    /// save): plain names only (no `..`, not absolute), in an existing directory inside
    /// the root (also through symbolic links), and not an existing file of another kind
    /// than a regular one.
    ///
    /// # Errors
    /// [`PipelineError::Asset`] naming `field` for any of those.
    pub fn resolve_for_writing(&self, relative: &str, field: &str) -> Result<PathBuf, PipelineError> {
        let fail = |message: String| PipelineError::Asset {
            field: field.to_string(),
            path: relative.to_string(),
            message,
        };
        let path = Path::new(relative);
        if !sheetform_io::is_plain_relative(relative) {
            return Err(fail("not a plain relative path inside the served directory".into()));
        }
        let root = self
            .root
            .canonicalize()
            .map_err(|e| fail(format!("the directory {}: {e}", self.root.display())))?;
        let parent = root
            .join(path.parent().unwrap_or(Path::new("")))
            .canonicalize()
            .map_err(|e| fail(format!("its directory: {e}")))?;
        if !parent.starts_with(&root) {
            return Err(fail("it lies outside the served directory".into()));
        }
        let full = parent.join(path.file_name().expect("a normal last component"));
        match std::fs::symlink_metadata(&full) {
            Ok(m) if !m.is_file() => Err(fail("exists and is not a regular file".into())),
            _ => Ok(full),
        }
    }

    /// The bytes of the file a scene's `field` names (see [`Self::resolve`]).
    ///
    /// # Errors
    /// As [`Self::resolve`], and read errors; a file that grew past the bound while read.
    pub fn read(&self, relative: &str, field: &str) -> Result<Vec<u8>, PipelineError> {
        let full = self.resolve(relative, field)?;
        let fail = |message: String| PipelineError::Asset {
            field: field.to_string(),
            path: relative.to_string(),
            message,
        };
        let file = std::fs::File::open(&full).map_err(|e| fail(format!("cannot open it: {e}")))?;
        let mut bytes = Vec::new();
        file.take(self.max_bytes + 1)
            .read_to_end(&mut bytes)
            .map_err(|e| fail(format!("cannot read it: {e}")))?;
        if bytes.len() as u64 > self.max_bytes {
            return Err(fail(format!("more than the {} bytes a scene may read", self.max_bytes)));
        }
        Ok(bytes)
    }
}

/// Which outputs a run renders.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum OutputSet {
    /// Every file the command writes.
    #[default]
    All,
    /// What a live preview shows: the model (GLB), the pattern (SVG) and the report; no
    /// OBJ, STL, DXF, PDF, frames or colour maps.
    Preview,
}

/// The context of one run: assets, progress, cancellation, outputs.
pub struct RunContext<'a> {
    /// The files the scene may read.
    pub assets: AssetResolver,
    /// Called as the run advances with a stage name and the fraction done (0–1).
    pub progress: &'a dyn Fn(&str, f64),
    /// Set from another thread to stop the run at its next stage
    /// ([`PipelineError::Cancelled`]).
    pub cancel: Option<&'a AtomicBool>,
    /// Which outputs to render.
    pub outputs: OutputSet,
}

impl std::fmt::Debug for RunContext<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RunContext")
            .field("assets", &self.assets)
            .field("cancel", &self.cancel.map(|c| c.load(Ordering::Relaxed)))
            .field("outputs", &self.outputs)
            .finish_non_exhaustive()
    }
}

/// A progress callback that ignores every report.
pub fn no_progress(_stage: &str, _fraction: f64) {}

impl<'a> RunContext<'a> {
    /// Assets under `root`, no progress, no cancellation, every output.
    pub fn new(root: impl Into<PathBuf>) -> Self {
        Self {
            assets: AssetResolver::new(root),
            progress: &no_progress,
            cancel: None,
            outputs: OutputSet::All,
        }
    }

    /// The same with a progress callback.
    pub fn with_progress(mut self, progress: &'a dyn Fn(&str, f64)) -> Self {
        self.progress = progress;
        self
    }

    /// The same with a cancellation flag.
    pub fn with_cancel(mut self, cancel: &'a AtomicBool) -> Self {
        self.cancel = Some(cancel);
        self
    }

    /// The same rendering only `outputs`.
    pub fn with_outputs(mut self, outputs: OutputSet) -> Self {
        self.outputs = outputs;
        self
    }

    /// Reports progress.
    pub fn progress(&self, stage: &str, fraction: f64) {
        (self.progress)(stage, fraction);
    }

    /// Stops the run if it was cancelled.
    ///
    /// # Errors
    /// [`PipelineError::Cancelled`] once the flag is set.
    pub fn check_cancelled(&self) -> Result<(), PipelineError> {
        match self.cancel {
            Some(flag) if flag.load(Ordering::Relaxed) => Err(PipelineError::Cancelled),
            _ => Ok(()),
        }
    }

    /// Whether every output is rendered (not a preview).
    pub fn renders_all(&self) -> bool {
        self.outputs == OutputSet::All
    }
}

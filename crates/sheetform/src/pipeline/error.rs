//! Why a pipeline stopped ([`PipelineError`] and its [`ErrorKind`]) and how a finished run
//! ended ([`Outcome`]): decided here, so that every front end (the CLI's exit codes, the
//! web server's responses, the Python binding's exceptions) tells the same story.

use sheetform_bend::BendError;
use sheetform_ffd::FfdError;
use sheetform_flatten::FlattenError;
use sheetform_io::IoError;
use sheetform_io::MeshReadError;
use sheetform_pattern::PatternError;
use sheetform_photo::PhotoError;
use sheetform_slit::SlitError;

use thiserror::Error;

/// Why a pipeline stopped.
#[derive(Debug, Error)]
pub enum PipelineError {
    /// The input file could not be read.
    #[error("cannot read {path}: {source}")]
    Read {
        /// The file.
        path: String,
        /// The OS error.
        source: std::io::Error,
    },
    /// The bend model is invalid or cannot be built.
    #[error(transparent)]
    Bend(#[from] BendError),
    /// The shape cannot be made (system A: the curve of regression enters the sheet):
    /// nothing is meshed, and the report says where.
    #[error("{error}")]
    Inadmissible {
        /// What failed, and where (the bend error).
        error: BendError,
        /// The report of the refused shape (status `inadmissible`, with where it fails).
        report: Box<crate::report::Report>,
    },
    /// Writing the outputs failed.
    #[error(transparent)]
    Io(#[from] IoError),
    /// A mesh file cannot be read.
    #[error(transparent)]
    MeshRead(#[from] MeshReadError),
    /// A mesh cannot be flattened.
    #[error(transparent)]
    Flatten(#[from] FlattenError),
    /// The target cannot be developed (`develop`).
    #[error(transparent)]
    Develop(#[from] sheetform_develop::DevelopError),
    /// The result to be written is not a valid mesh (a non-finite coordinate, an index
    /// out of range): the run stops before any file is rendered, so no NaN reaches a file.
    #[error("the result cannot be written: {0}")]
    InvalidResult(sheetform_mesh::MeshError),
    /// A command-line option is out of range.
    #[error("option `{option}`: {message}")]
    Option {
        /// The option.
        option: &'static str,
        /// What is wrong.
        message: String,
    },
    /// An array handed over by a binding is not a mesh (a shape, a non-finite coordinate,
    /// an index out of range; [`super::mesh_from_arrays`]).
    #[error("{array}: {message}")]
    InvalidArray {
        /// The array, by its argument's name (`vertices`, `faces`, `uv`, …).
        array: &'static str,
        /// What is wrong, naming the row.
        message: String,
    },
    /// The slit-sheet model is invalid or cannot be built.
    #[error(transparent)]
    Slit(#[from] SlitError),
    /// The FFD scene is invalid or the restoration failed.
    #[error(transparent)]
    Ffd(#[from] FfdError),
    /// The pattern files cannot be made.
    #[error(transparent)]
    Pattern(#[from] PatternError),
    /// The photo annotation is invalid or cannot be reconstructed.
    #[error(transparent)]
    Photo(#[from] PhotoError),
    /// An image the scene names (a bend scene's texture, a photo annotation's photograph)
    /// is not a PNG or JPEG that decodes to its end.
    #[error("{field}: `{path}`: {what} cannot be used: {problem}")]
    Image {
        /// The scene field that names it (`texture`, `image.path`).
        field: &'static str,
        /// The path as written in the scene.
        path: String,
        /// What the image is, in the command's terms (`the texture`, `the photo`).
        what: &'static str,
        /// What is wrong with it.
        problem: sheetform_io::ImageError,
    },
    /// A file the scene names cannot be read: outside the scene's directory, not a
    /// regular file, too large or missing.
    #[error("{field}: `{path}`: {message}")]
    Asset {
        /// The scene field that names it.
        field: String,
        /// The path as written in the scene.
        path: String,
        /// What is wrong.
        message: String,
    },
    /// The run was cancelled ([`super::RunContext::cancel`]).
    #[error("cancelled")]
    Cancelled,
    /// The output directory cannot be used.
    #[error("output directory {path}: {message}")]
    OutputDirectory {
        /// The directory.
        path: String,
        /// What is wrong.
        message: String,
    },
}

/// What kind of failure a [`PipelineError`] is: the CLI's exit code, a binding's
/// exception class.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// The input is malformed, out of range or unreadable (a scene, mesh, annotation,
    /// option or the file itself); the message names the field or place.
    InvalidInput,
    /// The input is valid but describes a shape that cannot be made; the error carries
    /// the report saying where.
    Inadmissible,
    /// A solver or a construction failed on valid input.
    Failed,
    /// The outputs cannot be written.
    Output,
    /// The run was cancelled.
    Cancelled,
}

impl ErrorKind {
    /// The process exit code of a run that stopped with this kind of error: 3 for an
    /// inadmissible shape, 130 when cancelled (as after Ctrl-C), 1 otherwise.
    pub fn exit_code(self) -> u8 {
        match self {
            Self::Inadmissible => 3,
            Self::Cancelled => 130,
            Self::InvalidInput | Self::Failed | Self::Output => 1,
        }
    }
}

impl PipelineError {
    /// What kind of failure this is.
    pub fn kind(&self) -> ErrorKind {
        match self {
            Self::Inadmissible { .. } => ErrorKind::Inadmissible,
            Self::Cancelled => ErrorKind::Cancelled,
            Self::Io(_) | Self::OutputDirectory { .. } => ErrorKind::Output,
            // A mesh that is not a clean manifold, or not a disk where one is needed, is
            // the input's problem; a layout solver that fails is ours.
            Self::Flatten(
                sheetform_flatten::FlattenError::Topology { .. }
                | sheetform_flatten::FlattenError::NotADisk { .. }
                | sheetform_flatten::FlattenError::TooManyPieces { .. },
            ) => ErrorKind::InvalidInput,
            Self::Flatten(sheetform_flatten::FlattenError::Cancelled) => ErrorKind::Cancelled,
            Self::Develop(sheetform_develop::DevelopError::Cancelled) => ErrorKind::Cancelled,
            Self::Develop(sheetform_develop::DevelopError::Solver { .. }) => ErrorKind::Failed,
            Self::Develop(_) => ErrorKind::InvalidInput,
            Self::Flatten(_) | Self::InvalidResult(_) => ErrorKind::Failed,
            Self::Photo(PhotoError::Solver(_)) | Self::Ffd(FfdError::Solver(_)) => ErrorKind::Failed,
            Self::Ffd(FfdError::Cancelled) | Self::Slit(sheetform_slit::SlitError::Cancelled) => ErrorKind::Cancelled,
            Self::Read { .. }
            | Self::Bend(_)
            | Self::MeshRead(_)
            | Self::Option { .. }
            | Self::InvalidArray { .. }
            | Self::Slit(_)
            | Self::Ffd(_)
            | Self::Pattern(_)
            | Self::Photo(_)
            | Self::Image { .. }
            | Self::Asset { .. } => ErrorKind::InvalidInput,
        }
    }

    /// The report to write even though the run stopped (an inadmissible shape's).
    pub fn report(&self) -> Option<&crate::report::Report> {
        match self {
            Self::Inadmissible { report, .. } => Some(report),
            _ => None,
        }
    }
}

/// How a finished run ended. Every output was rendered; the report's `status` says the
/// same.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// Every bound the report states holds.
    Ok,
    /// The pattern overlaps itself: it cannot be cut from one sheet as it is.
    Overlapping,
    /// A bound the report states is missed (e.g. a photo model not developable to the
    /// refinement's bound, or with a depth the drawing does not fix).
    OutOfTolerance,
}

impl Outcome {
    /// The process exit code: 0, 4 for an overlapping pattern, 5 out of tolerance.
    pub fn exit_code(self) -> u8 {
        match self {
            Self::Ok => 0,
            Self::Overlapping => 4,
            Self::OutOfTolerance => 5,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A solver that fails on valid input is `Failed` (the binding's `NotConvergedError`,
    /// exit code 1), not the input's fault; a cancelled FFD restoration is `Cancelled`.
    #[test]
    fn solver_failures_are_failed_and_scene_errors_invalid_input() {
        assert_eq!(
            PipelineError::Ffd(FfdError::Solver("singular".into())).kind(),
            ErrorKind::Failed
        );
        assert_eq!(
            PipelineError::Photo(PhotoError::Solver("singular".into())).kind(),
            ErrorKind::Failed
        );
        assert_eq!(PipelineError::Ffd(FfdError::Cancelled).kind(), ErrorKind::Cancelled);
        assert_eq!(ErrorKind::Cancelled.exit_code(), 130);
        assert_eq!(
            PipelineError::Ffd(FfdError::Panel {
                panel: "p".into(),
                message: "m".into()
            })
            .kind(),
            ErrorKind::InvalidInput
        );
    }
}

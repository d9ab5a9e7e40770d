//! One Python exception class per [`ErrorKind`] of the library, so that a notebook can
//! tell a bad scene from a shape that cannot be made or a solver that did not converge;
//! the message is the library's, which names the field or place.

use crate::convert::json_to_python;
use pyo3::exceptions::{PyException, PyRuntimeError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sheetform::pipeline::{ErrorKind, PipelineError};

pyo3::create_exception!(
    _native,
    SheetformError,
    PyException,
    "Base class of every error sheetform raises."
);
pyo3::create_exception!(
    _native,
    InvalidInputError,
    SheetformError,
    "The input is malformed, out of range or unreadable (a scene, an array, an option, a file); the message names the field or place."
);
pyo3::create_exception!(
    _native,
    InadmissibleError,
    SheetformError,
    "The input is valid but the shape cannot be made (a bent sheet whose curve of regression enters it); `.report` says where."
);
pyo3::create_exception!(
    _native,
    NotConvergedError,
    SheetformError,
    "A solver or a construction failed on valid input."
);
pyo3::create_exception!(
    _native,
    OutputError,
    SheetformError,
    "The outputs cannot be written (the directory, the disk)."
);
pyo3::create_exception!(
    _native,
    CancelledError,
    SheetformError,
    "The run was cancelled (Ctrl-C, a notebook's interrupt)."
);

/// The Python exception for a pipeline error; an inadmissible shape's carries its report
/// as `.report` (a dict, the `report.json` the CLI writes).
pub(crate) fn python_error(py: Python<'_>, error: PipelineError) -> PyErr {
    let message = match &error {
        // The library names its options as the CLI spells them (`--weld`); here they are
        // keyword arguments (`weld`, `tab_width`).
        PipelineError::Option { option, message } => format!("{}: {message}", keyword_of(option)),
        PipelineError::Pattern(sheetform::pattern::PatternError::Option { option, message }) => format!(
            "pattern option {}: {}",
            keyword_of(option),
            message.replace(" (--sheet-gap)", "")
        ),
        other => other.to_string(),
    };
    let exception = match error.kind() {
        ErrorKind::InvalidInput => InvalidInputError::new_err(message),
        ErrorKind::Inadmissible => InadmissibleError::new_err(message),
        ErrorKind::Failed => NotConvergedError::new_err(message),
        ErrorKind::Output => OutputError::new_err(message),
        ErrorKind::Cancelled => CancelledError::new_err(message),
    };
    if let Some(report) = error.report() {
        let value = serde_json::to_value(report).expect("a report serialises");
        let attached = json_to_python(py, &value).and_then(|dict| exception.value(py).setattr("report", dict));
        if let Err(e) = attached {
            return e;
        }
    }
    exception
}

/// The keyword argument of a library option named as the CLI spells it.
fn keyword_of(option: &str) -> String {
    match option {
        // The pattern library's names for what `PatternOptions` calls as the CLI.
        "tab width" => "tab_width".into(),
        "tab angle" => "tab_angle".into(),
        "smooth_bend_degrees" => "smooth_folds".into(),
        "inner_radius_mm" => "bend_radius".into(),
        "seam_allowance_mm" => "seam_allowance".into(),
        "kerf_mm" => "kerf".into(),
        "thickness_mm" => "thickness".into(),
        "min_fold_angle_degrees" => "min_fold_angle".into(),
        other => other.trim_start_matches("--").replace('-', "_"),
    }
}

/// Refuses the keywords a function was given beyond its own (`given`, its `**renamed`):
/// a keyword it took before under another name (`renamed`: old name, new name, and what
/// the new one is when it is not simply the CLI's flag of that name) names the new one;
/// any other is Python's unexpected-keyword `TypeError`.
pub(crate) fn refuse_renamed_keywords(
    function: &str,
    given: Option<&Bound<'_, PyDict>>,
    renamed: &[(&str, &str, &str)],
) -> PyResult<()> {
    let Some((name, _)) = given.and_then(|given| given.iter().next()) else {
        return Ok(());
    };
    let name = name.to_string();
    Err(match renamed.iter().find(|(old, _, _)| *old == name) {
        Some((old, new, "")) => invalid_argument(
            old,
            format!("is now `{new}`, the name of the CLI's --{}", new.replace('_', "-")),
        ),
        Some((old, new, meaning)) => invalid_argument(old, format!("is now `{new}`, {meaning}")),
        None => {
            pyo3::exceptions::PyTypeError::new_err(format!("{function} got an unexpected keyword argument '{name}'"))
        }
    })
}

/// An invalid argument of a binding function (not a scene field), named.
pub(crate) fn invalid_argument(argument: &str, message: impl std::fmt::Display) -> PyErr {
    InvalidInputError::new_err(format!("{argument}: {message}"))
}

/// Runs `job` without the interpreter's lock; a panic in it (a bug) is raised as a
/// `RuntimeError` instead of unwinding into the interpreter.
pub(crate) fn detached<T: Send>(py: Python<'_>, job: impl FnOnce() -> T + Send) -> PyResult<T> {
    py.detach(|| std::panic::catch_unwind(std::panic::AssertUnwindSafe(job)))
        .map_err(internal_error)
}

/// A panic inside a run (a bug): raised as an error rather than ending the interpreter.
pub(crate) fn internal_error(payload: Box<dyn std::any::Any + Send>) -> PyErr {
    let what = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into());
    PyRuntimeError::new_err(format!("sheetform internal error (please report it): {what}"))
}

/// Registers the exception classes.
pub(crate) fn register(module: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = module.py();
    module.add("SheetformError", py.get_type::<SheetformError>())?;
    module.add("InvalidInputError", py.get_type::<InvalidInputError>())?;
    module.add("InadmissibleError", py.get_type::<InadmissibleError>())?;
    module.add("NotConvergedError", py.get_type::<NotConvergedError>())?;
    module.add("OutputError", py.get_type::<OutputError>())?;
    module.add("CancelledError", py.get_type::<CancelledError>())?;
    Ok(())
}

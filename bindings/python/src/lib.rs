//! sheetform for Python: every system and mesh function of the library's pipeline as a
//! function over numpy arrays and dicts (PyO3). The binding is thin: it converts
//! arguments, calls the same typed pipeline as the CLI and the web editor
//! (`sheetform::pipeline`), and converts the result; no pipeline step is written here.
//!
//! The Python package (`python/sheetform/`) re-exports this module (`sheetform._native`);
//! its type stubs are `python/sheetform/_native.pyi`.

mod bend_editor;
mod convert;
mod errors;
mod mesh_functions;
mod pattern_options;
mod run;
mod systems;

use pyo3::prelude::*;

// The same allocator as the CLI, so that a run costs the same from Python.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// The native module.
#[pymodule(name = "_native")]
fn native_module(module: &Bound<'_, PyModule>) -> PyResult<()> {
    module.add("__version__", env!("CARGO_PKG_VERSION"))?;
    module.add_function(wrap_pyfunction!(systems::bend, module)?)?;
    module.add_function(wrap_pyfunction!(systems::slit, module)?)?;
    module.add_function(wrap_pyfunction!(systems::ffd, module)?)?;
    module.add_function(wrap_pyfunction!(systems::photo, module)?)?;
    module.add_function(wrap_pyfunction!(mesh_functions::check, module)?)?;
    module.add_function(wrap_pyfunction!(mesh_functions::flatten, module)?)?;
    module.add_function(wrap_pyfunction!(mesh_functions::develop, module)?)?;
    module.add_function(wrap_pyfunction!(mesh_functions::pattern, module)?)?;
    module.add_class::<run::Run>()?;
    module.add_function(wrap_pyfunction!(run::_restore_run, module)?)?;
    module.add_function(wrap_pyfunction!(run::_restore_mesh, module)?)?;
    module.add_class::<run::Mesh>()?;
    module.add_class::<pattern_options::PatternOptions>()?;
    module.add_class::<bend_editor::BendEditor>()?;
    errors::register(module)?;
    Ok(())
}

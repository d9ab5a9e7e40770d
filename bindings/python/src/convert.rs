//! Values between Python and the library: numpy arrays in (checked by the library's
//! [`sheetform::pipeline::mesh_from_arrays`]) and out (one copy each, into an array numpy
//! owns), JSON values as Python dicts and lists, scenes as dicts or paths.

use crate::errors::invalid_argument;
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use sheetform::geometry::{Vec2, Vec3};
use std::path::PathBuf;

/// A JSON value as the Python value `json.loads` would give (numbers keep every bit).
pub(crate) fn json_to_python<'py>(py: Python<'py>, value: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    use serde_json::Value;
    Ok(match value {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => b.into_pyobject(py)?.to_owned().into_any(),
        Value::Number(n) => match (n.as_i64(), n.as_u64()) {
            (Some(i), _) => i.into_pyobject(py)?.into_any(),
            (None, Some(u)) => u.into_pyobject(py)?.into_any(),
            _ => n.as_f64().unwrap_or(f64::NAN).into_pyobject(py)?.into_any(),
        },
        Value::String(s) => s.into_pyobject(py)?.into_any(),
        Value::Array(items) => {
            let list = PyList::empty(py);
            for item in items {
                list.append(json_to_python(py, item)?)?;
            }
            list.into_any()
        }
        Value::Object(map) => {
            let dict = PyDict::new(py);
            for (key, item) in map {
                dict.set_item(key, json_to_python(py, item)?)?;
            }
            dict.into_any()
        }
    })
}

/// A serialisable value (a report, a scene) as a Python dict.
pub(crate) fn to_python<'py>(py: Python<'py>, value: &impl serde::Serialize) -> PyResult<Bound<'py, PyAny>> {
    let value = serde_json::to_value(value).expect("library values serialise");
    json_to_python(py, &value)
}

/// A scene given as a dict (or any JSON-like value; numpy numbers and arrays in it are
/// taken as the numbers and lists they hold), as its JSON (or SVG) text, or as the path of
/// its file: its text, the directory its assets are read from (`root`, else the file's directory, else
/// the current one) and the path to record in the report.
pub(crate) struct SceneArgument {
    pub(crate) text: String,
    pub(crate) root: PathBuf,
    pub(crate) input: Option<String>,
}

pub(crate) fn scene_argument(
    py: Python<'_>,
    scene: &Bound<'_, PyAny>,
    root: Option<PathBuf>,
) -> PyResult<SceneArgument> {
    // A string that opens like JSON or SVG is the scene's text, not a path.
    if let Ok(text) = scene.extract::<String>() {
        if matches!(text.trim_start().chars().next(), Some('{' | '<')) {
            return Ok(SceneArgument {
                text,
                root: root.unwrap_or_else(|| PathBuf::from(".")),
                input: None,
            });
        }
    }
    if let Ok(path) = scene.extract::<PathBuf>() {
        let text = sheetform::pipeline::read_scene_file(&path).map_err(|e| crate::errors::python_error(py, e))?;
        return Ok(SceneArgument {
            text,
            root: root.unwrap_or_else(|| sheetform::pipeline::scene_directory(&path)),
            input: Some(path.display().to_string()),
        });
    }
    let json = py.import("json")?;
    let kwargs = PyDict::new(py);
    kwargs.set_item("allow_nan", false)?;
    // numpy numbers and arrays in a scene are written as the numbers and lists they hold.
    kwargs.set_item(
        "default",
        py.eval(
            c"lambda value: value.tolist() if hasattr(value, 'tolist') else (_ for _ in ()).throw(TypeError(f'a {type(value).__name__} is not a JSON value'))",
            None,
            None,
        )?,
    )?;
    let text: String = json
        .call_method("dumps", (scene,), Some(&kwargs))
        .map_err(|e| invalid_argument("scene", format!("not a JSON scene (a dict) or a path: {e}")))?
        .extract()?;
    Ok(SceneArgument {
        text,
        root: root.unwrap_or_else(|| PathBuf::from(".")),
        input: None,
    })
}

/// An `(n, columns)` float array (anything `numpy.asarray` takes), C-contiguous float64:
/// no copy when it already is one.
pub(crate) fn float_rows<'py>(
    argument: &str,
    value: &Bound<'py, PyAny>,
    columns: usize,
) -> PyResult<PyReadonlyArray2<'py, f64>> {
    let py = value.py();
    let numpy = py.import("numpy")?;
    let kwargs = PyDict::new(py);
    kwargs.set_item("dtype", numpy.getattr("float64")?)?;
    let array = numpy
        .call_method("ascontiguousarray", (value,), Some(&kwargs))
        .map_err(|e| invalid_argument(argument, format!("not an array of numbers: {e}")))?;
    rows_of(argument, array, columns, "numbers")
}

/// Any integer array (any integer dtype) as a C-contiguous int64 array: no copy when it
/// already is one. Floats are refused rather than truncated, unsigned values past int64
/// rather than wrapped.
fn int64_array<'py>(argument: &str, value: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    let py = value.py();
    let numpy = py.import("numpy")?;
    let array = numpy
        .call_method1("asarray", (value,))
        .map_err(|e| invalid_argument(argument, format!("not an array of indices: {e}")))?;
    let kind: String = array.getattr("dtype")?.getattr("kind")?.extract()?;
    let is_empty = array.getattr("size")?.extract::<usize>()? == 0;
    if !(kind == "i" || kind == "u" || is_empty) {
        let dtype = array.getattr("dtype")?.str()?.to_string();
        return Err(invalid_argument(
            argument,
            format!("integer indices expected, got an array of {dtype}"),
        ));
    }
    if kind == "u" && !is_empty && array.call_method0("max")?.gt(i64::MAX)? {
        return Err(invalid_argument(
            argument,
            format!("an index over {} (the largest a mesh may have)", i64::MAX),
        ));
    }
    let kwargs = PyDict::new(py);
    kwargs.set_item("dtype", numpy.getattr("int64")?)?;
    numpy.call_method("ascontiguousarray", (array,), Some(&kwargs))
}

/// An `(m, columns)` integer array as C-contiguous int64 ([`int64_array`]).
pub(crate) fn index_rows<'py>(
    argument: &str,
    value: &Bound<'py, PyAny>,
    columns: usize,
) -> PyResult<PyReadonlyArray2<'py, i64>> {
    rows_of(argument, int64_array(argument, value)?, columns, "indices")
}

fn rows_of<'py, T: numpy::Element>(
    argument: &str,
    array: Bound<'py, PyAny>,
    columns: usize,
    what: &str,
) -> PyResult<PyReadonlyArray2<'py, T>> {
    let shape: Vec<usize> = array.getattr("shape")?.extract()?;
    // An empty list comes as shape (0,): no rows.
    let array = if shape == [0] {
        array.call_method1("reshape", ((0usize, columns),))?
    } else {
        array
    };
    let shape: Vec<usize> = array.getattr("shape")?.extract()?;
    if shape.len() != 2 || shape[1] != columns {
        return Err(invalid_argument(
            argument,
            format!("an (n, {columns}) array of {what} expected, got shape {shape:?}"),
        ));
    }
    let typed = array.cast_into::<PyArray2<T>>().map_err(PyErr::from)?;
    Ok(typed.readonly())
}

/// An `(m,)` integer array ([`int64_array`]), copied.
pub(crate) fn index_list(argument: &str, value: &Bound<'_, PyAny>) -> PyResult<Vec<i64>> {
    let array = int64_array(argument, value)?;
    let shape: Vec<usize> = array.getattr("shape")?.extract()?;
    if shape.len() != 1 {
        return Err(invalid_argument(
            argument,
            format!("a one-dimensional array of integers expected, got shape {shape:?}"),
        ));
    }
    let typed = array.cast_into::<PyArray1<i64>>().map_err(PyErr::from)?;
    let values = typed.readonly().as_slice()?.to_vec();
    Ok(values)
}

/// 3D points as an `(n, 3)` float64 array (one copy, then owned by numpy).
pub(crate) fn points3<'py>(py: Python<'py>, points: &[Vec3]) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let flat: Vec<f64> = points.iter().flat_map(|p| [p.x, p.y, p.z]).collect();
    PyArray1::from_vec(py, flat).reshape([points.len(), 3])
}

/// Flat points as an `(n, 2)` float64 array (one copy).
pub(crate) fn points2<'py>(py: Python<'py>, points: &[Vec2]) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let flat: Vec<f64> = points.iter().flat_map(|p| [p.x, p.y]).collect();
    PyArray1::from_vec(py, flat).reshape([points.len(), 2])
}

/// Triangles as an `(m, 3)` int64 array (one copy).
pub(crate) fn triangles<'py>(py: Python<'py>, triangles: &[[u32; 3]]) -> PyResult<Bound<'py, PyArray2<i64>>> {
    let flat: Vec<i64> = triangles.iter().flat_map(|t| t.map(i64::from)).collect();
    PyArray1::from_vec(py, flat).reshape([triangles.len(), 3])
}

/// Labels as an `(m,)` int64 array (one copy).
pub(crate) fn labels<'py>(py: Python<'py>, labels: &[u32]) -> Bound<'py, PyArray1<i64>> {
    PyArray1::from_vec(
        py,
        labels
            .iter()
            .map(|&l| if l == u32::MAX { -1 } else { i64::from(l) })
            .collect(),
    )
}

//! The printable pattern's options as a Python class, [`PatternOptions`]: every option
//! the CLI's pattern flags set (`--scale`, `--tabs`, `--sheet`, `--seam-allowance`,
//! `--kerf`, `--thickness`, …), under the CLI's names (`-` as `_`), with the same
//! defaults and units; the library checks their values.

use crate::errors::{invalid_argument, refuse_renamed_keywords};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use sheetform::pattern::{
    sheet_size_from_text, BendAllowance, DxfUnit, MaterialAllowance, MaterialSide, PageSize, SheetOptions, TabOptions,
    TabSides, DEFAULT_MAX_PAGES,
};
use sheetform::pipeline::PatternOutputOptions;

/// How the printable pattern (`pattern.svg`, `.dxf`, `.pdf`) is made, as the CLI's
/// pattern flags, under their names: pass one (or a dict of the same keywords) as
/// `pattern=` to any function.
///
/// `scale` (1 = true size); `page` (`"a4"`, `"letter"`: the tiled PDF's paper);
/// `pattern_units` (`"mm"`, `"cm"`, `"in"`: the DXF's); `min_fold_angle` (degrees:
/// smaller folds are not drawn); `seam_labels` (matching IDs on both sides of every seam;
/// the CLI's `--no-seam-labels`); `tabs` (`"auto"`: on one side of every seam of a net
/// made by `flatten`, none otherwise; `"none"`; `"one"`: on one side of every seam;
/// `"alternate"`), `tab_width` (mm), `tab_angle` (degrees); `sheet` (pack the pieces onto
/// sheets: `"a4"`, `"a3"`, `"letter"`, `"600x400"` or `(width_mm, height_mm)`),
/// `sheet_gap` (mm); `max_pages` (a PDF that needs more is refused; default 100);
/// `seam_allowance` (mm; fabric, leather: the outline becomes a stitch line) with
/// `notches`; `kerf` (mm; laser cutting); `grain_lines`; `thickness` (mm; sheet metal,
/// greyboard, plywood: folds become bend zones, K-factor rule) with `bend_radius` (mm;
/// default: the thickness), `k_factor` (default 0.44), `material_side` (`"behind"`, the
/// default, `"centred"`, `"in-front"`); `smooth_folds` (degrees: folds under it are
/// drawn as bending guides; default: the function's choice). The names these keywords
/// had before (`kerf_mm`, `tab_width_mm`, `units`, ...) are refused with the new one.
#[pyclass(module = "sheetform", frozen)]
#[derive(Clone)]
pub struct PatternOptions {
    pub(crate) options: PatternOutputOptions,
    /// The glue tabs a net gets when `tabs="auto"` (`flatten`; as the CLI's `--tabs auto`).
    pub(crate) net_tabs: Option<TabOptions>,
    /// The keywords it was made with (a sheet size as its text, `"600x400"`): what it
    /// pickles as and how it prints.
    keywords: serde_json::Map<String, serde_json::Value>,
}

#[pymethods]
impl PatternOptions {
    #[new]
    #[pyo3(signature = (*, scale=1.0, page="a4", pattern_units="mm", min_fold_angle=1.0, seam_labels=true, tabs="auto", tab_width=5.0, tab_angle=45.0, sheet=None, sheet_gap=5.0, max_pages=None, seam_allowance=0.0, notches=true, kerf=0.0, grain_lines=false, thickness=None, bend_radius=None, k_factor=None, material_side=None, smooth_folds=None, **renamed))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        scale: f64,
        page: &str,
        pattern_units: &str,
        min_fold_angle: f64,
        seam_labels: bool,
        tabs: &str,
        tab_width: f64,
        tab_angle: f64,
        sheet: Option<&Bound<'_, PyAny>>,
        sheet_gap: f64,
        max_pages: Option<i64>,
        seam_allowance: f64,
        notches: bool,
        kerf: f64,
        grain_lines: bool,
        thickness: Option<f64>,
        bend_radius: Option<f64>,
        k_factor: Option<f64>,
        material_side: Option<&str>,
        smooth_folds: Option<f64>,
        renamed: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        refuse_renamed_keywords("PatternOptions()", renamed, &RENAMED_KEYWORDS)?;
        let mut keywords = serde_json::Map::new();
        {
            use serde_json::json;
            let mut keep = |name: &str, value: serde_json::Value| {
                if !value.is_null() {
                    keywords.insert(name.to_string(), value);
                }
            };
            keep("scale", json!(scale));
            keep("page", json!(page));
            keep("pattern_units", json!(pattern_units));
            keep("min_fold_angle", json!(min_fold_angle));
            keep("seam_labels", json!(seam_labels));
            keep("tabs", json!(tabs));
            keep("tab_width", json!(tab_width));
            keep("tab_angle", json!(tab_angle));
            keep("sheet_gap", json!(sheet_gap));
            keep("max_pages", json!(max_pages));
            keep("seam_allowance", json!(seam_allowance));
            keep("notches", json!(notches));
            keep("kerf", json!(kerf));
            keep("grain_lines", json!(grain_lines));
            keep("thickness", json!(thickness));
            keep("bend_radius", json!(bend_radius));
            keep("k_factor", json!(k_factor));
            keep("material_side", json!(material_side));
            keep("smooth_folds", json!(smooth_folds));
        }
        let one_of = |argument: &str, value: &str, choices: &str| {
            invalid_argument(argument, format!("`{value}`: one of {choices}"))
        };
        let page = match page {
            "a4" => PageSize::A4,
            "letter" => PageSize::Letter,
            other => return Err(one_of("page", other, "\"a4\", \"letter\"")),
        };
        let dxf_unit = match pattern_units {
            "mm" => DxfUnit::Mm,
            "cm" => DxfUnit::Cm,
            "in" => DxfUnit::In,
            other => return Err(one_of("pattern_units", other, "\"mm\", \"cm\", \"in\"")),
        };
        let tab = |sides| TabOptions {
            width_mm: tab_width,
            angle_degrees: tab_angle,
            sides,
            ..Default::default()
        };
        let (tabs, net_tabs) = match tabs {
            "auto" => (None, Some(tab(TabSides::One))),
            "none" => (None, None),
            "one" => (Some(tab(TabSides::One)), None),
            "alternate" => (Some(tab(TabSides::Alternate)), None),
            other => return Err(one_of("tabs", other, "\"auto\", \"none\", \"one\", \"alternate\"")),
        };
        // (As the CLI's flags, which require `--thickness`.)
        if thickness.is_none() {
            for (given, name) in [
                (bend_radius.is_some(), "bend_radius"),
                (k_factor.is_some(), "k_factor"),
                (material_side.is_some(), "material_side"),
            ] {
                if given {
                    return Err(invalid_argument(
                        name,
                        "goes with thickness (a sheet's thickness), not given",
                    ));
                }
            }
        }
        let max_pdf_pages = match max_pages {
            None => DEFAULT_MAX_PAGES,
            Some(pages) => usize::try_from(pages).ok().filter(|&p| p > 0).ok_or_else(|| {
                invalid_argument("max_pages", format!("must be a positive number of pages, got {pages}"))
            })?,
        };
        let material_side = match material_side.unwrap_or("behind") {
            "behind" => MaterialSide::Behind,
            "centred" => MaterialSide::Centred,
            "in-front" => MaterialSide::InFront,
            other => return Err(one_of("material_side", other, "\"behind\", \"centred\", \"in-front\"")),
        };
        let sheet = match sheet {
            None => None,
            Some(value) => {
                let (width_mm, height_mm) = match value.extract::<String>() {
                    Ok(text) => sheet_size_from_text(&text).map_err(|e| invalid_argument("sheet", e))?,
                    Err(_) => value
                        .extract::<(f64, f64)>()
                        .ok()
                        .filter(|(w, h)| [w, h].iter().all(|v| v.is_finite() && **v > 0.0))
                        .ok_or_else(|| {
                            invalid_argument(
                                "sheet",
                                "a size such as \"a4\", \"600x400\" or (width_mm, height_mm), both positive",
                            )
                        })?,
                };
                keywords.insert("sheet".into(), format!("{width_mm}x{height_mm}").into());
                Some(SheetOptions {
                    width_mm,
                    height_mm,
                    gap_mm: sheet_gap,
                })
            }
        };
        Ok(Self {
            options: PatternOutputOptions {
                scale,
                page,
                dxf_unit,
                min_fold_angle_degrees: min_fold_angle,
                seam_labels,
                tabs,
                sheet,
                max_pdf_pages,
                allowance: MaterialAllowance {
                    seam_allowance_mm: seam_allowance,
                    notches,
                    kerf_mm: kerf,
                    grain_lines,
                    bend: thickness.map(|thickness| BendAllowance {
                        thickness_mm: thickness,
                        inner_radius_mm: bend_radius.unwrap_or(thickness),
                        k_factor: k_factor.unwrap_or(BendAllowance::default().k_factor),
                        material_side,
                    }),
                },
                smooth_bend_degrees: smooth_folds,
            },
            net_tabs,
            keywords,
        })
    }

    /// Pickles as the keywords it was made with (`pickle`, `copy`, Dask's workers).
    fn __getnewargs_ex__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyTuple>, Bound<'py, PyAny>)> {
        let keywords = crate::convert::json_to_python(py, &serde_json::Value::Object(self.keywords.clone()))?;
        Ok((PyTuple::empty(py), keywords))
    }

    fn __repr__(&self) -> String {
        let keywords: Vec<String> = self
            .keywords
            .iter()
            .map(|(name, value)| match value {
                serde_json::Value::String(text) => format!("{name}={text:?}"),
                serde_json::Value::Bool(flag) => format!("{name}={}", if *flag { "True" } else { "False" }),
                other => format!("{name}={other}"),
            })
            .collect();
        format!("sheetform.PatternOptions({})", keywords.join(", "))
    }
}

/// The keywords `PatternOptions` had before they took the CLI's names (issue 39), and
/// the names they have now.
const RENAMED_KEYWORDS: [(&str, &str, &str); 10] = [
    ("units", "pattern_units", ""),
    ("min_fold_angle_degrees", "min_fold_angle", ""),
    ("tab_width_mm", "tab_width", ""),
    ("tab_angle_degrees", "tab_angle", ""),
    ("sheet_gap_mm", "sheet_gap", ""),
    ("seam_allowance_mm", "seam_allowance", ""),
    ("kerf_mm", "kerf", ""),
    ("thickness_mm", "thickness", ""),
    ("bend_radius_mm", "bend_radius", ""),
    ("smooth_folds_degrees", "smooth_folds", ""),
];

/// The `pattern=` argument: `None` (the defaults), a [`PatternOptions`] or a dict of its
/// keywords.
pub(crate) fn pattern_argument(py: Python<'_>, pattern: Option<&Bound<'_, PyAny>>) -> PyResult<PatternOptions> {
    let Some(value) = pattern else {
        // (The class's own defaults: they are written once, in its signature.)
        let defaults = py.get_type::<PatternOptions>().call0()?;
        return Ok(defaults.cast::<PatternOptions>()?.get().clone());
    };
    if let Ok(options) = value.cast::<PatternOptions>() {
        return Ok(options.get().clone());
    }
    let dict = value
        .cast::<PyDict>()
        .map_err(|_| invalid_argument("pattern", "a sheetform.PatternOptions or a dict of its keywords"))?;
    let class = py.get_type::<PatternOptions>();
    let options = class.call((), Some(dict)).map_err(|e| {
        // (An option's own error names it; an unknown keyword is named by Python's.)
        if e.is_instance_of::<crate::errors::InvalidInputError>(py) {
            e
        } else {
            invalid_argument("pattern", e.value(py))
        }
    })?;
    Ok(options.cast::<PatternOptions>()?.get().clone())
}

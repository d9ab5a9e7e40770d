//! The pipelines every front end calls.

use crate::report::{RegionReport, RegressionEntry, Report, Timings, REPORT_FORMAT};
use sheetform_bend::{bend, BendError, BendModel, BendScene, BentSheet};
use sheetform_io::{glb_bytes, obj_string, stl_bytes, svg_pattern, write_atomic, IoError, SvgOptions, Texture};
use sheetform_mesh::{developability_error, isometry_error, SheetMesh};
use std::path::Path;
use std::time::Instant;
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
    /// Writing the outputs failed.
    #[error(transparent)]
    Io(#[from] IoError),
    /// The texture is not a PNG or JPEG image.
    #[error("texture {path}: not a PNG or JPEG image")]
    Texture {
        /// The file.
        path: String,
    },
    /// The output directory cannot be used.
    #[error("output directory {path}: {message}")]
    OutputDirectory {
        /// The directory.
        path: String,
        /// What is wrong.
        message: String,
    },
}

/// Knobs of `sheetform bend`.
#[derive(Debug, Clone, Default)]
pub struct BendRunOptions {
    /// Write this many frames of the isometric deformation from flat to bent.
    pub animate_frames: usize,
    /// Input path, recorded in the report.
    pub input: Option<String>,
    /// Directory that relative paths in the scene (the texture) are relative to.
    pub base_dir: Option<std::path::PathBuf>,
}

/// A finished bend run: the model, the bent sheet, the files to write and the report.
#[derive(Debug)]
pub struct BendRun {
    /// The validated model.
    pub model: BendModel,
    /// The bent sheet.
    pub sheet: BentSheet,
    /// Rendered outputs `(file name, bytes)`, not yet written.
    pub files: Vec<(String, Vec<u8>)>,
    /// The report (its `outputs` lists `files` and `report.json`).
    pub report: Report,
}

fn ms(d: std::time::Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

/// Runs system A on a scene's JSON text and renders every output in memory.
///
/// `progress(stage, fraction)` is called as the run advances.
///
/// # Errors
/// [`PipelineError::Bend`] for invalid scenes and inadmissible shapes (the error carries
/// where), nothing else.
pub fn run_bend(
    scene_text: &str,
    options: &BendRunOptions,
    progress: &mut dyn FnMut(&str, f64),
) -> Result<BendRun, PipelineError> {
    let start = Instant::now();
    progress("reading scene", 0.0);
    let scene = BendScene::from_json(scene_text)?;
    let model = BendModel::from_scene(&scene)?;
    let parsed = Instant::now();
    progress("bending", 0.1);
    let sheet = bend(&model)?;
    let solved = Instant::now();
    progress("exporting", 0.5);
    let name = model.name.clone().unwrap_or_else(|| "sheet".into());
    let texture_bytes = match &model.texture {
        Some(relative) => {
            let path = options.base_dir.clone().unwrap_or_default().join(relative);
            Some(std::fs::read(&path).map_err(|source| PipelineError::Read {
                path: path.display().to_string(),
                source,
            })?)
        }
        None => None,
    };
    let texture = match &texture_bytes {
        Some(bytes) => Some(Texture::from_bytes(bytes).ok_or_else(|| PipelineError::Texture {
            path: model.texture.clone().unwrap_or_default(),
        })?),
        None => None,
    };
    let mut files: Vec<(String, Vec<u8>)> = vec![
        ("model.obj".into(), obj_string(&sheet.mesh, &name).into_bytes()),
        ("model.glb".into(), glb_bytes(&sheet.mesh, &name, texture)),
        ("model.stl".into(), stl_bytes(&sheet.mesh)),
        (
            "pattern.svg".into(),
            svg_pattern(
                &sheet.mesh,
                &SvgOptions {
                    title: format!("{name}: flat pattern"),
                    ..Default::default()
                },
            )
            .into_bytes(),
        ),
    ];
    let frames = options.animate_frames;
    for i in 0..frames {
        let t = if frames == 1 {
            1.0
        } else {
            i as f64 / (frames - 1) as f64
        };
        let frame = sheet.frame(&model, t)?;
        files.push((
            format!("frames/frame-{i:04}.obj"),
            obj_string(&frame, &format!("{name} t={t:.4}")).into_bytes(),
        ));
        progress("animating", 0.5 + 0.5 * (i + 1) as f64 / frames as f64);
    }
    let exported = Instant::now();
    let mut report = bend_report(&model, &sheet, options.input.clone(), &files);
    report.timings = Timings {
        parse_ms: ms(parsed - start),
        solve_ms: ms(solved - parsed),
        export_ms: ms(exported - solved),
        total_ms: ms(exported - start),
    };
    progress("done", 1.0);
    Ok(BendRun {
        model,
        sheet,
        files,
        report,
    })
}

/// Mesh measures shared by every command's report.
fn mesh_measures(mesh: &SheetMesh) -> (f64, f64, f64, f64, f64) {
    let iso = isometry_error(mesh);
    let dev = developability_error(mesh);
    let mm = mesh.unit.millimetres();
    (
        iso.max_relative,
        iso.mean_relative,
        dev.max_radians,
        mesh.flat_area() * mm * mm,
        mesh.area() * mm * mm,
    )
}

fn bend_report(model: &BendModel, sheet: &BentSheet, input: Option<String>, files: &[(String, Vec<u8>)]) -> Report {
    let mm = model.unit.millimetres();
    let (iso_max, iso_mean, dev_max, flat_area, area) = mesh_measures(&sheet.mesh);
    let mut outputs: Vec<String> = files.iter().map(|f| f.0.clone()).collect();
    outputs.push("report.json".into());
    Report {
        format: REPORT_FORMAT,
        command: "bend".into(),
        sheetform_version: env!("CARGO_PKG_VERSION"),
        input,
        status: "ok".into(),
        model_unit: model.unit.symbol().into(),
        admissible: true,
        regression_entry: None,
        vertex_count: sheet.mesh.vertex_count(),
        face_count: sheet.mesh.triangles.len(),
        piece_count: sheet.mesh.pieces.len(),
        ruling_count: sheet.regions.iter().map(|r| r.ruling_count).sum(),
        isometry_error_max_relative: iso_max,
        isometry_error_mean_relative: iso_mean,
        developability_error_max_rad: dev_max,
        flat_area_mm2: flat_area,
        area_mm2: area,
        regions: sheet
            .regions
            .iter()
            .map(|r| RegionReport {
                name: r.name.clone(),
                ruling_count: r.ruling_count,
                curve_length_mm: r.curve_length * mm,
                total_fold_rad: r.total_fold_radians,
                max_fold_rad: r.max_fold_radians,
                admissible: r.admissibility.admissible,
                regression_margin_mm: r.admissibility.regression_margin.map(|m| m * mm),
                curve_deviation_mm: r.curve_deviation * mm,
                closure_gap_mm: r.closure_gap.map(|g| g * mm),
            })
            .collect(),
        outputs,
        timings: Timings::default(),
    }
}

/// The report of a shape refused as inadmissible (no mesh is made).
pub fn inadmissible_report(error: &BendError, unit_mm: f64, input: Option<String>) -> Option<Report> {
    let BendError::Inadmissible(detail) = error else {
        return None;
    };
    Some(Report {
        format: REPORT_FORMAT,
        command: "bend".into(),
        sheetform_version: env!("CARGO_PKG_VERSION"),
        input,
        status: "inadmissible".into(),
        model_unit: String::new(),
        admissible: false,
        regression_entry: Some(RegressionEntry {
            message: detail.message.clone(),
            region: detail.region,
            arc_length_range_mm: detail.arc_length_range.map(|v| v * unit_mm),
            flat_point_mm: detail.flat_point.map(|v| v * unit_mm),
            point_mm: detail.point.map(|p| p.map(|v| v * unit_mm)),
        }),
        vertex_count: 0,
        face_count: 0,
        piece_count: 0,
        ruling_count: 0,
        isometry_error_max_relative: f64::NAN,
        isometry_error_mean_relative: f64::NAN,
        developability_error_max_rad: f64::NAN,
        flat_area_mm2: 0.0,
        area_mm2: 0.0,
        regions: vec![],
        outputs: vec!["report.json".into()],
        timings: Timings::default(),
    })
}

/// Writes rendered files and the report into `dir` (created if missing), each file
/// atomically; subdirectories named in file names are created.
///
/// # Errors
/// The directory cannot be created, or a write fails.
pub fn write_outputs(dir: &Path, files: &[(String, Vec<u8>)], report: &Report) -> Result<(), PipelineError> {
    if dir.exists() && !dir.is_dir() {
        return Err(PipelineError::OutputDirectory {
            path: dir.display().to_string(),
            message: "exists and is not a directory".into(),
        });
    }
    std::fs::create_dir_all(dir).map_err(|e| PipelineError::OutputDirectory {
        path: dir.display().to_string(),
        message: e.to_string(),
    })?;
    for (name, bytes) in files {
        let path = dir.join(name);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).map_err(|e| PipelineError::OutputDirectory {
                path: parent.display().to_string(),
                message: e.to_string(),
            })?;
        }
        write_atomic(&path, bytes)?;
    }
    let json = serde_json::to_vec_pretty(report).expect("report serialises");
    write_atomic(&dir.join("report.json"), &json)?;
    Ok(())
}

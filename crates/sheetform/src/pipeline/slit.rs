//! `sheetform slit`: system B (Tsuruta et al.).

use crate::report::{Command, MouldReport, Report, ScanFitReport, SlitReport, Status, StripReport, Timings};
use sheetform_io::{glb_bytes, obj_string, stl_bytes, UpAxis};
use sheetform_mesh::{Piece, PieceKind, SheetMesh};
use sheetform_slit::{build_mould, slit_mesh, solve_design_until, SlitDesign, SlitModel, SlitScene};

type Vec2 = nalgebra::Vector2<f64>;
use super::context::RunContext;
use super::error::{Outcome, PipelineError};
use super::outputs::{output_names, pattern_files, PatternOutputOptions, RenderedFiles};
use super::sheet_report::sheet_mesh_report;
use std::time::Instant;

/// Knobs of `sheetform slit`.
#[derive(Debug, Clone, Default)]
pub struct SlitRunOptions {
    /// How the pattern is written.
    pub pattern: PatternOutputOptions,
    /// Input path, recorded in the report.
    pub input: Option<String>,
}

/// A finished slit run.
#[derive(Debug)]
pub struct SlitRun {
    /// The validated model.
    pub model: SlitModel,
    /// The solved design.
    pub design: SlitDesign,
    /// The full symmetric sheet.
    pub mesh: SheetMesh,
    /// Rendered outputs `(file name, bytes)`, not yet written.
    pub files: RenderedFiles,
    /// The report.
    pub report: Report,
    /// How the run ended (the report's `status` says the same).
    pub outcome: Outcome,
}

/// Runs system B on a scene: solve the strips, build the full sheet and its pattern, the
/// mould, and the report (the scan, if any, is read through the context's assets).
///
/// # Errors
/// [`PipelineError::Slit`] for invalid scenes (naming the field) and impossible moulds;
/// [`PipelineError::Asset`] for the scan file; [`PipelineError::Cancelled`].
pub fn run_slit(scene: &SlitScene, options: &SlitRunOptions, context: &RunContext) -> Result<SlitRun, PipelineError> {
    let start = Instant::now();
    context.progress("reading scene", 0.0);
    let scan = match &scene.scan {
        Some(spec) => Some(context.assets.read(&spec.points, "scan.points")?),
        None => None,
    };
    let model = SlitModel::from_scene(scene, scan.as_deref())?;
    let parsed = Instant::now();
    context.check_cancelled()?;
    context.progress("solving the strips", 0.1);
    // (The solve looks at the run's cancel flag at every iteration of every strip: an
    // abandoned editor request frees its solve slot.)
    let design = solve_design_until(&model, context.cancel).map_err(|e| match e {
        sheetform_slit::SlitError::Cancelled => PipelineError::Cancelled,
        other => PipelineError::from(other),
    })?;
    let mesh = slit_mesh(&model, &design);
    let mould = if model.mould.enabled {
        Some(build_mould(&model, &design)?)
    } else {
        None
    };
    let solved = Instant::now();
    context.check_cancelled()?;
    context.progress("exporting", 0.8);
    let name = model.name.clone().unwrap_or_else(|| "slit sheet".into());
    let all = context.renders_all();
    let mut files: RenderedFiles = Vec::new();
    if all {
        files.push(("model.obj".into(), obj_string(&mesh, &name, UpAxis::Y).into_bytes()));
    }
    files.push(("model.glb".into(), glb_bytes(&mesh, &name, None, UpAxis::Y)));
    if all {
        files.push(("model.stl".into(), stl_bytes(&mesh)));
    }
    let (pattern, pattern_report) =
        pattern_files(&mesh, &name, &options.pattern, context.outputs, None, UpAxis::Y, 0.0)?;
    files.extend(pattern);
    let mm = model.unit.millimetres();
    let mould_report = mould.as_ref().map(|m| {
        let solid = SheetMesh {
            positions: m.positions.clone(),
            flat: vec![Vec2::zeros(); m.positions.len()],
            triangles: m.triangles.clone(),
            face_pieces: vec![0; m.triangles.len()],
            pieces: vec![Piece {
                name: "mould".into(),
                kind: PieceKind::Planar,
            }],
            rulings: vec![],
            smooth_edges: vec![],
            unit: model.unit,
        };
        if all {
            files.push(("mould.stl".into(), stl_bytes(&solid)));
        }
        MouldReport {
            face_count: m.triangles.len(),
            volume_mm3: m.volume() * mm * mm * mm,
            watertight: m.is_watertight(),
        }
    });
    let exported = Instant::now();
    let mut report = sheet_mesh_report(Command::Slit, options.input.clone(), &mesh);
    report.pattern = Some(pattern_report);
    report.slit = Some(SlitReport {
        solve_mode: model.solver.mode,
        gap_handling: model.solver.gap,
        subdivision_count: design.level,
        normalised_error: design.normalised_error,
        gap_max_mm: design.gap * mm,
        converged: design.strips.iter().all(|s| s.converged),
        strips: design
            .strips
            .iter()
            .map(|s| StripReport {
                strip: s.strip,
                quad_count: s.quads,
                iterations: s.iterations,
                initial_penalty: s.initial_penalty,
                penalty: s.penalty.total,
                penalty_terms: s.penalty,
                gap_mm: s.gap * mm,
                normalised_error: s.normalised_error,
                converged: s.converged,
                time_ms: s.time_ms,
            })
            .collect(),
        mould: mould_report,
        scan_fit: design.scan_fit(&model).map(|f| ScanFitReport {
            scanned_point_count: f.scanned_point_count,
            fitted_point_count: f.fitted_point_count,
            distance_mean_mm: f.distance_mean * mm,
            distance_rms_mm: f.distance_rms * mm,
            distance_max_mm: f.distance_max * mm,
        }),
    });
    report.timings = Timings::from_stages(start, parsed, solved, exported);
    report.outputs = output_names(&files);
    // A strip whose solve stopped before its bound: written, and said so.
    let outcome = if design.strips.iter().all(|s| s.converged) {
        Outcome::Ok
    } else {
        report.status = Status::NotConverged;
        Outcome::OutOfTolerance
    };
    context.progress("done", 1.0);
    Ok(SlitRun {
        model,
        design,
        mesh,
        files,
        report,
        outcome,
    })
}

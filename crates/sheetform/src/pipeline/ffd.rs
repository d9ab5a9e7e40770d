//! `sheetform ffd`: system C (Wang & Tang).

use crate::report::{ChartMethod, Command, FfdReport, FfdStepReport, Report, Status, Timings};
use sheetform_ffd::{run_design_resuming, FfdDesign, FfdError, FfdScene, ModelSource, SolverMethod};
use sheetform_flatten::Chart;
use sheetform_flatten::{distortion, exact_unfold, ChartSet, FlattenError, UnfoldOptions};
use sheetform_io::{glb_bytes, obj_string, stl_bytes};
use sheetform_io::{glb_vertex_colours, mesh_from_bytes, ply_vertex_colours};
use sheetform_mesh::{mesh_topology, SheetMesh};
use std::path::Path;

use super::context::RunContext;
use super::error::{Outcome, PipelineError};
use super::flatten::sheet_from_charts;
use super::outputs::{output_names, pattern_files, PatternOutputOptions, RenderedFiles, SMOOTH_PANEL_BEND_DEGREES};
use super::sheet_report::{angle_defects, chart_report, defect_colours, sheet_mesh_report};
use std::time::Instant;

/// Knobs of `sheetform ffd`.
#[derive(Debug, Clone, Default)]
pub struct FfdRunOptions {
    /// How the pattern is written.
    pub pattern: PatternOutputOptions,
    /// Input path, recorded in the report.
    pub input: Option<String>,
    /// Overrides the scene's solver (`--solver`).
    pub solver: Option<SolverMethod>,
    /// An earlier run's design to resume from (an editor's last result): the
    /// deformations the two scenes share are taken over, only the rest restored
    /// ([`sheetform_ffd::run_design_resuming`]; the same result as a run from scratch).
    pub warm_start: Option<std::sync::Arc<FfdDesign>>,
}

/// A finished FFD run.
#[derive(Debug)]
pub struct FfdRun {
    /// The design: panels, lattice, every deformation step.
    pub design: FfdDesign,
    /// The restored object with each panel's exact flat pattern (pieces = panels).
    pub sheet: SheetMesh,
    /// The panels after the last plain FFD (before restoration), welded at the seams.
    pub plain: sheetform_mesh::TriangleMesh,
    /// The panels after the last restoration, welded as `plain`.
    pub restored: sheetform_mesh::TriangleMesh,
    /// Angle defect at each vertex of `plain` (radians; the colour map
    /// `developability-before`).
    pub angle_defects_before_rad: Vec<f64>,
    /// Angle defect at each vertex of `restored` (radians; `developability-after`).
    pub angle_defects_after_rad: Vec<f64>,
    /// Rendered outputs `(file name, bytes)`, not yet written.
    pub files: RenderedFiles,
    /// The report.
    pub report: Report,
    /// How the run ended (the report's `status` says the same).
    pub outcome: Outcome,
}

/// Why a restored panel cannot be unfolded, in the FFD scene's terms: the flattening's own
/// advice ("cut it into charts") is the `flatten` command's; here the panels are the
/// scene's model, each one piece of the pattern.
fn panel_unfolding_failed(panel: &str, error: FlattenError) -> PipelineError {
    let message = match error {
        FlattenError::Cancelled => return PipelineError::Cancelled,
        FlattenError::NotADisk { boundary_loops, .. } => format!(
            "cannot be unfolded into one piece of the pattern: it is not disk-like ({boundary_loops} boundary \
             loops; a closed or tube-like panel has none or two); split it along a seam into panels that each \
             open flat (an OBJ group per panel)"
        ),
        FlattenError::Topology { problem } => format!("cannot be unfolded: {problem}"),
        FlattenError::Solver { message } => {
            tracing::debug!(panel, message, "ffd: the exact unfolding of a panel failed");
            "cannot be unfolded: the restored panel has collapsed triangles (its unfolding has no solution); \
             undo the edit that squashes it"
                .to_string()
        }
        other => format!("cannot be unfolded: {other}"),
    };
    PipelineError::Ffd(FfdError::Panel {
        panel: panel.to_string(),
        message,
    })
}

/// Runs system C on a scene: build (or read, through the context's assets) the panels,
/// embed them in the lattice, apply each deformation and restore developability, then
/// unfold every panel exactly and write the plain and restored meshes, colour maps, the
/// pattern and the report.
///
/// The context's progress is called as the run goes (fraction in `[0, 1]`, never
/// decreasing): after reading, after each iteration of each restoration (the stage
/// names the deformation, the iteration and the largest angle defect), before the
/// export, and at the end. Cancellation is checked between the stages.
///
/// # Errors
/// [`PipelineError::Ffd`] for invalid scenes (naming the field), vertices outside the
/// lattice and solver failures; unreadable mesh files; panels that cannot be unfolded.
pub fn run_ffd(scene: &FfdScene, options: &FfdRunOptions, context: &RunContext) -> Result<FfdRun, PipelineError> {
    let start = Instant::now();
    context.progress("reading scene", 0.0);
    let mut scene = scene.clone();
    if let Some(method) = options.solver {
        scene.solver.method = method;
    }
    // Sizes and fields first: a procedural model is built only within its bounds.
    scene.validate()?;
    let mesh = match &scene.model {
        ModelSource::Procedural(model) => model.build(),
        ModelSource::Mesh(path) => {
            let bytes = context.assets.read(path, "model")?;
            mesh_from_bytes(Path::new(path), &bytes)?
        }
    };
    context.check_cancelled()?;
    let parsed = Instant::now();
    // Restorations take 5 % to 90 % of the bar, in equal shares per deformation.
    let mut shown = 0.05;
    context.progress("restoring", shown);
    let design = run_design_resuming(
        &scene,
        &mesh,
        options.warm_start.as_deref(),
        &mut |p| {
            let fraction = 0.05 + 0.85 * (p.deformation as f64 + p.fraction()) / p.deformation_count as f64;
            shown = fraction.max(shown);
            let stage = format!(
                "deformation {}/{}: iteration {}, max defect {:.1e} rad",
                p.deformation + 1,
                p.deformation_count,
                p.iteration,
                p.angle_defect_max_rad
            );
            context.progress(&stage, shown);
        },
        context.cancel,
    )
    .map_err(|e| match e {
        FfdError::Cancelled => PipelineError::Cancelled,
        other => other.into(),
    })?;
    context.check_cancelled()?;
    context.progress("exporting", 0.9);
    let solved = Instant::now();
    let unit = scene.units;
    let mm = unit.millimetres();
    let name = scene.name.clone();
    let assembly = &design.assembly;
    let last = design.steps.last().expect("validated: at least one deformation");
    let restored = assembly.mesh_at(&last.restored);
    let deformed = assembly.mesh_at(&last.deformed);
    // Each panel unfolded exactly (a panel is a disk: its seams are its boundary).
    let panel_names: Vec<String> = assembly.panels.iter().map(|p| p.name.clone()).collect();
    let charts = |positions: &[nalgebra::Vector3<f64>]| -> Result<ChartSet, PipelineError> {
        let mut charts = Vec::with_capacity(assembly.panels.len());
        for (k, panel) in assembly.panels.iter().enumerate() {
            let panel_mesh = assembly.panel_mesh(k, positions);
            let unfolding = exact_unfold(&panel_mesh, &UnfoldOptions::default())
                .map_err(|e| panel_unfolding_failed(&panel.name, e))?;
            let d = distortion(&panel_mesh, &unfolding.flat);
            charts.push(Chart {
                faces: panel.faces.clone(),
                vertices: panel.vertices.clone(),
                triangles: panel_mesh.triangles.clone(),
                flat: unfolding.flat,
                distortion: d,
                solver: unfolding.solver,
            });
        }
        Ok(ChartSet {
            face_chart: assembly.mesh.face_groups.clone(),
            charts,
            seam_edge_count: 0,
            initial_chart_count: assembly.panels.len(),
            split_count: 0,
            opened_count: 0,
            merged_count: 0,
            straightened_count: 0,
        })
    };
    let tab_room = options.pattern.room_between_pieces(mm);
    let restored_charts = charts(&last.restored)?;
    let sheet = sheet_from_charts(
        &restored,
        &restored_charts.charts,
        &name,
        Some(&panel_names),
        unit,
        tab_room,
    );
    let deformed_charts = charts(&last.deformed)?;
    let deformed_sheet = sheet_from_charts(
        &deformed,
        &deformed_charts.charts,
        &name,
        Some(&panel_names),
        unit,
        tab_room,
    );
    // Colour maps on one logarithmic scale, from 1e-8 rad (blue) to the largest defect
    // before restoration (red), so the two maps compare directly (the paper's Fig. 4).
    let topology = mesh_topology(&deformed);
    let (before, before_vertices) = angle_defects(&deformed, &topology, FFD_DEFECT_TOLERANCE, mm);
    let (after, after_vertices) = angle_defects(&restored, &topology, FFD_DEFECT_TOLERANCE, mm);
    let top = before.angle_defect_max_rad;
    let colours_before = defect_colours(&before_vertices.angle_defect, FFD_DEFECT_TOLERANCE, top);
    let colours_after = defect_colours(&after_vertices.angle_defect, FFD_DEFECT_TOLERANCE, top);
    let mut files: RenderedFiles = vec![
        (
            "model.obj".into(),
            obj_string(&sheet, &name, scene.up_axis).into_bytes(),
        ),
        ("model.glb".into(), glb_bytes(&sheet, &name, None, scene.up_axis)),
        ("model.stl".into(), stl_bytes(&sheet)),
        (
            "deformed.obj".into(),
            obj_string(&deformed_sheet, &format!("{name} (plain FFD)"), scene.up_axis).into_bytes(),
        ),
        (
            "deformed.glb".into(),
            glb_bytes(&deformed_sheet, &format!("{name} (plain FFD)"), None, scene.up_axis),
        ),
        (
            "developability-before.ply".into(),
            ply_vertex_colours(
                &deformed,
                &colours_before,
                &before_vertices.angle_defect,
                "angle_defect",
            )
            .into_bytes(),
        ),
        (
            "developability-before.glb".into(),
            glb_vertex_colours(&deformed, &colours_before, mm / 1000.0, &name, scene.up_axis),
        ),
        (
            "developability-after.ply".into(),
            ply_vertex_colours(&restored, &colours_after, &after_vertices.angle_defect, "angle_defect").into_bytes(),
        ),
        (
            "developability-after.glb".into(),
            glb_vertex_colours(&restored, &colours_after, mm / 1000.0, &name, scene.up_axis),
        ),
    ];
    if !context.renders_all() {
        // A preview shows the models (GLB) only.
        files.retain(|(n, _)| n.ends_with(".glb"));
    }
    let (pattern, pattern_report) = pattern_files(
        &sheet,
        &name,
        &options.pattern,
        context.outputs,
        None,
        scene.up_axis,
        SMOOTH_PANEL_BEND_DEGREES,
    )?;
    files.extend(pattern);
    let exported = Instant::now();
    let mut report = sheet_mesh_report(Command::Ffd, options.input.clone(), &sheet);
    report.pattern = Some(pattern_report);
    report.charts = restored_charts
        .charts
        .iter()
        .zip(&panel_names)
        .map(|(c, n)| chart_report(n, ChartMethod::Exact, c.faces.len(), &c.distortion))
        .collect();
    // Linked copies must coincide: the largest distance between vertices of one node.
    let node_positions = assembly.node_positions_of(&restored.positions);
    let linked_gap = restored
        .positions
        .iter()
        .zip(&assembly.vertex_node)
        .map(|(p, &n)| (p - node_positions[n as usize]).norm())
        .fold(0.0, f64::max);
    let deformed_distortion = deformed_charts
        .charts
        .iter()
        .map(|c| c.distortion.edge_length_max_relative)
        .fold(0.0, f64::max);
    report.ffd = Some(FfdReport {
        solver: scene.solver.method,
        bending_weight: scene.solver.bending_weight,
        line_search_memory: scene.solver.line_search_memory,
        step_unknowns: scene.solver.step_unknowns,
        panel_count: assembly.panels.len(),
        node_count: assembly.node_count,
        linked_node_count: assembly.linked_node_count(),
        linked_vertex_gap_max_mm: linked_gap * mm,
        linear_embedding: design.linear_embedding,
        embedding_time_ms: design.embedding_time_ms,
        resumed_deformations: design.resumed_deformations,
        lattice_counts: design.lattice.counts(),
        lattice_degrees: design.lattice.degrees(),
        angle_defects_before: before,
        angle_defects_after: after,
        deformed_pattern_edge_length_max_relative: deformed_distortion,
        steps: design
            .steps
            .iter()
            .map(|s| FfdStepReport {
                name: s.name.clone(),
                solver: s.info.solver,
                iterations: s.info.iterations,
                chord_steps: s.info.chord_steps,
                converged: s.info.converged,
                bending_weight: s.info.bending_weight,
                bending_fallback_iteration: s.info.bending_fallback_iteration,
                sub_steps: s.info.sub_steps,
                variable_node_count: s.info.variable_node_count,
                constraint_count: s.info.constraint_count,
                developability_g_before_rad2: s.info.developability_g_before,
                developability_g_after_rad2: s.info.developability_g_after,
                angle_defect_max_before_rad: s.info.angle_defect_max_before_rad,
                angle_defect_max_after_rad: s.info.angle_defect_max_after_rad,
                spring_energy_mm2: s.info.spring_energy_after * mm * mm,
                deviation_max_mm: s.deviation_max * mm,
                edge_length_change_max_relative: s.edge_length_change_max_relative,
                edge_length_change_mean_relative: s.edge_length_change_mean_relative,
                fold_angle_max_before_rad: s.fold_angle_max_before,
                fold_angle_max_after_rad: s.fold_angle_max_after,
                fold_angle_change_max_rad: s.fold_angle_change_max,
                time_ms: s.info.time_ms,
            })
            .collect(),
    });
    // The bound the report states: every restoration stopped by its rule and, unless no
    // restoration was asked for (`none`), ended within the defect tolerance (the paper's
    // method stops on the change of G, which does not promise the tolerance).
    let tolerance = scene.solver.tolerance_rad;
    let restoring = scene.solver.method != SolverMethod::None;
    report.status = if !design.steps.iter().all(|s| s.info.converged) {
        Status::NotConverged
    } else if restoring
        && design
            .steps
            .iter()
            .any(|s| s.info.angle_defect_max_after_rad > tolerance)
    {
        Status::OutOfTolerance
    } else {
        Status::Ok
    };
    report.timings = Timings::from_stages(start, parsed, solved, exported);
    report.outputs = output_names(&files);
    context.progress("done", 1.0);
    let outcome = if report.status == Status::Ok {
        Outcome::Ok
    } else {
        Outcome::OutOfTolerance
    };
    Ok(FfdRun {
        design,
        sheet,
        plain: deformed,
        restored,
        angle_defects_before_rad: before_vertices.angle_defect,
        angle_defects_after_rad: after_vertices.angle_defect,
        files,
        report,
        outcome,
    })
}

/// Angle defects below this count as developable in the FFD colour maps and `D[M]`
/// (radians; the paper's `λ`).
pub const FFD_DEFECT_TOLERANCE: f64 = 1e-8;

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 35: a panel that cannot be unfolded got the `flatten` command's advice ("cut
    /// it into charts first") and could get a solver's pivot: it is told in the scene's
    /// terms.
    #[test]
    fn a_panel_that_cannot_be_unfolded_is_explained_in_the_scenes_terms() {
        for error in [
            FlattenError::NotADisk {
                components: 1,
                boundary_loops: 0,
                euler: 2,
            },
            FlattenError::Solver {
                message: "the linear system has no unique solution (pivot 7 of 9 is not positive)".into(),
            },
        ] {
            let text = panel_unfolding_failed("front", error).to_string();
            assert!(text.starts_with("panel `front`: cannot be unfolded"), "{text}");
            for flatten_words in ["charts", "--", "pivot"] {
                assert!(!text.contains(flatten_words), "{text}");
            }
        }
    }
}

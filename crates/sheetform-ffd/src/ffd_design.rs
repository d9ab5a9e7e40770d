//! A whole FFD run: embed, deform step by step, restore developability.

use crate::{
    apply_edits, embed_points, fold_angle_figures, restore_along_path, restore_constrained_with_progress,
    restore_paper_with_progress, DevelopabilityProblem, FfdError, FfdScene, NurbsVolume, PanelAssembly, PaperOptions,
    RestorationInfo, RestorationProgress, SolverMethod,
};
use nalgebra::Vector3;
use rayon::prelude::*;
use sheetform_mesh::TriangleMesh;
use std::time::Instant;

type Vec3 = Vector3<f64>;

/// One deformation and its restoration.
#[derive(Debug, Clone)]
pub struct DeformationStep {
    /// Name from the scene (or `deformation-N`).
    pub name: String,
    /// The lattice after the edits.
    pub volume: NurbsVolume,
    /// Node positions of the plain FFD `M′` (the previous parameters in the new lattice).
    pub deformed: Vec<Vec3>,
    /// Parameters after restoration.
    pub parameters: Vec<Vec3>,
    /// Node positions after restoration `M*`.
    pub restored: Vec<Vec3>,
    /// What the solver did.
    pub info: RestorationInfo,
    /// Largest `|q* − q′|` over the nodes (model units).
    pub deviation_max: f64,
    /// Largest relative edge-length change `|l* − l′| / l′`.
    pub edge_length_change_max_relative: f64,
    /// Mean relative edge-length change.
    pub edge_length_change_mean_relative: f64,
    /// Largest fold angle of the plain FFD `M′` (radians, see [`crate::fold_angle_max`]), inside
    /// the panels and across their seams.
    pub fold_angle_max_before: f64,
    /// Largest fold angle after restoration `M*` (radians, panels and seams): far above
    /// `fold_angle_max_before` when the restoration crinkled the panels or creased a seam.
    pub fold_angle_max_after: f64,
    /// Largest change of one edge's signed fold angle from `M′` to `M*` (radians, panels
    /// and seams; see [`crate::fold_angle_change_max`]): the crease the restoration added, also
    /// where `fold_angle_max_before` is a fold the design has on purpose.
    pub fold_angle_change_max: f64,
}

/// The result of [`run_design`].
#[derive(Debug, Clone)]
pub struct FfdDesign {
    /// The panels.
    pub assembly: PanelAssembly,
    /// The undeformed lattice.
    pub lattice: NurbsVolume,
    /// Parameters of the nodes in the undeformed lattice.
    pub embedding: Vec<Vec3>,
    /// Whether the embedding was linear (parallelepiped lattice).
    pub linear_embedding: bool,
    /// Time spent embedding (milliseconds; 0 when [`run_design_resuming`] took the
    /// embedding over from an earlier design).
    pub embedding_time_ms: f64,
    /// The deformations, in order.
    pub steps: Vec<DeformationStep>,
    /// The scene this design was run from (its solver as run).
    pub scene: FfdScene,
    /// How many of `steps` were taken unchanged from the design the run resumed
    /// ([`run_design_resuming`]; 0 for a run from scratch).
    pub resumed_deformations: usize,
}

impl FfdDesign {
    /// Node positions after the last step.
    pub fn final_positions(&self) -> &[Vec3] {
        &self.steps.last().expect("at least one deformation").restored
    }
}

/// Runs a scene on `mesh` (the panels, one group each): builds the assembly, embeds its
/// nodes in the lattice, then applies each deformation to the lattice and restores
/// developability from the previous step's parameters.
///
/// # Errors
/// Bad panels, lattice or edits (naming the field), vertices outside the lattice, a
/// failing solver.
pub fn run_design(scene: &FfdScene, mesh: &TriangleMesh) -> Result<FfdDesign, FfdError> {
    run_design_with_progress(scene, mesh, &mut |_| {})
}

/// [`run_design`], calling `progress` after each iteration of each restoration (a
/// 100k-vertex duct takes minutes; the CLI shows these as a progress bar).
///
/// # Errors
/// As [`run_design`].
pub fn run_design_with_progress(
    scene: &FfdScene,
    mesh: &TriangleMesh,
    progress: &mut dyn FnMut(&RestorationProgress),
) -> Result<FfdDesign, FfdError> {
    run_design_with_cancel(scene, mesh, progress, None)
}

/// [`run_design_with_progress`] that stops at the next iteration of a restoration once
/// `cancel` is set (from another thread, e.g. on Ctrl-C or a newer edit in an editor).
///
/// # Errors
/// As [`run_design`]; [`FfdError::Cancelled`] when cancelled.
pub fn run_design_with_cancel(
    scene: &FfdScene,
    mesh: &TriangleMesh,
    progress: &mut dyn FnMut(&RestorationProgress),
    cancel: Option<&std::sync::atomic::AtomicBool>,
) -> Result<FfdDesign, FfdError> {
    run_design_resuming(scene, mesh, None, progress, cancel)
}

/// [`run_design_with_cancel`] that starts where `previous` (an earlier run) can take it:
/// when `previous` was run on the same panels (`mesh`) with the same units, model,
/// lattice, solver and up axis, its embedding is kept and its steps for the leading
/// deformations the two scenes share are taken as they are; only the deformations after
/// them are restored, from the last shared step's lattice and parameters. An editor
/// whose drag appends one deformation restores that one alone (a warm start); undoing
/// it (the scene one deformation shorter) restores nothing. The result is the same, bit
/// for bit, as a run from scratch, since each step depends only on the lattice and the
/// parameters the previous step left. [`FfdDesign::resumed_deformations`] says how many
/// steps were taken over. Any other `previous` is ignored.
///
/// # Errors
/// As [`run_design_with_cancel`].
pub fn run_design_resuming(
    scene: &FfdScene,
    mesh: &TriangleMesh,
    previous: Option<&FfdDesign>,
    progress: &mut dyn FnMut(&RestorationProgress),
    cancel: Option<&std::sync::atomic::AtomicBool>,
) -> Result<FfdDesign, FfdError> {
    scene.validate()?;
    let assembly = PanelAssembly::from_mesh(mesh)?;
    let previous = previous.filter(|p| {
        let (a, b) = (&p.scene, scene);
        a.units == b.units
            && a.model == b.model
            && a.lattice == b.lattice
            && a.solver == b.solver
            && a.up_axis == b.up_axis
            && p.assembly.mesh == assembly.mesh
    });
    if let Some(previous) = previous {
        let shared = previous
            .steps
            .iter()
            .zip(&previous.scene.deformations)
            .zip(&scene.deformations)
            .take_while(|((_, a), b)| a == b)
            .count();
        let base = FfdDesign {
            assembly: previous.assembly.clone(),
            lattice: previous.lattice.clone(),
            embedding: previous.embedding.clone(),
            linear_embedding: previous.linear_embedding,
            // Taken over, not computed by this run.
            embedding_time_ms: 0.0,
            steps: previous.steps[..shared].to_vec(),
            scene: scene.clone(),
            resumed_deformations: shared,
        };
        return continue_design(base, progress, cancel);
    }
    if assembly.node_count > crate::MAX_PROCEDURAL_VERTICES {
        return Err(FfdError::field(
            "model",
            format!(
                "{} vertices after linking, more than the {} a restoration may have",
                assembly.node_count,
                crate::MAX_PROCEDURAL_VERTICES
            ),
        ));
    }
    let nodes = assembly.node_positions();
    let lattice = scene.lattice(&nodes)?;
    let start = Instant::now();
    let embedding = embed_points(&lattice, &nodes).map_err(|e| match e {
        FfdError::OutsideVolume {
            vertex,
            x,
            y,
            z,
            distance,
        } => {
            // Report the first mesh vertex of the node.
            let v = assembly
                .vertex_node
                .iter()
                .position(|&n| n as usize == vertex)
                .unwrap_or(vertex);
            FfdError::OutsideVolume {
                vertex: v,
                x,
                y,
                z,
                distance,
            }
        }
        other => other,
    })?;
    let base = FfdDesign {
        embedding_time_ms: start.elapsed().as_secs_f64() * 1e3,
        linear_embedding: lattice.affine_map().is_some(),
        assembly,
        lattice,
        embedding,
        steps: Vec::new(),
        scene: scene.clone(),
        resumed_deformations: 0,
    };
    continue_design(base, progress, cancel)
}

/// `design` with the deformations of `design.scene` after its `steps` (the first
/// `resumed_deformations`) restored, from the last step's lattice and parameters (or the
/// undeformed lattice and the embedding).
fn continue_design(
    mut design: FfdDesign,
    progress: &mut dyn FnMut(&RestorationProgress),
    cancel: Option<&std::sync::atomic::AtomicBool>,
) -> Result<FfdDesign, FfdError> {
    let (scene, assembly) = (&design.scene, &design.assembly);
    let mut steps = Vec::new();
    let (mut volume, mut parameters) = match design.steps.last() {
        Some(last) => (last.volume.clone(), last.parameters.clone()),
        None => (design.lattice.clone(), design.embedding.clone()),
    };
    let problem_options = scene.solver.problem_options();
    for (k, deformation) in scene.deformations.iter().enumerate().skip(design.resumed_deformations) {
        let previous_volume = volume;
        volume = apply_edits(
            &previous_volume,
            &deformation.edits,
            &format!("deformations[{k}].edits"),
        )?;
        let mut problem = DevelopabilityProblem::new(&volume, assembly, parameters.clone(), &problem_options);
        problem.cancel = cancel;
        let deformation_count = scene.deformations.len();
        // The solvers report iteration 0 (the start) first.
        let mut angle_defect_max_start_rad = 0.0;
        let tolerance_rad = match scene.solver.method {
            SolverMethod::Constrained => scene.solver.tolerance_rad,
            _ => 0.0,
        };
        let mut report = |iteration: usize, angle_defect_max_rad: f64| {
            if iteration == 0 {
                angle_defect_max_start_rad = angle_defect_max_rad;
            }
            progress(&RestorationProgress {
                deformation: k,
                deformation_count,
                iteration,
                angle_defect_max_start_rad,
                angle_defect_max_rad,
                tolerance_rad,
            })
        };
        let (new_parameters, info) = match scene.solver.method {
            SolverMethod::Constrained => {
                let options = scene.solver.constrained_options();
                match &scene.solver.continuation {
                    Some(continuation) => restore_along_path(
                        &previous_volume,
                        &problem,
                        &problem_options,
                        &options,
                        &continuation.options(),
                        &mut report,
                    )?,
                    None => restore_constrained_with_progress(&problem, &options, &mut report)?,
                }
            }
            SolverMethod::Paper => {
                let mut options = PaperOptions::default();
                if let Some(m) = scene.solver.max_iterations {
                    options.max_steps = m;
                }
                restore_paper_with_progress(&problem, &options, &mut report)
            }
            SolverMethod::None => {
                let mut info = RestorationInfo::begin(
                    crate::SolverMethod::None,
                    &problem,
                    &problem.evaluate(&problem.gather(&parameters)),
                );
                info.developability_g_after = info.developability_g_before;
                info.angle_defect_max_after_rad = info.angle_defect_max_before_rad;
                info.sub_steps = 0;
                (parameters.clone(), info)
            }
        };
        // (The paper's solver stops early when cancelled; the result is not used.)
        problem.check_cancelled()?;
        let deformed = problem.target.clone();
        let restored: Vec<Vec3> = new_parameters.par_iter().map(|&x| volume.point(x)).collect();
        let deviation_max = deformed
            .iter()
            .zip(&restored)
            .map(|(a, b)| (a - b).norm())
            .fold(0.0, f64::max);
        let (max, mean) = edge_length_change(assembly, &deformed, &restored);
        // Over the welded panels: inside each panel and across the seams.
        let folds = fold_angle_figures(
            &assembly.node_triangles,
            &assembly.node_edges,
            |n| deformed[n as usize],
            |n| restored[n as usize],
        );
        steps.push(DeformationStep {
            name: deformation
                .name
                .clone()
                .unwrap_or_else(|| format!("deformation-{}", k + 1)),
            volume: volume.clone(),
            deformed,
            parameters: new_parameters.clone(),
            restored,
            info,
            deviation_max,
            edge_length_change_max_relative: max,
            edge_length_change_mean_relative: mean,
            fold_angle_max_before: folds.max_before,
            fold_angle_max_after: folds.max_after,
            fold_angle_change_max: folds.change_max,
        });
        parameters = new_parameters;
    }
    design.steps.extend(steps);
    Ok(design)
}

/// `(max, mean)` of `|l_b − l_a| / l_a` over the mesh edges.
fn edge_length_change(assembly: &PanelAssembly, a: &[Vec3], b: &[Vec3]) -> (f64, f64) {
    let (mut max, mut sum, mut count) = (0.0f64, 0.0, 0usize);
    for t in &assembly.mesh.triangles {
        for k in 0..3 {
            let (i, j) = (
                assembly.vertex_node[t[k] as usize] as usize,
                assembly.vertex_node[t[(k + 1) % 3] as usize] as usize,
            );
            let la = (a[i] - a[j]).norm();
            if la > 0.0 {
                let change = ((b[i] - b[j]).norm() - la).abs() / la;
                max = max.max(change);
                sum += change;
                count += 1;
            }
        }
    }
    (max, if count > 0 { sum / count as f64 } else { 0.0 })
}

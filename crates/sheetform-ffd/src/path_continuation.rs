//! Restoration along the deformation's path (continuation), in adaptive sub-steps.

use crate::{
    restore_constrained_with_progress, ConstrainedOptions, DevelopabilityProblem, FfdError, NurbsVolume,
    ProblemOptions, RestorationInfo,
};
use nalgebra::Vector3;
use std::time::Instant;

type Vec3 = Vector3<f64>;

/// Knobs of [`restore_along_path`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContinuationOptions {
    /// Largest curvature a sub-step may create before it is restored: the sub-step is
    /// halved until the plain FFD of the last restored parameters in the sub-step's
    /// lattice has `max |g| · A/l̄² ≤ sub_step_curvature` (`g` the angle defects, `A/l̄²`
    /// the panels' area over their squared mean edge length,
    /// [`DevelopabilityProblem::resolution`]). A vertex's defect is its Gaussian
    /// curvature times its area (about `l̄²·√3/2`), so the figure is about the largest
    /// Gaussian curvature times the panels' area, and the same deformation gives the
    /// same figure at every resolution. Default 0.5: the skirt's deformation (1.3) takes
    /// four sub-steps, the duct's (3.3) eight.
    pub sub_step_curvature: f64,
    /// Most sub-steps along the path; the shortest sub-step is `1/max_sub_steps` of the
    /// deformation (default 64).
    pub max_sub_steps: usize,
}

impl Default for ContinuationOptions {
    fn default() -> Self {
        Self {
            sub_step_curvature: 0.5,
            max_sub_steps: 64,
        }
    }
}

/// Restores developability along the path from the lattice `from` to `problem.volume`,
/// starting at the parameters `problem.start` (developable in `from`).
///
/// The lattice moves linearly, `Q(t) = (1 − t)·Q_from + t·Q_to` (control points and
/// weights), `t` from 0 to 1 in sub-steps `h`; each sub-step is restored by the
/// constrained solver ([`restore_constrained_with_progress`]) from the last restored
/// parameters, with springs at the sub-step's plain FFD — the paper's deformations in
/// succession (Wang & Tang 2004, §4: later deformations apply to the restored shape),
/// cut finely enough that each restoration starts close to the developable set, where
/// the Gauss–Newton projection's full steps are accepted.
///
/// Adaptive sub-steps: each starts at twice the last accepted one (the first at the
/// whole path) and is halved while its plain FFD has an angle defect above
/// [`ContinuationOptions::sub_step_curvature`], or when its restoration does not converge,
/// down to `1/max_sub_steps`. Departure from a fixed `k`: the defect a sub-step creates
/// grows about linearly with `h`, so this picks `k ≈ d₁/d_max` (`d₁` the whole
/// deformation's defect) and spends fewer sub-steps where the path is gentle.
///
/// The result's [`RestorationInfo`] compares the start with the end of the whole path
/// (defects before: the plain FFD of `problem.start` in `problem.volume`); its
/// `iterations` and `time_ms` add up over the sub-steps, `sub_steps` counts them.
///
/// # Errors
/// As [`restore_constrained_with_progress`].
pub fn restore_along_path(
    from: &NurbsVolume,
    problem: &DevelopabilityProblem<'_>,
    problem_options: &ProblemOptions,
    options: &ConstrainedOptions,
    continuation: &ContinuationOptions,
    progress: &mut dyn FnMut(usize, f64),
) -> Result<(Vec<Vec3>, RestorationInfo), FfdError> {
    let clock = Instant::now();
    // No chord steps along the path (see `ConstrainedOptions::chord_steps`): the
    // report's `chord_steps` stays 0.
    let sub_options = ConstrainedOptions {
        chord_steps: 0,
        ..*options
    };
    let mut info = RestorationInfo::begin(
        crate::SolverMethod::Constrained,
        problem,
        &problem.evaluate(&problem.gather(&problem.start)),
    );
    let shortest = 1.0 / continuation.max_sub_steps.max(1) as f64;
    let mut parameters = problem.start.clone();
    let (mut t, mut h) = (0.0f64, 1.0f64);
    let mut iterations = 0;
    let mut sub_steps = 0;
    let mut variable_node_count = 0;
    progress(0, info.angle_defect_max_before_rad);
    loop {
        h = h.min(1.0 - t).max(shortest.min(1.0 - t));
        // The sub-step's lattice: halve `h` while the plain FFD's defect is too large.
        let (volume, end) = loop {
            let end = if 1.0 - (t + h) <= 0.5 * shortest { 1.0 } else { t + h };
            let volume = if end == 1.0 {
                problem.volume.clone()
            } else {
                from.interpolated(problem.volume, end)
            };
            let curvature = start_curvature(&volume, problem, &parameters, problem_options);
            if curvature <= continuation.sub_step_curvature || h <= shortest {
                break (volume, end);
            }
            h = (0.5 * h).max(shortest);
        };
        problem.check_cancelled()?;
        let mut sub_problem =
            DevelopabilityProblem::new(&volume, problem.assembly, parameters.clone(), problem_options);
        sub_problem.cancel = problem.cancel;
        let offset = iterations;
        let (restored, sub_info) = restore_constrained_with_progress(&sub_problem, &sub_options, &mut |i, defect| {
            if i > 0 {
                progress(offset + i, defect);
            }
        })?;
        iterations += sub_info.iterations;
        if sub_info.bending_fallback_iteration.is_some() && info.bending_fallback_iteration.is_none() {
            info.bending_fallback_iteration = sub_info.bending_fallback_iteration.map(|i| offset + i);
        }
        if !sub_info.converged && h > shortest {
            tracing::debug!("continuation: sub-step {t:.4} → {end:.4} did not converge; halving it");
            h = (0.5 * h).max(shortest);
            continue;
        }
        sub_steps += 1;
        variable_node_count = variable_node_count.max(sub_info.variable_node_count);
        tracing::debug!(
            "continuation: sub-step {sub_steps} {t:.4} → {end:.4}: defect {:.3e} → {:.3e} rad in {} iterations",
            sub_info.angle_defect_max_before_rad,
            sub_info.angle_defect_max_after_rad,
            sub_info.iterations
        );
        parameters = restored;
        t = end;
        if !sub_info.converged || t >= 1.0 {
            info.iterations = iterations;
            info.converged = sub_info.converged;
            info.variable_node_count = variable_node_count;
            info.constraint_count = info.constraint_count.max(sub_info.constraint_count);
            info.developability_g_after = sub_info.developability_g_after;
            info.angle_defect_max_after_rad = sub_info.angle_defect_max_after_rad;
            info.spring_energy_after = sub_info.spring_energy_after;
            info.bending_weight = sub_info.bending_weight;
            info.sub_steps = sub_steps;
            info.time_ms = clock.elapsed().as_secs_f64() * 1e3;
            return Ok((parameters, info));
        }
        h *= 2.0;
    }
}

/// `max |g| · A/l̄²` of the plain FFD of `parameters` in `volume`, over the interior
/// vertices of the panels.
fn start_curvature(
    volume: &NurbsVolume,
    problem: &DevelopabilityProblem<'_>,
    parameters: &[Vec3],
    problem_options: &ProblemOptions,
) -> f64 {
    let probe = DevelopabilityProblem::new(volume, problem.assembly, parameters.to_vec(), problem_options);
    let defect = probe
        .evaluate_defects(&probe.gather(&probe.start))
        .iter()
        .fold(0.0, |m: f64, g| m.max(g.abs()));
    defect * probe.resolution()
}

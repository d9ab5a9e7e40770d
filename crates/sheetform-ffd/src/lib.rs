//! System C: developability-preserving free-form deformation (Wang & Tang 2004).
//!
//! A designer deforms an object made of developable panels (a duct, a dress, trousers)
//! with a NURBS lattice; the panels' vertices keep their lattice parameters `(u, v, w)`,
//! and restoring developability moves those parameters (not the control points and not
//! the vertices directly), so later deformations apply to the optimised shape without
//! inverting the lattice again.
//!
//! - [`NurbsVolume`]: the trivariate NURBS volume `Q(u,v,w)` with its Jacobian;
//! - [`lattice_edit`]: move, re-weight or transform control points;
//! - [`embed_points`]: the parameters of the undeformed vertices (linear or Newton);
//! - [`PanelAssembly`]: panels (OBJ groups) and their linked vertices;
//! - [`corner_angle_gradient`], [`corner_angle_hessian`]: a corner angle's exact first
//!   and second derivatives;
//! - [`DevelopabilityProblem`]: `min E(X)` subject to `g(q_i(X)) = 0` (Eq. 2-2 to 2-6);
//! - [`restore_constrained`] (default) and [`restore_paper`] (§3): the solvers;
//! - [`restore_along_path`]: the constrained solver along a deformation's path, in
//!   adaptive sub-steps (continuation);
//! - [`procedural_panels`]: the examples' developable panel assemblies;
//! - [`fold_angle_max`], [`fold_angle_change_max`]: the fairness of a result (crinkles
//!   show as large fold angles, creases the restoration added as large changes);
//! - [`scene`], [`ffd_design`]: the scene file and the whole run.

#![warn(missing_docs)]

mod bending_metric;
mod constrained_gauss_newton;
mod developability_problem;
mod embedding;
mod error;
mod fold_angle;
pub use sheetform_solve::MAX_FACTOR_BYTES;
mod normal_step_reduction;
mod nurbs_volume;
mod panel_assembly;
mod path_continuation;
mod penalty_conjugate_gradient;
mod restoration_info;

pub mod ffd_design;
pub mod lattice_edit;
pub mod procedural_panels;
pub mod scene;

pub use constrained_gauss_newton::{
    restore_constrained, restore_constrained_with_progress, ConstrainedOptions, StepUnknowns,
};
pub use developability_problem::{DevelopabilityProblem, Evaluation, ProblemOptions, Spring};
pub use embedding::{embed_points, lattice_size, newton_inversion, EMBEDDING_TOLERANCE};
pub use error::FfdError;
pub use ffd_design::{
    run_design, run_design_resuming, run_design_with_cancel, run_design_with_progress, DeformationStep, FfdDesign,
};
pub use fold_angle::{fold_angle_change_max, fold_angle_figures, fold_angle_max, FoldAngleFigures};
pub use lattice_edit::{apply_edits, ControlPointSelection, IndexRanges, LatticeEdit};
pub use nurbs_volume::{NurbsVolume, DIRECTION_NAMES};
pub use panel_assembly::{Panel, PanelAssembly, LINK_TOLERANCE};
pub use path_continuation::{restore_along_path, ContinuationOptions};
pub use penalty_conjugate_gradient::{restore_paper, restore_paper_with_progress, PaperOptions};
pub use procedural_panels::MAX_PROCEDURAL_VERTICES;
pub use restoration_info::{RestorationInfo, RestorationProgress};
pub use scene::*;
pub use sheetform_mesh::{corner_angle, corner_angle_gradient, corner_angle_hessian};

//! Inverse design (issue 36): a target shape → the nearest surface made of a few exactly
//! developable pieces, joined along their seams.
//!
//! - [`seam_pieces`]: the pieces a target is cut into along its seams, and the vertices
//!   inside them;
//! - [`segment_developable`]: automatic seams, the target cut into a few pieces whose
//!   normals lie close to a cone's (a developable's Gauss image is a curve);
//! - [`develop_pieces`]: the target's vertices moved as little as possible so that every
//!   vertex inside a piece is flat (angle sum 2π): a constrained Gauss–Newton projection
//!   on the shared [`sheetform_solve::KktSystem`];
//! - [`smooth_seams`]: seams slid over a surface onto smooth curves (the pipeline slides
//!   the automatic seams over the developed surface and develops the pieces again);
//! - [`slit_unflattened_vertices`]: slits from the cone points a solve could not flatten.
//!
//! The pieces are then unfolded exactly and laid out by the pipeline (`run_develop`),
//! like every other system's.

#![warn(missing_docs)]

mod cone_slits;
mod developable_projection;
mod developable_segmentation;
mod error;
mod seam_pieces;
mod seam_smoothing;

pub use cone_slits::slit_unflattened_vertices;
pub use developable_projection::{
    develop_pieces, DevelopOptions, Developed, MirrorBoundary, CHORD_CONTRACTION, DIAGONAL_METRIC_SMOOTHNESS,
    HOPELESS_COMPANION_STEPS, HOPELESS_DEFECT, HOPELESS_STEPS, MAX_CHORD_STEPS, MAX_ITERATIONS, MAX_SMOOTHNESS,
    POLISH_STEPS, STALL_DEFECT, STALL_STEPS, STALL_TOLERANCE, STEP_REACH, STEP_TOLERANCE,
};
pub use developable_segmentation::{
    segment_developable, ConeProxy, Segmentation, SegmentationOptions, MAX_SEGMENTATION_PIECES,
};
pub use error::DevelopError;
pub use seam_pieces::{mirror_interior, seam_pieces, SeamPieces};
pub use seam_smoothing::{smooth_seams, SeamSmoothingOptions, SmoothedSeams, MAX_SEAM_SMOOTHING_ITERATIONS};

//! System D of sheetform: developable patterns from an annotated photograph
//! (A. Fondevilla, A. Bousseau, D. Rohmer, S. Hahmann, M.-P. Cani, "Patterns from
//! Photograph: Reverse-Engineering Developable Products", Computers & Graphics 66, 2017).
//!
//! A user traces silhouettes and boundaries over one photo of a mirror-symmetric object
//! made of developable patches ([`PhotoAnnotation`]); [`reconstruct`] lifts the drawing to
//! a 3D curve network and meshes each patch. One file per step of the paper:
//!
//! | step | file | paper |
//! |---|---|---|
//! | curves split at their intersections | `curve_network.rs` | §5.1 |
//! | patches = minimal cycles | `patch_cycles.rs` | §5.1 |
//! | samples along the curves | `curve_samples.rs` | §5.2, §5.3 |
//! | rulings by dynamic time warping | `ruling_propagation.rs` | §5.2, Eq. 2 |
//! | ruling ends at parallel tangents | `ruling_alignment.rs` | §5.2 |
//! | orthographic or perspective camera | `camera.rs` | beyond §9 (Fig. 14) |
//! | symmetry plane, mirror-pair relation | `symmetry_plane.rs` | §6.1 |
//! | symmetric correspondences | `symmetric_correspondences.rs` | §5.3 |
//! | the six energy terms, sparse solve | `curve_lifting.rs` | §6, Eq. 3–4 |
//! | exact developability along rulings | `developability_refinement.rs` | beyond §8.2 |
//! | symmetrised curves and rulings | `symmetrization.rs` | §7 |
//! | strips and minimal-surface fills | `patch_mesh.rs` | §7 |
//! | bands closed around their axis | `revolved_bands.rs` | beyond §9 (Pottmann & Randrup 1998) |
//! | overlay over the photograph | `overlay.rs` | Fig. 4–7 |
//! | annotations drawn in Inkscape | `svg_import.rs` | — |
//!
//! Kernels do no I/O: the caller reads the annotation and the image and writes outputs
//! (`sheetform::pipeline::run_photo`).

mod annotation;
mod camera;
pub mod cubic;
mod curve_lifting;
mod curve_network;
mod curve_samples;
mod developability_refinement;
mod error;
mod focal_length_estimate;
mod overlay;
mod patch_cycles;
mod patch_mesh;
mod reconstruction;
mod revolved_bands;
mod ruling_alignment;
mod ruling_propagation;
mod svg_import;
mod symmetric_correspondences;
mod symmetrization;
mod symmetry_plane;

pub use annotation::{
    image_to_model, model_to_image, AnalysisLengths, AnalysisSpec, BackSide, CameraSpec, CurveKind, CurveSpec,
    EnergyWeights, ImagePoint, ImageSpec, PhotoAnnotation, Projection, SymmetrySpec, TrueSizeSpec, MAX_CONTROL_POINTS,
    MAX_CURVES, MAX_FOCAL_LENGTH_DIAGONALS, MAX_IMAGE_SIDE, MIN_FOCAL_LENGTH_DIAGONALS,
};
pub use camera::{Camera, FILM_35MM_DIAGONAL_MM};
pub use curve_lifting::{assemble_energy, image_prior, place_image, solve_energy, Energy, EnergyRow, EnergyTerm};
pub use curve_network::{
    build_curve_network, knot_snap_radius, CurveNetwork, NetworkCurve, NetworkSegment, MAX_CROSSINGS, MAX_CURVE_SAMPLES,
};
pub use curve_samples::{sample_curves, CurvePoint, CurveSamples, SampledChain};
pub use developability_refinement::{
    refine_developability, refinement_iteration_work, ruling_errors, Refinement, RefinementInfo, MAX_DENSE_VALUES,
    MAX_REFINEMENT_WORK, REFINEMENT_BOUND,
};
pub use error::PhotoError;
pub use focal_length_estimate::{
    estimate_focal_length, FocalLengthEstimate, REFINEMENT_COUNT, SCAN_COUNT, SCAN_FIRST_DIAGONALS, SCAN_RATIO,
};
pub use overlay::{overlay_png, overlay_svg};
pub use patch_cycles::{find_patches, HalfEdge, Patch};
pub use patch_mesh::{mesh_patches, PatchMesh, PatchSurface, MAX_FILL_VERTICES, MAX_FILL_VERTICES_PER_PATCH};
pub use reconstruction::{
    place_point, reconstruct, AngleSummary, PhotoReconstruction, StageTimes, DEPTH_SENSITIVITY_BOUND,
};
pub use revolved_bands::{
    fit_revolution_axis, revolve_bands, Revolution, RevolvedBand, MAX_REVOLUTION_SEGMENTS, MIN_REVOLUTION_RULINGS,
    REVOLUTION_FIT_BOUND, REVOLUTION_FIT_WARNING, REVOLUTION_SILHOUETTE_BOUND_DEGREES,
    REVOLUTION_SILHOUETTE_WARNING_DEGREES,
};
pub use ruling_alignment::{align_rulings, align_rulings_in_perspective, move_ruling_ends};
pub use ruling_propagation::{
    propagate_rulings, PropagationCounts, PropagationOptions, RuledStrip, MAX_STRIP_SAMPLES, MAX_WARPING_CELLS,
    MAX_WARPING_CELLS_TOTAL,
};
pub use svg_import::{annotation_from_svg, svg_image_reference};
pub use symmetric_correspondences::{
    curve_chain, symmetric_pairs, symmetric_pairs_of_curves, SymmetricPair, MAX_CORRESPONDENCE_TESTS,
};
pub use symmetrization::{
    split_at_mirror_nodes, symmetrize, MirrorMap, SymmetrizationInfo, MAX_MIRROR_SEARCH_EVALUATIONS,
    MAX_RULING_LOOKUP_WORK, MAX_SEGMENT_COMPARISONS,
};
pub use symmetry_plane::SymmetryPlane;

//! sheetform: design with developable surfaces, shapes made by bending sheet material
//! without stretching or tearing.
//!
//! This facade re-exports the parts and holds the pipelines that every front end (the
//! `sheetform` command, the web editor, bindings) calls, so no app repeats a step:
//!
//! - [`geometry`]: curves, frames, polygons;
//! - [`mesh`]: [`mesh::SheetMesh`], the mesh that carries its own flat pattern;
//! - [`bend`]: system A, sheets bent by geodesic control curves (Bo & Wang 2007);
//! - [`slit`]: system B, furniture from one sheet with parallel slits (Tsuruta et al.);
//! - [`ffd`]: system C, developability-preserving free-form deformation (Wang & Tang);
//! - [`photo`]: system D, developable patterns from an annotated photograph (Fondevilla et al.);
//! - [`flatten`]: exact unfolding of developable meshes, distortion and overlap measures;
//! - [`io`]: readers (OBJ, PLY, STL, OFF), exports (OBJ, GLB, STL, SVG), atomic writing;
//! - [`pattern`]: cutting patterns as SVG, DXF and tiled true-scale PDF;
//! - [`pipeline`]: scene file → model → mesh + pattern → files + `report.json`.
//!
//! ```
//! use sheetform::bend::BendScene;
//! use sheetform::pipeline::{run_bend, BendRunOptions, Outcome, RunContext};
//! // Parsing stays at the edge; the pipeline takes the typed scene and a context (the
//! // directory its assets may be read from, progress, cancellation, outputs).
//! let scene = BendScene::from_json(include_str!("../../../examples/bent-rectangle.json")).unwrap();
//! let run = run_bend(&scene, &BendRunOptions::default(), &RunContext::new("examples")).unwrap();
//! assert_eq!(run.outcome, Outcome::Ok);
//! assert_eq!(run.report.admissible, Some(true));
//! assert!(run.report.isometry_error_max_relative.unwrap() < 1e-9);
//! // The bent sheet is developable: no angle defect at its interior vertices.
//! assert!(run.report.angle_defects.unwrap().angle_defect_max_rad < 1e-9);
//! ```

#![warn(missing_docs)]

pub mod pipeline;
pub mod report;

pub use sheetform_bend as bend;
pub use sheetform_ffd as ffd;
pub use sheetform_flatten as flatten;
pub use sheetform_geometry as geometry;
pub use sheetform_io as io;
pub use sheetform_mesh as mesh;
pub use sheetform_pattern as pattern;
pub use sheetform_photo as photo;
pub use sheetform_slit as slit;

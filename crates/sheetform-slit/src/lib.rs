//! System B: furniture from one sheet with parallel slits (Tsuruta et al.).
//!
//! A rectangular sheet with parallel slits of equal length is bent into a symmetric shape
//! (a chair, a bench, a "monument"): the two unslit ends become side panels (legs) and
//! every strip between two slits is a chain of planar quads folded along ridge lines,
//! whose end must meet its mirror image on the symmetry plane. Only half is modelled.
//!
//! - [`scene`]: the JSON scene file;
//! - [`SheetLayout`], [`SidePanel`], [`SeatCurve`]: the flat sheet (Fig. 2) and the two
//!   design curves (Fig. 11);
//! - [`strip_folding`]: a strip folded along its ridge lines, with exact derivatives;
//! - [`strip_penalty`]: the penalty `F` of Eq. 1 as least-squares residuals with an
//!   exact Jacobian;
//! - [`strip_solver`]: Levenberg–Marquardt with the gap as a constraint, per strip or
//!   jointly;
//! - [`slit_design`]: scene → model → solved design; anchors, subdivision;
//! - [`mod@slit_mesh`]: the full symmetric sheet as a mesh carrying its flat pattern;
//! - [`mould`]: the closed, printable mould under the strips (§4.2);
//! - [`point_cloud`]: scanned points for fitting (§4.1).

#![warn(missing_docs)]

mod error;
mod seat_curve;
mod sheet_layout;
mod side_panel;

pub mod mould;
pub mod point_cloud;
pub mod scene;
pub mod slit_design;
pub mod slit_mesh;
pub mod strip_folding;
pub mod strip_penalty;
pub mod strip_solver;

pub use error::SlitError;
pub use mould::{build_mould, Mould};
pub use scene::*;
pub use seat_curve::{SeatCurve, SeatProjection};
pub use sheet_layout::SheetLayout;
pub use side_panel::SidePanel;
pub use slit_design::{
    solve_design, solve_design_until, ScanFit, SlitDesign, SlitModel, MAX_ITERATIONS, MAX_QUADS,
    MAX_QUADS_SOLVED_TOGETHER, MAX_STRIPS,
};
pub use slit_mesh::slit_mesh;
pub use strip_solver::StripSolveInfo;

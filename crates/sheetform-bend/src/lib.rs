//! System A of sheetform: a sheet bent by 3D control curves that are geodesics on it
//! (P. Bo and W. Wang, "Geodesic-Controlled Developable Surfaces for Modeling Paper
//! Bending", Computer Graphics Forum 26(3), 2007).
//!
//! Data flow: [`BendScene`] (JSON) → [`BendModel`] (validated) → per region
//! [`sample_rulings`] (rectifying developable, Eq. 1; curve of regression, Eq. 4–5) →
//! [`ruling_extent`] (boundary, §3.3) → [`check_region`] (admissibility, Eq. 6) →
//! [`flat_layout`] (cut the flat sheet along the rulings) → [`FoldedStrip`] + [`place`]
//! (composite placement, §3.4 / §4.2) → [`sheetform_mesh::SheetMesh`].

mod admissibility;
mod bend;
mod control_curve;
mod curve_of_regression;
mod edit;
mod error;
mod flat_layout;
mod flat_path;
mod folded_strip;
mod model;
mod rectifying_developable;
mod ruling_extent;
mod scene;

pub use admissibility::{check_region, RegionAdmissibility};

/// Most rulings per curved region (`tessellation.rulings`, `tessellation.max_rulings`):
/// each costs a few hundred bytes in the mesh and the flat layout, so a million keep a
/// region within a few hundred megabytes (1e8 asked for 12 GB and aborted).
pub const MAX_RULINGS: usize = 1_000_000;
/// Most curved regions in one scene (each is placed against the others).
pub const MAX_REGIONS: usize = 256;
/// Most vertices of the outline and holes together (the crossing check and the ruling
/// extents cost rulings × outline edges).
pub const MAX_OUTLINE_VERTICES: usize = 100_000;
pub use bend::{bend, place, region_geometries, region_geometry, BentSheet, Placement, RegionGeometry, RegionSummary};
pub use control_curve::{AnalyticCurve, ControlCurve, CurveShape};
pub use curve_of_regression::{curve_of_regression_near_sheet, regression_distance};
pub use edit::{
    check_control_point_index, check_edit_coordinates, check_edit_number, solve_end_normals, trim_to_length,
    BendEditor, EditInfo, EndHandle, EndHandleOptions, LengthPreservation, MAX_EDIT_COORDINATE,
};
pub use error::{BendError, InadmissibleDetail};
pub use flat_layout::{flat_layout, Cell, EdgeKind, FlatLayout};
pub use flat_path::{FlatCurve, FlatFrame, FlatPath};
pub use folded_strip::{lift, FoldedStrip};
pub use model::{curve_shape, BendModel, CurvedRegion};
pub use rectifying_developable::{sample_rulings, RulingSample};
pub use ruling_extent::{ruling_extent, BoundaryPoint, RulingExtent};
pub use scene::{BendScene, CurveSpec, CurvedRegionSpec, FlatCurveSpec, TessellationOptions};

//! Geometry core of sheetform: Bézier and B-spline curves in 2D and 3D with exact
//! derivatives, arc length and arc-length reparametrisation, Frenet and Darboux frames,
//! 2D polygons with holes, numbers and tokens written short for messages, and JSON
//! documents read with errors that name the field.
//!
//! Everything is `f64`. Lengths are in the model's units (the scene file says which;
//! millimetres by default). Kernels do no I/O.

mod arc_length;
mod bezier;
mod bspline;
mod bspline_basis;
mod curve;
mod error;
mod frame;
mod helix;
mod json_document;
mod message_text;
mod polygon;
mod rigid;

pub use arc_length::{gauss_legendre_length, ArcLengthOptions, ArcLengthTable};
pub use bezier::{Bezier, Bezier2, Bezier3, MAX_BEZIER_DEGREE};
pub use bspline::{BSpline, BSpline2, BSpline3};
pub use bspline_basis::{BSplineBasis, BasisTable, MAX_BSPLINE_DEGREE};
pub use curve::{Curve3, ParametricCurve};
pub use error::GeometryError;
pub use frame::{curve_frame, CurveFrame, CurveFrameDerivatives};
pub use helix::Helix;
pub use json_document::{json_from_text, JsonFieldError, WHOLE_DOCUMENT};
pub use message_text::{
    numbers_apart, quoted_token, refused_number, short_number, shortened_message, triangulation_problem, xml_escaped,
    ShortNumber, QUOTED_TOKEN_CHARS,
};
pub use polygon::{
    convex_hull, cross2, fits_turned, fitting_rotation, hull_fits_rectangle, rings_contain, segment_distance,
    segment_intersection, segments_cross, segments_meet, signed_area, triangles_overlap, Polygon, PolygonEdge, RayHit,
};
pub use rigid::{rotation_about_axis, RigidMotion};

/// A 2D vector or point (flat-sheet coordinates).
pub type Vec2 = nalgebra::Vector2<f64>;
/// A 3D vector or point (bent-sheet coordinates).
pub type Vec3 = nalgebra::Vector3<f64>;

//! Flattening triangle meshes into patterns: exact unfolding of developable meshes from
//! their intrinsic edge lengths, least-squares conformal maps for meshes that are only
//! nearly developable, distortion and overlap measures, and rigid 2D alignment. ARAP and
//! cutting into charts come next (issue 3).

mod alignment;
mod distortion;
mod error;
mod exact_unfolding;
mod lscm;

pub use alignment::{align_rigid, RigidAlignment};
pub use distortion::{distortion, Distortion};
pub use error::FlattenError;
pub use exact_unfolding::{exact_unfold, UnfoldOptions, Unfolding};
pub use lscm::lscm;

/// A 2D point on the pattern.
pub type Vec2 = nalgebra::Vector2<f64>;

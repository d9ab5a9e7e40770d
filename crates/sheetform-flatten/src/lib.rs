//! Flattening triangle meshes into patterns: exact unfolding of developable meshes from
//! their intrinsic edge lengths, least-squares conformal maps for meshes that are only
//! nearly developable, as-rigid-as-possible flattening, distortion and overlap measures,
//! and rigid 2D alignment. Cutting into charts comes next (issue 3).

mod alignment;
mod arap;
mod distortion;
mod error;
mod exact_unfolding;
mod lscm;

pub use alignment::{align_rigid, RigidAlignment};
pub use arap::{arap, ArapOptions};
pub use distortion::{distortion, Distortion};
pub use error::FlattenError;
pub use exact_unfolding::{exact_unfold, UnfoldOptions, Unfolding};
pub use lscm::lscm;

/// A 2D point on the pattern.
pub type Vec2 = nalgebra::Vector2<f64>;

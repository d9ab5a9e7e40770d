//! Flattening triangle meshes into patterns: exact unfolding of developable meshes from
//! their intrinsic edge lengths, least-squares conformal maps for meshes that are only
//! nearly developable, as-rigid-as-possible flattening, distortion and overlap measures,
//! rigid 2D alignment, cutting closed or high-genus meshes into charts that each
//! flatten without overlap, and edge unfolding of faceted meshes into nets.

mod alignment;
mod arap;
mod border_straightening;
mod chart_segmentation;
mod distortion;
mod edge_unfolding;
mod error;
mod exact_unfolding;
mod island_joining;
mod layout_choice;
mod lscm;
mod user_seams;

pub use alignment::{align_rigid, RigidAlignment};
pub use arap::{arap, ArapOptions};
pub use chart_segmentation::{
    cut_into_charts, cut_into_charts_until, Chart, ChartOptions, ChartSet, MAX_CONE_POINTS, MAX_PIECES, MAX_SEAM_LOOPS,
    SMALL_CHART_FACES,
};
pub use distortion::{distortion, Distortion};
pub use edge_unfolding::{
    unfold_net, Net, NetOptions, MAX_NET_FACES, MAX_NET_OVERLAP_TESTS, MAX_NET_WORK, NET_TESTS_PER_FACE_WHEN_SPENT,
};
pub use error::FlattenError;
pub use exact_unfolding::{exact_unfold, UnfoldOptions, Unfolding};
pub use layout_choice::{choose_layout, Layout, LayoutChoice, CONE_POINT_DEFECT, FACETED_FOLD_DEGREES};
pub use lscm::lscm;
pub use user_seams::{open_user_seams, user_seam_edges};

/// A 2D point on the pattern.
pub type Vec2 = nalgebra::Vector2<f64>;

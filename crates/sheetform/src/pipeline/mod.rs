//! The pipelines every front end calls: one module per command, the outputs and report
//! parts they share.

mod asset_relocation;
mod bend;
mod bend_edit;
mod check;
mod context;
mod develop;
mod error;
mod ffd;
mod flatten;
mod mesh_arrays;
mod outputs;
mod photo;
mod scene_file;
mod sheet_report;
mod slit;

pub use asset_relocation::*;
pub use bend::*;
pub use bend_edit::*;
pub use check::*;
pub use context::*;
pub use develop::*;
pub use error::*;
pub use ffd::*;
pub use flatten::*;
pub use mesh_arrays::*;
pub use outputs::*;
pub use photo::*;
pub use scene_file::*;
pub use sheet_report::*;
pub use slit::*;

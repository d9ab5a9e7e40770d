//! End-to-end tests of the `sheetform` command, run in temporary directories. They check
//! the geometry in the files written, not only that the files exist.
//!
//! One module per command; `common` holds the readers they share.

mod bend;
mod check;
mod common;
mod develop;
mod ffd;
mod flatten;
mod gluing;
mod nets;
mod pattern;
mod photo;
mod robustness;
mod schema;
mod serve;
mod slit;

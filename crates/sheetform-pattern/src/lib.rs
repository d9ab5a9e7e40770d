//! Cutting patterns shared by every sheetform method: the [`Pattern`] of a mesh (cut
//! loops, fold/score lines, labels, in millimetres), written as SVG (true size), DXF for
//! laser cutters and plotters, and a tiled true-scale PDF for printing on A4 or Letter.

mod dxf_pattern;
mod error;
mod pattern;
mod pdf_tiles;
mod svg_pattern;

pub use dxf_pattern::{dxf_bytes, DxfUnit};
pub use error::PatternError;
pub use pattern::{pattern_from_mesh, Pattern, PatternOptions};
pub use pdf_tiles::{pdf_tiled, PageSize, PdfOptions, TiledPdf};
pub use svg_pattern::svg_bytes;

/// A point on the pattern (millimetres).
pub type Vec2 = nalgebra::Vector2<f64>;

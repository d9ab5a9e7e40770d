//! Cutting patterns shared by every sheetform method: the [`Pattern`] of a mesh (pieces
//! with cut loops, mountain/valley folds and bending guides, labels, matching seam IDs,
//! glue tabs, in millimetres), packed onto sheets when asked, written as SVG (true size),
//! DXF for laser cutters and plotters, and a tiled true-scale PDF for printing on A4 or
//! Letter.

mod bend_allowance;
mod dxf_pattern;
mod error;
mod glue_tabs;
mod label_placement;
mod material_allowance;
mod pattern;
mod pdf_tiles;
mod seam_matching;
mod sheet_packing;
mod svg_pattern;

pub use bend_allowance::{BendAllowance, BendGeometry, MaterialSide, MAX_BEND_DEGREES, MAX_THICKNESS_MM};
pub use dxf_pattern::{dxf_bytes, DxfUnit};
pub use error::PatternError;
pub use glue_tabs::{
    add_glue_tabs, TabOptions, TabReport, TabSides, TabbedLoops, DEFAULT_CUT_CLEARANCE_MM, DEFAULT_MIN_TAB_FRACTION,
};
pub use material_allowance::{MaterialAllowance, MAX_ALLOWANCE_MM};
pub use pattern::{
    pattern_from_mesh, point_bounds, Fold, FoldStyle, Label, LabelKind, Pattern, PatternOptions, PatternPiece,
    PatternTexture, Placement,
};
pub use pdf_tiles::{pdf_tiled, PageSize, PdfOptions, TiledPdf, DEFAULT_MAX_PAGES, MAX_PAGES, MAX_TEXTURE_PIXELS};
pub use seam_matching::{match_seams, SeamRun};
pub use sheet_packing::{
    arrange_in_rows, pack_pieces, rotated, sheet_size_from_text, smallest_bounding_rotation, SheetOptions,
    MAX_SHEET_GAP_MM,
};
pub use svg_pattern::svg_bytes;

/// A point on the pattern (millimetres).
pub type Vec2 = nalgebra::Vector2<f64>;

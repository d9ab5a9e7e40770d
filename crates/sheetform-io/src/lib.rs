//! File formats of sheetform: exports of a [`sheetform_mesh::SheetMesh`] (OBJ with the
//! flat pattern as `vt` at 1:1 scale, glTF 2.0 binary, STL, the flat pattern as SVG at
//! true size) and atomic file writing. Writers render into memory; [`write_atomic`] puts
//! bytes on disk through a temporary file and a rename, so a failed run never leaves a
//! half-written file.

mod atomic;
mod error;
mod glb;
mod obj;
mod stl;
mod svg_pattern;

pub use atomic::write_atomic;
pub use error::IoError;
pub use glb::{glb_bytes, Texture, GLB_FLAT_ATTRIBUTE};
pub use obj::obj_string;
pub use stl::stl_bytes;
pub use svg_pattern::{svg_pattern, SvgOptions};

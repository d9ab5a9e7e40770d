//! File formats of sheetform: exports of a [`sheetform_mesh::SheetMesh`] (OBJ with the
//! flat pattern as `vt` at 1:1 scale, glTF 2.0 binary, STL, colour maps), mesh readers and
//! atomic file writing. Patterns (SVG, DXF, PDF) are in `sheetform-pattern`. Writers render into memory; [`write_atomic`] puts
//! bytes on disk through a temporary file and a rename, so a failed run never leaves a
//! half-written file.

mod atomic;
mod bounded_read;
mod colour_map;
mod error;
mod file_set;
mod glb;
mod image_file;
mod mesh_read;
mod obj;
mod photo_exif;
mod point_cloud;
mod stl;

pub use atomic::write_atomic;
pub use bounded_read::{read_bounded, MAX_MESH_FILE_BYTES, MAX_SCENE_FILE_BYTES};
pub use colour_map::{colour_ramp, ply_vertex_colours};
pub use error::IoError;
pub use file_set::{is_plain_relative, replace_file_set};
pub use glb::{glb_bytes, glb_bytes_projected, glb_vertex_colours, Texture, GLB_FLAT_ATTRIBUTE};
pub use image_file::{ImageError, MAX_DECODED_JPEG_BYTES};
pub use mesh_read::{mesh_from_bytes, parse_obj, parse_off, parse_ply, parse_stl, read_mesh, MeshReadError};
pub use obj::obj_string;
pub use photo_exif::focal_length_35mm_from_exif;
pub use point_cloud::read_points;
pub use sheetform_mesh::UpAxis;
pub use stl::stl_bytes;

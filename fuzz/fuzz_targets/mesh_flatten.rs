//! Any bytes as a mesh file (the first byte picks OBJ, OFF, PLY or STL), then `flatten`
//! with every output rendered (charts, nets, pattern SVG/DXF/PDF).
#![no_main]
mod common;

use libfuzzer_sys::fuzz_target;
use sheetform::pipeline::{run_flatten, FlattenOptions};

fuzz_target!(|data: &[u8]| {
    let Some(mesh) = common::mesh_from_fuzz_bytes(data) else {
        return;
    };
    if let Ok(run) = run_flatten(mesh, &FlattenOptions::default(), &common::context()) {
        common::assert_finite(&run.files);
    }
});

//! Any bytes as a mesh file (the first byte picks OBJ, OFF, PLY or STL), then `check`.
#![no_main]
mod common;

use libfuzzer_sys::fuzz_target;
use sheetform::io::mesh_from_bytes;
use sheetform::pipeline::{run_check, CheckOptions};
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let Some((&kind, bytes)) = data.split_first() else {
        return;
    };
    let name = ["m.obj", "m.off", "m.ply", "m.stl"][kind as usize % 4];
    let Ok(mesh) = mesh_from_bytes(Path::new(name), bytes) else {
        return;
    };
    if let Ok(run) = run_check(mesh, &CheckOptions::default(), &common::context()) {
        common::assert_finite(&run.files);
    }
});

//! Any bytes as a mesh file (the first byte picks OBJ, OFF, PLY or STL), then `check`.
#![no_main]
mod common;

use libfuzzer_sys::fuzz_target;
use sheetform::pipeline::{run_check, CheckOptions};

fuzz_target!(|data: &[u8]| {
    let Some(mesh) = common::mesh_from_fuzz_bytes(data) else {
        return;
    };
    if let Ok(run) = run_check(mesh, &CheckOptions::default(), &common::context()) {
        common::assert_finite(&run.files);
    }
});

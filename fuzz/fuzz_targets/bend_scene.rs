//! Any text as a `bend` scene, through the whole pipeline with every output rendered.
#![no_main]
mod common;

use libfuzzer_sys::fuzz_target;
use sheetform::pipeline::{run_bend, BendRunOptions};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let Ok(scene) = sheetform::bend::BendScene::from_json(text) else {
        return;
    };
    if let Ok(run) = run_bend(&scene, &BendRunOptions::default(), &common::context()) {
        common::assert_finite(&run.files);
    }
});

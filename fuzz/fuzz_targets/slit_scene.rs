//! Any text as a `slit` scene, through the whole pipeline with every output rendered.
#![no_main]
mod common;

use libfuzzer_sys::fuzz_target;
use sheetform::pipeline::{run_slit, SlitRunOptions};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let Ok(scene) = sheetform::slit::SlitScene::from_json(text) else {
        return;
    };
    if let Ok(run) = run_slit(&scene, &SlitRunOptions::default(), &common::context()) {
        common::assert_finite(&run.files);
    }
});

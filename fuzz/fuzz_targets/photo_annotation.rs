//! Any text as a `photo` annotation (JSON) or drawing (SVG), through the whole
//! pipeline, with the bundled photographs (`examples/photo`) as the assets it may read.
#![no_main]
mod common;

use libfuzzer_sys::fuzz_target;
use sheetform::pipeline::{run_photo, PhotoInput, PhotoRunOptions};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let Ok(input) = PhotoInput::from_text(text) else { return };
    if let Ok(run) = run_photo(&input, &PhotoRunOptions::default(), &common::photo_context()) {
        common::assert_finite(&run.files);
    }
});

//! `sheetform serve` in a browser (issue 20): the Playwright script
//! `apps/serve/web/tests/editor.test.mjs` drives Debian's chromium against this binary
//! (loading an example, dragging a control point with the mouse, undo, a drag stopped
//! at the boundary of the admissible shapes, the server's confinement and faults). Its screenshots and the measured
//! round trip of an edit go to `target/tmp/browser-tests/`.

use crate::common::repo;
use std::process::Command;

#[test]
fn the_web_editor_passes_its_browser_test() {
    let output_dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("browser-tests");
    let script = repo().join("apps/serve/web/tests/editor.test.mjs");
    let output = Command::new("node")
        .arg(&script)
        .arg(env!("CARGO_BIN_EXE_sheetform"))
        .arg(repo())
        .arg(&output_dir)
        .output()
        .expect("node runs (README prerequisites: Node.js and chromium)");
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "browser test failed:\n{stdout}\n{stderr}");
    let figures: serde_json::Value =
        serde_json::from_str(stdout.lines().last().unwrap_or("")).expect("the figures line");
    let round_trip = &figures["bend_1000_rulings_round_trip_ms"];
    assert!(round_trip["count"].as_u64().unwrap() >= 20, "{figures}");
    eprintln!("browser test figures (not a timing assertion): {figures}");
    for shot in ["bend.png", "bend-boundary.png"] {
        let bytes = std::fs::read(output_dir.join(shot)).expect("the screenshot");
        assert!(bytes.starts_with(b"\x89PNG") && bytes.len() > 10_000, "{shot}");
    }
}

//! What every target shares: a run context that can read no file, and the check that a
//! run that succeeded wrote only finite numbers.

use sheetform::pipeline::RunContext;

#[allow(dead_code)]
/// A context rooted at an empty directory: a fuzzed scene naming an asset gets an error.
pub fn context() -> RunContext<'static> {
    let root = std::env::temp_dir().join("sheetform-fuzz-empty");
    let _ = std::fs::create_dir_all(&root);
    RunContext::new(root)
}

#[allow(dead_code)]
/// A context rooted at the bundled photographs (`examples/photo`).
pub fn photo_context() -> RunContext<'static> {
    RunContext::new(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/photo"))
}

#[allow(dead_code)]
/// Any bytes as a mesh file: the first byte picks OBJ, OFF, PLY or STL, the rest is the
/// file; `None` when the reader refuses it.
pub fn mesh_from_fuzz_bytes(data: &[u8]) -> Option<sheetform::mesh::TriangleMesh> {
    let (&kind, bytes) = data.split_first()?;
    let name = ["m.obj", "m.off", "m.ply", "m.stl"][kind as usize % 4];
    sheetform::io::mesh_from_bytes(std::path::Path::new(name), bytes).ok()
}

/// Every `v` and `vt` line of the OBJ files has finite numbers ("no NaN reaches a file").
pub fn assert_finite(files: &[(String, Vec<u8>)]) {
    for (name, bytes) in files {
        if !name.ends_with(".obj") {
            continue;
        }
        for line in String::from_utf8_lossy(bytes).lines() {
            if line.starts_with("v ") || line.starts_with("vt ") {
                for token in line.split_whitespace().skip(1) {
                    let x: f64 = token.parse().unwrap_or(f64::NAN);
                    assert!(x.is_finite(), "{name}: `{line}`");
                }
            }
        }
    }
}

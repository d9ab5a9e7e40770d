//! Embeds the editor's front end: our own files from `web/src/` and three.js from npm
//! (`web/package.json` pins the version; `npm ci` installs it when it is missing or
//! another version is installed). No third-party code is committed into the tree.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The files of the `three` package the editor loads: (path inside the package, name
/// served under `/vendor/three/`).
const THREE_FILES: [(&str, &str); 3] = [
    ("build/three.module.js", "three.module.js"),
    ("build/three.core.js", "three.core.js"),
    (
        "examples/jsm/controls/OrbitControls.js",
        "addons/controls/OrbitControls.js",
    ),
];

/// `name`'s version pinned in a package.json's dependencies, or (`name` = "version") the
/// package's own version.
fn pinned_version(package_json: &Path, name: &str) -> Option<String> {
    let text = std::fs::read_to_string(package_json).ok()?;
    let value: serde_json::Value = serde_json::from_str(&text).ok()?;
    if name == "version" {
        return value.get("version")?.as_str().map(str::to_string);
    }
    ["dependencies", "devDependencies"]
        .iter()
        .find_map(|key| value.get(key)?.get(name)?.as_str().map(str::to_string))
}

fn main() {
    let manifest = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets it"));
    let web = manifest.join("web");
    println!("cargo:rerun-if-changed=web/package.json");
    println!("cargo:rerun-if-changed=web/package-lock.json");
    println!("cargo:rerun-if-changed=web/node_modules/three/package.json");
    let three = web.join("node_modules/three");
    let wanted = pinned_version(&web.join("package.json"), "three").expect("web/package.json pins `three`");
    let installed = pinned_version(&three.join("package.json"), "version");
    if installed.as_deref() != Some(wanted.as_str()) {
        let status = Command::new("npm")
            .args(["ci", "--no-audit", "--no-fund", "--loglevel=error"])
            .current_dir(&web)
            .status();
        if !matches!(status, Ok(s) if s.success()) {
            panic!(
                "sheetform serve embeds three.js {wanted} from npm: install Node.js and npm (see the \
                 README's prerequisites), then build again or run `npm ci --prefix apps/serve/web`"
            );
        }
    }
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets it")).join("vendor/three");
    for (source, target) in THREE_FILES {
        let target = out.join(target);
        std::fs::create_dir_all(target.parent().expect("a file in a directory")).expect("OUT_DIR is writable");
        std::fs::copy(three.join(source), &target).unwrap_or_else(|e| panic!("three.js file {source} (from npm): {e}"));
    }
}

//! Embeds the editor's front end: our own files from `web/src/` and three.js from npm
//! (`web/package.json` pins the version; `npm ci` installs it when it is missing or
//! another version is installed). No third-party code is committed into the tree.
//!
//! Without npm (or with `SHEETFORM_BUILD_WITHOUT_NPM=1`, which simulates that) the build
//! goes on with a warning: the binary is whole (every command, the server's API) but its
//! editor page says that three.js was not embedded and how to get it (cfg
//! `sheetform_without_three`).

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
    println!("cargo:rerun-if-env-changed=SHEETFORM_BUILD_WITHOUT_NPM");
    println!("cargo::rustc-check-cfg=cfg(sheetform_without_three)");
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets it")).join("vendor/three");
    let without_npm = std::env::var_os("SHEETFORM_BUILD_WITHOUT_NPM").is_some_and(|v| v == "1");
    if without_npm || installed.as_deref() != Some(wanted.as_str()) {
        let status = if without_npm {
            None
        } else {
            Command::new("npm")
                .args(["ci", "--no-audit", "--no-fund", "--loglevel=error"])
                .current_dir(&web)
                .status()
                .ok()
        };
        if !status.is_some_and(|s| s.success()) {
            println!(
                "cargo:warning=sheetform serve is built without its web editor: it embeds three.js {wanted} \
                 from npm, which could not be installed here. Every command and the server's API work; for the \
                 editor install Node.js and npm (see the README's prerequisites) and build again, or run \
                 `npm ci --prefix apps/serve/web`."
            );
            println!("cargo:rustc-cfg=sheetform_without_three");
            // Empty stand-ins, so that the files the binary embeds exist.
            for (_, target) in THREE_FILES {
                let target = out.join(target);
                std::fs::create_dir_all(target.parent().expect("a file in a directory")).expect("OUT_DIR is writable");
                std::fs::write(&target, b"").expect("OUT_DIR is writable");
            }
            return;
        }
    }
    for (source, target) in THREE_FILES {
        let target = out.join(target);
        std::fs::create_dir_all(target.parent().expect("a file in a directory")).expect("OUT_DIR is writable");
        std::fs::copy(three.join(source), &target).unwrap_or_else(|e| panic!("three.js file {source} (from npm): {e}"));
    }
}

#!/usr/bin/env bash
# The test command (README, CI): installs the Khronos glTF validator the end-to-end tests
# use, then runs every test of the workspace (unit, oracle, property, CLI, doc tests).
set -euo pipefail
cd "$(dirname "$0")/.."
npm ci --prefix tools/gltf-validate --no-audit --no-fund --loglevel=error
cargo test --workspace --all-targets
cargo test --workspace --doc

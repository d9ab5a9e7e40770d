#!/usr/bin/env bash
# Builds the Python package's wheel (issue 39): one abi3 wheel for every CPython >= 3.9,
# manylinux-tagged by maturin's audit (the oldest glibc its symbols allow), into
# target/wheels/. Prints the wheel's path. `pip install target/wheels/sheetform-*.whl`
# then installs in seconds without Rust.
set -euo pipefail
cd "$(dirname "$0")/.."
python3 -m pip install --quiet --disable-pip-version-check "maturin>=1.9.4,<2" >&2
rm -rf target/wheels
python3 -m maturin build --quiet --release -m bindings/python/Cargo.toml --out target/wheels >&2
ls target/wheels/sheetform-*-abi3-manylinux*.whl

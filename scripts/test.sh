#!/usr/bin/env bash
# The test command (README, CI): installs the outside checkers the end-to-end tests use
# (Khronos glTF validator, ezdxf, pdftoppm), then runs every test of the workspace (unit,
# oracle, property, CLI, doc tests) and of the Python package (pytest).
set -euo pipefail
cd "$(dirname "$0")/.."
npm ci --prefix tools/gltf-validate --no-audit --no-fund --loglevel=error
# Outside readers the pattern tests check against: ezdxf (DXF) and poppler's pdftoppm (PDF).
python3 -c "import ezdxf" 2>/dev/null || python3 -m pip install --quiet --disable-pip-version-check ezdxf
if ! command -v pdftoppm >/dev/null; then
  apt-get update -qq && apt-get install -y -qq poppler-utils >/dev/null
fi
# The web editor's browser test: Debian's chromium driven by playwright-core (installed
# with the editor's npm packages, apps/serve/web/package.json).
if ! command -v chromium >/dev/null; then
  apt-get update -qq && apt-get install -y -qq chromium >/dev/null
fi
npm ci --prefix apps/serve/web --no-audit --no-fund --loglevel=error
cargo test --workspace --all-targets
cargo test --workspace --doc
# The examples assert their results: run them (dev profile, built by the tests above).
examples_out=$(mktemp -d)
trap 'rm -rf "$examples_out"' EXIT
cargo run --quiet -p sheetform --example scan_fitted_chair -- "$examples_out/scan-fitted-chair"
for scene in examples/slit/*.json; do
  cargo run --quiet -p sheetform-slit --example solve_scene -- "$scene"
done
for name in two-panels duct skirt trousers; do
  cargo run --quiet -p sheetform-ffd --example run_scene -- "examples/ffd/$name.json"
done
# The Python package (bindings/python, issues 21 and 39): built as the abi3 manylinux
# wheel users install (scripts/build_wheel.sh, kept in target/wheels/), installed with its
# test extra into a fresh virtual environment, and tested there, not from the source
# tree (pytest): results against the CLI built above, trimesh round trips, errors, the
# editor, the stubs (mypy's stubtest), the example, batch jobs on a Dask LocalCluster.
wheel=$(bash scripts/build_wheel.sh)
rm -rf target/python-venv
python3 -m venv target/python-venv
target/python-venv/bin/python -m pip install --quiet --disable-pip-version-check "${wheel}[test]"
root=$PWD
(cd bindings/python/tests && SHEETFORM_CLI="$root/target/debug/sheetform" "$root/target/python-venv/bin/python" -m pytest -q -p no:cacheprovider .)

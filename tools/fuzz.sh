#!/usr/bin/env bash
# Fuzzes one target (or all) of fuzz/ with cargo-fuzz (libFuzzer), on stable Rust
# (RUSTC_BOOTSTRAP=1: cargo-fuzz works on stable that way), from seed corpora built out of
# the bundled examples and test meshes.
#
#   tools/fuzz.sh TARGET|all SECONDS
#
# Limits per input: 30 s (-timeout) and 4 GB (-rss_limit_mb); a crash, a timeout or an
# out-of-memory input is saved under fuzz/artifacts/TARGET/ and the script fails. It
# fails too when cargo fuzz itself fails (the fuzz crate does not build, libFuzzer does
# not start) or libFuzzer does not report its "Done N runs" at the time limit.
# Installs cargo-fuzz when it is missing.
set -euo pipefail
cd "$(dirname "$0")/.."
target=${1:?target or all}
seconds=${2:?seconds}
export RUSTC_BOOTSTRAP=1
command -v cargo-fuzz >/dev/null || cargo install --quiet --locked cargo-fuzz
targets=(mesh_check mesh_flatten bend_scene slit_scene ffd_scene photo_annotation serve_routes)
[ "$target" = all ] || targets=("$target")
seed() {
  local dir=fuzz/corpus/$1
  mkdir -p "$dir"
  case $1 in
    mesh_check | mesh_flatten)
      # The first byte picks the format: 0 OBJ, 1 OFF, 2 PLY, 3 STL.
      local kind
      for mesh in examples/meshes/*.{obj,stl} tests/data/*.obj crates/*/tests/data/*.{obj,off,ply,stl}; do
        [ -f "$mesh" ] || continue
        [ "$(stat -c %s "$mesh")" -le 200000 ] || continue
        case $mesh in *.obj) kind='\x00' ;; *.off) kind='\x01' ;; *.ply) kind='\x02' ;; *.stl) kind='\x03' ;; esac
        { printf "$kind"; cat "$mesh"; } > "$dir/$(basename "$mesh")"
      done
      printf '\x00v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 1\nf 1 2 3\nf 2 4 3\n' > "$dir/two-triangles.obj"
      printf '\x01OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n1 1 1\n3 0 1 2\n3 1 3 2\n' > "$dir/two-triangles.off"
      ;;
    bend_scene) cp examples/*.json "$dir/" ;;
    slit_scene) cp examples/slit/*.json "$dir/" ;;
    ffd_scene) for f in examples/ffd/*.json; do case $f in *100k*) ;; *) cp "$f" "$dir/" ;; esac; done ;;
    photo_annotation) cp examples/photo/*.json examples/photo/*.svg examples/photo/synthetic/*.json "$dir/" 2>/dev/null || true ;;
    serve_routes)
      # The first byte picks the route (fuzz/fuzz_targets/serve_routes.rs): 0 bend,
      # 1 a bend edit, 2 slit, 3 FFD, 4 photo, 5 to 8 meshes, 9 relocate, 10 save,
      # 11 to 15 downloads, 16 a mesh laid out whole (the mesh mode's "whole"), 17 a
      # mesh developed (the mesh mode's "develop"), 18 developed with a mirror plane.
      { printf '\x00'; cat examples/bent-rectangle.json; } > "$dir/bend.json"
      printf '\x01{"kind": "move_control_point", "region": 0, "index": 1, "position": [80, 20, 0]}' > "$dir/edit-move.json"
      printf '\x01{"kind": "drag_preserving_length", "region": 0, "index": 2, "position": [150, -10, 40]}' > "$dir/edit-drag.json"
      printf '\x01{"kind": "drag_end_handles", "region": 0}' > "$dir/edit-handles.json"
      { printf '\x02'; cat examples/slit/chair.json; } > "$dir/slit.json"
      { printf '\x03'; cat examples/ffd/duct.json; } > "$dir/ffd.json"
      { printf '\x04'; cat examples/photo/coffee-cup.json; } > "$dir/photo.json"
      { printf '\x05'; cat examples/meshes/gift-box.obj; } > "$dir/mesh.obj"
      printf '\x06OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n1 1 1\n3 0 1 2\n3 1 3 2\n' > "$dir/mesh.off"
      { printf '\x10'; cat examples/meshes/crumpled-developable.obj; } > "$dir/mesh-whole.obj"
      { printf '\x11'; cat examples/meshes/gift-box.obj; } > "$dir/mesh-develop.obj"
      { printf '\x12'; cat examples/meshes/gift-box.obj; } > "$dir/mesh-develop-mirror.obj"
      { printf '\x09'; cat examples/photo/coffee-cup.json; } > "$dir/relocate.json"
      printf '\x0a{"a": 1}' > "$dir/save.json"
      ;;
  esac
}
log=$(mktemp)
trap 'rm -f "$log"' EXIT
for t in "${targets[@]}"; do
  seed "$t"
  echo "fuzzing $t for $seconds s"
  # The whole output is kept: the summary lines are shown, and when cargo fuzz fails
  # (the fuzz crate does not build, libFuzzer does not start or stops early) its tail.
  status=0
  (cd fuzz && cargo fuzz run -O "$t" "corpus/$t" -- \
    -max_total_time="$seconds" -timeout=30 -rss_limit_mb=4096 -print_final_stats=1) >"$log" 2>&1 || status=$?
  grep -E "^(#[0-9]+[[:space:]]+DONE|Done [0-9]+ runs|stat::number_of_executed_units|stat::peak_rss_mb|==[0-9]+== ERROR|SUMMARY|artifact_prefix|Test unit written)" "$log" || true
  # libFuzzer also saves slow inputs (over 10 s with its instrumentation) as slow-unit-*:
  # reported, not failures (the limit is -timeout).
  if ls "fuzz/artifacts/$t/"{crash,timeout,oom,leak}-* >/dev/null 2>&1; then
    echo "fuzz/artifacts/$t/ holds failing inputs" >&2
    exit 1
  fi
  # When the time limit ends the run, libFuzzer prints "Done N runs in S second(s)" and
  # exits with 0; anything else is a failure, even with no artifact saved.
  if [ "$status" -ne 0 ]; then
    tail -n 40 "$log" >&2
    echo "cargo fuzz run $t failed (exit status $status) before its time limit ended normally" >&2
    exit 1
  fi
  if ! grep -qE "^Done [0-9]+ runs" "$log"; then
    tail -n 40 "$log" >&2
    echo "cargo fuzz run $t printed no \"Done N runs\" line: libFuzzer did not run to its time limit" >&2
    exit 1
  fi
  ls "fuzz/artifacts/$t/"slow-unit-* 2>/dev/null | sed 's/^/slow (not a failure): /' || true
done

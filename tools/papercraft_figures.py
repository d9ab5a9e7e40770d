#!/usr/bin/env python3
"""The figures of docs/papercraft-comparison.md: `sheetform flatten` on the issue's models,
with every default and with `--sheet a4`, each output read back by
tools/pattern_audit.py (the files, not the report), one Markdown row a run.

    pip install trimesh ezdxf
    cargo build --release
    python3 tools/make_primitive_objs.py out/primitives
    python3 tools/papercraft_figures.py out/primitives [OUT]

Columns: pieces and PDF pages (A4); glued edge pairs; pairs with a tab on both copies /
on neither; seams and seams whose ID is not on both copies; the shallowest tab and the
least clearance between a tab and another cut line (mm); pairs of cut lines of one
piece closer than 1 mm that share no point (narrow slits); the run's time.
"""
import json
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
BIN = os.path.join(HERE, "..", "target", "release", "sheetform")


def row(name, mesh, extra, out):
    start = time.perf_counter()
    done = subprocess.run([BIN, "flatten", mesh, "-o", out, "-q", *extra], capture_output=True, text=True)
    seconds = time.perf_counter() - start
    if done.returncode not in (0, 5):
        return f"| {name} | {' '.join(extra) or 'defaults'} | failed: {done.stderr.strip()} |"
    r = json.load(open(os.path.join(out, "report.json")))
    a = json.loads(subprocess.run([sys.executable, os.path.join(HERE, "pattern_audit.py"), out],
                                  capture_output=True, text=True, check=True).stdout)
    p = r["pattern"]
    if a.get("pieces_unregistered"):
        audit = f"{a['pieces_unregistered']} pieces not found in the SVG"
        return f"| {name} | {' '.join(extra) or 'defaults'} | {r['layout']} | {p['piece_count']} / {p['page_count']} | {audit} |"
    fmt = lambda x: "—" if x is None else f"{x:.2f}"
    missing = a["seams_id_one_side"] + a["seams_id_none"] + a["seams_id_mismatch"]
    return (f"| {name} | {' '.join(extra) or 'defaults'} | {r['layout']} | {p['piece_count']} / {p['page_count']} "
            f"| {a['glued_edge_pairs']} | {a['pairs_tab_both']} / {a['pairs_tab_none']} "
            f"| {a['seams']} / {missing} | {fmt(a['tab_depth_min_mm'])} / {fmt(a['tab_clearance_min_mm'])} "
            f"| {a['slit_pairs_closer_than_clearance']} | {seconds:.2f} s |")


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    primitives = sys.argv[1]
    out = sys.argv[2] if len(sys.argv) == 3 else tempfile.mkdtemp()
    repo = os.path.join(HERE, "..")
    models = [
        ("gift box (12)", os.path.join(repo, "examples/meshes/gift-box.obj"), []),
        ("box (12)", os.path.join(primitives, "box.obj"), []),
        ("closed cylinder (128)", os.path.join(primitives, "cylinder.obj"), []),
        ("icosphere (320)", os.path.join(primitives, "icosphere.obj"), []),
        ("torus (2 048)", os.path.join(primitives, "torus.obj"), []),
        ("bunny (99), 150 mm high", os.path.join(repo, "examples/meshes/bunny-99.stl"), ["--size", "150"]),
    ]
    print("| model (faces) | options | layout | pieces / pages | glued pairs | both-tab / no-tab pairs "
          "| seams / IDs not on both | tab depth min / clearance min (mm) | narrow slits | time |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name, mesh, extra in models:
        for options in ([], ["--sheet", "a4"]):
            target = os.path.join(out, f"{len(os.listdir(out)) if os.path.isdir(out) else 0}")
            print(row(name, mesh, extra + options, target), flush=True)


if __name__ == "__main__":
    main()

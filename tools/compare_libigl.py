#!/usr/bin/env python3
"""Times libigl's LSCM against `sheetform flatten --method lscm` on the same meshes.

The meshes are developable half-cylinder grids (radius 100, height 200), the ones
`cargo bench -p sheetform --bench flatten` uses. For libigl the timed call is
`igl.lscm(V, F, b, bc)` with two pinned boundary vertices; for sheetform it is the
`solve_ms` of report.json (the LSCM solve alone, reading and writing excluded). Both run
on one machine in one invocation; compare the ratio.

Usage:  pip install libigl numpy scipy
        cargo build --release
        python3 tools/compare_libigl.py [--large]     # --large adds 1M faces
"""
import json, math, os, subprocess, sys, tempfile, time

import numpy as np
import igl

SIZES = [("1k", 25, 20), ("10k", 100, 50), ("100k", 250, 200)]
if "--large" in sys.argv:
    SIZES.append(("1M", 1000, 500))
BIN = os.path.join(os.path.dirname(__file__), "..", "target", "release", "sheetform")


def cylinder(nu, nv):
    a = np.pi * np.arange(nu + 1) / nu
    z = 200.0 * np.arange(nv + 1) / nv
    A, Z = np.meshgrid(a, z, indexing="ij")
    V = np.stack([100 * np.cos(A), 100 * np.sin(A), Z], axis=-1).reshape(-1, 3)
    idx = lambda i, j: i * (nv + 1) + j
    I, J = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    I, J = I.ravel(), J.ravel()
    F = np.concatenate([np.stack([idx(I, J), idx(I + 1, J), idx(I + 1, J + 1)], 1),
                        np.stack([idx(I, J), idx(I + 1, J + 1), idx(I, J + 1)], 1)])
    return V, F.astype(np.int64)


def write_obj(path, V, F):
    with open(path, "w") as f:
        f.write("".join(f"v {x:.17g} {y:.17g} {z:.17g}\n" for x, y, z in V))
        f.write("".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in F))


def best_of(n, fn):
    best = math.inf
    for _ in range(n):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return best


print("| faces | libigl LSCM | sheetform LSCM | sheetform / libigl |")
print("|---|---|---|---|")
with tempfile.TemporaryDirectory() as tmp:
    for label, nu, nv in SIZES:
        V, F = cylinder(nu, nv)
        loop = igl.boundary_loop(F)
        b = np.array([loop[0], loop[len(loop) // 2]], dtype=np.int64)
        bc = np.array([[0.0, 0.0], [1.0, 0.0]])
        runs = 3 if len(F) < 500_000 else 1
        t_igl = best_of(runs, lambda: igl.lscm(V, F, b, bc))
        path = os.path.join(tmp, f"cyl-{label}.obj")
        write_obj(path, V, F)
        t_ours = math.inf
        for _ in range(runs):
            out = os.path.join(tmp, f"out-{label}")
            subprocess.run([BIN, "flatten", path, "-o", out, "--method", "lscm", "-q"], check=True)
            t_ours = min(t_ours, json.load(open(os.path.join(out, "report.json")))["timings"]["solve_ms"] / 1e3)
        print(f"| {len(F):,} ({label}) | {t_igl * 1e3:.1f} ms | {t_ours * 1e3:.1f} ms | {t_ours / t_igl:.2f} |", flush=True)

#!/usr/bin/env python3
"""Corners of a pattern's cut outline, read from the files `sheetform` wrote.

    python3 tools/cut_corners.py OUT_DIR [--angle DEG]

Reads OUT_DIR/model.obj (the `vt` pattern at 1:1 of the model) and the pattern scale and
model unit from report.json (inputs, not results). Walks every border loop of the flat
pattern (edges of one `vt` face only, tabs not included) and counts the corners where
the cut turns by more than DEG degrees (default 30): the turns a knife or scissors must
make. Prints one JSON object: the cut length (mm as printed), corners, corners per 100 mm
of cut, and the same for the cut edges that are seams (their 3D edge has a face on each
side in the model; the model's own boundary left out). Used for the `develop` seam
smoothing figures in docs/benchmarks-history.md (session 32)."""
import json, math, sys
from collections import defaultdict

def main():
    out = sys.argv[1]
    angle = 30.0
    if "--angle" in sys.argv:
        angle = float(sys.argv[sys.argv.index("--angle") + 1])
    v, vt, faces, scale = [], [], [], 1.0
    unit_mm = {"mm": 1.0, "cm": 10.0, "m": 1000.0, "in": 25.4}
    for line in open(f"{out}/model.obj"):
        w = line.split()
        if not w:
            continue
        if w[0] == "v":
            v.append(tuple(map(float, w[1:4])))
        elif w[0] == "vt":
            vt.append(tuple(map(float, w[1:3])))
        elif w[0] == "f":
            faces.append([tuple(int(x) - 1 for x in c.split("/")[:2]) for c in w[1:]])
    report = json.load(open(f"{out}/report.json"))
    unit = unit_mm.get(report.get("model_unit", "mm"), 1.0) * report.get("pattern", {}).get("scale", 1.0)
    # vt are in the model's unit at 1:1 (flatten's convention): scale to mm.
    flat_edges = defaultdict(int)
    owner = {}
    for f in faces:
        for k in range(len(f)):
            a, b = f[k], f[(k + 1) % len(f)]
            key = tuple(sorted((a[1], b[1])))
            flat_edges[key] += 1
            owner[(a[1], b[1])] = (a[0], b[0])
    # The model's pieces may repeat a vertex on each side of a seam: edges are matched by
    # their 3D end points.
    key3 = lambda i: tuple(round(c, 9) for c in v[i])
    mesh_edges = defaultdict(int)
    for f in faces:
        for k in range(len(f)):
            a, b = key3(f[k][0]), key3(f[(k + 1) % len(f)][0])
            mesh_edges[tuple(sorted((a, b)))] += 1
    nxt = {}
    for (a, b), (pa, pb) in owner.items():
        if flat_edges[tuple(sorted((a, b)))] == 1:
            nxt[a] = (b, mesh_edges[tuple(sorted((key3(pa), key3(pb))))] == 2)
    seen = set()
    total = seam_len = 0.0
    corners = seam_corners = 0
    for start in nxt:
        if start in seen:
            continue
        loop = []
        x = start
        while x not in seen:
            seen.add(x)
            loop.append(x)
            x = nxt[x][0]
        n = len(loop)
        for i in range(n):
            a, b, c = loop[i - 1], loop[i], loop[(i + 1) % n]
            pa, pb, pc = vt[a], vt[b], vt[c]
            e = math.dist(pb, pc) * unit
            total += e
            seam = nxt[b][1]
            if seam:
                seam_len += e
            u = (pb[0] - pa[0], pb[1] - pa[1])
            w = (pc[0] - pb[0], pc[1] - pb[1])
            turn = math.degrees(abs(math.atan2(u[0] * w[1] - u[1] * w[0], u[0] * w[0] + u[1] * w[1])))
            if turn > angle:
                corners += 1
                if nxt[a][1] and seam:
                    seam_corners += 1
    print(json.dumps({
        "cut_length_mm": round(total, 1),
        "corners": corners,
        "corners_per_100mm": round(100 * corners / max(total, 1e-9), 2),
        "seam_cut_length_mm": round(seam_len, 1),
        "seam_corners": seam_corners,
        "seam_corners_per_100mm": round(100 * seam_corners / max(seam_len, 1e-9), 2),
    }))

main()

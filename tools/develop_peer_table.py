#!/usr/bin/env python3
"""The develop table in the issue's columns (issue 36: GIT, Stein et al., EvoDevelop), every
figure read from the files `sheetform develop` writes, not from its report's counts:

    python3 tools/develop_targets.py /tmp/dt          # the trimesh targets (torus, spheres, capsule)
    python3 tools/develop_peer_table.py target/release/sheetform /tmp/dt /tmp/peer-table

For each row it runs `sheetform develop MESH --size 200 -o OUT [options]` under
/usr/bin/time and prints a Markdown row: CPU s; the largest and mean angle defect at the
vertices inside the printed pieces (degrees, from model.obj: `v` positions, pieces the
connected parts of `vt`); the printed pieces and those of at least 1 % of the area (GIT's
column); the seam length (edges whose two faces give a vertex different `vt`s, 3D length)
over the bounding-box diagonal; the Hausdorff distance over the diagonal (report.json
`develop.hausdorff_relative`, a sampled two-sided surface distance); the pattern stretch
(largest |flat edge length / 3D edge length - 1| over every face edge, `vt` being the
pattern at 1:1).
"""
import json
import math
import subprocess
import sys
from collections import defaultdict
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent


def rows(targets):
    meshes = REPO / "examples/meshes"
    return [
        ("coffee cup", meshes / "coffee-cup.obj", []),
        ("coffee cup", meshes / "coffee-cup.obj", ["--max-distance", "0.5%", "--max-pieces", "25"]),
        ("Spot", meshes / "spot.obj", []),
        ("koala", meshes / "koala.obj", []),
        ("koala", meshes / "koala.obj", ["--max-pieces", "30"]),
        ("wing nut", meshes / "wingnut.obj", []),
        ("wing nut", meshes / "wingnut.obj", ["--cone-angle", "5.7"]),
        ("torus", targets / "torus.obj", []),
        ("icosphere", targets / "sphere.obj", []),
        ("UV sphere", targets / "uvsphere.obj", []),
        ("capsule", targets / "capsule.obj", []),
    ]


def read_obj(path):
    v, vt, faces = [], [], []
    for line in open(path):
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "v":
            v.append(tuple(map(float, parts[1:4])))
        elif parts[0] == "vt":
            vt.append(tuple(map(float, parts[1:3])))
        elif parts[0] == "f":
            corners = []
            for c in parts[1:4]:
                ids = c.split("/")
                corners.append((int(ids[0]) - 1, int(ids[1]) - 1))
            faces.append(corners)
    return v, vt, faces


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def norm(a):
    return math.sqrt(sum(x * x for x in a))


def angle(a, b):
    c = sum(x * y for x, y in zip(a, b)) / (norm(a) * norm(b))
    return math.acos(max(-1.0, min(1.0, c)))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def measure(obj):
    v, vt, faces = read_obj(obj)
    # Pieces: faces joined by a shared texture vertex.
    parent = list(range(len(vt)))

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    for f in faces:
        for k in range(1, 3):
            parent[find(f[k][1])] = find(f[0][1])
    piece_area = defaultdict(float)
    for f in faces:
        a, b, c = (v[i] for i, _ in f)
        piece_area[find(f[0][1])] += 0.5 * norm(cross(sub(b, a), sub(c, a)))
    total = sum(piece_area.values())
    large = sum(1 for area in piece_area.values() if area >= 0.01 * total)
    # Edges of the pattern (vt pairs): used once = on a piece's border.
    uses = defaultdict(int)
    for f in faces:
        for k in range(3):
            a, b = f[k][1], f[(k + 1) % 3][1]
            uses[(min(a, b), max(a, b))] += 1
    border = set()
    for (a, b), n in uses.items():
        if n == 1:
            border.update((a, b))
    # Angle sums at texture vertices inside a piece (3D angles).
    sums = defaultdict(float)
    for f in faces:
        for k in range(3):
            p = v[f[k][0]]
            q = v[f[(k + 1) % 3][0]]
            r = v[f[(k + 2) % 3][0]]
            sums[f[k][1]] += angle(sub(q, p), sub(r, p))
    defects = [abs(2 * math.pi - s) for t, s in sums.items() if t not in border]
    # Cut edges: a 3D edge (welded by position) whose two sides have different vt pairs.
    key = {}
    weld = [key.setdefault(p, len(key)) for p in v]
    sides = defaultdict(list)
    for f in faces:
        for k in range(3):
            (a, ta), (b, tb) = f[k], f[(k + 1) % 3]
            pa, pb = weld[a], weld[b]
            uv = (ta, tb) if pa < pb else (tb, ta)
            sides[(min(pa, pb), max(pa, pb))].append((uv, (a, b)))
    seam = 0.0
    for s in sides.values():
        if len(s) == 2 and s[0][0] != s[1][0]:
            a, b = s[0][1]
            seam += norm(sub(v[a], v[b]))
    lo = [min(p[i] for p in v) for i in range(3)]
    hi = [max(p[i] for p in v) for i in range(3)]
    diagonal = norm(sub(hi, lo))
    stretch = 0.0
    for f in faces:
        for k in range(3):
            (a, ta), (b, tb) = f[k], f[(k + 1) % 3]
            length = norm(sub(v[a], v[b]))
            if length > 0:
                stretch = max(stretch, abs(norm(sub(vt[ta], vt[tb])) / length - 1))
    return {
        "defect_max_deg": math.degrees(max(defects, default=0.0)),
        "defect_mean_deg": math.degrees(sum(defects) / len(defects)) if defects else 0.0,
        "pieces": len(piece_area),
        "large_pieces": large,
        "seam_over_diagonal": seam / diagonal,
        "stretch": stretch,
    }


def main():
    binary, targets, out = sys.argv[1], Path(sys.argv[2]), Path(sys.argv[3])
    out.mkdir(parents=True, exist_ok=True)
    print("| target (faces) | options | status | CPU s | max / mean angle defect inside the pieces | pieces (≥ 1 % of area) | seam length / diagonal | Hausdorff / diagonal | pattern stretch max |")
    print("|---|---|---|---|---|---|---|---|---|")
    for k, (name, mesh, options) in enumerate(rows(targets)):
        target = out / f"row{k}"
        timing = out / f"row{k}.time"
        subprocess.run(["/usr/bin/time", "-o", str(timing), "-f", "%U", binary, "develop", str(mesh), "--size", "200", "-o", str(target), "-q", *options],
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        report = json.load(open(target / "report.json"))
        d = report["develop"]
        m = measure(target / "model.obj")
        cpu = float(open(timing).read().split()[-1])
        print(f"| {name} ({d['target_face_count']}) | {' '.join(options) or 'defaults'} | {report['status']} | {cpu:.2f} "
              f"| {m['defect_max_deg']:.0e}° / {m['defect_mean_deg']:.0e}° | {m['pieces']} ({m['large_pieces']}) "
              f"| {m['seam_over_diagonal']:.1f} | {100 * d['hausdorff_relative']:.2f} % | {m['stretch']:.0e} |")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Moves each silhouette end of the synthetic photo examples along the curve it stops on
(by arc length, the silhouette kept straight) and runs `sheetform photo` on each drawing;
prints the failures and a count per view (issue 37: where the user puts a point).

    python3 tools/photo_point_sweep.py [VIEW ...]   # default: the six synthetic views

Needs a release build (`cargo build --release`), or another binary named by
SHEETFORM_BIN (an older commit's, to compare). Writes only to a temporary directory.
"""
import json, math, os, shutil, subprocess, sys, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.environ.get("SHEETFORM_BIN", os.path.join(ROOT, "target", "release", "sheetform"))
SYNTHETIC = os.path.join(ROOT, "examples", "photo", "synthetic")
VIEWS = ["cylinder-ortho", "cone-ortho", "composite-ortho",
         "cylinder-perspective", "cone-perspective", "composite-perspective"]
OFFSETS = [-3, -2.5, -2, -1.5, -1, -0.5, 0.5, 1, 1.5, 2, 2.5, 3]


def bez(c, u):
    return [(1 - u) ** 3 * c[0][k] + 3 * (1 - u) ** 2 * u * c[1][k] + 3 * (1 - u) * u * u * c[2][k]
            + u ** 3 * c[3][k] for k in range(2)]


def along(curve, p, dist):
    """The point `dist` px of arc length along `curve` from its point nearest `p`."""
    cps = curve["control_points"]
    pts = [bez(cps[3 * j:3 * j + 4], i / 2000) for j in range((len(cps) - 1) // 3) for i in range(2000)]
    pts.append(cps[-1])
    i = min(range(len(pts)), key=lambda k: math.hypot(pts[k][0] - p[0], pts[k][1] - p[1]))
    step, acc = (1 if dist > 0 else -1), 0.0
    while acc < abs(dist):
        j = i + step
        if j < 0 or j >= len(pts):
            if not curve.get("closed"):
                break
            j %= len(pts)
        acc += math.hypot(pts[j][0] - pts[i][0], pts[j][1] - pts[i][1])
        i = j
    return pts[i]


def sweep(view, work):
    base = json.load(open(os.path.join(SYNTHETIC, view + ".json")))
    shutil.copy(os.path.join(SYNTHETIC, base["image"]["path"]), work)
    fails = total = 0
    for sil in [c for c in base["curves"] if c["kind"] == "silhouette"]:
        for end in (0, -1):
            p = sil["control_points"][end]
            host = min((c for c in base["curves"] if c["kind"] == "boundary"),
                       key=lambda c: min(math.hypot(q[0] - p[0], q[1] - p[1]) for q in c["control_points"][::3]))
            for d in OFFSETS:
                a = json.loads(json.dumps(base))
                s = [c for c in a["curves"] if c["name"] == sil["name"]][0]
                c = s["control_points"]
                c[end] = along(host, p, d)
                if len(c) == 4:
                    c[1] = [c[0][k] + (c[3][k] - c[0][k]) / 3 for k in range(2)]
                    c[2] = [c[0][k] + 2 * (c[3][k] - c[0][k]) / 3 for k in range(2)]
                path = os.path.join(work, "moved.json")
                json.dump(a, open(path, "w"))
                r = subprocess.run([BIN, "photo", path, "-o", os.path.join(work, "out")],
                                   capture_output=True, text=True)
                total += 1
                if r.returncode != 0:
                    fails += 1
                    last = (r.stderr.strip().splitlines() or [""])[-1]
                    print(f"{view}: {sil['name']} end {end} {d:+.1f} px along {host['name']}: exit {r.returncode}: {last[:140]}")
    print(f"{view}: {fails}/{total} failed")


if __name__ == "__main__":
    with tempfile.TemporaryDirectory() as work:
        for view in sys.argv[1:] or VIEWS:
            sweep(view, work)

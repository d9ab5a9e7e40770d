"""Inputs of the work-budget audit (issue 19, docs/benchmarks-history.md "Robustness, second
session"), written into the current directory:

  python3 tools/make_stress_inputs.py grid-obj 300        # grid300.obj: 300 x 300 vertices
  python3 tools/make_stress_inputs.py fan-obj 10000       # fan10000.obj: a disk of thin triangles
  python3 tools/make_stress_inputs.py crossings 120       # crossings120.json: two zig-zag curves
  python3 tools/make_stress_inputs.py comb 80 0.38        # comb80.json: a comb-shaped closed curve
  python3 tools/make_stress_inputs.py bezier 8000         # bezier8000.json: a bend curve of 8 000 points

The photo annotations name `coffee.png`: copy examples/photo/coffee.png beside them.
"""
import json
import math
import sys

SYMMETRY = {"frame": [[[284.26, 165.13], [290.24, 112.77]], [[290.24, 112.77], [240.04, 196.81]]],
            "points": [[183.81, 67.94], [396.68, 157.6]]}


def cubic_path(path):
    """A polyline as Bézier control points (each segment a straight cubic)."""
    points = [path[0]]
    for p, q in zip(path, path[1:]):
        points += [[p[0] + (q[0] - p[0]) * f, p[1] + (q[1] - p[1]) * f] for f in (1 / 3, 2 / 3)] + [q]
    return points


def grid_obj(n):
    with open(f"grid{n}.obj", "w") as f:
        for j in range(n):
            for i in range(n):
                f.write(f"v {float(i)} {float(j)} 0\n")
        for j in range(n - 1):
            for i in range(n - 1):
                a = j * n + i + 1
                f.write(f"f {a} {a + 1} {a + n + 1}\nf {a} {a + n + 1} {a + n}\n")


def fan_obj(n):
    with open(f"fan{n}.obj", "w") as f:
        f.write("v 0 0 0\n")
        for k in range(n):
            a = 2 * math.pi * k / n
            f.write(f"v {math.cos(a)} {math.sin(a)} {0.35 * math.sin(a) ** 2}\n")
        for k in range(n):
            f.write(f"f 1 {k + 2} {(k + 1) % n + 2}\n")


def photo(name, curves, extra):
    annotation = {"name": name, "image": {"path": "coffee.png", "width": 600, "height": 400},
                  "curves": curves, "symmetry": SYMMETRY,
                  "true_size": {"from": [100, 30], "to": [500, 30], "length": 62.0}}
    annotation.update(extra)
    with open(f"{name}.json", "w") as f:
        json.dump(annotation, f)


def crossings(rows):
    across, down = [], []
    for i in range(rows):
        t = i / (rows - 1)
        y, x = 30 + 340 * t, 50 + 500 * t
        across += [[45, y], [555, y]] if i % 2 == 0 else [[555, y], [45, y]]
        down += [[x, 25], [x, 375]] if i % 2 == 0 else [[x, 375], [x, 25]]
    photo(f"crossings{rows}",
          [{"name": "across", "kind": "boundary", "control_points": cubic_path(across)},
           {"name": "down", "kind": "boundary", "control_points": cubic_path(down)}],
          {"analysis": {"snap_distance_px": 0.5}})


def comb(teeth, spacing=None):
    ys = [20 + 360 * i / (2 * teeth - 1) for i in range(2 * teeth)]
    path = [[40, ys[0]], [540, ys[0]]]
    for r in range(2 * teeth - 1):
        x = path[-1][0]
        path += [[x, ys[r + 1]], [80 if x == 540 else 540, ys[r + 1]]]
    path += [[40, ys[-1]], [40, ys[0]]]
    extra = {"self_symmetric_curves": ["comb"]}
    if spacing:
        extra["analysis"] = {"sample_spacing_px": float(spacing), "ruling_spacing_px": float(spacing)}
    photo(f"comb{teeth}", [{"name": "comb", "kind": "boundary", "closed": True, "control_points": cubic_path(path)}],
          extra)


def bezier(n):
    points = [[i * 0.02, 0.0, math.sin(i * 0.001)] for i in range(n)]
    scene = {"outline": [[0, -60], [240, -60], [240, 60], [0, 60]],
             "regions": [{"flat_start": [0, 0], "flat_direction": [1, 0],
                          "curve": {"type": "bezier", "control_points": points}}]}
    with open(f"bezier{n}.json", "w") as f:
        json.dump(scene, f)


if __name__ == "__main__":
    kind, size, *rest = sys.argv[1:]
    {"grid-obj": grid_obj, "fan-obj": fan_obj, "crossings": crossings, "comb": comb, "bezier": bezier}[kind](
        int(size), *rest)

#!/usr/bin/env python3
"""The tube example of the photo reconstruction's symmetrisation (system D, §7).

Writes examples/photo/tube.json and examples/photo/tube.png: an open tube lying on its
side (radius 60 px, length 300 px, axis along world x), turned 25 deg about the vertical
and tilted 20 deg towards the viewer, seen orthographically in a 480 x 360 image.  The
plane halfway along the tube is its mirror plane: the two visible end arcs are a
symmetric pair and every ruling crosses the plane, the case where the paper replaces
rulings by ones that join mirror points.  The same model is built in
crates/sheetform-photo/tests/symmetrization.rs (with noise variants).

The PNG is a flat-shaded rendering of the visible outside of the tube (ray cast per
pixel, 2 x 2 supersampling), so that the overlay and the GLB's texture show something.

Run from the repository root:  python3 tools/make_tube_example.py
"""

import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from make_photo_examples import write_png  # noqa: E402  (one PNG writer for the example tools)

RADIUS = 60.0
HALF_LENGTH = 150.0
CENTRE = (240.0, 180.0)
WIDTH, HEIGHT = 480, 360
YAW, PITCH = math.radians(25.0), math.radians(20.0)


def rotate(p):
    """World -> camera: about y by YAW, then about x by PITCH."""
    x, y, z = p
    x, z = x * math.cos(YAW) + z * math.sin(YAW), -x * math.sin(YAW) + z * math.cos(YAW)
    y, z = y * math.cos(PITCH) - z * math.sin(PITCH), y * math.sin(PITCH) + z * math.cos(PITCH)
    return (x, y, z)


def unrotate(c):
    x, y, z = c
    y, z = y * math.cos(PITCH) + z * math.sin(PITCH), -y * math.sin(PITCH) + z * math.cos(PITCH)
    x, z = x * math.cos(YAW) - z * math.sin(YAW), x * math.sin(YAW) + z * math.cos(YAW)
    return (x, y, z)


def image(p):
    c = rotate(p)
    return [CENTRE[0] + c[0], CENTRE[1] - c[1]]


def silhouette_angle():
    ny, nz = rotate((0, 1, 0)), rotate((0, 0, 1))
    return math.atan2(-ny[2], nz[2])


def end_arc(x):
    a0 = silhouette_angle()
    facing = lambda a: rotate((0, math.cos(a), math.sin(a)))[2]
    sweep = math.pi if facing(a0 + 0.5 * math.pi) > 0 else -math.pi
    step = sweep / 4
    k = 4 / 3 * math.tan(step / 4)
    at = lambda a: (x, RADIUS * math.cos(a), RADIUS * math.sin(a))
    tangent = lambda a: (0.0, -RADIUS * math.sin(a), RADIUS * math.cos(a))
    add = lambda p, q, s: tuple(pi + s * qi for pi, qi in zip(p, q))
    points = [at(a0)]
    for i in range(4):
        a, b = a0 + step * i, a0 + step * (i + 1)
        points += [add(at(a), tangent(a), k), add(at(b), tangent(b), -k), at(b)]
    return [image(p) for p in points]


def straight(a, b):
    lerp = lambda t: [a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t]
    return [a, lerp(1 / 3), lerp(2 / 3), b]


def annotation():
    left, right = end_arc(-HALF_LENGTH), end_arc(HALF_LENGTH)
    a0 = silhouette_angle()
    end = lambda x: (x, RADIUS * math.cos(a0), RADIUS * math.sin(a0))
    pair = [end(-HALF_LENGTH), end(HALF_LENGTH)]
    if rotate(pair[0])[2] > rotate(pair[1])[2]:
        pair.reverse()
    return {
        "name": "open tube lying on its side (synthetic; mirror plane across the middle)",
        "image": {"path": "tube.png", "width": WIDTH, "height": HEIGHT},
        "units": "mm",
        "curves": [
            {"name": "left-end", "kind": "boundary", "control_points": left},
            {"name": "right-end", "kind": "boundary", "control_points": right},
            {"name": "first-silhouette", "kind": "silhouette", "control_points": straight(left[0], right[0])},
            {"name": "second-silhouette", "kind": "silhouette", "control_points": straight(left[12], right[12])},
        ],
        "symmetry": {
            "frame": [[image((0, 0, 0)), image((0, RADIUS, 0))], [image((0, 0, 0)), image((0, 0, RADIUS))]],
            "points": [image(pair[0]), image(pair[1])],
        },
        "symmetric_curves": [["left-end", "right-end"]],
        "true_size": {"from": image(end(-HALF_LENGTH)), "to": image(end(HALF_LENGTH)), "length": 300.0},
    }


def shade(u, v):
    """Grey level of image point (u, v): the nearest visible point of the tube's outside."""
    cx, cy = u - CENTRE[0], CENTRE[1] - v
    # Ray (cx, cy, t) in the camera frame: world p(t) = o + t d.
    o, d = unrotate((cx, cy, 0.0)), unrotate((0.0, 0.0, 1.0))
    # (o_y + t d_y)^2 + (o_z + t d_z)^2 = R^2, nearest to the viewer: largest t.
    a = d[1] ** 2 + d[2] ** 2
    b = 2 * (o[1] * d[1] + o[2] * d[2])
    c = o[1] ** 2 + o[2] ** 2 - RADIUS ** 2
    disc = b * b - 4 * a * c
    if disc < 0:
        return None
    for t in sorted([(-b + math.sqrt(disc)) / (2 * a), (-b - math.sqrt(disc)) / (2 * a)], reverse=True):
        p = tuple(oi + t * di for oi, di in zip(o, d))
        if abs(p[0]) <= HALF_LENGTH:
            n = (0.0, p[1] / RADIUS, p[2] / RADIUS)
            nc = rotate(n)
            light = (-0.35, 0.55, 0.76)
            lambert = abs(sum(x * y for x, y in zip(nc, light)))
            outside = nc[2] > 0
            base = (200, 150, 90) if outside else (120, 90, 60)
            return tuple(int(min(255, c * (0.35 + 0.65 * lambert))) for c in base)
    return None


def render(path):
    rows = []
    for v in range(HEIGHT):
        row = bytearray([0])
        for u in range(WIDTH):
            acc = [0, 0, 0]
            for du in (0.25, 0.75):
                for dv in (0.25, 0.75):
                    s = shade(u + du, v + dv) or (235, 235, 230)
                    acc = [x + y for x, y in zip(acc, s)]
            row += bytes(x // 4 for x in acc)
        rows.append(bytes(row))
    write_png(path, WIDTH, HEIGHT, b"".join(rows))


if __name__ == "__main__":
    with open("examples/photo/tube.json", "w") as f:
        json.dump(annotation(), f, indent=1)
        f.write("\n")
    render("examples/photo/tube.png")
    print("wrote examples/photo/tube.json and examples/photo/tube.png")

#!/usr/bin/env python3
"""Writes the bundled meshes of the editor's mesh mode and of `sheetform flatten`
into examples/meshes/ (plain Python, no packages):

    python3 tools/make_mesh_examples.py examples/meshes

- lamp-shade.obj: a cone frustum (radius 90 at the bottom, 50 at the top, 120 mm high;
  48 rulings, 6 rows), developable, two boundaries: flattened into charts opened along
  a straight seam;
- gift-box.obj: a closed box 60 × 40 × 30 mm (12 triangles), faceted: unfolded as a net
  with glue tabs.
"""
import math
import os
import sys


def write(path, vertices, faces, comment):
    with open(path, "w") as f:
        f.write(f"# {comment}\n")
        for v in vertices:
            f.write("v {:.9f} {:.9f} {:.9f}\n".format(*v))
        for t in faces:
            f.write("f {} {} {}\n".format(*(i + 1 for i in t)))


def lamp_shade():
    around, rows = 48, 6
    vertices = []
    for j in range(rows + 1):
        z = 120.0 * j / rows
        r = 90.0 + (50.0 - 90.0) * j / rows
        for i in range(around):
            a = 2 * math.pi * i / around
            vertices.append((r * math.cos(a), r * math.sin(a), z))
    faces = []
    for j in range(rows):
        for i in range(around):
            a, b = j * around + i, j * around + (i + 1) % around
            c, d = a + around, b + around
            faces += [(a, b, d), (a, d, c)]
    return vertices, faces


def gift_box():
    x, y, z = 60.0, 40.0, 30.0
    vertices = [(i * x, j * y, k * z) for k in (0, 1) for j in (0, 1) for i in (0, 1)]
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    faces = []
    for a, b, c, d in quads:
        faces += [(a, b, c), (a, c, d)]
    return vertices, faces


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: make_mesh_examples.py OUT_DIR")
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    write(os.path.join(out, "lamp-shade.obj"), *lamp_shade(), "a cone frustum lamp shade (tools/make_mesh_examples.py)")
    write(os.path.join(out, "gift-box.obj"), *gift_box(), "a closed gift box (tools/make_mesh_examples.py)")


if __name__ == "__main__":
    main()

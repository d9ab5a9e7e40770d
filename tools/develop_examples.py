#!/usr/bin/env python3
"""Writes the bundled targets of `sheetform develop` (examples/meshes/): a UV sphere of
radius 50 mm with its seams along 12 meridians (OBJ `l` polylines), whose developed
pieces are globe gores. Run from the repository root: python3 tools/develop_examples.py
"""
import math

def sphere_with_gore_seams(path, radius=50.0, rings=24, sections=48, gores=12):
    positions = [(0.0, 0.0, -radius)]
    for r in range(1, rings):
        phi = math.pi * r / rings - math.pi / 2
        for s in range(sections):
            t = 2 * math.pi * s / sections
            positions.append((radius * math.cos(phi) * math.cos(t), radius * math.cos(phi) * math.sin(t), radius * math.sin(phi)))
    positions.append((0.0, 0.0, radius))
    north = len(positions) - 1
    at = lambda r, s: 1 + (r - 1) * sections + s % sections
    faces = []
    for s in range(sections):
        faces.append((0, at(1, s + 1), at(1, s)))
        faces.append((north, at(rings - 1, s), at(rings - 1, s + 1)))
    for r in range(1, rings - 1):
        for s in range(sections):
            faces.append((at(r, s), at(r, s + 1), at(r + 1, s + 1)))
            faces.append((at(r, s), at(r + 1, s + 1), at(r + 1, s)))
    with open(path, "w") as f:
        f.write(f"# UV sphere, radius {radius} mm, seams along {gores} meridians (sheetform develop example)\n")
        for p in positions:
            f.write("v %.6f %.6f %.6f\n" % p)
        for a, b, c in faces:
            f.write(f"f {a + 1} {b + 1} {c + 1}\n")
        for g in range(gores):
            s = g * sections // gores
            line = [0] + [at(r, s) for r in range(1, rings)] + [north]
            f.write("l " + " ".join(str(v + 1) for v in line) + "\n")

if __name__ == "__main__":
    sphere_with_gore_seams("examples/meshes/sphere-gore-seams.obj")

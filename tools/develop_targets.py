#!/usr/bin/env python3
"""Writes the targets of the `develop` figures in docs/benchmarks-history.md (sessions 24, 25) into a
folder (`pip install trimesh manifold3d`):

    python3 tools/develop_targets.py OUT_DIR
    python3 tools/develop_targets.py --coffee-cup examples/meshes/coffee-cup.obj

sphere.obj (icosphere, subdivisions 3, radius 50: 1 280 faces), capsule.obj (height 60,
radius 25, 1 024 faces), torus.obj (50 / 15, 48 × 24 sections: 2 304 faces),
cylinder.obj (radius 30, height 80, 48 sections, capped: 192 faces), uvsphere.obj
(examples/meshes/sphere-gore-seams.obj without its `l` seam lines) and coffee-cup.obj
(the bundled one, `--coffee-cup` alone writes it: a 90 mm mug, 4 mm wall, with a ring
handle, 2 142 faces, genus 1; the peers' favourite target).
"""
import os
import sys

import numpy as np
import trimesh


def coffee_cup():
    """A mug: a revolved profile (radius 40, height 90, wall 4, base 6 mm with a 4 mm
    chamfer; the profile cut every 10 mm, 32 sections) united with a ring handle (a torus
    20 / 3.5 mm, 24 × 8 sections, its inner side inside the wall) by manifold3d."""
    radius, height, wall, base = 40.0, 90.0, 4.0, 6.0
    corners = [[0, 0], [radius - 4, 0], [radius, 4], [radius, height], [radius - wall, height],
               [radius - wall, base], [0, base]]
    profile = []
    for a, c in zip(corners[:-1], corners[1:]):
        a, c = np.array(a, float), np.array(c, float)
        n = max(1, int(np.ceil(np.linalg.norm(c - a) / 10.0)))
        profile += [a + (c - a) * k / n for k in range(n)]
    profile.append(np.array(corners[-1], float))
    body = trimesh.creation.revolve(np.array(profile), sections=32)
    handle = trimesh.creation.torus(major_radius=20, minor_radius=3.5, major_sections=24, minor_sections=8)
    handle.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [1, 0, 0]))
    handle.apply_translation([radius + 20, 0, height / 2])
    return trimesh.boolean.union([body, handle], engine="manifold")


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "--coffee-cup":
        coffee_cup().export(sys.argv[2])
        return
    if len(sys.argv) != 2:
        sys.exit("usage: develop_targets.py OUT_DIR | --coffee-cup FILE")
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    c = trimesh.creation
    c.icosphere(subdivisions=3, radius=50).export(os.path.join(out, "sphere.obj"))
    c.capsule(height=60, radius=25, count=[32, 16]).export(os.path.join(out, "capsule.obj"))
    c.torus(major_radius=50, minor_radius=15, major_sections=48, minor_sections=24).export(
        os.path.join(out, "torus.obj")
    )
    c.cylinder(radius=30, height=80, sections=48).export(os.path.join(out, "cylinder.obj"))
    here = os.path.dirname(os.path.abspath(__file__))
    with open(os.path.join(here, "..", "examples", "meshes", "sphere-gore-seams.obj")) as source:
        lines = [line for line in source if not line.startswith("l ")]
    with open(os.path.join(out, "uvsphere.obj"), "w") as target:
        target.writelines(lines)
    coffee_cup().export(os.path.join(out, "coffee-cup.obj"))


if __name__ == "__main__":
    main()

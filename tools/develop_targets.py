#!/usr/bin/env python3
"""Writes the targets of the `develop` figures in docs/benchmarks.md (session 24) into a
folder (`pip install trimesh`):

    python3 tools/develop_targets.py OUT_DIR

sphere.obj (icosphere, subdivisions 3, radius 50: 1 280 faces), capsule.obj (height 60,
radius 25, 1 024 faces), torus.obj (50 / 15, 48 × 24 sections: 2 304 faces),
cylinder.obj (radius 30, height 80, 48 sections, capped: 192 faces) and uvsphere.obj
(examples/meshes/sphere-gore-seams.obj without its `l` seam lines).
"""
import os
import sys

import trimesh


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: develop_targets.py OUT_DIR")
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


if __name__ == "__main__":
    main()

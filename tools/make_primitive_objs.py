#!/usr/bin/env python3
"""Writes the trimesh shapes issue 23 was tried on as OBJ files into a folder, for
`sheetform flatten` and the figures in docs/benchmarks-history.md and
docs/papercraft-comparison.md (`pip install trimesh`):

    python3 tools/make_primitive_objs.py out/primitives

box(40, 60, 80), icosphere(2, r 50), torus(R 60, r 20), cylinder(r 30, h 80, 32) and
cone(r 30, h 80, 32) closed; the cylinder without its caps, the cone without its base;
the upper half of icosphere(3, r 50); the upper half of icosphere(4, r 50) (`dome4`).
"""
import os
import sys

import numpy as np
import trimesh


def upper_half(mesh):
    return mesh.submesh([np.where(mesh.triangles_center[:, 2] > 0)[0]], append=True)


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: make_primitive_objs.py OUT_DIR")
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    c = trimesh.creation
    cylinder = c.cylinder(radius=30, height=80, sections=32)
    cone = c.cone(radius=30, height=80, sections=32)
    meshes = {
        "box": c.box(extents=(40, 60, 80)),
        "icosphere": c.icosphere(subdivisions=2, radius=50),
        "torus": c.torus(major_radius=60, minor_radius=20),
        "cylinder": cylinder,
        "cone": cone,
        "open_cylinder": cylinder.submesh([np.where(np.abs(cylinder.face_normals[:, 2]) < 0.5)[0]], append=True),
        "open_cone": cone.submesh([np.where(cone.face_normals[:, 2] > -0.99)[0]], append=True),
        "hemisphere": upper_half(c.icosphere(subdivisions=3, radius=50)),
        "dome4": upper_half(c.icosphere(subdivisions=4, radius=50)),
    }
    for name, mesh in meshes.items():
        mesh.export(os.path.join(out, f"{name}.obj"))
        print(f"{name}: {len(mesh.faces)} faces")


if __name__ == "__main__":
    main()

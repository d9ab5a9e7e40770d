#!/usr/bin/env python3
"""Writes a developable half-cylinder grid (radius 100, height 200, two triangles per
quad) as OBJ: the mesh of the flattening benchmarks, as a file for `sheetform flatten`.

    python3 tools/make_cylinder_obj.py 1000 500 out/cylinder-1m.obj   # 1 000 000 faces
"""
import math
import sys


def main():
    if len(sys.argv) != 4:
        sys.exit("usage: make_cylinder_obj.py NU NV OUT.obj  (2 * NU * NV faces)")
    nu, nv, path = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
    with open(path, "w") as f:
        for i in range(nu + 1):
            a = math.pi * i / nu
            for j in range(nv + 1):
                f.write(f"v {100 * math.cos(a):.12f} {100 * math.sin(a):.12f} {200 * j / nv:.12f}\n")
        for i in range(nu):
            for j in range(nv):
                a = i * (nv + 1) + j + 1
                b = (i + 1) * (nv + 1) + j + 1
                f.write(f"f {a} {b} {b + 1}\nf {a} {b + 1} {a + 1}\n")


if __name__ == "__main__":
    main()

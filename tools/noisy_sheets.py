#!/usr/bin/env python3
"""Writes the noisy sheets of docs/benchmarks-history.md (session 23, flatten's work budget):
200 x 200 mm grids with Gaussian height noise, as OBJ, into DIR (default /tmp).
    python3 tools/noisy_sheets.py [DIR]      # needs numpy
noisy-100k.obj (224² vertices, sigma 0.5 mm, seed 1), noisy-250k.obj (354², sigma 0.5,
seed 1, after the 100k one), mild-100k.obj (224², sigma 0.05, seed 2)."""
import sys
import numpy as np

def sheet(path, n, sigma, rng):
    xs = np.linspace(0, 200, n)
    x, y = np.meshgrid(xs, xs)
    z = rng.normal(0, sigma, x.shape)
    with open(path, "w") as f:
        f.write("".join(f"v {a:.4f} {b:.4f} {c:.4f}\n" for a, b, c in zip(x.ravel(), y.ravel(), z.ravel())))
        for i in range(n - 1):
            for j in range(n - 1):
                a = i * n + j
                b, c, d = a + 1, a + n, a + n + 1
                f.write(f"f {a + 1} {b + 1} {d + 1}\nf {a + 1} {d + 1} {c + 1}\n")

if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else "/tmp"
    rng = np.random.default_rng(1)
    sheet(f"{out}/noisy-100k.obj", 224, 0.5, rng)
    sheet(f"{out}/noisy-250k.obj", 354, 0.5, rng)
    sheet(f"{out}/mild-100k.obj", 224, 0.05, np.random.default_rng(2))

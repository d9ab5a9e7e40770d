"""The Python binding's per-call overhead next to the library call it wraps (issue 21).

    python3 tools/python_overhead.py

Flattens an exactly developable cylinder grid of about 1 000 and 1 000 000 faces with
``sheetform.flatten(V, F, charts="never", outputs="preview")`` and prints, per size, the
median wall time of the Python call, the library's own time for ``run_flatten``
(``Run.pipeline_seconds``, measured inside the binding around that call only), their
difference (the binding: checking and copying the arrays in, the thread the run goes
on, the arrays and the report dict out) and, for scale, what numpy takes to copy the
input and output arrays once.
"""

import statistics
import time

import numpy as np

import sheetform


def cylinder_grid(around, along, radius=100.0, height=300.0):
    """``(around + 1) × (along + 1)`` vertices on half a cylinder, two triangles per
    cell: every cell is planar (its edges are rulings), so the mesh is developable."""
    angle = np.linspace(0.0, np.pi, around + 1)
    z = np.linspace(0.0, height, along + 1)
    a, h = np.meshgrid(angle, z, indexing="ij")
    vertices = np.column_stack([radius * np.cos(a).ravel(), radius * np.sin(a).ravel(), h.ravel()])
    i, j = np.meshgrid(np.arange(around), np.arange(along), indexing="ij")
    v00 = (i * (along + 1) + j).ravel()
    v10, v01, v11 = v00 + along + 1, v00 + 1, v00 + along + 2
    faces = np.vstack([np.column_stack([v00, v10, v11]), np.column_stack([v00, v11, v01])])
    return vertices, faces


def measure(around, along, repeats):
    vertices, faces = cylinder_grid(around, along)
    walls, pipelines = [], []
    for _ in range(repeats):
        start = time.perf_counter()
        run = sheetform.flatten(vertices, faces, charts="never", outputs="preview")
        walls.append(time.perf_counter() - start)
        pipelines.append(run.pipeline_seconds)
    assert run.outcome == "ok" and run.report["isometry_error_max_relative"] < 1e-9
    start = time.perf_counter()
    for _ in range(repeats):
        copies = (vertices.copy(), faces.copy(), run.vertices.copy(), run.faces.copy(), run.uv.copy(), run.face_pieces.copy())
    copy = (time.perf_counter() - start) / repeats
    del copies
    wall, pipeline = statistics.median(walls), statistics.median(pipelines)
    overheads = sorted(w - p for w, p in zip(walls, pipelines))
    return len(faces), wall, pipeline, statistics.median(overheads), copy


def main():
    print("faces | python call (median) | run_flatten alone | binding overhead | numpy copy of the arrays in and out")
    for around, along, repeats in ((25, 20, 200), (1000, 500, 5)):
        faces, wall, pipeline, overhead, copy = measure(around, along, repeats)
        print(
            f"{faces} | {wall * 1e3:.3f} ms | {pipeline * 1e3:.3f} ms | {overhead * 1e3:.3f} ms "
            f"({100 * overhead / wall:.1f} %) | {copy * 1e3:.3f} ms"
        )


if __name__ == "__main__":
    main()

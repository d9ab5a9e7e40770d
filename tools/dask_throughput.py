#!/usr/bin/env python3
"""Throughput of batch flattening on Dask (issue 39): N flatten jobs on a LocalCluster of
1 worker and of 2 worker processes (one thread each), jobs per second.

    python3 tools/dask_throughput.py [N]          # default 200

Each job flattens one of a few trimesh primitives (an icosphere, a torus, a capsule, a
box, a cylinder, sizes varied) into a net with the preview outputs; the jobs are built
here and sent with sheetform.batch.run_all, their runs gathered back. Prints one JSON
object: jobs, failures and seconds per worker count. Needs dask[distributed] and trimesh.
"""
import json
import sys
import time

import trimesh
from dask.distributed import Client, LocalCluster

import sheetform
import sheetform.batch


def jobs(count):
    makers = [
        lambda k: trimesh.creation.icosphere(subdivisions=2, radius=30 + k % 7),
        lambda k: trimesh.creation.torus(major_radius=40 + k % 5, minor_radius=12, major_sections=32, minor_sections=16),
        lambda k: trimesh.creation.capsule(height=40 + k % 9, radius=15, count=[16, 16]),
        lambda k: trimesh.creation.box((30 + k % 11, 20, 10)),
        lambda k: trimesh.creation.cylinder(radius=20, height=30 + k % 13, sections=32),
    ]
    meshes = [makers[k % len(makers)](k) for k in range(count)]
    return [(m.vertices, m.faces) for m in meshes]


def main():
    count = int(sys.argv[1]) if len(sys.argv) > 1 else 200
    work = jobs(count)
    figures = {"jobs": count}
    for workers in (1, 2):
        with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, Client(cluster) as client:
            # One job first, so that each worker has imported sheetform before the clock.
            sheetform.batch.run_all(client, sheetform.flatten, work[:workers], charts="net", outputs="preview")
            started = time.perf_counter()
            results = sheetform.batch.run_all(client, sheetform.flatten, work, charts="net", outputs="preview")
            seconds = time.perf_counter() - started
        figures[f"{workers}_worker"] = {
            "seconds": round(seconds, 2),
            "jobs_per_second": round(count / seconds, 1),
            "failed": sum(r.error is not None for r in results),
            "not_ok": sum(not r.ok for r in results),
        }
    figures["speedup"] = round(figures["1_worker"]["seconds"] / figures["2_worker"]["seconds"], 2)
    print(json.dumps(figures))


if __name__ == "__main__":
    main()

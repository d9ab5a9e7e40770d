#!/usr/bin/env python3
"""`sheetform develop` with and without a mirror plane on symmetric targets (issue 36):
prints a Markdown table of printed pieces, Hausdorff distance over the bounding-box
diagonal, the layout kept (pieces across the plane or a centre seam), the target's own
asymmetry and user CPU seconds.

    python3 tools/develop_mirror_table.py

The smooth targets are made with trimesh (an icosphere scaled 1 : 0.7 : 1.3, a UV
sphere, a capsule, a torus); the others are bundled in examples/meshes. Needs a release
build (`cargo build --release`) or another binary named by SHEETFORM_BIN. Writes only to
a temporary directory.
"""
import json, os, resource, subprocess, sys, tempfile

import trimesh

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.environ.get("SHEETFORM_BIN", os.path.join(ROOT, "target", "release", "sheetform"))


def targets(directory):
    ellipsoid = trimesh.creation.icosphere(subdivisions=3, radius=40.0)
    ellipsoid.apply_scale([1.0, 0.7, 1.3])
    made = {
        "ellipsoid": ellipsoid,
        "UV sphere": trimesh.creation.uv_sphere(radius=50.0, count=[32, 32]),
        "capsule": trimesh.creation.capsule(height=60.0, radius=25.0),
        "torus": trimesh.creation.torus(40.0, 12.0),
    }
    paths = {}
    for name, mesh in made.items():
        paths[name] = os.path.join(directory, name.replace(" ", "-") + ".obj")
        mesh.export(paths[name])
    for name in ["spot", "koala", "coffee-cup"]:
        paths[name] = os.path.join(ROOT, "examples", "meshes", name + ".obj")
    return paths


# Each target with its planes of symmetry.
PLANES = {
    "ellipsoid": ["x", "y", "z"],
    "UV sphere": ["x", "z"],
    "capsule": ["x", "z"],
    "torus": ["x", "z"],
    "spot": ["x"],
    "koala": ["x"],
    "coffee-cup": ["y"],
}


def run(path, out, args):
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime
    subprocess.run([BIN, "develop", path, "-o", out, "-q", *args], check=False)
    seconds = resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime - before
    report = json.load(open(os.path.join(out, "report.json")))
    return report, seconds


def main():
    with tempfile.TemporaryDirectory() as directory:
        paths = targets(directory)
        print("| target | mirror | status | printed pieces | Hausdorff / diagonal | layout | target's asymmetry | CPU s |")
        print("|---|---|---|---|---|---|---|---|")
        for name, path in paths.items():
            for plane in [None] + PLANES[name]:
                args = ["--mirror", plane] if plane else []
                report, seconds = run(path, os.path.join(directory, "out"), args)
                d = report["develop"]
                layout = "" if plane is None else ("centre seam" if d["mirror_seam"] else "across")
                asymmetry = "" if plane is None else f"{100 * d['mirror_asymmetry_relative']:.2f} %"
                print(f"| {name} | {plane or 'none'} | {report['status']} | {d['piece_count']} | "
                      f"{100 * d['hausdorff_relative']:.2f} % | {layout} | {asymmetry} | {seconds:.2f} |")
                sys.stdout.flush()


if __name__ == "__main__":
    main()

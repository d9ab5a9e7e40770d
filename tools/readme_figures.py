#!/usr/bin/env python3
"""Renders the README's pictures from the bundled examples, so that they show what the
tools make today (issue 39):

    python3 tools/readme_figures.py [OUT_DIR]      # default docs/images

Runs each system through the Python package (the same pipeline as the CLI) and draws its
model in 3D beside its flat pattern at the same scale, the pieces in the same colours
(matplotlib, no window): desk.png (bend, examples/desk.json), chair.png (slit,
examples/slit/chair.json), trousers.png (FFD, examples/ffd/trousers.json),
coffee-cup.png (photo: the annotated photograph, the model, the pattern;
examples/photo/coffee-cup.json), gift-box.png (flatten: the box unfolded into one net,
examples/meshes/gift-box.obj) and koala.png (develop, examples/meshes/koala.obj).
Needs the sheetform package, numpy, matplotlib and trimesh (to read the koala).
"""
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import trimesh  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

import sheetform  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
PALETTE = plt.get_cmap("tab20").colors


def piece_colours(run):
    return np.array([PALETTE[p % len(PALETTE)] for p in run.face_pieces])


def draw_model(axes, run, up, view):
    """The model, lit from the camera's side, z up (`up`: the model's up axis)."""
    v = np.asarray(run.vertices, float)
    if up == "y":
        v = v[:, [0, 2, 1]] * [1, -1, 1]
    triangles = v[run.faces]
    normals = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True) + 1e-300
    elevation, azimuth = np.radians(view)
    towards_camera = np.array([np.cos(elevation) * np.cos(azimuth), np.cos(elevation) * np.sin(azimuth), np.sin(elevation)])
    light = 0.45 + 0.55 * np.abs(normals @ towards_camera)
    colours = piece_colours(run)[:, :3] * light[:, None]
    axes.add_collection3d(Poly3DCollection(triangles, facecolors=colours, edgecolors="none"))
    low, high = v.min(axis=0), v.max(axis=0)
    centre, half = (low + high) / 2, (high - low).max() / 2
    axes.set_xlim(centre[0] - half, centre[0] + half)
    axes.set_ylim(centre[1] - half, centre[1] + half)
    axes.set_zlim(centre[2] - half, centre[2] + half)
    axes.set_box_aspect((1, 1, 1))
    axes.view_init(elev=view[0], azim=view[1])
    axes.set_axis_off()


def draw_pattern(axes, run, title):
    """The flat pattern at 1:1 (`uv`), the pieces in the model's colours."""
    axes.add_collection(PolyCollection(run.uv[run.faces], facecolors=piece_colours(run), edgecolors="none"))
    axes.autoscale()
    axes.set_aspect("equal")
    axes.set_axis_off()
    printed = run.report["pattern"]
    axes.set_title(f"{title}: {printed['width_mm']:.0f} × {printed['height_mm']:.0f} mm as printed", fontsize=9)


def figure(name, run, caption, up="z", view=(25, -60), photo=None, out=Path("docs/images")):
    panels = 3 if photo is not None else 2
    fig = plt.figure(figsize=(4.2 * panels, 4.2), dpi=110)
    at = 1
    if photo is not None:
        axes = fig.add_subplot(1, panels, at)
        axes.imshow(mpimg.imread(photo))
        axes.set_axis_off()
        axes.set_title("the annotated photograph", fontsize=9)
        at += 1
    draw_model(fig.add_subplot(1, panels, at, projection="3d"), run, up, view)
    fig.axes[-1].set_title(caption, fontsize=9)
    draw_pattern(fig.add_subplot(1, panels, at + 1), run, "the flat pattern")
    fig.tight_layout()
    out.mkdir(parents=True, exist_ok=True)
    fig.savefig(out / f"{name}.png")
    plt.close(fig)
    print(out / f"{name}.png", run.report["status"])


def main():
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else REPO / "docs/images"
    desk = sheetform.bend(REPO / "examples/desk.json", outputs="preview")
    figure("desk", desk, "bend: a desk from one sheet", up="z", view=(22, -55), out=out)
    chair = sheetform.slit(REPO / "examples/slit/chair.json", outputs="preview")
    figure("chair", chair, "slit: a chair of slit strips", up="y", view=(15, -35), out=out)
    trousers = sheetform.ffd(REPO / "examples/ffd/trousers.json", outputs="preview")
    figure("trousers", trousers, "FFD: trousers, developable panels", up="z", view=(10, -70), out=out)
    cup = sheetform.photo(REPO / "examples/photo/coffee-cup.json", outputs="preview")
    figure(
        "coffee-cup",
        cup,
        "photo: the cup's developable band",
        up="z",
        view=(15, -90),
        photo=REPO / "examples/photo/coffee.png",
        out=out,
    )
    box = trimesh.load(REPO / "examples/meshes/gift-box.obj", process=False)
    net = sheetform.flatten(box.vertices, box.faces, name="gift-box", charts="net", outputs="preview")
    figure("gift-box", net, "flatten: a box unfolded into a net", up="z", view=(25, -60), out=out)
    koala = trimesh.load(REPO / "examples/meshes/koala.obj", process=False)
    developed = sheetform.develop(koala.vertices, koala.faces, name="koala", size=200.0, outputs="preview")
    figure("koala", developed, "develop: a scan in exact pieces", up="y", view=(15, -60), out=out)


if __name__ == "__main__":
    main()

"""sheetform from Python: bend a sheet, flatten a trimesh primitive, plot the patterns.

    pip install ./bindings/python trimesh matplotlib
    python examples/python/bend_and_flatten.py [OUTPUT_DIRECTORY]

Writes ``patterns.png`` (both flat patterns, true to scale, coloured by piece) and the
bent desk's files (``desk/``: model.obj, model.glb, pattern.svg, pattern.dxf,
pattern.pdf, report.json) into OUTPUT_DIRECTORY (default ``out/python``).
"""

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # no window: the plot goes to a file
import matplotlib.pyplot as plt
from matplotlib.collections import PolyCollection
import numpy as np
import trimesh

import sheetform

EXAMPLES = Path(__file__).resolve().parents[1]


def plot_pattern(axes, run, title):
    """The flat pattern of a run, each piece in its own colour, at true scale."""
    colours = plt.cm.tab10(np.arange(len(run.pieces)) % 10)
    for piece, name in enumerate(run.pieces):
        faces = run.faces[run.face_pieces == piece]
        axes.add_collection(PolyCollection(run.uv[faces], facecolors=colours[piece], edgecolors="none", alpha=0.8))
        centre = run.uv[np.unique(faces)].mean(axis=0)
        axes.annotate(name, centre, ha="center", va="center", fontsize=7)
    axes.autoscale_view()
    axes.set_aspect("equal")
    axes.set_title(title, fontsize=9)
    axes.set_xlabel("mm")


def main(output):
    output.mkdir(parents=True, exist_ok=True)

    # 1. Bend a cross-shaped sheet into a desk (Bo & Wang, Fig. 15), as `sheetform bend`.
    desk = sheetform.bend(EXAMPLES / "desk.json")
    desk.write(output / "desk")
    print(
        f"desk: {len(desk.vertices)} vertices, {len(desk.pieces)} pieces, "
        f"isometry error {desk.report['isometry_error_max_relative']:.1e}, "
        f"largest angle defect {np.abs(desk.angle_defects_rad).max():.1e} rad"
    )

    # 2. Flatten a mesh from trimesh without any file: a capped cylinder is not
    #    developable as a whole, so it is unfolded exactly into pieces, with glue tabs.
    cylinder = trimesh.creation.cylinder(radius=30.0, height=80.0, sections=24)
    net = sheetform.flatten(cylinder.vertices, cylinder.faces, name="can")
    edges = np.vstack([net.faces[:, [0, 1]], net.faces[:, [1, 2]], net.faces[:, [2, 0]]])
    length_3d = np.linalg.norm(np.diff(net.vertices[edges], axis=1)[:, 0], axis=1)
    length_flat = np.linalg.norm(np.diff(net.uv[edges], axis=1)[:, 0], axis=1)
    print(
        f"can: {net.report['layout']} of {len(net.pieces)} pieces ({net.report['layout_reason']}); "
        f"edge lengths kept to {np.abs(length_3d - length_flat).max():.1e} mm"
    )
    # The pattern back in trimesh as texture coordinates.
    textured = trimesh.Trimesh(
        net.vertices, net.faces, visual=trimesh.visual.TextureVisuals(uv=net.uv), process=False
    )
    print(f"can: area {textured.area:.1f} mm² in 3D, {net.report['flat_area_mm2']:.1f} mm² flat")

    figure, (left, right) = plt.subplots(1, 2, figsize=(11, 5))
    plot_pattern(left, desk, "desk.json bent: the sheet's pattern")
    plot_pattern(right, net, "trimesh cylinder flattened: its net")
    figure.tight_layout()
    figure.savefig(output / "patterns.png", dpi=110)
    print(f"wrote {output / 'patterns.png'} and {output / 'desk'}/")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("out/python"))

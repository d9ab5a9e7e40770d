"""The Python example (examples/python/bend_and_flatten.py) runs as a user would run it
and makes what it says: the desk's files, a plot of both patterns."""

import json
import subprocess
import sys

import matplotlib.image

from conftest import REPO


def test_the_python_example_bends_flattens_and_plots(tmp_path):
    done = subprocess.run(
        [sys.executable, str(REPO / "examples/python/bend_and_flatten.py"), str(tmp_path)],
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert lines[0].startswith("desk: 2916 vertices, 9 pieces"), lines[0]
    assert "net of" in lines[1], lines[1]
    report = json.loads((tmp_path / "desk" / "report.json").read_text())
    assert report["status"] == "ok" and report["isometry_error_max_relative"] < 1e-9
    for name in report["outputs"]:
        assert (tmp_path / "desk" / name).stat().st_size > 0, name
    image = matplotlib.image.imread(tmp_path / "patterns.png")
    assert image.shape[0] > 400 and image.shape[1] > 800
    # Not a blank figure: the patterns are drawn in colour.
    assert (image[..., :3].std(axis=2) > 0.1).mean() > 0.05

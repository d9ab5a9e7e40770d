"""Shared helpers of the binding's tests: the repository, the ``sheetform`` command to
compare with, and a reader for the OBJ files it writes."""

import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[3]


def cli_path():
    """The ``sheetform`` command the results are compared with: ``SHEETFORM_CLI``, else
    the workspace's debug or release build."""
    if os.environ.get("SHEETFORM_CLI"):
        return Path(os.environ["SHEETFORM_CLI"])
    for profile in ("debug", "release"):
        candidate = REPO / "target" / profile / "sheetform"
        if candidate.exists():
            return candidate
    raise RuntimeError(
        "no sheetform command to compare with: build it (cargo build) or set SHEETFORM_CLI"
    )


@pytest.fixture(scope="session")
def cli():
    """Runs ``sheetform ARGS...`` from the repository root; returns the completed process."""
    path = cli_path()

    def run(*args):
        return subprocess.run(
            [str(path), *map(str, args), "--quiet"],
            cwd=REPO,
            capture_output=True,
            text=True,
            check=False,
        )

    return run


def read_obj(path):
    """``(v (n, 3), vt (n, 2) or None, f (m, 3) 0-based)`` of an OBJ whose faces name the
    same index for the position and the texture coordinate, as sheetform writes them."""
    vertices, uv, faces = [], [], []
    for line in Path(path).read_text().splitlines():
        words = line.split()
        if not words:
            continue
        if words[0] == "v":
            vertices.append([float(w) for w in words[1:4]])
        elif words[0] == "vt":
            uv.append([float(w) for w in words[1:3]])
        elif words[0] == "f":
            corners = [w.split("/") for w in words[1:]]
            assert len(corners) == 3, line
            for c in corners:
                assert len(c) == 1 or c[1] in ("", c[0]), f"position and vt differ: {line}"
            faces.append([int(c[0]) - 1 for c in corners])
    return (
        np.array(vertices, dtype=float),
        np.array(uv, dtype=float) if uv else None,
        np.array(faces, dtype=np.int64),
    )


def read_report(directory):
    return json.loads((Path(directory) / "report.json").read_text())


def without_timings(value):
    """A report without what differs from run to run: the timings (``timings``, and every
    figure in milliseconds, ``*_ms``)."""
    if isinstance(value, dict):
        return {
            k: without_timings(v)
            for k, v in value.items()
            if k != "timings" and not k.endswith("_ms")
        }
    if isinstance(value, list):
        return [without_timings(v) for v in value]
    return value


def assert_close(actual, expected, path="report", tolerance=1e-12):
    """Every number of two JSON values equal to ``tolerance`` (relative to its size, or
    absolute below 1), every other value equal, the same keys."""
    if isinstance(expected, dict):
        assert isinstance(actual, dict), path
        assert sorted(actual) == sorted(expected), f"{path}: keys {sorted(actual)} != {sorted(expected)}"
        for key in expected:
            assert_close(actual[key], expected[key], f"{path}.{key}", tolerance)
    elif isinstance(expected, list):
        assert isinstance(actual, list) and len(actual) == len(expected), path
        for i, (a, e) in enumerate(zip(actual, expected)):
            assert_close(a, e, f"{path}[{i}]", tolerance)
    elif isinstance(expected, float) or isinstance(actual, float):
        assert abs(actual - expected) <= tolerance * max(1.0, abs(expected)), f"{path}: {actual} != {expected}"
    else:
        assert actual == expected, f"{path}: {actual!r} != {expected!r}"


def y_up(points, up_axis):
    """Points in a scene's frame turned as the OBJ and GLB are: +z to +y."""
    if up_axis == "y":
        return points
    return np.column_stack([points[:, 0], points[:, 2], -points[:, 1]])

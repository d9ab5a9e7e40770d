"""Runs cross process boundaries (issue 39): a `Run` and its meshes pickle, and come back
from worker processes of a spawned pool whole (arrays, report, outcome, files)."""

import concurrent.futures
import multiprocessing
import pickle

import numpy as np
import trimesh

import sheetform
from conftest import REPO, read_report


def flatten_box(size):
    """A worker's job: a box of the given size, flattened into a net."""
    box = trimesh.creation.box((size, 0.6 * size, 0.4 * size))
    return sheetform.flatten(box.vertices, box.faces, name=f"box-{size}")


def assert_same_run(a, b):
    for name in ("vertices", "faces", "uv", "face_pieces", "angle_defects_rad", "source_vertices"):
        x, y = getattr(a, name), getattr(b, name)
        if x is None:
            assert y is None, name
        else:
            np.testing.assert_array_equal(x, y, err_msg=name)
            assert x.dtype == y.dtype, name
    assert a.report == b.report and a.outcome == b.outcome and a.pieces == b.pieces
    assert a.files == b.files and a.pipeline_seconds == b.pipeline_seconds


def test_a_run_and_its_meshes_pickle_and_write_the_same_files(tmp_path):
    ffd = sheetform.ffd(REPO / "examples/ffd/two-panels.json")
    again = pickle.loads(pickle.dumps(ffd))
    assert_same_run(ffd, again)
    assert sorted(again.meshes) == sorted(ffd.meshes) == ["plain", "restored"]
    for name, mesh in ffd.meshes.items():
        for array in ("vertices", "faces", "angle_defects_rad"):
            np.testing.assert_array_equal(getattr(again.meshes[name], array), getattr(mesh, array))
    # What it writes is what the original writes, report.json included.
    ffd.write(tmp_path / "original")
    again.write(tmp_path / "unpickled")
    for name in [*ffd.files, "report.json"]:
        assert (tmp_path / "original" / name).read_bytes() == (tmp_path / "unpickled" / name).read_bytes(), name
    assert read_report(tmp_path / "unpickled")["status"] == ffd.report["status"]


def test_runs_come_back_from_worker_processes():
    sizes = [40.0, 55.0, 70.0, 85.0]
    context = multiprocessing.get_context("spawn")
    with concurrent.futures.ProcessPoolExecutor(max_workers=2, mp_context=context) as pool:
        runs = list(pool.map(flatten_box, sizes))
    for size, run in zip(sizes, runs):
        assert run.outcome == "ok" and run.report["status"] == "ok"
        assert run.pieces and "model.obj" in run.files
        # The same as the job run here.
        local = flatten_box(size)
        np.testing.assert_array_equal(run.vertices, local.vertices)
        np.testing.assert_array_equal(run.uv, local.uv)
        assert run.files == local.files


def test_pattern_options_pickle_as_the_keywords_they_were_made_with():
    """A PatternOptions goes to worker processes (Dask's run_all(..., pattern=...)): it
    pickles as its keywords, sheet sizes given as numbers included, and gives the same
    pattern."""
    options = sheetform.PatternOptions(tabs="one", sheet=(600, 400.5), kerf=0.2, seam_labels=False, smooth_folds=12.0)
    again = pickle.loads(pickle.dumps(options))
    assert repr(again) == repr(options)
    assert "kerf=0.2" in repr(options) and 'sheet="600x400.5"' in repr(options)
    box = trimesh.creation.box((60.0, 40.0, 30.0))
    first = sheetform.flatten(box.vertices, box.faces, pattern=options, outputs="preview")
    second = sheetform.flatten(box.vertices, box.faces, pattern=again, outputs="preview")
    assert first.files["pattern.svg"] == second.files["pattern.svg"]
    assert first.report["pattern"] == second.report["pattern"]

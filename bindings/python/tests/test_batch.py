"""Batch work on Dask (issue 39): jobs sent to a LocalCluster of 2 worker processes come
back in order as the same runs as here, and a failing job is reported on its own."""

import numpy as np
import pytest
import trimesh

import sheetform
import sheetform.batch

distributed = pytest.importorskip("dask.distributed")


def box(size):
    return trimesh.creation.box((size, 0.6 * size, 0.4 * size))


def test_jobs_run_on_two_worker_processes_and_each_failure_is_its_own():
    sizes = [40.0, 50.0, 60.0, 70.0, 80.0, 90.0]
    jobs = [(box(s).vertices, box(s).faces) for s in sizes]
    # A malformed mesh among them, and a job given as keywords.
    bad = box(30.0).vertices.copy()
    bad[0, 0] = np.nan
    jobs.insert(3, (bad, box(30.0).faces))
    jobs.append({"vertices": box(100.0).vertices, "faces": box(100.0).faces, "name": "big"})
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:
        workers = set(client.scheduler_info()["workers"])
        assert len(workers) == 2
        # (A PatternOptions travels to the workers too.)
        pattern = sheetform.PatternOptions(tabs="one", kerf=0.1)
        results = sheetform.batch.run_all(client, sheetform.flatten, jobs, outputs="preview", name="box", pattern=pattern)
    assert [r.index for r in results] == list(range(len(jobs)))
    failed = results[3]
    assert not failed.ok and failed.run is None
    assert failed.error_type == "InvalidInputError" and "vertices" in failed.error
    for job, result in zip(jobs[:3] + jobs[4:], results[:3] + results[4:]):
        assert result.ok and result.error is None, result.error
        assert result.worker in workers and result.seconds > 0
        # The same run as here, arrays to the bit.
        local = (
            sheetform.flatten(**job, outputs="preview", pattern=pattern)
            if isinstance(job, dict)
            else sheetform.flatten(*job, outputs="preview", name="box", pattern=pattern)
        )
        assert result.run.files["pattern.svg"] == local.files["pattern.svg"]
        np.testing.assert_array_equal(result.run.uv, local.uv)
        np.testing.assert_array_equal(result.run.vertices, local.vertices)
        assert result.run.report["status"] == "ok"
    # The keyword job's own name overrode the common one.
    assert "<title>big: " in results[-1].run.files["pattern.svg"].decode()


def test_run_job_reports_a_failure_without_dask():
    result = sheetform.batch.run_job(0, sheetform.flatten, (np.zeros((3, 3)), np.array([[0, 1, 5]])), {})
    assert result.run is None and result.error_type == "InvalidInputError"
    assert result.worker is None and not result.ok

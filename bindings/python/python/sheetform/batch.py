"""Many jobs at once, on the machines of a Dask cluster (``dask.distributed``).

A job is one call of a sheetform function (``flatten``, ``develop``, ``bend``, ...) on one
input: a mesh's arrays, a scene file, an annotation. ``run_all`` sends the jobs to the
cluster's workers with ``Client.map``, gathers them in order, and reports each job's
result on its own: a job that fails (a malformed mesh, an inadmissible scene) gives a
``JobResult`` with its error instead of stopping the others. A ``Run`` pickles whole
(arrays, report, files), so it comes back from any worker as if it had run here.

    from dask.distributed import Client, LocalCluster
    import sheetform, sheetform.batch, trimesh

    meshes = [trimesh.load(path) for path in paths]
    with Client(LocalCluster(n_workers=2, threads_per_worker=1)) as client:
        results = sheetform.batch.run_all(
            client, sheetform.flatten, [(m.vertices, m.faces) for m in meshes],
            outputs="preview",
        )
    for path, result in zip(paths, results):
        if result.error:
            print(path, "failed:", result.error_type, result.error)
        else:
            result.run.write(f"out/{path.stem}")

The same code runs on a cluster: give ``Client`` the scheduler's address, or a
``dask_jobqueue.SLURMCluster`` / ``dask_kubernetes`` cluster (docs/guide/python.md, the batch
section). Each job runs on one worker thread; sheetform's solvers may use a second core
themselves, so ``threads_per_worker=1`` and one worker per core pair is a good start.

Requires ``dask[distributed]`` (``pip install "sheetform[dask]"``); only ``run_all``,
``submit`` and ``gather`` touch it.
"""

from __future__ import annotations

import time
import traceback
from dataclasses import dataclass
from typing import Any, Callable, Iterable, Optional

from ._native import Run, SheetformError

__all__ = ["JobResult", "run_job", "submit", "gather", "run_all"]


@dataclass(frozen=True)
class JobResult:
    """What one job gave: its ``run``, or why it failed.

    ``index`` is the job's place in the list given; ``run`` the ``Run`` (``None`` when the
    job failed; a run ``out_of_tolerance`` is a result, with its ``outcome``);
    ``error_type`` the exception's class name (``InvalidInputError``, ...) and ``error``
    its message; ``worker`` where it ran (a Dask worker's address, ``None`` here);
    ``seconds`` the job's time on its worker.
    """

    index: int
    run: Optional[Run]
    error_type: Optional[str]
    error: Optional[str]
    worker: Optional[str]
    seconds: float

    @property
    def ok(self) -> bool:
        """Whether the job ran and its run's outcome is ``"ok"``."""
        return self.run is not None and self.run.outcome == "ok"


def _call(function: Callable[..., Run], job: Any, options: dict[str, Any]) -> Run:
    """``function`` on one job: a tuple is its positional arguments, a dict its keywords
    (with ``options`` under them), anything else its one argument."""
    if isinstance(job, tuple):
        return function(*job, **options)
    if isinstance(job, dict):
        return function(**{**options, **job})
    return function(job, **options)


def _worker_address() -> Optional[str]:
    try:
        from distributed import get_worker

        return get_worker().address
    except (ImportError, ValueError):
        return None


def run_job(index: int, function: Callable[..., Run], job: Any, options: dict[str, Any]) -> JobResult:
    """Runs one job and reports it: a sheetform error (or any other exception of the job)
    becomes the result's ``error``; an interrupt still stops it."""
    started = time.perf_counter()
    try:
        run = _call(function, job, options)
        error_type = error = None
    except SheetformError as failure:
        run, error_type, error = None, type(failure).__name__, str(failure)
    except Exception as failure:  # noqa: BLE001 - any failure of one job is that job's result
        run, error_type = None, type(failure).__name__
        error = f"{failure}\n{traceback.format_exc(limit=4)}"
    return JobResult(index, run, error_type, error, _worker_address(), time.perf_counter() - started)


def submit(client: Any, function: Callable[..., Run], jobs: Iterable[Any], **options: Any) -> list[Any]:
    """Sends each job to the cluster (``client.map``): one future per job, in order.
    ``options`` are keywords for every call (``outputs="preview"``, ``pattern=...``).
    Jobs are never cached by Dask: the same job twice runs twice."""
    jobs = list(jobs)
    return client.map(
        run_job,
        range(len(jobs)),
        [function] * len(jobs),
        jobs,
        [options] * len(jobs),
        pure=False,
    )


def gather(client: Any, futures: list[Any]) -> list[JobResult]:
    """The jobs' results, in the order they were sent. A job whose worker died (the
    process killed, out of memory) gives a result with that error instead of stopping
    the gathering."""
    results = client.gather(futures, errors="skip")
    done = {r.index: r for r in results if isinstance(r, JobResult)}
    out = []
    for index, future in enumerate(futures):
        if index in done:
            out.append(done[index])
            continue
        failure = future.exception() if future.status == "error" else None
        out.append(
            JobResult(
                index,
                None,
                type(failure).__name__ if failure else "CancelledError",
                str(failure) if failure else f"the job ended {future.status}",
                None,
                0.0,
            )
        )
    return out


def run_all(client: Any, function: Callable[..., Run], jobs: Iterable[Any], **options: Any) -> list[JobResult]:
    """``submit`` then ``gather``: every job's ``JobResult``, in order."""
    return gather(client, submit(client, function, jobs, **options))

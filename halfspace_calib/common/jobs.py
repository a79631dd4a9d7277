"""Run a sweep as a list of independent jobs: serially, on local processes, or on a Dask cluster.

A failed job is captured with its error message and does not stop the others; results come back in
job order whichever path ran them, so a sweep gives identical numbers on every path. The progress
bar advances as jobs finish (in completion order), not as they are collected.
"""

import os
import time
import traceback
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass
from typing import Any

from tqdm.auto import tqdm

__all__ = ["JobResult", "run_jobs"]


@dataclass
class JobResult:
    """Outcome of one job: ``ok`` with its ``value``, or the ``error`` text."""

    index: int
    ok: bool
    value: Any = None
    error: str = ""
    seconds: float = 0.0


def _call(fn, index, job):
    t0 = time.perf_counter()
    try:
        value = fn(job)
    except Exception as exc:  # noqa: BLE001 - a failed job is reported, not raised
        msg = f"{type(exc).__name__}: {exc}"
        tb = traceback.format_exc(limit=3)
        return JobResult(index, False, None, f"{msg}\n{tb}", time.perf_counter() - t0)
    return JobResult(index, True, value, "", time.perf_counter() - t0)


def run_jobs(fn, jobs, *, workers=1, scheduler=None, progress=True, desc="sweep"):
    """Run ``fn(job)`` for every job and return the list of :class:`JobResult` in job order.

    Parameters
    ----------
    fn : callable
        A picklable (module-level) function of one job.
    jobs : sequence
        Picklable job descriptions.
    workers : int
        ``1`` runs in this process; ``> 1`` uses that many local processes;
        ``0`` means one per CPU. Ignored when ``scheduler`` is given.
    scheduler : str or dask.distributed.Client, optional
        Address of a Dask scheduler (``"tcp://host:8786"``) or a client: the jobs run there.
    progress : bool
        Show a progress bar.
    """
    jobs = list(jobs)
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 0:
        raise ValueError(f"workers must be an integer >= 0, got {workers!r}")
    bar = tqdm(total=len(jobs), desc=desc, disable=not progress, leave=False)
    try:
        if scheduler is not None:
            return _run_dask(fn, jobs, scheduler, bar)
        n = (os.cpu_count() or 1) if workers == 0 else workers
        if n == 1 or len(jobs) <= 1:
            out = []
            for i, job in enumerate(jobs):
                out.append(_call(fn, i, job))
                bar.update()
            return out
        with ProcessPoolExecutor(max_workers=min(n, len(jobs))) as pool:
            futures = [pool.submit(_call, fn, i, job) for i, job in enumerate(jobs)]
            for _ in as_completed(futures):
                bar.update()
            return [f.result() for f in futures]
    finally:
        bar.close()


def _run_dask(fn, jobs, scheduler, bar):
    try:
        from dask.distributed import Client, as_completed
    except ImportError:  # pragma: no cover - depends on the environment
        raise ImportError(
            "a Dask scheduler was given but dask.distributed is not installed: "
            "pip install 'dask[distributed]>=2023.1' (from a clone of this project: "
            "pip install -e '.[dask]')"
        ) from None
    own = not isinstance(scheduler, Client)
    client = Client(scheduler) if own else scheduler
    try:
        futures = client.map(_call, [fn] * len(jobs), range(len(jobs)), jobs, pure=False)
        for _ in as_completed(futures):
            bar.update()
        return client.gather(futures)
    finally:
        if own:
            client.close()

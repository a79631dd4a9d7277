"""Run a sweep as a list of independent jobs: serially, on local processes, or on a Dask cluster.

A failed job is captured with its error message and does not stop the others; results come back in
job order whichever path ran them, so a sweep gives identical numbers on every path. On Dask, a
worker that dies mid-job has its job rescheduled by the scheduler (up to its
``distributed.scheduler.allowed-failures``); a job whose workers all died is retried once
alone (a job that only shared a dying worker then completes), and if it kills its workers again
it comes back failed (``KilledWorker``), the others' results kept.
The progress bar advances as jobs finish (in completion order), not as they are collected.
"""

import time
import traceback
from concurrent.futures import as_completed
from dataclasses import dataclass
from typing import Any

from tqdm.auto import tqdm

from sbmf_cli import available_cpus, process_pool

__all__ = ["JobResult", "default_workers", "fft_threads", "run_jobs"]

#: most local processes chosen by default (measured: benchmarks/bench_workers.py)
DEFAULT_MAX_WORKERS = 2
#: FFT elements of one solve from which a sweep's load levels run on processes by default
#: (2^17, about 362^2: periodic grids from 363, non-periodic ones, padded 2x, from 182)
POOL_MIN_FFT_ELEMENTS = 2**17

#: FFT threads per process; set in each worker of a local process pool (``None``: the default)
_FFT_THREADS = None


def default_workers(fft_elements=None):
    """Local processes when none are given, for a sweep whose solves transform ``fft_elements``.

    ``min(2, available_cpus())`` from :data:`POOL_MIN_FFT_ELEMENTS` FFT elements on (each process
    then has ``available_cpus() // processes`` FFT threads: processes x FFT threads never exceed
    the CPUs), else ``1``: one process with threaded FFTs; also ``1`` without a size (jobs that
    were not measured). Measured on 2 cores with the CLI's wall time
    (``benchmarks/bench_workers.py``, docs/normal_contact.md): two processes are 1.09x faster on
    the default scene at 512^2 and on a measured file at 224^2 (FFT 448^2), and 0.88-0.98x (slower)
    at 128^2 and 256^2, where the pool's start-up is a larger share. More than 2 processes were
    not measured.
    """
    if fft_elements is None or fft_elements < POOL_MIN_FFT_ELEMENTS:
        return 1
    return min(DEFAULT_MAX_WORKERS, available_cpus())


def fft_threads():
    """Threads for ``scipy.fft`` in this process: workers x FFT threads never exceed the CPUs.

    In a worker of :func:`run_jobs`'s local pool: ``available_cpus() // workers`` (at least 1);
    otherwise :func:`available_cpus`.
    """
    return _FFT_THREADS if _FFT_THREADS is not None else available_cpus()


def _init_worker(threads):
    """A local worker's FFT threads (interrupts: :func:`sbmf_cli.process_pool`)."""
    global _FFT_THREADS
    _FFT_THREADS = threads


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


def run_jobs(fn, jobs, *, workers=None, scheduler=None, progress=True, desc="sweep"):
    """Run ``fn(job)`` for every job and return the list of :class:`JobResult` in job order.

    Parameters
    ----------
    fn : callable
        A picklable (module-level) function of one job.
    jobs : sequence
        Picklable job descriptions.
    workers : int or None
        ``1`` runs in this process; ``> 1`` uses that many local processes;
        ``0`` means one per CPU this process may use; ``None``: ``1`` (callers that know the
        solve size pass :func:`default_workers` of it).
        Ignored when ``scheduler`` is given.
        Each local process runs ``available_cpus() // processes`` FFT threads (at least 1).
    scheduler : str or dask.distributed.Client, optional
        Address of a Dask scheduler (``"tcp://host:8786"``) or a client: the jobs run there.
    progress : bool
        Show a progress bar.
    """
    jobs = list(jobs)
    if workers is None:
        workers = 1
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 0:
        raise ValueError(f"workers must be an integer >= 0, got {workers!r}")
    bar = tqdm(total=len(jobs), desc=desc, disable=not progress, leave=False)
    try:
        if scheduler is not None:
            return _run_dask(fn, jobs, scheduler, bar)
        n = available_cpus() if workers == 0 else workers
        if n == 1 or len(jobs) <= 1:
            out = []
            for i, job in enumerate(jobs):
                out.append(_call(fn, i, job))
                bar.update()
            return out
        n = min(n, len(jobs))
        threads = max(1, available_cpus() // n)
        # an interrupt ends the workers at once (Ctrl-C, SIGTERM: no run left hanging)
        with process_pool(n, _init_worker, (threads,)) as pool:
            futures = [pool.submit(_call, fn, i, job) for i, job in enumerate(jobs)]
            for _ in as_completed(futures):
                bar.update()
            return [f.result() for f in futures]
    finally:
        bar.close()


def _dask_result(i, future):
    """The job's result; a cluster failure (a worker that died on every retry) as a failed job."""
    try:  # _call catches the job's own errors: what reaches here is the cluster's
        return future.result()
    except Exception as exc:  # noqa: BLE001 - one lost job must not lose the others
        return JobResult(i, False, None, f"worker lost: {type(exc).__name__}: {exc}")


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
        try:
            for _ in as_completed(futures):
                bar.update()
        except BaseException:  # interrupted: the cluster stops the run's jobs
            client.cancel(futures)
            raise
        out = [_dask_result(i, f) for i, f in enumerate(futures)]
        # A job lost with its workers may only have shared a worker with the job that killed
        # it (the scheduler counts every task on a dying worker as suspect): each lost job is
        # retried once, alone, so that only a job that kills its workers itself ends failed.
        for i in [r.index for r in out if not r.ok and r.error.startswith("worker lost")]:
            out[i] = _dask_result(i, client.submit(_call, fn, i, jobs[i], pure=False))
        return out
    finally:
        if own:
            client.close()

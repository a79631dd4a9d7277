import math
import time

import pytest

from halfspace_calib.common.jobs import run_jobs


def _work(x):
    if x < 0:
        raise ValueError(f"negative job {x}")
    return math.sqrt(x) * 3.0


JOBS = [4.0, -1.0, 9.0, 2.0]


def _check(results):
    assert [r.index for r in results] == [0, 1, 2, 3]
    assert [r.ok for r in results] == [True, False, True, True]
    assert results[0].value == 6.0 and results[2].value == 9.0
    assert "ValueError: negative job -1.0" in results[1].error
    return [r.value for r in results]


def test_serial_and_process_paths_agree():
    a = _check(run_jobs(_work, JOBS, workers=1, progress=False))
    b = _check(run_jobs(_work, JOBS, workers=2, progress=False))
    assert a == b


def test_dask_local_cluster_path_agrees():
    distributed = pytest.importorskip("dask.distributed")
    with (
        distributed.LocalCluster(
            n_workers=1, threads_per_worker=1, processes=False, dashboard_address=":0"
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        c = _check(run_jobs(_work, JOBS, scheduler=client, progress=False))
        d = _check(run_jobs(_work, JOBS, scheduler=cluster.scheduler_address, progress=False))
    assert c == d == _check(run_jobs(_work, JOBS, progress=False))


def test_bad_workers():
    with pytest.raises(ValueError, match="workers must be an integer >= 0"):
        run_jobs(_work, JOBS, workers=-2)


def _sleep_then_stamp(seconds):
    time.sleep(seconds)
    return time.monotonic()  # CLOCK_MONOTONIC: one clock for every process of the machine


class _Bar:
    """Stands in for tqdm: records when each ``update`` happens."""

    stamps = []

    def __init__(self, *a, **k):
        type(self).stamps = []

    def update(self, n=1):
        type(self).stamps.append(time.monotonic())

    def close(self):
        pass


def test_progress_advances_as_jobs_finish(monkeypatch):
    """A slow first job does not hold back the bar: the fast job's tick comes before it ends."""
    import halfspace_calib.common.jobs as J

    monkeypatch.setattr(J, "tqdm", _Bar)
    res = run_jobs(_sleep_then_stamp, [3.0, 0.0], workers=2)
    assert [r.ok for r in res] == [True, True]
    slow_end, fast_end = res[0].value, res[1].value
    assert len(_Bar.stamps) == 2 and fast_end < slow_end
    assert fast_end <= _Bar.stamps[0] < slow_end  # old behaviour: first tick after the slow job

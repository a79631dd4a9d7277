"""The default processes of the sweeps: within the CPUs, and the same answer as one process.

``Scene.workers=None`` runs the load levels on ``min(2, available_cpus())`` processes, each with
``available_cpus() // processes`` FFT threads, from ``POOL_MIN_FFT_ELEMENTS`` FFT elements on
(measured faster there than one process with threaded FFTs on 2 cores,
benchmarks/bench_workers.py), else in this process. The parameters must not depend on it.
"""

import dataclasses

import numpy as np
import pytest

import sbmf_cli._processes as processes
from halfspace_calib.common import jobs
from halfspace_calib.pipeline.calibration import calibrate
from halfspace_calib.pipeline.sweep import sweeps
from halfspace_calib.pipeline.sweep.scene import Scene


@pytest.mark.parametrize("cpus", [1, 2, 3, 8])
def test_default_workers_never_oversubscribe(monkeypatch, cpus):
    monkeypatch.setattr(processes.os, "sched_getaffinity", lambda pid: set(range(cpus)))
    assert jobs.default_workers() == 1  # no size: this process
    assert jobs.default_workers(jobs.POOL_MIN_FFT_ELEMENTS - 1) == 1
    w = jobs.default_workers(jobs.POOL_MIN_FFT_ELEMENTS)
    assert w == min(2, cpus)
    threads = max(1, processes.available_cpus() // w)
    assert 1 <= w * threads <= cpus


@pytest.mark.parametrize(
    "grid, periodic, expected",
    [(256, True, 1), (362, True, 1), (363, True, 2), (176, False, 1), (184, False, 2)],
)
def test_sweeps_choose_processes_by_the_transform_size(monkeypatch, grid, periodic, expected):
    """Periodic grids from 363 and non-periodic ones (padded 2x) from 182 run on 2 processes."""
    seen = {}

    def fake_run_jobs(fn, jobs_, *, workers, scheduler, progress, desc):
        seen["workers"] = workers
        raise RuntimeError("stop")  # only the choice is under test

    monkeypatch.setattr(processes.os, "sched_getaffinity", lambda pid: {0, 1})
    monkeypatch.setattr(sweeps, "run_jobs", fake_run_jobs)
    given = dict(pressures=(1e8, 2e8, 3e8), adaptive_levels=False)  # given levels
    with pytest.raises(RuntimeError, match="stop"):
        sweeps.run_sweeps(Scene(grid=grid, periodic=periodic, **given), progress=False)
    assert seen["workers"] == expected
    with pytest.raises(RuntimeError, match="stop"):  # a given value is kept
        sweeps.run_sweeps(Scene(grid=grid, periodic=periodic, workers=1, **given), progress=False)
    assert seen["workers"] == 1
    with pytest.raises(RuntimeError, match="stop"):  # adaptive levels: each round alike
        sweeps.run_sweeps(Scene(grid=grid, periodic=periodic), progress=False)
    assert seen["workers"] == expected


def test_scene_workers_default_and_validation():
    assert Scene().workers is None
    assert Scene(scheduler="tcp://host:8786").scheduler == "tcp://host:8786"  # no conflict
    for bad in (-1, True, 1.5, "2"):
        with pytest.raises(ValueError, match="workers must be an integer >= 0 or None"):
            Scene(workers=bad)
    with pytest.raises(ValueError, match="with a Dask scheduler"):
        Scene(workers=2, scheduler="tcp://host:8786")


def _fields(cal):
    p, a = cal.sweeps.loading
    rel = [
        (lv.p_hist, tuple((r.p_mean, r.alpha, r.nit) for r in lv.reload))
        for lv in cal.sweeps.levels
    ]
    nit = [lv.loading.nit for lv in cal.sweeps.levels]
    law = {f.name: getattr(cal.params, f.name) for f in dataclasses.fields(cal.params)}
    law.pop("provenance")  # holds the wall times
    return law, p, a, rel, nit


@pytest.mark.parametrize("periodic", [True, False])
def test_same_parameters_in_one_or_two_processes(periodic):
    """Bit-identical parameters, curves and iteration counts (workers 1: FFTs on all CPUs)."""
    scene = Scene(grid=32, periodic=periodic, resolution_check=not periodic)
    one = calibrate(dataclasses.replace(scene, workers=1), progress=False)
    two = calibrate(dataclasses.replace(scene, workers=2), progress=False)
    auto = calibrate(scene, progress=False)
    for other in (two, auto):
        a, b = _fields(one), _fields(other)
        assert a[0] == b[0]  # FrictionParams to the last digit
        np.testing.assert_array_equal(a[1], b[1])
        np.testing.assert_array_equal(a[2], b[2])
        assert a[3] == b[3]
        assert a[4] == b[4]
    assert [lv.p_hist for lv in one.sweeps.levels] == list(one.sweeps.plan.pressures)
    if not periodic:
        assert one.resolution.params == two.resolution.params

"""A Dask worker that dies during a multi-sample calibration (docs/uncertainty.md).

Two worker processes of a ``LocalCluster``. One sample's job kills its worker process
(``os._exit``): once (the scheduler reschedules it on the other worker, every sample ends
calibrated, with the same numbers as in this process), or on every attempt (that sample is
reported failed by name, the other samples' results are kept and the band is made from them).
"""

import os
import sys
from pathlib import Path

import pytest

from halfspace_calib.pipeline.band.samples import SampleSpec, calibrate_samples, load_samples
from halfspace_calib.pipeline.calibration import Scene

distributed = pytest.importorskip("dask.distributed")

# a toy grid and four pressures: the acceptance (tested in test_failed_fit) is not checked here
FAST = dict(
    pressures=(25e6, 100e6, 300e6, 600e6), reload_fractions=(0.25, 0.5, 0.8), heldout_tol=0.5
)


class _Dying:
    """Stands for a sample's surfaces; in a worker process its first use kills the process.

    ``marker``: with a path, only the first use anywhere kills (the file records it); without,
    every use in a worker does.
    """

    def __init__(self, surfaces, marker=None):
        self._s, self._marker, self._parent = surfaces, marker, os.getpid()

    def __getattr__(self, name):
        if name in ("_s", "_marker", "_parent"):  # not set yet (unpickling)
            raise AttributeError(name)
        if name.startswith("__") or os.getpid() == self._parent:
            return getattr(self._s, name)
        if self._marker is None:
            os._exit(1)
        m = Path(self._marker)
        if not m.exists():
            m.write_text("killed once")
            os._exit(1)
        return getattr(self._s, name)


@pytest.fixture(scope="module")
def cluster():
    import cloudpickle
    import dask

    cloudpickle.register_pickle_by_value(sys.modules[__name__])  # workers cannot import tests
    with (
        dask.config.set({"distributed.scheduler.allowed-failures": 1}),
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0"
        ) as c,
    ):
        yield c


def _samples():
    scene = Scene(grid=16, **FAST)
    spec = SampleSpec(patches=4, n_bootstrap=50)
    return scene, spec, load_samples(scene, spec)


@pytest.mark.slow
def test_a_worker_killed_once_is_rescheduled(cluster, tmp_path):
    scene, spec, samples = _samples()
    victim = samples[1]
    samples[1] = type(victim)(victim.name, victim.scene, _Dying(victim.surfaces, tmp_path / "m"))
    sc = scene.__class__(**{**scene.as_dict(), "scheduler": cluster.scheduler_address})
    mc = calibrate_samples(sc, spec, samples=samples, progress=False)
    assert (tmp_path / "m").read_text() == "killed once"  # the worker did die
    assert mc.failed == {} and len(mc.calibrations) == 4 and mc.problems() == []
    ref = calibrate_samples(scene, spec, samples=_samples()[2], progress=False)
    for name, cal in ref.calibrations.items():
        assert mc.calibrations[name].params.C1 == cal.params.C1
    assert mc.params.C1 == ref.params.C1


@pytest.mark.slow
def test_a_job_whose_workers_all_die_is_reported_by_name(cluster, tmp_path):
    from halfspace_calib.output.uncertainty import write_sample_outputs

    scene, spec, samples = _samples()
    victim = samples[2]
    samples[2] = type(victim)(victim.name, victim.scene, _Dying(victim.surfaces))
    sc = scene.__class__(**{**scene.as_dict(), "scheduler": cluster.scheduler_address})
    mc = calibrate_samples(sc, spec, samples=samples, progress=False)
    assert list(mc.failed) == [victim.name] and "worker lost" in mc.failed[victim.name]
    assert sorted(mc.calibrations) == sorted(s.name for s in samples if s is not samples[2])
    probs = mc.problems()
    assert probs and victim.name in probs[0]  # the command exits 1 on problems
    out = write_sample_outputs(mc, tmp_path / "out")
    assert len(mc.params.uncertainty.samples) == 3
    assert (out / "params.json").is_file() and (out / "report.html").is_file()
    assert victim.name in (out / "report.html").read_text()

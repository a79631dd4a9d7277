"""Process workers x FFT threads never exceed the CPUs the process may use (issue 16)."""

import os

from halfspace_calib.common.jobs import fft_threads, run_jobs
from halfspace_calib.contact.influence import normal_operator
from sbmf_cli import available_cpus


def _threads(_):
    return fft_threads(), normal_operator((8, 8), 1e-6, 1e11).workers


def test_available_cpus_is_the_affinity():
    assert available_cpus() == len(os.sched_getaffinity(0))


def test_available_cpus_without_an_affinity_call(monkeypatch):
    """macOS and Windows have no os.sched_getaffinity: the count falls back to the CPU count."""
    monkeypatch.delattr(os, "sched_getaffinity")
    assert available_cpus() == max(1, (getattr(os, "process_cpu_count", None) or os.cpu_count)())


def test_serial_path_uses_the_available_cpus():
    assert _threads(None) == (available_cpus(), available_cpus())


def test_pool_workers_share_the_cpus():
    cpus = available_cpus()
    for workers in (2, 3):
        got = [r.value for r in run_jobs(_threads, [0] * workers, workers=workers, progress=False)]
        for threads, op_threads in got:
            assert threads == op_threads == max(1, cpus // workers)
            assert workers * threads <= max(cpus, workers)

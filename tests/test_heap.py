"""Freed grid-sized arrays stay in the heap (common/heap.py, issue 39): few page faults per FFT."""

import os
import subprocess
import sys
import textwrap

import pytest

from halfspace_calib.common import heap

pytestmark = pytest.mark.skipif(
    not sys.platform.startswith("linux"), reason="glibc's mallopt thresholds (Linux)"
)

_CHILD = textwrap.dedent(
    """
    import resource, sys
    import numpy as np, scipy.fft as sfft
    from halfspace_calib.common.heap import keep_heap
    on = keep_heap()
    x = np.random.default_rng(0).random((512, 512))
    for _ in range(5):  # the heap grows to its working size first
        sfft.irfft2(sfft.rfft2(x), s=x.shape)
    r0 = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    for _ in range(40):
        sfft.irfft2(sfft.rfft2(x), s=x.shape)
    print(on, resource.getrusage(resource.RUSAGE_SELF).ru_minflt - r0)
    """
)


def _faults(env_value):
    env = dict(os.environ, SBMF_KEEP_HEAP=env_value)
    out = subprocess.run(
        [sys.executable, "-c", _CHILD], env=env, capture_output=True, text=True, check=True
    )
    on, faults = out.stdout.split()
    return on == "True", int(faults)


def test_kept_heap_reuses_the_transforms_blocks():
    on, faults = _faults("1")
    if not on:
        pytest.skip("not glibc: keep_heap does nothing here")
    # 40 pairs of 2 MiB blocks would be 40 x 2 x 512 = 40,960 fresh pages if given back each time
    assert faults < 2000


def test_it_can_be_turned_off_and_is_idempotent():
    on, _ = _faults("0")
    assert on is False
    first = heap.keep_heap()
    assert heap.keep_heap() is first

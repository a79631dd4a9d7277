"""Issue 12: the runtime under hostile input (read-only arrays, extremes, bad files and dtypes)."""

import subprocess
import sys

import numba
import numpy as np
import pytest

import frictionlaw as fl
from frictionlaw import _reference as ref

H = 800e6


def params(**kw):
    base = dict(m=0.6, sigma_y=H / 2.8, H=H, C1=1.2, n1=2.0, C2=3.0, n2=2.0)
    base.update(kw)
    return fl.FrictionParams(**base)


def readonly(a):
    a = np.array(a, dtype=float)
    a.flags.writeable = False
    return a


# -- item 1: read-only input everywhere --------------------------------------------------------


def test_read_only_arrays_are_accepted():
    P = params()
    state = fl.HistoryState(p_hist=np.array([0.0, 0.5 * H, 2 * H]))
    p = np.array([0.3, 0.4, 1.0]) * H
    want = fl.shear_limit(p, state.p_hist.copy(), P)
    assert not state.p_hist.flags.writeable
    np.testing.assert_array_equal(fl.shear_limit(p, state.p_hist, P), want)
    np.testing.assert_array_equal(fl.shear_limit(readonly(p), state.p_hist, P), want)
    np.testing.assert_array_equal(fl.SBMFLaw(P).shear_limit(p, state.p_hist)[0], want)
    np.testing.assert_array_equal(
        fl.shear_limit_dp(readonly(p), state.p_hist, P),
        fl.shear_limit_dp(p, state.p_hist.copy(), P),
    )
    law = fl.SBMFLaw(P)
    du = np.array([[1e-6, 0.0], [0.0, -1e-7], [2e-7, 2e-7]])
    t_old = np.full((3, 2), 1e6)
    kt = np.full(3, 1e13)
    want = fl.traction_update(law, p, du, t_old, kt, state)
    got = fl.traction_update(law, readonly(p), readonly(du), readonly(t_old), readonly(kt), state)
    for a, b in zip(want, got, strict=True):
        np.testing.assert_array_equal(a, b)


def test_read_only_arrays_in_a_host_njit_loop():
    from frictionlaw import kernels

    law = fl.SBMFLaw(params())
    code, coeffs = law.code, readonly(law.coeffs)

    @numba.njit
    def host(p, p_hist, du, t_old, out):
        t_new, dtd, dtp = np.empty((p.size, 2)), np.empty((p.size, 2, 2)), np.empty((p.size, 2))
        for i in range(p.size):
            out[i] = kernels.traction_row(
                code, coeffs, p[i], p_hist[i], du, t_old, 1e13, t_new, dtd, dtp, i
            )

    p = readonly([0.0, 0.5 * H, H])
    du = np.zeros((3, 2))
    du[1, 0] = 1.0
    out = np.empty(3)
    host(p, readonly([0, 0, 0]), readonly(du), readonly(np.zeros((3, 2))), out)
    assert list(out) == [fl.OPEN, fl.SLIP, fl.STICK]


# -- item 10: frictionlaw.kernels as the README spells it ---------------------------------------


def test_kernels_reachable_as_attribute_and_import_stays_light():
    code = (
        "import sys, frictionlaw\n"
        "assert 'numba' not in sys.modules\n"
        "f = frictionlaw.kernels.shear_scalar\n"
        "print(f(0, frictionlaw.Coulomb(0.5).coeffs, 2.0, 0.0)[0])\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert float(out.stdout) == 1.0

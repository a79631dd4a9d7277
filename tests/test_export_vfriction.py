"""Abaqus/Explicit ``VFRICTION`` (general contact) against the runtime, block by block.

Node-type secondary surfaces (``nNodState = 1``): each contact point carries its own state and
the routine must equal ``traction_update_force`` + ``HistoryState`` (stick force as the trial).
Edge-type (``nNodState`` 2 or 4): the point's ``p_hist`` is the largest of its state nodes', and
each state node is raised to at least the current pressure. Both reload forms (the tabulated
form's sets ``tab`` and ``tab_flat`` of tests/test_export_fortran.py).
"""

import re

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from reload_tables import levels
from test_export_fortran import PARAM_SETS, TINY, assert_close, check_cache, pressures

import frictionlaw as fl
import frictionlaw.export as exp
from frictionlaw.export import harness

pytestmark = pytest.mark.skipif(
    harness.gfortran() is None,
    reason="gfortran not installed (.ci/run installs it: apt-get install -y gfortran)",
)

_LIBS = {}


def vfriction_lib(tmp_path_factory, key):
    if key not in _LIBS:
        path = tmp_path_factory.getbasetemp() / f"params_vf_{key}.json"
        PARAM_SETS[key].to_json(path)
        files, _ = exp.render("abaqus-vfriction", path)
        src = {n: t for n, t in files.items() if n.endswith(".f")}
        name = f"vfriction_{key}"
        _LIBS[key] = exp.target("abaqus-vfriction").harness.load(
            src, tmp_path_factory.mktemp(name), name=name
        )
    return _LIBS[key]


def run_vfriction(host, params, seed, nns, nsv, n=64, n_incr=8):
    rng = np.random.default_rng(seed)
    law = fl.SBMFLaw(params)
    state = np.zeros((n, nns, nsv))
    for _ in range(n_incr):
        ph_nodes = state[:, :, 0].copy()
        ph = ph_nodes.max(axis=1)
        area = 10.0 ** rng.uniform(-8, -4, n)
        area[rng.random(n) < 0.05] = 0.0  # no area: open
        p = pressures(rng, n, ph, params.H, levels(params))
        f_n = p * np.where(area > 0, area, 1e-6)
        f_stick = params.tau_max * np.where(area > 0, area, 1e-6) * 10.0 ** rng.uniform(-2, 1, n)
        before = state.copy()
        ft = host(f_n, f_stick, area, state)
        assert np.isfinite(ft).all() and np.isfinite(state).all()
        assert np.all(ft[:, 1] == 0)
        assert np.all(ft[:, 0] <= 0) and np.all(-ft[:, 0] <= f_stick)
        assert np.all(state[:, :, 0] >= 0)
        on = area > 0
        hs = fl.HistoryState(p_hist=ph[on])
        ref = fl.traction_update_force(
            law, f_n[on], area[on], -f_stick[on] / area[on], np.zeros(on.sum()), area[on], hs
        )
        assert_close(ft[on, 0], ref.traction, 1e-12, "fTangential(1)")
        assert np.all(ft[~on] == 0)
        # each state node: max(its p_hist, p); untouched where open
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            p_host = np.where(on, np.minimum(f_n / np.where(on, area, 1.0), np.finfo(float).max), 0)
        pc = np.where(p_host > 0, p_host, 0.0)  # the pressure the routine forms
        want = np.where(on[:, None], np.maximum(ph_nodes, pc[:, None]), ph_nodes)
        assert np.array_equal(state[:, :, 0], want)
        assert np.array_equal(state[on, :, 0].max(axis=1), hs.p_hist_trial)
        if nsv >= 2:
            # every cache is 0 ("recompute") or exactly that of its node's p_hist
            c = state[:, :, 1].ravel()
            phv = state[:, :, 0].ravel()
            known = c > 0
            check_cache(params, phv[known], c[known])
            # the node(s) holding the point's new p_hist carry its cache (> 0 where alpha1 < 1)
            phnew = state[:, :, 0].max(axis=1)
            top = state[:, :, 0] == phnew[:, None]
            raised = on & (pc > 0)
            a1 = fl.alpha_first(phnew[raised], params)
            must = np.repeat((a1 < 1 - 1e-12)[:, None], nns, 1) & top[raised]
            assert np.all(state[raised][:, :, 1][must] > 0)
            untouched = ~on
            assert np.array_equal(state[untouched, :, 1], before[untouched, :, 1])
        if nsv >= 3:
            tau = law.shear_limit(pc[on], ph[on])[0]
            edge = np.abs(f_stick[on] / area[on] - tau) <= 1e-9 * np.maximum(tau, TINY)
            st_out = state[on][:, :, 2].astype(int)
            for j in range(nns):
                assert np.array_equal(st_out[~edge, j], ref.status[~edge])
    return n * n_incr


@pytest.mark.parametrize("key", ["default", "soft", "sharp", "tab", "tab_flat"])
@settings(
    max_examples=12, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    seed=st.integers(0, 2**32 - 1), nns=st.sampled_from([1, 2, 4]), nsv=st.sampled_from([1, 2, 3])
)
def test_vfriction_agrees_with_runtime(tmp_path_factory, key, seed, nns, nsv):
    host, warnings = vfriction_lib(tmp_path_factory, key)
    others = [w for w in re.findall(r"Warning: (.*)", warnings) if "Unused dummy argument" not in w]
    assert others == []
    assert run_vfriction(host, PARAM_SETS[key], seed, nns, nsv) > 0

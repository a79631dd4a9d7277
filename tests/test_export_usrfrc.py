"""LS-DYNA ``usrfrc`` (SMP and MPP) against the runtime under LS-DYNA's explicit cycle.

The SMP routine is compiled with the host's precision flags (single precision as is; double
precision as LSTC's user-object makefiles build it, ifort ``-r8 -i8``, i.e. gfortran
``-fdefault-real-8 -fdefault-double-8 -fdefault-integer-8``) and driven as LS-DYNA's explicit
solver drives it: one call per cycle for the active slave nodes (``iisv5``), history committed
every cycle, no cut-backs, nodes entering and leaving contact, some never in contact. Each
cycle is compared node by node with ``frictionlaw.traction_update_force`` + ``HistoryState``.
Both reload forms (``tab``, ``tab_flat``: the tabulated form), single precision to 1e-6.
"""

import re

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from reload_tables import levels
from test_export_fortran import PARAM_SETS, check_cache, pressures

import frictionlaw as fl
import frictionlaw.export as exp
from frictionlaw.export import harness
from frictionlaw.export._templates import template_path

pytestmark = pytest.mark.skipif(
    harness.gfortran() is None,
    reason="gfortran not installed (.ci/run installs it: apt-get install -y gfortran)",
)

DTYPES = {"SP": np.float32, "DP": np.float64}
_LIBS = {}


def usrfrc_lib(tmp_path_factory, target, key, prec, k_t=None):
    tag = (target, key, prec, k_t)
    if tag not in _LIBS:
        path = tmp_path_factory.getbasetemp() / f"params_u_{key}.json"
        if not path.exists():
            PARAM_SETS[key].to_json(path)
        files, _ = exp.render(target, path, k_t=k_t)
        src = {n: t for n, t in files.items() if n.endswith(".f")}
        name = re.sub(r"[^a-z0-9]", "_", f"{target}_{key}_{prec}_{k_t}".lower())
        flags = ("-O2", *harness.HOST_PRECISION_FLAGS[prec])
        _LIBS[tag] = exp.target(target).harness.load(
            src, tmp_path_factory.mktemp(name), name=name, flags=flags, dtype=DTYPES[prec]
        )
    return _LIBS[tag]


def round_down(x, dtype):
    """The largest ``dtype`` value <= ``x`` (the routine's storage of ``p_hist``)."""
    r = np.minimum(x, np.finfo(dtype).max).astype(dtype)
    up = r.astype(np.float64) > x
    r[up] = np.nextafter(r[up], dtype(-np.inf))
    return r


def tangent_basis(n):
    """Two unit vectors orthogonal to each row of ``n`` (unit normals)."""
    a = np.where(np.abs(n[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    e1 = a - np.sum(a * n, axis=1, keepdims=True) * n
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    e2 = np.cross(n, e1)
    return e1, e2


def project(v, n):
    """Tangential part ``v - (v . n) n``, as the routine forms it (same ``n``)."""
    return v - np.sum(v * n, axis=1, keepdims=True) * n


def run_usrfrc(host, params, kt_spec, seed, nhv, n=64, n_cycles=10):
    """LS-DYNA's explicit cycle against the runtime; returns the number of node-cycles checked."""
    rng = np.random.default_rng(seed)
    dt = host.dtype
    sp = dt == np.float32
    law = fl.SBMFLaw(params)
    ilbsv = rng.permutation(n)  # history row of each slave node
    never = rng.random(n) < 0.15  # slave nodes never in contact
    fdat = np.zeros((n, 5), dt)
    fxyz = np.zeros((n, 3), dt)
    ufhist = np.zeros((n, nhv), dt)
    ph_c = np.zeros(n)  # committed p_hist per slave node (SI, double)
    active_prev = np.zeros(n, bool)
    checked = 0
    for _ in range(n_cycles):
        active = (rng.random(n) < 0.75) & ~never
        released = active_prev & ~active
        if rng.random() < 0.5:  # the host may or may not clear a released node's force
            fdat[released, 2:] = 0
        act = np.flatnonzero(active)
        # host inputs of this cycle (host REAL)
        area = 10.0 ** rng.uniform(-8, -4, n)
        area[rng.random(n) < 0.05] = 0.0  # zero area
        p = pressures(rng, n, ph_c, params.H, levels(params))
        if sp:  # single precision: forces and areas must be representable
            p = np.where((p > 0) & (p < 1e-30), 1e-30, np.minimum(p, 1e25))
        fni = (-p * area).astype(dt)
        kt_ref = 10.0 ** rng.uniform(11, 14, n)
        stfk = kt_ref * np.where(area > 0, area, 1e-6)
        stfk[rng.random(n) < 0.05] = 1e30 if sp else 1e290  # huge penalty
        stfk = stfk.astype(dt)
        nrm = rng.normal(size=(n, 3))
        rn = (nrm / np.linalg.norm(nrm, axis=1, keepdims=True)).astype(dt)
        mag = params.tau_max / kt_ref * 10.0 ** rng.uniform(-2, 1, n)
        d = (rng.normal(size=(n, 3)) * mag[:, None]).astype(dt)
        fxyz[:] = rng.normal(size=(n, 3)).astype(dt)
        fdat_in, fxyz_in, uf_in = fdat.copy(), fxyz.copy(), ufhist.copy()
        host(act, ilbsv, fni, area.astype(dt), stfk, 1.0, d, rn, fdat, fxyz, ufhist)
        # untouched: inactive nodes and their history rows
        assert np.array_equal(fdat[~active], fdat_in[~active])
        assert np.array_equal(fxyz[~active], fxyz_in[~active])
        rows_off = ilbsv[~active]
        assert np.array_equal(ufhist[rows_off], uf_in[rows_off])
        # never NaN, never a negative p_hist
        assert np.isfinite(fdat).all() and np.isfinite(fxyz).all() and np.isfinite(ufhist).all()
        if nhv:
            assert np.all(ufhist[:, 0] >= 0)
        # fxis += new friction force, in host arithmetic
        assert np.array_equal(fxyz[act], fxyz_in[act] + fdat[act, 2:])
        a64 = area.astype(dt).astype(np.float64)
        fn64 = -fni.astype(np.float64)
        noarea = active & ~(a64 > 0)
        assert np.all(fdat[noarea, 2:] == 0)
        if nhv:
            assert np.array_equal(ufhist[ilbsv[noarea], 0], uf_in[ilbsv[noarea], 0])
        # the reference, on the active nodes with an area
        on = np.flatnonzero(active & (a64 > 0))
        if on.size:
            nn = rn[on].astype(np.float64)
            nhat = nn / np.linalg.norm(nn, axis=1, keepdims=True)
            e1, e2 = tangent_basis(nhat)
            fo = project(fdat_in[on, 2:].astype(np.float64), nn)
            dd = project(d[on].astype(np.float64), nn)
            ph_in = np.maximum(uf_in[ilbsv[on], 0].astype(np.float64), 0) if nhv else 0 * a64[on]
            if not sp and nhv:
                assert np.array_equal(ph_in, ph_c[on])
            state = fl.HistoryState(p_hist=ph_in)
            pp = np.minimum(fn64[on] / a64[on], np.finfo(float).max)
            kt_pen = np.minimum(stfk[on].astype(np.float64) / a64[on], np.finfo(float).max)
            if kt_spec.kind == "host":
                kt = kt_pen
            elif kt_spec.kind == "constant":
                kt = np.full(on.size, kt_spec.value)
            else:
                kt = params.k_t(np.where(pp > 0, pp, 0.0))
            told = fo / a64[on, None]
            dd2 = np.stack([np.sum(dd * e1, 1), np.sum(dd * e2, 1)], 1)
            to2 = np.stack([np.sum(told * e1, 1), np.sum(told * e2, 1)], 1)
            with np.errstate(over="ignore", invalid="ignore"):
                ok = np.isfinite(kt * np.max(np.abs(dd2), 1)) & np.isfinite(to2).all(1)
            ref = fl.traction_update(law, np.where(pp > 0, pp, 0.0), dd2, to2, kt, state)
            f_ref = (ref.traction[:, :1] * e1 + ref.traction[:, 1:] * e2) * a64[on, None]
            f_out = fdat[on, 2:].astype(np.float64)
            with np.errstate(over="ignore"):
                # the raw (unprojected) vectors: in SP the host's normal is a unit vector only
                # to 1e-7, so the projection leaves that fraction of the normal parts
                d_raw = np.abs(d[on].astype(np.float64)).max(1)
                f_raw = np.abs(fdat_in[on, 2:].astype(np.float64)).max(1)
                kdd = np.maximum(kt * d_raw * a64[on], f_raw)
            scale = np.maximum.reduce(
                [
                    np.max(np.abs(f_ref), 1),
                    np.max(np.abs(fo), 1),
                    kdd,
                ]
            )
            rtol = 1e-6 if sp else 1e-12
            err = np.max(np.abs(f_out - f_ref), 1)
            floor = float(np.finfo(dt).tiny) * 1e6 if sp else 1e-300
            bad = ok & (err > rtol * np.maximum(scale, floor))
            assert not bad.any(), f"friction force: {bad.sum()} nodes off"
            # the force never exceeds tau(p, p_hist) area
            tau = law.shear_limit(np.where(pp > 0, pp, 0.0), ph_in)[0]
            # hypot, not the norm's sum of squares: forces of 1e-161 N square to subnormals
            fmag = np.hypot.reduce(f_out, axis=1)
            assert np.all(fmag <= tau * a64[on] * (1 + 1e-6) + floor)
            trial = np.maximum(ph_in, np.where(pp > 0, pp, 0.0))
            if nhv:
                got = ufhist[ilbsv[on], 0]
                if sp:
                    assert np.array_equal(got, round_down(trial, dt))
                else:
                    assert np.array_equal(got, state.p_hist_trial)
            if nhv >= 2:
                if sp:
                    assert np.all(ufhist[ilbsv[on], 1] == 0)
                else:
                    check_cache(params, ufhist[ilbsv[on], 0], ufhist[ilbsv[on], 1])
            if nhv >= 3:
                with np.errstate(over="ignore", invalid="ignore"):
                    tr = np.linalg.norm(to2 + kt[:, None] * dd2, axis=1)
                edge = np.abs(tr - tau) <= (1e-5 if sp else 1e-9) * np.maximum(tau, 1e-300)
                st_out = ufhist[ilbsv[on], 2].astype(int)
                keep = ok & ~edge
                assert np.array_equal(st_out[keep], ref.status[keep])
            ph_c[on] = ufhist[ilbsv[on], 0].astype(np.float64) if nhv else 0.0
            checked += on.size
        active_prev = active
    return checked


#: NHV >= 1: with none the guards refuse the law (tests/test_export_guards.py)
USRFRC_CASES = st.tuples(st.integers(0, 2**32 - 1), st.sampled_from([1, 2, 3]))


@pytest.mark.parametrize(
    "key,prec,k_t",
    [
        ("default", "DP", None),
        ("default", "SP", None),
        ("soft", "DP", None),
        ("sharp", "DP", 5e12),
        ("sharp", "SP", None),
        ("tab", "DP", None),
        ("tab", "SP", None),
        ("tab_flat", "DP", 5e12),
        ("tab_flat", "SP", None),
    ],
)
@settings(
    max_examples=12, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(case=USRFRC_CASES)
def test_usrfrc_agrees_with_runtime(tmp_path_factory, key, prec, k_t, case):
    seed, nhv = case
    host, warnings = usrfrc_lib(tmp_path_factory, "lsdyna-usrfrc", key, prec, k_t)
    others = [w for w in re.findall(r"Warning: (.*)", warnings) if "Unused dummy argument" not in w]
    assert others == []
    params = PARAM_SETS[key]
    kt_spec = exp.stiffness_spec(params, exp.UNIT_SYSTEMS["SI"], k_t)
    assert run_usrfrc(host, params, kt_spec, seed, nhv) > 0


def run_mpp(host, params, seed, nh, n=64, n_cycles=10):
    rng = np.random.default_rng(seed)
    dt = host.dtype
    sp = dt == np.float32
    law = fl.SBMFLaw(params)
    uh = np.zeros((n, nh), dt)
    ph_c = np.zeros(n)
    for _ in range(n_cycles):
        p = pressures(rng, n, ph_c, params.H, levels(params))
        if sp:
            p = np.where((p > 0) & (p < 1e-30), 1e-30, np.minimum(p, 1e25))
        prs = p.astype(dt)
        uh_in = uh.copy()
        mu = host(prs, uh)
        assert np.isfinite(mu).all() and np.all(mu >= 0) and np.array_equal(mu[:, 0], mu[:, 1])
        p64 = prs.astype(np.float64)
        ph = np.maximum(uh_in[:, 0].astype(np.float64), 0) if nh else np.zeros(n)
        on = p64 > 0
        tau = law.shear_limit(np.where(on, p64, 0.0), ph)[0]
        # mu p = tau(p, p_hist): the coefficient carries the law exactly (to host rounding)
        want = np.where(on, tau / np.where(on, p64, 1.0), 0.0)
        rtol = 1.2e-7 if sp else 1e-15
        normal = p64 > 1e-290
        np.testing.assert_allclose(mu[normal, 0].astype(np.float64), want[normal], rtol=rtol)
        assert np.all(mu[~on] == 0)
        if nh:
            trial = np.maximum(ph, np.where(on, p64, 0.0))
            got = uh[:, 0]
            if sp:
                assert np.array_equal(got, round_down(trial, dt))
            else:
                assert np.array_equal(got, trial)
            assert np.array_equal(uh[~on], uh_in[~on])
            ph_c = got.astype(np.float64)
        if nh >= 2 and not sp:
            check_cache(params, uh[:, 0], uh[:, 1])
    return n * n_cycles


@pytest.mark.parametrize(
    "key,prec",
    [
        ("default", "DP"),
        ("default", "SP"),
        ("soft", "DP"),
        ("tab", "DP"),
        ("tab", "SP"),
        ("tab_flat", "SP"),
    ],
)
@settings(
    max_examples=10, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(seed=st.integers(0, 2**32 - 1), nh=st.sampled_from([1, 2]))
def test_usrfrc_mpp_coefficient_agrees(tmp_path_factory, key, prec, seed, nh):
    host, warnings = usrfrc_lib(tmp_path_factory, "lsdyna-usrfrc-mpp", key, prec)
    others = [w for w in re.findall(r"Warning: (.*)", warnings) if "Unused dummy argument" not in w]
    assert others == []
    assert run_mpp(host, PARAM_SETS[key], seed, nh) > 0


def test_dp_build_without_double_8_is_refused(tmp_path):
    """``-fdefault-real-8`` alone (DOUBLE PRECISION promoted to quad) must not compile silently:
    the C library calls refuse a REAL(16) argument, so a wrong DP flag set is caught."""
    import subprocess

    path = tmp_path / "p.json"
    PARAM_SETS["default"].to_json(path)
    files, _ = exp.render("lsdyna-usrfrc", path)
    src = tmp_path / "u.f"
    src.write_text(files["sbmf_usrfrc_smp.f"])
    # LS-DYNA's iounits.inc (the routine's guards write to its units): the harness's stub
    (tmp_path / "iounits.inc").write_text(template_path("shims/iounits.inc").read_text())
    r = subprocess.run(
        [
            harness.gfortran(),
            "-fdefault-real-8",
            "-I",
            str(tmp_path),
            "-c",
            str(src),
            "-o",
            str(tmp_path / "u.o"),
        ],
        capture_output=True,
        text=True,
    )
    assert r.returncode != 0 and "REAL(16)" in r.stderr

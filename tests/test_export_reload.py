"""Both reload forms in every generated routine, on a grid that spans the reload table.

Each Fortran target is driven through its host harness so that what it returns is the shear
limit itself (a slip far beyond it: Abaqus FRIC's ``TAU`` and ``DDTDDP``, VFRIC's and
VFRICTION's force on a unit area with an unbounded stick force, ``SBMF_FRICTION``'s traction
and ``dt/dp``, LS-DYNA SMP's friction force on a unit area, MPP's coefficient times the
pressure), and compared node by node with the runtime's kernel (``frictionlaw.shear_limit`` and
``shear_limit_dp`` evaluate the same).

The grid: ``p_hist`` below the first level (down to 1e-300 Pa), at every level and one ulp
either side, between the levels, beyond the last one, at ``H`` and up to 1e6 ``H`` (the
routines whose guards stop above 100 H get the part of it up to 99 ``H``); ``p`` open
(0, negative), tiny (5e-324, 1e-310, 1e-300, 1e-200 Pa), 1e-12 .. 0.999 of ``p_hist``, 1e-12 and one ulp
below it, at it and above it. Every node twice: with the ``-ln alpha1(p_hist)`` cache the
routine itself wrote for ``p_hist`` (a first-loading call at ``p_hist``), and with 0
("recompute"); both must give the same numbers bit for bit.

In mm-t-s the reference is the runtime's kernel with ``tau_max`` and ``H`` in MPa (the table's
knots are in ``z = -ln(1 - p_hist/H)`` and ``C1, n1, C2, n2, s2`` are numbers: the levels
scale with ``H``, nothing else changes), on the routine's own MPa inputs.
LS-DYNA's single-precision builds get their inputs rounded to the host REAL (the reference is
evaluated on those rounded values) and must agree to 1e-6 relative (issue 31).
"""

import re

import numpy as np
import pytest
from reload_tables import levels
from test_export_fortran import PARAM_SETS, lib_for

import frictionlaw.export as exp
from frictionlaw._codes import CODE_SBMF
from frictionlaw.export import harness
from frictionlaw.law import evaluate, sbmf_coeffs

pytestmark = pytest.mark.skipif(
    harness.gfortran() is None,
    reason="gfortran not installed (.ci/run installs it: apt-get install -y gfortran)",
)

#: (parameter set, units): both forms, both continuous settings, one- and two-level tables
CASES = [
    ("default", "SI"),
    ("soft", "mm-t-s"),
    ("tab", "SI"),
    ("tab", "mm-t-s"),
    ("tab_flat", "SI"),
    ("tab_flat", "mm-t-s"),
    ("tab_single", "SI"),
    ("tab_pair", "mm-t-s"),
    ("tab_steep", "SI"),
]
#: every Fortran target with its host precision (LS-DYNA: SP and DP builds)
TARGETS = [
    ("abaqus-fric", "DP"),
    ("calculix", "DP"),
    ("abaqus-vfric", "DP"),
    ("abaqus-vfriction", "DP"),
    ("lsdyna", "DP"),
    ("ansys-userfric", "DP"),
    ("lsdyna-usrfrc", "DP"),
    ("lsdyna-usrfrc", "SP"),
    ("lsdyna-usrfrc-mpp", "DP"),
    ("lsdyna-usrfrc-mpp", "SP"),
]
#: the targets whose guards stop (or refuse) above 100 H: there the grid stops at 99 H; the
#: host-neutral SBMF_FRICTION returns the law beyond it (with its status) and runs all of it
STOPS_ABOVE_100H = {t for t, _ in TARGETS} - {"lsdyna", "ansys-userfric"}
#: agreement with the runtime: tau relative, dtau/dp relative (double hosts)
RTOL_TAU = {"DP": 1e-13, "SP": 1e-6}
RTOL_DTAU = 1e-12
BIG = 1e3  # slip (host length): a trial traction far beyond any shear limit

_LIBS = {}


def load(tmp_path_factory, target, key, units, prec):
    """The target's routine for parameter set ``key`` in ``units`` and host precision ``prec``."""
    if prec == "DP" and not target.startswith("lsdyna-usrfrc"):
        return lib_for(tmp_path_factory, target, key, units)[0]
    tag = (target, key, units, prec)
    if tag not in _LIBS:
        path = tmp_path_factory.getbasetemp() / f"params_r_{key}.json"
        if not path.exists():
            PARAM_SETS[key].to_json(path)
        files, _ = exp.render(target, path, units=units)
        src = {n: t for n, t in files.items() if n.endswith(".f")}
        name = re.sub(r"[^a-z0-9]", "_", f"r_{target}_{key}_{units}_{prec}".lower())
        flags = ("-O2", *harness.HOST_PRECISION_FLAGS[prec])
        dtype = np.float32 if prec == "SP" else np.float64
        _LIBS[tag] = exp.target(target).harness.load(
            src, tmp_path_factory.mktemp(name), name=name, flags=flags, dtype=dtype
        )[0]
    return _LIBS[tag]


def in_host_units(params, units):
    """The runtime's coefficient array of ``params`` with its stresses (``tau_max``, ``H``) in
    the host's unit: the law is dimensionless in ``p/H`` (the table's knots are in
    ``z = -ln(1 - p_hist/H)``), so the kernel then evaluates it on host-unit pressures."""
    c = sbmf_coeffs(params, params.tau_max * units.stress)
    c[1] = params.H * units.stress
    return c


def grid(params, rng):
    """``(p, p_hist)`` in Pa: the histories across the table times the pressures below them."""
    H = params.H
    lv = np.asarray(levels(params) or (0.1 * H, 0.5 * H, 0.95 * H))
    ph = [1e-300, 1e-200, 1e3, 1e6, 0.5 * lv[0], np.nextafter(lv[0], 0)]
    for a in lv:
        ph += [np.nextafter(a, 0), a, np.nextafter(a, 2 * a)]
    for a, b in zip(lv[:-1], lv[1:], strict=True):
        ph += [0.5 * (a + b), *rng.uniform(a, b, 2)]
    ph += [1.01 * lv[-1], 0.5 * (lv[-1] + H), np.nextafter(H, 0), H, np.nextafter(H, 2 * H)]
    ph += [2 * H, 1e3 * H, 1e6 * H]
    ph = np.asarray(ph)
    frac = np.array([1e-12, 1e-6, 1e-3, 0.01, 0.1, 0.3, 0.5, 0.7, 0.9, 0.999, 1 - 1e-12])
    cols = [np.zeros_like(ph), -ph, np.full_like(ph, 1e-300), np.full_like(ph, 1e-200)]
    cols += [np.full_like(ph, 5e-324), np.full_like(ph, 1e-310)]  # subnormal
    cols += [ph * f for f in frac]
    cols += [np.nextafter(ph, 0), ph, 2 * ph]
    p = np.stack(cols, 1)
    return p.ravel(), np.repeat(ph, len(cols))


def call(target, host, p, ph, g1):
    """``(tau, dtau or None, p_hist out, cache out or None)`` from the routine, host units."""
    n = p.size
    if target in ("abaqus-fric", "calculix"):
        out = host(p, np.full((n, 1), BIG), np.zeros((n, 1)), np.stack([ph, g1], 1), 1e-3)
        assert np.all((out["lm"] == 2) == ~(p > 0))
        return out["tau"][:, 0], out["ddtddp"][:, 0], out["statev"][:, 0], out["statev"][:, 1]
    if target == "abaqus-vfric":
        sv = np.ascontiguousarray(np.stack([ph, g1], 1))
        ft = host(p, np.full(n, 1e300), np.ones(n), sv)
        return -ft[:, 0], None, sv[:, 0], sv[:, 1]
    if target == "abaqus-vfriction":
        st = np.ascontiguousarray(np.stack([ph, g1], 1)[:, None, :])
        ft = host(p, np.full(n, 1e300), np.ones(n), st)
        return -ft[:, 0], None, st[:, 0, 0], st[:, 0, 1]
    if target in ("lsdyna", "ansys-userfric"):
        out = host(p, ph, g1, np.full((n, 1), BIG), np.zeros((n, 1)), 1e30)
        return out["t"][:, 0], out["dt_dp"][:, 0], out["p_hist"], out["g1h"]
    dt = host.dtype
    if target == "lsdyna-usrfrc-mpp":
        uh = np.ascontiguousarray(np.stack([ph, g1], 1).astype(dt))
        mu = host(p.astype(dt), uh)
        p_in = p.astype(dt).astype(np.float64)
        return mu[:, 0].astype(np.float64) * p_in, None, uh[:, 0], uh[:, 1]
    # lsdyna-usrfrc: unit areas, slip along x in the plane normal to z
    fdat = np.zeros((n, 5), dt)
    fxyz = np.zeros((n, 3), dt)
    uf = np.ascontiguousarray(np.stack([ph, g1, np.zeros(n)], 1).astype(dt))
    d = np.zeros((n, 3))
    d[:, 0] = BIG
    rn = np.zeros((n, 3))
    rn[:, 2] = 1.0
    host(np.arange(n), np.arange(n), -p, np.ones(n), np.full(n, 1e30), 1.0, d, rn, fdat, fxyz, uf)
    assert np.all(fdat[:, 3:] == 0) and np.all(fdat[:, 2] >= 0)
    return fdat[:, 2].astype(np.float64), None, uf[:, 0], uf[:, 1]


def rel(a, b, floor):
    """Node-wise ``|a - b| / max(|b|, floor)``."""
    return np.abs(a - b) / np.maximum(np.abs(b), floor)


def agreement(target, host, params, units, prec, p, ph):
    """Run the grid through the routine; returns the worst relative differences (dict)."""
    s = units.stress
    dt = np.float32 if prec == "SP" else np.float64
    tiny = float(np.finfo(dt).tiny)
    law = in_host_units(params, units)
    ps, phs = p * s, ph * s
    if prec == "SP":  # the host REAL: LS-DYNA passes single-precision pressures and history
        ps, phs = (v.astype(dt).astype(np.float64) for v in (ps, phs))
    # the routine's own cache for p_hist: a first-loading call at p = p_hist, p_hist = 0
    z = np.zeros_like(phs)
    cache = call(target, host, np.where(phs > 0, phs, 1.0), z, z)[3]
    cache = np.where(phs > 0, cache, 0.0).astype(np.float64)
    runs = [call(target, host, ps, phs, g) for g in (cache, z)]
    for a, b in zip(runs[0][:3], runs[1][:3], strict=True):  # cached == recomputed, bitwise
        assert a is None or np.array_equal(a, b)
    tau, dtau, ph_out, g1_out = runs[0]
    on = ps > 0  # the cache written: that of max(p_hist, p), whichever way it was found
    assert np.array_equal(g1_out[on], runs[1][3][on])
    assert np.array_equal(g1_out[~on], cache[~on].astype(g1_out.dtype))
    pos = np.where(ps > 0, ps, 0.0)
    want, want_d = evaluate(CODE_SBMF, law, pos, phs)
    # the history: max(p_hist, p) (LS-DYNA SP: rounded down to the host REAL)
    trial = np.maximum(phs, np.where(ps > 0, ps, 0.0))
    if prec == "SP":
        assert np.all(ph_out.astype(np.float64) <= trial)
        assert np.all(ph_out >= np.nextafter(trial.astype(dt), dt(0)))
    else:
        assert np.array_equal(ph_out, trial)
    assert np.all(np.isfinite(tau)) and np.all(tau >= 0)
    assert np.all(tau[~(ps > 0)] == 0)
    out = {"tau": rel(tau, want, tiny).max()}
    if target == "lsdyna-usrfrc-mpp":  # the coefficient itself: mu = tau/p
        on = ps > 1e-290
        mu = np.where(on, tau / np.where(on, ps, 1.0), 0.0)
        out["tau"] = rel(mu[on], want[on] / ps[on], tiny).max()
    if dtau is not None:
        out["dtau"] = rel(dtau, want_d, tiny).max()
    return out


@pytest.mark.parametrize("key,units", CASES)
@pytest.mark.parametrize("target,prec", TARGETS)
def test_routine_is_the_runtime_across_the_table(tmp_path_factory, target, prec, key, units):
    host = load(tmp_path_factory, target, key, units, prec)
    params = PARAM_SETS[key]
    p, ph = grid(params, np.random.default_rng(31))
    if prec == "SP":  # single-precision hosts: pressures a single-precision force can carry
        keep = (np.abs(p) * exp.UNIT_SYSTEMS[units].stress < 1e30) & (ph < 1e30)
        p, ph = p[keep], ph[keep]
    if target in STOPS_ABOVE_100H:
        keep = (p <= 99 * params.H) & (ph <= 99 * params.H)
        p, ph = p[keep], ph[keep]
    got = agreement(target, host, params, exp.UNIT_SYSTEMS[units], prec, p, ph)
    rtol = 1.2e-7 if (prec == "SP" and target.endswith("mpp")) else RTOL_TAU[prec]
    assert got["tau"] <= rtol, got
    if "dtau" in got:
        assert got["dtau"] <= RTOL_DTAU, got


def test_the_grid_spans_the_table():
    """The grid's histories reach every region the issue names, and the pressures hit them."""
    params = PARAM_SETS["tab"]
    p, ph = grid(params, np.random.default_rng(31))
    lv = np.asarray(levels(params))
    assert np.any(ph < lv[0]) and np.any(ph >= params.H) and np.any((ph > lv[-1]) & (ph < params.H))
    assert np.isin(lv, ph).all()
    between = (ph > lv[0]) & (ph < lv[-1]) & ~np.isin(ph, lv)
    assert between.sum() > 20
    assert np.any(p == 0) and np.any(p == 1e-300) and np.any(p == np.nextafter(ph, 0))
    # the reload branch for most nodes, first loading for the rest
    assert 0.6 < np.mean((p > 0) & (p < ph)) < 0.9
    # s2 at its lower bound: below p/p_hist = Q_START the branch starts quadratically, so dtau/dp
    # stays finite and moderate even at subnormal pressures (with q**s2 down to p = 0 it reached
    # the largest double here)
    steep = PARAM_SETS["tab_steep"]
    p, ph = grid(steep, np.random.default_rng(31))
    d = evaluate(CODE_SBMF, sbmf_coeffs(steep), p, ph)[1]
    below = ph < 0.99 * steep.H
    assert np.isfinite(d).all() and 100.0 < d[below].max() < 1e4
    # within 1e-6 of H the table's C2 rises to its cap 1e6 (the flattened limit): 1e3 times more
    assert d.max() < 1e8

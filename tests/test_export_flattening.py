"""The flattening under bulk strain in the exported routines (issue 43 part C), host emulation.

Where the host gives the bulk plastic strain (the host-neutral SBMF_FRICTION_V's DEPS, SIGY;
LS-DYNA's element plastic strain, UFEPS in SMP and UE in MPP), the routine flattens as the
runtime's traction update does with the same strain increments (1e-12 relative in double
precision, 1e-6 in LS-DYNA's single precision, where the history is stored as REAL, the fraction
rounded to nearest: over 20 000 cycles it stays within 1e-5 of the runtime, where rounding down
lost 4e-4);
where it does not (Abaqus' FRIC, VFRIC, VFRICTION, a deck without the state slots) it says so
once and runs the law without flattening (the patched CalculiX: tests/test_calculix_flattening.py). Tables and zoned exports of a
file with a flattening block are refused.
"""

import ctypes
import dataclasses
import re

import numpy as np
import pytest

import frictionlaw as fl
from frictionlaw import export as exp
from frictionlaw.export import harness
from frictionlaw.first_loading import FirstLoadingTable
from frictionlaw.flow_curve import SwiftCurve, TabulatedCurve
from frictionlaw.reload_form import ReloadTable

pytestmark = pytest.mark.skipif(harness.gfortran() is None, reason="needs gfortran")

H = 8e8
BASE = dict(m=0.5, sigma_y=H / 2.8, H=H, C1=1.05, n1=2.87, C2=7.44, n2=0.575)
FORMS = {
    "eq24-paper": {},
    "tabulated": dict(
        first_loading_form="tabulated",
        first_loading_table=FirstLoadingTable(
            p=(2e7, 5e7, 1e8, 2e8, 3e8, 4e8, 6e8, 7.6e8),
            alpha=(0.026, 0.064, 0.127, 0.25, 0.37, 0.48, 0.66, 0.79),
        ),
        reload_form="tabulated",
        reload_table=ReloadTable((1e8, 4e8, 7e8), (3.0, 6.0, 12.0), (0.5, 1.0, 2.0), 0.7),
        continuous_reload=True,
    ),
}


def law(form="eq24-paper", slope=0.05):
    return fl.FrictionParams(**BASE, **FORMS[form], flattening=fl.Flattening(slope=slope))


def load(tmp_path, target, params, *, units="SI", prec="DP", name=None, flow_curve=None):
    path = tmp_path / f"{name or target}.json"
    params.to_json(path)
    carries = bool(exp.target(target).form.bulk_strain) or params.flattening is None
    files, _ = exp.render(
        target, path, units=units, without_flattening=not carries, flow_curve=flow_curve
    )
    src = {n: t for n, t in files.items() if n.endswith(".f")}
    tag = re.sub(r"[^a-z0-9]", "_", f"f_{name or target}_{units}_{prec}".lower())
    options, flags = {}, ("-O2",)
    if "usrfrc" in target:
        flags = (*flags, *harness.HOST_PRECISION_FLAGS[prec])
        options["dtype"] = np.float32 if prec == "SP" else np.float64
    host, warnings = exp.target(target).harness.load(
        src, tmp_path / tag, name=tag, flags=flags, **options
    )
    assert "Error" not in warnings
    return host, files


def grid():
    p = np.array([0.01, 0.05, 0.1, 0.3, 0.6, 0.9]) * H
    g = np.meshgrid(p, [0.0, 0.5, 1.0, 2.0], [0.0, 0.2, 0.5, 0.8], [0, 1e-3, 0.01, 0.1], [0, 1])
    p, fac, af, de, sy = (a.ravel() for a in g)
    return p, fac * p, af, de, np.where(sy > 0, 2.0 * BASE["sigma_y"], 0.0)


def runtime(params, p, ph, af, de, sigy, hardening=None):
    """The runtime's traction update at slipping points: (|tau|, dtau/dp, trial alpha_f)."""
    n = p.size
    st = fl.HistoryState(p_hist=ph, alpha_f=af)
    sy = np.where(sigy > 0, sigy, params.sigma_y)
    res = fl.traction_update(
        fl.SBMFLaw(params),
        p,
        np.ones(n),
        np.zeros(n),
        1e30,
        st,
        d_eps=de,
        sigma_y=sy,
        hardening=hardening,
    )
    return np.abs(res.traction), res.dt_dp, st.alpha_f_trial.copy()


@pytest.mark.parametrize("form", FORMS)
def test_neutral_entry_flattens_as_the_runtime(tmp_path, form):
    _neutral_as_runtime(tmp_path, law(form), f"neutral_{form}")


def test_neutral_entry_at_the_smallest_slope(tmp_path):
    """A polished sheet (the validated range's end, 1e-8): full contact at any strain, as the
    runtime."""
    _neutral_as_runtime(tmp_path, law("tabulated", slope=1e-8), "neutral_smooth")


def _neutral_as_runtime(tmp_path, P, name):
    host, files = load(tmp_path, "lsdyna", P, name=name)
    assert "STATE(5)" in files["README.md"] and "DEPS" in files["README.md"]
    p, ph, af, de, sy = grid()
    n = p.size
    state = np.zeros((n, 5))
    state[:, 0], state[:, 4] = ph, af
    out = host.friction("", p, state, np.ones((n, 1)), np.zeros((n, 1)), 1e30, deps=de, sigy=sy)
    tau, dtdp, a_ref = runtime(P, p, ph, af, de, sy)
    assert np.all(out["ierr"] == 0)
    assert np.allclose(np.abs(out["t"][:, 0]), tau, rtol=1e-12, atol=0)
    # the tangent goes through the solve's last Newton step and the libm's cosh / sinh, which
    # differ between gfortran and LLVM in the last bits: 3e-12 seen at p = 0.01 H
    assert np.allclose(np.abs(out["dt_dp"][:, 0]), np.abs(dtdp), rtol=1e-11, atol=1e-300)
    assert np.allclose(state[:, 4], a_ref, rtol=1e-12, atol=0)
    assert np.array_equal(state[:, 0], np.maximum(ph, p))


@pytest.mark.parametrize("form", ["eq24-paper", "tabulated"])
def test_neutral_entry_limits_the_lattice_by_the_hardening_modulus(tmp_path, form):
    """STATE(6), the bulk's hardening modulus (Eqs. F2c, F2d): as the runtime's
    traction_update(..., hardening=), where the limit acts everywhere, nowhere and from inside
    the step, and where the sinking it holds stops the flattening; never
    written; 0 and NSTATE = 5 the perfectly plastic law bit for bit."""
    P = law(form)
    host, files = load(tmp_path, "lsdyna", P, name=f"neutral_h_{form}")
    assert "STATE(6) the bulk's hardening modulus" in files["README.md"]
    fn = host._lib.sbmf_nstate_
    fn.restype = ctypes.c_int
    assert fn() == 6
    p, ph, af, de, sy = grid()
    n = p.size
    # 6 p / h: 0.05 (limited throughout, 0.05 (1 - A) < c_L), 1.02 (the limit starts inside the
    # step: 1.02 (1 - A) falls below c_L as alpha rises), 50 (never but near full contact), and
    # DC04's modulus at eps 0.1 (700 MPa)
    cmax = np.array([0.05, 1.02, 50.0, np.nan])[np.arange(n) % 4]
    h = np.where(np.isnan(cmax), 7e8, 6.0 * p / np.nan_to_num(cmax, nan=1.0))
    state = np.zeros((n, 6))
    state[:, 0], state[:, 4], state[:, 5] = ph, af, h
    out = host.friction("", p, state, np.ones((n, 1)), np.zeros((n, 1)), 1e30, deps=de, sigy=sy)
    tau, dtdp, a_ref = runtime(P, p, ph, af, de, sy, hardening=h)
    assert np.all(out["ierr"] == 0)
    assert np.allclose(np.abs(out["t"][:, 0]), tau, rtol=1e-12, atol=0)
    assert np.allclose(np.abs(out["dt_dp"][:, 0]), np.abs(dtdp), rtol=1e-11, atol=1e-300)
    assert np.allclose(state[:, 4], a_ref, rtol=1e-12, atol=0)
    assert np.array_equal(state[:, 5], h)  # an input: never written
    # held at the sinking the modulus holds (Eq. F2d) on many of the points
    held = fl.alpha_first(np.maximum(ph, p), P) + 0.75 * p / (h * P.flattening.slope)
    assert np.sum((np.abs(state[:, 4] - held) <= 1e-12 * held) & (held > af)) > 10
    plastic = runtime(P, p, ph, af, de, sy)[2]
    slowed = (de > 0) & (cmax == 0.05) & (p > 0.05 * H) & (plastic < 1) & (plastic > af)
    assert slowed.sum() > 10 and np.all(a_ref[slowed] < plastic[slowed])
    for k in (5, 6):  # no slot, or a zero modulus: the perfectly plastic rate
        st = np.zeros((n, k))
        st[:, 0], st[:, 4] = ph, af
        host.friction("", p, st, np.ones((n, 1)), np.zeros((n, 1)), 1e30, deps=de, sigy=sy)
        assert np.allclose(st[:, 4], plastic, rtol=1e-12, atol=0)


def test_neutral_entry_in_mm_t_s_and_without_strain(tmp_path):
    P = law()
    host, _ = load(tmp_path, "lsdyna", P, units="mm-t-s", name="neutral_mm")
    p, ph, af, de, sy = grid()
    n = p.size
    state = np.zeros((n, 5))
    state[:, 0], state[:, 4] = ph * 1e-6, af
    out = host.friction(
        "", p * 1e-6, state, np.ones((n, 1)), np.zeros((n, 1)), 1e30, deps=de, sigy=sy * 1e-6
    )
    tau, _, a_ref = runtime(P, p, ph, af, de, sy)
    assert np.allclose(np.abs(out["t"][:, 0]) * 1e6, tau, rtol=1e-12, atol=0)
    assert np.allclose(state[:, 4], a_ref, rtol=1e-12, atol=0)
    # no strain on a surface never flattened: the law without a flattening block, bit for bit
    assert_plain_without_strain(tmp_path, host, p, ph, 5)


def assert_plain_without_strain(tmp_path, host, p, ph, nstate):
    """A routine in mm-t-s with a flattening block, called without strain on surfaces never
    flattened (``nstate`` state slots), returns the law without the block bit for bit: the
    traction, its derivatives, the status and the state."""
    n = p.size
    plain, _ = load(tmp_path, "lsdyna", fl.FrictionParams(**BASE), units="mm-t-s", name="plain")
    s1, s2 = (np.zeros((n, nstate)) for _ in range(2))
    s1[:, 0] = s2[:, 0] = ph * 1e-6
    o1 = host.friction("", p * 1e-6, s1, np.ones((n, 1)), np.zeros((n, 1)), 1e30)
    o2 = plain.friction("", p * 1e-6, s2, np.ones((n, 1)), np.zeros((n, 1)), 1e30)
    for k in ("t", "dt_ddu", "dt_dp", "status"):
        assert np.array_equal(o1[k], o2[k]), k
    assert np.array_equal(s1, s2)


def test_neutral_entry_without_the_state_slot_says_so_once(tmp_path):
    P = law()
    host, _ = load(tmp_path, "lsdyna", P, name="neutral_slot")
    p = np.array([0.1, 0.2, 0.3]) * H
    state = np.zeros((3, 4))
    out = host.friction("", p, state, np.ones((3, 1)), np.zeros((3, 1)), 1e30, deps=0.05)
    assert out["ierr"].tolist() == [9, 0, 0]
    assert np.allclose(np.abs(out["t"][:, 0]), fl.shear_limit(p, 0.0, P), rtol=1e-12)
    assert "NSTATE < 5" in host.message(9)


#: the workpiece's flow curves of --flow-curve: DC04's Swift curve and a table (MPa), whose
#: second and third segments the cycles' strains reach
CURVES = {
    None: None,
    "swift": SwiftCurve(530e6, 0.006, 0.24),
    "table": TabulatedCurve((0.0, 0.03, 0.1, 0.4), (2.0e8, 2.6e8, 3.1e8, 3.6e8)),
}


@pytest.mark.parametrize(
    ("prec", "curve"),
    [("DP", None), ("SP", None), ("DP", "swift"), ("DP", "table"), ("SP", "swift")],
)
def test_lsdyna_usrfrc_flattens_over_cycles(tmp_path, prec, curve):
    """SMP and MPP: the element plastic strain's increments between cycles in contact; with
    --flow-curve the flow stress and hardening modulus off the curve at the middle of each
    cycle's strain, as the runtime given both (traction_update(..., sigma_y=, hardening=))."""
    P = law()
    fc = CURVES[curve]
    smp, files = load(tmp_path, "lsdyna-usrfrc", P, prec=prec, flow_curve=fc)
    mpp, _ = load(tmp_path, "lsdyna-usrfrc-mpp", P, prec=prec, flow_curve=fc)
    assert ("SUBROUTINE SBMF_FLOW" in files["sbmf_usrfrc_smp.f"]) == (fc is not None)
    dt = np.float32 if prec == "SP" else np.float64
    tol = 1e-12 if prec == "DP" else 2e-6
    n = 4
    p = np.array([0.05, 0.1, 0.3, 0.5]) * H
    area = np.full(n, 1e-6)
    ufhist = np.zeros((n, 7), dt)
    uh = np.zeros((n, 7), dt)
    fdat = np.zeros((n, 5), dt)
    state = fl.HistoryState(n)
    rn = np.tile([0.0, 0.0, 1.0], (n, 1))
    d = np.tile([1.0, 0.0, 0.0], (n, 1))
    eps = np.zeros(n)
    prev_on = np.zeros(n, bool)
    plain = fl.HistoryState(n)  # the runtime without the curve, to show that it counts
    for cycle, (step, on) in enumerate(
        [(0.0, [1, 1, 1, 1]), (0.02, [1, 1, 1, 1]), (0.05, [1, 0, 1, 1]), (0.05, [1, 1, 1, 1])],
        start=1,
    ):
        eps = eps + step
        on = np.array(on, bool)
        act = np.flatnonzero(on)
        fni = np.where(on, -p * area, 0.0)
        smp(
            act,
            np.arange(n),
            fni,
            area,
            np.full(n, 1e6),
            1.0,
            d,
            rn,
            fdat,
            np.zeros((n, 3), dt),
            ufhist,
            ufeps=eps[:, None].astype(dt),
            ncycle=cycle,
        )
        mu = mpp(np.where(on, p, 0.0), uh, ue=eps[:, None].astype(dt), ncycle=cycle)
        # the runtime: the strain of this cycle counts where the point was in contact before
        de = np.where(on & prev_on, step, 0.0)
        af = state.alpha_f.copy()
        st = fl.HistoryState(p_hist=state.p_hist, alpha_f=af)
        kw = {}
        if fc is not None:  # at the middle of the cycle's strain, as the host's REAL holds it
            e_host = eps.astype(dt).astype(float)
            de_host = np.where(de > 0, e_host - (eps - step).astype(dt).astype(float), 0.0)
            mid = np.maximum(e_host - 0.5 * de_host, 0.0)
            kw = {"sigma_y": fc.sigma_y(mid), "hardening": fc.hardening(mid)}
            de = de_host
        fl.traction_update(
            fl.SBMFLaw(P), np.where(on, p, 0.0), np.ones(n), np.zeros(n), 1e30, st, d_eps=de, **kw
        )
        fl.traction_update(
            fl.SBMFLaw(P), np.where(on, p, 0.0), np.ones(n), np.zeros(n), 1e30, plain, d_eps=de
        )
        plain.commit()
        st.commit()
        state = st
        if cycle == 1:
            assert np.all(state.alpha_f == 0)  # nothing before: nothing counts
        if cycle >= 2:
            assert np.any(state.alpha_f > fl.alpha_first(p, P) + 0.01)
        for got in (ufhist[:, 4], uh[:, 4]):
            assert np.allclose(got.astype(float), state.alpha_f, rtol=tol, atol=0)
            if prec == "SP":  # stored rounded to nearest: within half a REAL ulp of it
                assert np.all(np.abs(got.astype(float) - state.alpha_f) <= 6e-8)
        tau = fl.SBMFLaw(P).shear_limit(p, 0.0)[0]
        lim = P.tau_max * np.maximum(state.alpha_f, fl.alpha_first(p, P))
        assert np.allclose(np.abs(fdat[on, 2]) / area[on], lim[on], rtol=tol)
        assert np.allclose(mu[on, 0].astype(float) * p[on], lim[on], rtol=tol)
        assert np.all(lim >= tau * (1 - 1e-12))
        prev_on = on
    assert smp.log()["messag"] == [] and mpp.log()["messag"] == []
    moved = np.abs(state.alpha_f - plain.alpha_f).max()
    assert (moved > 0.01) if fc is not None else (moved == 0.0)


def test_lsdyna_single_precision_does_not_drift_over_many_cycles(tmp_path):
    """20 000 cycles of 2e-6 of strain in single precision (MPP; its history as REAL): the
    fraction is stored rounded to nearest, so it stays within 1e-5 of the runtime given the
    total strain (the one-state update is exact, so any split gives the same); stored rounded
    down it lost half an ulp a cycle, 4e-4 after these cycles."""
    P = law()
    mpp, _ = load(tmp_path, "lsdyna-usrfrc-mpp", P, prec="SP", name="mpp_drift")
    n = 4
    p = np.array([0.05, 0.1, 0.3, 0.5]) * H
    uh = np.zeros((n, 7), np.float32)
    cycles, step = 20_000, 2e-6
    strain = (np.arange(1, cycles + 1) * step).astype(np.float32)
    for c in range(cycles):
        mpp(p, uh, ue=np.full((n, 1), strain[c], np.float32), ncycle=c + 1)
    st = fl.HistoryState(n)
    de = float(strain[-1]) - float(strain[0])  # the first cycle starts the count
    fl.traction_update(fl.SBMFLaw(P), p, np.ones(n), np.zeros(n), 1e30, st, d_eps=de)
    assert np.any(st.alpha_f_trial < 0.95) and np.all(uh[:, 4] > 0)
    np.testing.assert_allclose(uh[:, 4].astype(float), st.alpha_f_trial, rtol=0, atol=1e-5)


def test_lsdyna_without_strain_or_slots_says_so_once(tmp_path):
    P = law()
    smp, _ = load(tmp_path, "lsdyna-usrfrc", P, name="smp_few")
    mpp, _ = load(tmp_path, "lsdyna-usrfrc-mpp", P, name="mpp_few")
    n = 2
    p = np.array([0.1, 0.3]) * H
    area = np.full(n, 1e-6)
    for _ in range(2):
        fdat = np.zeros((n, 5))
        uf = np.zeros((n, 4))
        smp(
            np.arange(n),
            np.arange(n),
            -p * area,
            area,
            np.full(n, 1e6),
            1.0,
            np.tile([1.0, 0, 0], (n, 1)),
            np.tile([0, 0, 1.0], (n, 1)),
            fdat,
            np.zeros((n, 3)),
            uf,
            ufeps=np.full((n, 1), 0.1),
        )
        mu = mpp(p, np.zeros((n, 7)))  # NE = 0: no element data
        lim = fl.shear_limit(p, 0.0, P)
        assert np.allclose(np.abs(fdat[:, 2]) / area, lim, rtol=1e-12)
        assert np.allclose(mu[:, 0] * p, lim, rtol=1e-12)
    for host in (smp, mpp):
        warn = [x for x in host.log()["messag"] if "flattening block" in x]
        assert len(warn) == 1 and "Warning" in warn[0]
        assert "NHV < 7" in warn[0] or "NH < 7" in warn[0]


@pytest.mark.parametrize("target", ["abaqus-fric", "abaqus-vfric", "abaqus-vfriction"])
def test_hosts_without_bulk_strain_say_so_once_and_run_the_law(tmp_path, target):
    P = law()
    host, files = load(tmp_path, target, P)
    readme = files["README.md"]
    assert "flattening" in readme
    p = np.array([0.1, 0.3]) * H
    for _ in range(3):
        if target == "abaqus-fric":
            out = host(p, np.full((2, 1), 1e3), np.zeros((2, 1)), np.zeros((2, 3)), 1e-3)
            tau = np.abs(out["tau"][:, 0])
        else:  # Abaqus/Explicit: forces over the nodal area, a stick force far above
            state = np.zeros((2, 3)) if target == "abaqus-vfric" else np.zeros((2, 1, 3))
            ft = host(p * 1e-6, np.full(2, 1e9), np.full(2, 1e-6), state)
            tau = np.abs(ft[:, 0]) / 1e-6
        assert np.allclose(tau, fl.shear_limit(p, 0.0, P), rtol=1e-12)
    log = [t for lop, t in host.log() if "flattening block" in t]
    assert len(log) == 1 and host.exits() == 0
    assert "runs without flattening" in log[0]


def test_hosts_without_bulk_strain_need_the_users_word_and_the_option_is_never_ignored(tmp_path):
    """A host that passes no bulk strain would drop the flattening: refused unless the user says
    so (--without-flattening); the option where nothing is dropped is refused too."""
    from frictionlaw.export.cli import main

    flat = law().to_json(tmp_path / "flat.json")
    plain = dataclasses.replace(law(), flattening=None).to_json(tmp_path / "plain.json")
    for target in ("abaqus-fric", "abaqus-vfric", "abaqus-vfriction"):
        with pytest.raises(ValueError, match="passes no bulk plastic strain"):
            exp.render(target, flat)
        assert exp.render(target, flat, without_flattening=True)[0]
    for target in ("lsdyna-usrfrc", "calculix"):
        with pytest.raises(ValueError, match="runs the flattening"):
            exp.render(target, flat, without_flattening=True)
    with pytest.raises(ValueError, match="has none"):
        exp.render("abaqus-fric", plain, without_flattening=True)
    base = ["abaqus-fric", "--params", str(flat), "--out"]
    assert main([*base, str(tmp_path / "a")]) == 2 and not (tmp_path / "a").exists()
    assert main([*base, str(tmp_path / "b"), "--without-flattening"]) == 0


def test_a_flow_curve_is_read_where_the_host_passes_only_the_strain(tmp_path, capsys):
    """--flow-curve: LS-DYNA's usrfrc (SMP, MPP) with a flattening block; refused, saying why,
    where the caller passes the flow stress and modulus, the host no strain, or the file has no
    block (no option silently ignored); the header names the curve."""
    from frictionlaw.export.cli import main

    flat = law().to_json(tmp_path / "flat.json")
    plain = dataclasses.replace(law(), flattening=None).to_json(tmp_path / "plain.json")
    swift = "swift:530e6,0.006,0.24"
    with pytest.raises(ValueError, match="caller passes the flow stress .SIGY. and the hard"):
        exp.render("lsdyna", flat, flow_curve=swift)
    with pytest.raises(ValueError, match="its host passes no bulk plastic strain"):
        exp.render("abaqus-fric", flat, flow_curve=swift, without_flattening=True)
    with pytest.raises(ValueError, match="no flattening block"):
        exp.render("lsdyna-usrfrc", plain, flow_curve=swift)
    files, _ = exp.render("lsdyna-usrfrc-mpp", flat, flow_curve=swift, units="mm-t-s")
    src = files["sbmf_usrfrc_mpp.f"]
    assert "flow curve of the workpiece (--flow-curve): Swift: K 530 MPa" in src
    assert "PARAMETER (K = 5.3" in src.replace("5.30", "5.3")  # K in MPa for mm-t-s
    base = ["--params", str(flat), "--flow-curve"]
    assert main(["lsdyna", *base, swift, "--out", str(tmp_path / "a")]) == 2
    err = capsys.readouterr().err
    assert "--flow-curve applies to lsdyna-usrfrc" in err and "Traceback" not in err
    assert main(["lsdyna-usrfrc", *base, "swift:530,0.006,0.24", "--out", str(tmp_path / "b")]) == 2
    assert "K (Pa) must be in" in capsys.readouterr().err
    assert main(["lsdyna-usrfrc", *base, swift, "--out", str(tmp_path / "c")]) == 0
    assert not (tmp_path / "a").exists() and not (tmp_path / "b").exists()


@pytest.mark.parametrize("target", ["abaqus-fric", "lsdyna-usrfrc", "lsdyna"])
def test_a_calibration_with_a_tabulated_first_loading_exports(tmp_path, target, capsys):
    """The shipped calibration (fe_demo/data, the calibration's default tabulated first loading,
    whose fit record has no rmse: it passes through its points) exported through the command:
    exit 0, its fit in the header (the header once failed on the missing rmse, a traceback)."""
    from pathlib import Path

    from frictionlaw.export.cli import main

    path = Path(__file__).parents[1] / "fe_demo" / "data" / "sbmf_example_flattening.json"
    extra = ["--without-flattening"] if target == "abaqus-fric" else []
    assert main([target, "--params", str(path), "--out", str(tmp_path / "o"), *extra]) == 0
    assert "Traceback" not in capsys.readouterr().err
    src = next(p for p in (tmp_path / "o").iterdir() if p.suffix == ".f").read_text()
    assert "fit first_loading: tabulated form, max |d alpha|=0, points=11" in src


def test_tables_carry_no_flattening_and_say_so(tmp_path, capsys):
    """A table is a law of the pressure alone: a file with a flattening block is refused (exit
    2, naming --without-flattening); with the option the table of the law without it is
    written, the same rows as the file without its block, and its header says so. Zoned
    routines carry the block (tests/test_export_zones_flattening.py), under the same rule for
    hosts without strain."""
    from frictionlaw.export.cli import main

    path = law().to_json(tmp_path / "flat.json")
    plain = dataclasses.replace(law(), flattening=None).to_json(tmp_path / "plain.json")
    for target in ("abaqus-table", "lsdyna-table"):
        with pytest.raises(ValueError, match="table of the pressure alone"):
            exp.render(target, path)
        out = tmp_path / target
        assert main([target, "--params", str(path), "--out", str(out)]) == 2
        assert "give --without-flattening" in capsys.readouterr().err and not out.exists()
        files, table = exp.render(target, path, without_flattening=True)
        _, table0 = exp.render(target, plain)
        name = exp.target(target).file
        assert "flattening block (issue 43) is not carried" in " ".join(files[name].split())
        np.testing.assert_array_equal(table.p, table0.p)
        np.testing.assert_array_equal(table.mu, table0.mu)
    with pytest.raises(ValueError, match="passes no bulk plastic strain"):
        exp.render("abaqus-fric", None, zones=[("rim", path)])


def test_a_flow_curve_beside_a_beta_fitted_as_perfectly_plastic_is_warned(tmp_path, capsys):
    from frictionlaw.export.cli import main

    P = law()
    fitted = P.replace(provenance={"flattening": {"fit": {"beta": 0.5, "flow_curve": None}}})
    path = fitted.to_json(tmp_path / "fitted.json")
    argv = ["lsdyna-usrfrc", "--params", str(path), "--flow-curve", "swift:530e6,0.006,0.24"]
    assert main([*argv, "--out", str(tmp_path / "o")]) == 0
    assert "absorbs the sheet's hardening" in capsys.readouterr().err
    assert main(["lsdyna-usrfrc", "--params", str(path), "--out", str(tmp_path / "p")]) == 0
    assert "absorbs" not in capsys.readouterr().err

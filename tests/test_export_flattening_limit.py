"""The two-state flattening (model limit-analysis) in the exported routines, host emulation.

Where the host gives the bulk plastic strain (the host-neutral SBMF_FRICTION_V, LS-DYNA's
usrfrc in SMP and MPP, the patched CalculiX's FRIC), a routine exported from a parameter file
whose flattening block is the two-state model carries the shipped rate table and both states
(the flattened fraction and the flank slope, one more state slot than the one-state model),
and flattens as the runtime's traction update does given the same strain increments: 1e-12
relative on the shear and the states in double precision (the table read and integrated
statement by statement), 2e-6 in LS-DYNA's single precision; the update's d alpha/dp, carried
through the integration in both, to 1e-12. Without the extra slot the routine says so once and
runs the law without flattening.
"""

import numpy as np
import pytest
from test_export_flattening import BASE, H, assert_plain_without_strain, load

import frictionlaw as fl
from frictionlaw import export as exp
from frictionlaw._limit_table import rate_table
from frictionlaw.export import harness
from frictionlaw.export._flat import data_statements, fortran_short, limit_spec
from frictionlaw.export.cli import main as export_main

pytestmark = pytest.mark.skipif(harness.gfortran() is None, reason="needs gfortran")

TWO = "limit-analysis"
#: an edge-slope table (flattening.edge_slope): the flank the law reads follows it
EDGE = tuple(float(v) for v in 0.02 + 0.08 * np.linspace(0.0, 1.0, 21) ** 1.5)


def law(slope=0.05, beta=1.0, edge=None):
    flat = fl.Flattening(slope=slope, beta=beta, model=TWO, edge_slope=edge)
    return fl.FrictionParams(**BASE, flattening=flat)


def grid():
    """Pressures 0.01-0.9 H (the table's 0.02-0.6 H_P and beyond both ends), histories below,
    at and above, committed fractions and slopes (0: never flattened), strain increments
    0-0.1, the file's and a doubled flow stress."""
    p = np.array([0.01, 0.05, 0.1, 0.3, 0.6, 0.9]) * H
    g = np.meshgrid(
        p, [0.0, 0.5, 2.0], [0.0, 0.3, 0.8], [0.0, 0.02, 0.12], [0, 1e-3, 0.02, 0.1], [0, 1]
    )
    p, fac, af, sf, de, sy = (a.ravel() for a in g)
    return p, fac * p, af, sf, de, np.where(sy > 0, 2.0 * BASE["sigma_y"], 0.0)


def runtime(params, p, ph, af, sf, de, sigy):
    """The runtime's traction update at slipping points: (|tau|, dtau/dp, alpha_f', slope_f')."""
    n = p.size
    st = fl.HistoryState(p_hist=ph, alpha_f=af, slope_f=sf)
    sy = np.where(sigy > 0, sigy, params.sigma_y)
    res = fl.traction_update(
        fl.SBMFLaw(params), p, np.ones(n), np.zeros(n), 1e30, st, d_eps=de, sigma_y=sy
    )
    return np.abs(res.traction), res.dt_dp, st.alpha_f_trial.copy(), st.slope_f_trial.copy()


def test_the_table_is_written_bit_for_bit():
    """The DATA statements read back to the runtime's arrays exactly (shortest round-trip
    literals), in fixed form's 72 columns and at most 19 continuation lines a statement."""
    assert fortran_short(0.1) == "0.1D0" and fortran_short(-2.5e-7) == "-2.5D-7"
    assert float(fortran_short(np.pi).replace("D", "e")) == np.pi
    spec = limit_spec()
    table = rate_table()
    values = {}
    for stmt in spec.data:
        lines = stmt.splitlines()
        assert all(len(line) <= 72 for line in lines) and len(lines) - 1 <= 19
        name = lines[0].split("(")[1]
        body = " ".join(line[8:] for line in lines[1:]).rstrip(" /")
        values.setdefault(name, []).extend(
            float(v.replace("D", "e")) for v in body.split(",") if v.strip()
        )
    assert np.array_equal(values["OFF"], table.offsets)
    assert np.array_equal(values["AR"], table.a)
    assert np.array_equal(values["LS"], table.ln_s)
    assert np.array_equal(values["DA"], table.dA.ravel())
    assert np.array_equal(values["DS"], table.ds.ravel())
    first, *_ = data_statements("X", [1.0, 2.0, 3])
    assert first.endswith("1.0D0, 2.0D0, 3 /")


@pytest.mark.parametrize(
    ("target", "edge"), [("lsdyna", None), ("ansys-userfric", None), ("lsdyna", EDGE)]
)
def test_neutral_entry_flattens_as_the_runtime(tmp_path, target, edge):
    """The neutral entry's states, shear and tangent as the runtime's, with the block's one
    slope and with an edge-slope table (the routine then carries it as DATA, ``TEDG``)."""
    P = law(edge=edge)
    host, files = load(tmp_path, target, P, name=f"two_{target}_{edge is None}")
    routine = next(v for k, v in files.items() if k.endswith(".f"))
    assert ("TEDG" in routine) == (edge is not None)
    assert ("`edge_slope`, 21\nvalues" in files["README.md"]) == (edge is not None)
    readme = files["README.md"]
    assert "STATE(7)" in readme and "flank slope" in readme
    p, ph, af, sf, de, sy = grid()
    n = p.size
    state = np.zeros((n, 7))
    state[:, 0], state[:, 4], state[:, 6] = ph, af, sf
    state[:, 5] = 1e9  # a hardening modulus: not read by the two-state model
    out = host.friction("", p, state, np.ones((n, 1)), np.zeros((n, 1)), 1e30, deps=de, sigy=sy)
    tau, dtdp, a_ref, s_ref = runtime(P, p, ph, af, sf, de, sy)
    assert np.all(out["ierr"] == 0)
    assert np.allclose(np.abs(out["t"][:, 0]), tau, rtol=1e-12, atol=0)
    # carried through the integration in both (1.4e-14 seen)
    assert np.allclose(np.abs(out["dt_dp"][:, 0]), np.abs(dtdp), rtol=1e-12, atol=1e-300)
    assert np.allclose(state[:, 4], a_ref, rtol=1e-12, atol=0)
    assert np.allclose(state[:, 6], s_ref, rtol=1e-12, atol=0)
    assert np.array_equal(state[:, 0], np.maximum(ph, p))
    # the grid exercises the model: fractions grown, slopes turned, untouched without strain
    grew = state[:, 4] > np.maximum(af, fl.alpha_first(np.maximum(p, ph), P)) + 0.01
    assert grew.sum() > 100
    assert np.any(state[:, 6] < np.where(sf > 0, sf, 0.05) * 0.9)
    still = de == 0
    assert np.array_equal(state[still, 4], af[still]) and np.array_equal(state[still, 6], sf[still])
    # the one-state block's update on the same inputs differs (the model run is the two-state)
    one = fl.FrictionParams(**BASE, flattening=fl.Flattening(slope=0.05))
    st1 = fl.HistoryState(p_hist=ph, alpha_f=af)
    fl.traction_update(
        fl.SBMFLaw(one), p, np.ones(n), np.zeros(n), 1e30, st1, d_eps=de,
        sigma_y=np.where(sy > 0, sy, P.sigma_y),
    )  # fmt: skip
    assert np.abs(st1.alpha_f_trial - state[:, 4]).max() > 0.05


def test_neutral_entry_in_mm_t_s(tmp_path):
    """Exported for mm-t-s (MPa): pressures, flow stresses and shear in MPa, the table (in
    p / H_P, dimensionless) read the same; the states and the shear as the runtime's in SI to
    1e-12; without strain on a surface never flattened the law itself, bit for bit."""
    P = law()
    host, _ = load(tmp_path, "lsdyna", P, units="mm-t-s", name="two_mm")
    p, ph, af, sf, de, sy = grid()
    n = p.size
    state = np.zeros((n, 7))
    state[:, 0], state[:, 4], state[:, 6] = ph * 1e-6, af, sf
    out = host.friction(
        "", p * 1e-6, state, np.ones((n, 1)), np.zeros((n, 1)), 1e30, deps=de, sigy=sy * 1e-6
    )
    tau, dtdp, a_ref, s_ref = runtime(P, p, ph, af, sf, de, sy)
    assert np.all(out["ierr"] == 0)
    assert np.allclose(np.abs(out["t"][:, 0]) * 1e6, tau, rtol=1e-12, atol=0)
    assert np.allclose(np.abs(out["dt_dp"][:, 0]), np.abs(dtdp), rtol=1e-11, atol=1e-300)
    assert np.allclose(state[:, 4], a_ref, rtol=1e-12, atol=0)
    assert np.allclose(state[:, 6], s_ref, rtol=1e-12, atol=0)
    assert_plain_without_strain(tmp_path, host, p, ph, 7)


def test_neutral_entry_without_the_slope_slot_says_so_once(tmp_path):
    """NSTATE 5 or 6 (enough for the one-state model) is too few for the two-state model: the
    law without flattening, IERR = 9 once, the message naming STATE(7); SBMF_NSTATE() says 7."""
    P = law()
    host, files = load(tmp_path, "lsdyna", P, name="two_slot")
    assert "SBMF_NSTATE = 7" in files["sbmf_lsdyna.f"]
    p = np.array([0.1, 0.2, 0.3]) * H
    for nstate in (6, 5):
        state = np.zeros((3, nstate))
        out = host.friction("", p, state, np.ones((3, 1)), np.zeros((3, 1)), 1e30, deps=0.05)
        assert out["ierr"].tolist() == ([9, 0, 0] if nstate == 6 else [0, 0, 0])
        assert np.allclose(np.abs(out["t"][:, 0]), fl.shear_limit(p, 0.0, P), rtol=1e-12)
        assert np.all(state[:, 4] == 0)
    msg = host.message(9)
    assert "NSTATE < 7" in msg and "STATE(7)" in msg


@pytest.mark.parametrize(
    ("prec", "curve", "edge"),
    [("DP", None, None), ("SP", None, None), ("DP", "swift", None), ("DP", None, EDGE)],
)
def test_lsdyna_usrfrc_flattens_over_cycles(tmp_path, prec, curve, edge):
    """SMP and MPP: the element plastic strain's increments between cycles in contact, the
    slope in history variable 8 (NHV >= 8); with --flow-curve the flow stress off the curve at
    the middle of each cycle's strain, as the runtime given it (the hardening modulus not
    read: the table is perfectly plastic); with an edge-slope table as well."""
    from test_export_flattening import CURVES

    P = law(edge=edge)
    fc = CURVES[curve]
    tag = f"{prec}{curve}{edge is None}"
    smp, files = load(tmp_path, "lsdyna-usrfrc", P, prec=prec, flow_curve=fc, name=f"smp{tag}")
    mpp, mfiles = load(tmp_path, "lsdyna-usrfrc-mpp", P, prec=prec, flow_curve=fc, name=f"mpp{tag}")
    assert "(NHV >= 8)" in files["README.md"] and "(NH >= 8)" in mfiles["README.md"]
    dt = np.float32 if prec == "SP" else np.float64
    tol = 1e-12 if prec == "DP" else 2e-6
    n = 4
    p = np.array([0.05, 0.1, 0.3, 0.5]) * H
    area = np.full(n, 1e-6)
    ufhist = np.zeros((n, 8), dt)
    uh = np.zeros((n, 8), dt)
    fdat = np.zeros((n, 5), dt)
    state = fl.HistoryState(n)
    rn = np.tile([0.0, 0.0, 1.0], (n, 1))
    d = np.tile([1.0, 0.0, 0.0], (n, 1))
    eps = np.zeros(n)
    prev_on = np.zeros(n, bool)
    for cycle, (step, on) in enumerate(
        [(0.0, [1, 1, 1, 1]), (0.02, [1, 1, 1, 1]), (0.05, [1, 0, 1, 1]), (0.05, [1, 1, 1, 1])],
        start=1,
    ):
        eps = eps + step
        on = np.array(on, bool)
        act = np.flatnonzero(on)
        fni = np.where(on, -p * area, 0.0)
        start = ufhist[:, 4].astype(float), ufhist[:, 7].astype(float)  # as the host holds them
        smp(
            act, np.arange(n), fni, area, np.full(n, 1e6), 1.0, d, rn, fdat,
            np.zeros((n, 3), dt), ufhist, ufeps=eps[:, None].astype(dt), ncycle=cycle,
        )  # fmt: skip
        mu = mpp(np.where(on, p, 0.0), uh, ue=eps[:, None].astype(dt), ncycle=cycle)
        de = np.where(on & prev_on, step, 0.0)
        kw = {}
        if fc is not None:  # at the middle of the cycle's strain, as the host's REAL holds it
            e_host = eps.astype(dt).astype(float)
            de_host = np.where(de > 0, e_host - (eps - step).astype(dt).astype(float), 0.0)
            kw = {"sigma_y": fc.sigma_y(np.maximum(e_host - 0.5 * de_host, 0.0))}
            de = de_host
        st = fl.HistoryState(p_hist=state.p_hist, alpha_f=state.alpha_f, slope_f=state.slope_f)
        if prec == "SP":  # the host keeps the states as REAL: the runtime starts from them
            st = fl.HistoryState(p_hist=state.p_hist, alpha_f=start[0], slope_f=start[1])
        fl.traction_update(
            fl.SBMFLaw(P), np.where(on, p, 0.0), np.ones(n), np.zeros(n), 1e30, st, d_eps=de, **kw
        )
        st.commit()
        state = st
        if cycle >= 2:
            assert np.any(state.alpha_f > fl.alpha_first(p, P) + 0.01)
            moved = on & prev_on  # strained in contact: both states written
            assert np.all(state.slope_f[moved] > 0)
            assert np.any(np.abs(state.slope_f[moved] - 0.05) > 1e-3)
        for hist in (ufhist, uh):
            assert np.allclose(hist[:, 4].astype(float), state.alpha_f, rtol=tol, atol=0)
            assert np.allclose(hist[:, 7].astype(float), state.slope_f, rtol=tol, atol=0)
        lim = P.tau_max * np.maximum(state.alpha_f, fl.alpha_first(p, P))
        assert np.allclose(np.abs(fdat[on, 2]) / area[on], lim[on], rtol=tol)
        assert np.allclose(mu[on, 0].astype(float) * p[on], lim[on], rtol=tol)
        prev_on = on
    assert smp.log()["messag"] == [] and mpp.log()["messag"] == []


def test_lsdyna_with_seven_history_variables_says_so_once(tmp_path):
    """NHV = 7 (the one-state model's count): the law without flattening, one warning naming
    NHV < 8."""
    P = law()
    smp, _ = load(tmp_path, "lsdyna-usrfrc", P, name="smp_seven")
    n = 2
    p = np.array([0.1, 0.3]) * H
    area = np.full(n, 1e-6)
    ufhist = np.zeros((n, 7))
    fdat = np.zeros((n, 5))
    rn = np.tile([0.0, 0.0, 1.0], (n, 1))
    d = np.tile([1.0, 0.0, 0.0], (n, 1))
    for cycle, e in enumerate((0.0, 0.05, 0.1), start=1):
        smp(
            np.arange(n), np.arange(n), -p * area, area, np.full(n, 1e6), 1.0, d, rn, fdat,
            np.zeros((n, 3)), ufhist, ufeps=np.full((n, 1), e), ncycle=cycle,
        )  # fmt: skip
    assert np.all(ufhist[:, 4:] == 0)
    assert np.allclose(np.abs(fdat[:, 2]) / area, fl.shear_limit(p, 0.0, P), rtol=1e-12)
    log = smp.log()["messag"]
    assert len(log) == 1 and "NHV < 8" in log[0], log


@pytest.mark.parametrize("edge", [None, EDGE])
def test_calculix_fric_flattens_as_the_runtime(tmp_path, edge):
    """The patched ccx's FRIC (PREDEF(2, 1) the increment's strain): STATEV(5) and STATEV(6)
    as the runtime's trial states; FRIC_DEPVAR() asks for 6 (with an edge table too)."""
    P = law(edge=edge)
    host, files = load(tmp_path, "calculix", P, name=f"two_ccx_{edge is None}")
    assert "FRIC_DEPVAR = 6" in files["sbmf_fric.f"]
    p, ph, af, sf, de, sy = grid()
    keep = sy == 0  # FRIC: the file's flow stress (no flow curve baked in)
    p, ph, af, sf, de = p[keep], ph[keep], af[keep], sf[keep], de[keep]
    n = p.size
    sv = np.zeros((n, 6))
    sv[:, 0], sv[:, 4], sv[:, 5] = ph, af, sf
    eps = de + np.linspace(0.0, 0.3, n)  # the element's strain at the iterate
    out = host(
        p, np.full((n, 1), 1e3), np.zeros((n, 1)), sv, 1e-3, predef=np.column_stack([eps, de])
    )
    tau, _, a_ref, s_ref = runtime(P, p, ph, af, sf, de, np.zeros(n))
    assert np.all(out["lm"] == 0) and host.exits() == 0 and host.log() == []
    assert np.allclose(np.abs(out["tau"][:, 0]), tau, rtol=1e-12, atol=0)
    statev = out["statev"]
    assert np.allclose(statev[:, 4], a_ref, rtol=1e-12, atol=0)
    assert np.allclose(statev[:, 5], s_ref, rtol=1e-12, atol=0)
    assert np.any(statev[:, 4] > af + 0.05)


def test_strainless_hosts_take_it_without_flattening(tmp_path, capsys):
    """A host that passes no strain takes a two-state file only with --without-flattening (exit
    2 without it), and its routine then carries no flattening code (zoned two-state routines:
    tests/test_export_zones_flattening.py)."""
    path = tmp_path / "two.json"
    law().to_json(path)
    code = export_main(["abaqus-fric", "--params", str(path), "--out", str(tmp_path / "a")])
    assert code == 2 and "--without-flattening" in capsys.readouterr().err
    files, _ = exp.render("abaqus-fric", path, units="SI", without_flattening=True)
    assert "SBMF_TSHR" not in files["sbmf_fric.f"]  # nor the table: the host cannot run it
    assert "DATA (DA(I)" not in files["sbmf_fric.f"]

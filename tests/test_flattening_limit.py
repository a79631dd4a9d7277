"""The two-state flattening law, model ``limit-analysis`` (frictionlaw.flattening_limit).

Oracles independent of the module: the shipped CSV read with the ``csv`` module (the table's
reading at its own states and between its pressures), SciPy's adaptive ODE solver for the
integration of the rates, and the calibrated ``alpha1`` at zero strain.
"""

import csv
import json
import math
from importlib import resources

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from frictionlaw import Flattening, FrictionParams, alpha_first, flattening_curve
from frictionlaw.flattening import flattening_update
from frictionlaw.flattening_limit import limit_rates, limit_update, prandtl_ratio, table_pressures

H = 8e8
RS = math.sqrt(3.0) / 2.0
BASE = dict(m=0.5, sigma_y=H / 2.8, H=H, C1=1.05, n1=2.87, C2=7.44, n2=0.575)
MODEL = "limit-analysis"


def law(slope=0.1, beta=1.0, **kw):
    return FrictionParams(**{**BASE, **kw}, flattening=Flattening(slope, beta, model=MODEL))


def shipped():
    text = resources.files("frictionlaw").joinpath("data/limit_rates.csv").read_text("utf-8")
    lines = [ln for ln in text.splitlines() if not ln.startswith("#")]
    return [{k: float(v) for k, v in r.items() if k != "mesh"} for r in csv.DictReader(lines)]


# ----------------------------------------------------------------------------- the block
def test_the_block_names_its_model_and_round_trips(tmp_path):
    P = law(0.05, 1.3)
    path = tmp_path / "params.json"
    path.write_text(json.dumps(P.to_dict()))
    assert json.loads(path.read_text())["flattening"]["model"] == MODEL
    assert FrictionParams.from_json(path) == P
    assert Flattening(0.05).model == "layer-yield"


@pytest.mark.parametrize("slope", [0.009, 0.21, 1.0])
def test_a_slope_outside_the_table_is_refused_naming_the_range(slope):
    with pytest.raises(ValueError, match=r"flattening.slope \(limit-analysis\).*\[0.01, 0.2\]"):
        Flattening(slope, model=MODEL)


def test_an_unknown_model_is_refused():
    with pytest.raises(ValueError, match="flattening.model must be one of"):
        Flattening(0.05, model="wilson-sheu")


def test_the_one_state_equations_refuse_the_two_state_block():
    with pytest.raises(ValueError, match="two states per node"):
        flattening_update(0.0, 1e8, 1e8, 0.01, law())
    with pytest.raises(ValueError, match="model 'layer-yield'"):
        limit_update(0.0, 0.0, 1e8, 1e8, 0.01, FrictionParams(**BASE, flattening=Flattening(0.1)))


# ----------------------------------------------------------------------------- the table
def test_the_table_is_read_as_shipped_at_its_own_states():
    rows = shipped()
    assert len(rows) >= 800 and {r["p_over_H"] for r in rows} >= {0.02, 0.05, 0.1, 0.6}
    x, a, s = (np.array([r[k] for r in rows]) for k in ("p_over_H", "A", "s"))
    dA, ds = limit_rates(x, a, s)
    np.testing.assert_allclose(dA, np.maximum([r["dA_de"] for r in rows], 0.0), rtol=1e-12)
    np.testing.assert_allclose(ds, [r["ds_de"] for r in rows], rtol=1e-12, atol=1e-15)


def test_between_pressures_linear_in_ln_p_at_the_same_state():
    rows = {(r["p_over_H"], r["A"], r["s"]): r for r in shipped()}
    lo, hi, A, s = 0.2, 0.3, 0.96, 0.055
    for t in (0.25, 0.5, 0.8):
        x = lo * (hi / lo) ** t
        dA, ds = limit_rates(x, A, s)
        for got, key in ((dA, "dA_de"), (ds, "ds_de")):
            want = (1 - t) * rows[(lo, A, s)][key] + t * rows[(hi, A, s)][key]
            assert float(got) == pytest.approx(want, rel=1e-12)
    # clamped beyond the first and the last pressure
    assert limit_rates(0.01, 0.5, 0.1)[0] == limit_rates(0.02, 0.5, 0.1)[0]
    assert limit_rates(0.9, 0.97, 0.1)[1] == limit_rates(0.6, 0.97, 0.1)[1]


def test_the_table_pressure_is_over_the_prandtl_hardness_of_the_host_flow_stress():
    P = law()
    x = prandtl_ratio(1e8, P)
    assert float(x) == pytest.approx(1e8 / ((2 + math.pi) * P.k), rel=1e-15)
    assert float(prandtl_ratio(1e8, P, sigma_y=2 * P.sigma_y)) == pytest.approx(x / 2, rel=1e-15)
    with pytest.raises(ValueError, match="sigma_y must be in"):
        prandtl_ratio(1e8, P, sigma_y=1.0)


# ----------------------------------------------------------------------------- the curves
@pytest.mark.parametrize("ph, slope", [(0.02, 0.176), (0.05, 0.05), (0.3, 0.12), (0.5, 0.02)])
def test_the_midpoint_rule_against_an_adaptive_ode_solver(ph, slope):
    """The integrated states against SciPy's RK45 of the same rates at tight tolerances."""
    P = law(slope)
    p = ph * H
    x = float(prandtl_ratio(p, P))
    a0 = float(alpha_first(p, P))

    def rhs(_, y):
        dA, ds = limit_rates(x, min(max(y[0], 0.0), 1.0), max(math.exp(y[1]), 1e-3))
        return [float(dA) if y[0] < 1 else 0.0, float(ds) / max(math.exp(y[1]), 1e-3)]

    strains = np.array([0.005, 0.02, 0.05, 0.1, 0.2])
    ref = solve_ivp(
        rhs,
        (0, RS * strains[-1]),
        [a0, math.log(slope)],
        t_eval=RS * strains,
        rtol=1e-10,
        atol=1e-12,
        max_step=1e-4,
    )
    want = np.minimum(ref.y[0], 1.0)
    got = flattening_curve(p, strains, P)
    np.testing.assert_allclose(got, want, atol=2e-3)


def test_zero_strain_is_the_calibrated_law_and_the_curve_never_falls():
    P = law(0.08)
    p = np.geomspace(1e-4, 0.9, 25) * H
    np.testing.assert_array_equal(flattening_curve(p, 0.0, P), alpha_first(p, P))
    e = np.linspace(0, 0.5, 51)
    for pk in (0.01, 0.03, 0.1, 0.3, 0.7):
        a = flattening_curve(pk * H, e, P)
        assert np.all(np.diff(a) >= 0) and a.max() <= 1.0 and a[-1] > a[0]


def test_near_full_contact_at_large_strain():
    for slope in (0.01, 0.05, 0.1, 0.2):
        assert flattening_curve(0.3 * H, 0.5, law(slope)) >= 0.9


def test_steep_flanks_at_low_pressure_turn_before_they_flatten():
    """The mechanism the second state carries: at 0.02 H_P a 10 deg flank hardly grows its
    contact until it has turned, where the one-state model grows it at once."""
    slope = math.tan(math.radians(10))
    p = 0.02 * (2 + math.pi) * law().k
    two = flattening_curve(p, [0.01, 0.05], law(slope))
    one = flattening_curve(p, [0.01, 0.05], FrictionParams(**BASE, flattening=Flattening(slope)))
    assert two[1] < 0.5 * one[1]
    shallow = flattening_curve(p, [0.01, 0.05], law(0.02))
    assert shallow[1] > 2 * two[1]


def test_beta_scales_the_strain_axis():
    e = np.array([0.01, 0.03, 0.08])
    np.testing.assert_allclose(
        flattening_curve(0.1 * H, e, law(0.1, beta=2.0)),
        flattening_curve(0.1 * H, 2 * e, law(0.1)),
        rtol=0,
        atol=1e-12,
    )


def test_hardening_is_refused_and_a_flow_curve_reads_its_flow_stress():
    from frictionlaw.flow_curve import SwiftCurve

    P = law(0.1)
    with pytest.raises(ValueError, match="perfectly plastic"):
        flattening_curve(0.1 * H, 0.1, P, hardening=1e9)
    flat = SwiftCurve(K=P.sigma_y, eps0=1.0, n=1e-9)  # a flat curve: the file's flow stress
    np.testing.assert_allclose(
        flattening_curve(0.1 * H, [0.05, 0.1], P, flow_curve=flat),
        flattening_curve(0.1 * H, [0.05, 0.1], P),
        atol=2e-3,
    )
    from frictionlaw.flow_curve import TabulatedCurve

    short = TabulatedCurve((0.0, 0.05), (P.sigma_y, 1.1 * P.sigma_y))
    with pytest.raises(ValueError, match="beyond the flow curve's last strain 0.05"):
        flattening_curve(0.1 * H, 0.1, P, flow_curve=short)
    hard = SwiftCurve(K=530e6, eps0=0.006, n=0.24)
    P2 = law(0.1, sigma_y=float(hard.sigma_y(0.0)))
    # a hardening flow stress lowers p / H_P: slower than at the initial flow stress
    assert flattening_curve(0.05 * H, 0.1, P2, flow_curve=hard) < flattening_curve(
        0.05 * H, 0.1, P2
    )


# ----------------------------------------------------------------------------- the update
def test_the_update_adds_up_and_is_the_curve_at_constant_pressure():
    P = law(0.1)
    p = np.array([0.02, 0.1, 0.4]) * H
    d = 0.01 / RS  # a stretch of 20 steps
    a1, s1 = limit_update(0.0, 0.0, p, p, d, P)
    a2, s2 = limit_update(a1, s1, p, p, d, P)
    a, s = limit_update(0.0, 0.0, p, p, 2 * d, P)
    np.testing.assert_allclose(a2, a, atol=1e-14)
    np.testing.assert_allclose(s2, s, rtol=1e-13)
    np.testing.assert_allclose(a, flattening_curve(p, 2 * d, P), atol=1e-14)
    assert s[0] < 0.09 and np.all(s > 0)  # the flank turned at low pressure


def test_the_update_keeps_what_does_not_flatten():
    P = law(0.1)
    a, s = limit_update(
        [0.3, 0.3, 0.3], [0.0, 0.05, 0.07], 1e8, [1e8, 0.0, 1e8], [0.0, 0.1, 0.0], P
    )
    np.testing.assert_array_equal(a, 0.3)
    np.testing.assert_array_equal(s, [0.0, 0.05, 0.07])
    # never below alpha_f, and from the larger of alpha_f and alpha1(max(p, p_hist))
    a, _ = limit_update(0.9, 0.01, 0.0, 0.01 * H, 1e-4, P)
    assert 0.9 <= float(a) <= 1.0
    a_hist, _ = limit_update(0.0, 0.0, 0.5 * H, 0.05 * H, 1e-3, P)
    a_now, _ = limit_update(0.0, 0.0, 0.05 * H, 0.05 * H, 1e-3, P)
    assert float(a_hist) > float(a_now) >= float(alpha_first(0.05 * H, P))


@pytest.mark.parametrize(
    "kw, msg",
    [
        (dict(d_eps=-1e-3), "d_eps must be >= 0"),
        (dict(alpha_f=1.2), "alpha_f must be contact fractions"),
        (dict(slope_f=-0.1), "slope_f must be >= 0"),
        (dict(p=math.nan), "p must"),
        (dict(p=[1e8, 2e8], d_eps=[0.1, 0.1, 0.1]), "d_eps"),
    ],
)
def test_bad_input_is_refused_naming_it(kw, msg):
    args = dict(alpha_f=0.0, slope_f=0.0, p_hist=1e8, p=1e8, d_eps=1e-3) | kw
    with pytest.raises(ValueError, match=msg):
        limit_update(**args, params=law())


# ----------------------------------------------------------------------------- the calibration
QUICK = ["--grid", "16", "--pressures", "1e8,2e8,3e8,5e8", "--reload-fractions", "0.3,0.6"]


def test_the_command_writes_a_two_state_block(tmp_path, capsys):
    """--flattening-model limit-analysis (which implies --flattening): the same inputs, the
    model named in the block and the record, the record's table the block's own curves."""
    from halfspace_calib.cli import main

    out = tmp_path / "o"
    argv = [
        "--grid",
        "32",
        *QUICK[2:],
        "--flattening-model",
        MODEL,
        "--no-progress",
        "--out",
        str(out),
    ]
    assert main(argv) == 0
    doc = json.loads((out / "params.json").read_text())
    rec = doc["provenance"]["flattening"]
    assert doc["flattening"]["model"] == MODEL and rec["model"].startswith(MODEL)
    assert doc["flattening"]["slope"] == rec["slope"] and "the table" in rec["beta_source"]
    # the workpiece's edge slope at 51 contact fractions, read back as the block's
    edge = doc["flattening"]["edge_slope"]
    assert len(edge) == 51 and "bearing level" in rec["edge_slope_source"]
    assert min(edge) > 0 and 0.3 < np.mean(edge) / rec["slope"] < 3
    P = FrictionParams.from_json(out / "params.json")
    assert P.flattening.edge_slope == tuple(edge)
    t = rec["table"]
    for key, alphas in t["alpha_at_p_over_H"].items():
        got = flattening_curve(float(key[:-1]) * P.H, t["strains"], P).tolist()
        assert alphas == pytest.approx(got, abs=0)
    full = rec["full_contact"]["strain"]
    assert flattening_curve(0.3 * P.H, [full - 1e-3, full], P).tolist() == [
        pytest.approx(flattening_curve(0.3 * P.H, full - 1e-3, P)),
        1.0,
    ]
    assert flattening_curve(0.3 * P.H, full - 1e-3, P) < 1.0
    said = capsys.readouterr()
    assert f"model {MODEL}" in said.out
    assert "is perfectly plastic" in said.err and "prefer layer-yield" in said.err
    lo, hi = table_pressures(P)  # the table's pressures at the file's flow stress, said
    assert f"covers contact pressures {lo / 1e6:.3g}-{hi / 1e6:.3g} MPa" in said.err
    assert lo == pytest.approx(0.02 * (2 + np.pi) * P.k) and hi == pytest.approx(0.6 / 0.02 * lo)


def test_a_slope_outside_the_table_is_refused_before_any_sweep(tmp_path, capsys, monkeypatch):
    from realfiles import real_file

    from halfspace_calib.cli import main

    out = tmp_path / "o"
    argv = [*QUICK[:2], "--workpiece", str(real_file("metropro-1.dat")), "--no-resolution-check"]
    import halfspace_calib.cli as cli

    def no_sweep(*a, **k):
        raise AssertionError("a sweep ran")

    monkeypatch.setattr(cli, "calibrate", no_sweep)
    assert main([*argv, "--flattening-model", MODEL, "--no-progress", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "outside the two-state law's table [0.01, 0.2]" in err
    assert "--flattening-model layer-yield" in err and not out.exists()


def test_beta_of_the_two_state_law_is_recovered_with_a_band():
    from halfspace_calib.pipeline.sweep.flattening import FlatteningData, fit_beta

    P = law(0.08)
    p = np.repeat(np.array([0.05, 0.2]) * H, 4)
    eps = np.tile([0.01, 0.02, 0.04, 0.08], 2)
    truth = flattening_curve(p, eps, law(0.08, beta=1.7))
    noisy = np.clip(truth + np.random.default_rng(3).normal(0, 0.01, truth.size), 0, 1)
    fit = fit_beta(P, FlatteningData("lab.csv", eps, noisy, p))
    assert fit["band"][0] < 1.7 < fit["band"][1] and fit["beta"] == pytest.approx(1.7, rel=0.1)


def test_any_split_of_the_strain_into_increments_gives_the_same_fraction():
    """A host's increments are not multiples of the step: the last step of each is shorter. Any
    split of a strain into increments integrates to the one-step curve within the rule's error."""
    P = law(0.176)
    rng = np.random.default_rng(0)
    for ph in (0.02, 0.05, 0.3):
        p = float(ph * (2 + math.pi) * P.k)
        ref = float(flattening_curve(p, 0.1, P))
        for _ in range(5):
            w = rng.random(rng.integers(3, 40))
            a, s = 0.0, 0.0
            for d in 0.1 * w / w.sum():
                a, s = limit_update(a, s, p, p, d, P)
            assert float(a) == pytest.approx(ref, abs=1e-4)


def test_the_command_fits_the_two_state_law_and_reports_it(tmp_path, capsys):
    from pathlib import Path

    from halfspace_calib.cli import main

    data = Path(__file__).parent / "data" / "flattening_example.csv"
    out = tmp_path / "o"
    argv = ["--grid", "32", *QUICK[2:], "--flattening-model", MODEL, "--flattening-data"]
    assert main([*argv, str(data), "--no-progress", "--out", str(out)]) == 0
    doc = json.loads((out / "params.json").read_text())
    f, fit = doc["flattening"], doc["provenance"]["flattening"]["fit"]
    assert f["model"] == MODEL and f["beta_band"][0] < f["beta"] < f["beta_band"][1]
    P = FrictionParams.from_json(out / "params.json")
    p, eps = np.asarray(fit["p_Pa"]), np.asarray(fit["strain"])
    resid = np.asarray(fit["alpha"]) - flattening_curve(p, eps, P)
    assert fit["rms"] == pytest.approx(float(np.sqrt(np.mean(resid**2))), rel=1e-6)
    assert f"<p>model: {MODEL}" in (out / "report.html").read_text()
    assert (out / "flattening.png").stat().st_size > 0


def test_a_curves_points_share_one_integration_equal_to_each_on_its_own():
    """integrate_shared (what the curves and the fit use) against integrate point by point: the
    same steps, equal to rounding, at strains on and off the step grid, zero and to full contact."""
    from frictionlaw._limit_table import STEP, integrate, integrate_shared, rate_table

    t = rate_table()
    rng = np.random.default_rng(5)
    n = 600
    x = rng.choice([0.02, 0.045, 0.1, 0.33], n)
    a0 = np.where(x < 0.05, 0.03, np.where(x < 0.2, 0.12, 0.4))
    s0 = np.where(x == 0.33, 0.17, 0.08)
    st = rng.uniform(0.0, 0.5, n)
    st[:40] = np.round(st[:40] / STEP) * STEP
    st[40:50] = 0.0
    a1, s1 = integrate(a0, s0, x, st, t)
    a2, s2 = integrate_shared(a0, s0, x, st, t)
    np.testing.assert_allclose(a2, a1, rtol=0, atol=1e-13)
    np.testing.assert_allclose(s2, s1, rtol=1e-12)
    assert (a1 == 1.0).any() and (a1 < 1.0).any()


def test_a_two_state_fit_beyond_the_range_of_beta_is_refused_naming_the_bound():
    """Points that want beta beyond its range: the fit's refusal naming the bound (its grid
    evaluates the two-state curves at the range's ends)."""
    from halfspace_calib.pipeline.sweep.flattening import FlatteningData, fit_beta

    p = np.full(4, 0.1 * H)
    eps = np.array([1e-5, 2e-5, 3e-5, 4e-5])  # full contact at once: beta beyond 1000
    with pytest.raises(ValueError, match="bound of"):
        fit_beta(law(0.05), FlatteningData("fast.csv", eps, np.ones(4), p))


def test_table_pressures_scale_with_the_flow_stress():
    """The table's pressure range in Pa: 0.02 and 0.6 H_P, H_P = (2 + pi) k, k scaled by a
    host's flow stress; the law's rates are the same on either side of the lowest (clamped)."""
    P = law()
    lo, hi = table_pressures(P)
    assert prandtl_ratio(lo, P) == pytest.approx(0.02) and prandtl_ratio(hi, P) == pytest.approx(
        0.6
    )
    lo2, hi2 = table_pressures(P, sigma_y=2 * P.sigma_y)
    assert (lo2, hi2) == pytest.approx((2 * lo, 2 * hi))
    below = limit_rates(prandtl_ratio(0.5 * lo, P), 0.2, 0.05)
    at = limit_rates(prandtl_ratio(lo, P), 0.2, 0.05)
    assert np.allclose(below, at, rtol=1e-12)
    with pytest.raises(ValueError, match="sigma_y"):
        table_pressures(P, sigma_y=-1.0)

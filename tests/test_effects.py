"""Effect selection in the calibration: validation, the runs each effect adds, the report."""

import csv
import json

import numpy as np
import pytest
from plotcheck import assert_png_drawn, lines

import halfspace_calib.contact.tangential as tang
from frictionlaw import FrictionParams, shear_limit
from halfspace_calib import topography as S
from halfspace_calib.cli import build_parser, main, scene_from_args
from halfspace_calib.contact.cerruti import E_prime
from halfspace_calib.contact.materials import Materials
from halfspace_calib.contact.normal import composite_modulus, solve_normal_pair
from halfspace_calib.output.effects import plot_tangential
from halfspace_calib.output.geometric import plot_geometric
from halfspace_calib.output.report import write_outputs
from halfspace_calib.pipeline.calibration import Scene, calibrate, load_scene
from halfspace_calib.pipeline.sweep.effects import EFFECTS, check_effects, geo_decision
from halfspace_calib.studies.geometric import GeometricResult
from halfspace_calib.studies.presliding import presliding_curve, stiffness_power_law

SMALL = dict(
    grid=16, pressures=(50e6, 150e6, 300e6, 500e6), reload_fractions=(0.2, 0.5, 0.8), tol=1e-7
)
E_STAR = composite_modulus(210e9, 0.3, 210e9, 0.3)
E_PR = E_prime(210e9, 0.3, 210e9, 0.3)
SIGMA_Y = 800e6 / 2.8
MAT = Materials(m=0.5, sigma_y=SIGMA_Y)  # Table 1: E_star = E_STAR, E_prime = E_PR


# ----------------------------------------------------------------------------- selection
def test_check_effects_order_and_normal_always_on():
    assert EFFECTS == ("normal", "tangential", "inclined", "sliding")
    assert check_effects(()) == ("normal",)
    assert check_effects(["sliding", "tangential"]) == ("normal", "tangential", "sliding")
    assert check_effects("inclined, normal,sliding") == ("normal", "inclined", "sliding")
    assert Scene().effects == ("normal",)
    assert Scene(effects=["inclined"]).effects == ("normal", "inclined")


def test_validation_errors_name_the_field():
    with pytest.raises(ValueError, match=r"effects must be names from .*unknown \['friction'\]"):
        Scene(effects=("normal", "friction"))
    with pytest.raises(ValueError, match="effects must be"):
        Scene(effects=3)
    with pytest.raises(ValueError, match="geo_threshold must be a finite number >= 0"):
        Scene(geo_threshold=-0.1)
    with pytest.raises(ValueError, match="geo_threshold"):
        Scene(geo_threshold=float("nan"))
    with pytest.raises(ValueError, match="measured_n must be a multiple >= 2 of grid=16"):
        Scene(grid=16, measured_n=16, effects=("inclined",))
    Scene(grid=16, measured_n=16)  # fine without the inclined patches


def test_scene_file_and_cli_options(tmp_path):
    f = tmp_path / "s.toml"
    f.write_text('grid = 16\neffects = ["inclined", "tangential"]\ngeo_threshold = 0.2\n')
    s = load_scene(f)
    assert s.effects == ("normal", "tangential", "inclined") and s.geo_threshold == 0.2
    ap = build_parser()
    s = scene_from_args(ap.parse_args(["--effects", "tangential,inclined", "--geo-threshold", "0"]))
    assert s.effects == ("normal", "tangential", "inclined") and s.geo_threshold == 0.0
    # --sliding is the same as adding "sliding" to the effects (of the options or the scene file)
    assert scene_from_args(ap.parse_args(["--sliding"])).effects == ("normal", "sliding")
    s = scene_from_args(ap.parse_args(["--effects", "tangential", "--sliding"]))
    assert s.effects == ("normal", "tangential", "sliding")
    s = scene_from_args(ap.parse_args(["--scene", str(f), "--sliding"]))
    assert s.effects == ("normal", "tangential", "inclined", "sliding")
    assert main(["--effects", "normal,bogus", "--out", str(tmp_path / "x")]) == 2


# ----------------------------------------------------------------------------- tangential
@pytest.fixture(scope="module")
def loaded():
    wp, tl = S.dc04_edt_like(32), S.tool_like(32)
    r = solve_normal_pair(wp.heights, tl.heights, wp.dx, E_STAR, 200e6, H=800e6)
    return r, wp.dx


def test_presliding_full_sliding_equals_the_shortcut(loaded):
    r, dx = loaded
    c = presliding_curve(r.pressure, dx, materials=MAT)
    assert c.converged
    shortcut = tang.tau_adh_full_sliding(r.alpha, 0.5, SIGMA_Y)
    assert c.q_limit == pytest.approx(shortcut, rel=1e-14)
    full = c.delta >= c.delta_full * (1 - 1e-12)
    assert full.sum() == 2  # fractions 1.0 and 1.25
    np.testing.assert_allclose(c.q_mean[full], shortcut, rtol=1e-12)
    np.testing.assert_array_equal(c.slip_fraction[full], 1.0)
    # below: monotone, under the cap, partial slip that spreads with the shift
    part = ~full
    assert np.all(np.diff(c.q_mean) >= -1e-9 * shortcut)
    assert np.all(c.q_mean[part] < shortcut)
    assert np.all(np.diff(c.slip_fraction) >= 0) and c.slip_fraction[part][-1] < 1
    # stiffness: secant below the initial slope, the curve below the initial tangent
    assert c.k_sec == pytest.approx(shortcut / c.delta_full, rel=1e-14)
    assert 0 < c.k_sec < c.k_eq < c.k_t0
    # k_eq: the bilinear law with the curve's complementary energy int delta dq (trapezoid)
    d, q = c.delta[~full | (c.delta == c.delta_full)], c.q_mean[~full | (c.delta == c.delta_full)]
    w = np.sum(0.5 * (d[1:] + d[:-1]) * np.diff(q))
    assert c.k_eq == pytest.approx(shortcut**2 / (2 * w), rel=1e-12)
    assert np.all(c.q_mean <= c.k_t0 * c.delta * (1 + 1e-9))
    assert 0 < c.delta_stick < c.delta_full


def test_presliding_linear_below_first_slip(loaded):
    # while every element sticks the response is linear: q_mean = k_t0 delta exactly
    r, dx = loaded
    c = presliding_curve(r.pressure, dx, materials=MAT)
    for f in (0.3, 0.9):
        d = f * c.delta_stick
        s = tang.solve_tangential(
            r.pressure, dx, E_STAR, E_PR, delta=d, m=0.5, sigma_y=SIGMA_Y, periodic=True
        )
        assert not s.slip.any()
        assert s.q_mean == pytest.approx(c.k_t0 * d, rel=1e-6)
    # just beyond delta_stick the first element slips
    s = tang.solve_tangential(
        r.pressure,
        dx,
        E_STAR,
        E_PR,
        delta=1.05 * c.delta_stick,
        m=0.5,
        sigma_y=SIGMA_Y,
        periodic=True,
    )
    assert s.slip.any()


def test_presliding_bad_input(loaded):
    r, dx = loaded
    with pytest.raises(ValueError, match=r"m must be in \(0, 1\]"):
        presliding_curve(r.pressure, dx, materials=Materials(m=0.0, sigma_y=SIGMA_Y))
    with pytest.raises(ValueError, match="fractions"):
        presliding_curve(r.pressure, dx, materials=MAT, fractions=(0.5, 0.2))
    with pytest.raises(ValueError, match="at least one contact element"):
        presliding_curve(np.zeros((8, 8)), dx, materials=MAT)


def test_stiffness_power_law_recovers_exact_power():
    p = np.array([50e6, 100e6, 300e6, 600e6])
    f = stiffness_power_law(p, 2e14 * (p / 1e8) ** 1.3)
    assert f["k_ref"] == pytest.approx(2e14, rel=1e-12) and f["exponent"] == pytest.approx(1.3)
    assert f["max_rel_error"] < 1e-12
    with pytest.raises(ValueError, match="positive"):
        stiffness_power_law([1e8], [1e14])


# ----------------------------------------------------------------------------- geo decision
def test_geo_decision_both_ways():
    ta = np.array([10e6, 20e6, 40e6])
    res = GeometricResult(
        "x",
        np.array([1e8, 2e8, 4e8]),
        ta / 71.4e6,
        ta,
        0.08 * ta,
        np.full(3, 0.08),
        np.zeros(3),
        np.ones(3, bool),
    )
    off = geo_decision(res, 0.1, 0.5)
    assert off.geo_ratio == 0.0 and not off.applied
    assert "0.0800 <= geo_threshold = 0.1" in off.reason
    on = geo_decision(res, 0.05, 0.5)
    assert on.applied and on.geo_ratio == pytest.approx(0.08, rel=1e-14)
    assert "0.0800 > geo_threshold = 0.05" in on.reason


# ----------------------------------------------------------------------------- calibration
def _no_tangential(*args, **kwargs):
    raise RuntimeError("solve_tangential called")


def test_without_tangential_no_tangential_solve(monkeypatch):
    monkeypatch.setattr(tang, "solve_tangential", _no_tangential)
    cal = calibrate(Scene(**SMALL, effects=("inclined",)), progress=False)
    assert "tangential" not in cal.effects
    assert all(lv.tangential is None and lv.tangential_error is None for lv in cal.sweeps.levels)
    # positive control: with the effect, the patched solver is reached (and its failure recorded)
    cal = calibrate(Scene(**SMALL, effects=("tangential",)), progress=False)
    errs = cal.effects["tangential"].summary["errors"]
    assert len(errs) == 4 and "solve_tangential called" in errs[0]["error"]


@pytest.fixture(scope="module")
def cal_all():
    return calibrate(
        Scene(**SMALL, effects=("tangential", "inclined"), geo_threshold=0.0), progress=False
    )


def test_threshold_zero_fits_geo_ratio(cal_all):
    P = cal_all.params
    inc = cal_all.effects["inclined"]
    d = inc.decision
    assert d.applied and P.geo_ratio == d.geo_ratio > 0
    assert P.geo_ratio == pytest.approx(d.fit["geo_ratio"], rel=0)
    r = inc.result
    # the fitted ratio minimises the misfit of tau_geo = geo_ratio tau_adh (LAPACK oracle)
    g_lstsq = np.linalg.lstsq(r.tau_adh[:, None], r.tau_geo, rcond=None)[0][0]
    assert P.geo_ratio == pytest.approx(g_lstsq, rel=1e-10)
    # and lies between the smallest and largest pointwise ratio (a weighted mean of them)
    ratios = r.tau_geo / r.tau_adh
    assert ratios.min() <= P.geo_ratio <= ratios.max()
    np.testing.assert_array_equal(r.p_mean, SMALL["pressures"])
    # the runtime then gives (1 + geo_ratio) times the law without the term (Eq. 26)
    p = np.array([100e6, 300e6])
    for p_hist in (0.0, 400e6):  # first loading and reload branch
        base = shear_limit(p, p_hist, P.replace(geo_ratio=0.0))
        np.testing.assert_allclose(shear_limit(p, p_hist, P), (1 + P.geo_ratio) * base, rtol=1e-12)


def test_high_threshold_leaves_geo_ratio_out():
    cal = calibrate(Scene(**SMALL, effects=("inclined",), geo_threshold=10.0), progress=False)
    d = cal.effects["inclined"].decision
    assert cal.params.geo_ratio == 0.0 and not d.applied
    assert f"{d.ratio_mean:.4f} <= geo_threshold = 10" in d.reason
    rec = cal.params.provenance["extra"]["effects"]["inclined"]
    assert rec["reason"] == d.reason and rec["threshold"] == 10.0


def test_provenance_and_outputs(cal_all, tmp_path):
    write_outputs(cal_all, tmp_path)
    P = FrictionParams.from_json(tmp_path / "params.json")
    assert P.geo_ratio == cal_all.params.geo_ratio > 0
    extra = P.provenance["extra"]
    assert extra["model"]["effects"] == ["normal", "tangential", "inclined"]
    t = extra["effects"]["tangential"]
    assert [r["p_mean"] for r in t["rows"]] == list(SMALL["pressures"])
    assert all(r["converged"] and r["k_sec"] < r["k_eq"] < r["k_t0"] for r in t["rows"])
    assert t["full_sliding_max_rel_diff"] < 1e-12
    assert "traction_update" in t["recommendation"] and t["k_eq_fit"]["exponent"] > 0
    # stiffer with the load: more contact carries the shift
    k = [r["k_t0"] for r in t["rows"]]
    assert np.all(np.diff(k) > 0)
    inc = extra["effects"]["inclined"]
    assert inc["applied"] and inc["geo_ratio"] == P.geo_ratio and "sliding" not in extra["effects"]
    summ = json.loads((tmp_path / "summary.json").read_text())
    assert summ["effects"] == ["normal", "tangential", "inclined"]
    assert summ["geo_ratio"] == P.geo_ratio
    assert summ["effect_results"]["inclined"]["ratio_mean"] == inc["ratio_mean"]
    with open(tmp_path / "tangential" / "tangential_stiffness.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert float(rows[0]["k_t0_Pa_per_m"]) == pytest.approx(t["rows"][0]["k_t0"], rel=1e-15)
    with open(tmp_path / "geometric" / "geometric.csv", newline="") as fh:
        assert len(list(csv.DictReader(fh))) == 4
    for f in (
        "tangential/tangential_curves.png",
        "tangential/tangential_stiffness.png",
        "geometric/fig9_tau.png",
        "geometric/fig10_ratio.png",
    ):
        assert_png_drawn(tmp_path / f)
    # what is plotted: each level's pre-sliding curve and the stiffness table
    curves = [
        (lv.p_hist, lv.tangential) for lv in cal_all.sweeps.levels if lv.tangential is not None
    ]
    figs = plot_tangential(curves, t, tmp_path / "tangential")
    drawn = lines(figs["tangential_curves.png"])
    assert len(drawn) == len(curves) == 4
    for (x, y), (_, c) in zip(drawn, curves, strict=True):
        np.testing.assert_allclose(x, c.delta * 1e9, rtol=1e-15)
        np.testing.assert_allclose(y, c.q_mean / 1e6, rtol=1e-15)
    (_, k0), (_, keq), (_, ksec) = lines(figs["tangential_stiffness.png"])
    for got, key in ((k0, "k_t0"), (keq, "k_eq"), (ksec, "k_sec")):
        np.testing.assert_array_equal(got, [r[key] for r in t["rows"]])
    r = cal_all.effects["inclined"].result
    figs = plot_geometric([r], tmp_path / "geometric")
    (_, adh), (_, geo) = lines(figs["fig9_tau.png"])
    np.testing.assert_allclose(adh, r.tau_adh / 1e6, rtol=1e-15)
    np.testing.assert_allclose(geo, r.tau_geo / 1e6, rtol=1e-15)
    np.testing.assert_array_equal(lines(figs["fig10_ratio.png"])[0][1], r.ratio)
    assert not (tmp_path / "sliding").exists()
    # out=None: the same figures for a notebook, nothing written, not held by pyplot
    before = sorted(tmp_path.rglob("*"))
    nb = {**plot_tangential(curves, t, None), **plot_geometric([r], None)}
    assert sorted(nb) == sorted([*figs, "tangential_curves.png", "tangential_stiffness.png"])
    assert sorted(tmp_path.rglob("*")) == before
    assert all(f.canvas.manager is None for f in nb.values())
    np.testing.assert_array_equal(lines(nb["fig10_ratio.png"])[0][1], r.ratio)


def test_normal_only_records_no_effects(tmp_path):
    cal = calibrate(Scene(**SMALL), progress=False)
    assert cal.effects == {} and cal.params.geo_ratio == 0.0
    assert cal.params.provenance["extra"]["model"]["effects"] == ["normal"]
    assert cal.params.provenance["extra"]["effects"] == {}


def test_m_zero_skips_with_reasons(tmp_path, capsys):
    out = tmp_path / "o"
    argv = [
        "--grid",
        "16",
        "--pressures",
        "50e6,150e6,300e6,500e6",
        "--reload-fractions",
        "0.2,0.5,0.8",
        "--tol",
        "1e-7",
        "--out",
        str(out),
        "--no-progress",
        "--m",
        "0",
        "--effects",
        "tangential,inclined",
    ]
    assert main(argv) == 0
    text = capsys.readouterr().out
    assert "tangential (pre-sliding) skipped: m = 0" in text
    assert "inclined patches skipped: m = 0" in text
    eff = json.loads((out / "summary.json").read_text())["effect_results"]
    assert set(eff) == {"tangential", "inclined"} and all("skipped" in v for v in eff.values())


def test_inclined_uses_the_calibration_field():
    # with the inclined patches the synthetic surfaces come from the measured grid (4 x grid), so
    # the geometric study's solver surfaces are the calibration's surfaces (same random field)
    from halfspace_calib.pipeline.calibration import scene_surfaces
    from halfspace_calib.pipeline.sweep.effects import scene_measured_surfaces

    assert Scene(grid=16).measured_n is None
    for rough in (True, False):  # the smooth tool's field is the hard case (heavy-tailed)
        s = Scene(grid=16, effects=("inclined",), rough_tool=rough)
        assert s.measured_n == 64
        wp, tl = scene_surfaces(s)
        fw, ft, block = scene_measured_surfaces(s)
        assert block == 4 and fw.shape == (64, 64)
        for coarse, fine in ((wp, fw), (tl, ft)):
            avg = S.block_average(fine, 16).heights
            np.testing.assert_allclose(avg, coarse.heights, rtol=0, atol=1e-12 * S.rq(coarse))


def test_cli_all_effects(tmp_path, capsys):
    out = tmp_path / "all"
    argv = [
        "--grid",
        "16",
        "--pressures",
        "50e6,150e6,300e6,500e6",
        "--reload-fractions",
        "0.2,0.5,0.8",
        "--tol",
        "1e-7",
        "--out",
        str(out),
        "--no-progress",
        "--effects",
        "tangential,inclined",
        "--geo-threshold",
        "0",
        "--sliding",
    ]
    assert main(argv) == 0
    text = capsys.readouterr().out
    assert "effects modelled: normal, tangential, inclined, sliding" in text
    assert text.count("k_eq = ") == 4 and "> geo_threshold = 0: Eq. 26" in text
    assert text.count(" MPa: W_def / W_adh mean") == 6
    P = FrictionParams.from_json(out / "params.json")
    assert P.provenance["extra"]["model"]["effects"] == list(EFFECTS) and P.geo_ratio > 0
    sl = json.loads((out / "summary.json").read_text())["effect_results"]["sliding"]
    assert [r["p_mean"] for r in sl["rows"]] == [100e6, 200e6, 300e6, 400e6, 500e6, 600e6]
    assert 0 <= sl["ratio_max"] < 1 and sl["failed_pressures"] == []
    for sub in ("tangential/tangential.csv", "geometric/geometric.csv", "sliding/sliding.csv"):
        assert (out / sub).exists()


def test_calibrated_stiffness_and_range_reach_the_parameter_file(cal_all, tmp_path):
    P = cal_all.params
    rows = [r for r in cal_all.effects["tangential"].summary["rows"] if r["converged"]]
    assert P.k_t is not None and len(P.k_t.p) == len(rows) >= 2
    np.testing.assert_array_equal(P.k_t.p, sorted(r["p_mean"] for r in rows))
    np.testing.assert_allclose(P.k_t(P.k_t.p), [r["k_eq"] for r in rows], rtol=1e-12)
    assert P.p_range == (min(SMALL["pressures"]), max(SMALL["pressures"]))
    f = tmp_path / "params.json"
    P.to_json(f)
    assert FrictionParams.from_json(f).k_t == P.k_t
    # without the tangential effect there is no stiffness table
    assert calibrate(Scene(**SMALL), progress=False).params.k_t is None

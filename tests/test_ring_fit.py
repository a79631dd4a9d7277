"""``fe-demo ring-fit``: the friction factor m from ring tests, with the law itself."""

import json

import numpy as np
import pytest

import fe_demo.analysis.ringfit as ringfit
from fe_demo.analysis.ringfit import RingTest, fit_m, ring_curve
from fe_demo.cli import main
from fe_demo.scenes.laws import EXAMPLE_PARAMS_PATH
from frictionlaw import FrictionParams

# the shipped example law, asked for explicitly (ring-fit needs --params or --illustrative)
COARSE = ["--nr", "8", "--increments", "20", "--illustrative"]
KW = {"nr": 8, "n_increments": 20}


def _csv(path, rows, header="height_reduction,inner_diameter_change"):
    path.write_text(header + "\n" + "".join(",".join(map(str, r)) + "\n" for r in rows))
    return path


@pytest.fixture(scope="module")
def synthetic(tmp_path_factory):
    """Ring tests made by the same coarse FE model with the example law at m = 0.3."""
    P = FrictionParams.from_json(EXAMPLE_PARAMS_PATH)
    r, d = ring_curve("sbmf", 0.3, params=P, reduction=0.5, **KW)
    red = np.array([0.15, 0.25, 0.35, 0.45, 0.5])
    path = tmp_path_factory.mktemp("ring") / "rings.csv"
    return _csv(path, zip(red, np.interp(red, r, d), strict=True)), P


@pytest.mark.parametrize(
    "rows, header, message",
    [
        (
            [(0.3, 0.01), (0.5, 0.02)],
            "height_reduction,diameter",
            "line 1: an inner-diameter column is missing",
        ),
        (
            [(0.3, 0.01), (0.5, 0.02)],
            "stroke,inner_diameter_change",
            "line 1: a height-reduction column is missing (header: 'stroke'; "
            "'inner_diameter_change'); accepted columns",
        ),
        ([(0.3, 0.01), (0.8, 0.02)], None, "line 3: height reduction 0.8 is outside (0, 0.7]"),
        ([(0.0, 0.01), (0.5, 0.02)], None, "line 2: height reduction 0.0 is outside"),
        ([(0.3, "nan"), (0.5, 0.02)], None, "line 2: inner-diameter change is NaN"),
        ([(0.3, 0.01)], None, "at least 2 points"),
        (
            [(0.3, "x"), (0.5, 0.02)],
            None,
            "line 2: inner-diameter change 'x' in column 'inner_diameter_change' is not a number",
        ),
    ],
)
def test_bad_measured_files_exit_2_before_any_fe_run(
    tmp_path, capsys, monkeypatch, rows, header, message
):
    def no_fe(*a, **k):
        raise AssertionError("an FE run started on bad input")

    monkeypatch.setattr(ringfit, "run_ring", no_fe)
    path = _csv(tmp_path / "m.csv", rows, header or "height_reduction,inner_diameter_change")
    rc = main(["ring-fit", "--measured", str(path), *COARSE, "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc == 2 and message in err and "Traceback" not in err
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize(
    "argv, message",
    [
        (["--geometry", "18,20,6"], "--geometry needs 0 < ID < OD"),
        (["--band-level", "1.5"], "--band-level must be in (0, 1)"),
        (["--law", "tresca", "--params", str(EXAMPLE_PARAMS_PATH)], "--params is not used"),
    ],
)
def test_bad_options_exit_2(tmp_path, capsys, synthetic, argv, message):
    path, _ = synthetic
    rc = main(["ring-fit", "--measured", str(path), *COARSE, *argv, "--out", str(tmp_path / "o")])
    assert rc == 2 and message in capsys.readouterr().err


def test_points_no_m_can_produce_are_refused_saying_which_way(tmp_path, capsys):
    path = _csv(tmp_path / "m.csv", [(0.3, 0.9), (0.5, 0.95)])  # far above frictionless
    rc = main(["ring-fit", "--measured", str(path), *COARSE, "--workers", "1",
               "--out", str(tmp_path / "o")])  # fmt: skip
    err = capsys.readouterr().err
    assert rc == 2 and "lie above what any m in [0, 1] gives" in err and "m = 0" in err


def test_a_failed_fe_run_exits_1_naming_its_m(tmp_path, capsys, synthetic, monkeypatch):
    path, _ = synthetic
    real = ringfit.run_ring

    def failing(law, **kw):
        if law == "sbmf" and 0.55 < kw["params"].m < 0.65:  # the run and its retry fail
            raise ValueError("element inverted")
        return real(law, **kw)

    monkeypatch.setattr(ringfit, "run_ring", failing)
    rc = main(["ring-fit", "--measured", str(path), *COARSE, "--workers", "1",
               "--out", str(tmp_path / "o")])  # fmt: skip
    err = capsys.readouterr().err
    assert rc == 1 and "at m = 0.6 failed: element inverted (and again at m = 0.61)" in err


def test_fit_recovers_m_and_writes_its_outputs(tmp_path, capsys, synthetic):
    path, P = synthetic
    out = tmp_path / "fit"
    assert main(["ring-fit", "--measured", str(path), *COARSE, "--out", str(out)]) == 0
    rec = json.loads((out / "ring_fit.json").read_text())
    assert rec["m"] == pytest.approx(0.3, abs=0.01)  # noise-free data of the same FE model
    assert rec["m_lower"] <= rec["m"] <= rec["m_upper"]
    assert rec["n_points"] == 5 and rec["law"] == "sbmf"
    assert rec["n_fe_runs"] <= 15
    # the chart's m of the same data is far below the law's: alpha < 1 on the die face
    assert rec["m_tresca_chart"] < rec["m"] - 0.05
    assert rec["bias_chart_minus_law"] == pytest.approx(rec["m_tresca_chart"] - rec["m"])
    fitted = FrictionParams.from_json(out / "params.json")
    assert fitted.m == pytest.approx(rec["m"]) and fitted.k == P.k  # k is the file's
    assert fitted.provenance["ring_test"]["m"] == rec["m"]
    for name in ("ring_fit.csv", "ring_fit.png", "report.html"):
        assert (out / name).is_file()
    assert "ring fit (sbmf): m = " in capsys.readouterr().out


def test_band_from_the_scatter_covers_m_on_noisy_synthetic_data():
    """Linearised band on noisy data made from one response surface (no FE per draw)."""
    P = FrictionParams.from_json(EXAMPLE_PARAMS_PATH)
    red = np.linspace(0.1, 0.5, 8)
    fit0 = fit_m(RingTest(red, np.zeros_like(red), "inner_diameter_change", ()), "sbmf",
                 params=P, workers=1, **KW)  # fmt: skip
    truth = fit0.predict(red, 0.3)
    surf = ringfit._surface(fit0.curves, red)
    rng = np.random.default_rng(7)
    hits, draws = 0, 60
    for _ in range(draws):
        d = truth + rng.normal(0.0, 0.005, red.size)  # 0.5-point noise
        m = ringfit.least_squares_m(surf, d)
        half = ringfit.band_half_width(d - surf(m), surf.derivative()(m), 0.9)
        hits += abs(m - 0.3) <= half
    assert 0.8 <= hits / draws <= 1.0  # nominal 90 %; 60 draws: standard error 0.04


def test_the_fit_builds_each_response_surface_once(monkeypatch):
    """The output asks for the fitted curve and its band at the same reductions, and the
    measured points: one surface per set of reductions, not one per call."""
    fit0 = ringfit.RingFit(
        law="sbmf", m=0.3, m_lower=0.25, m_upper=0.35, band_level=0.9, rmse=0.0, n_points=2,
        residuals=np.zeros(2), n_fe_runs=3,
        curves={m: (np.array([0.0, 0.5]), np.array([0.0, -m])) for m in (0.0, 0.5, 1.0)},
    )  # fmt: skip
    built = []
    real = ringfit._surface
    monkeypatch.setattr(ringfit, "_surface", lambda c, r: built.append(len(r)) or real(c, r))
    r = np.linspace(0.0, 0.5, 60)[1:]
    curves = [fit0.predict(r, m) for m in (fit0.m_lower, fit0.m_upper, None)]
    assert built == [59]
    assert fit0.predict(r[:3]) == pytest.approx(curves[2][:3]) and built == [59, 3]
    assert curves[2][-1] == pytest.approx(-0.3)  # linear in m here: PCHIP reproduces it

"""fe-demo --band / --samples: the law's band carried to force and ring results.

The parameter file is made here (the shipped example law with an uncertainty block whose
edge laws have C1 scaled by 0.7 and 1.4): no calibration runs, and the band is wide enough
that the physics is visible. More friction (larger C1) must need more force in early upsetting
and close the ring's hole more.
"""

import csv
import json
from html.parser import HTMLParser

import numpy as np
import pytest
from reportcells import Cells, assert_page_agrees

from fe_demo.analysis.band import combine
from fe_demo.cli import main
from fe_demo.scenes.laws import example_params
from frictionlaw.uncertainty import Band, Interval, SampleLaw, Uncertainty

TINY = ["--nr", "6", "--increments", "8", "--no-progress", "--vtu-every", "0"]


def _law(P, f):
    return {"C1": P.C1 * f, "n1": P.n1, "C2": P.C2, "n2": P.n2}


@pytest.fixture(scope="module")
def params_file(tmp_path_factory):
    P = example_params()
    p = (1e6, 1e8, 3e8)
    u = Uncertainty(
        level=0.9,
        method="made for the test",
        n_bootstrap=100,
        seed=0,
        samples=tuple(SampleLaw(f"s{i}", **_law(P, f)) for i, f in enumerate((0.8, 1.0, 1.2))),
        parameters={"C1": Interval(P.C1, 0.7 * P.C1, 1.4 * P.C1)},
        edge_laws={"lower": _law(P, 0.7), "upper": _law(P, 1.4)},
        bands=(Band("alpha_first", None, p, (0.1, 0.2, 0.3), (0.05, 0.1, 0.2), (0.2, 0.3, 0.4)),),
    )
    path = tmp_path_factory.mktemp("params") / "params.json"
    P.replace(uncertainty=u).to_json(path)
    return path


def _csv(path):
    with path.open() as fh:
        return list(csv.DictReader(fh))


class _Cells(HTMLParser):
    def __init__(self):
        super().__init__()
        self.cells, self._key, self.images = {}, None, 0

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        self._key = a.get("data-key")
        if tag == "img":
            self.images += a["src"].startswith("data:image/png;base64,")

    def handle_data(self, data):
        if self._key is not None:
            self.cells[self._key] = data
            self._key = None


def test_upsetting_band_orders_the_force_and_report_agrees(params_file, tmp_path, capsys):
    out = tmp_path / "u"
    rc = main(["upsetting", "--params", str(params_file), "--band", "--out", str(out), *TINY])
    assert rc == 0
    assert "force at 50 %:" in capsys.readouterr().out
    rows = _csv(out / "history.csv")
    assert list(rows[0]) == [
        "height_reduction_fraction",
        "stage",
        "force_N",
        "force_lower_N",
        "force_upper_N",
    ]
    runs = {n: _csv(out / n / "history.csv") for n in ("central", "lower", "upper")}
    for i, row in enumerate(rows):
        f, lo, hi = (float(row[k]) for k in ("force_N", "force_lower_N", "force_upper_N"))
        assert lo <= f <= hi
        # the band is the least and greatest force of the three runs at each increment
        fr = [float(runs[n][i]["force_N"]) for n in ("central", "lower", "upper")]
        assert lo == pytest.approx(min(fr)) and hi == pytest.approx(max(fr))
        # more friction needs more force while the die pressure is moderate (at larger
        # reductions on this 6-element mesh the runs cross, hence the min/max band)
        if float(row["height_reduction_fraction"]) <= 0.25:
            assert fr[1] < fr[0] < fr[2]
    s = json.loads((out / "summary.json").read_text())
    at = s["force_at"]["50 %"]
    assert at["plus_minus"] == pytest.approx(0.5 * (at["upper"] - at["lower"]))
    assert at["central"] == pytest.approx(float(rows[-1]["force_N"]))
    assert at["plus_minus"] > 1e-3 * at["central"]
    page = _Cells()
    page.feed((out / "report.html").read_text(encoding="utf-8"))
    assert page.images == 1 and "force_at.50 %.plus_minus" in page.cells
    for key, text in page.cells.items():
        a, red, f = key.split(".", 2)
        assert float(text) == pytest.approx(s[a][red][f], rel=1e-5)


def test_ring_band_has_the_inner_diameter(params_file, tmp_path):
    out = tmp_path / "r"
    argv = ["ring", "--law", "sbmf", "--params", str(params_file), "--band", "--out", str(out)]
    assert main(argv + ["--reduction", "0.3", *TINY]) == 0
    s = json.loads((out / "summary.json").read_text())
    d = s["inner_diameter_change_at"]["25 %"]
    assert d["lower"] <= d["central"] <= d["upper"] and d["upper"] > d["lower"]
    end = {n: _csv(out / n / "history.csv")[-1] for n in ("lower", "upper")}
    # more friction closes the hole more: the inner diameter grows less (or shrinks)
    assert float(end["upper"]["inner_diameter_change_fraction"]) < float(
        end["lower"]["inner_diameter_change_fraction"]
    )
    assert (out / "ring_band.png").is_file() and (out / "report.html").is_file()


def test_samples_runs_every_sample_law(params_file, tmp_path):
    out = tmp_path / "m"
    argv = ["multistage", "--params", str(params_file), "--samples", "--out", str(out)]
    assert main(argv + TINY) == 0
    for n in ("central", "sample_s0", "sample_s1", "sample_s2"):
        assert (out / n / "history.csv").is_file()
    s = json.loads((out / "summary.json").read_text())
    assert s["mode"] == "samples" and set(s["runs"]) == {
        "central",
        "sample_s0",
        "sample_s1",
        "sample_s2",
    }
    rows = _csv(out / "history.csv")
    assert {r["stage"] for r in rows} >= {"1", "3"}


@pytest.mark.parametrize(
    "argv, match",
    [
        (["upsetting", "--band"], "needs --law sbmf and a --params"),
        (["upsetting", "--law", "tresca", "--band"], "needs --law sbmf"),
        (["upsetting", "--band", "--samples"], "not allowed with"),
    ],
)
def test_band_bad_input(argv, match, tmp_path, capsys):
    rc = main(argv + ["--out", str(tmp_path / "x")])
    assert rc == 2
    assert match in capsys.readouterr().err
    assert not (tmp_path / "x").exists()


def test_band_refuses_a_file_without_uncertainty(tmp_path, capsys):
    path = example_params().to_json(tmp_path / "p.json")
    rc = main(["upsetting", "--params", str(path), "--band", "--out", str(tmp_path / "x")])
    assert rc == 2 and "uncertainty block" in capsys.readouterr().err


def test_combine_interpolates_stage_by_stage():
    c = {
        "height_reduction": np.array([0.1, 0.2, 0.15, 0.25]),
        "stage": np.array([1, 1, 3, 3]),
        "force": np.array([1.0, 2.0, 1.5, 2.5]),
    }
    o = {
        "height_reduction": np.array([0.1, 0.2, 0.1, 0.3]),
        "stage": np.array([1, 1, 3, 3]),
        "force": np.array([2.0, 4.0, 1.0, 5.0]),
    }
    b = combine({"central": c, "other": o})
    np.testing.assert_allclose(b["force_upper"], [2.0, 4.0, 2.0, 4.0])
    np.testing.assert_allclose(b["force_lower"], [1.0, 2.0, 1.5, 2.5])


def test_every_run_writes_a_report_that_agrees_with_its_summary(tmp_path):
    out = tmp_path / "ring"
    argv = ["ring", "--m", "0.3", "--reduction", "0.2", "--out", str(out), *TINY]
    assert main(argv) == 0
    s = json.loads((out / "summary.json").read_text())
    page = Cells((out / "report.html").read_text(encoding="utf-8"))
    assert page.images == 3  # force-stroke, die profile, ring chart
    assert {
        "force_end_N",  # shown in kN
        "stopped_at_height_reduction",  # in %
        "inner_diameter_change",  # a ring: what a ring test measures
        "inner_diameter_min_change",
        "law_parameters.m",
        "billet.outer_diameter_m",  # in mm
        "material.K_Pa",
        "mesh.n_elements",
        "wall_time_s",
    } <= set(page.cells)
    assert page.text["force_end_N"] == f"{s['force_end_N'] / 1e3:.5g}"
    assert_page_agrees(page, s)

"""Every report shows the law the parameter file runs (issue 41, items 1 and 6).

A calibration runs one form per branch and keeps the other reload form beside it. The console,
``summary.json``, ``report.html`` and the plot titles name the form that runs, its parameters or
table and its held-out error, and give the other form as the comparison it is; ``fe-demo``'s
``summary.json`` and ``report.html`` name the same law with its source. All built from one
description (:mod:`frictionlaw.describe`) of the runtime's form records, which a new form
extends with one record (tests/test_branch_forms.py).
"""

import hashlib
import html
import json

import numpy as np
import pytest
from reportcells import Cells, assert_page_agrees

from fe_demo.__main__ import main as fe_demo
from fe_demo.output.figures import die_profile_figure, robust_limit
from frictionlaw import FrictionParams
from frictionlaw.describe import Quantity, describe_law
from halfspace_calib.__main__ import main as calibrate

#: the name reports give each first-loading form
FIRST = {"eq24": "Eq. 24", "tabulated": "the computed first loading, tabulated"}
SMALL = [
    "--grid", "32",
    "--pressures", "25e6,100e6,200e6,400e6,600e6",
    "--reload-fractions", "0.1,0.3,0.6,0.9",
    "--heldout-tol", "0.5",  # a toy grid: the acceptance is tested elsewhere
    "--no-progress",
]  # fmt: skip
FE = ["--nr", "6", "--increments", "6", "--reduction", "0.3", "--vtu-every", "0", "--quiet"]


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """Two calibrations of one scene: the default form choice (tabulated) and the paper's."""
    out = {}
    for form in ("auto", "paper"):
        folder = tmp_path_factory.mktemp(form) / "calibration"
        assert calibrate([*SMALL, "--reload-form", form, "--out", str(folder)]) == 0
        out[form] = folder
    return out


def _read(folder):
    summary = json.loads((folder / "summary.json").read_text())
    return summary, FrictionParams.from_json(folder / "params.json")


@pytest.mark.parametrize("form, other", [("auto", "paper"), ("paper", None)])
def test_summary_and_report_name_the_form_that_runs(runs, form, other):
    """The default run (tabulated, the paper's form beside it) and ``--reload-form paper``
    (the paper's form alone: no table is fitted)."""
    s, P = _read(runs[form])
    running = P.reload_form
    assert running == ("tabulated" if form == "auto" else "paper")
    reload = s["law"]["branches"]["reload"]
    assert (
        reload["runs"] == running and list(reload["forms"]) == [running, other][: 1 + bool(other)]
    )
    # each form carries the calibration's measured errors: the one that runs, the one beside it
    assert reload["forms"][running]["errors"]["heldout_max"] == s["errors"]["reload"]["heldout_max"]
    if other:
        beside = s["errors"][f"reload_{other}"]["heldout_max"]
        assert reload["forms"][other]["errors"]["heldout_max"] == beside
    if running == "tabulated":
        table = reload["forms"]["tabulated"]["table"]
        assert [r[0] for r in table["rows"]] == list(P.reload_table.p_hist)
        assert [r[1] for r in table["rows"]] == list(P.reload_table.C2)
        assert reload["forms"]["tabulated"]["parameters"]["s2"]["value"] == P.reload_table.s2
    assert reload["forms"]["paper"]["parameters"]["C2"]["value"] == P.C2
    assert s["law"]["forms"].startswith(FIRST[P.first_loading_form] + " + ")
    raw = (runs[form] / "report.html").read_text(encoding="utf-8")
    page_text = html.unescape(raw)
    name = {"tabulated": "Eq. 25 tabulated over p_hist", "paper": "the paper's Eq. 25"}
    assert f"{name[running]}: runs" in page_text
    for n in name:  # the reload form beside the one that runs, if any
        beside = f"{name[n]}: beside it for comparison, not run" in page_text
        assert beside == (n == other)
    page = Cells(raw)
    assert_page_agrees(page, s)
    # the paper's pair is shown only as that form's parameters, never as the law's
    assert "C2" not in page.cells and "reload_r2" not in page.cells
    assert "law.branches.reload.forms.paper.parameters.C2.value" in page.cells
    key = f"law.branches.reload.forms.{running}.errors.heldout_max"
    assert page.cells[key] == pytest.approx(s["errors"]["reload"]["heldout_max"], rel=1e-3)


def test_the_console_names_the_form_that_runs_and_the_one_beside_it(runs, tmp_path, capsys):
    out = tmp_path / "c"
    assert calibrate([*SMALL, "--out", str(out)]) == 0
    text = capsys.readouterr().out
    s, P = _read(out)
    forms = f"{FIRST[P.first_loading_form]} + Eq. 25 tabulated over p_hist"
    assert f"the law the parameter file runs: {forms}" in text
    held = s["errors"]["reload"]["heldout_max"]
    assert f"s2 = {P.reload_table.s2:.4g}" in text and f"held out max {held:.4f}" in text
    assert f"beside it, not run: the paper's Eq. 25: C2 = {P.C2:.4g}, n2 = {P.n2:.4g}" in text


def test_fe_demo_names_the_law_that_runs_its_source_and_the_force_in_kn(runs, tmp_path):
    params = runs["auto"] / "params.json"
    sha = hashlib.sha256(params.read_bytes()).hexdigest()
    out = tmp_path / "u"
    assert fe_demo(["upsetting", "--params", str(params), "--out", str(out), *FE]) == 0
    s = json.loads((out / "summary.json").read_text())
    lp = s["law_parameters"]
    assert lp["sha256"] == sha and lp["reload_form"] == "tabulated"
    law = lp["law"]
    assert law["source"] == {"path": str(params), "sha256": sha}
    P = FrictionParams.from_json(params)
    assert law["forms"] == f"{FIRST[P.first_loading_form]} + Eq. 25 tabulated over p_hist" + (
        " (continuous at p_hist)" if P.continuous_reload else ""
    )
    assert law["branches"]["reload"]["runs"] == "tabulated"
    # the run's label tells calibrations apart: folder, file and the sha256's first digits
    assert s["run"] == f"sbmf calibration/params.json [{sha[:8]}]"
    with (out / "history.csv").open() as fh:
        last = fh.read().splitlines()[-1].split(",")
    assert s["force_end_N"] == pytest.approx(float(last[1]), rel=1e-9)
    text = (out / "report.html").read_text(encoding="utf-8")
    page = Cells(text)
    assert_page_agrees(page, s)
    assert page.text["force_end_N"] == f"{s['force_end_N'] / 1e3:.5g}"
    assert "<td class='t'>kN</td>" in text and sha in text
    for key in (
        "law_parameters.m",
        "law_parameters.law.branches.reload.forms.tabulated.parameters.s2.value",
        "law_parameters.law.branches.reload.forms.tabulated.errors.heldout_max",
        "billet.diameter_m",
        "mesh.elements_radial",
    ):
        assert key in page.cells, key
    assert "at height reduction 30.0 % (the end of the run)" in text


def test_a_file_switched_to_the_other_form_is_described_with_that_forms_errors(runs):
    """A user switches a calibration to the paper's form: the description follows the file."""
    s, P = _read(runs["auto"])
    law = describe_law(P.replace(reload_form="paper"))
    reload = law.branch("reload")
    assert [f.form for f in reload.forms] == ["paper", "tabulated"]
    assert reload.running.errors.heldout_max == s["errors"]["reload_paper"]["heldout_max"]
    assert reload.others[0].errors.heldout_max == s["errors"]["reload"]["heldout_max"]


def test_a_hand_made_file_says_its_errors_are_not_recorded():
    P = FrictionParams(m=0.5, sigma_y=3e8, H=8e8, C1=1.0, n1=2.0, C2=3.0, n2=1.5)
    law = describe_law(P)
    assert [b.running.form for b in law.branches] == ["eq24", "paper"]
    assert all(b.running.errors is None and not b.others for b in law.branches)
    assert "errors not recorded in the file" in "\n".join(law.lines())
    assert law.to_dict()["inputs"]["m"] == Quantity("m", 0.5, "1", law.inputs[0].meaning).to_dict()


def test_the_die_profile_shows_the_shear_beside_an_edge_spike():
    r = np.linspace(0.0, 14e-3, 60)
    p = np.full(r.size, 650e6)
    tau = np.full(r.size, 60e6)
    p[-2], tau[-2] = 2000e6, 400e6  # the die edge's spike
    lim, clipped = robust_limit(p / 1e6)
    assert lim == pytest.approx(1.5 * 650) and list(clipped) == [r.size - 2]
    lim, clipped = robust_limit(np.full(5, 60.0))
    assert lim == pytest.approx(63.0) and clipped.size == 0
    prof = {"r": r, "p": p, "tau": tau, "p_hist": p, "height_reduction": 0.5}
    fig = die_profile_figure(prof, title="sbmf calibration/params.json [abcd1234]")
    top, shear = fig.axes
    assert "at height reduction 50.0 %" in fig._suptitle.get_text()
    assert shear.get_ylim()[1] == pytest.approx(90.0)  # 1.5 x the bulk's 60 MPa: readable
    assert top.get_ylim()[1] == pytest.approx(975.0)
    notes = [t.get_text() for a in fig.axes for t in a.texts]
    assert "p 2000 MPa (edge spike, off the axis)" in notes
    assert "tau 400 MPa (edge spike, off the axis)" in notes


def test_a_tabulated_first_loading_is_described_as_it_runs(runs):
    """A file running the computed first loading: its table and mu_eff, Eq. 24 beside it."""
    from frictionlaw.first_loading import FirstLoadingTable

    P = FrictionParams.from_json(runs["auto"] / "params.json")
    p = np.array([25e6, 100e6, 200e6, 400e6])
    a = np.array([0.05, 0.17, 0.31, 0.55])
    T = P.replace(first_loading_form="tabulated", first_loading_table=FirstLoadingTable(p, a))
    first = describe_law(T).branch("first_loading")
    assert first.running.form == "tabulated" and first.others[0].form == "eq24"
    rows = first.running.table.rows
    assert [r[0] for r in rows] == list(p) and [r[1] for r in rows] == list(a)
    mu = [q.value for q in first.running.parameters if q.name == "mu_eff"][0]
    assert mu == pytest.approx(T.tau_max * 0.05 / 25e6, rel=1e-12)

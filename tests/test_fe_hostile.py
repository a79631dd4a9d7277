"""Issue 12, items 11-15: fe-demo honours every option, and its outputs agree on where it stopped."""

import csv
import json

import pytest

from fe_demo.analysis.ring_chart import ring_chart
from fe_demo.cli import main
from fe_demo.cli.runs import write_run
from fe_demo.scenes import run_upsetting
from fe_demo.solver.model import SolverOptions

FAST = ["--nr", "4", "--increments", "3", "--no-progress", "--vtu-every", "0"]


def _rows(path):
    with path.open() as fh:
        return list(csv.DictReader(fh))


# -- item 11: a given --m runs that m alone; no option is silently ignored ------------------------


def test_ring_with_a_given_m_runs_that_m_alone(tmp_path):
    out = tmp_path / "ring"
    assert (
        main(
            ["ring", "--law", "tresca", "--m", "0", "--reduction", "0.15", "--out", str(out), *FAST]
        )
        == 0
    )
    assert (out / "history.csv").exists()
    assert not [p for p in out.iterdir() if p.is_dir()]  # no chart sweep into subfolders
    summary = json.loads((out / "summary.json").read_text())
    assert summary["law"] == "tresca" and summary["law_parameters"] == {"m": 0.0}


@pytest.mark.parametrize(
    "argv, fragment",
    [
        (["upsetting", "--law", "sbmf", "--m", "0.5"], "--m is not used by --law sbmf"),
        (["upsetting", "--law", "tresca", "--mu", "0.2"], "--mu is not used by --law tresca"),
        (
            ["upsetting", "--law", "coulomb", "--tau-max", "1e8"],
            "--tau-max is not used by --law coulomb",
        ),
        (["upsetting", "--law", "none", "--mu", "0.2"], "--mu is not used by --law none"),
        (
            ["upsetting", "--law", "cap", "--tau-max", "1e8", "--m", "0.5"],
            "--m is not used by --law cap",
        ),
        (["ring", "--law", "coulomb", "--m-list", "0,1"], "--m-list is not used by --law coulomb"),
        (["ring", "--m", "0.3", "--m-list", "0,1"], "give --m or --m-list, not both"),
        (
            ["multistage", "--law", "tresca", "--params", "x.json"],
            "--params is not used by --law tresca",
        ),
    ],
)
def test_options_the_run_would_not_use_are_refused(tmp_path, capsys, argv, fragment):
    assert main([*argv, "--out", str(tmp_path / "o"), *FAST]) == 2
    err = capsys.readouterr().err
    assert fragment in err and "Traceback" not in err
    assert not (tmp_path / "o").exists()  # refused before any work


# -- item 12: a reduction beyond the chart's reach still runs the FE ------------------------------


def test_ring_chart_ends_where_the_upper_bound_hole_closes():
    red, d = ring_chart(1.0, 0.65, n_steps=100)
    assert red[-1] < 0.65 and d[-1] > -1.0  # stopped before Ri <= 0
    red5, _ = ring_chart(0.5, 0.65, n_steps=100)
    assert red5[-1] == pytest.approx(0.65)


def test_ring_beyond_the_chart_runs_the_fe(tmp_path, capsys):
    out = tmp_path / "ring"
    rc = main(
        ["ring", "--law", "tresca", "--m", "0.3", "--reduction", "0.65", "--out", str(out), *FAST]
    )
    assert rc in (0, 1)
    assert (out / "history.csv").exists() and (out / "ring_chart.png").exists()
    assert "the upper-bound hole closes" in capsys.readouterr().out
    rows = _rows(out / "ring_chart_upper_bound.csv")
    m1 = [float(r["height_reduction_fraction"]) for r in rows if r["m"] == "1"]
    assert 0.5 < max(m1) < 0.65


# -- item 13: a run that stops records the accepted sub-steps everywhere --------------------------


def test_stopped_run_records_the_accepted_part_of_its_last_increment(tmp_path):
    # one increment to 70 %: cut back twice, sub-steps accepted, then it fails
    res = run_upsetting(
        "tresca",
        m=0.3,
        nr=4,
        reduction=0.7,
        n_increments=1,
        options=SolverOptions(max_iter=10, max_cutbacks=2),
        snapshot_every=1,
    )
    assert not res.converged and res.model.height_reduction > 0
    last = res.model.height_reduction
    assert res.history["height_reduction"][-1] == last
    assert res.history["partial"][-1] == 1
    assert res.snapshots[-1]["height_reduction"] == last
    write_run(tmp_path, res, "stopped")
    rows = _rows(tmp_path / "history.csv")
    assert float(rows[-1]["height_reduction_fraction"]) == pytest.approx(last, rel=1e-9)
    pvd = (tmp_path / "vtu" / "step.pvd").read_text()
    assert f'timestep="{last:.8g}"' in pvd.splitlines()[-3]
    assert json.loads((tmp_path / "summary.json").read_text())["stopped_at_height_reduction"] == (
        pytest.approx(last)
    )


# -- item 14: summary.json records the parameters the run used ------------------------------------


def test_summary_records_the_sbmf_parameters_used(tmp_path):
    from frictionlaw import FrictionParams

    P = FrictionParams(m=0.45, sigma_y=3e8, H=8e8, C1=1.5, n1=2.5, C2=3.0, n2=1.5)
    pfile = P.to_json(tmp_path / "p.json")
    out = tmp_path / "ups"
    argv = ["upsetting", "--law", "sbmf", "--params", str(pfile), "--reduction", "0.1"]
    assert main([*argv, "--out", str(out), *FAST]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert "mu" not in s and "m" not in s
    lp = s["law_parameters"]
    assert lp["params_file"] == str(pfile)
    assert lp["m"] == 0.45 and lp["C1"] == 1.5 and lp["n2"] == 1.5
    assert lp["continuous_reload"] is False


# -- item 15: unreadable parameter files -----------------------------------------------------------


@pytest.mark.parametrize("kind", ["nested", "binary"])
def test_unreadable_params_file_is_bad_input_naming_the_file(tmp_path, capsys, kind):
    f = tmp_path / f"{kind}.json"
    if kind == "nested":
        f.write_text("[" * 100_000 + "]" * 100_000)
    else:
        f.write_bytes(bytes(range(256)) * 4)
    assert (
        main(
            ["upsetting", "--law", "sbmf", "--params", str(f), "--out", str(tmp_path / "o"), *FAST]
        )
        == 2
    )
    err = capsys.readouterr().err
    assert str(f) in err and "Traceback" not in err
    assert not (tmp_path / "o").exists()

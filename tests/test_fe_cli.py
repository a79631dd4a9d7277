"""The fe-demo command line: files written, columns, bad input."""

import csv

import meshio
import numpy as np
import pytest

from fe_demo.cli import main
from fe_demo.output import HISTORY_UNITS, csv_header
from fe_demo.output.history import read_history_csv
from fe_demo.scenes.laws import make_law_factory


def _csv(path):
    with path.open() as fh:
        rows = list(csv.DictReader(fh))
    return rows


def test_upsetting_cli_writes_csv_png_vtu(tmp_path, capsys):
    out = tmp_path / "ups"
    rc = main(
        [
            "upsetting",
            "--nr",
            "4",
            "--increments",
            "4",
            "--reduction",
            "0.2",
            "--out",
            str(out),
            "--no-progress",
            "--vtu-every",
            "2",
        ]
    )
    assert rc == 0
    rows = _csv(out / "history.csv")
    assert len(rows) == 4
    assert list(rows[0])[:3] == ["height_reduction_fraction", "force_N", "stroke_m"]
    red = np.array([float(r["height_reduction_fraction"]) for r in rows])
    np.testing.assert_allclose(red, [0.05, 0.1, 0.15, 0.2], atol=1e-9)
    # stroke in m: 20 % of h0 = 10 mm; every dimensional column names its SI unit
    assert float(rows[-1]["stroke_m"]) == pytest.approx(2e-3, rel=1e-9)
    units = {csv_header(k): u for k, u in HISTORY_UNITS.items()}
    for col in rows[0]:  # every name states its unit; bare names are counts, flags, ratios
        assert col in units and (units[col] == "1" or col.endswith("_" + units[col])), col
    # what reads a history takes these names and the earlier ones alike
    hist = read_history_csv(out / "history.csv")
    np.testing.assert_array_equal(hist["height_reduction"], red)
    old = tmp_path / "old.csv"
    old.write_text("height_reduction,force\n0.1,5\n")
    assert read_history_csv(old)["height_reduction"][0] == 0.1
    with pytest.raises(ValueError, match="'foo' has no unit"):
        csv_header("foo")
    for png in ("force_stroke.png", "die_profile.png"):
        assert (out / png).stat().st_size > 1000
    pvd = (out / "vtu" / "step.pvd").read_text()
    assert pvd.count("<DataSet") == 3
    m = meshio.read(out / "vtu" / "step_0002.vtu")
    # VTU field names state their units
    assert {"displacement_m", "contact_pressure_Pa", "shear_Pa", "p_hist_Pa"} <= set(m.point_data)
    assert {"von_mises_Pa", "eps_p", "stress_zz_Pa"} <= set(m.cell_data)
    assert m.point_data["p_hist_Pa"].max() > 0
    assert "sbmf" in capsys.readouterr().out


def test_upsetting_all_laws_and_ring_and_multistage(tmp_path):
    out = tmp_path / "all"
    args = ["--nr", "4", "--increments", "3", "--reduction", "0.15", "--no-progress"]
    assert main(["upsetting", "--law", "all", "--out", str(out), "--vtu-every", "0", *args]) == 0
    assert (out / "law_comparison.png").exists()
    for law in ("coulomb", "tresca", "cap", "sbmf"):
        assert (out / law / "history.csv").exists()
    ring = tmp_path / "ring"
    assert main(["ring", "--m-list", "0,1", "--out", str(ring), "--vtu-every", "0", *args]) == 0
    assert (ring / "ring_chart.png").exists()
    rows = _csv(ring / "FE_m1" / "history.csv")
    assert list(rows[0])[:3] == [
        "height_reduction_fraction",
        "force_N",
        "inner_diameter_change_fraction",
    ]
    assert float(rows[-1]["inner_diameter_change_fraction"]) < 0
    ms = tmp_path / "ms"
    assert (
        main(
            [
                "multistage",
                "--out",
                str(ms),
                "--nr",
                "4",
                "--increments",
                "6",
                "--no-progress",
                "--vtu-every",
                "0",
            ]
        )
        == 0
    )
    assert (ms / "with_history" / "history.csv").exists()
    assert (ms / "multistage_force.png").exists()
    assert (ms / "recontact_friction.png").exists()


def test_bad_input(tmp_path, capsys):
    assert main(["upsetting", "--reduction", "1.2", "--out", str(tmp_path)]) == 2
    assert main(["upsetting", "--params", str(tmp_path / "nope.json")]) == 2
    assert main(["upsetting", "--law", "tresca", "--m", "2", "--out", str(tmp_path)]) == 2
    assert "m must be in [0, 1]" in capsys.readouterr().err
    assert main(["upsetting", "--law", "foo"]) == 2  # argparse's refusal, as an exit code
    with pytest.raises(ValueError, match="law must be one of"):
        make_law_factory("foo")
    with pytest.raises(ValueError, match="mu must be"):
        make_law_factory("coulomb", mu=-1)


@pytest.mark.parametrize("scene", ["upsetting", "ring", "multistage", "ring-fit"])
def test_a_bad_material_file_is_bad_input_naming_the_option(tmp_path, capsys, monkeypatch, scene):
    """--material missing, a folder, not JSON, or wrong: exit 2 naming --material and the path,
    before any FE run, no traceback, no output (a missing file exited 1 as a failed write)."""
    import fe_demo.analysis.ringfit as ringfit
    import fe_demo.cli.runs as runs

    def no_fe(*a, **k):
        raise AssertionError("an FE run started")

    for name in ("run_upsetting", "run_ring", "run_multistage"):
        monkeypatch.setattr(runs, name, no_fe)
    monkeypatch.setattr(ringfit, "run_ring", no_fe)
    argv = [scene, "--out", str(tmp_path / "o")]
    if scene == "ring-fit":
        measured = tmp_path / "r.csv"
        measured.write_text(
            "# geometry: OD = 18 mm, ID = 9 mm, H = 6 mm\n"
            "height_reduction,inner_diameter_change\n0.15,0.02\n0.3,0.05\n0.5,0.12\n"
        )
        argv += ["--measured", str(measured), "--illustrative"]
    (tmp_path / "bad.json").write_text("{not json")
    (tmp_path / "soft.json").write_text('{"E": 210e9, "n": 1.5}')
    for path, said in [
        (tmp_path / "gone.json", "no such file"),
        (tmp_path, "a folder, not a material JSON file"),
        (tmp_path / "bad.json", "not valid JSON"),
        (tmp_path / "soft.json", "n must be in [0, 1]"),
    ]:
        assert main([*argv, "--material", str(path)]) == 2
        err = capsys.readouterr().err
        assert f"--material {path}: {said}" in err and "Traceback" not in err
        assert len(err.strip().splitlines()) == 1
    assert main([*argv, "--material", ""]) == 2
    assert "argument --material: an empty value" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


def test_fe_demo_never_imports_halfspace_calib():
    import subprocess
    import sys

    code = (
        "import sys, fe_demo, fe_demo.cli, fe_demo.scenes, fe_demo.solver.remesh;"
        "print('halfspace_calib' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_run_figures_for_a_notebook(tmp_path):
    from fe_demo.scenes import contact_profile, run_upsetting

    res = run_upsetting("tresca", nr=4, n_increments=3, reduction=0.15, progress=False)
    before = sorted(tmp_path.iterdir())
    figs = res.figures("m=0.3")
    assert sorted(figs) == ["die_profile.png", "force_stroke.png"]
    assert all(f.canvas.manager is None for f in figs.values())  # not held by pyplot
    ((x, y),) = [(ln.get_xdata(), ln.get_ydata()) for ln in figs["force_stroke.png"].axes[0].lines]
    np.testing.assert_allclose(x, 100 * res.history["height_reduction"], rtol=1e-15)
    np.testing.assert_allclose(y, res.history["force"] / 1e3, rtol=1e-15)
    prof = contact_profile(res.model)
    on = prof["p"] > 0
    xp = figs["die_profile.png"].axes[0].lines[0].get_xdata()
    np.testing.assert_allclose(xp, 1e3 * prof["r"][on], rtol=1e-15)
    assert figs["force_stroke.png"].axes[0].get_title() == "m=0.3"
    assert sorted(tmp_path.iterdir()) == before  # nothing written

"""``fe-demo ring-fit`` as a new user meets it (issue 33): no m without its law, everyday CSV
files, the ring and material stated in the file, the provenance of m, the command contract.

Every refusal here happens before an FE run (``run_ring`` is replaced by one that fails the
test); the runs that fit use the coarse mesh.
"""

import hashlib
import json
import math
import os
import shutil

import numpy as np
import pytest

import fe_demo.analysis.ringfit as ringfit
from fe_demo.analysis.ringfit import RingFit, ring_curve
from fe_demo.cli import main
from fe_demo.output.ring_fit import ring_fit_figure
from fe_demo.scenes.laws import EXAMPLE_PARAMS_PATH
from frictionlaw import FrictionParams

COARSE = ["--nr", "8", "--increments", "20"]
RED = np.array([0.15, 0.25, 0.35, 0.45, 0.5])
GEOMETRY = "# geometry: OD = 18 mm, ID = 9 mm, H = 6 mm\n"
ALUMINIUM = "# material: E = 70 GPa, nu = 0.33, K = 180 MPa, eps0 = 0.01, n = 0.2\n"


def _sha(path):
    return hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.fixture(scope="module")
def points():
    """Inner-diameter changes of the coarse FE ring with the example law at m = 0.3."""
    P = FrictionParams.from_json(EXAMPLE_PARAMS_PATH)
    r, d = ring_curve("sbmf", 0.3, params=P, reduction=0.5, nr=8, n_increments=20)
    return np.interp(RED, r, d)


def _write(path, d, *, header="", sep=",", decimal=".", bom=False):
    rows = [f"height_reduction{sep}inner_diameter_change"]
    rows += [f"{a:.6f}{sep}{b:.6f}".replace(".", decimal) for a, b in zip(RED, d, strict=True)]
    text = header + "\n".join(rows) + "\n"
    path.write_bytes(("\ufeff" if bom else "").encode() + text.encode("utf-8"))
    return path


@pytest.fixture
def no_fe(monkeypatch):
    def fail(*a, **k):
        raise AssertionError("an FE run started")

    monkeypatch.setattr(ringfit, "run_ring", fail)


@pytest.fixture(scope="module")
def calibration(tmp_path_factory):
    """A calibration's parameter file (the example law's numbers, copied as a user's file)."""
    path = tmp_path_factory.mktemp("cal") / "params.json"
    shutil.copy(EXAMPLE_PARAMS_PATH, path)
    return path


@pytest.fixture(scope="module")
def fitted(tmp_path_factory, points, calibration):
    """One fit from a European CSV with a BOM that states its ring: output folder and streams."""
    work = tmp_path_factory.mktemp("fit")
    csv = _write(work / "rings.csv", points, header=GEOMETRY, sep=";", decimal=",", bom=True)
    out = work / "out"
    argv = ["ring-fit", "--measured", str(csv), "--params", str(calibration), *COARSE]
    rc = main([*argv, "--no-progress", "--out", str(out)])
    return rc, out, csv, calibration


def test_sbmf_without_params_exits_2_naming_it(tmp_path, capsys, points, no_fe):
    csv = _write(tmp_path / "r.csv", points)
    assert main(["ring-fit", "--measured", str(csv), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "--params is required with --law sbmf" in err and "--illustrative" in err
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize(
    "extra, message",
    [
        (["--illustrative", "--params", str(EXAMPLE_PARAMS_PATH)], "not both"),
        (["--law", "tresca", "--illustrative"], "--illustrative is not used by --law tresca"),
    ],
)
def test_illustrative_is_an_explicit_choice(tmp_path, capsys, points, no_fe, extra, message):
    csv = _write(tmp_path / "r.csv", points)
    assert main(["ring-fit", "--measured", str(csv), *extra, "--out", str(tmp_path / "o")]) == 2
    assert message in capsys.readouterr().err


def test_illustrative_law_says_so_in_params_json_and_on_stderr(tmp_path, capsys, points):
    csv = _write(tmp_path / "r.csv", points, header=GEOMETRY)
    out = tmp_path / "o"
    rc = main(["ring-fit", "--measured", str(csv), "--illustrative", *COARSE, "--out", str(out)])
    cap = capsys.readouterr()
    assert rc == 0 and "illustrative" in cap.err and "NOT a calibration result" in cap.err
    doc = json.loads((out / "params.json").read_text())
    assert "illustrative" in doc["provenance"]["note"]
    assert doc["provenance"]["ring_test"]["illustrative"] is True
    assert doc["provenance"]["ring_test"]["source_params"]["illustrative"] is True


def test_bom_and_european_csv_read_as_the_plain_file(tmp_path, points):
    plain = ringfit.read_ring_tests([_write(tmp_path / "a.csv", points)])
    bom = ringfit.read_ring_tests([_write(tmp_path / "b.csv", points, bom=True)])
    euro = ringfit.read_ring_tests([_write(tmp_path / "c.csv", points, sep=";", decimal=",")])
    tab = ringfit.read_ring_tests([_write(tmp_path / "d.csv", points, sep="\t", decimal=",")])
    for t in (bom, euro, tab):
        assert t.column == plain.column
        assert np.array_equal(t.reduction, plain.reduction)
        assert np.array_equal(t.d_inner, plain.d_inner)


def test_the_files_header_states_ring_and_material(tmp_path, points):
    header = "# geometry: OD = 20 mm, ID = 10 mm, H = 7 mm\n" + ALUMINIUM
    t = ringfit.read_ring_tests([_write(tmp_path / "a.csv", points, header=header)])
    assert t.geometry == pytest.approx(
        {"outer_diameter": 0.02, "inner_diameter": 0.01, "height": 0.007}
    )
    assert t.material == pytest.approx({"E": 70e9, "nu": 0.33, "K": 180e6, "eps0": 0.01, "n": 0.2})
    euro = "# geometry: OD = 20,5 mm; ID = 10 mm; H = 7 mm\n"
    t = ringfit.read_ring_tests([_write(tmp_path / "b.csv", points, header=euro)])
    assert t.geometry["outer_diameter"] == pytest.approx(0.0205)
    # a German data sheet's N/mm² and a US one's ksi (1000 lbf / in^2, exact: 6.894757 MPa)
    german = "# material: E = 70000 N/mm\u00b2; nu = 0,33; K = 180 N/mm2; eps0 = 0,01; n = 0,2\n"
    t = ringfit.read_ring_tests([_write(tmp_path / "c.csv", points, header=german)])
    assert t.material == pytest.approx({"E": 70e9, "nu": 0.33, "K": 180e6, "eps0": 0.01, "n": 0.2})
    us = "# material: E = 10152.6 ksi, K = 26.1066 ksi, eps0 = 0.01, n = 0.2\n"
    t = ringfit.read_ring_tests([_write(tmp_path / "d.csv", points, header=us)])
    assert t.material["E"] == pytest.approx(70e9, rel=1e-5)
    assert t.material["K"] == pytest.approx(180e6, rel=1e-5)


@pytest.mark.parametrize(
    "header, message",
    [
        ("# geometry: OD = 18, ID = 9 mm, H = 6 mm\n", "OD needs a unit"),
        ("# geometry: OD = 18 mm, ID = 9 mm\n", "lacks H"),
        ("# material: K = 530 MPa, eps0 = 0.006\n", "lacks n"),
        ("# material: K = 530 MPa, eps0 = 0.006, n = 0.24, sigma = 3\n", "cannot read"),
    ],
)
def test_bad_header_lines_are_refused_naming_the_file(tmp_path, points, header, message):
    with pytest.raises(ValueError, match=message):
        ringfit.read_ring_tests([_write(tmp_path / "a.csv", points, header=header)])


def test_a_geometry_that_contradicts_the_file_is_refused_with_both(tmp_path, capsys, points, no_fe):
    csv = _write(
        tmp_path / "r.csv", points, header="# geometry: OD = 20 mm, ID = 10 mm, H = 7 mm\n"
    )
    argv = ["ring-fit", "--measured", str(csv), "--illustrative", "--geometry", "18,9,6"]
    assert main([*argv, "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "--geometry 18,9,6 mm differs" in err and "(20,10,7 mm" in err


def _stderr_before_fe(tmp_path, capsys, monkeypatch, header, extra=()):
    """stderr of a ring fit whose first FE run fails (the hints come before it)."""

    def fail(*a, **k):
        raise ValueError("stop")

    monkeypatch.setattr(ringfit, "run_ring", fail)
    csv = _write(tmp_path / "r.csv", np.full(RED.size, 0.01), header=header)
    argv = ["ring-fit", "--measured", str(csv), *extra, *COARSE, "--workers", "1"]
    assert main([*argv, "--out", str(tmp_path / "o")]) == 1
    return capsys.readouterr().err


def test_an_unstated_geometry_is_warned(tmp_path, capsys, monkeypatch):
    err = _stderr_before_fe(tmp_path, capsys, monkeypatch, "", ["--illustrative"])
    assert "geometry is stated neither by --geometry nor in r.csv" in err and "18,9,6" in err
    err = _stderr_before_fe(tmp_path, capsys, monkeypatch, GEOMETRY, ["--illustrative"])
    assert "geometry is stated" not in err


def test_a_material_far_from_the_calibrations_sigma_y_is_warned(tmp_path, capsys, monkeypatch):
    err = _stderr_before_fe(tmp_path, capsys, monkeypatch, GEOMETRY + ALUMINIUM, ["--illustrative"])
    # sigma_y of the law 285 MPa; aluminium flows at 71.7-168 MPa up to 50 % (ln 2)
    lo, hi = (180 * (0.01 + e) ** 0.2 for e in (0.0, math.log(1 / 0.5)))
    assert "sigma_y = 285 MPa" in err and f"{lo:.4g}-{hi:.4g} MPa" in err
    err = _stderr_before_fe(tmp_path, capsys, monkeypatch, GEOMETRY, ["--illustrative"])
    assert "sigma_y" not in err  # DC04 flows at 155-460 MPa: the law's 285 MPa is inside


def test_a_material_that_contradicts_the_file_is_refused(tmp_path, capsys, points, no_fe):
    mat = tmp_path / "dc04.json"
    mat.write_text(json.dumps({"E": 210e9, "nu": 0.3, "K": 530e6, "eps0": 0.006, "n": 0.24}))
    csv = _write(tmp_path / "r.csv", points, header=GEOMETRY + ALUMINIUM)
    argv = ["ring-fit", "--measured", str(csv), "--illustrative", "--material", str(mat)]
    assert main([*argv, "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "K 530 MPa" in err and "K 180 MPa" in err and "differs" in err


def test_the_default_worker_count_is_portable(monkeypatch, points):
    """macOS and Windows have no os.sched_getaffinity: the fit still chooses its workers."""
    seen = {}

    def stop(test, law, params, top, kw, workers, bar):
        seen["workers"] = workers
        raise RuntimeError("stop")

    monkeypatch.delattr(os, "sched_getaffinity", raising=False)
    monkeypatch.setattr(ringfit, "_fit_runs", stop)
    test = ringfit.RingTest(RED, points, "inner_diameter_change", ())
    with pytest.raises(RuntimeError, match="stop"):
        ringfit.fit_m(test, "tresca")
    assert seen["workers"] == min(2, os.cpu_count() or 1)


def test_the_fit_obeys_the_command_contract(fitted, capsys):
    rc, out, _, _ = fitted
    assert rc == 0
    rec = json.loads((out / "ring_fit.json").read_text())
    summary = (out / "summary.txt").read_text()
    # the console's (and summary.txt's) count of FE runs is ring_fit.json's, both fits
    assert f"{rec['n_fe_runs']} FE runs (" in summary
    assert summary.startswith("ring fit (sbmf): m = ")


def test_quiet_prints_nothing_and_summary_txt_keeps_the_summary(tmp_path, capsys, points):
    csv = _write(tmp_path / "r.csv", points, header=GEOMETRY)
    out = tmp_path / "o"
    argv = ["ring-fit", "--measured", str(csv), "--illustrative", *COARSE, "--quiet"]
    assert main([*argv, "--out", str(out)]) == 0
    cap = capsys.readouterr()
    assert cap.out == "" and "illustrative" in cap.err  # the warning still reaches stderr
    summary = (out / "summary.txt").read_text()
    assert summary.startswith("ring fit (sbmf): m = ") and "illustrative law (shipped): " in summary


def test_a_failed_write_exits_1_and_keeps_the_earlier_output(fitted, tmp_path, capsys, monkeypatch):
    import fe_demo.cli.ring_fit as cmd

    _, out, csv, cal = fitted
    copy = tmp_path / "out"
    shutil.copytree(out, copy)
    before = {p.name: p.read_bytes() for p in copy.iterdir()}

    def broken(*a, **k):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(cmd, "write_ring_fit", broken)
    argv = ["ring-fit", "--measured", str(csv), "--params", str(cal), *COARSE, "--quiet"]
    assert main([*argv, "--out", str(copy)]) == 1
    err = capsys.readouterr().err
    assert "No space left" in err and "unchanged" in err and "Traceback" not in err
    assert {p.name: p.read_bytes() for p in copy.iterdir()} == before


def test_params_json_says_where_m_came_from(fitted):
    _, out, csv, cal = fitted
    doc = json.loads((out / "params.json").read_text())
    m = doc["parameters"]["m"]
    prov = doc["provenance"]
    ring = prov["ring_test"]
    assert ring["m"] == m and ring["m_lower"] <= m <= ring["m_upper"] and ring["band_level"] == 0.9
    assert ring["source_params"] == {
        "path": str(cal.resolve()),
        "sha256": _sha(cal),
        "illustrative": False,
    }
    assert ring["measured_files"] == [{"path": str(csv.resolve()), "sha256": _sha(csv)}]
    assert ring["n_points"] == RED.size and ring["column"] == "inner_diameter_change"
    assert ring["geometry_m"] == pytest.approx(
        {"outer_diameter": 0.018, "inner_diameter": 0.009, "height": 0.006}, rel=1e-15
    )
    assert ring["geometry_source"] == "stated in rings.csv"
    assert ring["material"]["K"] == 530e6 and ring["material_source"].startswith("DC04")
    # no field contradicts the fitted m
    assert prov["material"]["m"] == m
    assert f"m = {m:.4f}" in prov["inputs"]["m"] and "ring-compression tests" in prov["inputs"]["m"]
    assert "not fitted" not in json.dumps(prov)


def test_the_report_names_its_inputs(fitted):
    _, out, csv, cal = fitted
    page = (out / "report.html").read_text()
    for text in (str(cal.resolve()), _sha(cal), str(csv.resolve()), _sha(csv)):
        assert text in page
    assert "OD 18 mm, ID 9 mm, H 6 mm" in page and "stated in rings.csv" in page
    assert "K 530 MPa" in page


def _fake_fit(m, curves, refined=(), law="tresca"):
    return RingFit(
        law=law, m=m, m_lower=m - 0.01, m_upper=m + 0.01, band_level=0.9, rmse=0.0,
        n_points=2, residuals=np.zeros(2), n_fe_runs=len(curves), curves=curves,
        refined=refined,
    )  # fmt: skip


def test_ring_fit_png_labels_agree_with_the_record_and_do_not_overlap():
    """The chart's m carries the console's digits; the run labels do not collide."""
    r = np.linspace(0.0, 0.52, 30)
    ms = (0.0, 0.15, 0.196, 0.2, 0.202, 0.3, 0.6, 1.0)  # a refinement run next to a grid run
    curves = {m: (r, -m * r + 0.3 * (1 - m) * r) for m in ms}
    chart = _fake_fit(0.1975, curves, refined=(0.196, 0.202))
    law = _fake_fit(0.35, curves, law="sbmf")
    test = ringfit.RingTest(
        np.array([0.2, 0.4]), np.array([0.0, 0.01]), "inner_diameter_change", ()
    )
    fig = ring_fit_figure(test, law, chart)
    ax = fig.axes[0]
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "Tresca chart's fit, m = 0.1975" in labels and "sbmf, m = 0.3500" in labels
    renderer = fig.canvas.get_renderer()
    texts = [t for t in ax.texts]
    names = [t.get_text() for t in texts]
    assert "0.196" not in names and "0.202" not in names  # the refinements are not labelled
    boxes = [t.get_window_extent(renderer) for t in texts]
    assert not any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1 :])
    assert {"0", "0.15", "1"} <= set(names)


# -- ring sheets as labs write them (issue 41, items 2 and 3) --------------------------------------
def _lab_sheet(path, d, header, *, sep=";", decimal=",", percent=True, remarks=True, comments=""):
    """The points as a lab's spreadsheet export: its header, percent, remarks, Excel's empty rows."""
    scale, digits = (100.0, 4) if percent else (1.0, 6)  # the digits of the documented file
    rows = [header]
    for i, (a, b) in enumerate(zip(RED, d, strict=True)):
        cells = [f"{scale * a:.{digits}f}", f"{scale * b:.{digits}f}"]
        rows.append(
            sep.join(
                [c.replace(".", decimal) for c in cells]
                + (["ok"] if remarks and i else [""] if remarks else [])
            )
        )
    rows += [sep * (2 if remarks else 1)] * 2  # Excel's trailing empty rows
    path.write_text(comments + "\n".join(rows) + "\n", encoding="utf-8")
    return path


LAB_HEADERS = [
    ("height reduction (%);inner-diameter change (%);remarks", True),
    ("Höhenabnahme [%];Innendurchmesseränderung [%];Bemerkung", True),
    ("height_reduction (%);inner_diameter_change (%);Kommentar", True),
    ("Stauchung in %;ID change in %;notes", True),
    ("Height Reduction;Inner Diameter Change;remarks", False),
    ("height_reduction_fraction;inner_diameter_change_fraction;remarks", False),
]


@pytest.mark.parametrize("header, percent", LAB_HEADERS)
def test_a_labs_sheet_reads_as_the_documented_format(tmp_path, points, header, percent):
    plain = ringfit.read_ring_tests([_write(tmp_path / "a.csv", points)])
    sheet = _lab_sheet(tmp_path / "lab.csv", points, header, percent=percent, comments=GEOMETRY)
    lab = ringfit.read_ring_tests([sheet])
    assert lab.column == plain.column == "inner_diameter_change"
    np.testing.assert_allclose(lab.reduction, plain.reduction, rtol=1e-15)
    np.testing.assert_allclose(lab.d_inner, plain.d_inner, rtol=1e-14)
    remarks = header.split(";")[2]
    n = RED.size + 2  # the comment line, the header, the data
    assert lab.notes[0] == (
        f"lab.csv: column(s) not read: {remarks!r} (line 2; the fit reads the height reduction "
        "and the inner_diameter_change column)"
    )
    assert lab.notes[-1] == f"lab.csv: 2 empty row(s) skipped (line(s) {n + 1}-{n + 2})"
    assert any("read in percent" in x for x in lab.notes) == percent


def test_the_documented_names_keep_working_and_need_no_note(tmp_path, points):
    t = ringfit.read_ring_tests([_write(tmp_path / "a.csv", points, header=GEOMETRY)])
    assert t.notes == () and t.reduction.size == RED.size


@pytest.mark.parametrize(
    "text, message",
    [
        ("", "no header line (the file is empty or holds only comments); accepted columns"),
        ("# geometry: OD = 18 mm, ID = 9 mm, H = 6 mm\n", "no header line"),
        (
            "# a\n# b\nhöhe;durchmesser\n20;1\n",
            "line 3: a height-reduction column is missing (header: 'höhe'; 'durchmesser'); "
            "accepted columns (any case, '_' or '-' for spaces): height reduction: "
            "height_reduction, height reduction",
        ),
        (
            "height reduction (mm);ID change (%)\n2;1\n",
            "line 1: column 'height reduction (mm)' has the unit 'mm'",
        ),
        # the line of the file (comment lines counted), and only the bad value quoted
        (
            "# one\n# two\n# three\nHöhenabnahme (%);Innendurchmesseränderung (%)\n30;0,2994\n"
            "40;n. b.\n",
            "line 6: inner-diameter change 'n. b.' in column 'Innendurchmesseränderung (%)' is "
            "not a number",
        ),
        (
            "# c\nheight reduction (%);ID change (%)\n30;1\n80;2\n",
            "line 4: height reduction 80 % is outside (0, 70] %",
        ),
        ("height reduction;ID change\n0.3;\n0.4;0.01\n", "line 2: no inner-diameter change"),
    ],
)
def test_messages_name_the_files_line_the_accepted_columns_and_only_the_bad_value(
    tmp_path, text, message
):
    path = tmp_path / "lab.csv"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ValueError) as err:
        ringfit.read_ring_tests([path])
    assert message in str(err.value)
    assert "0,2994" not in str(err.value)


def test_a_labs_sheet_gives_the_same_m_as_the_documented_format(fitted, tmp_path, capsys):
    """``ring-fit`` with a German sheet in percent, remarks and empty rows: the same m."""
    rc, out, csv, cal = fitted
    assert rc == 0
    want = json.loads((out / "ring_fit.json").read_text())
    points = np.array([float(r.split(";")[1].replace(",", ".")) for r in
                       csv.read_text(encoding="utf-8-sig").splitlines()[2:]])  # fmt: skip
    header = "Höhenabnahme [%];Innendurchmesseränderung [%];Bemerkung"
    sheet = _lab_sheet(tmp_path / "labor.csv", points, header, comments=GEOMETRY)
    lab_out = tmp_path / "lab"
    argv = ["ring-fit", "--measured", str(sheet), "--params", str(cal), *COARSE]
    assert main([*argv, "--no-progress", "--out", str(lab_out)]) == 0
    err = capsys.readouterr().err
    assert "fe-demo: note: labor.csv: column(s) not read: 'Bemerkung'" in err
    assert "fe-demo: note: labor.csv: 2 empty row(s) skipped" in err
    got = json.loads((lab_out / "ring_fit.json").read_text())
    for key in ("m", "m_lower", "m_upper", "m_tresca_chart"):
        assert got[key] == pytest.approx(want[key], abs=1e-9), key
    assert got["n_points"] == want["n_points"] == RED.size
    assert got["measured_notes"][0].startswith("labor.csv: column(s) not read")

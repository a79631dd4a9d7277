"""``halfspace-calib --flattening``: the block from the surfaces, beta fitted to a measurement.

Geometry helpers against closed forms (a sinusoid's RMS slope and crossings, counted patches),
beta recovered from curves of known beta, and the command's runs (grid 16: a few seconds).
"""

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest
from realfiles import real_file

import halfspace_calib.cli as cli
from frictionlaw import Flattening, FrictionParams, flattening_curve
from frictionlaw.flattening_curves import FlatteningPaths
from halfspace_calib.cli import main
from halfspace_calib.pipeline.sweep.flattening import (
    FlatteningData,
    check_data_pressures,
    crossing_half_spacing,
    fit_beta,
    patch_half_spacing,
    profile_slopes,
    read_flattening_data,
)
from halfspace_calib.topography.surface import Surface

DATA = Path(__file__).parent / "data" / "flattening_example.csv"
QUICK = ["--grid", "16", "--pressures", "1e8,2e8,3e8,5e8", "--reload-fractions", "0.3,0.6"]
H = 8e8
LAW = FrictionParams(m=0.5, sigma_y=H / 2.8, H=H, C1=1.05, n1=2.87, C2=7.44, n2=0.575)


# ----------------------------------------------------------------------------- geometry
def test_slope_and_crossings_of_a_sinusoid():
    """``h = a sin(2 pi x / lam)``: RMS slope ``2 pi a / (lam sqrt 2)`` (central differences:
    times ``sin(2 pi dx / lam) / (2 pi dx / lam)``), crossings every ``lam``: ``l = lam / 2``."""
    n, dx, lam, a = 256, 1e-6, 32e-6, 0.5e-6
    x = np.arange(n) * dx
    h = np.repeat((a * np.sin(2 * np.pi * x / lam))[:, None], 8, axis=1)
    s = Surface(h, dx, dx, periodic=True)
    k = 2 * np.pi * dx / lam
    sx, sy = profile_slopes(s)
    assert sx == pytest.approx(2 * np.pi * a / (lam * math.sqrt(2)) * math.sin(k) / k, rel=1e-12)
    assert sy == 0.0
    lx, ly = crossing_half_spacing(s)
    assert lx == pytest.approx(0.5 * (n - 1) * dx / (n // 32), rel=1e-12) and ly is None
    assert lx == pytest.approx(lam / 2, rel=0.01)


def test_patches_are_counted_once_across_the_period():
    p = np.zeros((40, 40))
    p[5:8, 5:8] = 1.0  # one inside
    p[0:3, 20:23] = p[-2:, 20:23] = 1.0  # one across the x edge
    p[20:22, 0:2] = p[20:22, -3:] = 1.0  # one across the y edge
    l_per, n_per = patch_half_spacing(p, 1e-6, 1e-6, periodic=True)
    assert n_per == 3 and l_per == pytest.approx(0.5 * math.sqrt(40 * 40 * 1e-12 / 3))
    assert patch_half_spacing(p, 1e-6, 1e-6, periodic=False)[1] == 5
    assert patch_half_spacing(np.zeros((4, 4)), 1e-6, 1e-6, periodic=False) == (None, 0)


# ----------------------------------------------------------------------------- the data
def test_the_example_file_reads():
    d = read_flattening_data(DATA)
    assert d.strain.size == 6 and np.all(d.p == 2.4e8) and d.alpha[-1] == 0.86


@pytest.mark.parametrize(
    "text, msg",
    [
        (
            "strain,alpha\n0.1,0.5\n",
            "must name the columns strain, alpha and p with its unit.*missing p,",
        ),
        (
            "strain,alpha,p_Pa,p_MPa\n0.1,0.5,1e8,100\n0.2,0.6,1e8,100\n",
            "line 1: the column p appears twice \\('p_Pa' and 'p_MPa'\\)",
        ),
        ("strain,alpha,p_Pa\n0.1,x,1e8\n0.2,0.5,1e8\n", "line 2, column alpha: not a number"),
        (
            "strain,alpha,p_Pa\n0.1,0.4\n0.2,1.2,1e8\n",
            "line 2, column p_Pa: empty",
        ),
        (
            "strain,alpha,p_Pa\n0.1,0.4,1e8\n0.2,1.2,1e8\n",
            "line 3, column alpha: 1.2 is not a contact fraction in \\[0, 1\\]$",
        ),
        ("eps,alpha,p\n0.1,0.5,1e5\n", "line 1: the pressure column 'p' gives no unit"),
        (
            "strain,alpha,p [bar]\n0.1,0.5,1e5\n",
            "'p \\[bar\\]': unknown unit 'bar'; p takes Pa, kPa",
        ),
        ("strain,alpha [ppm],p_Pa\n0.1,0.5,1e5\n", "unknown unit 'ppm'; alpha takes none, -, 1, %"),
        ("strain,alpha\n0.1,0.5\n", "found 'strain', 'alpha'; names read: strain: strain, eps"),
        ("strain,alpha,strain,p_Pa\n0.1,0.5,0.2,1e8\n", "line 1: the column strain appears twice"),
        ("strain,alpha,p_Pa\n0.1,35,1e8\n0.2,50,1e8\n", "looks like per cent: divide by 100"),
        (
            "strain,alpha,p_Pa\n0,1,0.3,1e8\n0.2,0.5,1e8\n",
            "line 2: 4 cells under a header of 3 columns \\(a decimal comma",
        ),
        (
            "strain,alpha,p_Pa\n-0.1,0.5,1e8\n0.2,0.5,1e8\n",
            "line 2, column strain: strain must be >= 0.*a thickness strain is negative",
        ),
        (
            "strain,alpha,p_Pa\n0,0.3,1e8\n5,0.4,1e8\n20,0.6,1e8\n",
            "line 4, column strain: 20 is above 2.*it looks like per cent: divide by 100",
        ),
        ("strain,alpha,p_Pa\n0.1,0.5,0\n0.2,0.5,1e8\n", "line 2, column p_Pa: must be > 0"),
        ("strain,alpha,p_Pa\n0.0,0.5,1e8\n0.2,0.5,1e8\n", "at least two rows with strain > 0"),
        ("strain,alpha,p_Pa\n0.1,nan,1e8\n0.2,0.5,1e8\n", "not finite"),
    ],
)
def test_bad_data_is_refused_naming_file_row_and_column(tmp_path, text, msg):
    f = tmp_path / "d.csv"
    f.write_text(text)
    with pytest.raises(ValueError, match=msg) as exc:
        read_flattening_data(f)
    assert str(exc.value).startswith(str(f))


def test_beta_is_recovered_with_a_band():
    """Points of the model with beta = 2.5 (two pressures): recovered exactly without noise, and
    within a band that holds it with noise of 0.01 in alpha."""
    P = LAW.replace(flattening=Flattening(slope=0.08, beta=2.5))
    eps = np.array([0.0, 0.002, 0.005, 0.01, 0.02, 0.0, 0.003, 0.006, 0.01, 0.015])
    p = np.r_[np.full(5, 0.1 * H), np.full(5, 0.25 * H)]
    alpha = flattening_curve(p, eps, P)
    assert alpha.max() < 0.95  # every point carries information on beta
    base = LAW.replace(flattening=Flattening(slope=0.08))
    fit = fit_beta(base, FlatteningData("model", eps, alpha, p))
    assert fit["beta"] == pytest.approx(2.5, rel=1e-6) and fit["rms"] < 1e-7
    noisy = alpha + np.random.default_rng(3).normal(0.0, 0.01, alpha.size)
    fit = fit_beta(base, FlatteningData("noisy", eps, np.clip(noisy, 0, 1), p))
    assert fit["band"][0] < 2.5 < fit["band"][1] and fit["band"][1] / fit["band"][0] < 2.0
    assert fit["level"] == 0.9 and fit["points"] == 10


def test_data_the_model_cannot_describe_is_refused():
    eps = np.array([0.05, 0.1, 0.2])
    p = np.full(3, 0.1 * H)
    base = LAW.replace(flattening=Flattening(slope=0.08))
    flat = flattening_curve(p, 0 * eps, base)  # no rise at all: beta -> 0
    with pytest.raises(ValueError, match="on the bound"):
        fit_beta(base, FlatteningData("flat", eps, flat, p))


@pytest.mark.parametrize(
    "text",
    [
        "\ufeffstrain,alpha,p_Pa\n0.0,0.3,2.4e8\n0.01,0.4,2.4e8\n0.02,0.46,2.4e8\n",  # Excel's BOM
        "# lab sheet\nstrain;alpha;p_Pa\n0.0;0.3;2.4e8\n0.01;0.4;2.4e8\n0.02;0.46;2.4e8\n",
        "strain\talpha\tp_Pa\n0.0\t0.3\t2.4e8\n0.01\t0.4\t2.4e8\n0.02\t0.46\t2.4e8\n",
        "p_MPa,strain,alpha\n240,0.0,0.3\n240,0.01,0.4\n240,0.02,0.46\n",
        "Strain, Alpha , P_MPa\n0.0,0.3,240\n0.01,0.4,240\n0.02,0.46,240\n",  # any case
        # Excel's German or French CSV: semicolons and decimal commas, a note with a comma
        "strain;alpha;p_MPa;note (sample, lot)\n0;0,3;240;a\n0,01;0,4;240;b\n0,02;0,46;240;\n",
    ],
)
def test_what_spreadsheets_write_reads_the_same(tmp_path, text):
    f = tmp_path / "d.csv"
    f.write_text(text, encoding="utf-8")
    d = read_flattening_data(f)
    assert np.array_equal(d.strain, [0.0, 0.01, 0.02]) and np.array_equal(d.alpha, [0.3, 0.4, 0.46])
    assert np.array_equal(d.p, [2.4e8] * 3)


@pytest.mark.parametrize(
    "head, scale",
    [
        ("strain,alpha [%],p_MPa", (1, 100, 1e-6)),
        ("strain [-],alpha [-],p [MPa]", (1, 1, 1e-6)),
        ("strain,alpha,p_kPa", (1, 1, 1e-3)),
        ("strain,\u03b1,p_MPa", (1, 1, 1e-6)),
        ("Dehnung;Traganteil in %;Druck [N/mm\u00b2]", (1, 100, 1e-6)),
        ("strain (%),alpha_%,p / Pa", (100, 100, 1)),
        ("Umformgrad\tKontaktflaechenanteil\tp_GPa", None),  # unknown alpha name: refused
    ],
)
def test_unit_bearing_headers_convert_to_fractions_and_pa(tmp_path, head, scale):
    """The same sheet with its unit in the header reads the same numbers (alpha 0.3-0.46 at
    240 MPa): per cent divided by 100, kPa, MPa and N/mm2 multiplied to Pa."""
    sep = ";" if ";" in head else "\t" if "\t" in head else ","
    rows = [(0.0, 0.3, 2.4e8), (0.01, 0.4, 2.4e8), (0.02, 0.46, 2.4e8)]
    f = tmp_path / "d.csv"
    if scale is None:
        f.write_text(head + "\n" + "\n".join(sep.join(map(str, r)) for r in rows) + "\n")
        with pytest.raises(ValueError, match="missing alpha"):
            read_flattening_data(f)
        return
    body = [sep.join(f"{v * k:.10g}" for v, k in zip(r, scale, strict=True)) for r in rows]
    f.write_text(head + "\n" + "\n".join(body) + "\n", encoding="utf-8")
    d = read_flattening_data(f)
    assert d.strain == pytest.approx([0.0, 0.01, 0.02], rel=1e-12)
    assert d.alpha == pytest.approx([0.3, 0.4, 0.46], rel=1e-12)
    assert d.p == pytest.approx([2.4e8] * 3, rel=1e-12)


@pytest.mark.parametrize("unit, pa", [("psi", 1.0), ("ksi", 1e3)])
def test_a_us_sheet_in_psi_or_ksi_reads_in_pa(tmp_path, unit, pa):
    """psi: a pound-force (0.45359237 kg x 9.80665 m/s^2) per square inch (0.0254 m), exact."""
    psi = 0.45359237 * 9.80665 / 0.0254**2
    f = tmp_path / "d.csv"
    p = 2.4e8 / (psi * pa)
    f.write_text(f"strain,alpha,p [{unit}]\n0,0.3,{p!r}\n0.01,0.4,{p!r}\n0.02,0.46,{p!r}\n")
    assert read_flattening_data(f).p == pytest.approx([2.4e8] * 3, rel=1e-12)


@pytest.mark.parametrize(
    "units, scale",
    [
        ("-;%;MPa", (1, 100, 1e-6)),  # lab software's second header row
        (";[%];(kPa)", (1, 100, 1e-3)),  # bracketed, the strain's cell empty
        ("[1];-;N/mm\u00b2", (1, 1, 1e-6)),  # "1" alone would be a number
    ],
)
def test_a_units_row_under_the_header_gives_the_units(tmp_path, units, scale):
    """``strain; alpha; p`` over a row of units reads as ``alpha [%]``, ``p [MPa]``: the same
    numbers (alpha 0.3-0.46 at 240 MPa), and the messages keep the file's own lines."""
    rows = [(0.0, 0.3, 2.4e8), (0.01, 0.4, 2.4e8), (0.02, 0.46, 2.4e8)]
    body = [
        ";".join(f"{v * k:.10g}".replace(".", ",") for v, k in zip(r, scale, strict=True))
        for r in rows
    ]
    f = tmp_path / "d.csv"
    f.write_text("strain;alpha;p\n" + units + "\n" + "\n".join(body) + "\n", encoding="utf-8")
    d = read_flattening_data(f)
    assert d.strain == pytest.approx([0.0, 0.01, 0.02], rel=1e-12)
    assert d.alpha == pytest.approx([0.3, 0.4, 0.46], rel=1e-12)
    assert d.p == pytest.approx([2.4e8] * 3, rel=1e-12) and d.lines == (3, 4, 5)


@pytest.mark.parametrize(
    "text, msg",
    [
        (
            "strain,alpha,p\n-,%,mm\n0,30,240\n",
            "line 2 \\(the units row\\), column 'p': unknown unit 'mm'",
        ),
        ("strain,alpha,p_kPa\n-,%,MPa\n0,30,240\n", "says 'kPa' and the units row 'MPa': keep one"),
        ("strain,alpha,p\n-,%,\n0,30,240\n", "the pressure column 'p' gives no unit"),
        (
            'strain,alpha,p_Pa\n0,0.3,"240,000,000"\n',
            "line 2, column p_Pa: not a number \\(thousands",
        ),
        (
            "strain;alpha;p_Pa\n0;0,3;240.000.000\n",
            "line 2, column p_Pa: not a number \\(thousands",
        ),
    ],
)
def test_a_bad_units_row_and_thousands_separators_are_refused_by_line(tmp_path, text, msg):
    f = tmp_path / "d.csv"
    f.write_text(text + "0.01,0.4,2.4e8\n")
    with pytest.raises(ValueError, match=msg):
        read_flattening_data(f)


def test_an_engineering_strain_column_is_refused_with_the_conversion(tmp_path):
    """The law's strain is a true strain: e = 0.0202 engineering is eps = ln(1.0202) = 0.02."""
    f = tmp_path / "d.csv"
    f.write_text("engineering strain,alpha,p_MPa\n0,0.3,240\n0.0101,0.4,240\n0.0202,0.46,240\n")
    with pytest.raises(ValueError, match="true \\(logarithmic\\) strain.*ln\\(1 \\+ e\\)"):
        read_flattening_data(f)
    assert math.log(1.0202) == pytest.approx(0.02, abs=2e-4)  # the conversion the message asks


def test_a_code_page_sheet_is_refused_saying_save_as_csv_utf8(tmp_path):
    """German Excel's "CSV (Trennzeichen-getrennt)" writes Windows-1252: refused naming the line
    of the first byte that is no UTF-8, as the ring-test reader refuses it."""
    f = tmp_path / "d.csv"
    text = "strain;alpha;p_MPa\n# Prüfling DC04\n0,0;0,3;240\n0,01;0,4;240\n0,02;0,5;240\n"
    f.write_bytes(text.encode("cp1252"))
    with pytest.raises(ValueError, match='line 2: not UTF-8 text.*save the sheet as "CSV UTF-8"'):
        read_flattening_data(f)
    f.write_text(text, encoding="utf-8")  # saved as CSV UTF-8: read
    assert read_flattening_data(f).alpha[-1] == 0.5


def test_messages_name_the_files_own_line(tmp_path):
    f = tmp_path / "d.csv"
    f.write_text("# lab sheet\n\n# DC04\nstrain,alpha,p_Pa\n0.1,0.2,1e8\n0.2,x,1e8\n")
    with pytest.raises(ValueError, match="line 6, column alpha: not a number"):
        read_flattening_data(f)


def test_pressures_in_mpa_under_p_pa_are_refused():
    d = FlatteningData(
        "lab.csv", np.array([0.0, 0.1, 0.2]), np.array([0.2, 0.4, 0.6]), np.full(3, 240.0)
    )
    with pytest.raises(ValueError, match="pressures in MPa under p_Pa\\? Name the column p_MPa"):
        check_data_pressures(d, 8e8)
    check_data_pressures(FlatteningData("ok", d.strain, d.alpha, np.full(3, 2.4e8)), 8e8)
    with pytest.raises(ValueError, match="at or above the hardness H = 8e.08 Pa"):
        check_data_pressures(FlatteningData("hi", d.strain, d.alpha, np.full(3, 9e8)), 8e8)
    # one typo among the rows (MPa in a p_Pa file): its point would dominate the fit
    one = FlatteningData(
        "lab.csv", d.strain, d.alpha, np.array([2.4e8, 2.4e8, 1e3]), lines=(5, 6, 7)
    )
    with pytest.raises(ValueError, match="lab.csv: line 7, pressure 1000 Pa is below 1e-4 H"):
        check_data_pressures(one, 8e8)


# ----------------------------------------------------------------------------- the command
@pytest.fixture(scope="module")
def run(tmp_path_factory):
    out = tmp_path_factory.mktemp("flat") / "o"
    code = main([*QUICK, "--flattening", "--no-progress", "--out", str(out)])
    return code, out


def test_the_command_writes_the_block(run, capsys):
    code, out = run
    assert code == 0
    doc = json.loads((out / "params.json").read_text())
    assert doc["version"] == 3 and doc["flattening"]["beta"] == 1.0
    rec = doc["provenance"]["flattening"]
    assert rec["slope"] == doc["flattening"]["slope"] > 0
    assert rec["slope"] == pytest.approx(
        math.sqrt(0.5 * (rec["slope_x"] ** 2 + rec["slope_y"] ** 2))
    )
    P = FrictionParams.from_json(out / "params.json")
    t = rec["table"]
    for key, alphas in t["alpha_at_p_over_H"].items():
        f = float(key[:-1])
        assert alphas == pytest.approx(flattening_curve(f * P.H, t["strains"], P).tolist(), abs=0)
        assert alphas[0] == pytest.approx(float(flattening_curve(f * P.H, 0.0, P)), abs=0)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["flattening"] == rec
    html = (out / "report.html").read_text()
    assert "Flattening under bulk strain" in html and 'data-key="flattening.slope"' in html
    shown = re.findall(r'data-key="(flattening\.[^"]+)">([^<]*)<', html)
    assert len(shown) == 10 and all(v not in ("", "-") for _, v in shown), shown
    full = rec["full_contact"]["strain"]
    assert flattening_curve(0.3 * P.H, [0.99 * full, 1.01 * full], P).tolist()[1] == 1.0
    assert (out / "flattening.csv").is_file() and (out / "flattening.png").is_file()


def test_without_the_option_nothing_changes(tmp_path):
    assert main([*QUICK, "--no-progress", "--out", str(tmp_path / "o")]) == 0
    doc = json.loads((tmp_path / "o" / "params.json").read_text())
    # the version the law's forms need (3 for the tabulated first loading), not the flattening's
    assert "flattening" not in doc and "first_loading_law" in doc and doc["version"] == 3
    P = FrictionParams.from_dict(doc)
    assert P.replace(first_loading_form="eq24", first_loading_table=None).to_dict()["version"] == 2
    assert json.loads((tmp_path / "o" / "summary.json").read_text())["flattening"] is None
    assert not (tmp_path / "o" / "flattening.csv").exists()


def test_the_command_fits_beta_to_a_measurement(tmp_path, capsys):
    out = tmp_path / "o"
    assert main([*QUICK, "--flattening-data", str(DATA), "--no-progress", "--out", str(out)]) == 0
    doc = json.loads((out / "params.json").read_text())
    f = doc["flattening"]
    assert f["beta_band"][0] < f["beta"] < f["beta_band"][1] and f["band_level"] == 0.9
    fit = doc["provenance"]["flattening"]["fit"]
    assert fit["file"] == str(DATA) and fit["points"] == 6
    said = capsys.readouterr().out
    assert f"beta = {f['beta']:.4g} [" in said and "fitted to 6 measured points" in said


def test_the_command_fits_beta_with_the_sheets_flow_curve(tmp_path, capsys):
    """--flow-curve: the fit integrates each point along the sheet's curve; the record keeps the
    curve (rebuilt, it gives the fit's own misfit), the console says to pass the modulus."""
    from frictionlaw.flow_curve import flow_curve_from_dict

    out = tmp_path / "o"
    argv = [*QUICK, "--flattening-data", str(DATA), "--flow-curve", "swift:530e6,0.006,0.24"]
    assert main([*argv, "--no-progress", "--out", str(out)]) == 0
    doc = json.loads((out / "params.json").read_text())
    fit = doc["provenance"]["flattening"]["fit"]
    assert fit["flow_curve"] == "Swift: K 530 MPa, eps0 0.006, n 0.24"
    P = FrictionParams.from_dict(doc)
    fc = flow_curve_from_dict(fit["flow_curve_record"])
    a = FlatteningPaths(np.array(fit["p_Pa"]), np.array(fit["strain"]), P, fc).alpha()
    r = a - np.array(fit["alpha"])
    assert np.sqrt(np.mean(r * r)) == pytest.approx(fit["rms"], rel=1e-9)
    said = capsys.readouterr()
    assert "fitted with the sheet's flow curve (Swift" in said.out
    assert "pass the bulk's flow stress and hardening modulus" in said.out
    # the example's sheet (sigma_y 285.7 MPa) is not DC04's (155 MPa): said on stderr
    assert "the flow curve's initial flow stress 155.3 MPa is 0.543 times" in said.err


def test_bad_flow_curves_are_refused_before_any_sweep(tmp_path, capsys, monkeypatch):
    def no_run(*a, **k):
        raise AssertionError("a calibration started")

    monkeypatch.setattr(cli, "calibrate", no_run)
    o = ["--out", str(tmp_path / "o")]
    assert main([*QUICK, "--flattening", "--flow-curve", "swift:530e6,0.006,0.24", *o]) == 2
    assert "give the measurement too" in capsys.readouterr().err
    data = ["--flattening-data", str(DATA)]
    assert main([*QUICK, *data, "--flow-curve", "swift:530,0.006,0.24", *o]) == 2
    assert "K (Pa) must be in [1000, 1e+13]" in capsys.readouterr().err
    short = tmp_path / "short.csv"
    short.write_text("strain,sigma_y_MPa\n0,155\n0.01,200\n")
    assert main([*QUICK, *data, "--flow-curve", str(short), *o]) == 2
    assert "--flow-curve ends at strain 0.01; " in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


def test_bad_input_is_refused_before_any_sweep(tmp_path, capsys, monkeypatch):
    def no_run(*a, **k):
        raise AssertionError("a calibration started")

    monkeypatch.setattr(cli, "calibrate", no_run)
    bad = tmp_path / "bad.csv"
    bad.write_text("strain,alpha\n0.1,0.5\n")
    assert main([*QUICK, "--flattening-data", str(bad), "--out", str(tmp_path / "o")]) == 2
    assert "must name the columns" in capsys.readouterr().err
    mpa = tmp_path / "mpa.csv"  # pressures in MPa under p_Pa: refused before the sweep too
    mpa.write_text("strain,alpha,p_Pa\n0.0,0.3,240\n0.05,0.5,240\n0.1,0.6,240\n")
    assert main([*QUICK, "--flattening-data", str(mpa), "--out", str(tmp_path / "o")]) == 2
    assert "Name the column p_MPa" in capsys.readouterr().err
    argv = [*QUICK, "--patches", "2", "--flattening", "--out", str(tmp_path / "o")]
    assert main(argv) == 2
    assert "--flattening derives the block from one workpiece/tool pair" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize(
    "extra, said",
    [
        # argparse would keep the last and drop A without a word
        (["--flattening-data", "A", "--flattening-data", "B"], "argument --flattening-data: given "
         "more than once ('A', then 'B')"),
        (["--flattening-data", ""], "argument --flattening-data: an empty value"),
        (["--flattening-data", "  "], "argument --flattening-data: an empty value"),
        # the other single-valued options of the command are refused alike
        (["--grid", "32"], "argument --grid: given more than once (16, then 32)"),
        (["--flow-curve", "swift:5e8,0.006,0.2", "--flow-curve", "swift:5e8,0.006,0.3"],
         "argument --flow-curve: given more than once"),
        (["--workpiece", "a", "b", "--workpiece", "c"], "argument --workpiece: given more than once"),
        (["--scene", ""], "argument --scene: an empty value"),  # was: no scene, a default run
        (["--after-contact", ""], "argument --after-contact: an empty value"),
    ],
)  # fmt: skip
def test_a_repeated_or_empty_option_is_refused_naming_it(
    tmp_path, capsys, monkeypatch, extra, said
):
    monkeypatch.setattr(cli, "calibrate", lambda *a, **k: pytest.fail("a calibration started"))
    assert main([*QUICK, *extra, "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert said in err and "Traceback" not in err
    assert not (tmp_path / "o").exists()


def test_a_missing_measurement_is_named_with_its_option(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(cli, "calibrate", lambda *a, **k: pytest.fail("a calibration started"))
    gone = tmp_path / "gone.csv"
    assert main([*QUICK, "--flattening-data", str(gone), "--out", str(tmp_path / "o")]) == 2
    assert f"--flattening-data {gone}: no such file" in capsys.readouterr().err
    assert main([*QUICK, "--flattening-data", str(tmp_path), "--out", str(tmp_path / "o")]) == 2
    assert f"--flattening-data {tmp_path}: a folder, not a CSV file" in capsys.readouterr().err


def test_a_measurement_the_model_cannot_describe_fails_the_run(tmp_path, capsys):
    """Contact fractions below the calibrated first loading at every strain: beta would have to
    vanish; the run fails (exit 1) and keeps its parameters as params.failed.json, saying why."""
    data = tmp_path / "d.csv"
    data.write_text("strain,alpha,p_Pa\n0.05,0.0,2e8\n0.1,0.0,2e8\n0.2,0.0,2e8\n")
    out = tmp_path / "o"
    assert main([*QUICK, "--flattening-data", str(data), "--no-progress", "--out", str(out)]) == 1
    err = capsys.readouterr().err
    assert "flattening: the fit of beta" in err and "on the bound" in err
    doc = json.loads((out / "params.failed.json").read_text())
    assert any("fit of beta" in p for p in doc["provenance"]["run"]["problems"])
    assert not (out / "params.json").exists()


def test_a_polished_real_scan_calibrates(tmp_path):
    """The MetroPro scan, smooth on the solver's grid (RMS profile slope about 1e-4): the block is
    written (this once failed the run after the whole calibration) and bulk strain flattens it to
    full contact at strains of the order of its slope."""
    out = tmp_path / "o"
    argv = [*QUICK[:2], "--workpiece", str(real_file("metropro-1.dat")), "--flattening"]
    assert main([*argv, "--no-resolution-check", "--no-progress", "--out", str(out)]) == 0
    P = FrictionParams.from_json(out / "params.json")
    slope = P.flattening.slope
    assert 1e-5 < slope < 1e-3
    a = flattening_curve(0.1 * P.H, [0.0, 0.1 * slope, 10 * slope], P)
    assert a[0] < a[1] < 1.0 and a[2] == 1.0


def test_a_beta_far_from_one_and_a_poor_fit_are_noted():
    """Strains in per cent under 2 (a model that reaches full contact within 2 % strain): beta
    comes out 100 times too small; the fit says so in its notes (the command prints them on
    stderr). A band that reaches the range's bound fails the fit."""
    P = LAW.replace(flattening=Flattening(slope=0.05))
    eps, p = np.array([0.0, 0.005, 0.01, 0.015, 0.02]), np.full(5, 0.3 * H)
    a = flattening_curve(p, eps, P.replace(flattening=Flattening(slope=0.05, beta=0.3)))
    a = a + np.array([0.0, 0.01, -0.01, 0.01, -0.01])
    fit = fit_beta(P, FlatteningData("pct.csv", 100 * eps, a, p))
    assert fit["beta"] == pytest.approx(0.003, rel=0.05)
    assert any("per cent gives 100 times too small" in n for n in fit["notes"])
    assert fit_beta(P, FlatteningData("ok.csv", eps, a, p))["notes"] == []
    wide = FlatteningData(
        "few.csv", np.array([0.0, 0.001, 0.002]), np.array([0.3, 0.9, 0.2]), p[:3]
    )
    with pytest.raises(ValueError, match="band reaches the bound|on the bound"):
        fit_beta(P, wide)

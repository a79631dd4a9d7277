"""One flattening curve per distinct pressure (frictionlaw.flattening_curves) and large lab sheets.

The tables against the per-point solve of ``flattening_curve`` (the old fit's model, to
rounding); the paths along a flow curve against the per-point midpoint steps refined (closer to
the converged curve than the 32 steps the fit took before); the fit of ``beta`` against the old
per-row path; a 20 000-row sheet through the command (grid 16) and what ``params.json`` keeps of
it; a parameter file written before the fit's record had a version.
"""

import hashlib
import json
import math
from pathlib import Path

import numpy as np
import pytest

from frictionlaw import Flattening, FrictionParams, alpha_first, flattening_curve
from frictionlaw._flattening_j import _j_integrand
from frictionlaw.first_loading import FirstLoadingTable
from frictionlaw.flattening import _coeffs, _kinks, _p_cap, equivalent_strain
from frictionlaw.flattening_curves import FlatteningCurves, FlatteningPaths
from frictionlaw.flow_curve import SwiftCurve, TabulatedCurve
from halfspace_calib.cli import main
from halfspace_calib.pipeline.sweep.flattening import (
    ROWS_KEPT,
    FlatteningData,
    _fit,
    fit_beta,
    read_flattening_data,
)

H = 8e8
EQ24 = FrictionParams(m=0.5, sigma_y=H / 2.8, H=H, C1=1.05, n1=2.87, C2=7.44, n2=0.575)
TABLE = FirstLoadingTable(
    p=(2e7, 5e7, 1e8, 2e8, 3e8, 4e8, 6e8, 7.6e8),
    alpha=(0.026, 0.064, 0.127, 0.25, 0.37, 0.48, 0.66, 0.79),
)
TAB = EQ24.replace(first_loading_form="tabulated", first_loading_table=TABLE)
DC04 = SwiftCurve(530e6, 0.006, 0.24)
QUICK = ["--grid", "16", "--pressures", "1e8,2e8,3e8,5e8", "--reload-fractions", "0.3,0.6"]
V1 = Path(__file__).parent / "data" / "flattening_fit_v1_params.json"


def law(base, slope=0.08, beta=1.0):
    return base.replace(flattening=Flattening(slope=slope, beta=beta))


# ----------------------------------------------------------------------------- the tables
@pytest.mark.parametrize("base", [EQ24, TAB], ids=["eq24", "tabulated"])
def test_the_table_gives_the_per_point_solve_to_rounding(base):
    """Pressures from below the flattening floor to the cap, strains from 0 to full contact:
    the table's contact fraction is flattening_curve's, point by point, to 1e-11 (the per-point
    J's own quadrature error; 1e-13 typical), at the block's beta and at another one."""
    P = law(base, beta=2.5)
    rng = np.random.default_rng(0)
    levels = np.array([1e-13, 1e-4, 0.01, 0.05, 0.1, 0.25, 0.4, 0.6, 0.9, 0.99, 5.0]) * H
    p = np.repeat(levels, 24)
    eps = np.tile(np.r_[0.0, 1e-12, 1e-7, 0.3, rng.uniform(0.0, 0.05, 20)], levels.size)
    curves = FlatteningCurves(p, P)
    assert curves.pressures == 9  # below 1e-12 H and at the cap nothing flattens
    got = curves.alpha(eps)
    assert np.abs(got - flattening_curve(p, eps, P)).max() < 1e-11
    assert np.all(got[eps == 0] == flattening_curve(p[eps == 0], 0.0, P))  # exactly alpha1
    other = flattening_curve(p, eps, law(base, beta=0.4))
    assert np.abs(curves.alpha(eps, beta=0.4) - other).max() < 1e-11
    assert np.all(got <= 1.0) and np.all(got[(eps == 0.3) & (p > 1e-12 * H)] == 1.0)


def test_a_tabulated_alpha1_is_split_where_it_saturates():
    """The top level's power law reaches 1 between the levels and the cap: J to full contact
    against SciPy's adaptive quadrature with every kink given (1e-9; it was 2.5 % short before
    the NumPy J split there, as the kernels do)."""
    from scipy.integrate import quad

    P = law(TAB)
    coeffs = _coeffs(P)
    cap = _p_cap(P, coeffs)
    kinks = _kinks(P, cap) * H
    k = TABLE.knots(H)
    top = H * math.exp(k["u"][-1] - k["v"][-1] / k["d"][-1])
    assert 7.6e8 < top < cap and np.any(np.isclose(kinks, top, rtol=1e-15))
    for ph in (0.05, 0.25, 0.6):
        p = ph * H
        g = np.array([p / (2 * P.k)])

        def f(v, ph=ph, g=g):
            return float(
                _j_integrand(
                    np.array([ph]), np.array([[v]]), coeffs, H, g, 0.08, np.array([np.inf])
                )[0, 0]
            )

        ucap = math.acosh(cap / p)
        pts = [math.acosh(t / p) for t in kinks if p < t < cap]
        J = quad(f, 0.0, ucap, points=pts, limit=400, epsabs=0, epsrel=1e-13)[0] * ph**3
        eq = float(equivalent_strain(p, cap, P))
        kappa = 0.08 * H / (math.sqrt(3) / 2 * 2 * P.k)
        assert eq == pytest.approx(kappa * J / ph, rel=1e-9)


def test_bad_input_is_refused_naming_it():
    P = law(EQ24)
    with pytest.raises(ValueError, match="p must be finite and > 0"):
        FlatteningCurves([1e8, 0.0], P)
    c = FlatteningCurves([1e8, 2e8], P)
    with pytest.raises(ValueError, match="strains must be finite and >= 0"):
        c.alpha([0.01, -0.01])
    with pytest.raises(ValueError, match="beta must be a finite number > 0"):
        c.alpha(0.01, beta=0.0)
    with pytest.raises(ValueError, match="no flattening block"):
        FlatteningCurves([1e8], EQ24)
    with pytest.raises(ValueError, match=r"steps must be an integer in \[1, 100000\]"):
        FlatteningPaths([1e8], [0.01], P, DC04, steps=0)
    with pytest.raises(ValueError, match="beyond the flow curve's last strain 0.1"):
        FlatteningPaths([1e8], [0.2], P, TabulatedCurve((0.0, 0.1), (2e8, 3e8)))
    with pytest.raises(ValueError, match="beta must be finite and > 0"):
        FlatteningPaths([1e8], [0.01], P, DC04).alpha([1.0, -1.0])


# ----------------------------------------------------------------------------- the paths
def test_the_paths_approach_the_converged_per_point_curve():
    """Along DC04's curve: the paths (256 graded steps a pressure) against the per-point midpoint
    rule refined to 128 steps (within 1e-6 of converged): within 1e-5 at the worst point (where
    the hardening's limit of the lattice lets go within a step), no worse than the 32 steps a
    point the fit took before; zero strain is alpha1 exactly."""
    P = law(EQ24)
    p = np.repeat(np.array([0.05, 0.25, 0.4]) * H, 5)
    eps = np.tile([0.0, 0.0052, 0.0288, 0.0624, 0.1024], 3)
    paths = FlatteningPaths(p, eps, P, DC04)
    got = paths.alpha()
    ref = flattening_curve(p, eps, P, flow_curve=DC04, steps=128)
    old = flattening_curve(p, eps, P, flow_curve=DC04, steps=32)
    assert np.abs(got - ref).max() < 1e-5
    assert np.abs(got - ref).max() <= np.abs(old - ref).max()
    assert np.all(got[eps == 0] == flattening_curve(p[eps == 0], 0.0, P))
    # several beta side by side: each as its own path (to the last bits of the sums' order)
    many = paths.alpha(np.array([0.5, 1.0, 3.0]))
    assert np.abs(many[1] - got).max() < 1e-15
    alone = FlatteningPaths(p, eps, law(EQ24, beta=3.0), DC04).alpha()
    assert np.abs(many[2] - alone).max() < 1e-15 and np.all(many[0] <= got)


def test_the_paths_end_steps_at_a_tabulated_curves_points():
    """A tabulated flow curve's modulus jumps at its points; the paths step to them and converge
    at second order (256 steps within 1e-6 of 1024), where per-point midpoint steps straddle the
    jumps (first order: 64 steps miss by more than 1e-4)."""
    P = law(EQ24)
    tc = TabulatedCurve((0.0, 0.004, 0.01, 0.03, 0.1), (160e6, 200e6, 225e6, 260e6, 300e6))
    p, eps = np.full(6, 0.25 * H), np.array([0.002, 0.005, 0.009, 0.012, 0.02, 0.03])
    fine = FlatteningPaths(p, eps, P, tc, steps=1024).alpha()
    assert np.abs(FlatteningPaths(p, eps, P, tc).alpha() - fine).max() < 1e-6
    assert np.abs(flattening_curve(p, eps, P, flow_curve=tc, steps=64) - fine).max() > 1e-4


def test_the_paths_hold_the_sinking_a_stiff_hardening_holds():
    """Eq. F2d along the paths: a table of two stiff segments (moduli 2 and 1 GPa) holds the
    fraction at ``alpha1(p) + 3 p / (4 h tan(theta))`` until the modulus falls at the knot; the
    paths (which end a step there) as the per-point rule with the knot at a step end."""
    P = law(EQ24)
    tc = TabulatedCurve((0.0, 0.1, 0.4), (P.sigma_y, P.sigma_y + 2e8, P.sigma_y + 5e8))
    p, eps = np.full(6, 0.05 * H), np.array([0.02, 0.05, 0.1, 0.105, 0.2, 0.3])
    got = FlatteningPaths(p, eps, P, tc).alpha()
    ref = flattening_curve(p, eps, P, flow_curve=tc, steps=630)
    a0, k = float(alpha_first(0.05 * H, P)), 0.75 * 0.05 * H / P.flattening.slope
    held = np.array([a0 + k / 2e9] * 3 + [math.nan] + [a0 + k / 1e9] * 2)
    assert np.all(held[~np.isnan(held)] < 1.0) and ref[3] > held[2] + 0.01
    assert np.allclose(ref[[1, 2, 4, 5]], held[[1, 2, 4, 5]], rtol=0, atol=1e-12)
    assert np.abs(got - ref).max() < 1e-5


# ----------------------------------------------------------------------------- the fit
def _sheet(P, n, pressures, seed, flow_curve=None, noise=0.01):
    rng = np.random.default_rng(seed)
    p = np.asarray(pressures, dtype=float)[np.arange(n) % len(pressures)]
    eps = rng.uniform(0.0, 0.02, n)
    if flow_curve is None:  # the table for many rows: it is the per-point solve (above)
        a = flattening_curve(p, eps, P) if n <= 100 else FlatteningCurves(p, P).alpha(eps)
    else:
        a = FlatteningPaths(p, eps, P, flow_curve).alpha()
    alpha = np.clip(a + rng.normal(0.0, noise, n), 0.0, 1.0)
    return FlatteningData("lab.csv", eps, alpha, p, flow_curve=flow_curve)


@pytest.mark.parametrize("base", [EQ24, TAB], ids=["eq24", "tabulated"])
def test_the_fit_equals_the_per_row_path(base):
    """beta, its band and the misfit as the per-row model gave them (flattening_curve at every
    row for every trial beta, the same search): to 1e-9 relative (measured: 1e-12)."""
    made = law(base, beta=2.5)
    data = _sheet(made, 40, [0.1 * H, 0.25 * H, 0.4 * H], seed=2)
    start = law(base)
    new = fit_beta(start, data)

    def per_row(ln_beta):
        return np.stack(
            [flattening_curve(data.p, math.exp(b) * data.strain, start) for b in ln_beta]
        )

    old = _fit(per_row, data, 0.9)
    for key in ("beta", "rms", "max_abs"):
        assert new[key] == pytest.approx(old[key], rel=1e-9), key
    assert new["band"] == pytest.approx(old["band"], rel=1e-9)
    assert new["band"][0] < 2.5 < new["band"][1]


def test_a_sheet_with_every_row_at_its_own_pressure():
    """A continuous log: 3000 rows, 3000 pressures (one table each): beta recovered in its band,
    and the record lists no pressures (a summary in bins instead)."""
    made = law(EQ24, beta=0.6)
    rng = np.random.default_rng(4)
    p = rng.uniform(0.05, 0.6, 3000) * H
    data = _sheet(made, 3000, p, seed=5, noise=0.005)
    fit = fit_beta(law(EQ24), data)
    assert fit["band"][0] < 0.6 < fit["band"][1] and fit["band"][1] / fit["band"][0] < 1.01
    assert fit["pressures_Pa"] is None and "strain" not in fit
    d = fit["data"]
    assert d["pressures"] == 3000 and d["rows"] == 3000 and not d["rows_kept"]
    assert [b["rows"] for b in d["residuals_by_pressure"]] == [375] * 8
    assert d["p_Pa"] == [p.min(), p.max()]


# ----------------------------------------------------------------------------- the command
def _write_sheet(path, n, seed):
    """A continuous in-situ log: strain rising, the pressure drifting around 240 MPa (every row
    its own pressure), alpha from the law at beta = 0.8 on a slope of 0.049 plus noise."""
    rng = np.random.default_rng(seed)
    eps = np.sort(rng.uniform(0.0, 0.03, n))
    p = 2.4e8 * (1.0 + 0.05 * np.sin(np.linspace(0.0, 40.0, n))) + rng.normal(0.0, 1e5, n)
    P = law(EQ24, slope=0.049, beta=0.8)
    a = np.clip(FlatteningCurves(p, P).alpha(eps) + rng.normal(0.0, 0.01, n), 0.0, 1.0)
    lines = ["# a continuous in-situ log", "strain,alpha,p_MPa"]
    lines += [f"{e:.6g},{x:.5f},{q / 1e6:.5f}" for e, x, q in zip(eps, a, p, strict=True)]
    path.write_text("\n".join(lines) + "\n")


def test_a_20000_row_sheet_through_the_command(tmp_path, capsys):
    """The command fits a 20 000-row sheet at 20 000 pressures and keeps its digest, ranges and
    residuals in params.json, not its rows: the file stays the size of a small sheet's."""
    sheet = tmp_path / "log.csv"
    _write_sheet(sheet, 20_000, seed=6)
    out = tmp_path / "o"
    assert main([*QUICK, "--flattening-data", str(sheet), "--no-progress", "--out", str(out)]) == 0
    raw = (out / "params.json").read_text()
    doc = json.loads(raw)
    fit = doc["provenance"]["flattening"]["fit"]
    assert fit["record_version"] == 2 and fit["points"] == 20_000
    assert not {"strain", "alpha", "p_Pa"} & set(fit) and fit["pressures_Pa"] is None
    d = fit["data"]
    assert d["sha256"] == hashlib.sha256(sheet.read_bytes()).hexdigest()
    assert d["size_bytes"] == sheet.stat().st_size and d["rows"] == 20_000
    assert d["pressures"] == len(np.unique(read_flattening_data(sheet).p)) > 19_000
    assert d["rows_kept"] is False and d["rows_kept_up_to"] == ROWS_KEPT
    assert sum(b["rows"] for b in d["residuals_by_strain"]) == 20_000
    assert math.sqrt(sum(b["rows"] * b["rms"] ** 2 for b in d["residuals_by_strain"]) / 20_000) == (
        pytest.approx(fit["rms"], rel=1e-12)
    )
    assert len(raw) < 30_000  # the rows alone would be about 700 kB
    f = doc["flattening"]
    assert f["beta_band"][0] < f["beta"] < f["beta_band"][1]
    said = capsys.readouterr().out
    assert f"20000 rows at {d['pressures']} pressures, sha256 {d['sha256']}" in said
    assert "not its rows (kept up to 1000)" in said
    html = (out / "report.html").read_text()
    assert d["sha256"] in html and (out / "flattening.png").is_file()
    # the record alone (a later reader, without the file): the fit's curves over its strains
    from matplotlib.figure import Figure

    from halfspace_calib.output.flattening import MAX_FIT_LINES, _plot_measurement

    ax = Figure().subplots()
    _plot_measurement(ax, FrictionParams.from_dict(doc), fit, None)
    lines = ax.get_lines()
    # the record lists no pressures beyond 64: the fit at the lowest and the highest
    assert len(lines) == 2 < MAX_FIT_LINES and lines[0].get_xdata()[-1] == d["strain"][1]


def test_a_small_sheet_keeps_its_rows(tmp_path):
    """Up to ROWS_KEPT rows stay in the record, as before, beside the summary."""
    sheet = tmp_path / "lab.csv"
    _write_sheet(sheet, 300, seed=7)
    out = tmp_path / "o"
    assert main([*QUICK, "--flattening-data", str(sheet), "--no-progress", "--out", str(out)]) == 0
    fit = json.loads((out / "params.json").read_text())["provenance"]["flattening"]["fit"]
    data = read_flattening_data(sheet)
    assert fit["strain"] == data.strain.tolist() and fit["p_Pa"] == data.p.tolist()
    assert fit["data"]["rows_kept"] is True and fit["data"]["rows"] == 300
    assert fit["data"]["pressures"] == len(np.unique(data.p)) > 64 and fit["pressures_Pa"] is None


# ----------------------------------------------------------------------------- old files
def test_a_file_written_before_the_record_version_loads_and_reads(tmp_path):
    """The parameter file of commit d6a01f4 (every row in the record, no record_version): it
    loads, beta's provenance reads, and the report's plot and section read its record."""
    from matplotlib.figure import Figure

    from frictionlaw.flattening import beta_absorbs_hardening
    from halfspace_calib.output.flattening import _plot_measurement, flattening_section

    P = FrictionParams.from_json(V1)
    doc = json.loads(V1.read_text())
    fit = doc["provenance"]["flattening"]["fit"]
    assert "record_version" not in fit and len(fit["strain"]) == 6
    assert P.flattening.beta == fit["beta"] and P.flattening.beta_band == tuple(fit["band"])
    assert not beta_absorbs_hardening(P)  # fitted with the sheet's flow curve
    ax = Figure().subplots()
    _plot_measurement(ax, P, fit, None)
    labels = [ln.get_label() for ln in ax.get_lines()]
    assert labels[0] == "measured (beta fitted to it)" and len(ax.get_lines()) == 2
    assert np.array_equal(ax.get_lines()[0].get_xdata(), fit["strain"])
    section = flattening_section({"flattening": doc["provenance"]["flattening"]}, tmp_path)
    assert "beta fitted to 6 points of tests/data/flattening_example.csv" in section
    assert "sha256" not in section  # version 1 has no digest: nothing is made up

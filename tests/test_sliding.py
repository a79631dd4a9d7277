"""Sliding study (Sec. 3.3): conservation, limits, agreement with a plain solve, bad input."""

import csv

import numpy as np
import pytest
from plotcheck import assert_png_drawn, lines

from halfspace_calib import topography as S
from halfspace_calib.contact.materials import Materials, SolverSettings
from halfspace_calib.contact.normal import composite_modulus, solve_normal_pair
from halfspace_calib.output.sliding import plot_sliding, write_sliding_outputs
from halfspace_calib.studies.sliding import (
    adhesive_work,
    deformation_work,
    sliding_surfaces,
    sliding_sweep,
    sliding_workpiece,
)
from halfspace_calib.studies.sliding_study import SlidingStudy, sliding_study

E_STAR = composite_modulus(210e9, 0.3, 210e9, 0.3)
H = 800e6
SIGMA_Y = H / 2.8
MAT = Materials(H=H, m=0.5)  # Table 1: E_star = E_STAR
DX = 6.33e-3 / 384  # the paper's element size, 16.5 um


@pytest.fixture(scope="module")
def small():
    """Default-like case at the paper's element size: 48 x 24 strip under a 24 x 24 tool."""
    wp = sliding_workpiece(shape=(48, 24), size=(48 * DX, 24 * DX), seed=3)
    tl = S.tool_like(24, size=24 * DX, seed=4)
    return wp, tl


@pytest.fixture(scope="module")
def sweep_vc(small):
    wp, tl = small
    return sliding_sweep(wp, tl, DX, 300e6, materials=MAT, positions=12)


@pytest.fixture(scope="module")
def sweep_novc(small):
    wp, tl = small
    return sliding_sweep(
        wp,
        tl,
        DX,
        300e6,
        materials=MAT,
        solver=SolverSettings(volume_conservation=False),
        positions=12,
    )


def test_work_equations():
    assert deformation_work(800e6, 2e-15) == pytest.approx(1.6e-6, rel=1e-15)
    # tau_adh = m sigma_y / 2 alpha; W = tau A0 2a
    w = adhesive_work(0.5, 300e6, 0.4, 4e-6, 2e-5)
    assert w == pytest.approx(0.5 * 150e6 * 0.4 * 4e-6 * 2e-5, rel=1e-15)


def test_default_surfaces_match_sec33():
    wp, tl = sliding_surfaces()
    assert wp.shape == (384, 128) and tl.shape == (128, 128)
    assert wp.dx == pytest.approx(6.33e-3 / 384) and wp.dy == pytest.approx(2.11e-3 / 128)
    assert tl.dx == pytest.approx(wp.dy) and tl.dy == pytest.approx(wp.dy)
    r = wp.roughness()
    assert r.Ra == pytest.approx(0.989e-6, rel=1e-9) and r.Rq == pytest.approx(1.201e-6, rel=1e-9)


def test_first_position_equals_plain_solve(small, sweep_vc):
    wp, tl = small
    plain = solve_normal_pair(
        wp.heights[:24], tl.heights, DX, E_STAR, 300e6, H=H, periodic=True, tol=1e-8
    )
    r = sweep_vc
    assert r.u0[0] == pytest.approx(plain.u0, rel=1e-12, abs=1e-18)
    assert r.alpha[0] == plain.alpha
    h_max = (tl.heights + wp.heights[:24]).max()
    assert r.separation[0] == pytest.approx(h_max - plain.u0, rel=1e-12)
    assert r.displaced_volume[0] == pytest.approx(plain.removed_volume, rel=1e-12)
    assert r.W_def[0] == pytest.approx(H * plain.removed_volume, rel=1e-12)
    A0 = 24 * 24 * DX * DX
    assert r.W_adh[0] == pytest.approx(0.5 * SIGMA_Y / 2 * plain.alpha * A0 * DX, rel=1e-12)


def test_conservation_without_volume_conservation(small, sweep_novc):
    wp, _ = small
    r = sweep_novc
    dA = DX * DX
    total = r.displaced_volume.sum()
    assert total > 0
    # every displaced volume is written back into the long workpiece, and nothing else
    lost = (r.workpiece_initial - r.workpiece_final).sum() * dA
    assert lost == pytest.approx(total, rel=1e-10)
    assert r.plastic_displacement.sum() * dA == pytest.approx(total, rel=1e-12)
    np.testing.assert_allclose(
        r.workpiece_final, wp.heights - r.plastic_displacement, rtol=0, atol=1e-20
    )
    assert np.all(r.plastic_displacement >= 0)
    # rows beyond the last window were never touched
    n_touched = 12 + 24 - 1
    assert np.all(r.plastic_displacement[n_touched:] == 0)
    np.testing.assert_array_equal(r.workpiece_final[n_touched:], wp.heights[n_touched:])
    np.testing.assert_allclose(r.W_def, H * r.displaced_volume, rtol=1e-15)


def test_conservation_with_volume_conservation(sweep_vc):
    r = sweep_vc
    dA = DX * DX
    assert all("valleys hold only" not in m for m in r.messages)
    # the displaced volume is moved into the valleys: the workpiece volume is unchanged
    scale = np.abs(r.workpiece_initial).sum()
    assert abs(r.workpiece_final.sum() - r.workpiece_initial.sum()) < 1e-12 * scale
    assert r.plastic_displacement.sum() * dA == pytest.approx(r.displaced_volume.sum(), rel=1e-12)
    assert r.all_converged, r.message


def test_flat_surfaces_give_no_deformation_work():
    wp = np.zeros((30, 12))
    tl = np.zeros((12, 12))
    r = sliding_sweep(wp, tl, DX, 200e6, materials=Materials(H=H, m=0.7, sigma_y=300e6))
    assert r.position.size == 19
    np.testing.assert_array_equal(r.W_def, 0.0)
    np.testing.assert_array_equal(r.alpha, 1.0)
    A0 = 144 * DX * DX
    np.testing.assert_allclose(r.W_adh, 0.7 * 150e6 * A0 * DX, rtol=1e-14)
    np.testing.assert_array_equal(r.ratio, 0.0)
    np.testing.assert_allclose(r.u0, r.u0[0], rtol=1e-9)
    np.testing.assert_array_equal(r.workpiece_final, wp)


def test_flat_workpiece_under_rough_tool_stays_elastic():
    # a smooth tool on a flat sheet: full contact with p well below H, no plastic work
    tl = S.tool_like(16, size=16 * DX, seed=5).heights * 0.05  # Rq 8 nm
    wp = np.zeros((24, 16))
    r = sliding_sweep(wp, tl, DX, 300e6, materials=MAT)
    np.testing.assert_array_equal(r.W_def, 0.0)
    np.testing.assert_array_equal(r.plastic_fraction, 0.0)
    assert np.all(r.alpha > 0.9)
    np.testing.assert_allclose(r.W_adh, 0.5 * SIGMA_Y / 2 * r.alpha * 256 * DX**3, rtol=1e-14)


def test_flattened_front_gives_work_only_from_the_new_row():
    # flat tool, flat (already flattened) sheet with one raised row at x index 30: it is the only
    # plastically deformed row, and only the position where it enters the window does work
    nt, ny, row = 16, 16, 30
    wp = np.zeros((40, ny))
    wp[row] = 2e-6
    tl = np.zeros((nt, ny))
    r = sliding_sweep(
        wp,
        tl,
        DX,
        100e6,
        materials=MAT,
        solver=SolverSettings(periodic=True, volume_conservation=False),
    )
    enter = row - nt + 1
    np.testing.assert_array_equal(r.W_def[:enter], 0.0)
    assert r.W_def[enter] > 0
    assert np.all(r.W_def[enter + 1 :] <= 1e-6 * r.W_def[enter])
    assert r.plastic_fraction[enter] == pytest.approx(1 / nt)
    upl = r.plastic_displacement
    assert np.all(np.delete(upl, row, axis=0) == 0)
    # the row is flattened to a uniform plateau, and the displaced volume is that of the row
    assert np.ptp(upl[row]) < 1e-9 * upl[row].mean()
    assert upl[row].sum() * DX * DX == pytest.approx(r.displaced_volume.sum(), rel=1e-12)
    assert 0 < upl[row].mean() < 2e-6


@pytest.mark.parametrize("vc", [False, True])
def test_restart_on_the_flattened_sheet(small, vc):
    # a sheet whose front part is already flattened by an earlier pass: re-loading the last
    # window does no plastic work, and the sweep goes on as if it had never stopped
    wp, tl = small
    kw = dict(materials=MAT, solver=SolverSettings(volume_conservation=vc))
    long = sliding_sweep(wp, tl, DX, 300e6, positions=14, **kw)
    first = sliding_sweep(wp, tl, DX, 300e6, positions=12, **kw)
    again = sliding_sweep(first.workpiece_final[11:], tl, DX, 300e6, positions=3, **kw)
    assert again.W_def[0] < 1e-6 * long.W_def[1:].mean()
    np.testing.assert_allclose(again.W_def[1:], long.W_def[12:], rtol=1e-6)
    np.testing.assert_allclose(again.alpha[1:], long.alpha[12:], atol=1 / 576)


def test_warm_start_does_not_change_the_answer(small, sweep_vc):
    wp, tl = small
    for mode in ("none", "workpiece"):
        other = sliding_sweep(wp, tl, DX, 300e6, materials=MAT, positions=12, warm_start=mode)
        np.testing.assert_allclose(other.alpha, sweep_vc.alpha, atol=2 / 576)
        np.testing.assert_allclose(
            other.W_def, sweep_vc.W_def, rtol=1e-4, atol=1e-4 * sweep_vc.W_def[1:].mean()
        )
        np.testing.assert_allclose(other.u0, sweep_vc.u0, rtol=1e-6)


def test_ratio_small_on_default_like_case(small, sweep_vc):
    wp, tl = small
    # the paper's picture: a smooth (here flat) tool, only the entering row is fresh
    flat = sliding_sweep(wp, np.zeros_like(tl.heights), DX, 300e6, materials=MAT, positions=12)
    assert flat.steady["ratio_max"] < 0.05, flat.steady
    assert flat.steady["ratio_mean"] > 0
    # the Table 1 tool adds the ploughing of the flattened plateau by its own asperities: per
    # step the overlap (t_k - t_(k+1))^+ on the contact area, so the ratio grows by about
    # 2 H / (m sigma_y) * <(t_k - t_(k+1))^+> / 2a (docs/sliding.md)
    r = sweep_vc
    s = r.steady
    t = tl.heights
    est = (
        flat.steady["ratio_mean"]
        + 2 * H / (0.5 * SIGMA_Y) * np.maximum(t[:-1] - t[1:], 0).mean() / DX
    )
    assert 0.5 < s["ratio_mean"] / est < 1.5, (s["ratio_mean"], est)
    assert s["ratio_mean"] > flat.steady["ratio_mean"]
    # the first indentation displaces far more than one sliding step
    assert r.W_def[0] > 3 * r.W_def[1:].max()
    np.testing.assert_allclose(r.ratio, r.W_def / r.W_adh, rtol=1e-15)


def test_unconverged_positions_are_reported(small):
    wp, tl = small
    r = sliding_sweep(
        wp, tl, DX, 500e6, materials=MAT, solver=SolverSettings(maxiter=2), positions=3
    )
    assert r.position.size == 3
    assert not r.all_converged
    assert "NOT converged" in r.message and r.failed_positions


def test_study_runs_one_sweep_per_pressure_and_writes_outputs(small, sweep_vc, tmp_path):
    wp, tl = small
    st = sliding_study(
        (300e6, 150e6), workpiece=wp, tool=tl, materials=MAT, positions=12, progress=False
    )
    assert isinstance(st, SlidingStudy) and not st.errors
    a, b = st.results
    np.testing.assert_array_equal(a.W_def, sweep_vc.W_def)
    assert b.p_mean == 150e6 and b.steady["alpha_mean"] < a.steady["alpha_mean"]
    summ = st.summary()
    assert summ["ratio_max"] == max(a.steady["ratio_max"], b.steady["ratio_max"])
    out = write_sliding_outputs(st, tmp_path / "sliding")
    with open(out / "sliding.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0])[:8] == [
        "position",
        "x_m",
        "p_mean_Pa",
        "u0_m",
        "alpha",
        "W_def_J",
        "W_adh_J",
        "ratio",
    ]
    assert len(rows) == 24
    assert float(rows[5]["W_def_J"]) == a.W_def[5] and float(rows[12]["p_mean_Pa"]) == 150e6
    for name in ("fig11_u0", "fig12_alpha", "fig13_W_adh", "fig14_W_def", "fig15_ratio"):
        assert_png_drawn(out / f"{name}.png")
    figs = plot_sliding(st.ok, tmp_path / "sliding")
    for r, (x, y) in zip(st.ok, lines(figs["fig12_alpha.png"]), strict=True):
        np.testing.assert_allclose(x, r.x * 1e3, rtol=1e-15)
        np.testing.assert_array_equal(y, r.alpha)
    drawn = lines(figs["fig15_ratio.png"])  # positions >= 1, then the paper's 0.008 line
    assert len(drawn) == 3 and np.all(drawn[-1][1] == 0.008)
    for r, (x, y) in zip(st.ok, drawn[:2], strict=True):
        np.testing.assert_allclose(x, r.x[1:] * 1e3, rtol=1e-15)
        np.testing.assert_array_equal(y, np.where(r.ratio[1:] > 0, r.ratio[1:], np.nan))
    with open(out / "sliding_summary.csv", newline="") as fh:
        summ_rows = list(csv.DictReader(fh))
    assert [float(r["p_mean_Pa"]) for r in summ_rows] == [300e6, 150e6]
    assert float(summ_rows[0]["ratio_mean"]) == a.steady["ratio_mean"]
    one = write_sliding_outputs(a, tmp_path / "one")  # a single result writes its own rows
    with open(one / "sliding.csv", newline="") as fh:
        body = list(csv.reader(fh))[1:]
    assert len(body) == a.position.size == 12
    np.testing.assert_array_equal([int(r[0]) for r in body], a.position)
    np.testing.assert_array_equal([float(r[5]) for r in body], a.W_def)


@pytest.mark.parametrize(
    "kw, match",
    [
        (dict(p_mean=800e6), "p_mean"),
        (dict(p_mean=-1.0), "p_mean"),
        (dict(m=0.0), "m must"),
        (dict(m=1.5), "m must"),
        (dict(positions=0), "positions"),
        (dict(positions=26), "positions"),
        (dict(positions=2.5), "positions"),
        (dict(dx=0.0), "dx"),
        (dict(tol=1.0), "tol"),
        (dict(sigma_y=-1.0), "sigma_y"),
        (dict(H=float("nan")), "H"),
        (dict(tool=np.zeros((16, 8))), "width"),
        (dict(tool=np.zeros((48, 16))), "at least as long"),
        (dict(workpiece=np.full((40, 16), np.nan)), "finite"),
        (dict(workpiece=np.zeros(40)), "2-D"),
        (dict(warm_start=True), "warm_start"),
    ],
)
def test_bad_input(kw, match):
    args = dict(
        workpiece=np.zeros((40, 16)),
        tool=np.zeros((16, 16)),
        dx=DX,
        p_mean=100e6,
        H=H,
        m=0.5,
    )
    args.update(kw)
    mat = {k: args.pop(k) for k in ("H", "m", "sigma_y") if k in args}
    sol = {k: args.pop(k) for k in ("tol",) if k in args}
    pos = [args.pop(k) for k in ("workpiece", "tool", "dx", "p_mean")]
    with pytest.raises(ValueError, match=match):  # the records refuse some values themselves
        sliding_sweep(*pos, materials=Materials(**mat), solver=SolverSettings(**sol), **args)


def test_study_bad_input():
    with pytest.raises(ValueError, match="pressures"):
        sliding_study((100e6, 900e6), progress=False)
    with pytest.raises(ValueError, match="pressures"):
        sliding_study((), progress=False)
    with pytest.raises(ValueError, match="dx"):
        sliding_study(
            (100e6,), workpiece=np.zeros((40, 16)), tool=np.zeros((16, 16)), progress=False
        )
    with pytest.raises(ValueError, match="result must be"):
        write_sliding_outputs({"a": 1}, "unused")


def test_cli_sliding_option(tmp_path, capsys):
    from halfspace_calib.cli import main

    out = tmp_path / "cal"
    argv = [
        "--grid",
        "16",
        "--pressures",
        "50e6,150e6,300e6,500e6",
        "--reload-fractions",
        "0.2,0.5,0.8",
        "--tol",
        "1e-7",
        "--heldout-tol",  # a toy grid: the acceptance is tested in test_failed_fit
        "0.5",
        "--out",
        str(out),
        "--no-progress",
        "--sliding",
    ]
    assert main(argv) == 0
    text = capsys.readouterr().out
    assert "W_def / W_adh mean" in text and text.count(" MPa: W_def / W_adh") == 6
    with open(out / "sliding" / "sliding.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 6 * (48 - 16 + 1)
    assert {float(r["p_mean_Pa"]) for r in rows} == {100e6, 200e6, 300e6, 400e6, 500e6, 600e6}
    assert all(float(r["ratio"]) >= 0 for r in rows)
    assert (out / "sliding" / "fig15_ratio.png").exists() and (out / "params.json").exists()

    capsys.readouterr()
    assert main(argv[:-1] + ["--m", "0", "--sliding"]) == 0
    assert "sliding (Sec. 3.3) skipped: m must be in (0, 1]" in capsys.readouterr().out

"""The nearly conforming contact in the non-periodic solve: the plastic punch edge, its
diagnosis and the periodic fallback of calibrate() (docs/measured_surfaces.md)."""

import json

import numpy as np
import pytest
from realfiles import real_file

from halfspace_calib.cli import main
from halfspace_calib.contact.normal import solve_normal
from halfspace_calib.pipeline.calibration import Scene, calibrate
from halfspace_calib.pipeline.conformity import edge_plasticity, punch_edge_problem

FAST_KW = dict(pressures=(20e6, 100e6, 300e6, 600e6), reload_fractions=(0.1, 0.25, 0.5, 0.8))
H = 800e6
E_STAR = 1.2e11


def test_a_flat_patch_pressed_non_periodic_is_a_punch_with_a_plastic_rim():
    """Boussinesq's flat punch: the pressure rises towards the patch's edge, which alone
    reaches the cap; a periodic solve of the same flat patch has a uniform pressure."""
    n, L = 64, 1e-3
    flat = np.zeros((n, n))
    res = solve_normal(flat, L / n, E_STAR, 500e6, H=H, periodic=False)
    assert res.converged, res.message
    e = edge_plasticity(res.pressure, H)
    assert e.punch_edge
    assert e.rim_capped >= 0.9 and e.centre_capped == 0.0
    assert res.pressure.mean() == pytest.approx(500e6, rel=1e-9)
    per = solve_normal(flat, L / n, E_STAR, 500e6, H=H, periodic=True)
    assert not edge_plasticity(per.pressure, H).punch_edge
    assert np.ptp(per.pressure) < 1e-6 * 500e6


def test_plastic_asperities_spread_over_the_patch_are_not_a_punch_edge():
    rng = np.random.default_rng(1)
    p = rng.uniform(0, H, (64, 64))
    p[rng.random((64, 64)) < 0.2] = H  # 20 % at the cap, anywhere
    e = edge_plasticity(p, H)
    assert 0.15 < e.rim_capped < 0.25 and 0.15 < e.centre_capped < 0.25
    assert not e.punch_edge
    assert not edge_plasticity(np.zeros((16, 16)), H).punch_edge


@pytest.mark.parametrize(
    "p, H_, band, match",
    [
        (np.zeros((4, 4)), H, None, "at least 8 x 8"),
        (np.zeros(64), H, None, "2-D map"),
        (np.full((16, 16), np.nan), H, None, "finite"),
        (np.zeros((16, 16)), -1.0, None, "H must be"),
        (np.zeros((16, 16)), H, 5, "band must be in"),
    ],
)
def test_edge_plasticity_refuses_bad_input(p, H_, band, match):
    with pytest.raises(ValueError, match=match):
        edge_plasticity(p, H_, band)


def _metropro():
    return str(real_file("metropro-1.dat"))


def test_nearly_conforming_scan_non_periodic_fails_with_the_reason():
    f = _metropro()
    sc = Scene(workpiece=f, tool=f, grid=48, resolution_check=False, **FAST_KW)
    cal = calibrate(sc, progress=False, auto_periodic=False)
    assert not cal.scene.periodic and cal.notes == ()
    why = punch_edge_problem(cal)
    assert "flat punch" in why and "--periodic" in why
    assert why in cal.problems()
    assert cal.reload.r_squared < 0.9  # the reload fit fails on the plastic rim


def test_nearly_conforming_scan_falls_back_to_the_periodic_solve(tmp_path, capsys):
    f = _metropro()
    sc = Scene(workpiece=f, tool=f, grid=48, resolution_check=False, **FAST_KW)
    cal = calibrate(sc, progress=False)
    assert cal.scene.periodic
    assert len(cal.notes) == 1 and "flat punch" in cal.notes[0]
    assert cal.problems() == []
    assert cal.reload.r_squared > 0.9 and cal.first.r_squared > 0.9
    grid = cal.params.provenance["grid"]
    assert grid["periodic"] is True and "flat punch" in grid["periodic_reason"]
    # the CLI: the fallback is announced and recorded; --no-periodic keeps the failure
    fast = ["--pressures", "20e6,100e6,300e6,600e6", "--reload-fractions", "0.1,0.25,0.5,0.8"]
    base = ["--workpiece", f, "--tool", f, "--grid", "48", "--no-resolution-check", *fast]
    assert main([*base, "--out", str(tmp_path / "a"), "--quiet"]) == 0
    err = capsys.readouterr().err  # a change of the solve is a warning: stderr, even with --quiet
    assert "note: solved periodic after the non-periodic run failed" in err
    summary = json.loads((tmp_path / "a" / "summary.json").read_text())
    assert summary["periodic"] is True and len(summary["notes"]) == 1
    assert main([*base, "--no-periodic", "--out", str(tmp_path / "b"), "--quiet"]) == 1
    err = capsys.readouterr().err
    assert "RUN FAILED" in err and "flat punch" in err

"""The nearly conforming contact: the plastic punch edge of the isolated solve and its
diagnosis, and the mirror-symmetric boundary that has neither a punch edge nor a seam (the
default for files; docs/measured_surfaces.md, "The patch's boundary"): the three criteria of
reload curves that belong to the roughness, on real files."""

import dataclasses
import json

import numpy as np
import pytest
from realfiles import real_file

from halfspace_calib.cli import main
from halfspace_calib.contact.normal import solve_normal
from halfspace_calib.pipeline.calibration import Scene, calibrate
from halfspace_calib.pipeline.sweep.conformity import (
    edge_plasticity,
    punch_edge_problem,
    reload_deficit,
    reload_grid_change,
)
from halfspace_calib.pipeline.sweep.sweeps import run_sweeps

FAST_KW = dict(pressures=(20e6, 100e6, 300e6, 600e6), reload_fractions=(0.1, 0.25, 0.5, 0.8))
#: the criteria's sweep: every reload pressure of the 200 MPa curve is a first-loading level
CRIT_KW = dict(
    pressures=(10e6, 20e6, 50e6, 100e6, 200e6, 400e6, 700e6),
    reload_from=200e6,
    reload_fractions=(0.05, 0.1, 0.25, 0.5, 0.75),
)
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


def criteria(cal):
    """The three criteria of issue 31 from the calibration's raw sweeps, and the same sweeps at
    half the grid: (largest deficit of a reload point below the first loading, largest change
    of a reload point at half the grid, the border band's and the centre's capped fractions at
    the top level)."""
    sw = cal.sweeps
    p1, a1 = sw.loading
    deficit = reload_deficit(p1, a1, sw.reload_curves())
    half = dataclasses.replace(cal.scene, grid=cal.scene.grid // 2, resolution_check=False)
    change = reload_grid_change(
        sw.reload_curves(), run_sweeps(half, progress=False).reload_curves()
    )
    top = max(sw.levels, key=lambda lv: lv.p_hist)
    return deficit, change, edge_plasticity(top.pressure_map, cal.scene.H)


def test_nearly_conforming_scan_isolated_is_a_punch_whose_reloads_fall_below_first_loading():
    f = _metropro()
    sc = Scene(workpiece=f, tool=f, grid=48, boundary="isolated", resolution_check=False, **CRIT_KW)
    cal = calibrate(sc, progress=False)
    assert cal.scene.boundary == "isolated" and not cal.scene.periodic and cal.notes == ()
    deficit, change, edge = criteria(cal)
    assert deficit.worst > 0.2  # a flattened surface with less contact than the virgin one
    assert edge.punch_edge and edge.rim_capped > 0.9 and edge.centre_capped < 0.2
    why = punch_edge_problem(cal)
    if cal.reload.r_squared < 0.9 or cal.reload.at_bound:  # the diagnosis explains a failed fit
        assert "flat punch" in why and "--boundary mirror" in why
        assert why in cal.problems()


@pytest.mark.parametrize(
    "name, grid, kw",
    [
        ("metropro-1.dat", 48, {}),
        ("matrix-3.txt", 40, {}),
        ("sur-3.sur", 48, {"max_undefined": 0.95}),
    ],
)
def test_the_mirror_boundary_meets_the_three_criteria_on_real_files(name, grid, kw):
    """Default boundary of files: each reload curve at or above the first loading (0.02), the
    reload curves within 0.03 at half the grid, and the border band at the cap no more than
    the centre: the curves of the roughness, not of the patch (nearly conforming metropro-1,
    rough matrix-3, filled sur-3)."""
    f = str(real_file(name))
    sc = Scene(workpiece=f, tool=f, grid=grid, resolution_check=False, **CRIT_KW, **kw)
    assert sc.boundary == "mirror"
    cal = calibrate(sc, progress=False)
    assert cal.problems() == [] and cal.notes == ()
    deficit, change, edge = criteria(cal)
    assert deficit.worst <= 0.02, deficit
    assert change.worst <= 0.03, change
    assert edge.rim_capped <= edge.centre_capped + 0.05, edge
    assert not edge.punch_edge
    grid_rec = cal.params.provenance["grid"]
    assert grid_rec["boundary"] == "mirror" and "mirror-symmetric" in grid_rec["boundary_reason"]


def test_boundary_option_of_the_cli_and_the_scene(tmp_path, capsys):
    f = _metropro()
    fast = ["--pressures", "20e6,100e6,300e6,600e6", "--reload-fractions", "0.1,0.25,0.5,0.8"]
    fast += ["--heldout-tol", "0.5"]  # a toy grid: the acceptance is tested in test_failed_fit
    base = ["--workpiece", f, "--tool", f, "--grid", "32", "--no-resolution-check", *fast]
    assert main([*base, "--out", str(tmp_path / "a")]) == 0
    out = capsys.readouterr().out
    assert "boundary mirror" in out
    summary = json.loads((tmp_path / "a" / "summary.json").read_text())
    assert summary["boundary"] == "mirror" and summary["periodic"] is False
    params = json.loads((tmp_path / "a" / "params.json").read_text())
    assert params["provenance"]["grid"]["boundary"] == "mirror"
    for old in (["--boundary", "isolated"], ["--no-periodic"]):  # the behaviour before, by name
        main([*base, *old, "--out", str(tmp_path / "b"), "--quiet"])
        s = json.loads((tmp_path / "b" / "summary.json").read_text())
        assert s["boundary"] == "isolated"
    main([*base, "--periodic", "--out", str(tmp_path / "c"), "--quiet"])
    assert json.loads((tmp_path / "c" / "summary.json").read_text())["boundary"] == "periodic"
    capsys.readouterr()
    assert main([*base, "--periodic", "--boundary", "mirror", "--out", str(tmp_path / "d")]) == 2
    assert "give --boundary or --periodic, not both" in capsys.readouterr().err
    assert main([*base, "--boundary", "open", "--out", str(tmp_path / "d")]) == 2
    assert not (tmp_path / "d").exists()
    assert main(["--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "--boundary {periodic,mirror,isolated}" in text
    assert "default: periodic for synthetic surfaces, mirror for files" in text
    # the Scene: boundary, and periodic= as the older switch (True: periodic, False: isolated)
    assert Scene().boundary == "periodic" and Scene(workpiece=f).boundary == "mirror"
    assert Scene(workpiece=f, periodic=False).boundary == "isolated"
    sc = Scene(workpiece=f, tool=f)
    assert dataclasses.replace(sc, periodic=True).boundary == "periodic"
    assert dataclasses.replace(sc, grid=16).boundary == "mirror"
    assert dataclasses.replace(Scene(periodic=True), boundary="mirror").boundary == "mirror"
    with pytest.raises(ValueError, match="boundary must be one of"):
        Scene(boundary="open")
    scene_file = tmp_path / "s.toml"
    scene_file.write_text(f'workpiece = "{f}"\nboundary = "isolated"\nperiodic = false\n')
    from halfspace_calib.pipeline.sweep.scene import load_scene

    with pytest.raises(ValueError, match="give boundary or periodic"):
        load_scene(scene_file)
    scene_file.write_text(f'workpiece = "{f}"\nperiodic = false\n')
    assert load_scene(scene_file).boundary == "isolated"
    assert load_scene(scene_file, boundary="mirror").boundary == "mirror"

"""The study of Figs. 9-10: tau_geo of inclined patches against tau_adh (Sec. 3.2, Eqs. 19-23)."""

import csv

import numpy as np
import pytest
from plotcheck import assert_png_drawn, lines

from halfspace_calib import topography as S
from halfspace_calib.contact.materials import Materials, SolverSettings
from halfspace_calib.output.geometric import plot_geometric, write_geometric_outputs
from halfspace_calib.studies.geometric import (
    GeometricResult,
    fit_geo_ratio,
    geometric_study,
    geometric_sweep,
)
from halfspace_calib.topography import measured_surfaces

H, M = 800e6, 0.5
K = H / 2.8 / 2  # k = sigma_y / 2


def _plane(n_fine, dx, slope):
    x = np.arange(n_fine) * dx
    return np.broadcast_to((slope * x)[:, None], (n_fine, n_fine)).copy()


@pytest.mark.parametrize("slope", [0.02, 0.1])
def test_conformal_tilted_plane_gives_tan_phi(slope):
    # workpiece rising in +x, tool with the same plane (conformal): flat gap, full contact, uniform
    # p = p_mean, both normals equal -> tau_geo = p_mean tan(phi), ratio = p_mean tan(phi) / (m k)
    n, s, dx = 16, 4, 4e-6
    wp = S.Surface(_plane(n * s, dx, slope), dx, dx)
    tl = S.Surface(-_plane(n * s, dx, slope), dx, dx)  # tool heights point towards the workpiece
    p = (100e6, 400e6)
    r = geometric_sweep(wp, tl, p, block=s, materials=Materials(H=H, m=M))
    assert r.all_converged
    np.testing.assert_allclose(r.alpha, 1.0)
    np.testing.assert_allclose(r.tau_geo, np.array(p) * slope, rtol=1e-10)
    np.testing.assert_allclose(r.ratio, np.array(p) * slope / (M * K), rtol=1e-10)
    # sliding the other way: every patch is an exiting flank (Eq. 23 neglects them)
    back = geometric_sweep(wp, tl, p, block=s, materials=Materials(H=H, m=M), direction=-1)
    np.testing.assert_array_equal(back.tau_geo, 0.0)


def test_tilted_tool_on_flat_workpiece_elastic_rule_bisects():
    # flat workpiece, tilted tool: every contact patch elastic (H huge) takes the mean of both
    # normals, i.e. the bisector at phi / 2, whatever the pressure distribution: tau_geo =
    # sum(p) tan(phi / 2) / N = p_mean tan(phi / 2)
    n, s, dx, slope = 16, 4, 4e-6, 0.05
    wp = S.Surface(np.zeros((n * s, n * s)), dx, dx)
    tl = S.Surface(-_plane(n * s, dx, slope), dx, dx)  # seen from the workpiece: rising in +x
    r = geometric_sweep(
        wp,
        tl,
        (50e6,),
        block=s,
        materials=Materials(H=1e12, m=M),
        solver=SolverSettings(periodic=False),
    )
    assert r.all_converged and r.plastic_fraction[0] == 0.0 and r.alpha[0] < 1.0
    phi = np.arctan(slope)
    assert r.tau_geo[0] == pytest.approx(50e6 * np.tan(phi / 2), rel=1e-9)


def test_measured_surfaces_have_table1_ra_on_the_solver_grid():
    for rough, key in ((False, "tool"), (True, "rough_tool")):
        wp, tl = measured_surfaces(16, 4, rough_tool=rough)
        assert wp.shape == tl.shape == (64, 64)
        assert S.ra(S.block_average(wp, 16)) == pytest.approx(
            S.TABLE1["workpiece"]["Ra"], rel=1e-12
        )
        assert S.ra(S.block_average(tl, 16)) == pytest.approx(S.TABLE1[key]["Ra"], rel=1e-12)
    _, tl = measured_surfaces(16, 4, roughness_on="measured")
    assert S.ra(tl) == pytest.approx(S.TABLE1["tool"]["Ra"], rel=1e-12)


def test_measured_maps_are_the_solver_surfaces_at_a_finer_grid():
    """One random field at both grids: the block averages of the measured maps are exactly the
    surfaces the sweeps solve on (before, the smooth tool's correlated only 0.79, skewness -0.77
    against -2.93), and the points inside each element keep the measured grid's detail."""
    for rough in (False, True):
        wp, tl = measured_surfaces(16, 4, rough_tool=rough)
        sweeps = (S.dc04_edt_like(16, measured_n=64), S.tool_like(16, rough=rough, measured_n=64))
        for fine, coarse in zip((wp, tl), sweeps, strict=True):
            got = S.block_average(fine, 16).heights
            np.testing.assert_allclose(got, coarse.heights, rtol=0, atol=1e-12 * S.rq(coarse))
            detail = fine.heights - np.repeat(np.repeat(got, 4, axis=0), 4, axis=1)
            assert S.rq(fine) > S.rq(coarse) and np.std(detail) > 0.05 * S.rq(coarse)


@pytest.fixture(scope="module")
def study():
    return geometric_study((100e6, 300e6, 600e6), n=32, block=4, solver=SolverSettings(tol=1e-7))


def test_study_shape_smooth_below_rough(study):
    smooth, rough = study.results
    assert (smooth.label, rough.label) == ("smooth tool", "rough tool")
    for r in study.results:
        assert r.all_converged
        assert np.all(np.isfinite(r.ratio)) and np.all(r.ratio >= 0)
        assert np.all(r.ratio < 0.5)  # small against adhesion (Fig. 10)
        # nearly independent of the pressure (Fig. 10)
        assert r.ratio.max() / r.ratio.min() < 1.5
        np.testing.assert_allclose(r.tau_adh, M * K * r.alpha, rtol=1e-12)
    # A_real differs little between the tools (Fig. 9), the rougher tool gives more tau_geo
    np.testing.assert_allclose(smooth.alpha, rough.alpha, atol=0.05)
    assert np.all(rough.ratio > 1.3 * smooth.ratio)


def test_outputs(study, tmp_path):
    out = write_geometric_outputs(study, tmp_path / "geo")
    with open(out / "geometric.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 6 and {r["label"] for r in rows} == {"smooth tool", "rough tool"}
    r0 = study.results[0]
    assert float(rows[0]["ratio"]) == pytest.approx(r0.ratio[0], rel=1e-15)
    for name in ("fig9_tau.png", "fig10_ratio.png"):
        assert_png_drawn(out / name)
    figs = plot_geometric(study.results, tmp_path / "geo")
    tau, ratio = lines(figs["fig9_tau.png"]), lines(figs["fig10_ratio.png"])
    assert len(tau) == 4 and len(ratio) == 2
    for i, r in enumerate(study.results):
        np.testing.assert_allclose(tau[2 * i][0], r.p_mean / 1e6, rtol=1e-15)
        np.testing.assert_allclose(tau[2 * i][1], r.tau_adh / 1e6, rtol=1e-15)
        np.testing.assert_allclose(tau[2 * i + 1][1], r.tau_geo / 1e6, rtol=1e-15)
        np.testing.assert_array_equal(ratio[i][1], r.ratio)
    s = study.summary()["pairs"][1]
    assert s["ratio_min"] <= s["ratio_mean"] <= s["ratio_max"]


def _result(tau_adh, tau_geo, converged=None):
    k = len(tau_adh)
    ta = np.asarray(tau_adh, float)
    tg = np.asarray(tau_geo, float)
    return GeometricResult(
        "x",
        np.linspace(1e8, 6e8, k),
        ta / (M * K),
        ta,
        tg,
        tg / ta,
        np.zeros(k),
        np.ones(k, bool) if converged is None else np.asarray(converged),
    )


def test_fit_geo_ratio_least_squares():
    ta = np.array([10e6, 20e6, 40e6])
    f = fit_geo_ratio(_result(ta, 0.1 * ta))
    assert f["geo_ratio"] == pytest.approx(0.1, rel=1e-14) and f["rms_misfit"] < 1e-14
    # least squares weights the large stresses: against the plain mean of the ratios
    tg = np.array([3e6, 2e6, 4e6])
    f = fit_geo_ratio(_result(ta, tg))
    # independent oracle: LAPACK least squares of tau_geo = g tau_adh (no intercept); by hand,
    # g = (3*10 + 2*20 + 4*40) / (10^2 + 20^2 + 40^2) = 230 / 2100
    g_lstsq = np.linalg.lstsq(ta[:, None], tg, rcond=None)[0][0]
    assert f["geo_ratio"] == pytest.approx(g_lstsq, rel=1e-12)
    assert f["geo_ratio"] == pytest.approx(230 / 2100, rel=1e-14)
    assert f["ratio_mean"] == pytest.approx((0.3 + 0.1 + 0.1) / 3, rel=1e-14)
    # unconverged points are left out
    f = fit_geo_ratio(_result(ta, np.array([1e6, 2e6, 100e6]), [True, True, False]))
    assert f["geo_ratio"] == pytest.approx(0.1, rel=1e-14) and len(f["pressures"]) == 2
    with pytest.raises(ValueError, match="nothing to fit"):
        fit_geo_ratio(_result(ta, ta, [False] * 3))


def test_bad_input():
    wp, tl = measured_surfaces(8, 2)
    with pytest.raises(ValueError, match=r"m must be in \(0, 1\]"):
        geometric_sweep(wp, tl, (1e8,), block=2, materials=Materials(m=0.0))
    with pytest.raises(ValueError, match=r"pressures must be in \(0, H\)"):
        geometric_sweep(wp, tl, (1e8, 9e8), block=2)
    with pytest.raises(ValueError, match="block"):
        geometric_sweep(wp, tl, (1e8,), block=3)
    with pytest.raises(ValueError, match="share the measured grid"):
        geometric_sweep(wp, S.crop(tl, 8), (1e8,), block=2)
    with pytest.raises(ValueError, match="Surface"):
        geometric_sweep(wp.heights, tl, (1e8,), block=2)
    with pytest.raises(ValueError, match="block must be an integer >= 2"):
        measured_surfaces(8, 1)
    with pytest.raises(ValueError, match="roughness_on"):
        measured_surfaces(8, 2, roughness_on="both")
    with pytest.raises(ValueError, match="result must be"):
        write_geometric_outputs([1], "unused")

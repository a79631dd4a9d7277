"""The perimeter-corrected contact area of Yastrebov, Anciaux and Molinari (2017)."""

import math

import numpy as np
import pytest

from halfspace_calib.contact.area import (
    YAM_COEFFICIENT,
    contact_perimeter,
    corrected_contact_ratio,
)
from halfspace_calib.contact.normal import solve_normal
from halfspace_calib.contact.reference import hertz

E_STAR = 1.2e11


def test_coefficient_is_the_papers():
    assert YAM_COEFFICIENT == pytest.approx((math.pi - 1 + math.log(2)) / 24, rel=1e-15)
    assert YAM_COEFFICIENT == pytest.approx(0.118114, abs=1e-6)


@pytest.mark.parametrize("k", [1, 3, 10])
def test_square_block_known_area_and_perimeter(k):
    n = 32
    m = np.zeros((n, n), bool)
    m[5 : 5 + k, 7 : 7 + k] = True
    for periodic in (True, False):
        assert contact_perimeter(m, periodic=periodic) == 4 * k
        assert corrected_contact_ratio(m, periodic=periodic) == pytest.approx(
            (k * k - YAM_COEFFICIENT * 4 * k) / n**2, rel=1e-14
        )


def test_patch_border_counts_only_when_periodic():
    n = 16
    m = np.zeros((n, n), bool)
    m[:, :4] = True  # a stripe along the left border, 4 columns wide
    # non-periodic: only its inner side is a contact boundary; periodic: both sides
    assert contact_perimeter(m, periodic=False) == n
    assert contact_perimeter(m, periodic=True) == 2 * n
    m[:] = True  # full contact: no boundary at all
    assert contact_perimeter(m, periodic=True) == 0
    assert corrected_contact_ratio(m, periodic=True) == 1.0


def test_checkerboard_and_pressure_input():
    n = 8
    cb = (np.add.outer(np.arange(n), np.arange(n)) % 2).astype(bool)
    assert contact_perimeter(cb, periodic=True) == 2 * n * n  # every edge separates
    assert contact_perimeter(cb, periodic=False) == 2 * n * (n - 1)
    # a pressure map is read as p > 0; the ratio is clipped at 0 (here N_c - c N_p > 0)
    p = np.where(cb, 5e6, 0.0)
    assert corrected_contact_ratio(p, periodic=True) == corrected_contact_ratio(cb, periodic=True)
    assert corrected_contact_ratio(p, periodic=True) == pytest.approx(
        (32 - YAM_COEFFICIENT * 128) / 64
    )


def test_disc_perimeter_is_the_staircase_length():
    """A digitised disc (a digitally convex set) of 2 r + 1 elements across: its staircase
    boundary is as long as its bounding box's, 2 (2 r + 1) + 2 (2 r + 1) edges."""
    n, r = 101, 30
    i = np.arange(n) - n // 2
    disc = np.add.outer(i**2, i**2) <= r * r
    assert contact_perimeter(disc, periodic=False) == 8 * r + 4


@pytest.mark.parametrize("bad", [np.zeros(5), np.zeros((0, 3)), np.full((3, 3), np.nan)])
def test_bad_masks_are_refused(bad):
    with pytest.raises(ValueError, match="contact must be"):
        corrected_contact_ratio(bad, periodic=True)


def test_hertz_area_is_closer_with_the_correction_on_coarse_grids():
    """Sphere on a flat at five loads on grids of 24-64 elements (contact radius 3.6-22
    elements): the corrected ratio's mean error against pi a^2 is below the raw count's
    (measured: raw 4.2 / 3.0 / 1.7 %, corrected 2.0 / 1.6 / 0.55 %,
    benchmarks/contact_area_correction.py)."""
    L, R = 1e-3, 5e-3
    for n in (24, 32, 64):
        dx = L / n
        x = (np.arange(n) - (n - 1) / 2) * dx
        X, Y = np.meshgrid(x, x, indexing="ij")
        h = -(X**2 + Y**2) / (2 * R)
        raw, cor = [], []
        for af in (0.15, 0.2, 0.25, 0.3, 0.35):
            F = 4 * E_STAR * (af * L) ** 3 / (3 * R)
            exact = math.pi * hertz(F, R, E_STAR).a ** 2 / L**2
            res = solve_normal(h, dx, E_STAR, F / L**2, periodic=False)
            assert res.converged, res.message
            raw.append(abs(res.alpha / exact - 1))
            cor.append(abs(corrected_contact_ratio(res.pressure, periodic=False) / exact - 1))
        assert np.mean(cor) < 0.75 * np.mean(raw), (n, raw, cor)
        assert np.mean(cor) < 0.025


def test_scene_option_feeds_the_corrected_ratio_to_the_fits():
    from halfspace_calib.pipeline.calibration import Scene, calibrate
    from halfspace_calib.pipeline.sweep.sweeps import SolveRecord

    with pytest.raises(ValueError, match="contact_area must be 'count' or 'perimeter'"):
        Scene(contact_area="pixels")
    kw = dict(grid=32, pressures=(20e6, 100e6, 300e6, 500e6), reload_fractions=(0.25, 0.5, 0.8))
    count = calibrate(Scene(**kw), progress=False)
    perim = calibrate(Scene(contact_area="perimeter", **kw), progress=False)
    p, a_count = count.sweeps.loading
    _, a_perim = perim.sweeps.loading
    # same solves, only the estimator differs: the corrected ratio is the count minus
    # c N_p / N > 0, so strictly smaller wherever the contact has a boundary
    assert np.all(a_perim < a_count) and np.all(a_perim > 0.5 * a_count)
    assert perim.params.provenance["extra"]["model"]["contact_area"] == "perimeter"
    assert count.params.provenance["extra"]["model"]["contact_area"] == "count"
    # the record of one solve is the estimator applied to its pressure map
    h = np.random.default_rng(0).standard_normal((32, 32)) * 1e-6
    res = solve_normal(h, 1e-5, E_STAR, 50e6, periodic=True)
    rec = SolveRecord.of(res, "perimeter")
    assert rec.alpha == corrected_contact_ratio(res.pressure, periodic=True)
    assert SolveRecord.of(res).alpha == res.alpha

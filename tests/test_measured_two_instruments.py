"""Workpiece and tool scanned by different instruments (issue 26, item 1).

The coarser scan is S-filtered at ``lambda_s`` (at least 3 of its pixels by default) and so
band-limited: the loader puts it on the grid of the default rule (16 elements per
``lambda_s``) with :func:`band_limited_resample` instead of capping the grid at its pixel.
"""

import math

import numpy as np
import pytest

from halfspace_calib import topography as S
from halfspace_calib.cli import main
from halfspace_calib.pipeline.calibration import Scene
from halfspace_calib.pipeline.sweep.scene_surfaces import (
    ELEMENTS_PER_LAMBDA_S,
    area_resample,
    band_limited_resample,
    load_scene_surfaces,
)
from halfspace_calib.topography.filters import s_filter


def _truth(n=512, pitch=0.125e-6, cut=3e-6, seed=3):
    """A self-affine surface, band-limited by a Gaussian low-pass at ``cut`` (m), finely sampled."""
    s = S.self_affine((n, n), (n * pitch, n * pitch), rq=0.4e-6, seed=seed)
    return S.Surface(s_filter(s, cut).heights, pitch, pitch)


def _point_samples(s, r):
    """The values at the centres of ``r x r`` blocks (a coarse instrument's pixels), from ``s``.

    ``r`` even: the centre lies between four fine samples, their mean (exact to second order
    in a surface band-limited far below the fine pitch).
    """
    h = s.heights
    a, b = r // 2 - 1, r // 2
    c = (h[a::r, a::r] + h[b::r, b::r] + h[a::r, b::r] + h[b::r, a::r]) / 4
    return S.Surface(c, s.dx * r, s.dy * r)


def _rms(a, b):
    return float(np.sqrt(np.mean((a - b) ** 2)))


def test_band_limited_resample_of_a_coarse_scan_matches_the_fine_scan():
    # truth: band-limited at 3 um; fine scan 0.125 um pixels, coarse scan 1 um pixels (8x);
    # both S-filtered at lambda_s = 3 um (3 coarse pixels: the default rule's coarsest), then
    # put on 16 elements per lambda_s (0.1875 um, 5.3 elements per coarse pixel)
    lam, side = 3e-6, 64e-6
    t = _truth(cut=lam)
    fine = s_filter(t, lam)
    coarse = s_filter(_point_samples(t, 8), lam)
    m = 8 * math.ceil(ELEMENTS_PER_LAMBDA_S * side / lam / 8)
    ref = area_resample(fine, side, m).heights
    rq = float(np.std(ref))
    up = band_limited_resample(coarse, side, m)
    assert up.shape == (m, m) and up.dx == pytest.approx(side / m)
    # Tolerance 0.5 % of Rq (measured 0.27 %): what is left is the scan's edge (the even
    # extension of a surface whose slope is not zero there) and the coarse scan's content
    # near its Nyquist wavelength (2 um, transmission 0.33 of the 3 um filter), which its
    # samples alias; a staircase of copied pixels (area_resample of the coarse scan) is off by
    # 5.4 %, so the test tells the two apart
    assert _rms(up.heights, ref) < 0.005 * rq
    staircase = area_resample(coarse, side, m).heights
    assert _rms(staircase, ref) > 0.04 * rq
    # away from the edges (an eighth of the side): 0.3 % (measured 0.18 %)
    k = m // 8
    assert _rms(up.heights[k:-k, k:-k], ref[k:-k, k:-k]) < 0.003 * rq
    # Rq of the interpolated patch within 0.2 % (measured 0.00 %)
    assert float(np.std(up.heights)) == pytest.approx(rq, rel=2e-3)


def test_band_limited_resample_reproduces_a_cosine_and_averages_exactly():
    # one cosine of the scan's own series (k = 3 along x): its cell means are known exactly
    n, p = 24, 1e-6
    x = (np.arange(n) + 0.5) * p
    h = np.cos(np.pi * 3 * x / (n * p))[:, None] * np.ones((1, n))
    s = S.Surface(h * 1e-7, p, p)
    m = 60  # 0.4 um elements, 2.5 per pixel, on the whole 24 um square
    got = band_limited_resample(s, n * p, m).heights
    e = n * p / m
    a = np.arange(m) * e
    q = np.pi * 3 / (n * p)
    exact = (np.sin(q * (a + e)) - np.sin(q * a)) / (q * e) * 1e-7
    np.testing.assert_allclose(got, np.repeat(exact[:, None], m, axis=1), atol=1e-12 * 1e-7)
    with pytest.raises(ValueError, match="exceeds the surface's size"):
        band_limited_resample(s, 25e-6, m)


def _text_scan(path, s):
    """Write ``s`` as a text matrix with its own size and unit (like matrix-3.txt)."""
    w = s.size[1] * 1e6
    hgt = s.size[0] * 1e6
    head = f"Width: {w:.6f} um\nHeight: {hgt:.6f} um\nValue units: m"
    np.savetxt(path, s.heights, header=head)
    return str(path)


def test_loader_interpolates_the_coarser_scan_onto_the_default_rule(tmp_path):
    # workpiece 0.125 um pixels over 64 um; tool 1 um pixels over 96 um: the common square is
    # 64 um, the default lambda_s = 5 um (>= 3 tool pixels, >= 16 elements of 64 um at 256)
    t = _truth(n=512, cut=2e-6, seed=4)
    tool_truth = S.self_affine((96, 96), (96e-6, 96e-6), rq=0.3e-6, seed=9)
    wp = _text_scan(tmp_path / "wp.txt", t)
    tl = _text_scan(tmp_path / "tl.txt", tool_truth)
    ss = load_scene_surfaces(Scene(workpiece=wp, tool=tl))
    assert ss.lambda_s == 5e-6
    # 16 elements per lambda_s: 208 elements of 0.31 um; the pixel cap gave 64 (12.8 / lambda_s)
    assert ss.grid == 8 * math.ceil(16 * 64 / 5 / 8) == 208
    assert ss.lambda_s / ss.workpiece.dx >= ELEMENTS_PER_LAMBDA_S
    assert not [n for n in ss.notes if "elements per lambda_s" in n]
    rec = {r.role: r for r in ss.files}
    assert any(st.startswith("interpolated (band-limited") for st in rec["tool"].steps)
    assert not any("interpolated" in st for st in rec["workpiece"].steps)
    assert any(st.startswith("area-averaged") for st in rec["workpiece"].steps)
    # the tool is the band-limited resample of the levelled, filtered scan (then levelled)
    read = S.Surface(np.loadtxt(tl), 1e-6, 1e-6)
    ref = S.level(band_limited_resample(s_filter(S.level(read), 5e-6), 64e-6, 208))
    tol = 1e-9 * np.ptp(ref.heights)
    np.testing.assert_allclose(ss.tool.heights, ref.heights, rtol=0, atol=tol)
    # without the S-filter the coarser pixel still caps the grid (no band limit to use)
    raw = load_scene_surfaces(Scene(workpiece=wp, tool=tl, lambda_s=0))
    assert raw.grid == 64 and not any("interpolated" in st for f in raw.files for st in f.steps)


def test_too_fine_a_grid_and_an_unpairable_scan_are_refused_naming_the_option(tmp_path, capsys):
    t = S.self_affine((64, 64), (64e-6, 64e-6), rq=0.3e-6, seed=2)
    fine = _text_scan(tmp_path / "fine.txt", t)
    coarse = _text_scan(
        tmp_path / "coarse.txt", S.self_affine((40, 40), (800e-6, 800e-6), rq=2e-6, seed=1)
    )
    # a 20 um pixel needs lambda_s >= 60 um (default 80 um), beyond the 64 um common square
    code = main(["--workpiece", fine, "--tool", coarse, "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert code == 2 and "coarse.txt has pixels of 2e-05 m" in err and "--lambda-s" in err
    assert "Traceback" not in err
    # interpolation below the pixel is allowed down to lambda_s / 32, not further
    code = main(
        ["--workpiece", fine, "--tool", fine, "--lambda-s", "8e-6", "--grid", "512"]
        + ["--out", str(tmp_path / "o")]
    )
    err = capsys.readouterr().err
    assert code == 2 and "grid=512" in err and "--grid" in err and "allowed 0.25" in err
    ss = load_scene_surfaces(
        Scene(workpiece=fine, tool=fine, lambda_s=8e-6, grid=256), check_sampling=True
    )
    assert ss.grid == 256  # 32 elements per lambda_s: allowed

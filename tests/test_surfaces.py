import hashlib
import sys

import numpy as np
import pytest

from halfspace_calib import topography as S
from halfspace_calib.topography import _formats as io_topo
from halfspace_calib.topography import synthesis

L = 1e-3


def _random_surface(shape=(48, 40), seed=0, periodic=False):
    rng = np.random.default_rng(seed)
    return S.Surface(rng.normal(0, 1e-6, shape), 2e-6, 3e-6, periodic=periodic)


# -- synthetic surfaces -------------------------------------------------------------


@pytest.mark.parametrize("hurst", [0.3, 0.8, 1.0])
def test_psd_slope_recovers_hurst(hurst):
    # 2-D PSD of a self-affine surface ~ q^(-2 - 2H); average 4 realisations at 256^2
    logc = []
    for seed in range(4):
        s = S.self_affine(256, L, hurst=hurst, rq=1e-6, seed=seed)
        q, c = S.psd_radial(s, 24)
        logc.append(np.log(c))
    logc = np.mean(logc, axis=0)
    band = (q > 3 * 2 * np.pi / L) & (q < 0.7 * np.pi / s.dx)
    assert band.sum() >= 10
    slope = np.polyfit(np.log(q[band]), logc[band], 1)[0]
    assert (-slope - 2) / 2 == pytest.approx(hurst, abs=0.03)


def test_psd_rolloff_is_flat_below_and_self_affine_above():
    lr = 1e-4
    s = S.self_affine(256, L, hurst=0.8, rq=1e-6, seed=0, rolloff_wavelength=lr)
    q, c = S.psd_radial(s, 24)
    qr = 2 * np.pi / lr
    lo = q < 0.7 * qr
    hi = (q > 1.5 * qr) & (q < 0.7 * np.pi / s.dx)
    assert abs(np.polyfit(np.log(q[lo]), np.log(c[lo]), 1)[0]) < 0.3
    slope = np.polyfit(np.log(q[hi]), np.log(c[hi]), 1)[0]
    assert (-slope - 2) / 2 == pytest.approx(0.8, abs=0.06)


def test_cutoff_wavelength_removes_short_waves():
    ls = 8 * L / 128
    s = S.self_affine(128, L, rq=1e-6, cutoff_wavelength=ls, seed=1)
    c = np.abs(np.fft.fft2(s.heights)) ** 2
    qx = 2 * np.pi * np.fft.fftfreq(128, s.dx)
    q = np.hypot(qx[:, None], qx[None, :])
    above = q > 2 * np.pi / ls * (1 + 1e-9)
    assert c[above].max() < 1e-20 * c.max()
    assert c[~above].sum() > 0


@pytest.mark.parametrize(
    "kw",
    [
        {"rq": 1.267e-6},
        {"ra": 1.034e-6},
        {"ra": 1.034e-6, "rq": 1.267e-6},
        {"ra": 0.102e-6, "rq": 0.160e-6},
        {"ra": 0.9e-6, "rq": 1e-6},
    ],
)
def test_roughness_targets_hit(kw):
    s = S.self_affine(64, L, hurst=0.7, seed=5, **kw)
    if "rq" in kw:
        assert S.rq(s) == pytest.approx(kw["rq"], rel=1e-12)
    if "ra" in kw:
        assert S.ra(s) == pytest.approx(kw["ra"], rel=1e-12)
    assert abs(s.heights.mean()) < 1e-12 * S.rq(s)


def test_single_target_keeps_gaussian_ratio():
    # with a roll-off many independent modes carry the heights: Gaussian statistics
    s = S.self_affine(256, L, hurst=0.8, rq=1e-6, rolloff_wavelength=L / 16, seed=2)
    assert S.ra(s) / S.rq(s) == pytest.approx(np.sqrt(2 / np.pi), abs=0.02)
    assert S.rku(s) == pytest.approx(3.0, abs=0.3)


@pytest.mark.parametrize(
    "make, key",
    [
        (S.dc04_edt_like, "workpiece"),
        (S.tool_like, "tool"),
        (lambda **k: S.tool_like(rough=True, **k), "rough_tool"),
    ],
)
def test_presets_hit_table1(make, key):
    for kw in ({}, {"n": 64, "measured_n": 256}):
        s = make(**kw)
        assert S.ra(s) == pytest.approx(S.TABLE1[key]["Ra"], rel=1e-12)
        assert S.rq(s) == pytest.approx(S.TABLE1[key]["Rq"], rel=1e-12)
        assert s.size[0] == pytest.approx(S.PAPER_SIZE, rel=1e-15)
        assert s.periodic
    s = make(match="rq")
    assert S.rq(s) == pytest.approx(S.TABLE1[key]["Rq"], rel=1e-12)
    assert s.provenance["height_transform"] == 0.0


def test_tool_shape_is_deep_valleys():
    r = S.tool_like().roughness()
    assert r.Rsk < -1 and r.Rku > 6  # Ra/Rq = 0.64 needs a heavy (lower) tail
    r = S.dc04_edt_like().roughness()
    assert abs(r.Rsk) < 0.2 and r.Rku < 3  # Ra/Rq = 0.816 > 0.798: lighter tails


def test_measured_n_gives_one_surface_at_all_resolutions():
    a = S.dc04_edt_like(64, measured_n=256)
    b = S.block_average(S.dc04_edt_like(128, measured_n=256), 64)
    r = np.corrcoef(a.heights.ravel(), b.heights.ravel())[0, 1]
    assert r > 0.97
    c = S.dc04_edt_like(64, seed=7, measured_n=256)
    assert abs(np.corrcoef(a.heights.ravel(), c.heights.ravel())[0, 1]) < 0.3


def test_seed_reproducible():
    a = S.self_affine((32, 48), (L, 1.5 * L), rq=1e-6, ra=0.8e-6, seed=11)
    b = S.self_affine((32, 48), (L, 1.5 * L), rq=1e-6, ra=0.8e-6, seed=11)
    c = S.self_affine((32, 48), (L, 1.5 * L), rq=1e-6, ra=0.8e-6, seed=12)
    assert np.array_equal(a.heights, b.heights)
    assert not np.allclose(a.heights, c.heights)
    assert a.provenance["seed"] == 11 and a.provenance["source"] == "generator"
    assert a.dx == pytest.approx(L / 32) and a.dy == pytest.approx(1.5 * L / 48)


@pytest.mark.parametrize(
    "kw, word",
    [
        ({"hurst": 1.5, "rq": 1e-6}, "hurst"),
        ({"hurst": 0.0, "rq": 1e-6}, "hurst"),
        ({}, "rq"),
        ({"rq": -1.0}, "rq"),
        ({"ra": 2e-6, "rq": 1e-6}, "ra"),
        ({"rq": 1e-6, "cutoff_wavelength": 1e-6}, "cutoff_wavelength"),
        ({"rq": 1e-6, "rolloff_wavelength": 1e-4, "cutoff_wavelength": 2e-4}, "rolloff"),
        ({"rq": 1e-6, "seed": -1}, "seed"),
        ({"rq": 1e-6, "ra": 0.1e-6}, "Ra/Rq"),
        ({"rq": 1e-6, "ra": 0.99e-6}, r"\[0.5, 0.95\]"),
    ],
)
def test_self_affine_bad_input(kw, word):
    with pytest.raises(ValueError, match=word):
        S.self_affine(32, L, **kw)


def test_unreachable_ratio_is_reported():
    # an equal-weight two-level field keeps Ra/Rq = 1 under any monotone map
    with pytest.raises(ValueError, match="cannot be reached"):
        synthesis._shape_ra_rq(np.array([[-1.0, 1.0], [1.0, -1.0]]), 0.9)


# -- preparation ----------------------------------------------------------------------


def test_level_removes_added_plane_exactly():
    s = _random_surface()
    x, y = np.meshgrid(s.x, s.y, indexing="ij")
    plane = 3e-6 + 0.02 * x - 0.05 * y
    tilted = S.Surface(s.heights + plane, s.dx, s.dy)
    a, b = S.level(s), S.level(tilted)
    assert np.abs(a.heights - b.heights).max() < 1e-12 * S.rq(s)
    flat = S.level(S.Surface(plane, s.dx, s.dy))
    assert np.abs(flat.heights).max() < 1e-12 * np.abs(plane).max()
    op = b.provenance["operations"][-1]
    assert op["op"] == "level"
    assert op["slope_x"] - a.provenance["operations"][-1]["slope_x"] == pytest.approx(0.02)
    assert op["slope_y"] - a.provenance["operations"][-1]["slope_y"] == pytest.approx(-0.05)


def test_block_average_is_mean_of_covered_points_and_preserves_mean():
    s = _random_surface((96, 60))
    c = S.block_average(s, (12, 10))
    assert c.shape == (12, 10)
    assert c.dx == pytest.approx(8 * s.dx) and c.dy == pytest.approx(6 * s.dy)
    assert c.heights.mean() == pytest.approx(s.heights.mean(), rel=1e-13, abs=1e-22)
    for i, j in [(0, 0), (5, 7), (11, 9)]:
        block = s.heights[8 * i : 8 * i + 8, 6 * j : 6 * j + 6]
        assert c.heights[i, j] == pytest.approx(block.mean(), rel=1e-14)
    assert c.provenance["operations"][-1]["points_per_element"] == 48
    assert c.size == pytest.approx(s.size)


def test_block_average_non_dividing_grid():
    s = _random_surface((50, 40))
    with pytest.raises(ValueError, match="divide"):
        S.block_average(s, 12)
    c = S.block_average(s, 12, trim=True)
    assert c.shape == (12, 12)
    assert [op["op"] for op in c.provenance["operations"]] == ["crop", "block_average"]
    inner = s.heights[1:49, 2:38]  # 48 x 36 centred window
    assert c.heights.mean() == pytest.approx(inner.mean(), rel=1e-13)


def test_crop_and_errors():
    s = _random_surface((20, 30), periodic=True)
    c = S.crop(s, (5, 6), (3, 4))
    assert np.array_equal(c.heights, s.heights[3:8, 4:10]) and not c.periodic
    assert S.crop(s, (20, 30)).periodic
    with pytest.raises(ValueError, match="exceeds"):
        S.crop(s, (10, 10), (15, 0))
    with pytest.raises(ValueError, match="shape"):
        S.crop(s, (1, 10))


def test_surface_validation():
    with pytest.raises(ValueError, match="finite"):
        S.Surface(np.array([[0.0, np.nan], [1.0, 2.0]]), 1e-6, 1e-6)
    with pytest.raises(ValueError, match="2-D"):
        S.Surface(np.zeros(5), 1e-6, 1e-6)
    with pytest.raises(ValueError, match="dy"):
        S.Surface(np.zeros((3, 3)), 1e-6, 0.0)
    s = _random_surface()
    with pytest.raises(ValueError):
        s.heights[0, 0] = 1.0  # read-only


# -- roughness --------------------------------------------------------------------------


def test_roughness_of_sine_surface():
    amp, n_per, periods = 2e-6, 64, 3
    nx = n_per * periods
    dx = 5e-6
    x = np.arange(nx) * dx
    lam = n_per * dx
    h = np.repeat((amp * np.sin(2 * np.pi * x / lam))[:, None], 8, axis=1)
    s = S.Surface(h, dx, dx, periodic=True)
    r = s.roughness()
    # discrete sums over whole periods: sum |sin| = 2 cot(pi/N) per period, the rest exact
    assert r.Ra == pytest.approx(2 * amp / np.tan(np.pi / n_per) / n_per, rel=1e-13)
    assert r.Ra == pytest.approx(2 * amp / np.pi, rel=1.01 * np.pi**2 / (3 * n_per**2))
    assert r.Rq == pytest.approx(amp / np.sqrt(2), rel=1e-13)
    assert r.Rku == pytest.approx(1.5, rel=1e-12)
    assert abs(r.Rsk) < 1e-12
    k = 2 * np.pi / lam
    assert r.Rdq == pytest.approx(amp * np.sin(k * dx) / dx / np.sqrt(2), rel=1e-12)
    assert r.Rdq == pytest.approx(amp * k / np.sqrt(2), rel=(k * dx) ** 2 / 6 * 1.01)


def test_roughness_of_gaussian_heights():
    # white Gaussian heights: Ra/Rq -> sqrt(2/pi), Rsk -> 0, Rku -> 3 (sampling error ~1/sqrt(N))
    s = _random_surface((400, 400), seed=3)
    r = S.roughness(s)
    assert r.Ra / r.Rq == pytest.approx(np.sqrt(2 / np.pi), abs=0.005)
    assert abs(r.Rsk) < 0.02 and r.Rku == pytest.approx(3, abs=0.04)


def test_flat_surface_has_no_skew_or_kurtosis():
    s = S.Surface(np.full((4, 4), 1e-6), 1e-6, 1e-6)
    r = s.roughness()
    assert r.Ra == 0 and r.Rq == 0 and r.Rsk is None and r.Rku is None and r.Rdq == 0
    with pytest.raises(ValueError, match="flat"):
        S.rku(s)


def test_psd_parseval():
    s = S.self_affine(64, L, rq=1e-6, seed=4)
    c = np.abs(np.fft.fft2(s.heights)) ** 2 * s.dx * s.dy / s.heights.size
    dq = (2 * np.pi / L) ** 2
    assert c.sum() * dq / (2 * np.pi) ** 2 == pytest.approx(1e-12, rel=1e-12)
    q, cr = S.psd_radial(s, 16)
    assert np.all(np.diff(q) > 0) and np.all(cr > 0)


# -- files ----------------------------------------------------------------------------


@pytest.fixture
def surf():
    return S.self_affine((12, 9), (0.24e-3, 0.18e-3), rq=1.2e-6, seed=8)


def _sha(path):
    return hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.mark.parametrize("name", ["h.npy", "h.txt", "h.csv", "h.dat"])
@pytest.mark.parametrize("unit", ["um", "nm", "m"])
def test_roundtrip_matrix_formats(tmp_path, surf, name, unit):
    p = S.write_surface(surf, tmp_path / name, unit=unit)
    back = S.read_surface(p, unit=unit, dx=surf.dx, dy=surf.dy)
    np.testing.assert_allclose(back.heights, surf.heights, rtol=1e-14, atol=0)
    assert (back.dx, back.dy) == (surf.dx, surf.dy)
    assert back.provenance["sha256"] == _sha(p) and back.provenance["unit"] == unit
    by_size = S.read_surface(p, unit=unit, size=surf.size)
    assert by_size.dy == pytest.approx(surf.dy, rel=1e-15)


def test_roundtrip_xyz_shuffled_and_units(tmp_path, surf):
    p = S.write_surface(surf, tmp_path / "h.xyz", unit="um")
    back = S.read_surface(p, unit="um")
    np.testing.assert_allclose(back.heights, surf.heights, rtol=1e-14, atol=0)
    assert back.dx == pytest.approx(surf.dx, rel=1e-12)
    assert back.dy == pytest.approx(surf.dy, rel=1e-12)
    # rows in any order, x y in mm, z in nm, comma separated, rounded coordinates
    x, y = np.meshgrid(surf.x * 1e3, surf.y * 1e3, indexing="ij")
    pts = np.column_stack(
        [np.round(x.ravel(), 9), np.round(y.ravel(), 9), surf.heights.ravel() * 1e9]
    )
    pts = pts[np.random.default_rng(0).permutation(len(pts))]
    q = tmp_path / "pts.xyz"
    np.savetxt(q, pts, fmt="%.17g", delimiter=",")
    back = S.read_surface(q, unit="nm", xy_unit="mm")
    np.testing.assert_allclose(back.heights, surf.heights, rtol=1e-13, atol=0)
    assert back.dx == pytest.approx(surf.dx, rel=1e-8)


def test_xyz_not_gridded(tmp_path, surf):
    x, y = np.meshgrid(surf.x, surf.y, indexing="ij")
    pts = np.column_stack([x.ravel(), y.ravel(), surf.heights.ravel()])
    p = tmp_path / "missing.xyz"
    np.savetxt(p, pts[1:])
    with pytest.raises(ValueError, match="not gridded"):
        S.read_surface(p, unit="m")
    irregular = pts.copy()
    irregular[:, 0] = irregular[:, 0] ** 1.5 * 1e2
    np.savetxt(p, irregular)
    with pytest.raises(ValueError, match="regular grid"):
        S.read_surface(p, unit="m")
    dup = pts.copy()
    dup[1, :2] = dup[0, :2]
    dup[-1, :2] = [x.max() + surf.dx, 0.0]
    np.savetxt(p, dup)
    with pytest.raises(ValueError, match="regular grid|not gridded"):
        S.read_surface(p, unit="m")
    np.savetxt(p, pts[:, :2])
    with pytest.raises(ValueError, match="3 columns"):
        S.read_surface(p, unit="m")


def test_unreadable_and_incomplete_input(tmp_path, surf):
    junk = tmp_path / "junk.txt"
    junk.write_text("1 2 3\n4 five 6\n")
    with pytest.raises(ValueError, match="junk.txt"):
        S.read_surface(junk, unit="um", dx=1e-6)
    ragged = tmp_path / "ragged.csv"
    ragged.write_text("1,2,3\n4,5\n")
    with pytest.raises(ValueError, match="ragged.csv"):
        S.read_surface(ragged, unit="um", dx=1e-6)
    bad_npy = tmp_path / "bad.npy"
    bad_npy.write_bytes(b"\x00\x01not numpy")
    with pytest.raises(ValueError, match="bad.npy"):
        S.read_surface(bad_npy, unit="um", dx=1e-6)
    nan = tmp_path / "nan.txt"
    nan.write_text("1 2\nnan 4\n")
    with pytest.raises(ValueError, match="1 undefined"):
        S.read_surface(nan, unit="um", dx=1e-6)
    filled = S.read_surface(nan, unit="um", dx=1e-6, fill_undefined=True)
    # the harmonic fill of one point is the mean of its defined neighbours
    assert filled.heights[1, 0] == pytest.approx(2.5e-6, rel=1e-12)
    with pytest.raises(FileNotFoundError, match="nothere"):
        S.read_surface(tmp_path / "nothere.npy", unit="um", dx=1e-6)
    p = S.write_surface(surf, tmp_path / "h.npy")
    with pytest.raises(ValueError, match="unit"):
        S.read_surface(p, dx=1e-6)
    with pytest.raises(ValueError, match="unit"):
        S.read_surface(p, unit="inch", dx=1e-6)
    with pytest.raises(ValueError, match="dx or size"):
        S.read_surface(p, unit="um")
    with pytest.raises(ValueError, match="layout"):
        S.read_surface(p, unit="um", dx=1e-6, layout="tiff")
    with pytest.raises(ValueError, match="path must end"):
        S.write_surface(surf, tmp_path / "h.png")


def test_instrument_format_without_extra_names_it(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "SurfaceTopography", None)
    f = tmp_path / "scan.vk4"
    f.write_bytes(b"VK4_" + bytes(100))
    with pytest.raises(
        ImportError, match=r"SurfaceTopography>=1.27.*pip install -e .\.\[topography\]"
    ):
        S.read_surface(f)


def test_instrument_roundtrip_x3p(tmp_path):
    try:
        st = io_topo.import_surface_topography()
    except ImportError:
        pytest.skip("SurfaceTopography (the topography extra) is not installed")
    rng = np.random.default_rng(1)
    h_um = rng.normal(0, 1.0, (16, 12))
    topo = st.Topography(h_um, physical_sizes=(320.0, 240.0), unit="um")
    p = tmp_path / "scan.x3p"
    topo.to_x3p(str(p))
    s = S.read_surface(p)
    np.testing.assert_allclose(s.heights, h_um * 1e-6, rtol=1e-12, atol=1e-20)
    assert s.dx == pytest.approx(20e-6, rel=1e-6) and s.dy == pytest.approx(20e-6, rel=1e-6)
    assert s.provenance["layout"] == "instrument" and s.provenance["sha256"] == _sha(p)
    with pytest.raises(ValueError, match="lateral calibration"):
        S.read_surface(p, dx=1e-6)
    junk = tmp_path / "junk.vk4"
    junk.write_bytes(b"definitely not a keyence file" * 10)
    with pytest.raises(ValueError, match="junk.vk4"):
        S.read_surface(junk)


def test_instrument_undefined_points_and_units(tmp_path):
    try:
        st = io_topo.import_surface_topography()
    except ImportError:
        pytest.skip("SurfaceTopography (the topography extra) is not installed")
    h = np.linspace(0.0, 1.0, 48).reshape(8, 6)
    h[2, 3] = np.nan
    topo = st.Topography(np.ma.masked_invalid(h), physical_sizes=(160.0, 120.0), unit="um")
    p = tmp_path / "holes.x3p"
    topo.to_x3p(str(p))
    with pytest.raises(ValueError, match="fill_undefined"):
        S.read_surface(p)
    s = S.read_surface(p, fill_undefined=True)
    assert np.isfinite(s.heights).all() and s.provenance["filled_undefined"]
    # the hole lies on a plane: any sensible interpolation puts it there
    assert s.heights[2, 3] == pytest.approx((2 * 6 + 3) / 47 * 1e-6, rel=0.05)
    with pytest.raises(ValueError, match="contradicts"):
        S.read_surface(tmp_path / "holes.x3p", unit="nm", fill_undefined=True)

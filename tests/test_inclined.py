import numpy as np
import pytest

from halfspace_calib.studies.inclined import (
    contact_normals,
    fit_patch_planes,
    patch_normals,
    tau_geo,
)


def _fine_grid(nx, ny, sx, sy, dx, dy):
    x = np.arange(nx * sx) * dx
    y = np.arange(ny * sy) * dy
    return np.meshgrid(x, y, indexing="ij")


def _block_centres(nx, ny, sx, sy, dx, dy):
    xc = (np.arange(nx) * sx + (sx - 1) / 2) * dx
    yc = (np.arange(ny) * sy + (sy - 1) / 2) * dy
    return np.meshgrid(xc, yc, indexing="ij")


def test_exact_piecewise_planes_recovered():
    rng = np.random.default_rng(0)
    nx, ny, sx, sy, dx, dy = 6, 5, 4, 3, 1e-6, 2e-6
    A = rng.normal(scale=0.1, size=(nx, ny))
    B = rng.normal(scale=0.1, size=(nx, ny))
    Gc = rng.normal(scale=1e-6, size=(nx, ny))
    X, Y = _fine_grid(nx, ny, sx, sy, dx, dy)
    Xc, Yc = _block_centres(nx, ny, sx, sy, dx, dy)
    rep = lambda f: np.repeat(np.repeat(f, sx, 0), sy, 1)  # noqa: E731
    z = rep(A) * (X - rep(Xc)) + rep(B) * (Y - rep(Yc)) + rep(Gc)
    planes = fit_patch_planes(z, (sx, sy), dx, dy)
    np.testing.assert_allclose(planes.alpha, A, atol=1e-12)
    np.testing.assert_allclose(planes.beta, B, atol=1e-12)
    np.testing.assert_allclose(planes.gamma, Gc, atol=1e-18)
    assert np.all(planes.n_points == sx * sy)


def test_matches_lstsq_oracle_with_missing_points():
    rng = np.random.default_rng(1)
    nx, ny, s, dx = 4, 3, 5, 0.5e-6
    z = rng.normal(scale=1e-6, size=(nx * s, ny * s))
    z[rng.random(z.shape) < 0.2] = np.nan
    planes = fit_patch_planes(z, s, dx)
    X, Y = _fine_grid(nx, ny, s, s, dx, dx)
    for i in range(nx):
        for j in range(ny):
            sl = (slice(i * s, (i + 1) * s), slice(j * s, (j + 1) * s))
            zz, xx, yy = z[sl].ravel(), X[sl].ravel(), Y[sl].ravel()
            ok = np.isfinite(zz)
            xc = (i * s + (s - 1) / 2) * dx
            yc = (j * s + (s - 1) / 2) * dx
            D = np.column_stack([(xx[ok] - xc) / dx, (yy[ok] - yc) / dx, np.ones(ok.sum())])
            coef = np.linalg.lstsq(D, zz[ok], rcond=None)[0]  # Eq. 20 minimised directly
            coef[:2] /= dx
            assert planes.alpha[i, j] == pytest.approx(coef[0], rel=1e-9, abs=1e-12)
            assert planes.beta[i, j] == pytest.approx(coef[1], rel=1e-9, abs=1e-12)
            assert planes.gamma[i, j] == pytest.approx(coef[2], rel=1e-9, abs=1e-18)
            assert planes.n_points[i, j] == ok.sum()


def test_normals_convention():
    nv = patch_normals(np.array([0.0, 0.5]), np.array([0.0, -0.2]))
    np.testing.assert_allclose(np.linalg.norm(nv, axis=-1), 1.0)
    np.testing.assert_allclose(nv[0], [0, 0, 1])
    assert nv[1, 2] > 0
    np.testing.assert_allclose(nv[1, 0] / nv[1, 2], -0.5)  # nv_x / nv_z = -alpha
    np.testing.assert_allclose(nv[1, 1] / nv[1, 2], 0.2)


@pytest.mark.parametrize("phi_deg", [2.0, 10.0, 30.0])
def test_tilted_plane_tau_geo(phi_deg):
    tanphi = np.tan(np.radians(phi_deg))
    n, s, dx = 8, 4, 1e-6
    X, _ = _fine_grid(n, n, s, s, dx, dx)
    p = np.full((n, n), 300e6)
    rising = fit_patch_planes(tanphi * X, s, dx)  # rises in +x: faces the tool sliding in +x
    nv = patch_normals(rising.alpha, rising.beta)
    assert tau_geo(p, nv) == pytest.approx(300e6 * tanphi, rel=1e-12)
    # the same plane is an exiting flank for the reverse direction
    assert tau_geo(p, nv, direction=-1) == 0.0
    falling = fit_patch_planes(-tanphi * X, s, dx)
    nvf = patch_normals(falling.alpha, falling.beta)
    assert tau_geo(p, nvf) == 0.0  # exiting flanks neglected
    assert tau_geo(p, nvf, direction=-1) == pytest.approx(300e6 * tanphi, rel=1e-12)
    # contact only on part of the surface: Eq. 23 divides by all Nx Ny elements
    p_half = p.copy()
    p_half[: n // 2] = 0.0
    assert tau_geo(p_half, nv) == pytest.approx(0.5 * 300e6 * tanphi, rel=1e-12)


def test_elastic_and_plastic_rules():
    phi = np.radians(12.0)
    n = 4
    ones = np.ones((n, n))
    nw = patch_normals(np.tan(phi) * ones, 0 * ones)  # workpiece rising in +x
    p = np.full((n, n), 500e6)
    # flat tool: elastic mean normal is tilted by phi/2, plastic takes the tool's (flat) normal
    flat = patch_normals(0 * ones, 0 * ones)
    el = contact_normals(nw, flat, np.zeros((n, n), bool))
    pl = contact_normals(nw, flat, np.ones((n, n), bool))
    assert tau_geo(p, el) == pytest.approx(500e6 * np.tan(phi / 2), rel=1e-12)
    assert tau_geo(p, pl) == 0.0
    # a tool whose measured slope is -tan(phi) (heights towards the workpiece) is parallel to the
    # workpiece patch in the common frame: both rules give p tan(phi)
    alpha_t = -np.tan(phi) * ones
    nt = patch_normals(-alpha_t, 0 * ones)
    for plastic in (False, True):
        nc = contact_normals(nw, nt, np.full((n, n), plastic))
        assert tau_geo(p, nc) == pytest.approx(500e6 * np.tan(phi), rel=1e-12)
    # mixed mask picks per element
    mask = np.zeros((n, n), bool)
    mask[0] = True
    mixed = contact_normals(nw, flat, mask)
    np.testing.assert_allclose(mixed[0], pl[0])
    np.testing.assert_allclose(mixed[1:], el[1:])


def test_symmetric_triangle_wave():
    # symmetric ridges, slopes +-tan(phi), elements aligned with the flanks: half the elements
    # enter, half exit -> tau_geo = p tan(phi) / 2 with uniform pressure
    tanphi = 0.15
    n, s, dx = 8, 4, 1e-6
    im = np.arange(n * s) % (2 * s)
    prof = np.where(im < s, im, 2 * s - 1 - im) * dx * tanphi
    # each element holds one straight flank: rising (0..s-1) then falling
    z = np.repeat(prof[:, None], n * s, axis=1)
    planes = fit_patch_planes(z, s, dx)
    np.testing.assert_allclose(np.abs(planes.alpha), tanphi, rtol=1e-12)
    nv = patch_normals(planes.alpha, planes.beta)
    p = np.full((n, n), 200e6)
    assert tau_geo(p, nv) == pytest.approx(200e6 * tanphi / 2, rel=1e-12)
    assert tau_geo(p, nv, direction=-1) == pytest.approx(200e6 * tanphi / 2, rel=1e-12)
    # pressure only on the entering flanks doubles the share
    p_in = np.where(planes.alpha > 0, 400e6, 0.0)
    assert tau_geo(p_in, nv) == pytest.approx(200e6 * tanphi, rel=1e-12)
    # a ridge along x (profile in y) has no x-slope: no geometric shear in x
    planes_y = fit_patch_planes(z.T.copy(), s, dx)
    assert tau_geo(p, patch_normals(planes_y.alpha, planes_y.beta)) == pytest.approx(0.0, abs=1e-6)


def test_bad_input():
    z = np.zeros((8, 8))
    with pytest.raises(ValueError, match="divisible"):
        fit_patch_planes(z, 3, 1e-6)
    with pytest.raises(ValueError, match="at least 3"):
        fit_patch_planes(z, (1, 2), 1e-6)
    with pytest.raises(ValueError, match="block"):
        fit_patch_planes(z, 0, 1e-6)
    with pytest.raises(ValueError, match="dx"):
        fit_patch_planes(z, 4, -1e-6)
    with pytest.raises(ValueError, match="one line"):
        fit_patch_planes(z, (1, 4), 1e-6)  # single column of points in x
    zn = z.copy()
    zn[:4, :4] = np.nan
    zn[0, 0] = 0.0
    with pytest.raises(ValueError, match=r"element \(0, 0\)"):
        fit_patch_planes(zn, 4, 1e-6)
    nv = patch_normals(np.zeros((2, 2)), np.zeros((2, 2)))
    with pytest.raises(ValueError, match="p must"):
        tau_geo(-np.ones((2, 2)), nv)
    with pytest.raises(ValueError, match="shape"):
        tau_geo(np.ones((3, 2)), nv)
    with pytest.raises(ValueError, match="direction"):
        tau_geo(np.ones((2, 2)), nv, direction=0)
    with pytest.raises(ValueError, match="up"):
        contact_normals(-nv, nv, np.zeros((2, 2), bool))


def test_tau_geo_from_surfaces():
    from halfspace_calib.studies.inclined import tau_geo_from_surfaces

    rng = np.random.default_rng(4)
    n, s, dx = 8, 4, 1e-6
    zw = np.cumsum(rng.normal(scale=0.05 * dx, size=(n * s, n * s)), axis=0)
    p = rng.uniform(0, 500e6, size=(n, n))
    planes = fit_patch_planes(zw, s, dx)
    ref = tau_geo(p, patch_normals(planes.alpha, planes.beta))
    assert ref > 0
    # a conforming tool (heights towards the workpiece = -z_workpiece) has the workpiece's normals
    assert tau_geo_from_surfaces(p, zw, -zw, s, dx) == pytest.approx(ref, rel=1e-12)
    # flat tool: plastic contact takes the tool's normal -> no geometric shear
    flat = np.zeros_like(zw)
    assert tau_geo_from_surfaces(p, zw, flat, s, dx, plastic=np.ones((n, n), bool)) == 0.0
    el = tau_geo_from_surfaces(p, zw, flat, s, dx)
    assert 0 < el < ref
    with pytest.raises(ValueError, match="element grid"):
        tau_geo_from_surfaces(p[:4], zw, flat, s, dx)

"""The mirror-symmetric boundary of a patch (``boundary="mirror"``, docs/measured_surfaces.md,
"The patch's boundary"): the operator against the periodic operator of the explicit mirror
extension and against the analytic cosine mode, the solver against the explicit extension, and
the limiting cases that separate the three boundaries (a flat punch, a step at the seam)."""

import dataclasses

import numpy as np
import pytest

from halfspace_calib.contact.influence import (
    MirrorOperator,
    boundary_of,
    normal_operator,
)
from halfspace_calib.contact.materials import SolverSettings
from halfspace_calib.contact.normal import estimate_memory, solve_normal, solve_normal_pair
from halfspace_calib.pipeline.law.fit import ReloadCurve
from halfspace_calib.pipeline.sweep.conformity import (
    edge_plasticity,
    reload_deficit,
    reload_grid_change,
)

E_STAR = 1.2e11
H = 800e6


def mirror_extend(a):
    """The patch reflected across each edge: one period (2 Nx x 2 Ny) of the extension."""
    return np.pad(a, ((0, a.shape[0]), (0, a.shape[1])), mode="symmetric")


def smooth_random(shape, seed, rq=1e-7, corr=3.0):
    """A smooth random field that is not periodic (its opposite edges differ)."""
    rng = np.random.default_rng(seed)
    w = rng.standard_normal((shape[0] + 40, shape[1] + 40))
    k = np.exp(-0.5 * (np.arange(-12, 13) / corr) ** 2)
    w = np.apply_along_axis(lambda r: np.convolve(r, k, "same"), 0, w)
    w = np.apply_along_axis(lambda r: np.convolve(r, k, "same"), 1, w)[20:-20, 20:-20]
    return rq * (w - w.mean()) / w.std()


# ----------------------------------------------------------------------------- operator
@pytest.mark.parametrize("shape, dx, dy", [((16, 16), 1e-6, 1e-6), ((12, 20), 1e-6, 2.5e-6)])
def test_mirror_operator_is_the_periodic_operator_of_the_mirror_extension(shape, dx, dy):
    op = MirrorOperator(shape, dx, E_STAR, dy=dy)
    big = normal_operator((2 * shape[0], 2 * shape[1]), dx, E_STAR, dy=dy, periodic=True)
    p = np.random.default_rng(0).random(shape)
    u = op.apply(p)
    ref = big.apply(mirror_extend(p))
    assert np.abs(u - ref[: shape[0], : shape[1]]).max() <= 1e-12 * np.abs(ref).max()
    # the extension's response is mirror-symmetric too: the patch holds the whole problem
    assert np.allclose(
        ref, mirror_extend(ref[: shape[0], : shape[1]]), rtol=0, atol=1e-12 * ref.max()
    )
    # Parseval: the quadratic form from the cosine coefficients
    assert op.energy(op.forward(p)) == pytest.approx(float(p.ravel() @ u.ravel()), rel=1e-12)
    C = op.dense_matrix()
    assert np.allclose(C, C.T, rtol=0, atol=1e-12 * np.abs(C).max())
    assert np.linalg.eigvalsh(C).min() > -1e-12 * np.abs(C).max()  # positive semi-definite
    assert op.norm == pytest.approx(np.linalg.eigvalsh(C).max(), rel=1e-9)


def test_mirror_operator_on_a_cosine_mode_is_the_half_space_green_function():
    """cos(pi k (i + 1/2) / N): the even extension's mode of wavenumber q = pi k / L; the
    half-space answers 2 p / (E* q) (the Fourier transform of Eq. 1)."""
    n, m, dx = 32, 24, 2e-6
    i = (np.arange(n) + 0.5)[:, None]
    j = (np.arange(m) + 0.5)[None, :]
    op = MirrorOperator((n, m), dx, E_STAR)
    for kx, ky in ((1, 0), (3, 5), (0, 7), (31, 23)):
        mode = np.cos(np.pi * kx * i / n) * np.cos(np.pi * ky * j / m)
        q = np.hypot(np.pi * kx / (n * dx), np.pi * ky / (m * dx))
        assert np.allclose(
            op.apply(mode), 2 / (E_STAR * q) * mode, rtol=0, atol=1e-12 / (E_STAR * q)
        )
    assert np.abs(op.apply(np.ones((n, m)))).max() < 1e-25  # the mean mode: the approach's gauge


def test_mirror_operator_single_precision_and_its_memory():
    op = MirrorOperator((16, 16), 1e-6, E_STAR)
    p = np.random.default_rng(3).random((16, 16))
    s = op.single()
    assert np.abs(s.apply(p) - op.apply(p)).max() < 1e-6 * np.abs(op.apply(p)).max()
    assert op.apply(p).dtype == np.float64 and s.apply(p).dtype == np.float64
    # transforms of the grid's own size: the periodic estimate, a quarter of the padded FFTs
    assert estimate_memory((256, 256), "mirror") == estimate_memory((256, 256), True)
    assert estimate_memory((256, 256), "isolated") == estimate_memory((256, 256), False)
    assert estimate_memory((256, 256), "mirror") < estimate_memory((256, 256), "isolated")


def test_boundary_names_and_the_older_switch():
    assert boundary_of() == "periodic" and boundary_of(True) == "periodic"
    assert boundary_of(False) == "isolated" and boundary_of(False, "mirror") == "mirror"
    assert boundary_of(None, "mirror") == "mirror"
    with pytest.raises(ValueError, match="boundary must be one of periodic, mirror, isolated"):
        boundary_of(None, "open")
    with pytest.raises(ValueError, match="contradicts"):
        boundary_of(True, "mirror")
    with pytest.raises(ValueError, match="contradicts"):
        boundary_of(False, "periodic")
    with pytest.raises(ValueError, match="kernel='love'"):
        normal_operator((8, 8), 1e-6, E_STAR, boundary="mirror", kernel="love")
    assert SolverSettings().boundary == "periodic" and SolverSettings().periodic
    s = SolverSettings(boundary="mirror")
    assert not s.periodic and s.normal_kwargs()["boundary"] == "mirror"
    assert SolverSettings(periodic=False).boundary == "isolated"
    with pytest.raises(ValueError, match="contradicts"):
        SolverSettings(periodic=True, boundary="isolated")


# ----------------------------------------------------------------------------- solver
@pytest.mark.parametrize("H_", [None, 3e8])
def test_mirror_solve_is_the_periodic_solve_of_the_mirror_extension(H_):
    h = smooth_random((40, 48), 1)
    kw = dict(H=H_, dy=1.5e-6, tol=1e-10)
    a = solve_normal(h, 1e-6, E_STAR, 1e8, boundary="mirror", **kw)
    b = solve_normal(mirror_extend(h), 1e-6, E_STAR, 1e8, boundary="periodic", **kw)
    assert a.converged and b.converged
    assert a.boundary == "mirror" and not a.periodic and b.periodic
    assert np.abs(a.pressure - b.pressure[:40, :48]).max() < 1e-7 * 1e8
    assert a.alpha == b.alpha and a.plastic_fraction == b.plastic_fraction
    assert a.u0 == pytest.approx(b.u0, rel=1e-7)
    # the whole extension carries the load; the quarter is a quarter of it
    assert a.pressure.mean() == pytest.approx(1e8, rel=1e-10)


def test_mirror_solve_with_a_prebuilt_operator_and_nested_iteration():
    h = smooth_random((128, 128), 2, corr=6.0)
    op = normal_operator(h.shape, 1e-6, E_STAR, boundary="mirror")
    a = solve_normal(h, 1e-6, E_STAR, 2e8, H=H, boundary="mirror", operator=op)
    b = solve_normal(h, 1e-6, E_STAR, 2e8, H=H, boundary="mirror", nested=True)
    assert a.converged and b.converged and b.coarse_nit
    assert np.abs(a.pressure - b.pressure).max() < 1e-5 * 2e8
    with pytest.raises(ValueError, match="boundary 'isolated'"):
        solve_normal(h, 1e-6, E_STAR, 2e8, boundary="isolated", operator=op)


def test_a_flat_patch_mirrored_carries_a_uniform_pressure_without_a_plastic_rim():
    """A nominally flat, conforming patch: isolated it is Boussinesq's flat punch whose rim
    reaches the cap; its mirror extension is an infinite flat surface, uniformly loaded."""
    n, L = 64, 1e-3
    flat = np.zeros((n, n))
    mir = solve_normal(flat, L / n, E_STAR, 700e6, H=H, boundary="mirror")
    assert mir.converged and mir.alpha == 1.0 and mir.plastic_fraction == 0.0
    assert np.ptp(mir.pressure) < 1e-9 * 700e6
    e = edge_plasticity(mir.pressure, H)
    assert e.rim_capped == 0.0 == e.centre_capped and not e.punch_edge
    iso = solve_normal(flat, L / n, E_STAR, 700e6, H=H, boundary="isolated")
    e = edge_plasticity(iso.pressure, H)
    assert e.punch_edge and e.rim_capped > 0.9 and e.centre_capped == 0.0


def test_a_height_step_at_the_seam_loads_the_periodic_edge_not_the_mirrored_one():
    """h = A (1 - cos(pi x / L)) / 2: flat at both edges but A higher at one: a step of A at
    the periodic seam. Its mirror extension is one cosine of wavenumber pi / L, whose full
    contact is Westergaard's exact p = p_mean - (E* q A / 4) cos(q x) (the discrete patch
    samples that cosine, so the solve must reproduce it to the tolerance)."""
    n, L = 64, 1e-3
    dx = L / n
    q = np.pi / L
    A = 4 * 100e6 / (E_STAR * q)  # amplitude of the pressure wave: 100 MPa
    x = (np.arange(n) + 0.5) * dx
    h = np.broadcast_to((A * (1 - np.cos(q * x)) / 2)[:, None], (n, n))
    mir = solve_normal(h, dx, E_STAR, 400e6, H=H, boundary="mirror", tol=1e-10)
    exact = 400e6 - 100e6 * np.cos(q * x)
    assert mir.converged and mir.alpha == 1.0 and mir.plastic_fraction == 0.0
    assert np.abs(mir.pressure - exact[:, None]).max() < 1e-6 * 100e6
    per = solve_normal(h, dx, E_STAR, 400e6, H=H, boundary="periodic")
    assert per.converged
    rim = np.concatenate([per.pressure[:2], per.pressure[-2:]])
    assert (rim >= H * (1 - 1e-6)).any()  # the seam's step is driven into the cap
    assert per.pressure[8:-8].max() < H  # away from it the contact stays elastic
    assert np.abs(per.pressure - exact[:, None]).max() > 100e6


def test_volume_conservation_and_the_pair_with_the_mirror_boundary():
    wp = smooth_random((32, 32), 4, rq=5e-7)
    tl = smooth_random((32, 32), 5, rq=1e-7)
    r = solve_normal_pair(wp, tl, 2e-6, E_STAR, 400e6, H=H, boundary="mirror")
    assert r.converged and r.plastic_fraction > 0
    assert r.deformed_workpiece.sum() == pytest.approx(
        wp.sum(), rel=1e-10, abs=1e-10 * np.abs(wp).sum()
    )


# ----------------------------------------------------------------------------- criteria
def _curve(p_hist, ps, alphas):
    return ReloadCurve(p_hist, np.array(ps, float), np.array(alphas, float))


def test_reload_deficit_against_the_first_loading():
    p1 = np.array([10e6, 20e6, 40e6, 80e6])
    a1 = np.array([0.1, 0.2, 0.4, 0.8])
    above = [_curve(80e6, [20e6, 40e6], [0.25, 0.5])]
    d = reload_deficit(p1, a1, above)
    assert d.worst == pytest.approx(-0.05) and d.points == 2 and d.p == 20e6
    below = above + [_curve(40e6, [20e6, 30e6], [0.15, 0.35])]
    d = reload_deficit(p1[::-1], a1[::-1], below)  # any order
    assert d.worst == pytest.approx(0.05) and (d.p_hist, d.p) == (40e6, 20e6)
    # between the points: the monotone interpolant in log p (exact for alpha linear in log p)
    d = reload_deficit([10e6, 100e6], [0.2, 0.4], [_curve(100e6, [np.sqrt(1e15)], [0.28])])
    assert d.worst == pytest.approx(0.02)
    d = reload_deficit(p1, a1, [_curve(80e6, [5e6, 20e6], [0.0, 0.2])])  # 5 MPa: out of range
    assert d.points == 1 and d.worst == pytest.approx(0.0)
    with pytest.raises(ValueError, match="no reload point"):
        reload_deficit(p1, a1, [_curve(80e6, [5e6], [0.0])])
    with pytest.raises(ValueError, match="distinct"):
        reload_deficit([1e6, 1e6], [0.1, 0.1], above)


def test_reload_grid_change_matches_points_by_pressure():
    a = [_curve(100e6, [10e6, 50e6], [0.10, 0.50]), _curve(200e6, [20e6], [0.3])]
    b = [_curve(100e6, [10e6 * (1 + 1e-12), 50e6], [0.12, 0.49]), _curve(300e6, [20e6], [0.9])]
    g = reload_grid_change(a, b)
    assert g.points == 2 and g.worst == pytest.approx(0.02) and g.p == 10e6
    with pytest.raises(ValueError, match="no point in common"):
        reload_grid_change(a, [_curve(300e6, [20e6], [0.9])])


def test_a_solver_settings_record_is_not_silently_changed_by_replace():
    s = SolverSettings(boundary="mirror")
    assert dataclasses.replace(s, tol=1e-6).boundary == "mirror"

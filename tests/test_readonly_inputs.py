"""Every public entry point of halfspace_calib that takes arrays accepts read-only arrays.

``Surface.heights`` is read-only by design; the numba kernels of the normal solver once were
typed writable, so ``solve_normal(surface.heights, ...)`` raised numba's ``TypeError`` (issue 20,
item 1). Each call below runs once with read-only and once with writable copies of the same
input, and the results must be identical (not merely close: the same arithmetic runs).
"""

import numpy as np
import pytest

import halfspace_calib as hc
from halfspace_calib.contact import _kernels as K
from halfspace_calib.contact import cerruti_coefficients, tangential_bound
from halfspace_calib.contact._box_cg import project_box_sum, volume_conserving_lift
from halfspace_calib.pipeline.law.fit import ReloadCurve

E_STAR = 1.15e11
H = 2.0e9
N = 16


def ro(a):
    """A read-only copy of ``a``."""
    a = np.array(a, dtype=float)
    a.setflags(write=False)
    return a


def rw(a):
    return np.array(a, dtype=float)


@pytest.fixture(scope="module")
def surf():
    return hc.dc04_edt_like(N, seed=3)


def _same(a, b):
    if isinstance(a, tuple | list):
        assert len(a) == len(b)
        for x, y in zip(a, b, strict=True):
            _same(x, y)
    elif isinstance(a, np.ndarray | float | int):
        np.testing.assert_array_equal(a, b)
    elif hasattr(a, "__dataclass_fields__"):
        for name in a.__dataclass_fields__:
            _same(getattr(a, name), getattr(b, name))
    else:
        assert a == b


def test_surface_heights_are_read_only(surf):
    # the premise of the tests below: a Surface hands out a read-only array
    assert not surf.heights.flags.writeable


def test_solve_normal_with_surface_heights(surf):
    """The call of issue 20: the read-only ``Surface.heights`` straight into the solver."""
    p_init = ro(np.full(surf.shape, 80e6))
    for periodic in (True, False):
        a = hc.solve_normal(surf.heights, surf.dx, E_STAR, 100e6, H=H, periodic=periodic)
        b = hc.solve_normal(rw(surf.heights), surf.dx, E_STAR, 100e6, H=H, periodic=periodic)
        assert a.converged and b.converged
        _same(a, b)
        c = hc.solve_normal(surf.heights, surf.dx, E_STAR, 100e6, H=H, p_init=p_init)
        assert c.converged


def test_solve_normal_pair_read_only(surf):
    tool = hc.tool_like(N, seed=4)
    a = hc.solve_normal_pair(surf.heights, tool.heights, surf.dx, E_STAR, 200e6, H=H)
    b = hc.solve_normal_pair(rw(surf.heights), rw(tool.heights), surf.dx, E_STAR, 200e6, H=H)
    assert a.converged
    _same(a, b)
    _same(
        hc.composite_heights(surf.heights, tool.heights),
        hc.composite_heights(rw(surf.heights), rw(tool.heights)),
    )


def test_operator_and_coefficients_read_only(surf):
    x = ro(np.linspace(-3e-6, 3e-6, 7))[:, None]
    y = ro(np.linspace(-2e-6, 2e-6, 5))[None, :]
    _same(
        hc.love_coefficients(x, y, 1e-6, 1e-6, E_STAR),
        hc.love_coefficients(rw(x), rw(y), 1e-6, 1e-6, E_STAR),
    )
    _same(
        cerruti_coefficients(x, y, 2e-6, 2e-6, E_STAR, 1.1e11),
        cerruti_coefficients(rw(x), rw(y), 2e-6, 2e-6, E_STAR, 1.1e11),
    )
    p = ro(np.abs(surf.heights) * 1e14)
    for periodic in (True, False):
        op = hc.normal_operator(surf.shape, surf.dx, E_STAR, periodic=periodic)
        _same(op.apply(p), op.apply(rw(p)))
        _same(op.backward(op.forward(p)), op.backward(op.forward(rw(p))))
        spec = op.forward(p)
        spec.setflags(write=False)
        _same(op.backward(spec), op.backward(op.forward(rw(p))))
        _same(op.apply_inverse(p), op.apply_inverse(rw(p)))
        rows, cols = np.array([1, 2]), np.array([3, 4])
        rows.setflags(write=False)
        cols.setflags(write=False)
        _same(
            op.apply_sparse(rows, cols, ro([1e6, 2e6])), op.apply_sparse([1, 2], [3, 4], [1e6, 2e6])
        )
    kern = ro(hc.normal_operator(surf.shape, surf.dx, E_STAR).kernel)
    _same(
        hc.InfluenceOperator(kern, surf.shape, True).apply(p),
        hc.InfluenceOperator(rw(kern), surf.shape, True).apply(p),
    )


def test_tangential_read_only(surf):
    p = hc.solve_normal(surf.heights, surf.dx, E_STAR, 200e6, H=H).pressure
    kw = dict(delta=2e-8, m=0.3, sigma_y=H / 3)
    a = hc.solve_tangential(ro(p), surf.dx, E_STAR, 1.1e11, **kw)
    b = hc.solve_tangential(rw(p), surf.dx, E_STAR, 1.1e11, **kw)
    _same(a, b)
    _same(
        tangential_bound(ro(p), m=0.3, sigma_y=H / 3), tangential_bound(rw(p), m=0.3, sigma_y=H / 3)
    )


def test_projections_read_only():
    rng = np.random.default_rng(0)
    y = rng.normal(size=50)
    _same(project_box_sum(ro(y), 20.0, 1.5), project_box_sum(rw(y), 20.0, 1.5))
    gap = np.abs(y)
    _same(volume_conserving_lift(ro(gap), 3.0), volume_conserving_lift(rw(gap), 3.0))


def test_kernels_read_only_inputs():
    """Each numba kernel takes read-only arrays for every argument it does not write."""
    rng = np.random.default_rng(1)
    p = ro(np.clip(rng.normal(1.0, 1.0, 40), 0.0, 2.0))
    u, h, z, g, d = (ro(rng.normal(size=40)) for _ in range(5))
    pmax = 2.0
    _same(K.free_gap_sum(u, h, p, pmax), K.free_gap_sum(rw(u), rw(h), rw(p), pmax))
    o1, o2 = np.empty(40), np.empty(40)
    _same(
        K.gap_and_residual(u, h, p, pmax, 0.1, o1),
        K.gap_and_residual(rw(u), rw(h), rw(p), pmax, 0.1, o2),
    )
    _same(o1, o2)
    t1, t2 = rw(d), rw(d)
    _same(K.direction(z, g, p, pmax, 0.5, t1), K.direction(rw(z), rw(g), rw(p), pmax, 0.5, t2))
    _same(t1, t2)
    _same(
        K.step_project(p, z, g, d, 0.3, pmax, o1),
        K.step_project(rw(p), rw(z), rw(g), rw(d), 0.3, pmax, o2),
    )
    _same(o1, o2)
    K.active_gap(g, p, pmax, o1)
    K.active_gap(rw(g), rw(p), pmax, o2)
    _same(o1, o2)
    _same(K.dot_free(z, g, p, pmax), K.dot_free(rw(z), rw(g), rw(p), pmax))


def test_surfaces_and_fits_read_only(surf):
    s2 = hc.Surface(ro(rw(surf.heights)), surf.dx, surf.dy, periodic=surf.periodic)
    _same(hc.roughness(s2), hc.roughness(surf))
    _same(hc.level(s2).heights, hc.level(surf).heights)
    _same(hc.block_average(s2, N // 2).heights, hc.block_average(surf, N // 2).heights)
    p = np.array([10e6, 50e6, 100e6, 200e6, 400e6, 600e6])
    alpha = 0.9 * (1 - np.exp(-((1.5 * p / H) ** 0.8)))
    a = hc.fit_first_loading(ro(p), ro(alpha), H)
    b = hc.fit_first_loading(rw(p), rw(alpha), H)
    _same(a.C1, b.C1)
    _same(a.n1, b.n1)
    pr = ro([60e6, 120e6, 240e6, 360e6])
    ar = ro(0.9 * (1 - np.exp(-((2.0 * pr / H) ** 0.9))))
    fa = hc.fit_reload([ReloadCurve(400e6, pr, ar)], H, a.C1, a.n1)
    fb = hc.fit_reload([ReloadCurve(400e6, rw(pr), rw(ar))], H, a.C1, a.n1)
    _same(fa.C2, fb.C2)
    _same(fa.n2, fb.n2)


def test_sliding_sweep_read_only(surf):
    tool = hc.tool_like(N, seed=4).heights[: N // 2]
    tool.setflags(write=False)
    a = hc.sliding_sweep(surf.heights, tool, surf.dx, 200e6, positions=2)
    b = hc.sliding_sweep(rw(surf.heights), rw(tool), surf.dx, 200e6, positions=2)
    _same(a.alpha, b.alpha)

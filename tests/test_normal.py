import numpy as np
import pytest
from scipy import optimize

from halfspace_calib.contact.influence import normal_operator
from halfspace_calib.contact.normal import (
    composite_heights,
    composite_modulus,
    solve_normal,
    solve_normal_pair,
)
from halfspace_calib.contact.reference import (
    fourier_mode_displacement,
    hertz,
    hertz_pressure,
    westergaard_contact_halfwidth,
    westergaard_full_contact_pressure,
    westergaard_pressure,
)

E_STAR = composite_modulus(210e9, 0.3, 210e9, 0.3)
H_DC04 = 800e6


def rough_surface(n, seed, rq=1e-6, hurst=0.8, qr_frac=0.0):
    """Self-affine periodic random surface (test helper, numpy only): PSD ~ q^-(2 + 2 Hurst)."""
    rng = np.random.default_rng(seed)
    qx = np.fft.fftfreq(n)[:, None]
    qy = np.fft.rfftfreq(n)[None, :]
    q = np.hypot(qx, qy)
    amp = np.where(q > 0, np.maximum(q, qr_frac + 1e-12) ** (-(1 + hurst)), 0.0)
    spec = amp * (rng.standard_normal(q.shape) + 1j * rng.standard_normal(q.shape))
    h = np.fft.irfft2(spec, s=(n, n))
    return h * (rq / h.std())


# ----------------------------------------------------------------------------- Hertz
@pytest.mark.parametrize("n", [256, 255])
def test_hertz_non_periodic(n):
    L, R = 1e-3, 5e-3
    dx = L / n
    x = (np.arange(n) - (n - 1) / 2) * dx
    X, Y = np.meshgrid(x, x, indexing="ij")
    h = -(X**2 + Y**2) / (2 * R)
    a = L / 4
    F = 4 * E_STAR * a**3 / (3 * R)
    ref = hertz(F, R, E_STAR)
    res = solve_normal(h, dx, E_STAR, F / L**2, periodic=False)
    assert res.converged, res.message
    a_num = np.sqrt(res.alpha * L**2 / np.pi)
    assert a_num == pytest.approx(ref.a, rel=0.01)
    assert res.pressure.max() == pytest.approx(ref.p0, rel=0.01)
    assert res.u0 == pytest.approx(ref.delta, rel=0.01)
    p_ref = hertz_pressure(np.hypot(X, Y), F, R, E_STAR)
    assert np.linalg.norm(res.pressure - p_ref) / np.linalg.norm(p_ref) < 0.01
    inner = np.hypot(X, Y) < 0.9 * ref.a
    assert np.abs(res.pressure - p_ref)[inner].max() < 0.01 * ref.p0
    # load balance and the complementarity of the converged state
    assert res.pressure.mean() == pytest.approx(F / L**2, rel=1e-12)
    assert np.all(res.gap[res.pressure > 0] < 1e-6 * ref.delta)
    assert res.gap.min() > -1e-6 * ref.delta


def test_hertz_elasto_plastic_cap():
    """H below the Hertz peak: a central disc at the cap, load balance, u_pl on the cap only."""
    n, L, R = 128, 1e-3, 5e-3
    dx = L / n
    x = (np.arange(n) - (n - 1) / 2) * dx
    X, Y = np.meshgrid(x, x, indexing="ij")
    r = np.hypot(X, Y)
    h = -(r**2) / (2 * R)
    a = L / 4
    F = 4 * E_STAR * a**3 / (3 * R)
    p0 = hertz(F, R, E_STAR).p0
    H = 0.8 * p0
    res = solve_normal(h, dx, E_STAR, F / L**2, H=H, periodic=False, tol=1e-10)
    assert res.converged, res.message
    p = res.pressure
    cap = p >= H
    assert cap.any() and res.plastic_fraction == pytest.approx(cap.mean())
    assert p.max() <= H and p.min() >= 0
    assert p.mean() == pytest.approx(F / L**2, rel=1e-12)
    # the capped zone is a centred disc inside the contact
    assert r[cap].max() < r[(p > 0) & ~cap].min() + 1.5 * dx
    # plastic displacement lives on the cap and is the overlap; the total gap closes there
    assert np.all(res.plastic_displacement[~cap] == 0)
    assert res.plastic_displacement[cap].min() >= 0
    assert np.abs(res.gap[p > 0]).max() < 1e-8 * hertz(F, R, E_STAR).delta
    # more contact than elastic Hertz (load redistributed outwards)
    el = solve_normal(h, dx, E_STAR, F / L**2, periodic=False)
    assert res.alpha > el.alpha


# ----------------------------------------------------------------------------- Westergaard
@pytest.mark.parametrize("ratio", [0.3, 0.7])
def test_westergaard_partial_contact(ratio):
    n, lam, g = 256, 1e-4, 1e-7
    dx = lam / n
    x = np.arange(n) * dx
    h = (g * np.cos(2 * np.pi * x / lam))[:, None] * np.ones((1, 4))
    ps = westergaard_full_contact_pressure(g, lam, E_STAR)
    res = solve_normal(h, dx, E_STAR, ratio * ps)
    assert res.converged, res.message
    p_ref = westergaard_pressure(x, ratio * ps, g, lam, E_STAR)[:, None]
    assert np.linalg.norm(res.pressure - p_ref) / np.linalg.norm(p_ref) < 0.01
    a = westergaard_contact_halfwidth(ratio * ps, g, lam, E_STAR)
    assert abs(res.alpha - 2 * a / lam) < 2.0 / n


def test_westergaard_full_contact_and_fourier_mode():
    n, lam, g = 64, 1e-4, 1e-7
    dx = lam / n
    x = np.arange(n) * dx
    h = (g * np.cos(2 * np.pi * x / lam))[:, None] * np.ones((1, 8))
    ps = westergaard_full_contact_pressure(g, lam, E_STAR)
    res = solve_normal(h, dx, E_STAR, 1.5 * ps)
    assert res.converged and res.alpha == 1.0
    np.testing.assert_allclose(
        res.pressure,
        westergaard_pressure(x, 1.5 * ps, g, lam, E_STAR)[:, None] * np.ones((1, 8)),
        rtol=1e-10,
    )
    # displacement of the single mode p* cos(q x): 2 p*/(E* q) (periodic gauge: zero mean)
    amp = fourier_mode_displacement(ps, 2 * np.pi / lam, E_STAR)
    np.testing.assert_allclose(
        res.elastic_displacement,
        (amp * np.cos(2 * np.pi * x / lam))[:, None] * np.ones((1, 8)),
        atol=1e-10 * amp,
    )
    # just above the onset: still full contact; just below: not
    assert solve_normal(h, dx, E_STAR, 1.001 * ps).alpha == 1.0
    assert solve_normal(h, dx, E_STAR, 0.95 * ps).alpha < 1.0


# ----------------------------------------------------------------------------- oracle
def _oracle(h, dx, E, p_mean, H, periodic):
    """Independent solution of the box QP: L-BFGS-B on the dense Love matrix at fixed approach,
    the approach (the multiplier of the load) by Brent's method on the total load."""
    op = normal_operator(h.shape, dx, E, periodic=periodic, kernel="love")
    C = op.dense_matrix() * E / dx
    hv = h.ravel() * E / dx / p_mean
    n = h.size
    ub = None if H is None else H / p_mean
    start = np.ones(n)

    def box_solution(lam):
        sol = optimize.minimize(
            lambda s: (0.5 * s @ C @ s - s @ (hv + lam), C @ s - hv - lam),
            start,
            jac=True,
            bounds=[(0, ub)] * n,
            method="L-BFGS-B",
            options={"ftol": 1e-15, "gtol": 1e-12, "maxiter": 5000},
        )
        return sol.x

    lam = optimize.brentq(lambda lam: box_solution(lam).sum() - n, -1e4, 1e4, xtol=1e-13)
    return box_solution(lam).reshape(h.shape) * p_mean


@pytest.mark.parametrize("H", [None, 500e6])
@pytest.mark.parametrize("periodic", [True, False])
def test_against_qp_oracle(H, periodic):
    n, dx = 10, 2e-6
    h = rough_surface(n, seed=5, rq=0.3e-6)
    pm = 200e6
    res = solve_normal(h, dx, E_STAR, pm, H=H, periodic=periodic, kernel="love", tol=1e-11)
    assert res.converged, res.message
    ref = _oracle(h, dx, E_STAR, pm, H, periodic)
    np.testing.assert_allclose(res.pressure, ref, atol=1e-5 * pm)


# ----------------------------------------------------------------------------- rough surfaces
@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("p_mean", [100e6, 400e6, 700e6])
def test_rough_capped_invariants(seed, p_mean):
    n, L = 64, 2.11e-3
    h = rough_surface(n, seed)
    res = solve_normal(h, L / n, E_STAR, p_mean, H=H_DC04, tol=1e-9)
    assert res.converged, res.message
    p = res.pressure
    assert res.alpha >= p_mean / H_DC04
    assert p.min() >= 0 and p.max() <= H_DC04
    assert p.mean() == pytest.approx(p_mean, rel=1e-12)
    # complementarity, in length units relative to Rq
    rq = h.std()
    gap = res.gap
    assert np.abs(gap[p > 0]).max() < 1e-6 * rq
    assert gap[p == 0].min() > -1e-6 * rq
    assert res.residual < 1e-9


def test_alpha_tends_to_one_near_hardness():
    h = rough_surface(64, 3)
    res = solve_normal(h, 2.11e-3 / 64, E_STAR, 0.995 * H_DC04, H=H_DC04)
    assert res.converged, res.message
    assert 0.995 <= res.alpha <= 1.0


def test_elastic_rough_periodic_equals_exact_recurrence():
    """The spectral recurrence gives the same field as exact recomputation, and the
    preconditioned CG the same as the plain Polonsky-Keer iteration, in fewer iterations."""
    h = rough_surface(64, 4)
    kw = dict(dx=2.11e-3 / 64, E_star=E_STAR, p_mean=300e6, tol=1e-10)
    for H in (None, H_DC04):
        fast = solve_normal(h, H=H, **kw)
        exact = solve_normal(h, H=H, refresh=1, **kw)
        plain = solve_normal(h, H=H, precondition=False, **kw)
        assert fast.converged and exact.converged and plain.converged
        np.testing.assert_allclose(fast.pressure, exact.pressure, atol=1e-6 * 300e6)
        np.testing.assert_allclose(plain.pressure, fast.pressure, atol=1e-6 * 300e6)
        assert fast.nit < plain.nit


def test_volume_conservation_and_deformed_surface():
    n = 64
    h = rough_surface(n, 6)
    dx = 2.11e-3 / n
    res = solve_normal(h, dx, E_STAR, 200e6, H=H_DC04)
    assert (
        res.converged and res.removed_volume > 0 and "raises the whole surface" not in res.message
    )
    v0 = np.sum(h - h.min())
    assert abs(res.deformed_heights.sum() - h.sum()) <= 1e-10 * v0
    assert res.removed_volume == pytest.approx(res.plastic_displacement.sum() * dx * dx)
    # contact elements only lose height; out-of-contact ones rise evenly, each at most up to the
    # loaded tool (its gap): min(c, gap)
    out = res.pressure == 0
    rise = res.deformed_heights[out] - h[out]
    gap = res.gap[out]
    assert np.all(rise > 0) and np.all(rise <= gap * (1 + 1e-12))
    c = rise.max()
    np.testing.assert_allclose(rise, np.minimum(gap, c), rtol=1e-12, atol=1e-18)
    off = solve_normal(h, dx, E_STAR, 200e6, H=H_DC04, volume_conservation=False)
    np.testing.assert_allclose(off.deformed_heights, h - off.plastic_displacement)


def test_reload_on_deformed_surface_is_elastic():
    """Reloading the flattened surface (no volume transfer) to p_hist reproduces the pressure of
    the first loading without new plastic flow; unloading to p < p_hist gives alpha below."""
    n = 64
    h = rough_surface(n, 7)
    dx = 2.11e-3 / n
    first = solve_normal(h, dx, E_STAR, 400e6, H=H_DC04, volume_conservation=False, tol=1e-10)
    again = solve_normal(first.deformed_heights, dx, E_STAR, 400e6, H=H_DC04, tol=1e-10)
    assert again.converged
    np.testing.assert_allclose(again.pressure, first.pressure, atol=1e-5 * 400e6)
    assert again.removed_volume < 1e-6 * first.removed_volume
    lower = solve_normal(first.deformed_heights, dx, E_STAR, 200e6, H=H_DC04)
    assert lower.removed_volume == 0.0 and lower.alpha < first.alpha


def test_warm_start():
    h = rough_surface(64, 8)
    kw = dict(dx=2.11e-3 / 64, E_star=E_STAR, H=H_DC04, tol=1e-9)
    cold = solve_normal(h, p_mean=310e6, **kw)
    prev = solve_normal(h, p_mean=300e6, **kw)
    warm = solve_normal(h, p_mean=310e6, p_init=prev.pressure, **kw)
    assert warm.converged and warm.nit < cold.nit
    np.testing.assert_allclose(warm.pressure, cold.pressure, atol=1e-6 * 310e6)


def test_not_converged_is_reported():
    h = rough_surface(64, 9)
    res = solve_normal(h, 2.11e-3 / 64, E_STAR, 300e6, maxiter=3)
    assert not res.converged and res.nit == 3
    assert "NOT converged" in res.message and res.residual >= 1e-8
    assert np.all(np.isfinite(res.pressure))


# ----------------------------------------------------------------------------- two surfaces
def test_composite_modulus():
    assert composite_modulus(210e9, 0.3, 210e9, 0.3) == pytest.approx(210e9 / (2 * 0.91))
    assert composite_modulus(210e9, 0.3, np.inf, 0.3) == pytest.approx(210e9 / 0.91)
    with pytest.raises(ValueError, match="nu1"):
        composite_modulus(210e9, 0.7, 210e9, 0.3)
    with pytest.raises(ValueError, match="E2"):
        composite_modulus(210e9, 0.3, -1.0, 0.3)


def test_pair_deforms_workpiece_only():
    n = 64
    tool = rough_surface(n, 10, rq=0.16e-6)
    work = rough_surface(n, 11, rq=1.267e-6)
    dx = 2.11e-3 / n
    res = solve_normal_pair(work, tool, dx, E_STAR, 300e6, H=H_DC04)
    single = solve_normal(composite_heights(work, tool), dx, E_STAR, 300e6, H=H_DC04)
    np.testing.assert_array_equal(res.pressure, single.pressure)
    np.testing.assert_allclose(res.deformed_workpiece + tool, res.deformed_heights, atol=1e-18)
    assert abs(res.deformed_workpiece.sum() - work.sum()) <= 1e-10 * np.sum(work - work.min())
    with pytest.raises(ValueError, match="same shape"):
        composite_heights(work[:, :-1], tool)


# ----------------------------------------------------------------------------- input checks
def test_input_checks():
    h = rough_surface(16, 0)
    dx = 1e-5
    with pytest.raises(ValueError, match="p_mean must be < H"):
        solve_normal(h, dx, E_STAR, 900e6, H=800e6)
    with pytest.raises(ValueError, match="p_mean"):
        solve_normal(h, dx, E_STAR, -1.0)
    with pytest.raises(ValueError, match="E_star"):
        solve_normal(h, dx, 0.0, 1e6)
    with pytest.raises(ValueError, match="dx"):
        solve_normal(h, np.nan, E_STAR, 1e6)
    bad = h.copy()
    bad[0, 0] = np.nan
    with pytest.raises(ValueError, match="finite"):
        solve_normal(bad, dx, E_STAR, 1e6)
    with pytest.raises(ValueError, match="2-D"):
        solve_normal(h[0], dx, E_STAR, 1e6)
    with pytest.raises(ValueError, match="tol"):
        solve_normal(h, dx, E_STAR, 1e6, tol=0.0)
    with pytest.raises(ValueError, match="p_init"):
        solve_normal(h, dx, E_STAR, 1e6, p_init=np.ones((3, 3)))
    with pytest.raises(ValueError, match="max_memory"):
        solve_normal(np.zeros((4096, 4096)), dx, E_STAR, 1e6, max_memory=2**30)
    with pytest.raises(ValueError, match="operator"):
        solve_normal(h, dx, E_STAR, 1e6, operator=normal_operator((8, 8), dx, E_STAR))


def test_flat_surface_uniform_pressure():
    res = solve_normal(np.zeros((16, 16)), 1e-5, E_STAR, 123e6, H=H_DC04)
    assert res.converged and res.alpha == 1.0
    np.testing.assert_allclose(res.pressure, 123e6, rtol=1e-14)


def test_volume_conserving_lift_water_filling():
    from halfspace_calib.contact.normal import volume_conserving_lift

    gap = np.array([0.0, 1.0, 2.0, 4.0, 0.5])
    lift, rest = volume_conserving_lift(gap, 3.0)
    assert rest == 0.0 and lift.sum() == pytest.approx(3.0, rel=1e-15)
    c = lift.max()
    np.testing.assert_allclose(lift, np.minimum(gap, c))
    assert c == pytest.approx((3.0 - 0.5) / 3)  # the 0.5 valley fills, three share the rest
    lift, rest = volume_conserving_lift(gap, 10.0)  # more than the valleys hold
    np.testing.assert_array_equal(lift, gap)
    assert rest == pytest.approx(2.5)


# ----------------------------------------------------------------------------- numba kernels
def _kernel_data(seed, n=500):
    rng = np.random.default_rng(seed)
    H = 1.0
    p = rng.random(n) * 1.4 - 0.2
    p = np.clip(p, 0.0, H)  # a mix of zeros, caps and free values
    return rng, H, p, rng.standard_normal(n), rng.standard_normal(n), rng.standard_normal(n)


@pytest.mark.parametrize("pmax_is_inf", [False, True])
def test_kernels_against_numpy(pmax_is_inf):
    from halfspace_calib.contact import _kernels as K

    rng, H, p, u, h, t0 = _kernel_data(1)
    pmax = np.inf if pmax_is_inf else H
    free = (p > 0) & (p < pmax)
    s, nf = K.free_gap_sum(u, h, p, pmax)
    assert nf == free.sum() and s == pytest.approx((u - h)[free].sum(), rel=1e-12)

    g = np.empty_like(u)
    viol, G = K.gap_and_residual(u, h, p, pmax, 0.3, g)
    g_ref = u - h + 0.3
    np.testing.assert_allclose(g, g_ref, rtol=1e-15)
    r = np.where(p <= 0, np.minimum(g_ref, 0), np.where(p >= pmax, np.maximum(g_ref, 0), g_ref))
    assert viol == pytest.approx(np.sum(r**2), rel=1e-12)
    assert G == pytest.approx(np.sum(g_ref[free] ** 2), rel=1e-12)

    t = t0.copy()
    z = rng.standard_normal(p.size)
    gt = K.direction(z, g, p, pmax, 0.7, t)
    t_ref = np.where(free, z + 0.7 * t0, 0.0)
    t_ref[free] -= t_ref[free].mean()
    np.testing.assert_allclose(t, t_ref, atol=1e-14)
    assert gt == pytest.approx(np.dot(g, t_ref), rel=1e-12)

    q = np.empty_like(p)
    tau = 0.2
    released, changed, sfree, mfree, ncap = K.step_project(p, t, g, z, tau, pmax, q)
    raw = p - tau * t
    rel = ((p <= 0) & (g < 0)) | ((p >= pmax) & (g > 0))
    q_ref = np.clip(np.where(rel, p - tau * z, raw), 0.0, pmax)
    np.testing.assert_allclose(q, q_ref, rtol=1e-15)
    fq = (q_ref > 0) & (q_ref < pmax)
    assert released == rel.any() and changed == bool(np.any(q_ref != raw))
    assert sfree == pytest.approx(q_ref[fq].sum(), rel=1e-12)
    assert mfree == q_ref[fq].max() and ncap == np.sum(q_ref >= pmax)

    q2 = q.copy()
    K.scale_free(q2, 0.9, pmax)
    np.testing.assert_allclose(q2, np.where(fq, 0.9 * q, q), rtol=1e-15)

    # load restoration: NumPy oracle by bisection on the factor c of sum(min(c q, pmax)) = target
    n_q = np.count_nonzero(q)
    for target in (0.5 * q.sum(), 1.3 * q.sum(), 0.98 * n_q * pmax, 1.01 * n_q * pmax):
        if not np.isfinite(target):
            continue
        q2 = q.copy()
        ok, c, passes = K.restore_load(q2, target, pmax)
        capped = q >= pmax
        n_cap, n_pos = np.count_nonzero(capped), np.count_nonzero(q > 0)
        if pmax < np.inf and not (n_cap * pmax < target < n_pos * pmax):
            assert not ok and np.array_equal(q2, q)  # untouched when the load cannot be carried
            continue

        def load(c, capped=capped):  # elements at the cap stay there, the others scale
            return np.where(capped, pmax, np.minimum(c * q, pmax)).sum()

        lo, hi = 0.0, 1.0
        while load(hi) < target:
            hi *= 2.0
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if load(mid) < target else (lo, mid)
        ref = np.where(capped, pmax, np.minimum(hi * q, pmax))
        assert ok and c == pytest.approx(hi, rel=1e-9)
        np.testing.assert_allclose(q2, ref, rtol=1e-9, atol=1e-12 * (pmax if pmax < np.inf else 1))
        assert q2.sum() == pytest.approx(target, rel=1e-12)
        assert (passes == 1) == bool(np.all(hi * q[(q > 0) & ~capped] < pmax))

    ga = np.empty_like(g)
    K.active_gap(g, p, pmax, ga)
    np.testing.assert_array_equal(ga, np.where(free | rel, g, 0.0))
    assert K.dot_free(g, z, p, pmax) == pytest.approx(np.dot(g[free], z[free]), rel=1e-12)


@pytest.mark.parametrize(
    "q, target",
    [
        ((236294556.12002784, 147632542.5886099), 1299825455.186936),
        ((535674106.5603882, 150752807.9812582), 1025141079.0777335),
    ],
)
def test_load_restoration_ends_when_the_cap_test_and_its_threshold_disagree_by_an_ulp(q, target):
    """Water filling whose first factor ``c`` gives ``c * max(q) == pmax`` after rounding while
    ``pmax / c > max(q)``: the capped set must still grow (it looped forever on a real file's
    solve). Run in a child process so that a livelock fails instead of hanging the suite."""
    import subprocess
    import sys

    code = (
        "import numpy as np; from halfspace_calib.contact import _kernels as K; "
        f"q = np.array({list(q)!r}); ok, c, n = K.restore_load(q, {target!r}, 800e6); "
        "print(ok, repr(float(c)), n, repr(float(q[0])), repr(float(q[1])))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True
    ).stdout.split()
    assert out[0] == "True" and int(out[2]) == 2  # one pass finds the cap, the second checks
    c, q0, q1 = float(out[1]), float(out[3]), float(out[4])
    assert q0 == 800e6 and q1 == pytest.approx(target - 800e6, rel=1e-12)
    assert c == pytest.approx((target - 800e6) / q[1], rel=1e-12)


@pytest.mark.parametrize("H", [None, 0.5])
def test_project_box_sum_kernel_against_numpy_bisection(H):
    """The numba projection against an independent NumPy oracle (bisection on ``lam``)."""
    from halfspace_calib.contact.normal import project_box_sum

    rng = np.random.default_rng(7)
    for n, target in ((40, 7.0), (300, 0.1), (300, 120.0)):
        y = rng.standard_normal(n) * 3.0
        if H is not None and not target < n * H:
            continue
        ub = np.inf if H is None else H
        lo, hi = -y.max(), target - y.min() + (0 if H is None else H)
        for _ in range(300):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if np.clip(y + mid, 0, ub).sum() < target else (lo, mid)
        ref = np.clip(y + 0.5 * (lo + hi), 0, ub)
        np.testing.assert_allclose(project_box_sum(y, target, H), ref, atol=1e-12 * max(1, target))


def test_project_box_sum_is_the_projection():
    from halfspace_calib.contact.normal import project_box_sum

    rng = np.random.default_rng(12)
    y = rng.standard_normal(40)
    for H in (None, 0.5):
        target = 7.0
        x = project_box_sum(y, target, H)
        ub = np.inf if H is None else H
        assert x.sum() == pytest.approx(target, rel=1e-13)
        assert x.min() >= 0 and x.max() <= ub
        # optimality: no feasible pairwise exchange reduces |x - y|^2 (KKT of the projection):
        # y - x is constant on free elements, <= it at zeros, >= it at the cap
        d = y - x
        free = (x > 0) & (x < ub)
        lam = d[free].mean()
        np.testing.assert_allclose(d[free], lam, atol=1e-12)
        assert np.all(d[x == 0] <= lam + 1e-12)
        if H is not None:
            assert np.all(d[x >= ub] >= lam - 1e-12)


def test_rectangular_elements_transpose_symmetry():
    """2a x 2b elements: transposing the surface and swapping dx, dy transposes the answer."""
    h = rough_surface(48, 13)[:, :30]
    for periodic in (True, False):
        a = solve_normal(h, 1e-5, E_STAR, 2e8, dy=2.5e-5, H=6e8, periodic=periodic, tol=1e-10)
        b = solve_normal(h.T, 2.5e-5, E_STAR, 2e8, dy=1e-5, H=6e8, periodic=periodic, tol=1e-10)
        assert a.converged and b.converged
        np.testing.assert_allclose(a.pressure, b.pressure.T, atol=1e-6 * 2e8)
        assert a.alpha == b.alpha


def test_tiny_load_single_asperity():
    h = rough_surface(32, 14)
    res = solve_normal(h, 1e-5, E_STAR, 1.0, H=H_DC04)
    assert res.converged and res.alpha == 1 / h.size
    assert res.pressure.flat[np.argmax(h)] == pytest.approx(h.size * 1.0)


def test_single_precision_fft_option():
    h = rough_surface(64, 15)
    kw = dict(dx=2.11e-3 / 64, E_star=E_STAR, p_mean=300e6)
    for H in (None, H_DC04):
        ref = solve_normal(h, H=H, tol=1e-10, **kw)
        s = solve_normal(h, H=H, tol=1e-6, single=True, **kw)
        assert s.converged and s.residual < 1e-6
        assert abs(s.alpha - ref.alpha) < 1e-3
        assert np.linalg.norm(s.pressure - ref.pressure) / np.linalg.norm(ref.pressure) < 1e-4
        assert s.pressure.dtype == np.float64 and s.pressure.max() <= (H or np.inf)
    with pytest.raises(ValueError, match="single"):
        solve_normal(h, tol=1e-8, single=True, **kw)


# ----------------------------------------------------------------------------- nested iteration
@pytest.mark.parametrize("periodic", [True, False])
def test_nested_iteration_gives_the_same_solution(periodic):
    """Coarse-grid initial guesses change the path, not the answer; ``nit`` is the fine work."""
    from halfspace_calib.contact.normal import NESTED_MIN

    n = 2 * NESTED_MIN
    h = rough_surface(n, 21)
    kw = dict(dx=2.11e-3 / n, E_star=E_STAR, H=H_DC04, periodic=periodic, tol=1e-9)
    for p_mean, p_init in ((300e6, None), (100e6, "warm")):
        if p_init == "warm":
            p_init = solve_normal(h, p_mean=300e6, **kw).pressure  # a reload-like warm start
        a = solve_normal(h, p_mean=p_mean, p_init=p_init, **kw)
        b = solve_normal(h, p_mean=p_mean, p_init=p_init, nested=True, **kw)
        assert a.converged and b.converged and b.residual < 1e-9
        assert a.coarse_nit == () and len(b.coarse_nit) == 1 and b.coarse_nit[0] > 0
        assert b.nit > 0  # the fine grid is solved, not only the coarse one
        rel = np.linalg.norm(b.pressure - a.pressure) / np.linalg.norm(a.pressure)
        assert rel < 1e-5
        assert abs(b.alpha - a.alpha) <= 3 / h.size
        assert b.pressure.mean() == pytest.approx(p_mean, rel=1e-9)
    # grids that cannot be halved (odd side, or below NESTED_MIN) are solved directly
    for shape in ((n - 1, n), (NESTED_MIN, NESTED_MIN)):
        r = solve_normal(h[: shape[0], : shape[1]], p_mean=200e6, nested=True, **kw)
        assert r.converged and r.coarse_nit == ()

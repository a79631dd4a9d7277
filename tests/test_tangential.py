import numpy as np
import pytest

from halfspace_calib.contact.cerruti import E_prime, cerruti_coefficients, shear_modulus_composite
from halfspace_calib.contact.tangential import (
    _CerrutiOperator,
    solve_tangential,
    tangential_bound,
    tau_adh_full_sliding,
)

E, NU = 210e9, 0.3
E_STAR = 1.0 / (2 * (1 - NU**2) / E)
E_PR = E_prime(E, NU, E, NU)
G_STAR = shear_modulus_composite(E, NU, E, NU)


# ------------------------------------------------------------------ FFT application of Eq. 16


@pytest.mark.parametrize(
    "shape,dx,dy", [((7, 5), 1e-6, 0.7e-6), ((8, 8), 2e-6, 2e-6), ((1, 6), 1e-6, 1e-6)]
)
def test_nonperiodic_fft_equals_dense_sum(shape, dx, dy):
    nx, ny = shape
    op = _CerrutiOperator(shape, dx, dy, E_STAR, E_PR, periodic=False)
    X, Y = np.meshgrid(np.arange(nx) * dx, np.arange(ny) * dy, indexing="ij")
    Xf, Yf = X.ravel(), Y.ravel()
    C = cerruti_coefficients(
        Xf[:, None] - Xf[None, :], Yf[:, None] - Yf[None, :], dx, dy, E_STAR, E_PR
    )
    q = np.random.default_rng(1).normal(size=shape)
    u = op(q).ravel()
    np.testing.assert_allclose(u, C @ q.ravel(), rtol=0, atol=1e-13 * np.abs(C @ q.ravel()).max())
    np.testing.assert_allclose(op.dense(np.arange(nx * ny)), C, rtol=1e-12)
    # operator-norm bound used for the MPRGP step length
    assert np.linalg.eigvalsh(C).max() <= op.norm * (1 + 1e-12)


def test_periodic_operator_matches_nonperiodic_for_localised_load():
    n, dx = 256, 1e-6
    x = (np.arange(n) - n / 2) * dx
    X, Y = np.meshgrid(x, x, indexing="ij")
    R0 = 8 * dx
    q = np.exp(-(X**2 + Y**2) / (2 * R0**2))
    up = _CerrutiOperator((n, n), dx, dx, E_STAR, E_PR, periodic=True)(q)
    un = _CerrutiOperator((n, n), dx, dx, E_STAR, E_PR, periodic=False)(q)
    mask = X**2 + Y**2 < (2 * R0) ** 2
    dp = up - up[n // 2, n // 2]
    dn = un - un[n // 2, n // 2]
    assert np.abs(dn[mask]).max() > 0.3 * un.max()  # the comparison is not trivial
    assert np.abs(dp - dn)[mask].max() < 2e-3 * np.abs(dn[mask]).max()
    # anisotropy of Cerruti (E' > 0): u falls off more slowly along x than along y
    c = n // 2
    assert un[c + 10, c] > un[c, c + 10]
    assert up[c + 10, c] > up[c, c + 10]


@pytest.mark.parametrize("periodic", [True, False])
def test_operator_symmetric_positive(periodic):
    rng = np.random.default_rng(2)
    op = _CerrutiOperator((16, 12), 1e-6, 1.5e-6, E_STAR, E_PR, periodic)
    a, b = rng.normal(size=(2, 16, 12))
    assert np.sum(a * op(b)) == pytest.approx(np.sum(b * op(a)), rel=1e-12)
    a -= a.mean()  # periodic: the mean mode is the (zero) k = 0 mode
    assert np.sum(a * op(a)) > 0


# ------------------------------------------------------------------ helpers


def _hertz(n, p0=1e9, a=1e-4, box=2.2):
    L = box * a
    dx = L / n
    x = (np.arange(n) - (n - 1) / 2) * dx
    X, Y = np.meshgrid(x, x, indexing="ij")
    r2 = X**2 + Y**2
    p = np.where(r2 < a * a, p0 * np.sqrt(np.clip(1 - r2 / a**2, 0, None)), 0.0)
    return p, dx, r2, a, p0


def _rough_pressure(n, seed=3):
    """A patchy pressure field standing in for a rough normal solution."""
    rng = np.random.default_rng(seed)
    f = np.fft.irfft2(np.fft.rfft2(rng.normal(size=(n, n))) * _lowpass(n), s=(n, n))
    f = (f - f.mean()) / f.std()
    return np.where(f > 0.6, 8e8 * np.sqrt(np.clip(f - 0.6, 0, None)), 0.0)


def _lowpass(n):
    k = np.hypot(*np.meshgrid(np.fft.fftfreq(n), np.fft.rfftfreq(n), indexing="ij"))
    return np.exp(-((k / 0.08) ** 2))


def _check_kkt(res, p, dx, g, periodic, tol=1e-6):
    op = _CerrutiOperator(p.shape, dx, dx, E_STAR, E_PR, periodic)
    u = op(res.q)
    contact = g > 0
    assert np.all(res.q[~contact] == 0)
    assert np.all(np.abs(res.q) <= g * (1 + 1e-12))
    assert not np.any(res.stick & res.slip)
    assert np.array_equal(res.stick | res.slip, contact)
    slip_gap = res.delta - u  # slip of the tool relative to the workpiece
    scale = abs(res.delta)
    assert np.abs(slip_gap[res.stick]).max(initial=0) <= tol * scale
    # slip elements slide in the direction of their traction
    assert np.all(np.sign(res.q[res.slip]) * slip_gap[res.slip] >= -tol * scale)


# ------------------------------------------------------------------ Cattaneo-Mindlin


def _mindlin_case(n, ratio, mu=0.3):
    p, dx, r2, a, p0 = _hertz(n)
    L2 = (n * dx) ** 2
    P = p.sum() * dx * dx
    res = solve_tangential(p, dx, E_STAR, E_PR, q_mean=ratio * mu * P / L2, mu=mu, periodic=False)
    assert res.converged, res.message
    c_th = a * (1 - ratio) ** (1 / 3)
    c_num = np.sqrt(res.stick.sum() * dx * dx / np.pi)
    d_th = 3 * mu * P / (16 * a * G_STAR) * (1 - (1 - ratio) ** (2 / 3))
    q_th = mu * p - np.where(
        r2 < c_th**2, mu * p0 * c_th / a * np.sqrt(np.clip(1 - r2 / c_th**2, 0, None)), 0
    )
    err_q_max = np.abs(res.q - q_th).max() / (mu * p0)
    err_q_l2 = np.sqrt(((res.q - q_th) ** 2).sum() / (q_th**2).sum())
    return res, p, dx, mu, abs(c_num / c_th - 1), abs(res.delta / d_th - 1), err_q_max, err_q_l2


@pytest.mark.parametrize("ratio", [0.2, 0.5, 0.9])
def test_cattaneo_mindlin_128(ratio):
    res, p, dx, mu, e_c, e_d, e_qmax, e_ql2 = _mindlin_case(128, ratio)
    assert e_c < 0.01  # stick radius c = a (1 - Q/(mu P))^(1/3)
    assert e_d < 1e-3  # tangential compliance
    assert e_qmax < 0.035  # traction profile, max error relative to mu p0
    assert e_ql2 < 0.015
    _check_kkt(res, p, dx, tangential_bound(p, mu=mu), periodic=False)


@pytest.mark.slow
@pytest.mark.parametrize("ratio", [0.2, 0.5, 0.9])
def test_cattaneo_mindlin_256(ratio):
    res, p, dx, mu, e_c, e_d, e_qmax, e_ql2 = _mindlin_case(256, ratio)
    assert e_c < 0.005
    assert e_d < 1e-4
    assert e_qmax < 0.02
    assert e_ql2 < 0.007


def test_displacement_and_force_control_agree():
    p, dx, *_ = _hertz(64)
    rf = solve_tangential(p, dx, E_STAR, E_PR, q_mean=-0.4 * 0.3 * p.mean(), mu=0.3, periodic=False)
    rd = solve_tangential(p, dx, E_STAR, E_PR, delta=rf.delta, mu=0.3, periodic=False)
    assert rf.delta < 0 and rf.q_mean < 0
    assert rd.q_mean == pytest.approx(rf.q_mean, rel=1e-6)
    np.testing.assert_allclose(rd.q, rf.q, atol=1e-5 * 0.3 * p.max())
    # odd symmetry of the problem
    rp = solve_tangential(p, dx, E_STAR, E_PR, delta=-rf.delta, mu=0.3, periodic=False)
    np.testing.assert_allclose(rp.q, -rd.q, atol=1e-5 * 0.3 * p.max())


def test_stick_zone_shrinks_monotonically():
    p, dx, *_ = _hertz(48)
    sticks, means = [], []
    for d in np.linspace(0.2e-7, 4e-7, 6):
        r = solve_tangential(p, dx, E_STAR, E_PR, delta=d, mu=0.3, periodic=False)
        sticks.append(r.stick.sum())
        means.append(r.q_mean)
    assert all(s1 <= s0 for s0, s1 in zip(sticks, sticks[1:], strict=False))
    assert all(m1 > m0 for m0, m1 in zip(means, means[1:], strict=False))


# ------------------------------------------------------------------ Tresca bound (the paper), rough contact


@pytest.mark.parametrize("periodic", [False, True])
def test_rough_tresca_kkt_and_gauss_seidel_reference(periodic):
    n, dx = 24, 1e-6
    p = _rough_pressure(n)
    m, sy = 0.6, 300e6
    g = tangential_bound(p, m=m, sigma_y=sy)
    assert 0.1 < (g > 0).mean() < 0.6
    u_slide = _CerrutiOperator(p.shape, dx, dx, E_STAR, E_PR, periodic)(g)
    d_hi = u_slide[g > 0].max()  # from this shift on, everything slides
    for delta in (0.45 * d_hi, 0.7 * d_hi):
        rm = solve_tangential(
            p, dx, E_STAR, E_PR, delta=delta, m=m, sigma_y=sy, periodic=periodic, tol=1e-10
        )
        rg = solve_tangential(
            p,
            dx,
            E_STAR,
            E_PR,
            delta=delta,
            m=m,
            sigma_y=sy,
            periodic=periodic,
            method="gauss-seidel",
            tol=1e-10,
        )
        assert rm.converged and rg.converged, (rm.message, rg.message)
        assert rm.stick.any() and rm.slip.any()  # partial slip: a real test of both branches
        _check_kkt(rm, p, dx, g, periodic)
        _check_kkt(rg, p, dx, g, periodic)
        np.testing.assert_allclose(rm.q, rg.q, atol=1e-7 * 0.5 * m * sy)
        assert np.array_equal(rm.stick, rg.stick)


def test_full_sliding_shortcut_agrees_with_solver():
    n, dx = 32, 1e-6
    p = _rough_pressure(n, seed=5)
    m, sy = 0.8, 250e6
    alpha = (p > 0).mean()
    tau = tau_adh_full_sliding(alpha, m, sy)
    r = solve_tangential(p, dx, E_STAR, E_PR, delta=1e-6, m=m, sigma_y=sy, periodic=False)
    assert r.converged and not r.stick.any()
    assert r.q_mean == pytest.approx(tau, rel=1e-12)
    # force control at the sliding limit returns full sliding
    r2 = solve_tangential(p, dx, E_STAR, E_PR, q_mean=tau, m=m, sigma_y=sy, periodic=False)
    assert r2.converged and r2.slip.sum() == (p > 0).sum()
    assert r2.q_mean == pytest.approx(tau, rel=1e-12)
    # just below the limit some element still sticks, and the mean traction is met
    r3 = solve_tangential(p, dx, E_STAR, E_PR, q_mean=0.999 * tau, m=m, sigma_y=sy, periodic=False)
    assert r3.converged and r3.stick.any()
    assert r3.q_mean == pytest.approx(0.999 * tau, rel=1e-6)
    assert r3.delta < r2.delta * (1 + 1e-12)
    with pytest.raises(ValueError, match="sliding limit"):
        solve_tangential(p, dx, E_STAR, E_PR, q_mean=1.01 * tau, m=m, sigma_y=sy, periodic=False)


def test_periodic_force_control_rough():
    n, dx = 64, 1e-6
    p = _rough_pressure(n, seed=7)
    m, sy = 0.5, 300e6
    target = 0.5 * tau_adh_full_sliding((p > 0).mean(), m, sy)
    r = solve_tangential(p, dx, E_STAR, E_PR, q_mean=target, m=m, sigma_y=sy, periodic=True)
    assert r.converged, r.message
    assert r.q_mean == pytest.approx(target, rel=1e-6)
    _check_kkt(r, p, dx, tangential_bound(p, m=m, sigma_y=sy), periodic=True)


# ------------------------------------------------------------------ edge cases and input checks


def test_trivial_cases():
    p = np.zeros((8, 8))
    r = solve_tangential(p, 1e-6, E_STAR, E_PR, delta=1e-9, mu=0.3, periodic=False)
    assert r.converged and not r.q.any() and not r.stick.any()
    p, dx, *_ = _hertz(16)
    r = solve_tangential(p, dx, E_STAR, E_PR, q_mean=0.0, mu=0.3, periodic=False)
    assert r.converged and r.delta == 0 and not r.q.any()


def test_not_converged_is_reported():
    p, dx, *_ = _hertz(64)
    r = solve_tangential(p, dx, E_STAR, E_PR, delta=1e-7, mu=0.3, maxiter=3, periodic=False)
    assert not r.converged
    assert "NOT converged" in r.message


def test_bounds():
    p = np.array([[0.0, 1e8], [2e8, 0.0]])
    np.testing.assert_array_equal(tangential_bound(p, m=0.5, sigma_y=200e6), [[0, 50e6], [50e6, 0]])
    np.testing.assert_array_equal(tangential_bound(p, mu=0.1), [[0, 1e7], [2e7, 0]])
    assert tau_adh_full_sliding(0.25, 0.5, 200e6) == pytest.approx(12.5e6)
    with pytest.raises(ValueError, match="either"):
        tangential_bound(p, m=0.5, sigma_y=1e8, mu=0.1)
    with pytest.raises(ValueError, match="m must"):
        tangential_bound(p, m=1.5, sigma_y=1e8)
    with pytest.raises(ValueError, match="alpha_rc"):
        tau_adh_full_sliding(1.2, 0.5, 1e8)


@pytest.mark.parametrize(
    "kwargs,match",
    [
        (dict(delta=None), "exactly one"),
        (dict(q_mean=1.0), "exactly one"),
        (dict(method="cg"), "method"),
        (dict(tol=0.0), "tol"),
        (dict(maxiter=0), "maxiter"),
        (dict(delta=np.nan), "delta"),
        (dict(q0=np.zeros((3, 3))), "q0"),
        (dict(dx=-1.0), "dx"),
        (dict(E_star=0.0), "E_star"),
    ],
)
def test_bad_input(kwargs, match):
    p, dx, *_ = _hertz(16)
    args = dict(p=p, dx=dx, E_star=E_STAR, E_prime=E_PR, delta=1e-8, mu=0.3)
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        solve_tangential(**args)


def test_bad_pressure_and_gs_size():
    with pytest.raises(ValueError, match="p must be >= 0"):
        solve_tangential(-np.ones((4, 4)), 1e-6, E_STAR, E_PR, delta=1e-9, mu=0.3, periodic=False)
    with pytest.raises(ValueError, match="2-D"):
        solve_tangential(np.ones(4), 1e-6, E_STAR, E_PR, delta=1e-9, mu=0.3, periodic=False)
    with pytest.raises(ValueError, match="gauss-seidel"):
        solve_tangential(
            np.ones((100, 100)),
            1e-6,
            E_STAR,
            E_PR,
            delta=1e-9,
            mu=0.3,
            method="gauss-seidel",
            periodic=False,
        )


def test_periodic_full_contact_slides_everywhere():
    # periodic half-space in full contact: the mean mode is infinitely compliant, so any shift
    # slides every element (and the solver must not divide by the zero curvature)
    p = np.full((16, 16), 100e6)
    for method in ("mprgp", "gauss-seidel"):
        r = solve_tangential(
            p, 1e-6, E_STAR, E_PR, delta=-1e-9, m=0.5, sigma_y=200e6, periodic=True, method=method
        )
        assert r.converged, r.message
        assert r.slip.all()
        np.testing.assert_allclose(r.q, -50e6)

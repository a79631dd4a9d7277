"""The flattening model under bulk strain (frictionlaw.flattening, docs/flattening.md, Eqs. F1-F6).

Oracles independent of the module's own numerics: SciPy's adaptive quadrature for the J
integral (Eq. F4), the closed form of the lattice's rate alone (Eq. F3 where the layer's share
vanishes), and a finite difference of the curve against the rate of Eq. F3.
"""

import json
import math

import numpy as np
import pytest
from scipy import integrate

from frictionlaw import (
    Flattening,
    FrictionParams,
    alpha_first,
    alpha_reload,
    flattening_curve,
    shear_limit,
)
from frictionlaw.flattening import (
    STRETCH_PER_EQUIVALENT_STRAIN,
    contact_growth_rate,
    equivalent_strain,
    flattened_alpha,
    flattening_pressure,
    flattening_update,
    lattice_sink_rate,
    layer_sink_rate,
)
from frictionlaw.reload_form import ReloadTable

H = 8e8
#: the stretch across the ridges per unit von Mises equivalent strain in plane strain
RS = math.sqrt(3.0) / 2.0
BASE = dict(m=0.5, sigma_y=H / 2.8, H=H, C1=1.05, n1=2.87, C2=7.44, n2=0.575)


def law(slope=0.1, beta=1.0, **kw):
    return FrictionParams(**{**BASE, **kw}, flattening=Flattening(slope=slope, beta=beta))


def s0(P):
    return 2.0 * P.k


# ----------------------------------------------------------------------------- the record
def test_record_validates_and_round_trips(tmp_path):
    f = Flattening(slope=0.05, beta=2.0, beta_band=(1.5, 2.5), band_level=0.9)
    assert f.fitted and Flattening(slope=0.05).beta == 1.0
    assert Flattening.from_dict(json.loads(json.dumps(f.to_dict()))) == f
    P = FrictionParams(**BASE, flattening=f)
    path = P.to_json(tmp_path / "p.json")
    doc = json.loads(path.read_text())
    assert doc["version"] == 3 and doc["flattening"]["slope"] == 0.05
    assert FrictionParams.from_json(path) == P
    assert FrictionParams.from_json(path).flattening == f
    # without the block the file stays what it was (version 1 here) and reads without one
    assert FrictionParams(**BASE).to_dict()["version"] == 1
    for bad, msg in [
        (dict(slope=0.0), "flattening.slope must be in"),
        (dict(slope=float("nan")), "flattening.slope"),
        (dict(slope=0.1, beta=-1), "flattening.beta must be in"),
        (dict(slope=0.1, beta=True), "flattening.beta must be a real number"),
        (dict(slope=0.1, beta_band=(0.5, 2.0)), "come together"),
        (dict(slope=0.1, beta=3.0, beta_band=(0.5, 2.0), band_level=0.9), "must contain beta"),
        (dict(slope=0.1, beta_band=(0.5, 2.0), band_level=1.5), "band_level must be in"),
    ]:
        with pytest.raises(ValueError, match=msg):
            Flattening(**bad)


@pytest.mark.parametrize(
    "mutate, msg",
    [
        (lambda b: b.update(model="wilson-sheu"), "flattening.model must be"),
        (lambda b: b.update(version=4), "flattening.version: unsupported 4"),
        (lambda b: b.update(version=1), "flattening.version 1 is the layer-alone rate"),
        (lambda b: b.update(version=2), "flattening.version 2 read the bulk strain as the stretch"),
        (lambda b: b.pop("slope"), "missing 'slope'"),
        (lambda b: b.update(slope="steep"), "flattening.slope must be a real number"),
        (lambda b: b.update(slope=-0.1), "flattening.slope must be in"),
        # JSON numbers only: a quoted number is text, not converted
        (lambda b: b.update(slope="0.05"), "flattening.slope must be a real number.*string"),
        (lambda b: b.update(beta="2"), "flattening.beta must be a real number.*string"),
        (lambda b: b.update(beta=True), "flattening.beta must be a real number"),
        (
            lambda b: b.update(beta=2.0, beta_band=["1.5", 2.5], band_level=0.9),
            "flattening.beta_band lower must be a real number.*string",
        ),
        (
            lambda b: b.update(beta=2.0, beta_band=[1.5, 2.5], band_level="0.9"),
            "flattening.band_level must be a real number.*string",
        ),
        (lambda b: b.update(beta_band=[1.0], band_level=0.9), "flattening.beta_band must be"),
        (lambda b: b.update(units={"slope": "deg"}), "flattening.units"),
        (lambda b: b.update(spacing=1e-5), "unknown fields"),
    ],
)
def test_a_malformed_block_is_refused_naming_the_field(tmp_path, mutate, msg):
    doc = law().to_dict()
    mutate(doc["flattening"])
    path = tmp_path / "p.json"
    path.write_text(json.dumps(doc))
    with pytest.raises(ValueError, match=msg) as exc:
        FrictionParams.from_json(path)
    assert str(exc.value).startswith(str(path))


def test_the_block_needs_version_3(tmp_path):
    doc = law().to_dict()
    doc["version"] = 2
    with pytest.raises(ValueError, match="'flattening' needs version 3"):
        FrictionParams.from_dict(doc)
    doc = FrictionParams(**BASE).to_dict()
    doc["version"] = 3  # a version-3 file without the block: the law of the pressure alone
    assert FrictionParams.from_dict(doc).flattening is None


def test_a_law_without_the_block_says_so():
    with pytest.raises(ValueError, match="no flattening block"):
        flattening_curve(1e8, 0.1, FrictionParams(**BASE))


# ----------------------------------------------------------------------------- the equations
def _j_quad(P, p, pf):
    """Eq. F4's ``J`` by adaptive quadrature of Eq. 24's closed form and its derivative."""
    C1, n = P.C1, P.n1
    slope = P.flattening.slope

    def f(t):
        x = C1 * t / P.H
        y = x**n
        a = np.tanh(y) ** (1 / n)
        d = C1 / P.H * np.tanh(y) ** (1 / n - 1) / np.cosh(y) ** 2 * x ** (n - 1)
        s = np.sqrt(max(t * t - p * p, 0.0))
        W = 1.0 + (1.0 + slope * (1.0 - a)) * t * s / (s0(P) * p)  # lattice over layer
        return d * t * s / W

    return integrate.quad(f, p, pf, limit=400, epsrel=1e-11, epsabs=0.0)[0]


@pytest.mark.parametrize("ratio_p", [1e-3, 0.05, 0.3, 0.9])
@pytest.mark.parametrize("ratio_pf", [1.01, 1.5, 4.0])
def test_equivalent_strain_against_adaptive_quadrature(ratio_p, ratio_pf):
    """Eq. F4 by the module's Gauss-Legendre sum against SciPy's quad of alpha1' (differenced)."""
    P = law(slope=0.1, beta=1.0)
    p = ratio_p * H
    pf = min(ratio_pf * p, 3 * H)
    want = 0.1 * _j_quad(P, p, pf) / (1.0 * RS * s0(P) * p)
    got = equivalent_strain(p, pf, P)
    assert got == pytest.approx(want, rel=1e-9)


def test_closed_form_of_the_lattice_alone():
    """Where the layer's share vanishes (a host flow stress of 1 kPa: ``s0`` 5e-6 of the file's)
    Eq. F3 is the lattice's ``dA/d eps = r_s beta (1 + tan(theta) (1 - A)) / tan(theta)``, linear
    in ``A``: ``A = K - (K - alpha1(p)) exp(-r_s beta eps)``, ``K = 1 + 1 / tan(theta)``, until
    1 (``r_s = sqrt(3) / 2``, the stretch across the ridges per unit equivalent strain)."""
    P = law(slope=0.08, beta=1.7)
    K = 1.0 + 1.0 / 0.08
    eps = np.array([0.0, 1e-3, 3e-3, 0.01, 0.02, 0.2])
    for p in (0.05 * H, 0.3 * H):
        a0 = alpha_first(p, P)
        want = np.minimum(K - (K - a0) * np.exp(-RS * 1.7 * eps), 1.0)
        got = flattening_curve(p, eps, P, sigma_y=1e3)
        assert want[-1] == 1.0 and want[-2] < 1.0
        # the layer's rate at s0 = 1.4 kPa adds at most (s0 / p)^(2/3)-order fractions
        assert np.allclose(got, want, rtol=0, atol=2e-4)
        assert not np.allclose(flattening_curve(p, eps, P), want, rtol=0, atol=2e-2)


def test_the_curve_follows_the_rate_of_eq_f3():
    """A central difference of the curve equals Eq. F3 at the flattening pressure reached."""
    P = law(slope=0.12, beta=0.8)
    p = 0.2 * H
    for eps in (1e-3, 4e-3, 0.02):
        h = 1e-6
        a = flattening_curve(p, [eps - h, eps + h], P)
        pf = flattening_update(p, p, p, eps, P)
        assert a[1] < 1.0
        rate = contact_growth_rate(p, pf, alpha_first(pf, P), 0.12, 0.8, s0(P))  # dA / d eps
        assert (a[1] - a[0]) / (2 * h) == pytest.approx(rate, rel=1e-5)


def test_the_host_strain_is_the_equivalent_plastic_strain():
    """F1's strain is the stretch across the ridges of a plane-strain flow; the host passes the
    von Mises equivalent plastic strain, ``sqrt(2/3 e:e)`` of the plastic strain tensor. A
    plane-strain stretch ``e_xx = s`` (``e_zz = -s``) is the equivalent strain ``2 s / sqrt(3)``:
    the law given that equivalent strain flattens as the model given the stretch ``s``."""
    s_stretch = 0.01
    e = np.diag([s_stretch, 0.0, -s_stretch])
    eq = math.sqrt(2.0 / 3.0 * np.sum(e * e))
    assert STRETCH_PER_EQUIVALENT_STRAIN == pytest.approx(s_stretch / eq, rel=1e-15)
    P = law(slope=0.08, beta=1.0)
    p = 0.2 * H
    # the lattice's closed form in the stretch (the layer's share removed by a 1 kPa flow stress)
    K = 1.0 + 1.0 / 0.08
    a0 = alpha_first(p, P)
    want = K - (K - a0) * np.exp(-s_stretch)
    assert flattening_curve(p, eq, P, sigma_y=1e3) == pytest.approx(want, abs=2e-4)
    assert flattening_curve(p, s_stretch, P, sigma_y=1e3) < want - 0.01


def test_hardening_limits_the_lattice_and_the_sinking_in_closed_form():
    """Eqs. F2c and F2d: with the layer's share removed (a 1 kPa flow stress) and a hardening
    modulus that limits the lattice everywhere (``6 p / h = 0.4 < 1``), ``dA/d eps_eq = r_s beta
    0.4 (1 - A) / tan(theta)``: ``1 - A`` falls exponentially with strain until the sinking the
    hardening holds, ``3 p / (4 h) = 0.05`` half-spacings, ``A = alpha1(p) + 0.05 / tan(theta)``,
    where it stays."""
    P = law(slope=0.08, beta=1.3)
    p = 0.1 * H
    h = 6.0 * p / 0.4
    eps = np.array([0.0, 1e-3, 0.01, 0.05, 0.1, 0.5, 5.0])
    a0 = alpha_first(p, P)
    held = a0 + 0.75 * p / h / 0.08
    assert held == pytest.approx(a0 + 0.625, rel=1e-14)
    want = np.minimum(1.0 - (1.0 - a0) * np.exp(-RS * 1.3 * 0.4 * eps / 0.08), held)
    got = flattening_curve(p, eps, P, sigma_y=1e3, hardening=h)
    assert want[-3] < held and want[-2] == held
    assert np.allclose(got, want, rtol=0, atol=2e-4)
    assert got[-2:] == pytest.approx(held, abs=1e-12)
    # the strain to flatten beyond it: none
    assert equivalent_strain(p, flattening_pressure(held - 1e-3, P), P, hardening=h) < 0.5
    assert equivalent_strain(p, flattening_pressure(held + 1e-3, P), P, hardening=h) == np.inf
    # without the limits the lattice's exponential (test above) is far faster
    assert flattening_curve(p, 0.05, P, sigma_y=1e3) > want[3] + 0.1


def test_the_lattice_hardening_limit_falls_with_the_valleys():
    """Eq. F2c: the pressure works on the lattice's split only through the plateaus' descent
    against the surface's mean, ``(1 - A)`` of the relative sinking (the valleys, ``1 - A`` of
    the period, rise by ``A`` of it), so the limit is ``6 p (1 - A) / h``: 0 at full contact,
    ``6 p / h`` on a virgin point contact."""
    from frictionlaw.flattening import lattice_hardening_limit

    a = np.array([0.0, 0.25, 0.9, 1.0])
    got = lattice_hardening_limit(1e8, 1e9, a)
    assert got == pytest.approx([0.6, 0.45, 0.06, 0.0], rel=1e-14, abs=0)
    # the share 1 - A of the whole sinking, whatever the pressure and the modulus (per node)
    p, h = np.array([[1e6], [3e7], [4e8]]), np.array([[2e8], [7e9], [1e11]])
    ratio = lattice_hardening_limit(p, h, a) / lattice_hardening_limit(p, h, 0.0)
    assert np.allclose(ratio, 1.0 - a, rtol=1e-14, atol=0)
    assert np.all(lattice_hardening_limit(1e8, None, a) == np.inf)


@pytest.mark.parametrize("ph, a_c", [(0.1, 0.2), (0.2, 0.3), (0.2, 0.5)])
def test_the_strain_across_the_hardening_limits_start_against_scipy(ph, a_c):
    """Eq. F4 where F2c's limit starts to act inside the integral (at ``A_c``, a kink of the
    integrand: the sum is split there): the equivalent strain against SciPy's adaptive
    quadrature of Eq. F3 in ``A`` told the kink (1e-9; unsplit, the sum was 1.4e-5 off)."""
    P = law(slope=0.05, beta=1.2)
    f, p = P.flattening, ph * H
    h = 6.0 * p / (f.slope + 1.0 / (1.0 - a_c))  # 6 p (1 - A) / h = c_L at A_c
    a0 = float(alpha_first(p, P))
    s0 = 2.0 * float(P.k)

    def d_eps_d_a(a):
        t = float(flattening_pressure(a, P))
        c = min(1.0 + f.slope * (1.0 - a), 6.0 * p * (1.0 - a) / h)
        c_e = s0 * p / (t * math.sqrt(t * t - p * p))
        return f.slope / (RS * f.beta * (c + c_e))

    for a in (a_c - 0.05, a_c + 0.05, 0.9):
        want = integrate.quad(d_eps_d_a, a0, a, points=[a_c], limit=200, epsrel=1e-12)[0]
        got = float(equivalent_strain(p, flattening_pressure(a, P), P, hardening=h))
        assert got == pytest.approx(want, rel=1e-9), a


def test_the_sinking_limit_in_closed_form_and_its_arguments():
    """Eq. F2d's ``3 p / (4 h)`` from the plane-strain columns: ``d (2 k) / d eps_x = 4 h / 3``
    (``2 k = 2 sigma_y / sqrt 3``, ``eps_eq = 2 eps_x / sqrt 3``), so a stress difference ``p``
    is a stretch difference ``3 p / (4 h)``; no bound for ``h = 0`` or ``None``; named errors."""
    from frictionlaw.flattening import HARDENING_SINK, hardening_sinking_limit

    d2k_dx = (2 / math.sqrt(3)) * (2 / math.sqrt(3))  # per unit h
    assert HARDENING_SINK == pytest.approx(1 / d2k_dx, rel=1e-15)
    got = hardening_sinking_limit([1e7, 1e8, 1e8], [1e9, 1e9, 0.0])
    assert got[:2].tolist() == [0.0075, 0.075] and got[2] == np.inf
    assert np.all(hardening_sinking_limit([1e7, 2e8], None) == np.inf)
    with pytest.raises(ValueError, match="hardening must be finite and >= 0"):
        hardening_sinking_limit(1e8, -2.0)
    with pytest.raises(ValueError, match=r"p must be finite and >= 0 \(Pa\)"):
        hardening_sinking_limit(-1.0, 1e9)


def test_the_sinking_a_hardening_bulk_holds_is_reached_and_kept():
    """Eq. F2d in the per-node update: a node held at ``alpha1(max(p_hist, p)) + 3 p / (4 h
    tan(theta))`` stays there under more strain at that modulus, moves on as the modulus falls
    (a hardening that saturates), never falls when the pressure drops (the sinking is not
    undone), and a node loaded higher before is held above that history's fraction."""
    P = law(slope=0.1)
    p, h = 0.05 * H, 2e10
    held = alpha_first(p, P) + 0.75 * p / h / 0.1
    pf = flattening_update(0.0, p, p, 0.5, P, hardening=h)
    assert alpha_first(pf, P) == pytest.approx(held, abs=1e-12)
    assert flattening_update(pf, p, p, 0.5, P, hardening=h) == pf
    pf2 = flattening_update(pf, p, p, 0.5, P, hardening=h / 2)
    assert alpha_first(pf2, P) == pytest.approx(alpha_first(p, P) + 2 * (held - alpha_first(p, P)))
    assert flattening_update(pf2, p, 0.5 * p, 0.5, P, hardening=h / 2) == pf2
    ph = 0.3 * H
    top = flattening_update(0.0, ph, p, 0.5, P, hardening=h)
    assert alpha_first(top, P) == pytest.approx(alpha_first(ph, P) + (held - alpha_first(p, P)))


def test_hardening_slows_and_zero_is_perfect_plasticity():
    """A stiffer hardening flattens slower; 0 and ``None`` are the perfectly plastic law bit for
    bit; a limit above the lattice's rate changes nothing."""
    P = law(slope=0.1)
    p = np.array([0.05, 0.2, 0.5]) * H
    eps = 0.02
    base = flattening_curve(p, eps, P)
    assert np.array_equal(flattening_curve(p, eps, P, hardening=0.0), base)
    assert np.array_equal(
        flattening_update(p, p, p, eps, P, hardening=np.zeros(3)),
        flattening_update(p, p, p, eps, P),
    )
    # 6 p / h above 1 + tan(theta) for every p: the limit never acts
    assert np.array_equal(flattening_curve(p, eps, P, hardening=0.3 * p[0]), base)
    prev = base
    for h in (1e8, 1e9, 1e10):
        a = flattening_curve(p, eps, P, hardening=h)
        assert np.all(a <= prev) and np.all(a >= alpha_first(p, P))
        prev = a
    assert np.all(prev < base)
    assert equivalent_strain(p[0], 2 * p[0], P, hardening=1e10) > equivalent_strain(
        p[0], 2 * p[0], P
    )
    with pytest.raises(ValueError, match="hardening must be finite and >= 0"):
        flattening_update(p, p, p, eps, P, hardening=-1.0)


def test_the_layer_rate_and_its_limits():
    """Eq. F2: 0 without pressure, linear in ``r`` for small ``r``, unbounded at ``r = 1``; the
    lattice's ``1 + tan(theta) (1 - A)``: 1 at full contact, independent of the pressure."""
    assert np.array_equal(lattice_sink_rate([0.0, 0.5, 1.0], 0.1), [1.1, 1.05, 1.0])
    assert layer_sink_rate(0.0, 2.0) == 0.0
    assert layer_sink_rate(1e-6, 2.0) == pytest.approx(2e-6, rel=1e-11)
    assert np.isinf(layer_sink_rate(1.0, 2.0))
    r = np.linspace(0.0, 0.999, 50)
    assert np.all(np.diff(layer_sink_rate(r, 1.0)) > 0)


def test_the_start_is_a_two_thirds_power_of_strain():
    """At ``r -> 1`` the rate diverges as ``(A - A0)^(-1/2)``: ``A - A0 ~ eps^(2/3)`` (Eq. F3)."""
    P = law()
    p = 0.2 * H
    a0 = alpha_first(p, P)
    a = flattening_curve(p, [1e-10, 8e-10], P) - a0  # the lattice's linear term: 1e-3 of it
    assert a[1] / a[0] == pytest.approx(4.0, rel=1e-3)


# ----------------------------------------------------------------------------- the curve
def test_zero_strain_is_the_calibrated_law():
    for form in ("paper", "tabulated"):
        kw = {}
        if form == "tabulated":
            kw = dict(
                reload_form="tabulated",
                reload_table=ReloadTable((1e8, 4e8, 7e8), (3.0, 6.0, 12.0), (0.5, 1.0, 2.0), 0.7),
            )
        P = law(**kw)
        p = np.geomspace(1e5, 0.99 * H, 40)
        assert np.array_equal(flattening_curve(p, 0.0, P), alpha_first(p, P))
        # continuous at zero strain, with the 2/3-power start of Eq. F3 (next test)
        assert np.allclose(flattening_curve(p, 1e-22, P), alpha_first(p, P), rtol=0, atol=1e-9)


@pytest.mark.parametrize("slope", [0.02, 0.05, 0.1, 0.2])
def test_never_falls_stays_at_most_one_rises_at_low_pressure(slope):
    P = law(slope=slope)
    eps = np.linspace(0.0, 0.6, 121)
    for pr in (0.01, 0.05, 0.3, 0.6, 0.95):
        a = flattening_curve(pr * H, eps, P)
        assert np.all(np.diff(a) >= 0) and np.all(a <= 1.0) and a[0] == alpha_first(pr * H, P)
    low = flattening_curve(0.05 * H, [0.0, slope / 10, 0.5], P)  # the lattice: 1 / slope
    assert low[1] > low[0] + 0.08 and low[2] == 1.0


@pytest.mark.parametrize("slope", [0.02, 0.049, 0.1, 0.2])
def test_near_full_contact_at_large_strain(slope):
    """At 0.3 H and strain 0.5, at least 0.9 for realistic profile slopes (default scene 0.049)."""
    assert flattening_curve(0.3 * H, 0.5, law(slope=slope)) >= 0.9


def test_full_contact_at_the_finite_strain_of_eq_f4():
    P = law(slope=0.1)
    p = 0.3 * H
    full = equivalent_strain(p, 2**40 * H, P)
    a = flattening_curve(p, [0.98 * full, 1.02 * full, 10 * full], P)
    assert a[0] < 1.0 and a[1] == 1.0 and a[2] == 1.0


def test_strain_scales_with_beta_and_the_flow_stress_sets_the_layers_share():
    """``eps`` is proportional to ``1 / beta`` (Eq. F4); the host's flow stress (strain rate
    enters through it alone) scales the layer's rate, so a harder bulk flattens faster, and a
    steeper flank slower."""
    p, eps = 0.15 * H, np.array([0.01, 0.04, 0.1])
    ref = flattening_curve(p, eps, law(slope=0.05, beta=1.0))
    assert np.allclose(flattening_curve(p, eps / 3, law(slope=0.05, beta=3.0)), ref, atol=1e-12)
    P = law(slope=0.05)
    host = flattening_curve(p, eps, P, sigma_y=1.5 * P.sigma_y)
    assert np.all(host >= ref) and host[0] > ref[0] + 1e-3 and ref[0] < 1.0
    steep = flattening_curve(p, eps, law(slope=0.1))
    assert np.all(steep <= ref) and steep[0] < ref[0] - 1e-3
    with pytest.raises(ValueError, match="sigma_y must be in"):
        flattening_curve(p, eps, P, sigma_y=-1.0)


# ----------------------------------------------------------------------------- per node
def test_the_update_never_falls_and_adds_up():
    P = law()
    p = np.array([0.05, 0.2, 0.5]) * H
    pf0 = np.zeros(3)
    one = flattening_update(pf0, p, p, 0.04, P)
    two = flattening_update(flattening_update(pf0, p, p, 0.02, P), p, p, 0.02, P)
    assert np.allclose(two, one, rtol=1e-10)  # increments at a fixed pressure add up
    assert np.all(one >= p)
    assert np.array_equal(flattening_update(one, p, p, 0.0, P), one)  # no strain: unchanged
    assert np.array_equal(flattening_update(one, p, 0.5 * p, 0.0, P), one)
    assert np.array_equal(flattening_update(one, p, np.zeros(3), 0.1, P), one)  # open node
    lower = flattening_update(one, p, 0.1 * p, 0.05, P)
    assert np.all(lower >= one)  # a lower pressure flattens on, slowly, never back
    # trial/commit: every Newton iteration starts from the committed value, same result
    assert np.array_equal(flattening_update(pf0, p, p, 0.04, P), one)


def test_flattening_at_a_lower_pressure_than_the_history_is_slower():
    P = law()
    p = 0.1 * H
    virgin = flattening_update(0.0, p, p, 0.05, P)
    pressed = flattening_update(0.0, 0.5 * H, p, 0.05, P)  # loaded to 0.5 H before
    gain_virgin = alpha_first(virgin, P) - alpha_first(p, P)
    gain_pressed = alpha_first(pressed, P) - alpha_first(0.5 * H, P)
    assert 0 < gain_pressed < gain_virgin


def test_hostile_input_is_refused_or_finite():
    P = law()
    for bad, msg in [
        (dict(d_eps=-0.1), "d_eps must be >= 0"),
        (dict(d_eps=np.nan), "d_eps must not contain NaN"),
        (dict(p=np.inf), "p must be finite"),
        (dict(p_f=-1.0), "p_f and p_hist must be >= 0"),
    ]:
        args = dict(p_f=0.0, p_hist=1e8, p=1e8, d_eps=0.1) | bad
        with pytest.raises(ValueError, match=msg):
            flattening_update(args["p_f"], args["p_hist"], args["p"], args["d_eps"], P)
    huge = flattening_update(0.0, 1e8, 1e8, 1e300, P)
    assert np.isfinite(huge) and alpha_first(huge, P) == 1.0
    tiny = flattening_update(0.0, 1e-6, 1e-6, 0.5, P)  # below 1e-12 H: no flattening
    assert tiny == 0.0
    big = flattening_update(0.0, 1e30, 1e30, 0.5, P)  # beyond the cap: the pressure alone
    assert big == 0.0 and flattened_alpha(1e30, 1e30, big, P) == alpha_first(1e30, P)
    with pytest.raises(ValueError, match="p must be finite and > 0"):
        flattening_curve(0.0, 0.1, P)
    with pytest.raises(ValueError, match="strains must be finite and >= 0"):
        flattening_curve(1e8, -0.1, P)


def test_shape_mismatches_name_the_argument_and_both_shapes_before_any_work(monkeypatch):
    import frictionlaw.flattening as F

    P = law()

    def no_work(*a, **k):
        raise AssertionError("the law was evaluated before the shapes were checked")

    monkeypatch.setattr(F, "_coeffs", no_work)
    n3, n4 = np.full(3, 1e8), np.full(4, 1e8)
    for call, msg in [
        (lambda: flattening_update(n3, n3, n4, 0.1, P), r"p has shape \(4,\), p_f \(3,\)"),
        (lambda: flattening_update(0.0, n3, n3, n4, P), r"d_eps has shape \(4,\), p_hist \(3,\)"),
        (
            lambda: flattening_update(n3, n3, n3, 0.1, P, hardening=np.ones(4)),
            r"hardening has shape \(4,\), the nodes \(3,\)",
        ),
        (
            lambda: flattening_update(n3, n3, n3, 0.1, P, sigma_y=np.full(4, 2e8)),
            r"sigma_y has shape \(4,\), the nodes \(3,\)",
        ),
        (lambda: flattened_alpha(n3, n4, n3, P), r"p_hist has shape \(4,\), p \(3,\)"),
        (lambda: flattened_alpha(n3, 0.0, n4, P), r"p_f has shape \(4,\), p \(3,\)"),
        (lambda: equivalent_strain(n3, n4, P), r"p_f has shape \(4,\), p \(3,\)"),
        (
            lambda: equivalent_strain(n3, 2 * n3, P, hardening=np.ones(4)),
            r"hardening has shape \(4,\), the nodes \(3,\)",
        ),
        (lambda: flattening_curve(n3, np.zeros(4), P), r"strains has shape \(4,\), p \(3,\)"),
        (
            lambda: flattening_update(n3[:, None], n4, 1e8, np.zeros(5), P),
            r"d_eps has shape \(5,\), p_hist \(4,\)",
        ),
    ]:
        with pytest.raises(ValueError, match=msg):
            call()
    monkeypatch.undo()
    # shapes that broadcast still do: a column of pressures against a row of strains
    a = flattening_curve(n3[:, None] * [[0.5], [1.0], [2.0]], np.array([0.0, 0.1]), P)
    assert a.shape == (3, 2) and np.all(a[:, 1] > a[:, 0])


def test_extreme_input_stays_finite_without_warnings():
    """Pressures, histories and strains from the subnormals to the largest doubles, the validated
    ranges' ends of slope and beta: finite results in [0, 1], no warning (warnings are errors)."""
    rng = np.random.default_rng(7)
    big = np.finfo(float).max
    vals = np.array([0.0, 5e-324, 1e-300, 1e-6, 1.0, 1e5, 0.3 * H, H, 10 * H, 1e300, big])
    for slope, beta in ((1e-8, 1e3), (1e-8, 1e-3), (10.0, 1e-3), (0.1, 1.0)):
        P = law(slope=slope, beta=beta, continuous_reload=True)
        p, ph, pf = (rng.choice(vals, 300) for _ in range(3))
        d_eps = rng.choice([0.0, 1e-300, 1e-3, 0.5, 1e300, big], 300)
        new = flattening_update(pf, ph, p, d_eps, P)
        assert np.all(np.isfinite(new)) and np.all(new >= pf)
        a = flattened_alpha(p, np.maximum(ph, p), new, P)
        assert np.all(np.isfinite(a)) and np.all((a >= 0) & (a <= 1))
        c = flattening_curve(np.where(p > 0, p, 1.0), np.where(d_eps < 1e300, d_eps, 1.0), P)
        assert np.all(np.isfinite(c)) and np.all((c >= 0) & (c <= 1))


# ----------------------------------------------------------------------------- Eq. F5
@pytest.mark.parametrize("continuous", [False, True])
@pytest.mark.parametrize("form", ["paper", "tabulated"])
def test_without_flattening_the_contact_fraction_is_the_law(form, continuous):
    kw = dict(continuous_reload=continuous)
    if form == "tabulated":
        kw |= dict(
            reload_form="tabulated",
            reload_table=ReloadTable((1e8, 4e8, 7e8), (3.0, 6.0, 12.0), (0.5, 1.0, 2.0), 0.7),
        )
    P = law(**kw)
    p = np.linspace(0.0, 0.9 * H, 37)
    for ph in (0.0, 1e8, 5e8):
        for pf in (0.0, 0.5 * ph, ph):
            got = flattened_alpha(p, ph, pf, P)
            want = shear_limit(p, ph, P) / P.tau_max
            assert np.allclose(got, want, rtol=1e-14, atol=1e-16)


def test_the_reload_branch_starts_from_the_flattened_fraction():
    """After straining at ``p_hist``, unloading follows the law's reload branch of the level
    ``p_f`` (``alpha1(p_f)`` = the flattened fraction) at the same ratio ``p / p_hist``: with
    the continuous form it starts exactly at the flattened fraction and falls monotonically."""
    P = law(continuous_reload=True)
    ph = 0.2 * H
    pf = flattening_update(0.0, ph, ph, 0.05, P)
    a_f = alpha_first(pf, P)
    assert a_f > alpha_first(ph, P) + 0.1
    assert flattened_alpha(ph, ph, pf, P) == a_f  # loaded at p_hist: the flattened fraction
    q = np.linspace(0.01, 0.999999, 300)
    a = flattened_alpha(q * ph, ph, pf, P)
    assert a[-1] == pytest.approx(a_f, rel=1e-5)
    assert np.all(np.diff(a) > 0)
    assert np.allclose(a, alpha_reload(q * pf, pf, P), rtol=1e-14)
    # and above the history: the flattened fraction until the pressure alone exceeds it
    assert flattened_alpha(1.5 * ph, ph, pf, P) == a_f
    assert flattened_alpha(1.1 * pf, ph, pf, P) == alpha_first(1.1 * pf, P)
    # the paper's form keeps its own jump at the history, read at the level p_f
    Pj = law()
    jump = alpha_first(pf, Pj) - alpha_reload(pf, pf, Pj)
    assert a_f - flattened_alpha(ph * (1 - 1e-12), ph, pf, Pj) == pytest.approx(jump, rel=1e-6)


def test_the_export_says_where_a_host_runs_the_law_without_flattening(tmp_path):
    """Abaqus' FRIC gets no bulk strain: exported with --without-flattening (exit 0; refused with
    exit 2 without it), its README says the block is not run;
    a table of the pressure alone cannot carry the block: refused (exit 2), nothing written."""
    from frictionlaw.export.cli import main

    path = tmp_path / "params.json"
    law().to_json(path)
    base = ["abaqus-fric", "--params", str(path), "--out", str(tmp_path / "x")]
    assert main(base) == 2 and not (tmp_path / "x").exists()  # only with the user's word
    assert main([*base, "--without-flattening"]) == 0
    readme = (tmp_path / "x" / "README.md").read_text(encoding="utf-8")
    assert "flattening block (issue 43) is not run" in readme
    assert "runs without flattening" in readme
    assert main(["abaqus-table", "--params", str(path), "--out", str(tmp_path / "t")]) == 2
    assert not (tmp_path / "t").exists()


def test_extreme_inputs_give_no_warning_and_bad_ones_are_named():
    """A modulus of 1e-300 (no limit), a pressure of 1e-300 Pa (below the floor: no strain
    flattens it), non-finite histories and the rate functions' domains (the probe's cases)."""
    import warnings

    from frictionlaw.flattening import lattice_hardening_limit

    P = law()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        base = flattening_curve(0.1 * H, [0.0, 0.01], P)
        assert np.array_equal(flattening_curve(0.1 * H, [0.0, 0.01], P, hardening=1e-300), base)
        assert lattice_hardening_limit(1e8, 5e-324, 0.5) == np.inf
        assert lattice_hardening_limit([1e8, 1e8], [0.0, 5e-324], 1.0).tolist() == [np.inf] * 2
        eq = equivalent_strain([1e-300, 1e-100, 1e-300], [H, H, 1e-300], P)
        assert eq.tolist() == [np.inf, np.inf, 0.0]
    for call, name in (
        (lambda: flattened_alpha(1e8, np.inf, 0.0, P), "p_hist and p_f must be finite"),
        (lambda: layer_sink_rate(2.0, 1.0), "r must be in \\[0, 1\\]"),
        (lambda: lattice_sink_rate(5.0, 0.1), "alpha must be a contact fraction"),
        (lambda: lattice_hardening_limit(1e8, -1.0, 0.5), "hardening must be finite and >= 0"),
        (lambda: lattice_hardening_limit(1e8, 1e9, 1.5), "alpha must be a contact fraction"),
        (lambda: lattice_hardening_limit([1e8] * 3, 1e9, [0.1, 0.2]), "alpha has shape \\(2,\\)"),
        (lambda: contact_growth_rate(np.nan, 1e8, 0.3, 0.1, 1.0, 3e8), "p must not contain NaN"),
        (lambda: contact_growth_rate(1e8, 0.0, 0.3, 0.1, 1.0, 3e8), "p_f must be > 0"),
        (lambda: contact_growth_rate(1e8, 2e8, 0.3, 0.0, 1.0, 3e8), "slope must be finite and > 0"),
    ):
        with pytest.raises(ValueError, match=name):
            call()

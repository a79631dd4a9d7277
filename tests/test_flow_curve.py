"""The sheet's flow curve (frictionlaw.flow_curve) and the flattening along it.

Swift's curve and a table against their closed forms, the text a command line takes, and
``flattening_curve(..., flow_curve=)`` against an ODE solver integrating Eq. F3 with the
curve's flow stress and hardening modulus at every strain (SciPy, independent of Eq. F6's
solver), its midpoint convergence, and the fit of ``beta`` to a sheet measured with its curve.
"""

import math

import numpy as np
import pytest

from frictionlaw import Flattening, FrictionParams, alpha_first, flattening_curve
from frictionlaw.flattening import (
    STRETCH_PER_EQUIVALENT_STRAIN,
    flattening_pressure,
    lattice_hardening_limit,
    lattice_sink_rate,
    layer_sink_rate,
)
from frictionlaw.flattening_curves import FlatteningPaths
from frictionlaw.flow_curve import (
    SwiftCurve,
    TabulatedCurve,
    flow_curve_from_dict,
    read_flow_curve,
)
from halfspace_calib.pipeline.sweep.flattening import FlatteningData, fit_beta

H = 8e8
LAW = FrictionParams(
    m=0.5, sigma_y=H / 2.8, H=H, C1=1.05, n1=2.87, C2=7.44, n2=0.575,
    flattening=Flattening(slope=0.05),
)  # fmt: skip
#: DC04's Swift curve (the FE demo's sheet)
DC04 = SwiftCurve(530e6, 0.006, 0.24)


def test_swift_against_its_closed_form():
    e = np.array([0.0, 0.01, 0.2, 1.5])
    assert np.allclose(DC04.sigma_y(e), 530e6 * (0.006 + e) ** 0.24, rtol=1e-15)
    d = 1e-7
    fd = (DC04.sigma_y(e + d) - DC04.sigma_y(e + 0.0)) / d
    assert np.allclose(DC04.hardening(e + d / 2), fd, rtol=1e-5)
    assert DC04.hardening(0.0) == pytest.approx(0.24 * 530e6 * 0.006 ** (-0.76), rel=1e-14)
    flat = SwiftCurve(3e8, 0.1, 0.0)  # n = 0: perfectly plastic at K
    assert np.all(flat.sigma_y(e) == 3e8) and np.all(flat.hardening(e) == 0.0)
    assert flow_curve_from_dict(DC04.to_dict()) == DC04


def test_table_interpolates_and_gives_the_segments_slopes():
    t = TabulatedCurve((0.0, 0.1, 0.3), (2e8, 3e8, 3.5e8))
    assert t.sigma_y([0.0, 0.05, 0.1, 0.2, 0.3]).tolist() == pytest.approx(
        [2e8, 2.5e8, 3e8, 3.25e8, 3.5e8], rel=1e-15
    )
    assert t.hardening([0.0, 0.05, 0.1, 0.2, 0.3]).tolist() == pytest.approx(
        [1e9, 1e9, 2.5e8, 2.5e8, 2.5e8], rel=1e-12
    )
    with pytest.raises(ValueError, match="beyond the flow curve's last strain 0.3"):
        t.sigma_y(0.31)
    assert flow_curve_from_dict(t.to_dict()) == t


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (((0.01, 0.1), (2e8, 3e8)), "start at 0 and increase strictly"),
        (((0.0, 0.1, 0.1), (2e8, 3e8, 3e8)), "start at 0 and increase strictly"),
        (((0.0, 0.1), (3e8, 2e8)), "falls with strain"),
        (((0.0, 0.1), (200.0, 300.0)), r"sigma_y must be in \[1000, 1e\+13\] Pa"),
        (((0.0,), (2e8,)), "same length >= 2"),
    ],
)
def test_a_bad_table_is_refused_naming_why(args, match):
    with pytest.raises(ValueError, match=match):
        TabulatedCurve(*args)


@pytest.mark.parametrize(
    ("args", "match"),
    [
        ((530.0, 0.006, 0.24), r"K \(Pa\) must be in"),  # MPa typed for Pa
        ((530e6, 0.0, 0.24), r"eps0 must be in \(0, 1\]"),
        ((530e6, 0.006, 1.5), r"n must be in \[0, 1\]"),
        ((530e6, math.nan, 0.24), "eps0 must be in"),
        ((True, 0.006, 0.24), "K"),
    ],
)
def test_a_bad_swift_curve_is_refused_naming_the_parameter(args, match):
    with pytest.raises(ValueError, match=match):
        SwiftCurve(*args)


def test_the_command_line_text(tmp_path):
    assert read_flow_curve(" swift:530e6,0.006,0.24") == DC04
    f = tmp_path / "dc04.csv"
    f.write_text(
        "\ufeff# tensile test, true stress\nStrain;Sigma_y_MPa\n0;155\n0.1;300\n\n0.3;380\n"
    )
    t = read_flow_curve(str(f))
    assert t.strain == (0.0, 0.1, 0.3) and t.sigma_y_points == (155e6, 300e6, 380e6)
    with pytest.raises(ValueError, match="swift takes three numbers"):
        read_flow_curve("swift:530e6,0.006")
    with pytest.raises(ValueError, match="neither swift:K,eps0,n nor an existing CSV"):
        read_flow_curve(str(tmp_path / "none.csv"))
    f.write_text("strain,stress\n0,1e8\n0.1,2e8\n")
    with pytest.raises(ValueError, match="'stress' gives no unit: name it with one, e.g. sigma_y"):
        read_flow_curve(str(f))
    f.write_text("strain,force_kN\n0,1\n0.1,2\n")
    with pytest.raises(ValueError, match="must name the columns strain and sigma_y with its unit"):
        read_flow_curve(str(f))
    f.write_text("strain;sigma_y_MPa\n0;155\n0,1;300\n")  # a German sheet: decimal commas
    assert read_flow_curve(str(f)).strain == (0.0, 0.1)
    f.write_text("strain,sigma_y_MPa\n0,155\n0,1,300\n")
    with pytest.raises(ValueError, match="line 3: 3 cells under a header of 2 columns .a decimal"):
        read_flow_curve(str(f))
    f.write_text("strain,sigma_y_MPa\n0,155\n0.1,140\n")
    with pytest.raises(ValueError, match=f"{f.name}: tabulated flow curve: sigma_y falls"):
        read_flow_curve(str(f))


@pytest.mark.parametrize(
    "text",
    [
        "phi;kf [MPa]\n0;155\n0,1;300\n",  # a German sheet: Umformgrad and Fliessspannung
        "Umformgrad;Fließspannung\n-;N/mm²\n0;155\n0,1;300\n",  # a units row under the names
        "True strain,True stress (ksi)\n0,22.4808493482\n0.1,43.5113213191\n",  # a US sheet
        "plastic strain [%]\tflow stress / Pa\n0\t155e6\n10\t300e6\n",
        "# tensile test 3, RD\nPEEQ,sigma_y in GPa,remark\n0,0.155,yield\n0.1,0.300,\n",
        # a tensile test's export: engineering columns beside the true ones are not read, the
        # true plastic strain is read in place of the total one
        "Eng. strain;Eng. stress [MPa];True strain;True plastic strain;True stress [MPa]\n"
        "0,0008;155;0,0008;0;155\n0,106;271;0,1008;0,1;300\n",
    ],
)
def test_a_lab_flow_curve_reads_as_written(tmp_path, text):
    f = tmp_path / "curve.csv"
    f.write_text(text, encoding="utf-8")
    t = read_flow_curve(str(f))
    assert t.strain == pytest.approx((0.0, 0.1), abs=1e-15)
    # ksi: 1000 lbf / in^2, lbf = 0.45359237 kg x 9.80665 m/s^2, in = 0.0254 m (exact)
    assert t.sigma_y_points == pytest.approx((155e6, 300e6), rel=1e-8)


@pytest.mark.parametrize(
    "text, match",
    [
        (
            "engineering strain,engineering stress [MPa]\n0,155\n0.1,300\n",
            r"engineering \(nominal\) value: a flow curve is the true stress.*ln\(1 \+ e\)",
        ),
        ("strain,sigma_y [bar]\n0,1550\n0.1,3000\n", r"unknown unit 'bar'; sigma_y takes Pa, kPa"),
        ("strain,sigma_y_MPa,sigma_y_Pa\n0,155,1\n0.1,300,2\n", "the column sigma_y appears twice"),
        ("strain;kf\n-;furlong\n0;155\n0,1;300\n", r"line 2 \(the units row\).*'furlong'"),
        ("strain [MPa],sigma_y_MPa\n0,155\n0.1,300\n", "unknown unit 'MPa'; strain takes none"),
    ],
)
def test_a_flow_curve_header_the_reader_cannot_read_is_refused_naming_it(tmp_path, text, match):
    f = tmp_path / "curve.csv"
    f.write_text(text, encoding="utf-8")
    with pytest.raises(ValueError, match=match):
        read_flow_curve(str(f))


def _ode_curve(p, strains, params, curve):
    """Eq. F3 along the strain with the curve's flow stress and modulus at every strain,
    integrated in ``A`` by SciPy's adaptive Runge-Kutta (an oracle independent of Eq. F6)."""
    from scipy.integrate import solve_ivp

    f = params.flattening
    k_file = float(params.k)

    def rate(eps, y):
        a = min(float(y[0]), 1.0 - 1e-12)
        pf = float(flattening_pressure(a, params))
        s0 = 2.0 * k_file * float(curve.sigma_y(eps)) / params.sigma_y
        c = min(
            float(lattice_sink_rate(a, f.slope)),
            float(lattice_hardening_limit(p, float(curve.hardening(eps)), a)),
        )
        c += float(layer_sink_rate(p / pf, s0 / pf))
        return [STRETCH_PER_EQUIVALENT_STRAIN * f.beta * c / f.slope]

    # the layer's rate is singular at the start (A - alpha1(p) ~ eps^(2/3)): start just after
    # it from the model's own value, where both agree to 1e-12
    e0 = 1e-9
    a0 = float(flattening_curve(p, e0, params, flow_curve=curve, steps=1))
    sol = solve_ivp(rate, (e0, max(strains)), [a0], t_eval=strains, rtol=1e-10, atol=1e-12)
    assert sol.success
    return sol.y[0]


@pytest.mark.parametrize("p_over_h", [0.05, 0.3])
def test_the_curve_along_a_flow_curve_against_an_ode_solver(p_over_h):
    p = p_over_h * H
    eps = np.array([0.002, 0.005, 0.01, 0.02])
    got = flattening_curve(p, eps, LAW, flow_curve=DC04, steps=256)
    want = _ode_curve(p, eps, LAW, DC04)
    assert np.all(want < 1.0)
    assert np.allclose(got, want, rtol=0, atol=2e-5), (got, want)


def test_the_sinking_a_stiff_hardening_holds_against_an_ode_solver():
    """Eq. F2d along a flow curve: a table of two stiff segments (moduli 2 and 1 GPa) holds the
    flattening at ``alpha1(p) + 3 p / (4 h tan(theta))``, where it stays until the modulus
    falls at the knot and then grows again; against SciPy integrating Eq. F3 segment by segment
    up to that bound (an event ends the integration there, the bound holds the fraction to the
    segment's end)."""
    from scipy.integrate import solve_ivp

    curve = TabulatedCurve((0.0, 0.1, 0.4), (LAW.sigma_y, LAW.sigma_y + 2e8, LAW.sigma_y + 5e8))
    p, f = 0.05 * H, LAW.flattening
    eps = np.array([0.02, 0.05, 0.1, 0.105, 0.2, 0.3])

    def rate(e, y):
        a = min(float(y[0]), 1.0 - 1e-12)
        pf = float(flattening_pressure(a, LAW))
        s0 = 2.0 * float(LAW.k) * float(curve.sigma_y(e)) / LAW.sigma_y
        h = float(curve.hardening(e))
        c = min(float(lattice_sink_rate(a, f.slope)), float(lattice_hardening_limit(p, h, a)))
        c += float(layer_sink_rate(p / pf, s0 / pf))
        return [STRETCH_PER_EQUIVALENT_STRAIN * f.beta * c / f.slope]

    e0 = 1e-9  # the layer's singular start, as in the test above
    a = float(flattening_curve(p, e0, LAW, flow_curve=curve, steps=1))
    want, held = [], []
    for lo, hi, h in ((e0, 0.1, 2e9), (0.1, 0.3, 1e9)):
        bound = float(alpha_first(p, LAW)) + 0.75 * p / (h * f.slope)
        held.append(bound)
        at = eps[(eps > lo) & (eps <= hi)]
        sol = solve_ivp(
            rate, (lo, hi), [a], dense_output=True, rtol=1e-10, atol=1e-12,
            events=lambda e, y, b=bound: y[0] - b,
        )  # fmt: skip
        stop = sol.t_events[0][0] if sol.t_events[0].size else math.inf
        want += [bound if e >= stop else float(sol.sol(e)[0]) for e in at]
        a = bound if stop < hi else float(sol.sol(hi)[0])
    want = np.array(want)
    got = flattening_curve(p, eps, LAW, flow_curve=curve, steps=630)  # the knot a step end
    # the first segment reaches its bound before the knot, the second rises from it to its own
    assert want[0] < held[0] - 0.01 and np.all(want[1:3] == held[0])
    assert held[0] + 0.03 < want[3] < held[1] - 0.01 and want[-1] == held[1]
    assert np.allclose(got, want, rtol=0, atol=2e-5), (got, want)


def test_the_midpoint_steps_converge_at_second_order():
    p, eps = 0.05 * H, np.array([0.005, 0.02, 0.05])
    ref = flattening_curve(p, eps, LAW, flow_curve=DC04, steps=512)
    err = [
        np.abs(flattening_curve(p, eps, LAW, flow_curve=DC04, steps=s) - ref).max()
        for s in (8, 16, 32)
    ]
    assert err[0] > err[1] > err[2] and err[2] < 1e-5
    assert 2.5 < err[0] / err[1] < 6 and 2.5 < err[1] / err[2] < 6


def test_a_perfectly_plastic_curve_is_the_law_at_that_flow_stress():
    p, eps = np.array([0.05, 0.3]) * H, np.array([0.0, 0.004, 0.01])
    curve = SwiftCurve(1.2 * LAW.sigma_y, 0.5, 0.0)
    got = flattening_curve(p[:, None], eps, LAW, flow_curve=curve, steps=7)
    want = flattening_curve(p[:, None], eps, LAW, sigma_y=1.2 * LAW.sigma_y)
    assert np.allclose(got, want, rtol=0, atol=1e-12)
    assert np.array_equal(got[:, 0], alpha_first(p, LAW))


def test_hardening_slows_the_flattening_at_low_pressure():
    """DC04's modulus limits the lattice (Eq. F2c): at 0.05 H the sheet flattens slower along its
    curve than a perfectly plastic sheet at its initial flow stress, never falling, at most 1."""
    p, eps = 0.05 * H, np.linspace(0.0, 0.3, 31)
    a = flattening_curve(p, eps, LAW, flow_curve=DC04)
    plastic = flattening_curve(p, eps, LAW, sigma_y=float(DC04.sigma_y(0.0)))
    assert np.all(np.diff(a) >= 0) and a.max() <= 1.0 and a[-1] > a[0] + 0.3
    rising = plastic < 1.0
    assert rising.sum() >= 4 and np.all(a[1:][rising[1:]] < plastic[1:][rising[1:]] - 0.05)


@pytest.mark.parametrize("steps", [0, -3, 2.5, True, np.int64(0), "64", 100_001])
def test_steps_is_checked_with_and_without_a_flow_curve(steps):
    for kw in ({}, {"flow_curve": DC04}):  # a typo is caught whether or not a curve is given
        with pytest.raises(ValueError, match=r"steps must be an integer in \[1, 100000\]"):
            flattening_curve(0.1 * H, 0.01, LAW, steps=steps, **kw)


def test_steps_without_a_flow_curve_is_refused_not_ignored():
    with pytest.raises(ValueError, match="steps applies with flow_curve only"):
        flattening_curve(0.1 * H, 0.01, LAW, steps=8)
    # the default (None) is 64 steps with a curve; a numpy integer counts as an integer
    a = flattening_curve(0.1 * H, [0.0, 0.05], LAW, flow_curve=DC04)
    b = flattening_curve(0.1 * H, [0.0, 0.05], LAW, flow_curve=DC04, steps=np.int64(64))
    assert np.array_equal(a, b) and a[1] > a[0]


def test_bad_flow_curve_arguments_are_refused():
    with pytest.raises(ValueError, match="not both"):
        flattening_curve(0.1 * H, 0.01, LAW, flow_curve=DC04, sigma_y=2e8)
    with pytest.raises(ValueError, match=r"steps must be an integer in \[1, 100000\]"):
        flattening_curve(0.1 * H, 0.01, LAW, flow_curve=DC04, steps=0)
    t = TabulatedCurve((0.0, 0.1), (2e8, 3e8))
    with pytest.raises(ValueError, match="strains reach 0.2, beyond the flow curve's last"):
        flattening_curve(0.1 * H, [0.05, 0.2], LAW, flow_curve=t)
    with pytest.raises(ValueError, match="sigma_y must be in"):
        from frictionlaw.flattening import flattening_update

        flattening_update(0.0, 0.0, [1e8, 1e8], 0.01, LAW, sigma_y=[2e8, -1.0])


def test_beta_of_a_sheet_measured_with_its_flow_curve_is_recovered():
    """Points made with DC04's curve at beta = 0.7 (by the fit's model, one path a pressure,
    which the per-point midpoint steps approach): the fit with the curve returns 0.7; without
    it (a perfectly plastic sheet) it returns another beta, which absorbs the hardening."""
    strain = np.array([0.0, 0.005, 0.01, 0.02, 0.05, 0.005, 0.01, 0.02])
    p = np.r_[np.full(5, 0.05), np.full(3, 0.2)] * H
    made = LAW.replace(flattening=Flattening(slope=0.05, beta=0.7))
    alpha = FlatteningPaths(p, strain, made, DC04).alpha()
    per_point = flattening_curve(p, strain, made, flow_curve=DC04, steps=64)
    assert np.abs(alpha - per_point).max() < 1e-5
    data = FlatteningData("lab.csv", strain, alpha, p, flow_curve=DC04)
    fit = fit_beta(LAW, data)
    assert fit["beta"] == pytest.approx(0.7, rel=1e-6) and fit["max_abs"] < 1e-7
    assert fit["flow_curve"].startswith("Swift: K 530 MPa")
    assert flow_curve_from_dict(fit["flow_curve_record"]) == DC04
    plain = fit_beta(LAW, FlatteningData("lab.csv", strain, alpha, p))
    assert plain["flow_curve"] is None and abs(plain["beta"] - 0.7) > 0.1

"""The asperity truth (fe_demo.asperity): a plane-strain strip under a rigid flat, stretched.

Exact references and conservation, on coarse meshes (each test a few seconds):

- the plane-strain element: numba kernel against the NumPy oracle, volumes, no hoop terms;
- the tangent (material + geometric term) against finite differences of the residual;
- the elastic limit: Westergaard's sinusoidal contact, ``alpha = (2 / pi) asin(sqrt(p / p*))``;
- a flat strip under pressure, stretched: full contact, the plane-strain yield condition
  ``sigma_xx - sigma_zz = 2 sigma_y / sqrt(3)``, volume and force balance;
- a plastic wedge: pressing alone gives ``alpha`` near ``p / H``; stretch raises it, never
  lowers it; volume (plastic flow isochoric: ``ln(V / V0)`` = elastic dilatation) and force
  balance (the support carries ``p L``);
- the flat punch against the slip-line value ``(2 + pi) k``;
- bad input named.
"""

import math

import numpy as np
import pytest

from fe_demo.asperity import (
    AsperityMesh,
    AsperityOptions,
    StripModel,
    asperity_contact_fraction,
    flat_punch_pressure,
    geometric_stiffness,
    perfectly_plastic,
    prandtl_hardness,
    sine_profile,
    strip_mesh,
    wedge_profile,
)
from fe_demo.solver.element import Assembler, internal_force, kinematics, stiffness
from fe_demo.solver.material import Material
from sbmf_cli import ParameterError

MAT = perfectly_plastic()
H = prandtl_hardness(MAT.sigma_y0)


def _distorted_strip(seed):
    px, pz = wedge_profile(8.0, 40e-6)
    strip = strip_mesh(px, pz, 20e-6, 6, 4)
    rng = np.random.default_rng(seed)
    x = strip.x + rng.uniform(-1, 1, strip.x.shape) * 0.6e-6
    return strip, x


@pytest.mark.parametrize("seed", [0, 1])
def test_plane_strain_kinematics_numba_matches_numpy(seed):
    strip, x = _distorted_strip(seed)
    ref = kinematics(x, strip.t, plane_strain=True)
    new = kinematics(x, strip.t, kernels="numba", plane_strain=True)
    assert ref.valid and new.valid
    for name in ("B", "dV", "dNdx"):
        a, b = getattr(new, name), getattr(ref, name)
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * np.abs(b).max())
    rng = np.random.default_rng(seed)
    sig = rng.normal(0, 200e6, ref.dV.shape + (4,))
    fe = internal_force(ref, sig)
    np.testing.assert_allclose(internal_force(new, sig, "numba"), fe, atol=1e-12 * abs(fe).max())
    # plane strain: the volume is the area per unit thickness (the axisymmetric weight differs)
    xs = strip.x
    assert kinematics(xs, strip.t, plane_strain=True).dV.sum() == pytest.approx(
        np.trapezoid(xs[strip.top, 1], xs[strip.top, 0]), rel=1e-12
    )
    # the out-of-plane row of B is the B-bar's volumetric correction alone: B du of a uniform
    # in-plane shear has no eps_yy
    du = np.zeros(2 * xs.shape[0])
    du[0::2] = 1e-3 * xs[:, 1]
    asm = Assembler(strip.t, xs.shape[0])
    kin = kinematics(xs, strip.t, plane_strain=True)
    eps = np.einsum("eqia,ea->eqi", kin.B, du[asm.edofs])
    assert np.abs(eps[..., 2]).max() < 1e-12
    assert np.abs(eps[..., :2]).max() < 1e-12
    np.testing.assert_allclose(eps[..., 3], 1e-3, rtol=1e-10)


def test_tangent_with_the_geometric_term_matches_finite_differences():
    """The Newton tangent (consistent material tangent + the geometric term) against forward
    differences of the residual, column by column, at a plastic state of a pressed wedge: within
    2e-3 of the column's largest entry; without the geometric term the error is larger."""
    px, pz = wedge_profile(5.0, 100e-6)
    model = StripModel(strip_mesh(px, pz, 50e-6, 8, 4), MAT, kernels="numpy")
    hmax = 50e-6 * math.tan(math.radians(5.0))
    assert model.step(0.0, w=model.w - 0.1 * hmax).converged
    area = model.tributary()
    rng = np.random.default_rng(1)
    du = np.zeros(2 * model.n_nodes)
    du[model.free] = rng.normal(0, 2e-8, int(model.free.sum()))
    w = model.w - 0.02 * hmax
    t0 = model._evaluate(du, w, None, area)
    assert (t0.eps_p > model.eps_p).sum() > 10  # plastic points in the trial
    K = model._tangent(t0, area, False).toarray()
    Kmat = (
        model._pattern(False)
        .matrix(stiffness(t0.kin, t0.D), np.where(t0.active, model.eps_n * area, 0.0))
        .toarray()
    )
    free = np.flatnonzero(model.free)
    err, err_mat = [], []
    for j, k in enumerate(free[::3]):
        d2 = du.copy()
        d2[k] += 1e-12
        col = (model._evaluate(d2, w, None, area).R - t0.R)[model.free] / 1e-12
        scale = np.abs(col).max()
        err.append(np.abs(col - K[:, 3 * j]).max() / scale)
        err_mat.append(np.abs(col - Kmat[:, 3 * j]).max() / scale)
    assert max(err) < 2e-3
    assert max(err_mat) > 2 * max(err)


def test_geometric_stiffness_of_a_uniform_stress():
    """A uniform in-plane stress: the geometric matrix of a rigid translation is zero and it
    equals the einsum of its definition on a distorted mesh."""
    strip, x = _distorted_strip(3)
    kin = kinematics(x, strip.t, plane_strain=True)
    rng = np.random.default_rng(3)
    sig = rng.normal(0, 100e6, kin.dV.shape + (4,))
    ke = geometric_stiffness(kin, sig)
    s2 = np.zeros(sig.shape[:2] + (2, 2))
    s2[..., 0, 0], s2[..., 1, 1] = sig[..., 0], sig[..., 1]
    s2[..., 0, 1] = s2[..., 1, 0] = sig[..., 3]
    g = kin.dNdx
    ref = np.einsum("eq,eqij,eqaj,eqbm->eaibm", kin.dV, s2, g, g) - np.einsum(
        "eq,eqam,eqij,eqbj->eaibm", kin.dV, g, s2, g
    )
    np.testing.assert_allclose(ke, ref.reshape(ke.shape), atol=1e-12 * abs(ref).max())
    shift = np.tile([1.0, 0.0], 4)
    assert np.abs(ke @ shift).max() < 1e-9 * np.abs(ke).max()


def test_elastic_limit_is_westergaard():
    """A sinusoidal profile (amplitude / wavelength 1e-3) on an elastic strip one wavelength
    deep: ``alpha = (2 / pi) asin(sqrt(p / p*))``, ``p* = pi E* amplitude / wavelength``
    (Westergaard; Johnson, Contact Mechanics, 1985, Sec. 13.2), to the mesh's resolution."""
    lam, amp = 100e-6, 0.1e-6
    elastic = Material(E=210e9, nu=0.3, K=1e12, eps0=1.0, n=0.0)
    e_star = elastic.E / (1 - elastic.nu**2)
    p_star = math.pi * e_star * amp / lam
    px, pz = sine_profile(amp, lam)
    nx = 48
    for ratio in (0.1, 0.4):
        res = asperity_contact_fraction(
            px, pz, ratio * p_star, [0.0], elastic, AsperityMesh(nx, 16, lam)
        )
        assert res.converged
        exact = (2 / math.pi) * math.asin(math.sqrt(ratio))
        assert res.alpha[0] == pytest.approx(exact, abs=1.0 / nx), (ratio, res.alpha[0], exact)


def test_flat_strip_stretched_under_pressure_yields_in_plane_strain():
    """No roughness: full contact at every strain, the lateral stress of plane-strain yield under
    the pressure (``2 sigma_y / sqrt(3) - p``), volume change = elastic dilatation, the support
    carries ``p L``."""
    p = 0.3 * H
    res = asperity_contact_fraction(
        [0.0, 20e-6], [0.0, 0.0], p, [0.0, 0.1, 0.3], MAT, AsperityMesh(4, 4, 10e-6)
    )
    assert res.converged and np.all(res.alpha == pytest.approx(1.0, abs=1e-12))
    lateral = res.history.lateral_stress[-1]
    assert lateral == pytest.approx(2 * MAT.sigma_y0 / math.sqrt(3) - p, rel=1e-6)
    assert res.history.p_nominal[-1] == pytest.approx(p, rel=1e-6)
    assert abs(res.volume_change - res.elastic_dilatation) < 1e-8
    assert res.force_balance < 1e-5


@pytest.fixture(scope="module")
def wedge():
    px, pz = wedge_profile(5.0, 100e-6)
    strains = [0.0, 0.005, 0.01, 0.02, 0.05]
    return {
        p: asperity_contact_fraction(
            px, pz, p * H, strains, MAT, AsperityMesh(16, 8, 50e-6), AsperityOptions(rtol=1e-6)
        )
        for p in (0.1, 0.3)
    }


def test_plastic_wedge_pressed_alone_has_alpha_near_p_over_H(wedge):
    """A 5 degree wedge (E* tan(theta) / sigma_y = 130: plastic): the flattened tops carry a
    pressure below the punch value (a wedge flattens below (2 + pi) k) but of its order:
    ``p / H <= alpha <= 1.7 p / H`` on this coarse mesh (measured 0.158 and 0.350 at 0.1 and
    0.3 H; 0.119 and 0.327 with 64 x 24 elements, 0.6 H: 0.625)."""
    for p, res in wedge.items():
        assert res.converged, res.message
        assert p <= res.alpha_press <= 1.7 * p, (p, res.alpha_press)


def test_stretch_raises_alpha_monotonically_at_constant_pressure(wedge):
    for p, res in wedge.items():
        a = np.array(res.history.alpha)
        assert np.all(np.diff(a) >= -1.0 / 32), p  # one node may leave and re-enter
        assert np.all(np.diff(res.alpha) > 0) and res.alpha[-1] <= 1.0
        assert res.alpha[-1] > res.alpha_press + 0.3  # strong flattening by 5 % bulk strain
        assert np.allclose(res.history.p_nominal[1:], p * H, rtol=1e-5)


def test_history_records_the_surface_the_fraction_is_read_from(wedge):
    """Each increment's top surface and tool height (benchmarks/flattening_flank.py reads the
    flank from them): the nodes above the tool, with half their edges, are the recorded alpha;
    the last node sits on the stretched side ``x = L0 exp(eps)``; the valley rises towards the
    tool as the stretch flattens the wedge."""
    for res in wedge.values():
        h = res.history
        assert len(h.top) == len(h.tool) == len(h.alpha)
        for top, tool, a, e in zip(h.top, h.tool, h.alpha, h.strain, strict=True):
            x, z = top[:, 0], top[:, 1]
            trib = np.zeros(x.size)
            trib[:-1] += 0.5 * np.diff(x)
            trib[1:] += 0.5 * np.diff(x)
            assert trib[z > tool].sum() / x[-1] == pytest.approx(a, abs=1e-12)
            assert x[-1] == pytest.approx(50e-6 * math.exp(e), rel=1e-9)
        depth = np.array(h.tool) - np.array([t[-1, 1] for t in h.top])
        assert depth[-1] < 0.8 * depth[0]


def test_recorded_nodes_hold_the_top_surface_and_the_stretched_side():
    """``record_nodes`` keeps every node at each increment (a velocity-field study reads them):
    each column's last node is the recorded top surface, the right column sits at
    ``x = L0 exp(eps)``, the left on its symmetry plane; off by default."""
    x, z = wedge_profile(10.0, 100e-6)
    mat = perfectly_plastic()
    H = prandtl_hardness(mat.sigma_y0)
    opt = AsperityOptions(max_strain_step=0.005, record_nodes=True)
    mesh = AsperityMesh(8, 4, 100e-6)
    res = asperity_contact_fraction(x, z, 0.2 * H, [0.0, 0.01], mat, mesh, opt)
    h = res.history
    assert res.converged and len(h.nodes) == len(h.top) >= 3
    for nodes, top, e in zip(h.nodes, h.top, h.strain, strict=True):
        grid = nodes.reshape(9, 5, 2)
        np.testing.assert_array_equal(grid[:, -1], top)
        assert np.allclose(grid[-1, :, 0], 50e-6 * math.exp(e), rtol=1e-9)
        assert np.all(grid[0, :, 0] == 0.0)
    res = asperity_contact_fraction(x, z, 0.2 * H, [0.0, 0.005], mat, mesh)
    assert res.history.nodes == []


def test_wedge_conserves_volume_and_balances_forces(wedge):
    """After 5 % of bulk strain (local plastic strains far larger) the strip's volume change is
    its elastic dilatation to 1e-7 (measured 3e-9): the plastic flow is isochoric; the bottom
    carries the flat's load to the Newton tolerance."""
    for res in wedge.values():
        assert abs(res.volume_change - res.elastic_dilatation) < 1e-7
        assert res.force_balance < 1e-5


def test_flat_punch_reaches_the_slip_line_pressure():
    """A flat punch on the strip (4 elements under its half-width): the curve's knee (the limit
    load) lies 0-12 % above the slip-line value (2 + pi) k (measured 1.095 H; 1.055 H with 64 x 24
    elements, 1.04 H with 128 x 40: first-order convergence towards H), and the curve rises
    monotonically."""
    res = flat_punch_pressure(nx=32, nz=12, half_width=10e-6, depth=0.04, steps=40)
    assert res.converged, res.message
    assert 1.0 <= res.limit_pressure / res.H <= 1.12
    assert np.all(np.diff(res.pressure) > 0)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(p=-1.0), "p must be finite and > 0"),
        (dict(p=2 * H), "p must be below the hardness"),
        (dict(strains=[0.1, 0.0]), "strains must be non-decreasing"),
        (dict(strains=[float("nan")]), "strains must be"),
        (dict(profile_x=[0.0, 0.0]), "profile_x must be strictly increasing"),
        (dict(profile_z=[0.0]), "profile_z must have the shape"),
        (dict(material="steel"), "material must be a fe_demo Material"),
        (dict(mesh=(64, 24)), "mesh must be an AsperityMesh"),
    ],
)
def test_bad_input_is_named(kwargs, match):
    args = dict(profile_x=[0.0, 1e-5], profile_z=[0.0, 0.0], p=0.1 * H, strains=[0.0])
    args.update(material=MAT)
    args.update(kwargs)
    with pytest.raises(ParameterError, match=match):
        asperity_contact_fraction(**args)
    with pytest.raises(ParameterError, match="nx and nz"):
        AsperityMesh(1, 4)
    with pytest.raises(ParameterError, match="slope_deg"):
        wedge_profile(60.0, 1e-4)
    with pytest.raises(ParameterError, match="max_strain_step"):
        AsperityOptions(first_strain_step=0.02, max_strain_step=0.01)
    with pytest.raises(ParameterError, match="depth must exceed the deepest valley"):
        strip_mesh(*wedge_profile(10.0, 1e-4), 4e-6, 4, 4)

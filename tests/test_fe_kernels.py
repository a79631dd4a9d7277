"""Material return map and element kernels against independent references.

The numba kernels (fe_demo/solver/_kernels.py) are checked against the vectorised NumPy code, their oracle.
"""

import numpy as np
import pytest
import scipy.sparse as sp

from fe_demo.scenes import run_upsetting
from fe_demo.solver.element import (
    Assembler,
    internal_force,
    kinematics,
    stiffness,
    strain_increment,
)
from fe_demo.solver.material import DC04, Material, elastic_matrix, radial_return, von_mises
from fe_demo.solver.mesh import cylinder_mesh, ring_mesh
from fe_demo.solver.model import SolverOptions


def test_radial_return_consistency_and_tangent_by_finite_differences():
    rng = np.random.default_rng(1)
    sig0 = rng.normal(0, 80e6, (20, 4))
    ep0 = rng.uniform(0, 0.3, 20)
    sig0 *= 0.9 * DC04.flow_stress(ep0)[:, None] / von_mises(sig0)[:, None]  # inside the surface
    deps = rng.normal(0, 4e-3, (20, 4))
    sig, ep, D, plastic = radial_return(DC04, sig0, ep0, deps)
    assert plastic.sum() > 10
    # on the yield surface where plastic, unchanged eps_p and elastic update elsewhere
    np.testing.assert_allclose(von_mises(sig[plastic]), DC04.flow_stress(ep[plastic]), rtol=1e-10)
    assert np.all(ep[plastic] > ep0[plastic])
    De = elastic_matrix(DC04)
    np.testing.assert_allclose(sig[~plastic], sig0[~plastic] + deps[~plastic] @ De.T, rtol=1e-12)
    # pressure is elastic (plastic incompressibility)
    np.testing.assert_allclose(
        sig[:, :3].sum(1), sig0[:, :3].sum(1) + 3 * DC04.bulk * deps[:, :3].sum(1), rtol=1e-9
    )
    # consistent tangent = central finite differences of the return map
    h = 1e-8
    fd = np.empty_like(D)
    for j in range(4):
        e = np.zeros(4)
        e[j] = h
        sp_, _, _, _ = radial_return(DC04, sig0, ep0, deps + e)
        sm_, _, _, _ = radial_return(DC04, sig0, ep0, deps - e)
        fd[:, :, j] = (sp_ - sm_) / (2 * h)
    np.testing.assert_allclose(D, fd, rtol=1e-5, atol=1e-6 * DC04.E)


def test_uniaxial_return_matches_flow_curve():
    # uniaxial compression path: sigma_zz = -sigma_f(eps_p), total strain eps = eps_p + sigma/E
    mat = Material()
    ep_target = 0.2
    s = mat.flow_stress(ep_target)
    # strain increment in one step with lateral contraction such that sigma_rr = sigma_tt = 0
    nu_p = 0.5
    eps_z = -(ep_target + s / mat.E)
    lat = nu_p * ep_target + mat.nu * s / mat.E
    deps = np.array([[lat, eps_z, lat, 0.0]])
    sig, ep, _, _ = radial_return(mat, np.zeros((1, 4)), np.zeros(1), deps)
    assert ep[0] == pytest.approx(ep_target, rel=1e-9)
    np.testing.assert_allclose(sig[0], [0, -s, 0, 0], atol=1e-6 * s)


def test_material_validation():
    with pytest.raises(ValueError, match="nu"):
        Material(nu=0.5)
    with pytest.raises(ValueError, match="n must"):
        Material(n=1.5)
    with pytest.raises(ValueError, match="E must"):
        Material(E=-1)


def test_element_volume_patch_and_stiffness_symmetry():
    axi = ring_mesh(18e-3, 9e-3, 6e-3, nr=5, nz=3)
    x = axi.mesh.p.T.copy()
    # distort interior nodes (patch test on irregular quads)
    rng = np.random.default_rng(0)
    interior = np.setdiff1d(np.arange(x.shape[0]), axi.mesh.boundary_nodes())
    x[interior] += rng.uniform(-0.2, 0.2, (interior.size, 2)) * 0.5e-3
    kin = kinematics(x, axi.mesh.t)
    assert kin.valid
    assert kin.dV.sum() == pytest.approx(np.pi * (9e-3**2 - 4.5e-3**2) * 3e-3, rel=1e-12)
    # a linear displacement field gives its exact uniform strain at every point
    a, b, c, d = 1e-3, -2e-3, 0.5e-3, 0.0
    u = np.column_stack([a * x[:, 0] + c * x[:, 1], b * x[:, 1] + d * x[:, 0]]).ravel()
    asm = Assembler(axi.mesh.t, x.shape[0])
    eps = np.einsum("eqia,ea->eqi", kin.B, u[asm.edofs])
    # exact strain rr = a, zz = b, tt = u_r / r = a + c z / r, gamma_rz = c + d; B-bar keeps
    # its deviatoric part and replaces the volumetric part by the element mean
    zq = np.einsum("aq,ae->eq", kin.N, x[axi.mesh.t, 1])
    exact = np.stack(np.broadcast_arrays(a, b, a + c * zq / kin.r, c + d), axis=-1).astype(float)
    vol_ex = exact[..., :3].sum(-1)
    dev = eps.copy()
    dev[..., :3] -= eps[..., :3].sum(-1, keepdims=True) / 3
    dev_ex = exact.copy()
    dev_ex[..., :3] -= vol_ex[..., None] / 3
    np.testing.assert_allclose(dev, dev_ex, atol=1e-12)
    mean_ex = np.einsum("eq,eq->e", kin.dV, vol_ex) / kin.dV.sum(1)
    np.testing.assert_allclose(eps[..., :3].sum(-1), mean_ex[:, None] + 0 * vol_ex, atol=1e-12)
    K = asm.matrix(stiffness(kin, np.broadcast_to(elastic_matrix(DC04), kin.dV.shape + (4, 4))))
    assert abs(K - K.T).max() < 1e-9 * abs(K).max()
    # f_int = K u for a linear material
    sig = np.einsum("ij,eqj->eqi", elastic_matrix(DC04), eps)
    np.testing.assert_allclose(asm.vector(internal_force(kin, sig)), K @ u, rtol=1e-9, atol=1e-6)


def test_mesh_validation():
    with pytest.raises(ValueError, match="nr"):
        cylinder_mesh(nr=0)
    with pytest.raises(ValueError, match="inner_diameter"):
        ring_mesh(10e-3, 12e-3, 4e-3)
    axi = cylinder_mesh(20e-3, 10e-3, nr=4, nz=2)
    assert axi.n_elements == 8 and axi.axis_nodes.size == 3 and axi.sym_nodes.size == 5


# ---------------------------------------------------------------- numba kernels vs NumPy oracles


def _distorted_mesh(seed, nr=6, nz=4):
    """A ring mesh with randomly moved interior nodes (irregular, valid quads)."""
    axi = ring_mesh(18e-3, 9e-3, 6e-3, nr=nr, nz=nz)
    x = axi.mesh.p.T.copy()
    rng = np.random.default_rng(seed)
    interior = np.setdiff1d(np.arange(x.shape[0]), axi.mesh.boundary_nodes())
    x[interior] += rng.uniform(-0.25, 0.25, (interior.size, 2)) * 0.5e-3
    return axi, x


def _close(a, b, rtol=1e-12):
    """Agreement relative to the largest magnitude of the oracle."""
    np.testing.assert_allclose(a, b, rtol=0, atol=rtol * np.abs(b).max())


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_numba_kinematics_internal_force_and_stiffness_match_numpy(seed):
    axi, x = _distorted_mesh(seed)
    t = axi.mesh.t
    ref = kinematics(x, t)
    new = kinematics(x, t, kernels="numba")
    assert ref.valid and new.valid and new.min_detJ == pytest.approx(ref.min_detJ, rel=1e-14)
    for name in ("B", "dV", "r", "dNdx"):
        _close(getattr(new, name), getattr(ref, name))
    rng = np.random.default_rng(seed)
    ne, nq = ref.dV.shape
    sig = rng.normal(0, 200e6, (ne, nq, 4))
    _close(internal_force(new, sig, kernels="numba"), internal_force(ref, sig))
    # a random (unsymmetric) D per point, and the elastic D
    D = rng.normal(0, 100e9, (ne, nq, 4, 4))
    _close(stiffness(new, D, kernels="numba"), stiffness(ref, D))
    De = np.broadcast_to(elastic_matrix(DC04), (ne, nq, 4, 4))
    _close(stiffness(new, De, kernels="numba"), stiffness(ref, De))


def test_numba_kinematics_flags_an_inverted_element():
    axi, x = _distorted_mesh(0)
    t = axi.mesh.t
    x[t[2, 5]] = x[t[0, 5]] - 0.3 * (x[t[2, 5]] - x[t[0, 5]])  # fold element 5
    ref = kinematics(x, t)
    new = kinematics(x, t, kernels="numba")
    assert not ref.valid and not new.valid
    assert new.min_detJ == pytest.approx(ref.min_detJ, rel=1e-12)
    _close(new.B, ref.B)
    _close(new.dV, ref.dV)


def test_numba_strain_increment_and_rotation_match_numpy():
    axi, x = _distorted_mesh(3)
    kin = kinematics(x, axi.mesh.t)
    asm = Assembler(axi.mesh.t, x.shape[0])
    rng = np.random.default_rng(3)
    du = rng.normal(0, 1e-5, 2 * x.shape[0])
    sig = rng.normal(0, 200e6, kin.dV.shape + (4,))
    d_ref, s_ref = strain_increment(kin, asm.edofs, du, sig)
    d_new, s_new = strain_increment(kin, asm.edofs, du, sig, kernels="numba")
    _close(d_new, d_ref)
    _close(s_new, s_ref)
    assert np.abs(s_ref - sig).max() > 1e-3 * np.abs(sig).max()  # the rotation did something


@pytest.mark.parametrize("mat", [DC04, Material(n=0.05, eps0=0.002), Material(n=0.5, nu=0.2)])
def test_numba_radial_return_matches_numpy(mat):
    rng = np.random.default_rng(7)
    n = 400
    sig0 = rng.normal(0, 80e6, (n, 4))
    ep0 = rng.uniform(0, 0.5, n)
    ep0[:20] = 0.0
    sig0 *= (
        rng.uniform(0.2, 1.0, n)[:, None] * mat.flow_stress(ep0)[:, None] / von_mises(sig0)[:, None]
    )
    deps = rng.normal(0, 3e-3, (n, 4)) * rng.choice([1e-3, 1.0], n)[:, None]  # elastic and plastic
    ref = radial_return(mat, sig0, ep0, deps)
    new = radial_return(mat, sig0, ep0, deps, kernels="numba")
    assert 50 < ref[3].sum() < n - 50
    np.testing.assert_array_equal(new[3], ref[3])
    _close(new[0], ref[0])
    np.testing.assert_allclose(new[1], ref[1], rtol=1e-12, atol=1e-15)
    _close(new[2], ref[2])
    # stacked shapes as the model passes them, and an all-elastic call
    ref2 = radial_return(mat, sig0.reshape(100, 4, 4), ep0.reshape(100, 4), deps.reshape(100, 4, 4))
    new2 = radial_return(
        mat, sig0.reshape(100, 4, 4), ep0.reshape(100, 4), deps.reshape(100, 4, 4), kernels="numba"
    )
    assert new2[2].shape == (100, 4, 4, 4)
    _close(new2[0], ref2[0])
    el = radial_return(mat, 0 * sig0, ep0, 1e-9 * deps, kernels="numba")
    assert not el[3].any()
    _close(el[0], radial_return(mat, 0 * sig0, ep0, 1e-9 * deps)[0])


def test_bad_kernels_name():
    with pytest.raises(ValueError, match="kernels must be one of"):
        kinematics(np.zeros((4, 2)), np.zeros((4, 1), int), kernels="fortran")
    with pytest.raises(ValueError, match="kernels must be"):
        radial_return(DC04, np.zeros((1, 4)), np.zeros(1), np.zeros((1, 4)), kernels="c")
    with pytest.raises(ValueError, match="kernels must be one of"):
        SolverOptions(kernels="cuda")


def test_reduced_pattern_matches_the_sliced_global_matrix():
    axi, x = _distorted_mesh(4)
    t = axi.mesh.t
    asm = Assembler(t, x.shape[0])
    kin = kinematics(x, t)
    rng = np.random.default_rng(4)
    ke = stiffness(kin, rng.normal(0, 100e9, kin.dV.shape + (4, 4)))
    free = rng.random(asm.n_dof) > 0.2
    nodes = np.unique(t[2])[:5]
    zi, ri = 2 * nodes + 1, 2 * nodes
    rows, cols = np.concatenate([zi, ri, ri]), np.concatenate([zi, ri, zi])
    extra = rng.normal(0, 1e9, rows.size)
    extra[:2] = 0.0  # zero entries keep their place in the pattern
    full = asm.matrix(ke) + sp.coo_matrix((extra, (rows, cols)), shape=(asm.n_dof,) * 2).tocsr()
    ref = full[free][:, free].toarray()
    for fmt in ("csc", "csr"):
        pat = asm.reduced(free, rows, cols, fmt)
        K = pat.matrix(ke, extra[:5], extra[5:])
        assert K.format == fmt and K.nnz == pat.nnz
        _close(K.toarray(), ref)
    with pytest.raises(ValueError, match="values for a pattern"):
        pat.matrix(ke)


def test_numba_and_numpy_runs_give_the_same_force():
    kw = {"m": 0.3, "nr": 10, "n_increments": 10, "reduction": 0.3}
    opt = {"linear_solver": "superlu"}
    ref = run_upsetting("tresca", options=SolverOptions(kernels="numpy", **opt), **kw)
    new = run_upsetting("tresca", options=SolverOptions(kernels="numba", **opt), **kw)
    assert ref.converged and new.converged
    assert new.info["kernels"] == "numba" and ref.info["kernels"] == "numpy"
    assert new.info["newton_iterations"] == ref.info["newton_iterations"]
    np.testing.assert_allclose(new.history["force"], ref.history["force"], rtol=1e-9)
    np.testing.assert_allclose(new.model.x, ref.model.x, rtol=0, atol=1e-13)
    _close(new.model.sigma, ref.model.sigma, rtol=1e-8)

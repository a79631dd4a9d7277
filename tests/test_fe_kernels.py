"""Material return map and element kernels against independent references."""

import numpy as np
import pytest

from fe_demo.element import Assembler, internal_force, kinematics, stiffness
from fe_demo.material import DC04, Material, elastic_matrix, radial_return, von_mises
from fe_demo.mesh import cylinder_mesh, ring_mesh


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

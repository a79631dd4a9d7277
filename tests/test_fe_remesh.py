"""Remeshing with field transfer: geometry, transferred fields and p_hist, continued run."""

import copy

import numpy as np
import pytest

from fe_demo.scenes import run_ring
from fe_demo.solver.element import kinematics
from fe_demo.solver.remesh import _coons, block_corners, element_quality, remesh


def test_coons_reproduces_a_rectangular_grid_and_quality():
    r = np.linspace(1.0, 3.0, 5)
    z = np.linspace(0.0, 1.0, 4)
    R, Z = np.meshgrid(r, z, indexing="ij")
    grid = np.stack([R, Z], axis=-1)
    out = _coons(grid[:, 0], grid[:, -1], grid[0, :], grid[-1, :])
    np.testing.assert_allclose(out, grid, atol=1e-14)
    x = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [2, 0], [3, 1.0]], float)
    t = np.array([[0, 1, 2, 3], [1, 4, 5, 2]]).T
    q = element_quality(x, t)
    assert q[0] == pytest.approx(1.0) and 0 < q[1] < 1


def test_remesh_transfers_fields_and_keeps_history():
    res = run_ring("tresca", m=1.0, nr=8, n_increments=20, reduction=0.4)
    assert res.converged
    model = res.model
    twin = copy.deepcopy(model)
    q0 = element_quality(model.x, model.t, block_corners(model.axi)).min()
    ph_old = np.array(model.contact.state.p_hist)
    ep_old = model.eps_p.copy()
    vol_old = kinematics(model.x, model.t).dV.sum()
    q1 = remesh(model)
    assert q1 > q0 and model.n_remesh == 1
    # p_hist values are inherited from old contact nodes, never invented
    ph_new = np.array(model.contact.state.p_hist)
    assert np.isin(ph_new, ph_old).all()
    assert ph_new.max() == pytest.approx(ph_old.max())
    # volume and plastic-strain range are kept (linear interpolation is bounded)
    assert kinematics(model.x, model.t).dV.sum() == pytest.approx(vol_old, rel=5e-3)
    assert model.eps_p.max() <= ep_old.max() + 1e-12
    assert model.eps_p.min() >= ep_old.min() - 1e-12
    # both continue; the remeshed run stays close to the original one
    dz = -0.01 * model.h0 / 2
    for _ in range(3):
        assert model.increment(dz).converged
        assert twin.increment(dz).converged
    node = model.axi.inner_mid_node
    assert model.x[node, 0] == pytest.approx(twin.x[node, 0], rel=0.01)
    assert model.die_force() == pytest.approx(twin.die_force(), rel=0.03)

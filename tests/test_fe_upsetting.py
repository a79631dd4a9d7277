import numpy as np
import pytest

from fe_demo.solver.material import DC04
from fe_demo.solver.mesh import cylinder_mesh
from fe_demo.solver.model import FormingModel


def _frictionless(n_inc=10, reduction=0.5, nr=8, nz=4):
    axi = cylinder_mesh(20e-3, 10e-3, nr=nr, nz=nz)
    model = FormingModel(axi)
    dz = -reduction * model.h0 / 2 / n_inc
    rows = []
    for _ in range(n_inc):
        res = model.increment(dz)
        assert res.converged, res.message
        rows.append(model)
        ep = model.eps_p
        r_out = model.x[:, 0].max()
        rows[-1] = (model.height_reduction, model.die_force(), ep.min(), ep.max(), r_out)
    return model, rows


def test_frictionless_upsetting_is_homogeneous():
    model, rows = _frictionless()
    for _red, force, ep_min, ep_max, r_out in rows:
        # homogeneous plastic strain everywhere (penalty penetration ~1e-7 m is the only
        # source of non-uniformity)
        assert ep_max - ep_min < 2e-3 * ep_max
        # force = flow stress(strain) x current area within 1 %
        ref = DC04.flow_stress(ep_max) * np.pi * r_out**2
        assert force == pytest.approx(ref, rel=1e-2)
    # no barreling: every node keeps r proportional to its initial r
    x, X = model.x, model.X0
    lam = x[:, 0].max() / X[:, 0].max()
    np.testing.assert_allclose(x[:, 0], lam * X[:, 0], rtol=0, atol=1e-4 * X[:, 0].max())
    # volume (plastic incompressibility) -> lam^2 * h/h0 = 1 up to elastic dilatation
    assert lam**2 * (1 - rows[-1][0]) == pytest.approx(1.0, abs=2e-3)
    # total logarithmic strain matches ln(h0/h): eps_p + sigma/E
    red = rows[-1][0]
    sig = DC04.flow_stress(rows[-1][3])
    assert rows[-1][3] + sig / DC04.E == pytest.approx(np.log(1 / (1 - red)), rel=2e-3)

"""Why fe_demo assembles its own tangent beside scikit-fem: the same matrix both ways, timed.

On the default upsetting mesh (64 x 32 = 2,048 bilinear quads) this assembles the axisymmetric
tangent ``int B^T D B 2 pi r dA`` with a different 4 x 4 material tangent ``D`` at every Gauss point
(the per-point state of J2 plasticity) twice:

- fe_demo's own path: ``kinematics`` (B matrices) + ``stiffness`` (batched matmul) +
  ``Assembler.matrix`` (precomputed COO-to-CSR pattern);
- scikit-fem's ``BilinearForm`` / ``asm`` with the same ``D`` passed as a per-point field, on
  ``ElementVector(ElementQuad1())`` with the 2 x 2 Gauss rule.

Plain B (no B-bar) on both, so the matrices must agree to rounding: the check. fe_demo's B-bar
replaces the volumetric row by its element average, which a pointwise scikit-fem form cannot
express. Best of 5 CPU times. Writes benchmarks/results/skfem_boundary.csv.

Run: python benchmarks/bench_skfem_boundary.py [nr]   (default 64)
"""

import csv
import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from _provenance import run_record
from skfem import Basis, BilinearForm, ElementQuad1, ElementVector, asm
from skfem.quadrature import get_quadrature
from skfem.refdom import RefQuad

import fe_demo.solver.element as E
from fe_demo.solver.material import DC04, elastic_matrix
from fe_demo.solver.mesh import cylinder_mesh

OUT = Path(__file__).resolve().parent / "results"


def _best(f, repeat=5):
    best, out = math.inf, None
    for _ in range(repeat):
        t0 = time.process_time()
        out = f()
        best = min(best, time.process_time() - t0)
    return best, out


def _plain_kinematics(x, t):
    """fe_demo's kinematics with the B-bar correction undone (plain B, comparable to skfem)."""
    kin = E.kinematics(x, t)
    B = np.zeros_like(kin.B)
    B[..., 0, 0::2] = kin.dNdx[..., 0]
    B[..., 1, 1::2] = kin.dNdx[..., 1]
    B[..., 2, 0::2] = kin.N.T[None, :, :] / kin.r[..., None]
    B[..., 3, 0::2] = kin.dNdx[..., 1]
    B[..., 3, 1::2] = kin.dNdx[..., 0]
    kin.B = B
    return kin


def main(nr):
    OUT.mkdir(exist_ok=True)
    axi = cylinder_mesh(20e-3, 10e-3, nr)
    mesh = axi.mesh
    x, t = mesh.p.T.copy(), mesh.t
    ne = t.shape[1]
    rng = np.random.default_rng(0)
    De = elastic_matrix(DC04)
    D = De[None, None] * (1.0 + 0.1 * rng.random((ne, 4, 1, 1)))  # per-point tangents
    asmr = E.Assembler(t, x.shape[0])

    def own():
        kin = _plain_kinematics(x, t)
        return asmr.matrix(E.stiffness(kin, D))

    def own_bbar():
        return asmr.matrix(E.stiffness(E.kinematics(x, t), D))

    # scikit-fem: same element, same 2 x 2 Gauss rule; dofs interleaved (r, z) per node as ours
    basis = Basis(mesh, ElementVector(ElementQuad1()), quadrature=get_quadrature(RefQuad, 2))
    Dq = np.moveaxis(D, (0, 1), (2, 3))  # (4, 4, ne, nq)

    @BilinearForm
    def tangent(u, v, w):
        r = w.x[0]

        def strain(f):  # Voigt (rr, zz, tt, rz), engineering shear, stacked (4, ne, nq)
            g = f.grad
            return np.stack([g[0][0], g[1][1], f.value[0] / r, g[0][1] + g[1][0]])

        eu, ev = strain(u), strain(v)
        return 2.0 * np.pi * r * np.einsum("ien,ijen,jen->en", ev, w["D"], eu, optimize=True)

    def sk():
        return asm(tangent, basis, D=Dq).tocsr()

    t_own, K_own = _best(own)
    t_bbar, _ = _best(own_bbar)
    t_sk, K_sk = _best(sk)
    # scikit-fem orders the vector dofs node-major (r, z per node) like ours? map through basis
    perm = basis.nodal_dofs.T.ravel()  # our dof 2 n + c -> skfem dof nodal_dofs[c, n]
    K_sk_ours = K_sk[perm][:, perm]
    diff = abs(K_sk_ours - K_own).max() / abs(K_own).max()
    rows = [
        {"path": "fe_demo: kinematics + stiffness + Assembler (plain B)", "cpu_ms": 1e3 * t_own},
        {"path": "fe_demo: the same with B-bar (what the model runs)", "cpu_ms": 1e3 * t_bbar},
        {"path": "scikit-fem BilinearForm + asm (plain B)", "cpu_ms": 1e3 * t_sk},
    ]
    for r in rows:
        r.update(elements=ne, max_rel_diff_plain=diff)
    with (OUT / "skfem_boundary.csv").open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(f"{ne} quads; plain-B matrices agree to {diff:.1e} (max |diff| / max |K|)")
    for r in rows:
        print(f"{r['path']:58s} {r['cpu_ms']:7.1f} ms")


if __name__ == "__main__":
    with run_record(__file__):
        main(int(sys.argv[1]) if len(sys.argv) > 1 else 64)

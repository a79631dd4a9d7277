"""The Newton tangent's linear solve: a reused LU with iterative refinement gives the direct answer."""

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.sparse.linalg import spsolve

from fe_demo.scenes import run_upsetting
from fe_demo.solver import linsolve
from fe_demo.solver.linsolve import TangentSolver
from fe_demo.solver.model import SolverOptions


def _laplace_like(n, shift, rng):
    """An unsymmetric, diagonally dominant 2D five-point matrix with a perturbation."""
    m = int(np.sqrt(n))
    T = sp.diags([-1.0, 6.0 + shift, -1.2], [-1, 0, 1], shape=(m, m))
    eye = sp.identity(m)
    A = (sp.kron(eye, T) + sp.kron(sp.diags([-1.0, -0.8], [-1, 1], shape=(m, m)), eye)).tocsc()
    return A + sp.diags(0.01 * rng.random(m * m)).tocsc()


def test_reused_factor_gives_the_direct_answer_with_fewer_factorisations():
    rng = np.random.default_rng(3)
    s = TangentSolver(rtol=1e-10, max_iter=12)
    for k in range(6):  # slowly changing tangents, as in Newton
        A = _laplace_like(400, 0.02 * k, rng)
        b = rng.standard_normal(A.shape[0])
        x = s.solve(A, b)
        ref = spsolve(A, b)
        assert np.linalg.norm(A @ x - b) <= 1e-10 * np.linalg.norm(b)
        np.testing.assert_allclose(x, ref, rtol=0, atol=1e-8 * np.abs(ref).max())
    assert s.n_factor == 1 and s.n_krylov_solves == 5
    # a very different matrix: refinement misses the tolerance in 1 step, so it refactorises
    tight = TangentSolver(rtol=1e-10, max_iter=1)
    tight.solve(_laplace_like(400, 0.0, rng), np.ones(400))
    B = _laplace_like(400, 3.0, rng) + sp.random(400, 400, 0.01, random_state=1).tocsc()
    x = tight.solve(B.tocsc(), np.ones(400))
    assert tight.n_factor == 2
    np.testing.assert_allclose(B @ x, np.ones(400), atol=1e-10)
    # the reference path factorises every time
    ref = TangentSolver(reuse=False)
    for _ in range(3):
        ref.solve(B.tocsc(), np.ones(400))
    assert ref.n_factor == 3 and ref.n_krylov_solves == 0


def test_bad_settings():
    with pytest.raises(ValueError, match="rtol must be in"):
        TangentSolver(rtol=1e-3)
    with pytest.raises(ValueError, match="max_iter must be an integer >= 1"):
        TangentSolver(max_iter=0)


def test_upsetting_results_identical_to_the_fresh_factorisation():
    kw = {"nr": 12, "n_increments": 12, "reduction": 0.3, "progress": False}
    # SuperLU's reuse policy (max_iter 12); PARDISO's is tested below
    new = run_upsetting("sbmf", options=SolverOptions(linear_solver="superlu"), **kw)
    ref = run_upsetting(
        "sbmf", options=SolverOptions(reuse_factorisation=False, linear_solver="superlu"), **kw
    )
    assert new.converged and ref.converged
    assert new.info["newton_iterations"] == ref.info["newton_iterations"]
    ls, lr = new.info["linear_solver"], ref.info["linear_solver"]
    assert lr["factorisations"] == ref.info["newton_iterations"]
    assert ls["factorisations"] + ls["krylov_solves"] == new.info["newton_iterations"]
    assert ls["factorisations"] < 0.5 * lr["factorisations"]
    # Newton stops at |R| <= 1e-6 f_int; the linear solves differ by 1e-10: far below that
    np.testing.assert_allclose(new.history["force"], ref.history["force"], rtol=1e-8)
    np.testing.assert_allclose(new.model.x, ref.model.x, rtol=0, atol=1e-12)
    np.testing.assert_allclose(
        new.model.contact.state.p_hist, ref.model.contact.state.p_hist, rtol=1e-7, atol=1e-3
    )


needs_pardiso = pytest.mark.skipif(
    not linsolve.pardiso_available(),
    reason="pypardiso (the optional extra 'pardiso') is not installed",
)


def test_backend_choice_without_pypardiso(monkeypatch):
    monkeypatch.setattr(linsolve, "pardiso_available", lambda: False)
    assert TangentSolver(backend="auto").backend == "superlu"
    assert TangentSolver().backend == "superlu"
    with pytest.raises(ImportError, match="linear_solver='superlu'"):
        TangentSolver(backend="pardiso")
    with pytest.raises(ValueError, match="backend must be one of"):
        TangentSolver(backend="umfpack")
    with pytest.raises(ValueError, match="threads must be 1 or 2"):
        TangentSolver(threads=4)


@needs_pardiso
def test_pardiso_gives_the_direct_answer_and_reuses_its_analysis():
    rng = np.random.default_rng(5)
    s = TangentSolver(backend="pardiso", rtol=1e-10)
    assert s.backend == "pardiso" and TangentSolver(backend="auto").backend == "pardiso"
    for k in range(5):
        A = _laplace_like(400, 0.3 * k, rng)
        b = rng.standard_normal(A.shape[0])
        x = s.solve(A, b)
        assert np.linalg.norm(A @ x - b) <= 1e-10 * np.linalg.norm(b)
        np.testing.assert_allclose(x, spsolve(A, b), rtol=0, atol=1e-8)
    assert s.n_factor >= 2 and s.n_factor + s.n_krylov_solves == 5
    fresh = TangentSolver(backend="pardiso", reuse=False)
    B = _laplace_like(400, 1.0, rng)
    np.testing.assert_allclose(fresh.solve(B.tocsr(), np.ones(400)), spsolve(B, np.ones(400)))
    np.testing.assert_allclose(fresh.solve(B, 2 * np.ones(400)), spsolve(B, 2 * np.ones(400)))
    assert fresh.n_factor == 2 and fresh.n_factor_symmetric == 0


@needs_pardiso
def test_pardiso_factorises_a_symmetric_tangent_as_symmetric():
    rng = np.random.default_rng(6)
    A = _laplace_like(400, 0.0, rng)
    S = (A + A.T).tocsr()  # symmetric, not positive definite after the shift below
    S = (S - sp.diags(np.full(400, 9.0))).tocsr()
    s = TangentSolver(backend="pardiso", reuse=False)
    b = rng.standard_normal(400)
    x = s.solve(S, b)
    assert s.n_factor_symmetric == 1
    assert np.linalg.norm(S @ x - b) <= 1e-10 * np.linalg.norm(b) * np.abs(x).max()
    np.testing.assert_allclose(x, spsolve(S.tocsc(), b), rtol=1e-9, atol=1e-12)
    U = S.copy()
    U.data[U.indices == 3] *= 1.0 + 1e-12  # unsymmetric beyond rounding: general LU
    np.testing.assert_allclose(s.solve(U, b), spsolve(U.tocsc(), b), rtol=1e-9, atol=1e-12)
    assert s.n_factor == 2 and s.n_factor_symmetric == 1


@needs_pardiso
@pytest.mark.parametrize("law", ["sbmf", "tresca"])
def test_upsetting_with_pardiso_matches_superlu(law):
    kw = {"nr": 12, "n_increments": 12, "reduction": 0.3, "progress": False}
    new = run_upsetting(law, options=SolverOptions(linear_solver="pardiso"), **kw)
    ref = run_upsetting(law, options=SolverOptions(linear_solver="superlu"), **kw)
    lin = new.info["linear_solver"]
    assert lin["backend"] == "pardiso"
    # Tresca's tangent is symmetric (J2 tangent, no normal-shear coupling), the SBMF law's not
    if law == "tresca":
        assert lin["symmetric_factorisations"] == lin["factorisations"]
    else:
        assert lin["symmetric_factorisations"] < lin["factorisations"]
    assert new.info["newton_iterations"] == ref.info["newton_iterations"]
    np.testing.assert_allclose(new.history["force"], ref.history["force"], rtol=1e-8)
    np.testing.assert_allclose(new.model.x, ref.model.x, rtol=0, atol=1e-12)


@needs_pardiso
def test_pardiso_memory_is_released_with_the_solver():
    """PARDISO's factors live in MKL; a dropped solver frees them (else ~30 MB per solver here)."""
    import gc
    from pathlib import Path

    def rss_mb():
        status = Path("/proc/self/status").read_text()
        return int(status.split("VmRSS:")[1].split()[0]) / 1024

    A = _laplace_like(200 * 200, 0.0, np.random.default_rng(0)).tocsr()
    b = np.ones(A.shape[0])
    TangentSolver(backend="pardiso").solve(A, b)
    gc.collect()
    before = rss_mb()
    for _ in range(15):
        s = TangentSolver(backend="pardiso")
        s.solve(A, b)
        del s
        gc.collect()
    assert rss_mb() - before < 150

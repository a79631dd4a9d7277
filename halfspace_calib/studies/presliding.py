"""Pre-sliding: the tangential traction of a loaded rough contact against the rigid shift (Sec. 2.2).

After a normal solve the tool is shifted rigidly by ``delta`` in ``+x``; the uncoupled tangential
solve (Eq. 13 with the Tresca bound of Eq. 18, :func:`halfspace_calib.contact.tangential.solve_tangential`)
gives the mean traction ``q_mean(delta)`` over the apparent area: linear while every contact element
sticks, then softening as slip spreads, and equal to the full-sliding shortcut
``tau_adh = m (sigma_y / 2) alpha_rc`` from the shift ``delta_full = max(C g)`` on (every element at
the cap).

The interface's tangential stiffness is what an FE host needs as the penalty ``k_t`` of
:func:`frictionlaw.traction_update` (Pa/m):

- ``k_t0 = d q_mean / d delta`` at ``delta -> 0`` (all elements stick, the response is exactly
  linear, so one solve at a small shift gives it exactly);
- ``k_sec = tau_adh / delta_full``: the secant to full sliding, the stiffness of the bilinear
  stick/slip law of the runtime that reaches the cap at the same shift as the rough contact. The
  last sticking elements creep to the cap over a long tail, so this one is soft;
- ``k_eq = tau_adh^2 / (2 W_c)`` with ``W_c = int_0^tau_adh delta dq`` (trapezoidal rule over
  the computed curve): the bilinear law with the same complementary energy as the rough contact up
  to full sliding, insensitive to the tail. For the concave curve ``k_sec <= k_eq <= k_t0``.

In the periodic mode (the calibration's default) the mean tangential displacement of the periodic
half-space is a gauge (no finite value), so ``delta`` is measured from the mean surface displacement:
the stiffness is that of the roughness layer only, the bulk compliance belongs to the FE model.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..common.checks import tresca_factor
from ..contact import tangential as _tang
from ..contact.materials import records

__all__ = ["PRESLIDING_FRACTIONS", "PreslidingCurve", "presliding_curve", "stiffness_power_law"]

#: shifts of the curve as fractions of ``delta_full`` (1.0 and above: full sliding)
PRESLIDING_FRACTIONS = (
    0.02,
    0.05,
    0.08,
    0.12,
    0.16,
    0.2,
    0.25,
    0.3,
    0.4,
    0.5,
    0.65,
    0.8,
    1.0,
    1.25,
)


@dataclass
class PreslidingCurve:
    """``q_mean(delta)`` of one loaded contact and its stiffness (SI units).

    Attributes
    ----------
    delta, q_mean : ndarray
        Rigid shift (m) and mean tangential traction over the apparent area (Pa), ``delta = 0``
        first.
    slip_fraction : ndarray
        Fraction of the contact elements at the cap, per shift.
    q_limit : float
        Full-sliding traction ``m (sigma_y / 2) alpha_rc`` (Pa, the shortcut).
    delta_full : float
        Smallest shift at which every contact element slides (m).
    delta_stick : float
        Largest shift with no slip at all (m): the end of the linear range.
    k_t0, k_sec, k_eq : float
        Initial, secant and energy-equivalent tangential stiffness (Pa/m), see the module
        docstring.
    converged : bool
        Every tangential solve converged.
    nit : int
        Total MPRGP iterations.
    message : str
        Status (the first failure's message if any).
    """

    delta: np.ndarray
    q_mean: np.ndarray
    slip_fraction: np.ndarray
    q_limit: float
    delta_full: float
    delta_stick: float
    k_t0: float
    k_sec: float
    k_eq: float
    converged: bool
    nit: int
    message: str

    def as_dict(self):
        """JSON-ready record."""
        return {
            "delta": [float(v) for v in self.delta],
            "q_mean": [float(v) for v in self.q_mean],
            "slip_fraction": [float(v) for v in self.slip_fraction],
            "q_limit": self.q_limit,
            "delta_full": self.delta_full,
            "delta_stick": self.delta_stick,
            "k_t0": self.k_t0,
            "k_sec": self.k_sec,
            "k_eq": self.k_eq,
            "converged": self.converged,
            "nit": self.nit,
            "message": self.message,
        }


def presliding_curve(
    p,
    dx,
    *,
    materials=None,
    solver=None,
    dy=None,
    fractions=PRESLIDING_FRACTIONS,
):
    """Tangential traction against the rigid shift up to full sliding, and the stiffness.

    Parameters
    ----------
    p : array_like, shape (nx, ny)
        Contact pressure of the normal solution (Pa); needs at least one contact element.
    dx, dy : float
        Element size (m); ``dy`` defaults to ``dx``.
    materials : Materials, optional
        The composite moduli ``E_star``, ``E_prime`` (Eqs. 2, 17), the Tresca factor ``m`` (here
        in ``(0, 1]``) and ``sigma_y``: the bound ``m sigma_y / 2`` (Eq. 18); default Table 1.
    solver : SolverSettings, optional
        ``periodic`` (periodic half-space, the calibration's default, or an isolated patch),
        ``tol`` and ``maxiter`` (``None``: 10000) of each tangential solve.
    fractions : sequence of float
        Shifts as fractions of ``delta_full`` (positive, increasing); values ``>= 1`` are full
        sliding and must give ``q_limit``.

    Returns
    -------
    PreslidingCurve
    """
    mat, sol = records(materials, solver)
    E_star, E_prime, m, sigma_y = mat.E_star, mat.E_prime, mat.m, mat.sigma_y
    maxiter = 10000 if sol.maxiter is None else sol.maxiter
    p = np.asarray(p, dtype=float)
    tresca_factor(m, allow_zero=False, why=" (m = 0: no tangential traction)")
    fr = np.asarray(fractions, dtype=float)
    if fr.ndim != 1 or fr.size < 2 or not np.all(fr > 0) or not np.all(np.diff(fr) > 0):
        raise ValueError(f"fractions must be >= 2 increasing positive values, got {fractions!r}")
    if p.ndim != 2 or not np.all(np.isfinite(p)) or not np.any(p > 0):
        raise ValueError("p must be a finite 2-D pressure map with at least one contact element")
    kw = dict(m=m, sigma_y=sigma_y, dy=dy, periodic=sol.periodic, tol=sol.tol, maxiter=maxiter)
    contact = p > 0
    n_contact = int(contact.sum())
    q_limit = float(np.mean(_tang.tangential_bound(p, m=m, sigma_y=sigma_y)))
    full = _tang.solve_tangential(p, dx, E_star, E_prime, q_mean=q_limit, **kw)
    delta_full = float(full.delta)
    results = [full]
    # initial stiffness: a shift small enough that no element slips (exactly linear response)
    d0 = 1e-3 * delta_full
    for _ in range(20):
        r0 = _tang.solve_tangential(p, dx, E_star, E_prime, delta=d0, **kw)
        results.append(r0)
        if not r0.slip.any():
            break
        d0 *= 0.25
    q_over_d = np.abs(r0.q[contact]) / d0
    g = 0.5 * m * sigma_y
    delta_stick = float(g / q_over_d.max()) if q_over_d.max() > 0 else delta_full
    k_t0 = float(r0.q_mean / d0)
    deltas, qs, slips = [0.0], [0.0], [0.0]
    q0 = None
    for f in fr:
        r = _tang.solve_tangential(p, dx, E_star, E_prime, delta=f * delta_full, q0=q0, **kw)
        results.append(r)
        q0 = r.q
        deltas.append(float(f * delta_full))
        qs.append(r.q_mean)
        slips.append(float(r.slip.sum() / n_contact))
    d_arr, q_arr = np.array(deltas), np.array(qs)
    upto = d_arr <= delta_full * (1 + 1e-12)  # the curve from 0 to full sliding
    w_c = float(np.sum(0.5 * (d_arr[upto][1:] + d_arr[upto][:-1]) * np.diff(q_arr[upto])))
    ok = all(r.converged for r in results) and not r0.slip.any()
    bad = next((r.message for r in results if not r.converged), "")
    if r0.slip.any():
        bad = "no slip-free shift found for the initial stiffness"
    return PreslidingCurve(
        delta=d_arr,
        q_mean=q_arr,
        slip_fraction=np.array(slips),
        q_limit=q_limit,
        delta_full=delta_full,
        delta_stick=delta_stick,
        k_t0=k_t0,
        k_sec=q_limit / delta_full,
        k_eq=q_limit**2 / (2 * w_c) if w_c > 0 else float("inf"),
        converged=bool(ok),
        nit=int(sum(r.nit for r in results)),
        message=bad or f"{len(results)} tangential solves converged",
    )


def stiffness_power_law(p_mean, k, p_ref=100e6):
    """Least-squares fit ``k(p) = k_ref (p / p_ref)^b`` in log-log (for a per-node ``k_t`` array).

    Parameters
    ----------
    p_mean, k : array_like
        Pressures (Pa) and stiffnesses (Pa/m), positive, at least two points.
    p_ref : float
        Reference pressure (Pa).

    Returns
    -------
    dict
        ``k_ref`` (Pa/m), ``exponent``, ``p_ref`` (Pa) and ``max_rel_error`` over the points.
    """
    p = np.asarray(p_mean, dtype=float)
    k = np.asarray(k, dtype=float)
    if p.shape != k.shape or p.size < 2 or np.any(p <= 0) or np.any(k <= 0):
        raise ValueError("p_mean and k must be positive arrays of equal length >= 2")
    b, a = np.polyfit(np.log(p / p_ref), np.log(k), 1)
    fit = np.exp(a) * (p / p_ref) ** b
    return {
        "k_ref": float(np.exp(a)),
        "exponent": float(b),
        "p_ref": float(p_ref),
        "max_rel_error": float(np.max(np.abs(fit / k - 1))),
    }

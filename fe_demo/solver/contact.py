"""Rigid flat die contact: penalty normal pressure with an active set, friction from ``frictionlaw``.

The die is the plane ``z = z_die`` above the workpiece (the half-model's mid-plane
is the symmetry plane). Every candidate node (all boundary nodes off the mid-plane,
so that free-surface nodes folding onto the die during barreling are caught) is
checked each iteration: the penetration ``g = z - z_die`` gives the pressure
``p = eps_n max(g, 0)`` (penalty, Pa/m), so a node whose contact force would turn
tensile is released. The nodal area is the consistent axisymmetric lumping
``2 pi int N_a r ds`` of the node's boundary edges at the start of the increment.

Friction: the die is fixed radially, so the slip increment of a node is its radial
displacement increment. The tangential traction comes from
:func:`frictionlaw.traction_update` with the node's traction at the last accepted
increment and the runtime's :class:`frictionlaw.HistoryState` (trial ``p_hist``
during iterations, committed only for accepted increments).

Zones (issue 42): a law with ``zone_at(r)`` (``fe_demo.scenes.zones.RadialZones``) is a die
with a law per ring; each node runs the law of the zone under it at the start of the increment
with its own ``p_hist`` (:class:`frictionlaw.ZonedLaw`, ``traction_update(..., zone=)``).

Flattening (issue 43): a die with ``flattening = True`` passes each node's bulk plastic strain
increment of the increment, the bulk's current flow stress and its hardening modulus to the
law (``traction_update(..., d_eps=, sigma_y=, hardening=)``), which flattens the node's
asperities (its ``alpha_f`` in the :class:`frictionlaw.HistoryState`, under the same
trial/commit rules as ``p_hist``). The model gives them at the contact nodes by
:func:`surface_projection`: the lumped
L2 projection of the Gauss-point values of the elements around each node, which for a node on
the die is its first element layer.

Stick stiffness: the penalty ``eps_t`` (the demo passes ``eps_n``) unless the law's
parameter file carries a calibrated ``k_t(p)`` table (:class:`frictionlaw.TangentialStiffness`);
then every node gets ``k_t`` at its pressure at the start of the increment (the last
accepted one). That value is fixed during the Newton iterations, so the tangent that
:func:`frictionlaw.traction_update` returns (which treats ``k_t`` as a constant: no
``d k_t / d p`` term in ``dt_dp``) is the exact derivative of the residual; the pressure
dependence of the stiffness lags by one increment.
"""

import math
from dataclasses import dataclass

import numpy as np

from frictionlaw import HistoryState, traction_update

__all__ = ["nodal_areas", "surface_projection", "DieContact", "ContactEval", "FREEZE_AFTER"]

#: branch flips of a node within one increment after which its branch is frozen on Eq. 24
FREEZE_AFTER = 3


def nodal_areas(x, edges, nodes):
    """Consistent axisymmetric nodal areas ``2 pi int N_a r ds`` (m^2) over ``edges``.

    Parameters
    ----------
    x : ndarray, shape (n_nodes, 2)
    edges : ndarray, shape (2, n_edges)
    nodes : ndarray
        The nodes whose areas are returned (in this order).
    """
    a, b = edges
    L = np.hypot(x[b, 0] - x[a, 0], x[b, 1] - x[a, 1])
    ra, rb = x[a, 0], x[b, 0]
    area = np.zeros(x.shape[0])
    np.add.at(area, a, 2 * np.pi * L * (2 * ra + rb) / 6.0)
    np.add.at(area, b, 2 * np.pi * L * (ra + 2 * rb) / 6.0)
    return area[nodes]


def surface_projection(t, N, dV, values, nodes):
    """Gauss-point ``values`` carried to ``nodes``: ``sum N_a dV v / sum N_a dV`` over their elements.

    The lumped L2 projection of an element field onto the nodes, restricted to ``nodes`` (a die
    node's elements are its first layer under the die). ``t`` (4, n_elements) connectivity, ``N``
    (4, n_q) shape functions at the Gauss points, ``dV`` and ``values`` (n_elements, n_q).
    """
    w = dV @ N.T  # (n_elements, 4): each element's weight at its corner nodes
    v = (dV * values) @ N.T
    idx = t.T.ravel()
    n = int(max(idx.max(), np.max(nodes))) + 1
    num = np.bincount(idx, v.ravel(), minlength=n)
    den = np.bincount(idx, w.ravel(), minlength=n)
    return num[nodes] / np.where(den[nodes] > 0, den[nodes], 1.0)


@dataclass
class ContactEval:
    """Contact contributions at one iterate (arrays over candidate nodes)."""

    p: np.ndarray  # pressure (Pa)
    tau: np.ndarray  # radial traction on the die side (Pa); force on workpiece is -tau*A
    status: np.ndarray  # frictionlaw OPEN/STICK/SLIP
    fz: np.ndarray  # residual contribution at z dofs (N)
    fr: np.ndarray  # residual contribution at r dofs (N)
    kzz: np.ndarray  # d fz / d uz
    krr: np.ndarray  # d fr / d ur
    krz: np.ndarray  # d fr / d uz


class DieContact:
    """Penalty die contact with friction for the candidate nodes of a mesh.

    Parameters
    ----------
    nodes : ndarray
        Candidate node numbers.
    law : frictionlaw law or None
        ``None`` for frictionless contact.
    eps_n : float
        Normal penalty (Pa/m).
    eps_t : float
        Tangential (stick) penalty ``k_t`` (Pa/m).
    flattening : bool
        Pass the bulk strain increment to the law (its flattening block; :meth:`evaluate`).
    """

    def __init__(self, nodes, law, eps_n, eps_t, flattening=False):
        self.nodes = np.asarray(nodes)
        self.law = law
        self.eps_n = float(eps_n)
        self.eps_t = float(eps_t)
        self.state = HistoryState(self.nodes.size)
        self.tau_old = np.zeros(self.nodes.size)
        self.p_old = np.zeros(self.nodes.size)
        self.last = None
        self.k_t_used = (math.inf, 0.0)  # smallest, largest k_t (Pa/m) on a node in contact
        self._reset_branches()
        self.n_frozen = 0  # node evaluations on a frozen first-loading branch (summary.json)
        self.zone = None  # on a zoned die: each node's zone at the last evaluation
        self.flattening = bool(flattening)
        self.alpha = np.zeros(self.nodes.size)  # contact fraction of the last accepted increment

    @property
    def pass_hardening(self):
        """Whether the bulk's hardening modulus goes to the law (Eq. F2c) in a flattening run.

        Not where a law's ``beta`` was fitted to a sheet taken as perfectly plastic
        (:func:`frictionlaw.flattening.beta_absorbs_hardening`): that ``beta`` absorbs the
        sheet's hardening already, and the modulus would count it twice; nor for the two-state
        model (``limit-analysis``), whose table is perfectly plastic (the law refuses it).
        """
        from frictionlaw.flattening import LIMIT_MODEL, beta_absorbs_hardening

        laws = getattr(self.law, "laws", None) or [self.law]
        params = [getattr(w, "params", None) for w in laws]
        return not any(
            p is not None
            and getattr(p, "flattening", None) is not None
            and (beta_absorbs_hardening(p) or p.flattening.model == LIMIT_MODEL)
            for p in params
        )

    def _reset_branches(self):
        """Forget the branch flips of the increment (after a commit or a cut-back)."""
        self._below = np.zeros(self.nodes.size, dtype=bool)
        self._flips = np.zeros(self.nodes.size, dtype=np.int64)

    def k_t_table(self):
        """The law's calibrated ``k_t(p)`` table, or ``None`` (then the penalty ``eps_t``).

        A zoned die (a law with ``zone_at``): None unless a zone's law has one
        (:meth:`stick_stiffness` then takes each node's zone's table).
        """
        if hasattr(self.law, "zone_at"):
            tables = [getattr(getattr(w, "params", None), "k_t", None) for w in self.law.law.laws]
            return next((t for t in tables if t is not None), None)
        return getattr(getattr(self.law, "params", None), "k_t", None)

    def stick_stiffness(self, zone=None):
        """Tangential stick stiffness per node (Pa/m) for the current increment.

        ``k_t(p_old)`` from the parameter file's table at each node's pressure at the start
        of the increment, or the scalar penalty ``eps_t`` when the law has no table; on a zoned
        die (``zone``: each node's zone) each node's zone's table, the penalty where its zone's
        law has none.
        """
        table = self.k_t_table()
        if table is None:
            return self.eps_t
        if zone is None:
            return table(self.p_old)
        kt = np.full(self.nodes.size, self.eps_t)
        for i, law in enumerate(self.law.law.laws):
            t = getattr(getattr(law, "params", None), "k_t", None)
            here = zone == i
            if t is not None and here.any():
                kt[here] = t(self.p_old[here])
        return kt

    def zones_at(self, r):
        """``(law, zone)`` the traction update runs.

        The law and None, or on a zoned die (a law with ``zone_at``) its
        :class:`frictionlaw.ZonedLaw` and each node's zone at radius ``r`` (the start of the
        increment: the zones stay fixed through its iterations).
        """
        if not hasattr(self.law, "zone_at"):
            return self.law, None
        if r is None:
            raise ValueError("a zoned die needs the nodes' radii (r)")
        zone = self.law.zone_at(r)
        self.zone = zone
        return self.law.law, zone

    def stiffness_record(self):
        """What the run used as stick stiffness (for ``summary.json``)."""
        if self.k_t_table() is None:
            return {"source": "penalty eps_n (no k_t in the law)", "eps_t_Pa_per_m": self.eps_t}
        lo, hi = self.k_t_used
        used = math.isfinite(lo)  # False before any node was in contact
        return {
            "source": "k_t(p) of the parameter file, at the node's pressure at the start of "
            "the increment",
            "k_t_min_Pa_per_m": lo if used else None,
            "k_t_max_Pa_per_m": hi if used else None,
            "eps_n_Pa_per_m": self.eps_n,
        }

    def evaluate(self, z, z_die, dur, area, r=None, d_eps=None, sigma_y=None, hardening=None):
        """Pressure, friction traction and their residual/tangent contributions.

        Parameters
        ----------
        z : ndarray
            Current z of the candidate nodes (m).
        z_die : float
            Die position (m).
        dur : ndarray
            Radial displacement increment of the candidate nodes in this increment (m).
        area : ndarray
            Nodal areas (m^2).
        r : ndarray, optional
            Radii of the candidate nodes at the start of the increment (m): on a zoned die the
            zone under each node (:meth:`zones_at`).
        d_eps, sigma_y, hardening : ndarray, optional
            The bulk's plastic strain increment of the increment, its flow stress (Pa) and its
            hardening modulus ``d sigma_y / d eps_p`` (Pa) at the nodes, for a die with
            ``flattening`` (``d_eps`` required there, refused otherwise).
        """
        if self.flattening != (d_eps is not None):
            raise ValueError("d_eps is given exactly when the die runs the flattening")
        g = z - z_die
        active = g > 0
        p = np.where(active, self.eps_n * g, 0.0)
        fz = p * area
        kzz = np.where(active, self.eps_n * area, 0.0)
        n = self.nodes.size
        if self.law is None:
            tau = np.zeros(n)
            status = np.where(active, 2, 0).astype(np.int8)
            fr = np.zeros(n)
            krr = np.zeros(n)
            krz = np.zeros(n)
            self.state.propose(p)
        else:
            law, zone = self.zones_at(r)
            state = self._history(p, active)
            kw = {}
            if d_eps is not None:
                kw = {"d_eps": d_eps, "sigma_y": sigma_y, "hardening": hardening}
            res = traction_update(
                law, p, dur, self.tau_old, self.stick_stiffness(zone), state, zone=zone, **kw
            )
            if state is not self.state and d_eps is not None:  # a frozen branch's own state
                self.state.flattening_arrays()[1][:] = state.alpha_f_trial
            tau, status = res.traction, res.status
            fr = tau * area
            krr = res.dt_dslip * area
            krz = np.where(active, res.dt_dp * self.eps_n * area, 0.0)
            if not getattr(self.law, "uses_history", False):
                self.state.propose(p)  # track p_hist for output whatever the law
        ev = ContactEval(p, tau, status, fz, fr, kzz, krr, krz)
        self.last = ev
        return ev

    def _history(self, p, active):
        """The history ``traction_update`` sees: the node's, or a frozen first-loading branch.

        Eq. 25 jumps below Eq. 24 at ``p = p_hist`` (unless the law is continuous). A node whose
        pressure sits at its history then flips between the branches from one Newton iteration
        to the next, its traction jumps by the law's reload jump each time, and Newton cannot
        converge (measured: a ring with sur-3's law stalled at ``|R|/|f| = 2.2e-4`` after 7
        cut-backs). A node that has flipped :data:`FREEZE_AFTER` times in the increment is
        evaluated on Eq. 24 at its pressure for the rest of the increment (it is at its history,
        where the law is two-valued); its trial ``p_hist`` stays ``max(p_hist, p)``.
        """
        params = getattr(self.law, "params", None)
        if not getattr(self.law, "uses_history", False) or getattr(
            params, "continuous_reload", False
        ):
            return self.state  # no history, or no jump to chatter across
        hist = self.state.committed_array()
        below = active & (p < hist)
        self._flips += below != self._below
        self._below = below
        frozen = below & (self._flips >= FREEZE_AFTER)
        if not frozen.any():
            return self.state
        self.n_frozen += int(frozen.sum())
        self.state.propose(p)  # the real trial history, max(p_hist, p)
        return HistoryState(p_hist=np.where(frozen, p, hist), alpha_f=self.state.alpha_f)

    def commit(self, ev):
        """Accept the increment: traction becomes the old traction, ``p_hist`` is committed."""
        if self.law is not None and self.k_t_table() is not None and (ev.p > 0).any():
            kt = np.broadcast_to(self.stick_stiffness(self.zone), ev.p.shape)[ev.p > 0]
            lo, hi = self.k_t_used
            self.k_t_used = (min(lo, float(kt.min())), max(hi, float(kt.max())))
        self.tau_old = np.where(ev.p > 0, ev.tau, 0.0)
        self.p_old = np.maximum(ev.p, 0.0)
        if self.law is not None:
            self.alpha = contact_fraction(self.law, ev.p, self.state, self.zone)
        self.state.commit()
        self._reset_branches()

    def reset_history(self):
        """Forget the committed ``p_hist`` (a law without history, for comparisons)."""
        self.state = HistoryState(self.nodes.size)

    def rollback(self):
        """Cut-back: discard the trial ``p_hist``."""
        self.state.rollback()
        self._reset_branches()


def contact_fraction(law, p, state, zone=None):
    """Each node's contact fraction at ``p`` (Eq. F5 with its trial ``alpha_f``; 0 if open).

    ``tau / tau_max`` of its law's shear limit after the committed ``p_hist`` (and the trial
    flattened fraction of a flattening run): the SBMF law's ``alpha``; for the other laws the
    ratio of the limit to the cap where they have one, else 0. On a zoned die each node's zone.
    """
    from frictionlaw.flattening import flattened_alpha, flattening_pressure

    one = law.law.laws if hasattr(law, "zone_at") else (law,)
    out = np.zeros(p.shape)
    ph = state.committed_array()
    af = state.alpha_f_trial
    for i, w in enumerate(one):
        here = p > 0
        if zone is not None and hasattr(law, "zone_at"):
            here &= zone == i
        P = getattr(w, "params", None)
        if P is None or not here.any():
            continue
        pf = flattening_pressure(af[here], P) if P.flattening is not None else 0.0 * af[here]
        out[here] = flattened_alpha(p[here], ph[here], pf, P)
    return out

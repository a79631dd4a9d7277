"""The FE demo's guard against nodes chattering across the reload jump at ``p = p_hist``.

Eq. 25 lies below Eq. 24 at ``p = p_hist`` (``reload_jump``). A node whose pressure sits at its
history flips branch between Newton iterations and Newton stalls; ``DieContact`` freezes such a
node on Eq. 24 after ``FREEZE_AFTER`` flips in an increment (fe_demo/solver/contact.py).
"""

import numpy as np
import pytest

from fe_demo.analysis.ringfit import ring_curve
from fe_demo.solver.contact import FREEZE_AFTER, DieContact
from frictionlaw import FrictionParams, SBMFLaw, reload_jump, shear_limit

#: a law calibrated from the shipped sur-3.sur against the default tool (its ring stalled)
SUR3 = FrictionParams(
    m=0.35,
    sigma_y=285714285.71428573,
    H=800e6,
    C1=1.2697710303318583,
    n1=3.1772528726035305,
    C2=3.502296106516847,
    n2=0.5742321353514186,
)


def _contact(p_hist):
    law = SBMFLaw(SUR3)
    c = DieContact(np.arange(1), law, eps_n=1e12, eps_t=1e12)
    c.state.propose(np.array([p_hist]))
    c.state.commit()
    return c


def test_a_node_flipping_at_its_history_is_frozen_on_first_loading():
    p_hist = 400e6
    assert float(reload_jump(SUR3, p_hist)) > 0.01 * float(shear_limit(p_hist, 0.0, SUR3))
    c = _contact(p_hist)
    area = np.ones(1)
    z_die = 0.0
    below, above = p_hist * (1 - 1e-4), p_hist * (1 + 1e-4)
    taus = []
    for k in range(2 * FREEZE_AFTER):
        p = below if k % 2 == 0 else above
        ev = c.evaluate(np.array([p / c.eps_n]), z_die, np.array([1e-3]), area)  # sliding
        taus.append(float(ev.tau[0]))
        # the trial history is the node's own, whatever branch is evaluated
        assert c.state.p_hist_trial[0] == pytest.approx(max(p_hist, p))
    # before freezing: Eq. 25 below, Eq. 24 above (the jump between them)
    assert taus[0] == pytest.approx(float(shear_limit(below, p_hist, SUR3)), rel=1e-9)
    assert taus[1] == pytest.approx(float(shear_limit(above, p_hist, SUR3)), rel=1e-9)
    # after FREEZE_AFTER flips: Eq. 24 at p below the history too
    # flips after evaluation k: k + 1 (the first one is entering the lower branch)
    frozen = [k for k in range(len(taus)) if k % 2 == 0 and k + 1 >= FREEZE_AFTER]
    assert frozen and c.n_frozen == len(frozen)
    for k in frozen:
        assert taus[k] == pytest.approx(float(shear_limit(below, 0.0, SUR3)), rel=1e-9)
    # a new increment forgets the flips (its history: the last iterate, above the old one)
    c.commit(ev)
    assert c.state.p_hist[0] == pytest.approx(above)
    ev = c.evaluate(np.array([below / c.eps_n]), z_die, np.array([1e-3]), area)
    assert float(ev.tau[0]) == pytest.approx(float(shear_limit(below, above, SUR3)), rel=1e-9)


def test_the_ring_that_stalled_now_converges():
    """Before the guard: no convergence at 31.6 % (|R|/|f| = 2.2e-4 after 7 cut-backs)."""
    r, d = ring_curve("sbmf", 0.35, params=SUR3, reduction=0.52)
    assert r[-1] >= 0.5
    assert np.isfinite(d).all()


def test_a_continuous_law_never_freezes():
    c = DieContact(np.arange(1), SBMFLaw(SUR3.replace(continuous_reload=True)), 1e12, 1e12)
    c.state.propose(np.array([400e6]))
    c.state.commit()
    for k in range(8):
        p = 400e6 * (1 + (-1) ** k * 1e-4)
        c.evaluate(np.array([p / c.eps_n]), 0.0, np.array([1e-3]), np.ones(1))
    # no jump, nothing to chatter across: the node keeps its own branch
    assert c.n_frozen == 0

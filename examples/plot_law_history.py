"""
The law and its history on arrays
=================================

Evaluate Eq. 24 (first loading) and Eq. 25 (un- and reloading below the largest pressure a node
has carried, ``p_hist``) on arrays of contact nodes, and drive the history the way an FE code
does: propose a trial history in each Newton iteration, commit it once per accepted increment.
"""

import matplotlib.pyplot as plt
import numpy as np

from frictionlaw import FrictionParams, HistoryState, SBMFLaw, shear_limit, traction_update

# A parameter set as a calibration writes it (SI units: Pa); k = sigma_y / 2 unless given.
params = FrictionParams(m=0.5, sigma_y=286e6, H=800e6, C1=1.05, n1=2.9, C2=7.4, n2=0.58)
print(
    f"mu_eff = {params.mu_eff:.4f} (small-p Coulomb slope), tau_max = {params.tau_max / 1e6:.1f} MPa"
)

# %%
# First loading and reloading
# ---------------------------
# ``shear_limit(p, p_hist, params)`` is the shear a node can carry: Eq. 24 where ``p >= p_hist``,
# Eq. 25 below its history. A virgin node has ``p_hist = 0``.

p = np.linspace(0.0, 800e6, 401)
fig, ax = plt.subplots(figsize=(6, 4))
ax.plot(p / 1e6, np.asarray(shear_limit(p, 0.0, params)) / 1e6, "k", label="first loading (Eq. 24)")
for p_hist in (200e6, 400e6, 600e6):
    below = p[p <= p_hist]
    tau = np.asarray(shear_limit(below, np.full_like(below, p_hist), params))
    ax.plot(below / 1e6, tau / 1e6, label=f"reload below p_hist = {p_hist / 1e6:.0f} MPa (Eq. 25)")
ax.set_xlabel("contact pressure p (MPa)")
ax.set_ylabel("shear limit tau (MPa)")
ax.legend(fontsize=8)
fig.tight_layout()

# %%
# The history of three nodes through load, unload and reload
# -----------------------------------------------------------
# ``HistoryState`` keeps ``p_hist`` per node. ``traction_update`` returns the traction (stick or
# slip) and proposes ``max(p_hist, p)`` as the trial history; ``commit()`` accepts it. A Newton
# iteration that is thrown away (a cut-back) calls ``rollback()`` instead, so the history never
# ratchets on iterations the host did not accept.

law = SBMFLaw(params)
state = HistoryState(3)
slip = np.full(3, 1e-3)  # a large slip increment (m): every node in contact slides
traction = np.zeros(3)
schedule = [
    np.array([100e6, 300e6, 500e6]),  # load
    np.array([50e6, 150e6, 250e6]),  # unload to half: Eq. 25
    np.array([100e6, 300e6, 500e6]),  # reload to the first pressures
]
for step, p_nodes in enumerate(schedule):
    res = traction_update(law, p_nodes, slip, traction, k_t=1e14, state=state)
    state.commit()
    traction = res.traction
    print(
        f"step {step}: p = {p_nodes / 1e6} MPa, tau = {np.round(res.traction / 1e6, 2)} MPa, "
        f"p_hist = {state.p_hist / 1e6} MPa"
    )

"""
Flattening under bulk strain, node by node
==========================================

A law with a ``flattening`` block (docs/flattening.md) makes the contact fraction grow with the
workpiece's bulk plastic strain at the contact. ``flattening_curve`` gives it at constant
pressure from a virgin surface; in an FE run the host passes each node's equivalent plastic
strain increment (and, optionally, its flow stress and hardening modulus) to
``traction_update``, which keeps the flattened fraction per node under the same trial / commit
rules as ``p_hist``.
"""

import matplotlib.pyplot as plt
import numpy as np

from frictionlaw import (
    Flattening,
    FrictionParams,
    HistoryState,
    SBMFLaw,
    flattening_curve,
    traction_update,
)

# The paper's law (SI units) with a flattening block: the asperities' RMS flank slope, as
# ``halfspace-calib --flattening`` derives it from the workpiece's surface, and beta = 1.
params = FrictionParams(
    m=0.5,
    sigma_y=286e6,
    H=800e6,
    C1=1.05,
    n1=2.9,
    C2=7.4,
    n2=0.58,
    flattening=Flattening(slope=0.05),
)
H = params.H

# %%
# The contact fraction against strain at constant pressure
# --------------------------------------------------------
# At zero strain it is the calibrated first loading ``alpha1(p)`` exactly; it never falls and
# reaches full contact at a finite strain. A hardening bulk (its modulus ``d sigma_y / d eps``
# passed) flattens slower at low pressure: the slip-line lattice's sinking is limited by the
# hardening its uneven slip costs (Eq. F2c), and the flattening beyond the pressing by the
# sinking the hardening holds, ``3 p / (4 h)`` half-spacings (Eq. F2d): at a constant modulus
# the dashed curves at 0.05 and 0.1 H level off below full contact (0.35 and 0.70).

eps = np.linspace(0.0, 0.06, 121)
fig, ax = plt.subplots(figsize=(6, 4))
for x, color in ((0.05, "C0"), (0.1, "C1"), (0.3, "C2")):
    ax.plot(eps, flattening_curve(x * H, eps, params), color=color, label=f"p = {x:g} H")
    hardened = flattening_curve(x * H, eps, params, hardening=2e9)
    ax.plot(eps, hardened, color=color, ls="--", label=f"p = {x:g} H, hardening 2 GPa")
ax.set_xlabel("equivalent bulk plastic strain")
ax.set_ylabel("contact fraction alpha")
ax.legend(fontsize=7)
fig.tight_layout()
for x in (0.05, 0.1, 0.3):
    a = flattening_curve(x * H, [0.0, 0.01, 0.02], params)
    print(f"p = {x:g} H: alpha {a[0]:.3f} -> {a[1]:.3f} (eps 0.01) -> {a[2]:.3f} (eps 0.02)")

# %%
# A host's loop over increments
# -----------------------------
# Each increment the host passes the nodes' plastic strain increments ``d_eps`` (and here their
# flow stress and hardening modulus); the update proposes the trial fraction, the host commits
# it once the increment is accepted. Three nodes at 0.1 H, one of them in a region that does not
# flow plastically.

law = SBMFLaw(params)
state = HistoryState(3)
p = np.full(3, 0.1 * H)
d_eps = np.array([0.004, 0.004, 0.0])  # per increment
traction = np.zeros(3)
for step in range(5):
    res = traction_update(
        law,
        p,
        np.full(3, 1e-3),  # slip increment (m): every node slides
        traction,
        k_t=1e14,
        state=state,
        d_eps=d_eps,
        sigma_y=np.full(3, 300e6),
        hardening=np.array([0.0, 2e9, 2e9]),
    )
    state.commit()
    traction = res.traction
    print(
        f"increment {step}: alpha_f = {np.round(state.alpha_f, 3)}, "
        f"tau = {np.round(res.traction / 1e6, 2)} MPa"
    )

# %%
# The two-state model
# -------------------
# The block's opt-in model ``limit-analysis`` carries the asperities' flank slope as a second
# state per node (``HistoryState.slope_f``) and grows both at the tabulated rates of a
# rigid-plastic limit analysis: at low pressure it turns a steep flank before it grows the
# contact, where the default grows it at once (docs/flattening.md, "The two-state model"; it
# takes no hardening modulus: its table is perfectly plastic).

steep = np.tan(np.radians(10.0))
one = params.replace(flattening=Flattening(slope=steep))
two = params.replace(flattening=Flattening(slope=steep, model="limit-analysis"))
eps = np.linspace(0.0, 0.2, 201)
fig, ax = plt.subplots(figsize=(6, 4))
for x, color in ((0.02, "C0"), (0.05, "C1"), (0.2, "C2")):
    ax.plot(
        eps, flattening_curve(x * H, eps, one), color=color, ls="--", label=f"{x:g} H, one state"
    )
    ax.plot(eps, flattening_curve(x * H, eps, two), color=color, label=f"{x:g} H, two states")
ax.set_xlabel("equivalent bulk plastic strain")
ax.set_ylabel("contact fraction alpha (10 deg flanks)")
ax.legend(fontsize=7)
fig.tight_layout()
state = HistoryState(1)
for step in range(4):
    traction_update(SBMFLaw(two), [0.02 * H], [1e-3], [0.0], 1e14, state, d_eps=0.025)
    state.commit()
    print(f"increment {step}: alpha_f {state.alpha_f[0]:.3f}, flank slope {state.slope_f[0]:.4f}")

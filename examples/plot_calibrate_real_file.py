"""
Calibrate the law from a real instrument file
=============================================

A Zygo MetroPro scan shipped in ``tests/data`` (a public file of SurfaceTopography's test set,
MIT licence) is the workpiece; the tool is the built-in smooth synthetic tool. The calibration
runs the elasto-plastic half-space model at a few mean pressures, fits Eq. 24 to the first
loading and Eq. 25 to the reloads, and returns the law's parameters. A coarse grid (64^2) and
five load levels keep this example to seconds; ``halfspace-calib`` uses finer defaults.

Reading instrument files needs the ``topography`` extra (SurfaceTopography).
"""

import os
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from frictionlaw import alpha_first
from frictionlaw.describe import describe_law
from halfspace_calib import Scene, calibrate

repo = Path(os.environ.get("SBMF_REPO", Path.cwd()))
scan = repo / "tests" / "data" / "metropro-1.dat"

scene = Scene(
    workpiece=str(scan),
    grid=64,
    pressures=(20e6, 100e6, 300e6, 500e6, 700e6),
    reload_fractions=(0.25, 0.5, 0.8),
)
cal = calibrate(scene, progress=False)
params = cal.params
# the law the parameters run: each branch's form with its parameters (or table) and its measured
# errors, then the form beside it, as every report of the law gives it
print("\n".join(describe_law(params).lines()))
print(f"mu_eff = {params.mu_eff:.4f}")

# %%
# The contact ratio against pressure: the half-space solves and the fitted Eq. 24.
levels = [lv.loading for lv in cal.sweeps.levels if lv.loading.converged]
p_pts = np.array([r.p_mean for r in levels])
a_pts = np.array([r.alpha for r in levels])
p = np.linspace(0.0, p_pts.max(), 200)
fig, ax = plt.subplots(figsize=(6, 4))
ax.plot(p_pts / 1e6, a_pts, "o", label="half-space model")
ax.plot(p / 1e6, alpha_first(p, params), "-", label="Eq. 24, fitted")
ax.plot(p / 1e6, p / params.H, ":", label="p / H (the bound alpha >= p/H)")
ax.set_xlabel("mean contact pressure (MPa)")
ax.set_ylabel("real contact ratio alpha")
ax.legend()
fig.tight_layout()

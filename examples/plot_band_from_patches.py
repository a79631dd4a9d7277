"""
A band from several scans
=========================

One scan is cut into patches; each patch is calibrated on its own, the pooled law is fitted to
all of them, and a bootstrap over the patches gives a band on the law (here at 90 %). The same
runs from the command line as ``halfspace-calib --workpiece SCAN --patches 4``; with several
files, ``--workpiece A B C``. The FE demo carries the band to the forming result
(``fe-demo upsetting --band``).
"""

import os
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from frictionlaw import FrictionParams, shear_limit
from halfspace_calib.cli import main as halfspace_calib

repo = Path(os.environ.get("SBMF_REPO", Path.cwd()))
out = Path(tempfile.mkdtemp()) / "band"
code = halfspace_calib(
    [
        "--workpiece", str(repo / "tests" / "data" / "metropro-1.dat"),
        "--patches", "4",
        "--grid", "64",  # at 32^2 a patch's reload law misses held-out levels by up to 0.07
        "--pressures", "2e7,1e8,3e8,5e8,7e8",
        "--reload-fractions", "0.25,0.5,0.8",
        "--bootstrap", "100",
        "--quiet",
        "--out", str(out),
    ]
)  # fmt: skip
assert code == 0
params = FrictionParams.from_json(out / "params.json")
edges = params.edge_laws()
print(f"{len(params.uncertainty.samples)} samples; pooled mu_eff = {params.mu_eff:.4f}")
print(f"band on mu_eff: [{edges['lower'].mu_eff:.4f}, {edges['upper'].mu_eff:.4f}]")

# %%
# The pooled law with its edge laws, on first loading.
p = np.linspace(1e6, 700e6, 200)
fig, ax = plt.subplots(figsize=(6, 4))
ax.fill_between(
    p / 1e6,
    np.asarray(shear_limit(p, 0.0, edges["lower"])) / 1e6,
    np.asarray(shear_limit(p, 0.0, edges["upper"])) / 1e6,
    alpha=0.3,
    label="band (edge laws)",
)
ax.plot(p / 1e6, np.asarray(shear_limit(p, 0.0, params)) / 1e6, "k", label="pooled law")
for name, law in params.sample_laws().items():
    ax.plot(p / 1e6, np.asarray(shear_limit(p, 0.0, law)) / 1e6, lw=0.7, label=name)
ax.set_xlabel("contact pressure p (MPa)")
ax.set_ylabel("shear limit tau (MPa)")
ax.legend(fontsize=7)
fig.tight_layout()

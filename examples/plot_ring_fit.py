"""
Fit the friction factor m from ring tests
=========================================

The law is ``tau = m k alpha(p, p_hist)``: the roughness calibration gives ``alpha``, ring tests
give ``m``. Here the shipped **synthetic** ring tests (``fe_demo/data/ring_example.csv``: the FE
model with the example law at ``m = 0.35``, plus 0.5-point noise) are fitted with the law itself
and, for comparison, with Tresca's law, which is what a classical ring chart reads. A coarse FE
mesh keeps this example to seconds; ``fe-demo ring-fit`` uses the default mesh
(docs/getting_m.md).
"""

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import fe_demo
from fe_demo.analysis.ringfit import fit_m, read_ring_tests
from frictionlaw import FrictionParams

data = Path(fe_demo.__file__).parent / "data"
rings = read_ring_tests([data / "ring_example.csv"])
params = FrictionParams.from_json(data / "sbmf_example.json")
mesh = {"nr": 8, "n_increments": 20, "workers": 1}

law = fit_m(rings, "sbmf", params=params, **mesh)
chart = fit_m(rings, "tresca", **mesh)
print(f"the law's m = {law.m:.3f} [{law.m_lower:.3f}, {law.m_upper:.3f}] (90 %), {law.message}")
print(f"a Tresca chart of the same model reads m = {chart.m:.3f} from the same rings")

# %%
# The measured points, the fitted law's curve with its band, and the Tresca fit.
r = np.linspace(0.05, rings.reduction.max(), 50)
fig, ax = plt.subplots(figsize=(6, 4))
ax.fill_between(100 * r, 100 * law.predict(r, law.m_lower), 100 * law.predict(r, law.m_upper),
                alpha=0.3, label="90 % band on m")  # fmt: skip
ax.plot(100 * r, 100 * law.predict(r), label=f"the law, m = {law.m:.3f}")
ax.plot(100 * r, 100 * chart.predict(r), "--", label=f"Tresca, m = {chart.m:.3f}")
ax.plot(100 * rings.reduction, 100 * rings.d_inner, "ko", label="rings (synthetic)")
ax.set_xlabel("height reduction (%)")
ax.set_ylabel("inner diameter change (%)")
ax.legend()
fig.tight_layout()

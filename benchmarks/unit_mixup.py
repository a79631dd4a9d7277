"""The unit mix-up no guard can see (issue 40, item 5): an SI routine in an mm-t-s deck.

A routine exported for SI (Pa, m) in an mm-t-s deck (MPa, mm) that wrongly states SI (the
data line ``SI``, ``PROPS(1) = 1.``) gets pressures in MPa and reads them as Pa: ``p`` MPa
arrives as ``p`` Pa, far below 100 H, and the shear it returns in Pa is read as MPa. The deck's
shear is then ``tau_SI(p Pa, p_hist Pa)`` where the law is ``tau_SI(p MPa, p_hist MPa)``: the
same wherever the law is homogeneous in ``p`` and ``p_hist`` (its Coulomb regime, ``p << H``),
not where it bends towards ``tau_max``. Every generated routine equals the runtime
(``frictionlaw.shear_limit``) bit for bit (docs/fe_codes.md), so the runtime gives the routine's
numbers.

For the default calibration (``calibrate(Scene())``, the law ``halfspace-calib`` writes without
options) and for fe-demo's shipped example law: the relative error of the deck's shear on first
loading at a few pressures, and on reloading (``p < p_hist``) over ``p_hist`` and ``p / p_hist``
bands.

Run: python benchmarks/unit_mixup.py
Writes benchmarks/results/unit_mixup.md and prints it.
"""

from pathlib import Path

import numpy as np
from _provenance import run_record

from frictionlaw import FrictionParams, shear_limit
from halfspace_calib.pipeline.calibration import Scene, calibrate

RESULTS = Path(__file__).parent / "results"
EXAMPLE = Path(__file__).resolve().parents[1] / "fe_demo" / "data" / "sbmf_example.json"
FIRST = (10.0, 100.0, 300.0, 500.0, 760.0, 1000.0)  # MPa
P_HIST_BANDS = ((10.0, 100.0), (100.0, 300.0), (300.0, 500.0), (500.0, 760.0), (760.0, 1000.0))
Q_BANDS = ((0.01, 0.1), (0.1, 0.3), (0.3, 0.6), (0.6, 0.999))


def error(params, p, p_hist):
    """The deck's shear over the law's, minus 1, at ``p`` and ``p_hist`` in MPa."""
    wrong = shear_limit(p, p_hist, params)  # the MPa numbers read as Pa; the result read as MPa
    return wrong / (shear_limit(p * 1e6, p_hist * 1e6, params) / 1e6) - 1.0


def _band(params, p_hist, q):
    ph = np.geomspace(*p_hist, 200)[:, None]
    qq = np.linspace(*q, 200)[None, :]
    e = error(params, ph * qq, ph * np.ones_like(qq))
    return float(e.min()), float(e.max())


def table(name, params):
    """Markdown lines for one law."""
    out = [f"## {name} (reload form: {params.reload_form})", ""]
    out += ["First loading (`p_hist = 0`):", "", "| p (MPa) | error |", "|---|---|"]
    out += [f"| {p:g} | {100 * float(error(params, np.array(p), 0.0)):+.1f} % |" for p in FIRST]
    out += ["", "Reloading, smallest and largest error over each band:", ""]
    out += ["| p_hist (MPa) | " + " | ".join(f"p/p_hist {a:g}-{b:g}" for a, b in Q_BANDS) + " |"]
    out += ["|---" * (len(Q_BANDS) + 1) + "|"]
    for ph in P_HIST_BANDS:
        cells = [_band(params, ph, q) for q in Q_BANDS]
        out.append(
            f"| {ph[0]:g}-{ph[1]:g} | "
            + " | ".join(f"{100 * lo:+.1f} .. {100 * hi:+.1f} %" for lo, hi in cells)
            + " |"
        )
    lo, hi = _band(params, (10.0, 760.0), (0.01, 0.999))
    out += ["", f"Reloading with `p_hist` 10-760 MPa: {100 * lo:+.1f} % .. {100 * hi:+.1f} %.", ""]
    return out


def main():
    default = calibrate(Scene()).params
    lines = ["# An SI routine in an mm-t-s deck that states SI (benchmarks/unit_mixup.py)", ""]
    lines += table("The default calibration", default)
    lines += table("fe-demo's example law", FrictionParams.from_json(EXAMPLE))
    text = "\n".join(lines)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "unit_mixup.md").write_text(text, encoding="utf-8")
    print(text)


if __name__ == "__main__":
    with run_record(__file__):
        main()

"""
Export the law to Abaqus and check the routine
==============================================

``frictionlaw-export abaqus-fric`` writes the law as an Abaqus/Standard ``FRIC`` user subroutine
with the parameter file's constants compiled in. Here the routine is written from the shipped
example parameter file, compiled with gfortran (when it is installed) and called through the
project's emulation of Abaqus' documented ``FRIC`` interface (``frictionlaw.export.harness``, the
one the test suite uses). Its slip traction is compared with the Python runtime on the same
pressures and histories.
"""

import tempfile
from pathlib import Path

import numpy as np

import fe_demo
from frictionlaw import FrictionParams, shear_limit
from frictionlaw.export import export, harness, target

params_file = Path(fe_demo.__file__).parent / "data" / "sbmf_example.json"
params = FrictionParams.from_json(params_file)
out = Path(tempfile.mkdtemp()) / "abaqus"
export("abaqus-fric", params_file, out)
routine = out / "sbmf_fric.f"
print(f"wrote {routine.name} ({len(routine.read_text().splitlines())} lines) and README.md")
print("\n".join(routine.read_text().splitlines()[:12]))

# %%
# Compile and call it as Abaqus does
# ----------------------------------
# Each contact point gets its pressure ``PRESS``, a slip increment ``DGAM`` large enough to slide,
# and its state ``STATEV`` (``STATEV(1) = p_hist``) at the start of the increment.

p = np.array([50e6, 200e6, 400e6, 100e6, 300e6])
p_hist = np.array([0.0, 0.0, 0.0, 400e6, 600e6])  # the last two are unloaded: Eq. 25
if harness.gfortran() is None:
    print("gfortran is not installed: the routine was written but not compiled here")
else:
    # the target's record names its host emulation: the FRIC shim and its driver
    fric, warnings = target("abaqus-fric").harness.load(
        {routine.name: routine.read_text()}, out / "build", name="example"
    )
    n = p.size
    statev = np.zeros((n, 3))
    statev[:, 0] = p_hist
    res = fric(p, np.full((n, 1), 1e-3), np.zeros((n, 1)), statev, 1e-3)
    tau_fortran = np.abs(res["tau"][:, 0])
    tau_python = np.asarray(shear_limit(p, p_hist, params))
    for row in zip(p, p_hist, tau_fortran, tau_python, strict=True):
        print(
            "p = {:5.0f} MPa, p_hist = {:5.0f} MPa: Fortran {:8.4f} MPa, runtime {:8.4f} MPa".format(
                *(v / 1e6 for v in row)
            )
        )
    rel = np.max(np.abs(tau_fortran - tau_python) / tau_python)
    print(f"largest relative difference: {rel:.1e}")
    assert rel < 1e-12

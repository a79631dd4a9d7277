import json
import subprocess
import sys

HEAVY = ("scipy", "skfem", "halfspace_calib", "fe_demo", "numba", "matplotlib", "meshio")

CODE = r"""
import json, sys
heavy = %r
loaded = lambda: sorted(m for m in sys.modules if m.split('.')[0] in heavy)
import frictionlaw
after_import = loaded()
p = frictionlaw.FrictionParams(m=0.5, sigma_y=3e8, H=8e8, C1=1, n1=2, C2=3, n2=2)
frictionlaw.shear_limit([1e8, 2e8], 0.0, p)
print(json.dumps([after_import, loaded()]))
""" % (HEAVY,)

NUMBA_ALONE = r"""
import json, sys
import numba
import numpy as np
numba.njit(lambda a: a.sum())(np.ones(3))  # numba's array targets load scipy.linalg for BLAS
print(json.dumps(sorted(m for m in sys.modules if m.split('.')[0] in %r)))
""" % (HEAVY,)


def _run(code):
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def test_runtime_import_stays_light():
    after_import, after_eval = _run(CODE)
    # importing the runtime loads none of scipy, skfem, numba, matplotlib or the other packages
    assert after_import == []
    # evaluating loads numba and nothing beyond what numba loads by itself for any array kernel
    # (its version check imports scipy, its BLAS check scipy.linalg, when scipy is installed)
    numba_alone = set(_run(NUMBA_ALONE))
    extra = {m for m in set(after_eval) - numba_alone if not m.startswith("numba")}
    assert not extra, sorted(extra)
    assert not any(m.split(".")[0] in ("skfem", "halfspace_calib", "fe_demo") for m in after_eval)


def test_the_runtime_does_not_load_the_command_layer():
    """``import frictionlaw`` and evaluating the law load no command code (sbmf_cli)."""
    code = (
        "import json, sys\nimport frictionlaw\n"
        "p = frictionlaw.FrictionParams(m=0.5, sigma_y=3e8, H=8e8, C1=1, n1=2, C2=3, n2=2)\n"
        "frictionlaw.shear_limit([1e8, 2e8], 0.0, p)\n"
        "print(json.dumps(sorted(m for m in sys.modules if m.split('.')[0] == 'sbmf_cli')))"
    )
    assert _run(code) == []
    # the probe can see the layer: the export command loads it
    assert "sbmf_cli" in _run(
        "import json, sys\nimport frictionlaw.export.cli\nprint(json.dumps(sorted(sys.modules)))"
    )


def test_the_packages_commands_start_without_numpy():
    """``import frictionlaw``, ``frictionlaw.export`` and both command modules load no NumPy:
    ``--version`` and Ctrl-C are handled before it (issue 41)."""
    code = (
        "import json, sys\nimport frictionlaw, frictionlaw.export, frictionlaw.__main__\n"
        "import frictionlaw.export.__main__\n"
        "print(json.dumps(sorted(m for m in sys.modules if m.split('.')[0] == 'numpy')))"
    )
    assert _run(code) == []

"""Side-by-side ring figures: the GetFEM coupling against ``fe-demo ring``.

Runs ``couplings/getfem/ring.py`` in a Python that imports GetFEM (a subprocess:
Debian's ``python3-getfem`` is built against Debian's NumPy, not the project's)
and ``fe_demo.scenes.run_ring`` in this process, and interpolates both histories
at the requested height reductions.
"""

import csv
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from sbmf_cli import column_key

__all__ = [
    "getfem_python",
    "getfem_missing",
    "run_getfem_ring",
    "read_history",
    "at_reductions",
    "fe_demo_ring_multistage",
    "multistage_agreement",
]

ROOT = Path(__file__).resolve().parents[2]
RING = Path(__file__).resolve().with_name("ring.py")


def getfem_python():
    """Interpreter for the coupling: ``$FRICTIONLAW_GETFEM_PYTHON``, else ``/usr/bin/python3``."""
    return os.environ.get("FRICTIONLAW_GETFEM_PYTHON", "/usr/bin/python3")


def getfem_missing():
    """``None`` when the coupling can run, else the reason (for pytest's skip)."""
    py = getfem_python()
    if not Path(py).exists():
        return f"{py} not found (set FRICTIONLAW_GETFEM_PYTHON)"
    r = subprocess.run(
        [py, "-c", "import getfem, numba, scipy"], capture_output=True, text=True, check=False
    )
    if r.returncode:
        tail = r.stderr.strip().splitlines()[-1:] or ["?"]
        return (
            f"GetFEM coupling not runnable with {py} ({tail[0]}); install it with "
            "apt-get install -y python3-getfem python3-numba python3-scipy"
        )
    return None


def run_getfem_ring(out, args, timeout=3600):
    """Run the coupling script; returns (exit status, wall seconds, combined output)."""
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    cmd = [getfem_python(), str(RING), "--out", str(out), *args]
    t0 = time.perf_counter()
    r = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=timeout, check=False)
    return r.returncode, time.perf_counter() - t0, r.stdout + r.stderr


def read_history(path):
    """``history.csv`` as a dict of column -> array, keyed without units (``force_N``: ``force``)."""
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {column_key(k): np.array([float(r[k]) for r in rows]) for k in rows[0]}


def at_reductions(hist, reductions):
    """Force (N) and inner-diameter change interpolated at the given height reductions."""
    red = np.concatenate([[0.0], hist["height_reduction"]])
    force = np.concatenate([[0.0], hist["force"]])
    d = np.concatenate([[0.0], hist["inner_diameter_change"]])
    if max(reductions) > red[-1] + 1e-9:
        raise ValueError(f"history ends at reduction {red[-1]:.4f} < {max(reductions)}")
    return np.interp(reductions, red, force), np.interp(reductions, red, d)


def fe_demo_ring_multistage(
    params, *, nr, first_reduction, reduction, increments, n_unload=4, reset_history=False
):
    """``fe-demo multistage``'s press-lift-press on the 6:3:2 ring, in fe-demo.

    ``fe_demo.run_multistage`` drives a solid cylinder, which the GetFEM wedge cannot mesh
    (its axis would collapse the hexahedra), so both codes run the ring: fe-demo's own
    ``FormingModel`` and increment driver over the die schedule of the GetFEM script
    (:func:`couplings.getfem.ring.schedule`, the rule of ``run_multistage``).
    Returns ``(history, profiles)``: the accepted increments' columns (with ``stage``) and
    the die-face nodes' ``p_hist`` after each stage (reference and current radius).
    """
    from fe_demo.scenes import LawSpec, Run, drive
    from fe_demo.solver.mesh import ring_mesh
    from fe_demo.solver.model import FormingModel

    from .ring import RingSetup, schedule

    setup = RingSetup(
        law="sbmf",
        params=str(params),
        nr=nr,
        reduction=reduction,
        increments=increments,
        first_reduction=first_reduction,
        n_unload=n_unload,
    )
    axi = ring_mesh(setup.outer_diameter, setup.inner_diameter, setup.height, nr, None)
    spec = LawSpec("sbmf", params=str(params))
    model = FormingModel(axi, _fe_material(setup), spec.factory())
    node = axi.inner_mid_node
    r_in = float(model.X0[node, 0])
    stage = {"k": 1}

    def extra(mdl):
        return {"stage": stage["k"], "inner_diameter_change": (mdl.x[node, 0] - r_in) / r_in}

    run = Run(model, spec, extra=extra)
    hists, profiles = [], []
    for z_target, n_inc, k in schedule(setup):
        if k == 3 and stage["k"] == 2 and reset_history:
            model.contact.reset_history()
        stage["k"] = k
        ok, msg, h, _ = drive(run, [(z_target, n_inc)])
        if not ok:
            raise RuntimeError(f"fe-demo ring multistage failed: {msg}")
        hists.append(h)
        if k == 2 and (model.accepted.p > 0).any():
            raise RuntimeError("fe-demo ring multistage: contact did not open during the lift")
        nodes = model.contact.nodes
        top = model.X0[nodes, 1] >= model.X0[:, 1].max() - 1e-12
        order = np.argsort(model.X0[nodes, 0][top])
        profiles.append(
            {
                "stage": k,
                "height_reduction": float(model.height_reduction),
                "r0": model.X0[nodes, 0][top][order],
                "r": model.x[nodes, 0][top][order],
                "p_hist": np.asarray(model.contact.state.p_hist)[top][order],
            }
        )
    hist = {c: np.concatenate([h[c] for h in hists]) for c in hists[0]}
    return hist, profiles


def _fe_material(setup):
    """fe-demo's material with the GetFEM script's Swift constants (the same DC04-like set)."""
    from fe_demo.solver.material import DC04

    m = setup.material
    for name in ("E", "nu", "K", "eps0", "n"):
        if not np.isclose(getattr(DC04, name), getattr(m, name), rtol=1e-12):
            raise RuntimeError(f"material {name} differs between the GetFEM script and fe-demo")
    return DC04


SEGMENTS = ("press", "lift", "recontact", "reload")


def multistage_agreement(gf_hist, gf_profiles, fd_hist, fd_profiles, min_force=0.01):
    """Force and die-face ``p_hist`` agreement of the two press-lift-press runs.

    Force, GetFEM / fe-demo - 1 where the force exceeds ``min_force`` times the stage's
    largest (the first touch of a re-contact is a few newtons of penalty force): stage 1 at
    GetFEM's die positions (fe-demo interpolated: a smooth press), stage 3 at the die
    positions both runs accepted (the nominal increments; GetFEM adds cut-back steps), since
    the re-contact has a kink that interpolation would blur. ``p_hist``: after each segment of the schedule (``SEGMENTS``),
    fe-demo's die-face profile interpolated over the reference radius at GetFEM's die-face
    nodes, the difference relative to the largest ``p_hist``. Returns a dict of arrays.
    """
    out = {}
    # stage 1: a smooth monotone press, fe-demo interpolated at GetFEM's die positions
    g = gf_hist["stage"] == 1
    f = fd_hist["stage"] == 1
    sg, fg = gf_hist["stroke"][g], gf_hist["force"][g]
    sf, ff = fd_hist["stroke"][f], fd_hist["force"][f]
    on = (sg >= sf.min()) & (sg <= sf.max())
    ref = np.interp(sg[on], sf, ff)
    keep = ref > min_force * ff.max()
    out["stroke_stage1"] = sg[on][keep]
    out["force_rel_stage1"] = fg[on][keep] / ref[keep] - 1.0
    # stage 3: the re-contact has a kink; only the die positions both runs accepted
    g = gf_hist["stage"] == 3
    f = fd_hist["stage"] == 3
    sg, fg = gf_hist["stroke"][g], gf_hist["force"][g]
    sf, ff = fd_hist["stroke"][f], fd_hist["force"][f]
    ig, jf = np.nonzero(np.abs(sg[:, None] - sf[None, :]) <= 1e-12)
    keep = (ff[jf] > min_force * ff.max()) & (fg[ig] > 0)
    out["stroke_stage3"] = sg[ig][keep]
    out["force_rel_stage3"] = fg[ig][keep] / ff[jf][keep] - 1.0
    for name, pg, pf in zip(SEGMENTS, gf_profiles, fd_profiles, strict=True):
        r0g = np.asarray(pg["r0"])
        phg = np.asarray(pg["p_hist"])
        phf = np.interp(r0g, pf["r0"], pf["p_hist"])
        scale = max(phg.max(), np.max(pf["p_hist"]))
        out[f"p_hist_rel_{name}"] = (phg - phf) / scale if scale > 0 else np.zeros_like(phg)
        out[f"p_hist_max_{name}"] = np.array([phg.max(), np.max(pf["p_hist"])])
    g3 = gf_hist["stage"] == 3
    f3 = fd_hist["stage"] == 3
    out["n_eq25_stage3"] = np.array(
        [gf_hist["n_reload_eq25"][g3].max(), fd_hist["n_reload_eq25"][f3].max()]
    )
    return out


if __name__ == "__main__":
    print(getfem_missing() or f"GetFEM coupling runnable with {getfem_python()}")
    sys.exit(0)

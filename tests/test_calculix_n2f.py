"""CalculiX node-to-surface contact on C3D8I slave elements: a block pressed to 350 MPa.

ccx's node-to-surface contact chooses each slave node's master face anew in the first 8
iterations of an increment and keeps them from the 9th on. The block's bottom centre line lies
on an edge between two faces of the plate; the loaded plate dishes, the two faces' normals
differ, and the slave node there is pushed across the edge and back from one iteration to the
next while every slave node sticks. At ccx's default ``I_R = 8`` (it judges the convergence
rate from the 8th iteration on) that bounce, 5.0e-6 mm at 340 MPa with the routine's
default stick, was above ccx's 1 % displacement criterion and ccx gave up ("too many
cutbacks": a smaller increment does not shrink the bounce). With ``*CONTROLS`` setting
``I_R = 9`` ccx reaches its 9th iteration, where it keeps the master faces, and the increment
converges (docs/fe_codes.md, "CalculiX"; ccx's own Coulomb friction with the same stick slope
iterates the same).

Checked on the runs with that line: the normal contact forces balance the load at every output
time, the friction forces the reaction that slides the block, and no slave node's shear
exceeds the law's ``tau(p, p_hist)`` (the slipping ones are on it). The build and its fixtures:
tests/test_calculix.py.
"""

import re

import numpy as np
import pytest
import test_calculix as base
from ccx_decks import SLAVE0, plastic_block, read_blocks
from test_calculix import EXAMPLE, ROOT, _doc_lines, _run
from test_calculix_contact import _sta

from frictionlaw import FrictionParams, shear_limit

ccx_work, export_dir, ccx = base.ccx_work, base.export_dir, base.ccx

#: (pressure MPa, ux mm) at the end of each step: the block pressed to 200, then 350 MPa
PRESS = [(200.0, 0.0), (350.0, 0.0)]
#: then slid by 0.1 mm at 350 MPa
SLIDE = [*PRESS, (350.0, 0.1)]
#: the block's top (12 x 8 mm) carries the pressure
TOP_AREA = 96.0
#: the deck lines of docs/fe_codes.md for each step: ccx's time incrementation controls with
#: I_R = 9 (the other values ccx's defaults)
CONTROLS = ["*CONTROLS, PARAMETERS=TIME INCREMENTATION", "4,9"]
#: the bottom centre node of the block, on the plate's edge at y = 4 mm
CENTRE = SLAVE0 + 17


def _controls_lines():
    """The controls lines of docs/fe_codes.md ("CalculiX"), as printed there."""
    text = (ROOT / "docs" / "fe_codes.md").read_text(encoding="utf-8")
    section = text.split("## CalculiX: `calculix`", 1)[1].split("\n## ", 1)[0]
    block = section.split("\n    *CONTROLS", 1)[1].split("\n\n", 1)[0]
    lines = [ln.strip() for ln in ("    *CONTROLS" + block).splitlines()]
    assert lines == CONTROLS, lines
    return lines


def test_the_docs_and_the_export_readme_give_the_controls_lines(export_dir):
    readme = (export_dir / "README.md").read_text()
    assert "      " + "\n      ".join(_controls_lines()) + "\n" in readme


def _deck(steps, static="0.1, 1., 1e-6, 0.1", controls=True):
    """The elastic C3D8I block on the 6 x 4 plate, node-to-surface, the docs' deck lines (with
    ``controls``, the controls lines in each step)."""
    deck = plastic_block(
        steps,
        _doc_lines(),
        contact="NODE TO SURFACE",
        static=static,
        element="C3D8I",
        plastic=False,
    )
    if not controls:
        return deck
    return deck.replace("*STATIC\n", "\n".join([*_controls_lines(), "*STATIC\n"]))


def _areas():
    """Each slave node's area (mm^2): the block's bottom, 6 x 4 faces of 2 x 2 mm."""
    w = np.zeros((5, 7))
    for j in range(4):
        for i in range(6):
            w[j : j + 2, i : i + 2] += 1.0
    return {SLAVE0 + k: float(v) for k, v in enumerate(w.ravel())}


def _load(t):
    """The pressure on the block's top at total time ``t`` (MPa)."""
    return 200.0 * t if t <= 1.0 else min(200.0 + 150.0 * (t - 1.0), 350.0)


def _check(proc, dat, folder, n_inc):
    """The run converged, ``n_inc`` increments each at its first attempt, and its contact
    balances the load and the driving force, the shear within the law's; returns the .sta rows
    and the slipping node-times."""
    assert proc.returncode == 0 and "Job finished" in proc.stdout, proc.stdout[-2000:]
    assert "*ERROR" not in proc.stdout and "*WARNING in a user routine" not in proc.stdout
    rows = _sta(folder)
    assert len(rows) == n_inc and all(r[2] == 1 for r in rows), rows
    areas, law = _areas(), FrictionParams.from_json(EXAMPLE)
    blocks = read_blocks(dat)
    assert len(blocks) == n_inc  # every converged increment printed
    n_slip = 0
    for t, block in blocks:
        stress = {int(r[0]): r[1:] for r in block["stress"]}
        sdv = {int(r[0]): r[1:] for r in block["sdv"]}
        assert set(stress) == set(areas)  # every slave node in contact
        p = np.array([stress[n][0] for n in areas])
        t1 = np.array([stress[n][1] for n in areas])  # along x: t1 of the flat plate
        tau = np.hypot(t1, [stress[n][2] for n in areas])
        a = np.array(list(areas.values()))
        # the normal contact forces carry the load (measured within 1.3e-3)
        assert (p * a).sum() == pytest.approx(_load(t) * TOP_AREA, rel=2e-3), t
        p_hist = np.array([sdv[n][0] for n in areas])
        assert np.all(p_hist >= p * (1 - 1e-6))
        limit = shear_limit(p * 1e6, p_hist * 1e6, law) / 1e6
        assert np.all(tau <= limit * (1 + 2e-6)), (t, (tau / limit).max())
        slip = np.array([sdv[n][2] == 2.0 for n in areas])
        np.testing.assert_allclose(tau[slip], limit[slip], rtol=2e-6)
        if slip.all():  # full slip: the friction forces balance the top's reaction (2.0e-3)
            assert (t1 * a).sum() == pytest.approx(block["total"][0][0], rel=3e-3), t
        n_slip += int(slip.sum())
    return rows, n_slip


def test_without_the_controls_line_ccx_gives_up_at_its_eighth_iteration(ccx, tmp_path):
    """The press with ccx's default controls stops in the second step: every attempt of the
    increment is given up at iteration 8, the largest correction the centre node's sideways
    bounce across the plate's edge."""
    proc, _ = _run(ccx, _deck(PRESS, controls=False), tmp_path)
    assert proc.returncode != 0 and "too many cutbacks" in proc.stdout
    attempts = re.split(r"increment \d+ attempt \d+", proc.stdout)[1:]
    slow = [a for a in attempts if "too slow convergence" in a]
    assert len(slow) >= 5
    for a in slow:
        assert "iteration 8\n" in a and "iteration 9\n" not in a
        last = a.rsplit("largest correction to disp=", 1)[1].split("\n", 1)[0]
        assert last.endswith(f"in node {CENTRE} and dof 2"), last
    last = _sta(tmp_path)[-1]  # the last converged increment: within the second step
    assert last[0] == 2 and 0.5 < last[5] < 1.0, last


def test_press_and_slide_converge_with_the_controls_line(ccx, tmp_path):
    """Pressed to 350 MPa and slid by 0.1 mm with I_R = 9: every increment converges at its
    first attempt (measured 77 iterations over the 30, the bounced ones in 9), the normal
    forces carry the load, the friction forces the driving force at full slip, and the shear
    is the law's where a node slips."""
    proc, dat = _run(ccx, _deck(SLIDE), tmp_path)
    rows, n_slip = _check(proc, dat, tmp_path, 30)
    assert max(r[3] for r in rows) == 9 and sum(r[3] for r in rows) <= 100
    assert n_slip > 9 * 30  # every node slips in the slide's last 9 increments


def test_finer_increments_converge_with_the_controls_line(ccx, tmp_path):
    """Increments of 0.05 halve ccx's displacement increments but not the bounce: without the
    line a smaller increment cannot help; with it they converge too."""
    proc, dat = _run(ccx, _deck(PRESS, "0.05, 1., 1e-6, 0.05"), tmp_path)
    _check(proc, dat, tmp_path, 40)

"""CalculiX node-to-surface contact on C3D8I slave elements: a block pressed to 350 MPa.

ccx's node-to-surface contact chooses each slave node's master face anew in the first 8
iterations of an increment (from iteration 9 on it keeps them). The block's bottom centre
line lies on an edge between two faces of the plate; the loaded plate dishes, the two faces'
normals differ, and the node there is pushed across the edge and back from iteration to
iteration by an amount that shrinks as the stick stiffens. With Abaqus' elastic slip of
0.005 CHRLNGTH that exceeded ccx's 1 % displacement criterion at about 330 MPa and ccx gave
up ("too many cutbacks"; ccx's own Coulomb friction with the same stick slope iterates the
same to 6 digits); the CalculiX target's 0.001 CHRLNGTH converges in 2 iterations an increment,
and ``*CONTROLS`` letting ccx reach its 9th iteration (I_R = 9) converges either stick
(docs/fe_codes.md, "CalculiX").

Checked on the converged run: the normal contact forces balance the load and the plate's
support at every output time, and no slave node's shear exceeds the law's
``tau(p, p_hist)``. The build and its fixtures: tests/test_calculix.py.
"""

import numpy as np
import pytest
import test_calculix as base
from ccx_decks import SLAVE0, plastic_block, read_blocks
from test_calculix import EXAMPLE, _doc_lines, _link, _run
from test_calculix_contact import _sta

from frictionlaw import FrictionParams, shear_limit
from frictionlaw.export.cli import main as export_main

ccx_work, export_dir, ccx = base.ccx_work, base.export_dir, base.ccx

#: (pressure MPa, ux mm) at the end of each step: the block pressed to 200, then 350 MPa
PRESS = [(200.0, 0.0), (350.0, 0.0)]
#: the block's top (12 x 8 mm) carries the pressure
TOP_AREA = 96.0
#: ccx's time incrementation with the 9th iteration reached before it judges the rate (I_R)
CONTROLS = "*CONTROLS, PARAMETERS=TIME INCREMENTATION\n4,9\n*STATIC\n"


def _deck(static="0.1, 1., 1e-6, 0.1", controls=False):
    """The elastic C3D8I block on the 6 x 4 plate, node-to-surface, the docs' deck lines; the
    plate's support reaction printed too."""
    deck = plastic_block(
        PRESS,
        _doc_lines(),
        contact="NODE TO SURFACE",
        static=static,
        element="C3D8I",
        plastic=False,
    )
    deck = deck.replace(
        "*CONTACT PRINT\n", "*NODE PRINT, NSET=NBASE, TOTALS=ONLY\nRF\n*CONTACT PRINT\n"
    )
    return deck.replace("*STATIC\n", CONTROLS) if controls else deck


def _areas():
    """Each slave node's area (mm^2): the block's bottom, 6 x 4 faces of 2 x 2 mm."""
    w = np.zeros((5, 7))
    for j in range(4):
        for i in range(6):
            w[j : j + 2, i : i + 2] += 1.0
    return {SLAVE0 + k: float(v) for k, v in enumerate(w.ravel())}


def _load(t):
    """The pressure on the block's top at total time ``t`` (MPa)."""
    return 200.0 * t if t <= 1.0 else 200.0 + 150.0 * (t - 1.0)


def _check_run(proc, dat, folder):
    """The run converged and its contact balances the load, the shear within the law's;
    returns (increments, iterations, slipping node-times)."""
    assert proc.returncode == 0 and "Job finished" in proc.stdout, proc.stdout[-2000:]
    assert "*ERROR" not in proc.stdout and "*WARNING in a user routine" not in proc.stdout
    rows = _sta(folder)
    assert rows[-1][4] == pytest.approx(2.0)
    areas, law = _areas(), FrictionParams.from_json(EXAMPLE)
    blocks = read_blocks(dat)
    assert len(blocks) == len(rows)  # every converged increment printed
    n_slip = 0
    for t, block in blocks:
        load = _load(t) * TOP_AREA  # N
        stress = {int(r[0]): r[1:] for r in block["stress"]}
        sdv = {int(r[0]): r[1:] for r in block["sdv"]}
        assert set(stress) == set(areas)  # every slave node in contact
        normal = sum(stress[n][0] * a for n, a in areas.items())
        assert normal == pytest.approx(load, rel=2e-3), (t, normal, load)
        fz_base = block["total"][1][2]  # the plate's support (the block's top comes first)
        assert fz_base == pytest.approx(load, rel=1e-4), (t, fz_base, load)
        p = np.array([stress[n][0] for n in areas])
        tau = np.array([np.hypot(stress[n][1], stress[n][2]) for n in areas])
        p_hist = np.array([sdv[n][0] for n in areas])
        assert np.all(p_hist >= p * (1 - 1e-6))
        limit = shear_limit(p * 1e6, p_hist * 1e6, law) / 1e6
        assert np.all(tau <= limit * (1 + 2e-6)), (t, (tau / limit).max())
        slip = np.array([sdv[n][2] == 2.0 for n in areas])
        np.testing.assert_allclose(tau[slip], limit[slip], rtol=2e-6)
        n_slip += int(slip.sum())
    return len(rows), sum(r[3] for r in rows), n_slip


def test_c3d8i_press_converges_at_the_default_stick(ccx, tmp_path):
    """The default routine (elastic slip 0.001 CHRLNGTH): every increment of 0.1 converges at
    its first attempt in at most 3 iterations (measured 41 iterations over the 20)."""
    proc, dat = _run(ccx, _deck(), tmp_path)
    n_inc, n_it, n_slip = _check_run(proc, dat, tmp_path)
    assert n_inc == 20 and n_it <= 3 * n_inc, (n_inc, n_it)
    assert n_slip > 0  # the block's corners slip outwards: the law's bound is reached


@pytest.fixture(scope="module")
def ccx_abaqus_slip(ccx_work, tmp_path_factory):
    """ccx with the abaqus-fric routine: the same FRIC with Abaqus' 0.005 CHRLNGTH."""
    out = tmp_path_factory.mktemp("abaqus_slip") / "export"
    args = ["abaqus-fric", "--params", str(EXAMPLE), "--out", str(out), "--units", "mm-t-s"]
    assert export_main([*args, "--quiet"]) == 0
    assert "PARAMETER (FSLIP = 5.00000000000000010D-3)" in (out / "sbmf_fric.f").read_text()
    return _link(ccx_work, out / "sbmf_fric.f", out / "ccx")


def test_abaqus_elastic_slip_needs_ccx_to_reach_its_ninth_iteration(ccx_abaqus_slip, tmp_path):
    """The former stick, Abaqus' 0.005 CHRLNGTH: ccx gives up on the press at its 8th iteration
    (the block's bottom centre node bounces across the plate's edge: "too many cutbacks"); with
    I_R = 9, ccx keeps the master faces at the 9th iteration and the run converges, the
    affected increments in 9 iterations."""
    proc, _ = _run(ccx_abaqus_slip, _deck(), tmp_path / "default")
    assert proc.returncode != 0 and "too many cutbacks" in proc.stdout
    assert "largest correction to disp= " in proc.stdout
    last = proc.stdout.rsplit("largest correction to disp=", 1)[1].split("\n", 1)[0]
    assert f"in node {SLAVE0 + 17} and dof 2" in last  # the bottom centre node, across the edge
    folder = tmp_path / "controls"
    proc, dat = _run(ccx_abaqus_slip, _deck(controls=True), folder)
    n_inc, _, _ = _check_run(proc, dat, folder)
    assert n_inc == 20 and max(r[3] for r in _sta(folder)) == 9


def test_finer_increments_converge_with_the_controls_line(ccx, tmp_path):
    """Increments of 0.05 halve ccx's displacement increments but not the bounce across the
    edge; with the documented I_R = 9 the default routine converges there too."""
    proc, dat = _run(ccx, _deck("0.05, 1., 1e-6, 0.05", controls=True), tmp_path)
    n_inc, _, _ = _check_run(proc, dat, tmp_path)
    assert n_inc == 40

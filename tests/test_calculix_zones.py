"""Zonal laws in CalculiX (issue 42): a two-zone deck runs each contact pair on its own law.

Two blocks side by side on one base (tests/ccx_decks.py, ``two_zones``), each block's bottom a
node-to-surface contact pair with its own surface interaction, ``RIM`` and ``FLANK``; the routine
``frictionlaw-export calculix --zone rim=... --zone flank=...`` (no default law) chooses the law
by ``CINAME``, the interaction's name the patched ccx passes. Pressed, slid, unloaded and
reloaded: at every fully sliding output time every slave node's shear stress (``CSTR``) equals
``shear_limit(p, p_hist)`` of its own block's parameter file, node by node, with ``p_hist`` the
largest pressure ccx printed at that node; the other zone's law is far from it. An interaction
whose name no zone gives stops ccx (exit 201) with the routine's message naming it.
"""

import dataclasses

import numpy as np
import pytest
from ccx_decks import SLAVE0, SLAVE1, read_blocks, two_zones
from reload_tables import STRONG
from test_calculix import EXAMPLE, _link, _run, _run_ok, ccx_work  # noqa: F401

from frictionlaw import FrictionParams, shear_limit
from frictionlaw.export.cli import main as export_main

#: zone rim: the shipped example law (Eq. 24, the paper's Eq. 25); zone flank: another tool's
#: law (m 0.45, the tabulated reload form)
RIM = FrictionParams.from_json(EXAMPLE)
FLANK = dataclasses.replace(RIM, m=0.45, reload_form="tabulated", reload_table=STRONG)
#: (pressure MPa, ux mm) at the end of each step: press, slide, unload while sliding, reload at
#: rest, slide on the reload branch. (tests/test_calculix.py's steps, which reload while
#: sliding, take ccx's automatic incrementation past 200 increments in the reload step with two
#: blocks of different laws; with both blocks on one law they run.)
STEPS = [(400.0, 0.0), (400.0, 0.1), (150.0, 0.2), (300.0, 0.2), (300.0, 0.3)]
#: the output times at which every slave node slides (the block's first slide reaches full slip
#: at about t = 1.3; step 4 is at rest; step 5 slides again)
SLIDING = ((1.5, 3.0), (4.5, 5.0))


def _interaction(name):
    return [
        f"*SURFACE INTERACTION, NAME={name}",
        "*FRICTION, USER, DEPVAR=4, PROPERTIES=1",
        "MM-T-S",
    ]


@pytest.fixture(scope="module")
def zoned_ccx(ccx_work, tmp_path_factory):  # noqa: F811
    folder = tmp_path_factory.mktemp("zones")
    files = {}
    for name, params in (("rim", RIM), ("flank", FLANK)):
        files[name] = folder / f"{name}.json"
        params.to_json(files[name])
    out = folder / "export"
    args = ["calculix", "--out", str(out), "--units", "mm-t-s", "--quiet"]
    args += ["--zone", f"Rim={files['rim']}", "--zone", f"flank={files['flank']}"]
    assert export_main(args) == 0
    return _link(ccx_work, out / "sbmf_fric.f", out / "ccx")


def test_two_zone_deck_runs_each_pair_on_its_own_law(zoned_ccx, tmp_path):
    dat = _run_ok(
        zoned_ccx, two_zones(STEPS, [_interaction("RIM"), _interaction("Flank")]), tmp_path
    )
    nodes = {SLAVE0 + k: RIM for k in range(16)} | {SLAVE1 + k: FLANK for k in range(16)}
    other = {id(RIM): FLANK, id(FLANK): RIM}
    p_hist, worst, off, checked, below, law_of = {}, 0.0, [], 0, 0, {}
    for t, blocks in read_blocks(dat):
        for row in blocks.get("stress", []):
            node, p, t1, t2 = int(row[0]), *row[1:4]
            p_hist[node] = max(p_hist.get(node, 0.0), p)
            if not any(a <= t <= b for a, b in SLIDING):
                continue
            params = nodes[node]
            tau = float(shear_limit(p * 1e6, p_hist[node] * 1e6, params)) / 1e6
            worst = max(worst, abs(np.hypot(t1, t2) - tau) / tau)
            alt = float(shear_limit(p * 1e6, p_hist[node] * 1e6, other[id(params)])) / 1e6
            off.append(abs(alt - tau) / tau)
            checked += 1
            below += p < p_hist[node]
        for row in blocks.get("sdv", []):  # STATEV(4): the law that wrote the cache
            law_of[int(row[0])] = row[4]
    # ccx's node-to-surface search leaves one interior slave node of each block out of contact
    # here (1006, 2011); every other slave node is checked at every sliding output time
    for first in (SLAVE0, SLAVE1):
        assert len([k for k in p_hist if first <= k < first + 16]) >= 15
    assert set(p_hist) <= set(nodes) and checked >= 10 * 30
    assert worst < 1e-5, worst
    assert np.median(off) > 0.1, np.median(off)  # the other zone's law is far from it
    assert below > 100  # the reload branch, under each zone's own law
    assert law_of == {n: (1.0 if n < SLAVE1 else 2.0) for n in p_hist}


def test_an_interaction_no_zone_gives_stops_ccx_naming_it(zoned_ccx, tmp_path):
    deck = two_zones(STEPS[:1], [_interaction("RIM"), _interaction("TIP")])
    proc, _ = _run(zoned_ccx, deck, tmp_path)
    assert proc.returncode == 201, proc.stdout[-2000:]
    assert "*ERROR in a user routine: SBMF friction: CINAME = 'TIP'" in proc.stdout
    assert "is none of this routine's zones (Rim, flank)" in proc.stdout

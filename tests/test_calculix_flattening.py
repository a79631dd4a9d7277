"""The flattening under bulk strain in CalculiX (issue 43): the slave element's plastic strain.

The patched ccx passes the routine of ``frictionlaw-export calculix`` the equivalent plastic
strain under a contact point (CalculiX's PEEQ averaged over a solid element's integration points:
face-to-face, the element whose face carries the point; node-to-surface, the elements of the
slave node's faces, weighted by area) as its predefined field 1: ``PREDEF(1, 1)`` at
the iterate, ``PREDEF(2, 1)`` its increment since the start of the increment (``NPRED = 1``);
the contact elements are computed after every solid element of the iterate, so that it is the
iterate's strain. The routine keeps the flattened fraction in ``STATEV(5)``.

- Host emulation (gfortran): the routine given ``PREDEF`` flattens as the runtime's traction
  update given the same increments (1e-12), with a flow curve baked in (``--flow-curve``) at the
  middle of the increment's strain; without the field (layered or beam elements) it says so once
  and keeps the fraction it has.
- Real ccx runs: each contact point's flattened fraction is the runtime's replay of its
  converged increments, from the pressures and slave-element strains ccx printed; one thread and
  two give the same; node-to-surface, each slave node's fraction is the replay with the mean
  strain of its faces' elements; while sliding, the shear at slipping points is the flattened
  law's and the friction force exceeds the law's without flattening; a deck with too few state
  variables is refused while ccx reads it; a ring compression with the flattening matches
  ``fe-demo ring --flattening``.
"""

import dataclasses

import numpy as np
import pytest
import test_calculix as base
from ccx_decks import SLAVE0, plastic_block, read_blocks
from ccx_decks import ring as ring_deck
from test_calculix import ROOT, _link, _ring_result, _run, _run_ok
from test_export_flattening import grid, law, load, runtime

import frictionlaw as fl
from frictionlaw.export import harness
from frictionlaw.export.cli import main as export_main
from frictionlaw.flattening import flattened_alpha, flattening_pressure
from frictionlaw.flow_curve import SwiftCurve

ccx_work = base.ccx_work

FLAT = ROOT / "fe_demo" / "data" / "sbmf_example_flattening.json"
LINES = ["*SURFACE INTERACTION, NAME=SBMF", "*FRICTION, USER, DEPVAR=5, PROPERTIES=1", "MM-T-S"]
DC04 = SwiftCurve(530e6, 0.006, 0.24)

needs_gfortran = pytest.mark.skipif(harness.gfortran() is None, reason="needs gfortran")


# -- host emulation ------------------------------------------------------------------------------


@needs_gfortran
@pytest.mark.parametrize("form", ["eq24-paper", "tabulated"])
@pytest.mark.parametrize("curve", [None, DC04], ids=["perfectly-plastic", "flow-curve"])
def test_routine_flattens_with_the_slave_strain_as_the_runtime(tmp_path, form, curve):
    P = law(form)
    spec = None if curve is None else "swift:530e6,0.006,0.24"
    host, files = load(tmp_path, "calculix", P, name=f"ccx_{form}", flow_curve=spec)
    assert "PREDEF(2, 1)" in files["README.md"] and "DEPVAR >= 5" in files["README.md"]
    p, ph, af, de, _ = grid()
    n = p.size
    eps = de + np.linspace(0.0, 0.3, n)  # the element's strain at the iterate
    sv = np.zeros((n, 5))
    sv[:, 0], sv[:, 4] = ph, af
    out = host(
        p, np.full((n, 1), 1e3), np.zeros((n, 1)), sv, 1e-3, predef=np.column_stack([eps, de])
    )
    kw = {"sigy": np.zeros(n)}
    if curve is not None:
        mid = np.maximum(eps - 0.5 * de, 0.0)
        kw = {"sigy": curve.sigma_y(mid), "hardening": curve.hardening(mid)}
    tau, _, a_ref = runtime(P, p, ph, af, de, **kw)
    assert np.all(out["lm"] == 0) and host.exits() == 0 and host.log() == []
    assert np.allclose(np.abs(out["tau"][:, 0]), tau, rtol=1e-12, atol=0)
    assert np.allclose(out["statev"][:, 4], a_ref, rtol=1e-12, atol=0)
    assert np.array_equal(out["statev"][:, 0], np.maximum(ph, p))
    assert np.any(a_ref > fl.alpha_first(p, P) + 0.1)  # it flattened


@needs_gfortran
def test_routine_without_the_field_keeps_its_fraction_and_says_so_once(tmp_path):
    """``NPRED = 0`` (layered or beam elements): one warning, the stored fraction read, no growth."""
    P = law()
    host, _ = load(tmp_path, "calculix", P, name="ccx_nofield")
    p = np.array([0.1, 0.3, 0.5]) * P.H
    af = np.array([0.0, 0.6, 0.2])
    sv = np.zeros((3, 5))
    sv[:, 4] = af
    for _ in range(3):
        out = host(p, np.full((3, 1), 1e3), np.zeros((3, 1)), sv, 1e-3)
        tau, _, a_ref = runtime(P, p, np.zeros(3), af, np.zeros(3), np.zeros(3))
        assert np.allclose(np.abs(out["tau"][:, 0]), tau, rtol=1e-12)
        assert np.array_equal(out["statev"][:, 4], a_ref) and np.array_equal(a_ref, af)
    log = [t for _, t in host.log() if "flattening block" in t]
    assert len(log) == 1 and host.exits() == 0
    assert "layered (composite) or beam-derived" in log[0]


def test_export_says_what_the_deck_needs(tmp_path, capsys):
    """The README gives DEPVAR=5 and the field; --without-flattening is refused (it runs)."""
    out = tmp_path / "x"
    assert export_main(["calculix", "--params", str(FLAT), "--out", str(out), "--quiet"]) == 0
    readme = (out / "README.md").read_text()
    assert "*FRICTION, USER, DEPVAR=5, PROPERTIES=1" in readme
    assert "TYPE=SURFACE TO SURFACE" in readme
    code = export_main(
        ["calculix", "--params", str(FLAT), "--out", str(tmp_path / "y"), "--without-flattening"]
    )
    assert code == 2 and "runs the flattening" in capsys.readouterr().err


# -- real ccx runs -------------------------------------------------------------------------------


def _export(tmp_path, params_path, name):
    out = tmp_path / name
    code = export_main(
        ["calculix", "--params", str(params_path), "--out", str(out), "--units", "mm-t-s"]
        + ["--quiet"]
    )
    assert code == 0
    return out


@pytest.fixture(scope="module")
def ccx_flat(ccx_work, tmp_path_factory):
    out = _export(tmp_path_factory.mktemp("ccxflat"), FLAT, "flat")
    return _link(ccx_work, out / "sbmf_fric.f", out / "ccx")


def _with_peeq(deck):
    """The deck with ``*EL PRINT`` of the block's PEEQ in every step."""
    return deck.replace("*END STEP", "*EL PRINT, ELSET=EBLOCK\nPEEQ\n*END STEP")


def _points(dat):
    """Per output time: (time, {(element, face, point): (p, sdv...)}, {element: mean PEEQ})."""
    out = []
    for t, block in read_blocks(dat):
        stress, sdv = np.array(block["stress"]), np.array(block["sdv"])
        assert np.array_equal(stress[:, :2], sdv[:, :2])
        pts = {
            (int(r[0]), int(r[1]), int(r[2])): (s[2], *r[3:])
            for s, r in zip(stress, sdv, strict=True)
        }
        peeq = {}
        for el, _, pe in block["peeq"]:
            peeq.setdefault(int(el), []).append(pe)
        out.append((t, pts, {el: float(np.mean(v)) for el, v in peeq.items()}))
    return out


PRESS = [(200.0, 0.0), (350.0, 0.0)]
INCREMENTS = "0.1, 1., 1e-6, 0.1"


@pytest.fixture(scope="module")
def pressed(ccx_flat, tmp_path_factory):
    folder = tmp_path_factory.mktemp("pressed")
    deck = _with_peeq(plastic_block(PRESS, LINES, static=INCREMENTS))
    runs = []
    for threads in (1, 2):
        proc, dat = _run(ccx_flat, deck, folder / f"t{threads}", threads=threads)
        assert proc.returncode == 0 and "Job finished" in proc.stdout, proc.stdout[-2000:]
        assert "*WARNING in a user routine" not in proc.stdout
        runs.append(_points(dat))
    return runs


def _replay_miss(run, P, lag=False):
    """The largest miss of each point's STATEV(5) against the runtime's update of its face's
    previous states, and how many points flattened by more than 0.05.

    Face-to-face contact lays the slave integration points out anew as the block spreads, and
    each new point takes the whole state of one old point of its face (the patch's rule), so a
    point's previous state is one of its face's at the previous output: the miss of a point is
    the smallest over them. ``lag``: the strain increment of the increment before (what a
    routine reading the previous iterate's strain would come close to)."""
    prev_pts, prev_peeq, prev_de = {}, {}, {}
    worst, grew = 0.0, 0
    for _, pts, peeq in run:
        de_now = {el: peeq[el] - prev_peeq.get(el, 0.0) for el in peeq}
        faces, old = {}, {}
        for k in pts:
            faces.setdefault(k[:2], []).append(k)
        for k in prev_pts:
            old.setdefault(k[:2], []).append(prev_pts[k])
        for face, keys in faces.items():
            p = np.array([pts[k][0] for k in keys]) * 1e6
            got = np.array([pts[k][5] for k in keys])
            de = np.full(len(keys), (prev_de if lag else de_now).get(face[0], 0.0))
            best = np.full(len(keys), np.inf)
            for row in old.get(face, [(0.0, 0.0, 0.0, 0.0, 0.0, 0.0)]):
                st = fl.HistoryState(
                    p_hist=np.full(len(keys), row[1] * 1e6), alpha_f=np.full(len(keys), row[5])
                )
                fl.traction_update(
                    fl.SBMFLaw(P), p, np.ones(len(keys)), np.zeros(len(keys)), 1e30, st, d_eps=de
                )
                best = np.minimum(best, np.abs(st.alpha_f_trial - got))
            on = p > 0
            worst = max(worst, float(best[on].max(initial=0.0)))
            grew += int(np.sum(got[on] > fl.alpha_first(p[on], P) + 0.05))
        prev_pts, prev_peeq, prev_de = pts, peeq, de_now
    return worst, grew


def test_each_point_flattens_as_the_runtime_replay_of_its_increments(pressed):
    """Pressing the elastic-plastic block (yield 250 MPa) to 350 MPa in 20 increments: at each
    converged increment every contact point's STATEV(5) is the runtime's update, from one of
    its face's previous states, with the increment of its slave element's mean PEEQ at its
    pressure (1.4e-7 seen: ccx prints 7 digits). The slave elements flow (PEEQ to 0.045) and
    the points reach full contact; the increment before's strain misses by far more."""
    P = fl.FrictionParams.from_json(FLAT)
    run = pressed[0]
    assert len(run) == 20
    assert max(run[-1][2].values()) > 0.01  # the slave elements flowed
    worst, grew = _replay_miss(run, P)
    assert worst < 1e-6, worst
    assert grew > 1000 and max(v[5] for v in run[-1][1].values()) == 1.0
    assert _replay_miss(run, P, lag=True)[0] > 1e-2


def test_two_threads_give_the_one_threads_flattening(pressed):
    one, two = pressed
    for (t1, a, _), (t2, b, _) in zip(one, two, strict=True):
        assert t1 == t2 and a.keys() == b.keys()
        for k in a:
            assert abs(a[k][5] - b[k][5]) <= 1e-6


def test_sliding_shear_is_the_flattened_laws_and_above_the_law_without(
    ccx_work, ccx_flat, tmp_path
):
    """Press to 350 MPa, then slide 0.3 mm: at every slipping point ccx's shear is the
    flattened law's, ``tau = tau_law(p, p_hist) alpha_F5 / alpha_law`` (7 digits), and the
    friction force at the end of the slide is above the same deck's with the law exported
    without its flattening block."""
    P = fl.FrictionParams.from_json(FLAT)
    deck = plastic_block([*PRESS, (350.0, 0.3)], LINES, static=INCREMENTS)
    proc, dat = _run(ccx_flat, deck, tmp_path / "flat")
    assert proc.returncode == 0 and "Job finished" in proc.stdout, proc.stdout[-2000:]
    plain = dataclasses.replace(P, flattening=None).to_json(tmp_path / "plain.json")
    out = _export(tmp_path, plain, "plain")
    binary = _link(ccx_work, out / "sbmf_fric.f", out / "ccx")
    proc0, dat0 = _run(binary, deck, tmp_path / "plain_run")
    assert proc0.returncode == 0 and "Job finished" in proc0.stdout
    n_slip = 0
    for _, block in read_blocks(dat):
        stress, sdv = np.array(block["stress"]), np.array(block["sdv"])
        slip = sdv[:, 5] == 2.0
        p, tau = stress[slip, 2] * 1e6, np.hypot(stress[slip, 3], stress[slip, 4]) * 1e6
        ph, af = sdv[slip, 3] * 1e6, sdv[slip, 7]
        ratio = flattened_alpha(p, ph, flattening_pressure(af, P), P) / flattened_alpha(
            p, ph, 0.0, P
        )
        law = fl.shear_limit(p, ph, P) * ratio
        assert np.allclose(tau, law, rtol=2e-6), np.abs(tau / law - 1).max()
        n_slip += int(slip.sum())
    assert n_slip > 100
    # the reaction at the block's top in the sliding direction (TOTALS=ONLY)
    force, force0 = (read_blocks(d)[-1][1]["total"][0][0] for d in (dat, dat0))
    assert abs(force) > 1.2 * abs(force0) > 0, (force, force0)


def test_node_to_surface_nodes_flatten_with_their_elements_strain(ccx_flat, tmp_path):
    """Node-to-surface contact (C3D8): each slave node's STATEV(5) is the runtime's update of its
    previous one with the mean PEEQ increment of the elements of its slave faces (ccx weighs
    them as the node's area takes each face: equal faces here, to the spread of the block;
    3e-6 seen), at its pressure; the increment before's strain misses by far more."""
    P = fl.FrictionParams.from_json(FLAT)
    deck = _with_peeq(
        plastic_block(PRESS, LINES, static=INCREMENTS, contact="NODE TO SURFACE", element="C3D8")
    )
    proc, dat = _run(ccx_flat, deck, tmp_path)
    assert proc.returncode == 0 and "Job finished" in proc.stdout, proc.stdout[-2000:]
    assert "*WARNING in a user routine" not in proc.stdout
    # the block's bottom layer (its slave faces S1: the first four nodes of each element)
    rows = deck.split("ELSET=EBLOCK\n", 1)[1].split("*", 1)[0].strip().splitlines()
    faces = {}
    for row in rows:
        el, *nodes = (int(v) for v in row.split(","))
        if min(nodes) < SLAVE0 + 7 * 5:  # the bottom layer's nodes: 7 x 5 of them
            for node in nodes[:4]:
                faces.setdefault(node, []).append(el)

    def miss(lag):
        prev, prev_peeq, prev_de, worst = {}, {}, {}, 0.0
        for _, block in read_blocks(dat):
            peeq = {}
            for el, _, pe in block["peeq"]:
                peeq.setdefault(int(el), []).append(pe)
            peeq = {el: float(np.mean(v)) for el, v in peeq.items()}
            de_now = {
                n: float(np.mean([peeq[e] - prev_peeq.get(e, 0.0) for e in els]))
                for n, els in faces.items()
            }
            sdv = {int(r[0]): r[1:] for r in block["sdv"]}
            stress = {int(r[0]): r[1] for r in block["stress"]}
            nodes = sorted(sdv)
            p = np.array([stress[n] for n in nodes]) * 1e6
            st = fl.HistoryState(
                p_hist=np.array([prev.get(n, (0.0,) * 5)[0] for n in nodes]) * 1e6,
                alpha_f=np.array([prev.get(n, (0.0,) * 5)[4] for n in nodes]),
            )
            de = np.array([(prev_de if lag else de_now).get(n, 0.0) for n in nodes])
            fl.traction_update(
                fl.SBMFLaw(P), p, np.ones(len(nodes)), np.zeros(len(nodes)), 1e30, st, d_eps=de
            )
            got = np.array([sdv[n][4] for n in nodes])
            worst = max(worst, float(np.abs(got - st.alpha_f_trial)[p > 0].max(initial=0.0)))
            prev, prev_peeq, prev_de = sdv, peeq, de_now
        return worst, prev

    worst, last = miss(False)
    assert worst < 1e-5, worst
    assert len(last) == len(faces) == 35 and max(v[4] for v in last.values()) > 0.5
    assert miss(True)[0] > 1e-2


def test_too_few_state_variables_are_refused_while_ccx_reads_the_deck(ccx_flat, tmp_path):
    lines = [LINES[0], "*FRICTION, USER, DEPVAR=3, PROPERTIES=1", "MM-T-S"]
    proc, _ = _run(ccx_flat, plastic_block(PRESS, lines), tmp_path)
    assert proc.returncode != 0 and "Job finished" not in proc.stdout
    assert "USER needs DEPVAR" in proc.stdout and ">= 5" in proc.stdout


def test_ring_compression_with_flattening_matches_fe_demo(ccx_work, tmp_path):
    """The 6:3:2 ring of DC04 to 50 % in 50 increments (axisymmetric CAX4R, node-to-surface),
    the shipped calibration with its flattening block and DC04's flow curve baked in
    (``--flow-curve``), against ``fe-demo ring --flattening`` (its J2 solver passing each die
    node's surface strain and DC04's modulus): two FE codes, one law. Measured: force 231.18 kN
    against 231.32 kN, inner diameter -16.9 % against -17.6 %; without the flattening fe-demo
    gives -2.1 % (ccx -1.6 %): the flattening is most of the friction's effect on the ring."""
    from fe_demo.scenes import run_ring

    out = tmp_path / "ring"
    code = export_main(
        ["calculix", "--params", str(FLAT), "--out", str(out), "--units", "mm-t-s", "--quiet"]
        + ["--flow-curve", "swift:530e6,0.006,0.24"]
    )
    assert code == 0
    binary = _link(ccx_work, out / "sbmf_fric.f", out / "ccx")
    dat = _run_ok(binary, ring_deck(LINES, nr=12, reduction=0.5, n_inc=50), tmp_path / "run")
    force, d_inner = _ring_result(dat)
    P = fl.FrictionParams.from_json(FLAT)
    kw = {"params": P, "nr": 12, "reduction": 0.5, "n_increments": 50}
    ref, plain = (run_ring("sbmf", flattening=f, **kw) for f in (True, False))
    assert ref.converged and plain.converged
    f_ref = float(ref.history["force"][-1])
    d_ref, d_plain = (float(r.history["inner_diameter_change"][-1]) for r in (ref, plain))
    assert abs(force - f_ref) < 0.015 * f_ref, (force, f_ref)
    assert abs(d_inner - d_ref) < 0.015, (d_inner, d_ref)
    assert d_ref < d_plain - 0.1 and d_inner < d_plain - 0.1


def test_a_zoned_routine_flattens_its_zone_in_ccx(ccx_work, tmp_path):
    """A zoned export (``--zone SBMF=flattening file --zone OTHER=the same law without its
    block``) in the pressed block's deck, whose interaction is SBMF: the routine chooses the
    zone by CINAME and runs its flattening (``SBMF_ZFSHR``), every point as the one-law replay
    (1e-6); the interaction renamed OTHER runs the law without flattening (SDV5 stays 0)."""
    P = fl.FrictionParams.from_json(FLAT)
    plain = dataclasses.replace(P, flattening=None).to_json(tmp_path / "plain.json")
    out = tmp_path / "zoned"
    code = export_main(
        ["calculix", "--zone", f"SBMF={FLAT}", "--zone", f"OTHER={plain}", "--out", str(out)]
        + ["--units", "mm-t-s", "--quiet"]
    )
    assert code == 0
    binary = _link(ccx_work, out / "sbmf_fric.f", out / "ccx")
    deck = _with_peeq(plastic_block(PRESS, LINES, static=INCREMENTS))
    proc, dat = _run(binary, deck, tmp_path / "sbmf")
    assert proc.returncode == 0 and "Job finished" in proc.stdout, proc.stdout[-2000:]
    run = _points(dat)
    worst, grew = _replay_miss(run, P)
    assert worst < 1e-6 and grew > 1000, (worst, grew)
    other = deck.replace("NAME=SBMF", "NAME=OTHER").replace("INTERACTION=SBMF", "INTERACTION=OTHER")
    proc, dat = _run(binary, other, tmp_path / "other")
    assert proc.returncode == 0 and "Job finished" in proc.stdout, proc.stdout[-2000:]
    assert all(v[5] == 0.0 for _, pts, _ in _points(dat) for v in pts.values())


#: an edge-slope table for the two-state block (flattening.edge_slope): shallow first edges
EDGE = (0.02, 0.03, 0.045, 0.06, 0.08, 0.1)


def _two_state(tmp_path, edge=None):
    """The example's block as the two-state model (with ``edge`` its edge-slope table):
    (params, its file)."""
    P = fl.FrictionParams.from_json(FLAT)
    flat = fl.Flattening(P.flattening.slope, model="limit-analysis", edge_slope=edge)
    P = P.replace(flattening=flat)
    path = tmp_path / "two.json"
    P.to_json(path)
    return P, path


def _replay_two(run, P):
    """The largest misses of each point's STATEV(5) and STATEV(6) against the runtime's update
    (``P``: a one-law two-state file, or a ZonedLaw with ``zone``) of one of its face's previous
    states, and how many point states have a turned slope."""
    law, zone = P if isinstance(P, tuple) else (fl.SBMFLaw(P), None)
    slope0 = (law.laws[zone] if zone is not None else law).params.flattening.slope
    prev_pts, prev_peeq = {}, {}
    worst_a = worst_s = 0.0
    turned = 0
    for _, pts, peeq in run:
        faces, old = {}, {}
        for k in pts:
            faces.setdefault(k[:2], []).append(k)
        for k in prev_pts:
            old.setdefault(k[:2], []).append(prev_pts[k])
        for face, keys in faces.items():
            n = len(keys)
            p = np.array([pts[k][0] for k in keys]) * 1e6
            got = np.array([[pts[k][5], pts[k][6]] for k in keys])
            de = np.full(n, peeq.get(face[0], 0.0) - prev_peeq.get(face[0], 0.0))
            best = np.full((n, 2), np.inf)
            for row in old.get(face, [(0.0,) * 7]):
                st = fl.HistoryState(
                    p_hist=np.full(n, row[1] * 1e6),
                    alpha_f=np.full(n, row[5]),
                    slope_f=np.full(n, row[6]),
                )
                kw = {} if zone is None else {"zone": np.full(n, zone)}
                fl.traction_update(law, p, np.ones(n), np.zeros(n), 1e30, st, d_eps=de, **kw)
                miss = np.abs(np.column_stack([st.alpha_f_trial, st.slope_f_trial]) - got)
                pick = miss.sum(axis=1) < best.sum(axis=1)
                best[pick] = miss[pick]
            on = p > 0
            worst_a = max(worst_a, float(best[on, 0].max(initial=0.0)))
            worst_s = max(worst_s, float(best[on, 1].max(initial=0.0)))
            moved = on & (got[:, 1] > 0) & (np.abs(got[:, 1] - slope0) > 1e-3)
            turned += int(np.sum(moved))
        prev_pts, prev_peeq = pts, peeq
    return worst_a, worst_s, turned


SIX = [LINES[0], "*FRICTION, USER, DEPVAR=6, PROPERTIES=1", "MM-T-S"]


@pytest.mark.parametrize("edge", [None, EDGE])
def test_the_two_state_model_flattens_in_ccx_as_the_runtime_replay(ccx_work, tmp_path, edge):
    """The example's block as the two-state model (limit-analysis), with its one slope and with
    an edge-slope table: ccx asks for DEPVAR = 6 (5 is refused while it reads the deck), and
    pressing the elastic-plastic block at every converged increment gives each contact point's
    STATEV(5) and STATEV(6) (the flattened fraction and the flank slope) as the runtime's update
    from one of its face's previous states with its slave element's PEEQ increment (1.2e-7 and
    6.3e-8 seen: ccx prints 7 digits)."""
    P, path = _two_state(tmp_path, edge)
    out = _export(tmp_path, path, "two")
    exe = _link(ccx_work, out / "sbmf_fric.f", out / "ccx")
    assert "*FRICTION, USER, DEPVAR=6, PROPERTIES=1" in (out / "README.md").read_text()
    few = [LINES[0], "*FRICTION, USER, DEPVAR=5, PROPERTIES=1", "MM-T-S"]
    proc, _ = _run(exe, plastic_block(PRESS, few), tmp_path / "few")
    assert proc.returncode != 0 and "USER needs DEPVAR" in proc.stdout and ">= 6" in proc.stdout
    proc, dat = _run(exe, _with_peeq(plastic_block(PRESS, SIX, static=INCREMENTS)), tmp_path / "r")
    assert proc.returncode == 0 and "Job finished" in proc.stdout, proc.stdout[-2000:]
    run = _points(dat)
    worst_a, worst_s, turned = _replay_two(run, P)
    assert worst_a < 1e-6 and worst_s < 1e-6, (worst_a, worst_s)
    assert turned > 100
    assert max(v[5] for v in run[-1][1].values()) > 0.9


def test_a_zoned_routine_with_a_two_state_zone_in_ccx(ccx_work, tmp_path):
    """``--zone SBMF=two-state file --zone OTHER=the one-state file``: the pressed block under
    the interaction SBMF grows both states as the zoned runtime's replay (1e-6), under OTHER
    the one-state zone grows the fraction as its one-law replay and leaves the slope at 0."""
    P, path = _two_state(tmp_path)
    out = tmp_path / "zoned"
    code = export_main(
        ["calculix", "--zone", f"SBMF={path}", "--zone", f"OTHER={FLAT}", "--out", str(out)]
        + ["--units", "mm-t-s", "--quiet"]
    )
    assert code == 0
    binary = _link(ccx_work, out / "sbmf_fric.f", out / "ccx")
    zl = fl.ZonedLaw(
        ("SBMF", "OTHER"), (fl.SBMFLaw(P), fl.SBMFLaw(fl.FrictionParams.from_json(FLAT)))
    )
    deck = _with_peeq(plastic_block(PRESS, SIX, static=INCREMENTS))
    proc, dat = _run(binary, deck, tmp_path / "sbmf")
    assert proc.returncode == 0 and "Job finished" in proc.stdout, proc.stdout[-2000:]
    worst_a, worst_s, turned = _replay_two(_points(dat), (zl, 0))
    assert worst_a < 1e-6 and worst_s < 1e-6 and turned > 100, (worst_a, worst_s, turned)
    other = deck.replace("NAME=SBMF", "NAME=OTHER").replace("INTERACTION=SBMF", "INTERACTION=OTHER")
    proc, dat = _run(binary, other, tmp_path / "other")
    assert proc.returncode == 0 and "Job finished" in proc.stdout, proc.stdout[-2000:]
    run = _points(dat)
    worst, grew = _replay_miss(run, fl.FrictionParams.from_json(FLAT))
    assert worst < 1e-6 and grew > 1000, (worst, grew)
    assert all(v[6] == 0.0 for _, pts, _ in run for v in pts.values())

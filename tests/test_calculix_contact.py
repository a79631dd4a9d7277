"""CalculiX with ``*FRICTION, USER``: face-to-face contact, output, restart, the routine's interface.

Real ccx runs of the patched build (see tests/test_calculix.py for the build and its fixtures):

- face-to-face contact (``TYPE=SURFACE TO SURFACE``): load, slide, unload, reload; every slave
  integration point's shear equals ``tau(p, p_hist)`` of the runtime (``frictionlaw.shear_limit``)
  with ``p_hist`` the routine's own state as ccx prints it (``*CONTACT PRINT, CSDV``);
- slip output: CDIS (``.dat``) and CSLIP (``.frd``) under USER equal the Coulomb deck's in full
  slip, node-to-surface and face-to-face;
- ``p_hist`` output: the printed state is the largest pressure each node carried in converged
  increments, also after a cut-back whose trial pressure was larger; the ``.frd`` block CSDV
  carries it;
- restart: a run restarted between the steps gives the uninterrupted run's output;
- the routine's interface: DEPVAR checked at input (``FRIC_DEPVAR``), Abaqus' ``STDB_ABQERR`` and
  ``XIT``, KSTEP, KINC, TIME and DTIME as ccx's increments, PNEWDT as a cut-back;
- the routine's guards: a deck that states no unit system or another one than the routine's
  (both directions) and an SI model under an mm-t-s routine stop ccx with the routine's message
  (exit 201; the SI model after the routine's cut-backs, on its converged pressure); a
  converged pressure beyond the calibrated range warns once (two threads). Automatic
  incrementation through iterates above 100 H, Debian's stock ccx on the documented deck and
  face-to-face history at several GPa: tests/test_calculix_runs.py.
"""

import json
import os
import re
import shutil
import subprocess

import numpy as np
import pytest
import test_calculix as base
from ccx_decks import SLAVE0, read_blocks, read_dat, two_blocks
from test_calculix import EXAMPLE, STEPS, _doc_lines, _link, _run, _run_ok

from frictionlaw import FrictionParams, shear_limit
from frictionlaw.export.cli import main as export_main

# the patched build and the exported routine (fixtures of tests/test_calculix.py)
ccx_work, export_dir, ccx = base.ccx_work, base.export_dir, base.ccx

F2F = "SURFACE TO SURFACE"
N2F = "NODE TO SURFACE"
COULOMB = ["*SURFACE INTERACTION, NAME=SI", "*FRICTION", "0.21, 1e5"]
#: Abaqus' FRIC argument list, for the wrappers below
_ARGS = """LM,TAU,DDTDDG,DDTDDP,DSLIP,SED,SFD,
     1 DDTDDT,PNEWDT,STATEV,DGAM,TAULM,PRESS,DPRESS,DDPDDH,SLIP,
     2 KSTEP,KINC,TIME,DTIME,NOEL,CINAME,SLNAME,MSNAME,NPT,NODE,
     3 NPATCH,COORDS,RCOORD,DROT,TEMP,PREDEF,NFDIR,MCRD,NPRED,
     4 NSTATV,CHRLNGTH,PROPS,NPROPS)"""
_WRAPPER = f"""
C     test wrapper: the generated routine (renamed SBMFFRIC), then the
C     test's lines
      SUBROUTINE FRIC({_ARGS}
      INCLUDE 'ABA_PARAM.INC'
      CHARACTER*80 CINAME,SLNAME,MSNAME
      CHARACTER*8 CHARV(2)
      DIMENSION TAU(NFDIR),DDTDDG(NFDIR,NFDIR),DDTDDP(NFDIR),
     1 DSLIP(NFDIR),DDTDDT(NFDIR,2),STATEV(*),DGAM(NFDIR),
     2 TAULM(NFDIR),SLIP(NFDIR),TIME(2),COORDS(MCRD),
     3 RCOORD(MCRD),DROT(2,2),TEMP(2),PREDEF(2,*),PROPS(NPROPS)
      DIMENSION INTV(4),REALV(4)
      SAVE IDONE,PTRIAL
      DATA IDONE /0/
      DATA PTRIAL /0.0D0/
      CALL SBMFFRIC({_ARGS}
{{body}}
      RETURN
      END
"""


def _wrapped(export_dir, ccx_work, folder, body, extra=""):
    """ccx linked with the generated routine behind a FRIC that runs ``body`` after it."""
    src = (export_dir / "sbmf_fric.f").read_text()
    assert src.count("      SUBROUTINE FRIC(") == 1
    folder.mkdir(parents=True, exist_ok=True)
    routine = folder / "wrapped_fric.f"
    routine.write_text(
        src.replace("      SUBROUTINE FRIC(", "      SUBROUTINE SBMFFRIC(")
        + _WRAPPER.format(body=body)
        + extra
    )
    return _link(ccx_work, routine, folder / "ccx")


def _sta(folder, job="job"):
    """ccx's .sta rows of converged increments: (step, increment, attempt, iterations, total
    time, step time, increment size); attempts that did not converge (``1U``) are left out."""
    rows = []
    for line in (folder / f"{job}.sta").read_text().splitlines()[2:]:
        parts = line.split()
        if len(parts) == 7 and parts[2].isdigit():
            rows.append(tuple(int(v) for v in parts[:4]) + tuple(float(v) for v in parts[4:]))
    return rows


def _frd_blocks(path, name):
    """Node values of every ``.frd`` result block ``name``: a list of ``{node: values}``."""
    out = []
    cur = None
    for line in path.read_text().splitlines():
        if line.startswith(" -4  "):
            cur = {} if line[5:13].strip() == name else None
            if cur is not None:
                out.append(cur)
        elif cur is not None and line.startswith(" -1"):
            body = line[13:]
            cur[int(line[3:13])] = tuple(
                float(body[i : i + 12]) for i in range(0, len(body) - 11, 12)
            )
        elif line.startswith(" -3"):
            cur = None
    return out


def _points(block, kind):
    """(keys, p, |tau|, sdv) of one output time: per slave node or integration point."""
    stress = np.array(block["stress"])
    sdv = np.array(block["sdv"])
    k = 1 if kind == N2F else 2  # face-to-face rows start with element, face
    assert len(stress) == len(sdv) > 0
    np.testing.assert_array_equal(stress[:, :k], sdv[:, :k])  # the same points, in order
    return (
        sdv[:, : k + (kind == F2F)],
        stress[:, k],
        np.hypot(stress[:, k + 1], stress[:, k + 2]),
        sdv[:, k + (kind == F2F) :],
    )


# --- face-to-face contact -------------------------------------------------------------------


@pytest.fixture(scope="module")
def f2f_slide(ccx, tmp_path_factory):
    folder = tmp_path_factory.mktemp("f2f")
    deck = two_blocks(STEPS, _doc_lines(), contact=F2F, contact_print=("CSTR", "CDIS", "CSDV"))
    _run_ok(ccx, deck, folder)
    return folder


def test_face_to_face_every_point_has_the_runtime_shear(f2f_slide):
    """Load, slide, unload, reload: each sliding point's shear is tau(p, p_hist) of the runtime.

    p_hist is the routine's STATEV(1) as ccx prints it (CSDV); at the end of an increment it is
    max(p_hist at its start, p), and tau(p, max(p_hist, p)) = tau(p, p_hist) for the law.
    Measured: within 6e-7 (the 7 digits ccx prints) at every point and time from full slip on
    (t >= 1.2, 24 output times): 13,364 point-times below their p_hist, 2,978 on first loading.
    """
    params = FrictionParams.from_json(EXAMPLE)
    n_below = n_first = 0
    for t, block in read_blocks(f2f_slide / "job.dat"):
        _, p, tau, sdv = _points(block, F2F)
        p_hist = sdv[:, 0]
        assert (p_hist >= p * (1 - 1e-6)).all()  # the history holds the current pressure
        assert (sdv[:, 2] == 2.0).all() or t < 1.2  # status: every point slides from t = 1.2
        if t < 1.2:
            continue
        law = shear_limit(p * 1e6, p_hist * 1e6, params) / 1e6
        rel = np.abs(tau - law) / law
        assert rel.max() < 2e-6, (t, rel.max())
        below = p < p_hist * (1 - 1e-4)
        n_below += int(below.sum())
        n_first += int((~below).sum())
        if below.any():
            # below p_hist the law is Eq. 25: first loading would be far off for some points
            first = shear_limit(p[below] * 1e6, 0.0, params) / 1e6
            assert (np.abs(first - tau[below]) / tau[below]).max() > 0.05
    assert n_below > 5000 and n_first > 2000, (n_below, n_first)


def test_face_to_face_unloading_keeps_p_hist(f2f_slide):
    """After unloading (t = 3) every point's p_hist is above its pressure: the state survived
    the new point layouts of each increment and the points that left contact."""
    blocks = dict(read_blocks(f2f_slide / "job.dat"))
    _, p, _, sdv = _points(blocks[3.0], F2F)
    assert (sdv[:, 0] > p).all()
    _, p_load, _, _ = _points(blocks[2.0], F2F)
    # p_hist is bounded by the pressures points carried before
    assert sdv[:, 0].max() <= p_load.max() * 1.05 + 1.0


@pytest.mark.parametrize("kind", [N2F, F2F], ids=["node-to-surface", "face-to-face"])
def test_lift_off_keeps_p_hist(ccx, kind, tmp_path):
    """Press to 400 MPa and slide, lift the block off (no contact at all), press it back by a
    prescribed displacement while sliding: p_hist survives the open contact (node-to-surface:
    each node's value before the lift-off) and every point reloads below it on Eq. 25."""
    steps = [(400.0, 0.0), (400.0, 0.1), (0.0, 0.1, {"uz": 0.05}), (0.0, 0.2, {"uz": -0.004})]
    deck = two_blocks(steps, _doc_lines(), contact=kind, contact_print=("CSTR", "CSDV"))
    blocks = dict(read_blocks(_run_ok(ccx, deck, tmp_path)))
    assert not blocks[3.0].get("stress")  # open: no contact element at all
    keys, p, tau, sdv = _points(blocks[4.0], kind)
    p_hist = sdv[:, 0]
    assert (p < 0.8 * p_hist).all() and p.max() > 100.0
    params = FrictionParams.from_json(EXAMPLE)
    law = shear_limit(p * 1e6, p_hist * 1e6, params) / 1e6
    assert (np.abs(tau - law) <= 2e-6 * law + 1e-5).all()
    first = shear_limit(p * 1e6, 0.0, params) / 1e6
    assert (np.abs(first - tau) / tau).max() > 0.3  # first loading would be far off
    if kind == N2F:
        before = {int(r[0]): r[1] for r in blocks[2.0]["sdv"]}
        for node, ph in zip(keys[:, 0].astype(int), p_hist, strict=True):
            assert ph == before[node]


# --- slip output (CDIS, CSLIP) ---------------------------------------------------------------


@pytest.mark.parametrize("kind", [N2F, F2F], ids=["node-to-surface", "face-to-face"])
def test_slip_output_matches_coulomb_in_full_slip(ccx, ccx_work, kind, tmp_path):
    """CDIS's tangential slip under USER equals the Coulomb deck's (mu = 0.21, the law's
    tau_max C1/H) when every point slides; CSLIP1 in the .frd equals CDIS (node-to-surface).

    The slip is about 0.19 mm of the 0.2 mm the top moved. The two laws put different shear on
    the block's edges (the law caps it at tau_max = 85.5 MPa, Coulomb gives 0.21 p, up to
    150 MPa), so the block shears differently: measured 1.2 % at most per node
    (node-to-surface) and 1.4 % on the mean over the points (face-to-face). Before the patch put
    its slip after CalculiX's Coulomb lines, CDIS printed 0.
    """
    steps = [(400.0, 0.0), (400.0, 0.2)]
    keys = dict(contact=kind, contact_print=("CDIS", "CSTR"), contact_file=("CDIS", "CSTR"))
    user = _run_ok(ccx, two_blocks(steps, _doc_lines(), **keys), tmp_path / "user")
    ref = _run_ok(ccx_work / "ccx_reference", two_blocks(steps, COULOMB, **keys), tmp_path / "ref")
    (_, bu), (_, br) = read_blocks(user)[-1], read_blocks(ref)[-1]
    assert read_blocks(user)[-1][0] == 2.0
    du, dr = np.array(bu["disp"]), np.array(br["disp"])
    k = 1 if kind == N2F else 2
    slip_u, slip_r = du[:, k + 1], dr[:, k + 1]
    assert slip_r.min() > 0.15 and np.abs(dr[:, k + 2]).max() < 0.02
    if kind == N2F:
        np.testing.assert_array_equal(du[:, 0], dr[:, 0])
        assert np.abs(slip_u - slip_r).max() < 0.03 * slip_r.max()
        cont = _frd_blocks(user.with_suffix(".frd"), "CONTACT")[-1]
        frd_slip = np.array([cont[int(n)][1] for n in du[:, 0]])
        np.testing.assert_allclose(frd_slip, slip_u, rtol=1e-4)
    else:
        assert abs(slip_u.mean() - slip_r.mean()) < 0.03 * slip_r.mean()
        assert slip_u.min() > 0.15


# --- p_hist in the output (CSDV) -------------------------------------------------------------


def test_printed_p_hist_is_the_largest_converged_pressure(ccx, tmp_path):
    """Node-to-surface: CSDV's p_hist = each node's largest printed pressure so far, at every
    output time (every increment is printed), through unloading and reloading; the .frd block
    CSDV carries the same values."""
    deck = two_blocks(STEPS, _doc_lines(), contact_print=("CSTR", "CSDV"), contact_file=("CSDV",))
    dat = _run_ok(ccx, deck, tmp_path)
    p_max = {}
    n_below = 0
    for _, block in read_blocks(dat):
        keys, p, _, sdv = _points(block, N2F)
        for node, pi, ph in zip(keys[:, 0].astype(int), p, sdv[:, 0], strict=True):
            p_max[node] = max(p_max.get(node, 0.0), pi)
            assert abs(ph - p_max[node]) <= 1e-6 * p_max[node], (node, ph, p_max[node])
            n_below += pi < 0.9 * ph
    assert n_below > 100  # unloading and reloading below p_hist happened
    frd = _frd_blocks(dat.with_suffix(".frd"), "CSDV")
    assert len(frd) == len(read_blocks(dat))
    last = read_blocks(dat)[-1][1]["sdv"]
    for row in last:
        np.testing.assert_allclose(frd[-1][int(row[0])], row[1:], rtol=2e-5)


@pytest.mark.parametrize("kind", [N2F, F2F], ids=["node-to-surface", "face-to-face"])
def test_a_cut_back_discards_the_trial_p_hist(export_dir, ccx_work, kind, tmp_path):
    """A load peak (400 -> 600 -> 400 MPa while sliding) reached by a first attempt that the
    routine rejects (PNEWDT = 0.3): the retried increments never land on the peak, so the
    trial pressures exceed every converged one. The printed p_hist is the converged maximum
    (node-to-surface: per node, exactly), never the trial's; the shear stays tau(p, p_hist)."""
    body = """      IF (KSTEP.EQ.3 .AND. KINC.EQ.1) THEN
        IF (DTIME .GT. 0.4D0) THEN
          PTRIAL = MAX(PTRIAL, PRESS)
          PNEWDT = 0.3D0
        ELSE IF (IDONE .EQ. 0) THEN
          IDONE = 1
          REALV(1) = PTRIAL
          CALL STDB_ABQERR(1, 'trial maximum %R', INTV, REALV, CHARV)
        END IF
      END IF"""
    binary = _wrapped(export_dir, ccx_work, tmp_path / "bin", body)
    steps = [
        (400.0, 0.0),
        (400.0, 0.1),
        (400.0, 0.2, {"amplitude": "PEAK", "static": "0.5, 1.0, 1e-5, 0.5"}),
    ]
    amp = {"PEAK": [(0.0, 1.0), (0.5, 1.5), (1.0, 1.0)]}
    deck = two_blocks(
        steps, _doc_lines(), contact=kind, contact_print=("CSTR", "CSDV"), amplitudes=amp
    )
    proc, dat = _run(binary, deck, tmp_path / "run")
    assert proc.returncode == 0 and "Job finished" in proc.stdout, proc.stdout[-2000:]
    # the cut-back happened: step 3's first increment took a second attempt
    sta = _sta(tmp_path / "run")
    assert [r for r in sta if r[:2] == (3, 1)][0][2] == 2
    assert "through pnewdt" in proc.stdout
    trial = float(re.search(r"trial maximum (\S+)", proc.stdout).group(1))
    blocks = read_blocks(dat)
    p_conv = max(float(np.max(_points(b, kind)[1])) for _, b in blocks)
    params = FrictionParams.from_json(EXAMPLE)
    _, p, tau, sdv = _points(blocks[-1][1], kind)
    assert trial > 1.02 * sdv[:, 0].max(), (trial, sdv[:, 0].max())
    assert sdv[:, 0].max() <= p_conv * (1 + 1e-6)
    law = shear_limit(p * 1e6, sdv[:, 0] * 1e6, params) / 1e6
    assert (np.abs(tau - law) / law).max() < 2e-6
    if kind == N2F:
        p_max = {}
        for _, b in blocks:
            keys, p, _, _ = _points(b, kind)
            for node, pi in zip(keys[:, 0].astype(int), p, strict=True):
                p_max[node] = max(p_max.get(node, 0.0), pi)
        keys, _, _, sdv = _points(blocks[-1][1], kind)
        for node, ph in zip(keys[:, 0].astype(int), sdv[:, 0], strict=True):
            assert abs(ph - p_max[node]) <= 1e-6 * p_max[node]


# --- restart ---------------------------------------------------------------------------------


@pytest.mark.parametrize("kind", [N2F, F2F], ids=["node-to-surface", "face-to-face"])
def test_restart_continues_the_state(ccx, kind, tmp_path):
    """Steps 1-2 with *RESTART, WRITE, then steps 3-5 from the restart file: the same output as
    the uninterrupted run (the routine's STATEV are part of xstate, which the restart file
    holds), bit for bit."""
    keys = dict(contact=kind, contact_print=("CSTR", "CSDV"))
    full = two_blocks(STEPS, _doc_lines(), **keys)
    starts = [m.start() for m in re.finditer(r"^\*STEP", full, flags=re.M)]
    first = full[: starts[2]].replace("*STEP", "*RESTART, WRITE, FREQUENCY=1\n*STEP", 1)
    ref = _run_ok(ccx, full, tmp_path / "full")
    folder = tmp_path / "restart"
    _run_ok(ccx, first, folder)
    shutil.copy(folder / "job.rout", folder / "second.rin")
    (folder / "second.inp").write_text("*RESTART, READ\n" + full[starts[2] :])
    env = dict(os.environ, OMP_NUM_THREADS="1", NUMBER_OF_CPUS="1")
    proc = subprocess.run(
        [str(ccx), "-i", "second"], cwd=folder, capture_output=True, text=True, timeout=300, env=env
    )
    assert proc.returncode == 0 and "Job finished" in proc.stdout, proc.stdout[-2000:]
    want = {t: b for t, b in read_blocks(ref) if t > 2.0}
    got = dict(read_blocks(folder / "second.dat"))
    assert sorted(got) == sorted(want) and len(got) > 10
    for t, block in got.items():
        for kind_ in ("forces", "stress", "sdv"):
            assert block[kind_] == want[t][kind_], (t, kind_)


# --- the routine's interface -----------------------------------------------------------------


@pytest.mark.parametrize(
    "friction, message",
    [
        ("*FRICTION, USER", "DEPVAR is missing or 0"),
        ("*FRICTION, USER, DEPVAR=0", "DEPVAR is missing or 0"),
    ],
    ids=["missing", "zero"],
)
def test_user_friction_without_depvar_stops_at_input(ccx, friction, message, tmp_path):
    deck = two_blocks(STEPS[:1], ["*SURFACE INTERACTION, NAME=SBMF", friction])
    proc, _ = _run(ccx, deck, tmp_path)
    assert proc.returncode != 0 and "Job finished" not in proc.stdout
    assert re.search(r"USER needs DEPVAR\s+>= 1", proc.stdout), proc.stdout[-1500:]
    assert message in proc.stdout


def test_a_routine_states_the_depvar_it_needs(export_dir, ccx_work, tmp_path):
    """FRIC_DEPVAR() beside FRIC replaces the patch's default of 1 (the generated routine
    defines it: 1): DEPVAR=2 is refused for a routine that needs 3, DEPVAR=3 runs."""
    src = (export_dir / "sbmf_fric.f").read_text()
    assert src.count("      FRIC_DEPVAR = 1\n") == 1
    routine = tmp_path / "fric3.f"
    routine.write_text(src.replace("      FRIC_DEPVAR = 1\n", "      FRIC_DEPVAR = 3\n"))
    binary = _link(ccx_work, routine, tmp_path / "ccx")
    short = [(400.0, 0.0, {"static": "0.5, 1.0, 1e-5, 0.5"})]
    friction = ["*FRICTION, USER, DEPVAR=2, PROPERTIES=1", "MM-T-S"]
    deck = two_blocks(short, ["*SURFACE INTERACTION, NAME=SBMF", *friction])
    proc, _ = _run(binary, deck, tmp_path / "two")
    assert proc.returncode != 0 and re.search(r"USER needs DEPVAR\s+>= 3", proc.stdout)
    assert "(DEPVAR=2 given)" in proc.stdout
    _run_ok(binary, deck.replace("DEPVAR=2", "DEPVAR=3"), tmp_path / "three")


_MESSAGES = """      IF (NODE.EQ.1001 .AND. KSTEP.EQ.1 .AND. KINC.EQ.1) THEN
        INTV(1) = NODE
        INTV(2) = NSTATV
        REALV(1) = 2.5D0
        CHARV(1) = 'SBMF'
        CALL STDB_ABQERR(1, 'node %I of %S: %R, %I states',
     1    INTV, REALV, CHARV)
        CALL STDB_ABQERR(-1, 'a warning at 100%', INTV, REALV, CHARV)
      END IF
      IF (KSTEP.EQ.1 .AND. KINC.EQ.3) THEN
        INTV(1) = KINC
        REALV(1) = PRESS
        {stop}
      END IF"""


@pytest.mark.parametrize(
    "stop, message",
    [
        (
            "CALL STDB_ABQERR(-3, 'stop in increment %I at %R MPa',\n     1    INTV, REALV, CHARV)",
            r"\*ERROR in a user routine: stop in increment 3 at \S+ MPa",
        ),
        ("CALL XIT", r"\*ERROR: a user routine called XIT"),
    ],
    ids=["stdb_abqerr", "xit"],
)
def test_abaqus_message_routines(export_dir, ccx_work, stop, message, tmp_path):
    """STDB_ABQERR substitutes %I, %R, %S in order; LOP 1 and -1 continue, LOP -3 and XIT stop
    with status 201 after the converged increments' output."""
    binary = _wrapped(export_dir, ccx_work, tmp_path / "bin", _MESSAGES.format(stop=stop))
    proc, dat = _run(binary, two_blocks(STEPS[:1], _doc_lines()), tmp_path / "run")
    assert proc.returncode == 201 and "Job finished" not in proc.stdout
    assert "*INFO in a user routine: node 1001 of SBMF: 2.5000000E+00, 3 states" in proc.stdout
    assert "*WARNING in a user routine: a warning at 100%" in proc.stdout
    assert re.search(message, proc.stdout), proc.stdout[-1500:]
    # increments 1 and 2 converged and were written; the run stopped in increment 3
    assert [t for t, _ in read_blocks(dat)] == [0.1, 0.2]


def test_kstep_kinc_time_dtime_and_pnewdt(export_dir, ccx_work, tmp_path):
    """KSTEP, KINC, TIME(1), TIME(2) and DTIME are ccx's step, increment, step and total time at
    the increment's start and its size (as in its .sta file); PNEWDT = 0.5 in step 2,
    increment 2 makes ccx retry it with half the size."""
    body = """      IF (NODE.EQ.1001) THEN
        INTV(1) = KSTEP
        INTV(2) = KINC
        REALV(1) = TIME(1)
        REALV(2) = TIME(2)
        REALV(3) = DTIME
        CALL STDB_ABQERR(1, 'clock %I %I %R %R %R', INTV, REALV, CHARV)
      END IF
      IF (KSTEP.EQ.2 .AND. KINC.EQ.2 .AND. DTIME.GT.0.075D0)
     1  PNEWDT = 0.5D0"""
    binary = _wrapped(export_dir, ccx_work, tmp_path / "bin", body)
    proc, _ = _run(binary, two_blocks(STEPS[:3], _doc_lines()), tmp_path / "run")
    assert proc.returncode == 0 and "Job finished" in proc.stdout, proc.stdout[-2000:]
    clock = {
        (int(a), int(b), round(float(c), 6), round(float(d), 6), round(float(e), 6))
        for a, b, c, d, e in re.findall(r"clock (\d+) (\d+) (\S+) (\S+) (\S+)", proc.stdout)
    }
    sta = _sta(tmp_path / "run")
    assert len(sta) > 12
    for step, inc, _, _, total, step_time, dt in sta:
        want = (step, inc, round(step_time - dt, 6), round(total - dt, 6), round(dt, 6))
        assert want in clock, want
    # the cut-back asked for: attempt 2 of step 2, increment 2, at half the size
    retry = [r for r in sta if r[:2] == (2, 2)]
    assert retry[0][2] == 2 and abs(retry[0][6] - 0.05) < 1e-9
    assert (2, 2, 0.1, 1.1, 0.1) in clock  # the rejected attempt
    assert "increment size decrease requested by a material user routine" in proc.stdout
    assert {c[0] for c in clock} == {1, 2, 3} and SLAVE0 == 1001


# --- the routine's guards (docs/fe_codes.md, "Guards") ---------------------------------------


def _export(tmp_path, name, params, units):
    """``frictionlaw-export calculix`` of ``params`` (a path) into ``tmp_path/name``."""
    out = tmp_path / name
    code = export_main(
        ["calculix", "--params", str(params), "--out", str(out), "--units", units, "--quiet"]
    )
    assert code == 0
    return out


@pytest.mark.parametrize(
    "friction, message",
    [
        (
            ["*FRICTION, USER, DEPVAR=3, PROPERTIES=1", "SI"],
            "SBMF friction: the deck states the unit system PROPS(1) = 1, but this routine was "
            "exported for mm-t-s (MPa, mm), PROPS(1) = 2",
        ),
        (
            ["*FRICTION, USER, DEPVAR=3"],
            "SBMF friction: the deck does not state its unit system; this routine was exported "
            "for mm-t-s (MPa, mm): set PROPS(1) = 2",
        ),
        (
            ["*FRICTION, USER, DEPVAR=3, PROPERTIES=2", "MM-T-S, 0.5"],
            "SBMF friction: the deck gives 2 properties, but the routine takes one, its unit "
            "system PROPS(1) = 2",
        ),
    ],
    ids=["contradicting", "unstated", "a property too many"],
)
def test_a_deck_that_does_not_state_the_routines_units_stops(ccx, friction, message, tmp_path):
    """The mm-t-s routine in a deck that states SI, or no unit system, or a leftover value beside
    the unit system's: ccx stops (exit 201) at the routine's first call, with its message."""
    deck = two_blocks(STEPS[:1], ["*SURFACE INTERACTION, NAME=SBMF", *friction])
    proc, _ = _run(ccx, deck, tmp_path)
    assert proc.returncode == 201 and "Job finished" not in proc.stdout
    assert f"*ERROR in a user routine: {message}" in proc.stdout, proc.stdout[-1500:]
    assert proc.stdout.count("*ERROR in a user routine:") == 1


def test_an_si_routine_in_an_mm_deck_stops(ccx_work, tmp_path):
    """The direction the pressure cannot show (an SI routine in an mm-t-s deck agrees with the
    law up to about 400 MPa): the deck's PROPERTIES value 2 against the routine's SI."""
    out = _export(tmp_path, "si", EXAMPLE, "SI")
    binary = _link(ccx_work, out / "sbmf_fric.f", tmp_path / "ccx")
    proc, _ = _run(binary, two_blocks(STEPS[:1], _doc_lines()), tmp_path / "run")
    assert proc.returncode == 201 and "Job finished" not in proc.stdout
    assert (
        "*ERROR in a user routine: SBMF friction: the deck states the unit system PROPS(1) = 2, "
        "but this routine was exported for SI (Pa, m), PROPS(1) = 1" in proc.stdout
    ), proc.stdout[-1500:]


def test_an_si_model_under_an_mm_routine_stops_on_its_pressure(ccx, tmp_path):
    """The same blocks in SI (m, Pa) under the mm-t-s routine, the deck wrongly naming
    mm-t-s: every iterate's pressure (in Pa) is far above 100 H = 80000 (MPa). The routine asks
    for cut-backs (PNEWDT = 0.25) until the increment is at most 1/32 of its size (three, to
    1/64), the increment then converges at pressures still above 100 H, and the next call stops
    ccx with the unit message naming that converged pressure."""
    deck = two_blocks(STEPS[:1], _doc_lines(), si=True)
    proc, _ = _run(ccx, deck, tmp_path)
    assert proc.returncode == 201 and "Job finished" not in proc.stdout
    m = re.search(
        r"\*ERROR in a user routine: SBMF friction: converged contact pressure \(p_hist, state "
        r"variable 1\) (\S+) MPa > 100 H = 80000 MPa: this routine was exported for mm-t-s "
        r"\(MPa, mm\) and the model looks SI \(Pa, m\)",
        proc.stdout,
    )
    assert m, proc.stdout[-1500:]
    assert float(m.group(1)) > 1e5  # a pressure in Pa
    assert proc.stdout.count("asks for a smaller increment: PNEWDT = 2.5") == 3
    sizes = [r[6] for r in _sta(tmp_path) if r[:2] == (1, 1)]  # the converged attempt
    assert sizes == [pytest.approx(0.1 / 64)]


def test_beyond_the_calibrated_range_ccx_warns_once(ccx_work, tmp_path):
    """The example law with a calibrated range up to 300 MPa, the blocks pressed to 400 and
    500 MPa on two threads: the run finishes, with one warning naming p_max, a converged
    pressure beyond it (a p_hist at the start of an increment, which ccx printed), and where
    the largest pressures are (p_hist)."""
    doc = json.loads(EXAMPLE.read_text())
    doc["calibrated_range"] = {"p_min": 10e6, "p_max": 300e6, "unit": "Pa"}
    params = tmp_path / "params.json"
    params.write_text(json.dumps(doc))
    out = _export(tmp_path, "ranged", params, "mm-t-s")
    binary = _link(ccx_work, out / "sbmf_fric.f", tmp_path / "ccx")
    deck = two_blocks(STEPS, _doc_lines(), contact_print=("CSTR", "CSDV"))
    proc, dat = _run(binary, deck, tmp_path / "run", threads=2)
    assert proc.returncode == 0 and "Job finished" in proc.stdout, proc.stdout[-2000:]
    warns = re.findall(r"\*WARNING in a user routine: (SBMF friction: .*)", proc.stdout)
    assert len(warns) == 1, warns
    m = re.fullmatch(
        r"SBMF friction: converged contact pressure \(p_hist at the start of an increment\) "
        r"(\S+) MPa is beyond the calibrated range \(p_max = 300 MPa\): the law is "
        r"extrapolated there. Written once per process; the largest pressure each contact point "
        r"carried is its p_hist \(state variable 1\)",
        warns[0],
    )
    assert m, warns[0]
    named = float(m.group(1))
    # a converged history: one of the p_hist ccx printed, beyond p_max
    printed = {row[1] for _, b in read_blocks(dat) for row in b["sdv"]}
    assert named > 300 and min(abs(named - v) for v in printed) <= 1e-5 * named
    # the run went on: the largest pressures printed reach beyond p_max
    p_top = max(max(v[0] for v in c.values()) for _, _, c in read_dat(dat))
    assert p_top > 400

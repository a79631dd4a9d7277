"""The guards of every generated routine, in every host's emulation (issue 32, items 1 and 4).

Every Fortran target checks, before it runs the law, what the deck gave it: enough state
variables, the unit system it states (the unit property, 1 SI, 2 mm-t-s) against the one the
routine was exported for, and that no pressure exceeds 100 H (then the deck's units are not
the routine's); a pressure beyond the calibrated range gives one warning per process. The
explicit hosts' routines check the increment's pressure (every increment commits); ``FRIC``
(Abaqus/Standard, CalculiX), called on Newton iterates, checks what has converged, the
committed ``p_hist``, and asks for a smaller increment (``PNEWDT``) where an iterate is above
100 H (issue 40; the harness emulates the cut-backs). How each host hears of it
(docs/fe_codes.md, "Guards"):

- Abaqus/Standard and CalculiX (``FRIC``): ``STDB_ABQERR`` with ``LOP = -3``, then ``XIT``;
  the warning with ``LOP = -1``. Abaqus/Explicit (``VFRIC``, ``VFRICTION``): ``XPLB_ABQERR``,
  ``XPLB_EXIT``.
- LS-DYNA (``usrfrc`` SMP and MPP, single and double precision): one message per kind and
  process to the terminal, d3hsp and messag units; the law is refused (no friction, history
  untouched) where a check fails.
- The host-neutral ``SBMF_FRICTION`` (LS-DYNA templates, ANSYS): the status ``IERR`` and the
  message text ``SBMF_MESSAGE`` gives for it.

Each library here is compiled fresh (the once-per-process flags live in it), and what passes
the guards still equals the runtime.
"""

import ctypes
import re
import threading

import numpy as np
import pytest
from default_params import DEFAULT

import frictionlaw as fl
import frictionlaw.export as exp
from frictionlaw.export import harness
from frictionlaw.export._law import guard_spec

pytestmark = pytest.mark.skipif(
    harness.gfortran() is None,
    reason="gfortran not installed (.ci/run installs it: apt-get install -y gfortran)",
)

P_MAX = 760e6
#: the default calibration's law with its calibrated range (p_max = 760 MPa)
RANGED = fl.FrictionParams(**DEFAULT, p_range=(10e6, P_MAX))
UNITS = exp.UNIT_SYSTEMS
ABAQUS = {"abaqus-fric": "DEPVAR", "calculix": "DEPVAR"}
EXPLICIT = {"abaqus-vfric": "DEPVAR (nStateVar)", "abaqus-vfriction": "DEPVAR (nStates)"}
LSDYNA = {"lsdyna-usrfrc": "NHV", "lsdyna-usrfrc-mpp": "NH"}
NEUTRAL = ("lsdyna", "ansys-userfric")
#: the drop-in routines (every target but the host-neutral entry), with host precision
DROP_IN = [(t, "DP") for t in (*ABAQUS, *EXPLICIT, *LSDYNA)] + [(t, "SP") for t in LSDYNA]
#: the unit property's name per target, as the messages and the README name it
UNIT_INPUT = {
    "abaqus-fric": "PROPS(1)",
    "calculix": "PROPS(1)",
    "abaqus-vfric": "props(1)",
    "abaqus-vfriction": "props(1)",
    "lsdyna-usrfrc": "UA(1)",
    "lsdyna-usrfrc-mpp": "UC(1)",
    "lsdyna": "IUNIT",
    "ansys-userfric": "IUNIT",
}


@pytest.fixture(scope="module")
def params_files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("guards")
    out = {}
    for key, params in (("ranged", RANGED), ("plain", fl.FrictionParams(**DEFAULT))):
        out[key] = folder / f"params_{key}.json"
        params.to_json(out[key])
    return out


def fresh(tmp_path, params_file, target, units, prec="DP", flags=("-O2",)):
    """A newly compiled library of ``target`` (its once-per-process flags unset)."""
    files, _ = exp.render(target, params_file, units=units)
    src = {n: t for n, t in files.items() if n.endswith(".f")}
    name = re.sub(r"[^a-z0-9]", "_", f"g_{target}_{units}_{prec}".lower())
    options = {}
    if target in LSDYNA:
        flags = (*flags, *harness.HOST_PRECISION_FLAGS[prec])
        options["dtype"] = np.float32 if prec == "SP" else np.float64
    host, _ = exp.target(target).harness.load(
        src, tmp_path / name, name=name, flags=flags, **options
    )
    return host


def drive(target, host, p, p_hist=None, nsv=3):
    """Call the routine as its host does at pressures ``p`` (host units, slipping far).

    Returns ``(shear, p_hist out)`` per point in host units (NaN where the host's error exit
    ended the call before the point).
    """
    n = p.size
    ph = np.zeros(n) if p_hist is None else np.asarray(p_hist, float)
    if target in ABAQUS:
        sv = np.zeros((n, nsv))
        sv[:, : min(nsv, 1)] = ph[:, None][:, : min(nsv, 1)]
        out = host(p, np.full((n, 1), 1e3), np.zeros((n, 1)), sv, 1e-3)
        return np.abs(out["tau"][:, 0]), out["statev"][:, 0] if nsv else np.full(n, np.nan)
    if target in EXPLICIT:
        st = np.zeros((n, nsv))
        if nsv:
            st[:, 0] = ph
        if target == "abaqus-vfriction":
            st = np.ascontiguousarray(st[:, None, :])
        ft = host(p, np.full(n, 1e300), np.ones(n), st)
        return -ft[:, 0], st.reshape(n, nsv)[:, 0] if nsv else np.full(n, np.nan)
    if target in NEUTRAL:
        out = host(p, ph, np.zeros(n), np.full((n, 1), 1e3), np.zeros((n, 1)), 1e30)
        return np.abs(out["t"][:, 0]), out["p_hist"]
    dt = host.dtype
    if target == "lsdyna-usrfrc-mpp":
        uh = np.zeros((n, nsv), dt)
        if nsv:
            uh[:, 0] = ph
        mu = host(p.astype(dt), uh)
        return mu[:, 0].astype(float) * p, uh[:, 0].astype(float) if nsv else np.full(n, np.nan)
    fdat = np.zeros((n, 5), dt)
    fxyz = np.zeros((n, 3), dt)
    uf = np.zeros((n, nsv), dt)
    if nsv:
        uf[:, 0] = ph
    d = np.zeros((n, 3))
    d[:, 0] = 1e3
    rn = np.zeros((n, 3))
    rn[:, 2] = 1.0
    host(np.arange(n), np.arange(n), -p, np.ones(n), np.full(n, 1e30), 1.0, d, rn, fdat, fxyz, uf)
    return np.hypot(fdat[:, 2], fdat[:, 3]).astype(float), (
        uf[:, 0].astype(float) if nsv else np.full(n, np.nan)
    )


def messages(target, host):
    """``(errors, warnings, exits)`` the routine wrote since the last look: the error and the
    warning messages (their text), and how often it called the host's error exit."""
    if target in LSDYNA:
        lines = host.log()
        assert lines["tty"] == lines["d3hsp"] == lines["messag"]  # each unit gets it all
        errs = [x[len(" *** Error: ") :] for x in lines["tty"] if x.startswith(" *** Error: ")]
        warns = [x[len(" *** Warning: ") :] for x in lines["tty"] if x.startswith(" *** Warning")]
        return errs, warns, 0
    log = host.log()
    return [t for lop, t in log if lop == -3], [t for lop, t in log if lop == -1], host.exits()


# -- the deck's state variables -----------------------------------------------------------------
@pytest.mark.parametrize("target,prec", DROP_IN)
def test_too_few_state_variables_stop_or_refuse(tmp_path, params_files, target, prec):
    host = fresh(tmp_path, params_files["ranged"], target, "mm-t-s", prec)
    p = np.array([100.0, 300.0, 500.0])
    tau, _ = drive(target, host, p, nsv=0)
    errs, warns, exits = messages(target, host)
    name = {**ABAQUS, **EXPLICIT, **LSDYNA}[target]
    assert len(errs) == 1 and not warns
    assert errs[0].startswith(f"SBMF friction: {name}")
    assert "= 0, but the routine needs at least 1 state variable (1: p_hist)" in errs[0]
    if target in LSDYNA:  # no error exit documented: the law is refused, one message
        assert exits == 0 and np.all(tau == 0)
        tau, _ = drive(target, host, p, nsv=0)
        assert messages(target, host) == ([], [], 0) and np.all(tau == 0)  # not repeated
    else:  # the host's error exit ends the analysis at the first point
        assert exits == 1 and np.isnan(tau).all()


def test_fric_states_the_depvar_it_needs(tmp_path, params_files):
    """``FRIC_DEPVAR()`` beside FRIC (read by the CalculiX patch when ccx reads the deck)."""
    host = fresh(tmp_path, params_files["plain"], "calculix", "mm-t-s")
    fn = host._lib.fric_depvar_
    fn.restype = ctypes.c_int
    assert fn() == 1
    for target in ("abaqus-fric", "calculix"):
        src = exp.render(target, params_files["plain"])[0]["sbmf_fric.f"]
        assert "      INTEGER FUNCTION FRIC_DEPVAR()\n" in src


# -- the deck's unit system ---------------------------------------------------------------------
@pytest.mark.parametrize("units", ["SI", "mm-t-s"])
@pytest.mark.parametrize("target,prec", DROP_IN)
def test_the_deck_must_state_the_routines_unit_system(tmp_path, params_files, target, prec, units):
    us = UNITS[units]
    other = UNITS["SI" if units == "mm-t-s" else "mm-t-s"]
    host = fresh(tmp_path, params_files["plain"], target, units, prec)
    p = np.array([100e6, 300e6]) * us.stress  # plausible pressures in the routine's units
    name = UNIT_INPUT[target]
    # stated right: the law runs
    tau, ph = drive(target, host, p)
    assert messages(target, host) == ([], [], 0)
    want = fl.shear_limit(p / us.stress, 0.0, RANGED) * us.stress
    np.testing.assert_allclose(tau, want, rtol=1e-6)
    # not stated: stop (Abaqus, CalculiX) or refuse (LS-DYNA), naming the property and value
    for value, kind in ((None, 2), (other.code, 3), (3.5, 3)):
        host.deck_units = value
        tau, _ = drive(target, host, p)
        errs, _, exits = messages(target, host)
        if target in LSDYNA and value == 3.5:  # kind 3 again: LS-DYNA wrote it once already
            assert errs == [] and np.all(tau == 0)
            continue
        assert len(errs) == 1, (value, errs)
        msg = errs[0]
        assert f"this routine was exported for {us.describe()}" in msg
        assert f"{name} = {us.code}" in msg and "1 = SI (Pa, m), 2 = mm-t-s (MPa, mm)" in msg
        if kind == 3:
            shown = f"{value:.5E}" if value == 3.5 else str(value)
            assert f"the deck states the unit system {name} = {shown}, but" in msg, msg
        else:
            assert "the deck does not state its unit system" in msg
        if target in LSDYNA:
            assert exits == 0 and np.all(tau == 0)
        else:
            assert exits == 1 and np.isnan(tau).all()
    # FRIC (Abaqus, CalculiX): a property beside the unit system's (a leftover coefficient on
    # the *FRICTION, USER data line) is refused, not ignored
    if target in ("abaqus-fric", "calculix"):
        host.deck_units = (us.code, 0.5)
        tau, _ = drive(target, host, p)
        errs, _, exits = messages(target, host)
        assert exits == 1 and np.isnan(tau).all() and len(errs) == 1
        assert errs[0].startswith("SBMF friction: the deck gives 2 properties, but the routine ")
        assert f"takes one, its unit system {name} = {us.code}" in errs[0], errs[0]
        host.deck_units = us.code
    # LS-DYNA: one message per kind and process, however often it is called
    if target in LSDYNA:
        host.deck_units = other.code
        tau, _ = drive(target, host, p)
        assert messages(target, host) == ([], [], 0) and np.all(tau == 0)


@pytest.mark.parametrize("target,prec", DROP_IN)
def test_a_pressure_above_100_h_names_both_unit_systems(tmp_path, params_files, target, prec):
    """An mm-t-s routine in an SI deck: 300 MPa arrives as 3e8 'MPa' (the issue's case).

    The explicit hosts' routines see the increment's pressure; ``FRIC`` the committed
    ``p_hist`` (``STATEV(1)`` at the start of the increment), so it is driven with 3e8 as the
    converged history of the second point."""
    host = fresh(tmp_path, params_files["plain"], target, "mm-t-s", prec)
    p = np.array([50.0, 3e8, 100.0])
    committed = target in ABAQUS
    tau, ph = drive(target, host, p, p_hist=np.where(p > 1e6, p, 0.0) if committed else None)
    msgs, _, exits = messages(target, host)
    assert len(msgs) == 1
    what = (
        "converged contact pressure \\(p_hist, state variable 1\\)"
        if committed
        else "contact pressure"
    )
    assert re.fullmatch(
        rf"SBMF friction: {what} 3[.]00000E\+08 MPa > 100 H = 80000 MPa: this routine "
        r"was exported for mm-t-s \(MPa, mm\) and the model looks SI \(Pa, m\)",
        msgs[0],
    ), msgs[0]
    law = fl.shear_limit(np.array([50e6, 100e6]), 0.0, RANGED) / 1e6
    if target in LSDYNA:  # refused at that node only; the others run the law
        assert exits == 0 and tau[1] == 0 and ph[1] == 0
        np.testing.assert_allclose(tau[[0, 2]], law, rtol=1e-6)
    else:  # the analysis ends there: the third point is never called
        assert exits == 1 and np.isnan(tau[2])
        np.testing.assert_allclose(tau[0], law[0], rtol=1e-12)
    # an SI routine has no unit system beyond it: the message says the deck's is not Pa
    host = fresh(tmp_path, params_files["plain"], target, "SI", prec)
    drive(target, host, np.array([1e13]), p_hist=np.array([1e13]) if committed else None)
    msg = messages(target, host)[0][0]
    assert "> 100 H = 8e+10 Pa: this routine was exported for SI (Pa, m)" in msg
    assert "does not use Pa" in msg


# -- FRIC on Newton iterates: cut-backs (the harness emulates Abaqus' incrementation) ----------
def _increment(host, iterates, p_hist=0.0, kinc=1, dtime=1.0):
    """One emulated increment of ``FRIC`` at one point, sliding far, from ``p_hist``."""
    sv = np.array([[p_hist, 0.0, 0.0]])
    return host.increment(
        iterates, np.full((1, 2), 1e3), np.zeros((1, 2)), sv, 1e-3, kinc=kinc, dtime=dtime
    )


@pytest.mark.parametrize("target", ABAQUS)
def test_an_iterate_above_100_h_asks_for_a_smaller_increment(tmp_path, params_files, target):
    """A Newton iterate overshoots to 320 GPa at the increment's full size (the issue's case:
    iterates above 100 H, converged pressures of a few hundred MPa): FRIC returns
    ``PNEWDT = 0.25``, the host retries at a quarter, twice, and the increment converges at
    400 MPa with nothing written and the law's shear and history; the run goes on. An
    increment whose every pressure stays below 100 H is never cut back."""
    host = fresh(tmp_path, params_files["ranged"], target, "mm-t-s")
    p_end = 400.0

    def iterates(dtime):  # the overshoot shrinks with the increment, the converged state not
        return [np.array([p_end + 3.2e5 * dtime]), np.array([p_end])]

    inc = _increment(host, iterates)
    assert inc.converged and inc.exits == 0
    assert [a.dtime for a in inc.attempts] == [1.0, 0.25, 0.0625]
    assert [a.pnewdt for a in inc.attempts][:2] == [0.25, 0.25] and inc.attempts[2].pnewdt > 1
    assert inc.attempts[1].p_max > 80000 > inc.attempts[2].p_max
    assert messages(target, host) == ([], [], 0)
    assert inc.out["statev"][0, 0] == p_end  # the committed history is the converged pressure
    law = fl.shear_limit(p_end * 1e6, 0.0, RANGED) / 1e6
    np.testing.assert_allclose(np.hypot(*inc.out["tau"][0]), law, rtol=1e-12)
    # the next increment starts from it; below 100 H on every iterate: no cut-back
    inc = _increment(host, lambda dt: [np.array([7e4]), np.array([300.0])], p_end, kinc=2)
    assert inc.converged and len(inc.attempts) == 1 and inc.attempts[0].pnewdt > 1
    assert messages(target, host) == ([], [], 0) and inc.out["statev"][0, 0] == p_end


@pytest.mark.parametrize("target", ABAQUS)
def test_an_si_deck_stops_on_its_converged_pressure(tmp_path, params_files, target):
    """An SI model under the mm-t-s routine: its pressures are above 100 H on every iterate at
    any increment size. FRIC asks for cut-backs until the increment is 1/32 of its size or
    less (three, to 1/64), then asks no more (the host's own limit, five cut-backs, would end
    the run with the host's message): the increment converges at 4.7e6 'MPa', and the next
    increment's first call stops the run with the unit message naming that converged pressure.
    """
    host = fresh(tmp_path, params_files["plain"], target, "mm-t-s")

    def iterates(dtime):  # 300 MPa in Pa, ramped over the increment
        return [np.array([3e8 * dtime]), np.array([3e8 * dtime])]

    inc = _increment(host, iterates)
    assert inc.converged
    assert [a.dtime for a in inc.attempts] == [1.0, 0.25, 0.0625, 0.015625]
    assert messages(target, host) == ([], [], 0)
    p_conv = inc.out["statev"][0, 0]
    assert p_conv == 3e8 / 64
    inc = _increment(host, lambda dt: [np.array([3e8])], p_conv, kinc=2)
    assert not inc.converged and inc.exits == 1
    errs, _, _ = messages(target, host)
    assert errs == [
        "SBMF friction: converged contact pressure (p_hist, state variable 1) 4.68750E+06 MPa "
        "> 100 H = 80000 MPa: this routine was exported for mm-t-s (MPa, mm) and the model "
        "looks SI (Pa, m)"
    ]
    # each increment counts its own cut-backs: the floor is relative to its first overshoot
    inc = _increment(host, iterates, kinc=3, dtime=0.5)
    assert [a.dtime for a in inc.attempts] == [0.5, 0.125, 0.03125, 0.0078125]


# -- the calibrated range ---------------------------------------------------------------------
@pytest.mark.parametrize("units", ["SI", "mm-t-s"])
@pytest.mark.parametrize("target,prec", DROP_IN)
def test_beyond_the_calibrated_range_one_warning_per_process(
    tmp_path, params_files, target, prec, units
):
    """Four increments beyond the range: one warning, naming the first pressure beyond it.

    FRIC warns on the committed history (each increment starts from the last one's converged
    ``p_hist``): the pressure named is a converged one, one increment later."""
    s = UNITS[units].stress
    host = fresh(tmp_path, params_files["ranged"], target, units, prec)
    p_si = np.array([[500e6, 700e6], [800e6, 1200e6], [900e6, 1348e6], [600e6, 2000e6]])
    committed = np.zeros(2)
    for row in p_si:  # increments (cycles), each beyond the range
        tau, ph = drive(target, host, row * s, p_hist=committed)
        rtol = 1e-6 if prec == "SP" else 1e-12
        want = fl.shear_limit(row, committed / s, RANGED) * s
        np.testing.assert_allclose(tau, want, rtol=rtol)
        assert np.all(ph >= row * s * (1 - 3e-7))  # the history runs on
        committed = ph if target in ABAQUS else np.zeros(2)
    errs, warns, exits = messages(target, host)
    assert len(warns) == 1 and errs == [] and exits == 0, (errs, warns)
    unit = UNITS[units].stress_unit
    first = 800e6 * s  # the first pressure beyond p_max: the largest the process had seen
    shown = f"{first:.0f}" if first < 1e6 else f"{first:.5E}"
    seen = "converged contact pressure (p_hist at the start of an increment)"
    seen = seen if target in ABAQUS else "contact pressure"
    assert (
        f"{seen} {shown} {unit} is beyond the calibrated range "
        f"(p_max = {P_MAX * s:.6g} {unit}): the law is extrapolated there" in warns[0]
    ), warns[0]
    assert "once per process" in warns[0] and "p_hist (state variable 1)" in warns[0]


@pytest.mark.parametrize("target", ABAQUS)
def test_fric_warns_on_converged_pressures_only(tmp_path, params_files, target):
    """Iterates beyond p_max whose increment converges below it: no warning (the issue named an
    iterate's 760 MPa where the largest converged pressure was 470 MPa)."""
    host = fresh(tmp_path, params_files["ranged"], target, "SI")
    inc = _increment(host, lambda dt: [np.array([1.5e9]), np.array([470e6])])
    inc = _increment(host, lambda dt: [np.array([900e6]), np.array([300e6])], 470e6, kinc=2)
    assert inc.converged and inc.out["statev"][0, 0] == 470e6
    assert messages(target, host) == ([], [], 0)


@pytest.mark.parametrize("target,prec", DROP_IN[:4])
def test_no_range_recorded_no_warning(tmp_path, params_files, target, prec):
    """The shipped example has no calibrated range: nothing to warn about below 100 H."""
    host = fresh(tmp_path, params_files["plain"], target, "SI", prec)
    drive(target, host, np.array([5e9, 5e10]))
    assert messages(target, host) == ([], [], 0)


@pytest.mark.parametrize("target", ["abaqus-fric", "abaqus-vfriction", "lsdyna-usrfrc"])
def test_one_warning_from_threads_calling_at_once(tmp_path, params_files, target):
    """4 OS threads at once (the routine compiled with -fopenmp, as a threaded host builds it),
    every point beyond the range: one warning between them, 5 times over on fresh libraries."""
    for rep in range(5):
        flags = ("-O2", "-fopenmp")
        host = fresh(tmp_path / str(rep), params_files["ranged"], target, "SI", "DP", flags)
        p = np.full(4000, 1e9)
        barrier = threading.Barrier(4)
        chunks = np.array_split(np.arange(p.size), 4)

        def work(i, host=host, barrier=barrier, p=p, chunks=chunks):
            barrier.wait()  # FRIC warns on the committed history: p_hist = p
            drive(target, host, p[chunks[i]], p_hist=p[chunks[i]])

        threads = [threading.Thread(target=work, args=(i,)) for i in range(4)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        assert len(messages(target, host)[1]) == 1


# -- the host-neutral entry: a status ---------------------------------------------------------
@pytest.mark.parametrize("units", ["SI", "mm-t-s"])
@pytest.mark.parametrize("target", NEUTRAL)
def test_sbmf_friction_returns_the_guards_status(tmp_path, params_files, target, units):
    us = UNITS[units]
    s = us.stress
    host = fresh(tmp_path, params_files["ranged"], target, units)
    p = np.array([100e6, 800e6, 1348e6, 50e6, 1e3 * RANGED.H, -1.0]) * s

    def run(pp):
        z = np.zeros((pp.size, 1))
        return host(pp, z[:, 0], z[:, 0], np.full((pp.size, 1), 1e3), z, 1e30)

    out = run(p)
    # 5 once (the first beyond p_max in this process), -4 above 100 H, 0 elsewhere
    assert out["ierr"].tolist() == [0, 5, 0, 0, -4, 0]
    assert run(p)["ierr"].tolist() == [0, 0, 0, 0, -4, 0]
    # the outputs stay the law's (the caller stops on ierr < 0)
    want = fl.shear_limit(np.maximum(p / s, 0), 0.0, RANGED) * s
    np.testing.assert_allclose(np.abs(out["t"][:, 0]), want, rtol=1e-12)
    # a committed history above 100 H: -6 (before -4), naming it as converged
    ph = np.array([0.0, 1e3 * RANGED.H * s])
    z = np.zeros((2, 1))
    got = host(np.array([1e3, 1e3]) * s, ph, np.zeros(2), np.full((2, 1), 1e3), z, 1e30)
    assert got["ierr"].tolist() == [0, -6]
    assert "converged contact pressure (p_hist, state variable 1)" in host.message(6, ph[1])
    text = host.message(5, p[1])
    assert "is beyond the calibrated range" in text and "once per process" in text
    assert "this routine was exported for " + us.describe() in host.message(4, p[4])
    for value, code in ((None, -2), (3 - us.code, -3), (7, -3)):
        host.deck_units = value
        assert np.all(run(p)["ierr"] == code), value
    host.deck_units = 3 - us.code
    assert f"IUNIT = {3 - us.code}, but this routine was exported for {us.describe()}" in (
        host.message(3, 3 - us.code)
    )
    assert "does not state its unit system" in host.message(2)


def test_every_message_fits_the_hosts_limits(params_files):
    """Each message of each target fits the 400 characters of SBMF_MESSAGE's buffer (Abaqus'
    STDB_ABQERR takes up to 500), names the target's own fields, and no line passes column 72."""
    for target in exp.TARGETS:
        record = exp.target(target)
        if not isinstance(record.form, exp.Routine):
            continue
        for units in UNITS:
            us = UNITS[units]
            guard = guard_spec(RANGED, us)
            form = record.form
            msgs = guard.messages(form.state_name, form.units_input, form.implicit)
            for before, after in msgs.values():
                assert len(before) + len(after or "") + 24 <= 400
            assert record.form.units_input[0] == UNIT_INPUT[target]
            files, _ = exp.render(target, params_files["ranged"], units=units)
            src = files[record.file]
            assert "SUBROUTINE SBMF_MESSAGE(" in src and "FUNCTION SBMF_ONCE(" in src

"""Thread safety of every generated Fortran routine.

Abaqus (threads), LS-DYNA SMP and ANSYS call user routines from several threads at once. Each
Fortran target is compiled with ``-fopenmp`` (as a threaded host builds user code) and called
concurrently from 4 OS threads (ctypes releases the GIL during the call) over disjoint node sets
of shared arrays, many times; every result must equal the serial run bit for bit. A static check
rejects any SAVE, COMMON, DATA, EQUIVALENCE or initialised declaration (implicitly SAVEd) in the
generated sources: the routines keep no state of their own between calls, but for the guards'
once-per-process flags in ``SBMF_ONCE`` and, in ``FRIC``'s file, the record of the increment's
first iterate above 100 H in ``SBMF_CUTS`` (docs/fe_codes.md, "Guards"), which are read and
written only with OpenMP atomics (checked here; one warning from 4 threads at once:
tests/test_export_guards.py). Both reload forms:
the static check on each (the tabulated form's table is PARAMETER arrays), the concurrent calls
on the tabulated form for FRIC, VFRICTION and the single-precision ``usrfrc``.
"""

import re
import threading

import numpy as np
import pytest
from test_export_fortran import PARAM_SETS

import frictionlaw.export as exp
from frictionlaw.export import harness

pytestmark = pytest.mark.skipif(
    harness.gfortran() is None,
    reason="gfortran not installed (.ci/run installs it: apt-get install -y gfortran)",
)

# "calculix" writes the abaqus-fric routine unchanged (checked in test_calculix.py, where ccx
# calls it from its own threads)
FORTRAN_TARGETS = [t for t in exp.TARGETS if not t.endswith("-table") and t != "calculix"]
N_THREADS = 4
N_REPEAT = 25
N_NODES = 4 * 2000


def _code_lines(text):
    """Non-comment statements of a fixed-form source (comments: C, c, * or ! in column 1)."""
    out = []
    for line in text.splitlines():
        if not line or line[0] in "Cc*!":
            continue
        out.append(line.split("!")[0])
    return out


_STATIC = [
    (re.compile(r"^\s*SAVE\b|\bSAVE\s*$|\bSAVE\s*/", re.I), "SAVE"),
    (re.compile(r"\bCOMMON\s*/", re.I), "COMMON"),
    (re.compile(r"^\s*DATA\b", re.I), "DATA"),
    (re.compile(r"\bEQUIVALENCE\b", re.I), "EQUIVALENCE"),
    # F90 declaration with an initial value (implies SAVE), unless it is a PARAMETER
    (re.compile(r"^(?!.*\bPARAMETER\b).*::[^=]*=(?!=)", re.I), "initialised declaration"),
    # old-style initial value in a type declaration: REAL X /1.0/
    (
        re.compile(r"^\s*(INTEGER|REAL|DOUBLE\s+PRECISION|LOGICAL|CHARACTER)\b[^=]*/[^/]+/", re.I),
        "initialised declaration",
    ),
    (re.compile(r"\bSAVE\b", re.I), "SAVE"),
]


def static_storage(text):
    """Statements that give a local static storage: ``[(line, kind), ...]``."""
    bad = []
    for line in _code_lines(text):
        for rx, kind in _STATIC:
            if rx.search(line):
                bad.append((line.strip(), kind))
                break
    return bad


#: the functions with static storage: the guards' once-per-process flags (every target) and
#: FRIC's record of the increment's first iterate above 100 H
_GUARDED = re.compile(
    r"^      (?:INTEGER|DOUBLE PRECISION) FUNCTION (SBMF_ONCE|SBMF_CUTS)\(.*?\)\n(.*?)^      END\n",
    re.M | re.S,
)


def guarded_functions(text):
    """``(text without SBMF_ONCE and SBMF_CUTS, {name: body})``."""
    bodies = {m.group(1): m.group(2) for m in _GUARDED.finditer(text)}
    return _GUARDED.sub("", text), bodies


def once_flags(text):
    """``(text without SBMF_ONCE, SBMF_ONCE's body)``; the body is None if there is none."""
    rest, bodies = guarded_functions(text)
    return rest, bodies.get("SBMF_ONCE")


def atomic_only(body):
    """The statements of ``body`` that touch its SAVEd variables outside an OpenMP atomic."""
    lines = body.splitlines()
    names = re.findall(r"SAVE :: (\w+)", body)
    bad = []
    for i, line in enumerate(lines):
        if line[:1] in "Cc*!" or "SAVE ::" in line:
            continue
        if not any(re.search(rf"\b{n}\b", line) for n in names):
            continue
        prev = [x for x in lines[:i] if x.strip()][-1]
        in_capture = prev.startswith("!$OMP ATOMIC CAPTURE") or (
            lines[i - 2].startswith("!$OMP ATOMIC CAPTURE") and lines[i + 1] == "!$OMP END ATOMIC"
        )
        if not (prev.startswith(("!$OMP ATOMIC READ", "!$OMP ATOMIC WRITE")) or in_capture):
            bad.append(line.strip())
    return bad


#: the k_t table's, the reload table's and the first-loading table's PARAMETER arrays are checked
#: too
KEYS = ("soft", "tab_flat", "first_bump")


@pytest.fixture(scope="module")
def params_files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("thr")
    for key in KEYS:
        PARAM_SETS[key].to_json(folder / f"params_{key}.json")
    return {key: folder / f"params_{key}.json" for key in KEYS}


@pytest.mark.parametrize("key", KEYS)
@pytest.mark.parametrize("target", FORTRAN_TARGETS)
def test_generated_sources_have_no_static_storage(params_files, target, key):
    for k_t in (None, 5e12):
        files, _ = exp.render(target, params_files[key], k_t=k_t)
        for name, text in files.items():
            if name.endswith(".f"):
                rest, bodies = guarded_functions(text)
                assert static_storage(rest) == [], f"{target}/{name}"
                # the guards' flags: one SAVEd array, touched only under OpenMP atomics; FRIC's
                # SBMF_CUTS: two SAVEd scalars, the same way
                want = {"SBMF_ONCE", "SBMF_CUTS"} if target == "abaqus-fric" else {"SBMF_ONCE"}
                assert set(bodies) == want
                for body in bodies.values():
                    assert atomic_only(body) == []
                    kinds = {kind for _, kind in static_storage(body)}
                    assert kinds == {"initialised declaration"}


def test_atomic_check_finds_a_plain_access():
    """The atomic check itself: the generated SBMF_ONCE passes, one without its directives not."""
    body = """      INTEGER K, N
      INTEGER, SAVE :: FLAGS(5) = 0
!$OMP ATOMIC READ
      N = FLAGS(K)
      IF (N .EQ. 0) THEN
!$OMP ATOMIC CAPTURE
        N = FLAGS(K)
        FLAGS(K) = 1
!$OMP END ATOMIC
      END IF
"""
    assert atomic_only(body) == []
    assert atomic_only(body.replace("!$OMP ATOMIC READ\n", "")) == ["N = FLAGS(K)"]
    plain = body.replace("!$OMP ATOMIC CAPTURE\n", "").replace("!$OMP END ATOMIC\n", "")
    assert atomic_only(plain) == ["N = FLAGS(K)", "FLAGS(K) = 1"]


def test_atomic_check_finds_a_plain_access_in_sbmf_cuts(params_files):
    """FRIC's SBMF_CUTS passes; without its atomic writes its two stores are found."""
    text = exp.render("abaqus-fric", params_files["soft"])[0]["sbmf_fric.f"]
    body = guarded_functions(text)[1]["SBMF_CUTS"]
    assert atomic_only(body) == []
    plain = body.replace("!$OMP ATOMIC WRITE SEQ_CST\n", "")
    assert atomic_only(plain) == ["SBMFCD = DTIME", "SBMFCK = KEY"]


def test_static_check_finds_static_storage():
    """The check itself: each kind of static local is found, PARAMETERs are not."""
    ok = (
        "      DOUBLE PRECISION X\n      PARAMETER (X = 1.0D0)\n      INTEGER, PARAMETER :: N = 3\n"
    )
    assert static_storage(ok) == []
    for bad in (
        "      SAVE\n",
        "      SAVE X\n",
        "      COMMON /BLK/ X\n",
        "      DATA X /1.0D0/\n",
        "      INTEGER :: ICALL = 0\n",
        "      REAL X /1.0/\n",
        "      EQUIVALENCE (X, Y)\n",
    ):
        assert static_storage(ok + bad) != [], bad
    assert static_storage("C     SAVE in a comment\n") == []


# -- concurrent calls ---------------------------------------------------------------------------
def _inputs(target, params, rng, n):
    """Random host inputs (open points, Eq. 24 and 25 branches, stick and slip)."""
    H = params.H
    ph = np.where(rng.random(n) < 0.5, 10.0 ** rng.uniform(np.log10(H) - 2, np.log10(H) + 1, n), 0)
    p = 10.0 ** rng.uniform(np.log10(H) - 3, np.log10(H) + 1.9, n)  # below 100 H: the guards
    p = np.where(rng.random(n) < 0.3, ph * rng.random(n), p)
    p = np.where(rng.random(n) < 0.1, -1.0, p)
    kt = 10.0 ** rng.uniform(11, 14, n)
    return ph, p, kt


def _run(target, lib, params, rng, chunks):
    """Call ``lib`` once per chunk (disjoint node sets); returns a function doing chunk ``c``
    and a function collecting the outputs, for shared input/outputs made here."""
    n = N_NODES
    ph, p, kt = _inputs(target, params, rng, n)
    tmax = params.tau_max
    if target == "abaqus-fric":
        dgam = rng.normal(size=(n, 2)) * (tmax / 1e13) * 10.0 ** rng.uniform(-2, 1, (n, 1))
        tau0 = rng.normal(size=(n, 2)) * tmax * 0.1
        sv = np.stack([ph, np.zeros(n), np.zeros(n)], 1)
        chr_ = 10.0 ** rng.uniform(-4, -2, n)
        res = [None] * len(chunks)

        def call(c):
            i = chunks[c]
            res[c] = lib(p[i], dgam[i], tau0[i], sv[i], chr_[i])

        def collect():
            return {k: np.concatenate([r[k] for r in res]) for k in res[0]}

        return call, collect
    if target in ("abaqus-vfric", "abaqus-vfriction"):
        area = 10.0 ** rng.uniform(-8, -4, n)
        fn = p * area
        fst = tmax * area * 10.0 ** rng.uniform(-2, 1, n)
        if target == "abaqus-vfric":
            st0 = np.stack([ph, np.zeros(n), np.zeros(n)], 1)
        else:
            st0 = np.stack([ph, np.zeros(n), np.zeros(n)], 1)[:, None, :].repeat(2, 1)
        st = [np.ascontiguousarray(st0[i]) for i in chunks]
        res = [None] * len(chunks)

        def call(c):
            i = chunks[c]
            res[c] = lib(fn[i], fst[i], area[i], st[c])

        def collect():
            return {"f": np.concatenate(res), "state": np.concatenate(st)}

        return call, collect
    if target in ("lsdyna", "ansys-userfric"):
        du = rng.normal(size=(n, 2)) * (tmax / kt[:, None]) * 10.0 ** rng.uniform(-2, 1, (n, 1))
        told = rng.normal(size=(n, 2)) * tmax * 0.1
        res = [None] * len(chunks)

        def call(c):
            i = chunks[c]
            res[c] = lib(p[i], ph[i], np.zeros(i.size), du[i], told[i], kt[i])

        def collect():
            return {k: np.concatenate([r[k] for r in res]) for k in res[0]}

        return call, collect
    dt = lib.dtype
    if target == "lsdyna-usrfrc-mpp":
        uh = [np.ascontiguousarray(np.stack([ph, np.zeros(n)], 1)[i].astype(dt)) for i in chunks]
        res = [None] * len(chunks)

        def call(c):
            res[c] = lib(p[chunks[c]].astype(dt), uh[c])

        def collect():
            return {"mu": np.concatenate(res), "uh": np.concatenate(uh)}

        return call, collect
    # lsdyna-usrfrc: the threads share LS-DYNA's arrays, each with its own active slave nodes
    area = 10.0 ** rng.uniform(-8, -4, n)
    ilbsv = rng.permutation(n)
    fni = (-p * area).astype(dt)
    stfk = (kt * area).astype(dt)
    nrm = rng.normal(size=(n, 3))
    rn = (nrm / np.linalg.norm(nrm, axis=1, keepdims=True)).astype(dt)
    d = rng.normal(size=(n, 3)) * (tmax / kt[:, None]) * 10.0 ** rng.uniform(-2, 1, (n, 1))
    d = d.astype(dt)
    fdat = np.zeros((n, 5), dt)
    fdat[:, 2:] = (rng.normal(size=(n, 3)) * tmax * 0.1 * area[:, None]).astype(dt)
    fxyz = rng.normal(size=(n, 3)).astype(dt)
    uf = np.zeros((n, 3), dt)
    uf[ilbsv, 0] = ph.astype(dt)
    a = area.astype(dt)

    def call(c):
        lib(chunks[c], ilbsv, fni, a, stfk, 1.0, d, rn, fdat, fxyz, uf)

    def collect():
        return {"fdat": fdat.copy(), "fxyz": fxyz.copy(), "ufhist": uf.copy()}

    return call, collect


def _concurrently(calls):
    barrier = threading.Barrier(len(calls))
    errors = []

    def work(f):
        try:
            barrier.wait()
            f()
        except BaseException as exc:  # pragma: no cover - reported below
            errors.append(exc)

    threads = [threading.Thread(target=work, args=(f,)) for f in calls]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    if errors:
        raise errors[0]


@pytest.mark.parametrize(
    "target,prec,key",
    [(t, "DP", "soft") for t in FORTRAN_TARGETS]
    + [("lsdyna-usrfrc", "SP", "soft"), ("lsdyna-usrfrc-mpp", "SP", "soft")]
    # the tabulated reload form: its core in an implicit, an explicit and an SP host routine
    + [("abaqus-fric", "DP", "tab_flat"), ("abaqus-vfriction", "DP", "tab_flat")]
    + [("lsdyna-usrfrc", "SP", "tab_flat")]
    # the tabulated first loading (under the tabulated reload form)
    + [("abaqus-fric", "DP", "first_bump")],
)
def test_concurrent_calls_equal_serial(tmp_path_factory, params_files, target, prec, key):
    files, _ = exp.render(target, params_files[key], k_t=None if target != "lsdyna" else 5e12)
    src = {k: v for k, v in files.items() if k.endswith(".f")}
    lsdyna = target.startswith("lsdyna-usrfrc")
    flags = ("-O2", "-fopenmp", *(harness.HOST_PRECISION_FLAGS[prec] if lsdyna else ()))
    name = re.sub(r"[^a-z0-9]", "_", f"thr_{target}_{prec}_{key}")
    options = {"dtype": np.float32 if prec == "SP" else np.float64} if lsdyna else {}
    host, _ = exp.target(target).harness.load(
        src, tmp_path_factory.mktemp(name), name=name, flags=flags, **options
    )
    params = PARAM_SETS[key]
    order = np.random.default_rng(7).permutation(N_NODES)
    chunks = np.array_split(order if lsdyna else np.arange(N_NODES), N_THREADS)
    chunks = [np.sort(c) for c in chunks]
    # serial reference: the same chunks, one after the other
    call, collect = _run(target, host, params, np.random.default_rng(1), chunks)
    for c in range(N_THREADS):
        call(c)
    serial = collect()
    for _ in range(N_REPEAT):
        call, collect = _run(target, host, params, np.random.default_rng(1), chunks)
        _concurrently([lambda c=c, f=call: f(c) for c in range(N_THREADS)])
        got = collect()
        for k in serial:
            assert np.array_equal(got[k], serial[k], equal_nan=False), k

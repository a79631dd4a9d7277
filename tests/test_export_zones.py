"""Zonal laws in every exported routine (issue 42): one routine, a law per tool zone, by name.

A host-interface driver (frictionlaw.export.harness) calls each routine as its host does, with
the names of two zones and with a name no zone has: every slipping point's shear equals
``shear_limit`` of its own zone's parameter file with its own ``p_hist`` (to 1e-10; LS-DYNA's
single precision to 1e-6), and the unknown name stops the run with a message naming it
(Abaqus, CalculiX: the error exit; LS-DYNA: no friction there and the message; the host-neutral
entry: status -7 and ``SBMF_ZMESSAGE``). Names are compared trimmed and case-insensitive; the
default law (``--params``) takes every other name; state variable 4 records the law that wrote
the cache, so a point that changes zone runs the new zone's law on its carried ``p_hist``.
"""

import ctypes
import dataclasses
import hashlib
import re

import numpy as np
import pytest
from default_params import DEFAULT
from reload_tables import FIRST, STRONG

import frictionlaw as fl
import frictionlaw.export as exp
from frictionlaw.export import harness

pytestmark = pytest.mark.skipif(harness.gfortran() is None, reason="gfortran not installed")

H = 800e6
#: zone 1: the default calibration (Eq. 24, the paper's Eq. 25), range to 760 MPa
ZA = fl.FrictionParams(**DEFAULT, p_range=(10e6, 760e6))
#: zone 2: another tool: m 0.9, the tabulated forms, range to 500 MPa
ZB = fl.FrictionParams(
    m=0.9, sigma_y=H / 2.5, H=H, C1=3.0, n1=1.5, C2=5.0, n2=1.0,
    reload_form="tabulated", reload_table=STRONG,
    first_loading_form="tabulated", first_loading_table=FIRST["bump"],
    p_range=(10e6, 500e6),
)  # fmt: skip
#: the default law: a third, softer hardness (100 H = 60 GPa)
ZD = fl.FrictionParams(m=0.3, sigma_y=H / 2.8, H=0.75 * H, C1=1.2, n1=2.0, C2=3.0, n2=2.0)

NAMES = {"lsdyna-usrfrc": ("3", "12"), "lsdyna-usrfrc-mpp": ("3", "12")}
#: how each zone's name reaches the routine in a call (trimmed, case-insensitive)
CALLED = {"Rim": (" rim ", "RIM"), "Flank": ("flank", "  FLANK")}
TARGETS = [
    ("abaqus-fric", "DP"),
    ("calculix", "DP"),
    ("abaqus-vfric", "DP"),
    ("abaqus-vfriction", "DP"),
    ("lsdyna-usrfrc", "DP"),
    ("lsdyna-usrfrc", "SP"),
    ("lsdyna-usrfrc-mpp", "DP"),
    ("lsdyna-usrfrc-mpp", "SP"),
    ("lsdyna", "DP"),
]


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("zones")
    out = {}
    flat = dataclasses.replace(ZA, flattening=fl.Flattening(slope=0.05))
    for key, params in (("a", ZA), ("b", ZB), ("d", ZD), ("flat", flat)):
        out[key] = folder / f"zone_{key}.json"
        params.to_json(out[key])
    return out


def names(target):
    return NAMES.get(target, ("Rim", "Flank"))


def load(tmp_path, target, prec, zones, params=None, zone_by=None):
    files_, _ = exp.render(target, params, zones=zones, zone_by=zone_by)
    src = {n: t for n, t in files_.items() if n.endswith(".f")}
    name = re.sub(r"[^a-z0-9]", "_", f"z_{target}_{prec}".lower())
    options, flags = {}, ("-O2",)
    if "usrfrc" in target:
        flags = (*flags, *harness.HOST_PRECISION_FLAGS[prec])
        options["dtype"] = np.float32 if prec == "SP" else np.float64
    host, warnings = exp.target(target).harness.load(
        src, tmp_path / name, name=name, flags=flags, **options
    )
    assert "Error" not in warnings
    return host


def call(target, host, name, p, p_hist, state=None, nsv=4):
    """One call of the routine with the zone's ``name`` at pressures ``p``, slipping far.

    Returns ``(shear, state out)``: the shear stress per point (NaN where the host's error exit
    ended the call) and the state array the routine wrote (the host's layout, points first).
    """
    n = p.size
    if state is None:
        state = np.zeros((n, nsv))
        state[:, 0] = p_hist
    if target in ("abaqus-fric", "calculix"):
        out = host(p, np.full((n, 1), 1e3), np.zeros((n, 1)), state, 1e-3, ciname=name)
        return np.abs(out["tau"][:, 0]), out["statev"]
    if target == "abaqus-vfric":
        st = np.ascontiguousarray(state, dtype=float)
        ft = host(p, np.full(n, 1e300), np.ones(n), st, surf_int=name)
        return -ft[:, 0], st
    if target == "abaqus-vfriction":
        st = np.ascontiguousarray(state[:, None, :], dtype=float)
        ft = host(p, np.full(n, 1e300), np.ones(n), st, surf_int=name)
        return -ft[:, 0], st[:, 0, :]
    if target == "lsdyna":
        st = np.ascontiguousarray(state, dtype=float)
        out = host.friction(name, p, st, np.full((n, 1), 1e3), np.zeros((n, 1)), 1e30)
        call.ierr = out["ierr"]
        return np.abs(out["t"][:, 0]), st
    dt = host.dtype
    if target == "lsdyna-usrfrc-mpp":
        uh = np.ascontiguousarray(state, dtype=dt)
        mu = host(p.astype(dt), uh, nosl=int(name))
        return mu[:, 0].astype(float) * p, uh.astype(float)
    fdat = np.zeros((n, 5), dt)
    uf = np.ascontiguousarray(state, dtype=dt)
    d = np.zeros((n, 3))
    d[:, 0] = 1e3
    rn = np.zeros((n, 3))
    rn[:, 2] = 1.0
    host(
        np.arange(n), np.arange(n), -p, np.ones(n), np.full(n, 1e30), 1.0, d, rn, fdat,
        np.zeros((n, 3), dt), uf, nosl=int(name),
    )  # fmt: skip
    return np.hypot(fdat[:, 2], fdat[:, 3]).astype(float), uf.astype(float)


def errors(target, host):
    """The error messages the routine wrote since the last look, and its error exits."""
    if "usrfrc" in target:
        tty = host.log()["tty"]
        return [x[len(" *** Error: ") :] for x in tty if x.startswith(" *** Error: ")], 0
    return [t for lop, t in host.log() if lop == -3], host.exits()


def points(rng, n):
    """Pressures on both branches (a third below their p_hist) and histories, Pa."""
    p = rng.uniform(2e6, 0.95 * H, n)
    p_hist = np.where(rng.random(n) < 0.4, 0.0, rng.uniform(0.05, 1.2, n) * H)
    return p, p_hist


@pytest.mark.parametrize("target,prec", TARGETS)
def test_each_zone_runs_its_own_law_and_an_unknown_name_stops(tmp_path, files, target, prec):
    """The judgement of issue 42, in every routine's host emulation."""
    na, nb = names(target)
    host = load(tmp_path, target, prec, [(na, files["a"]), (nb, files["b"])])
    rng = np.random.default_rng(42)
    sp = prec == "SP"
    for name, params in ((na, ZA), (nb, ZB)):
        spellings = CALLED.get(name, (name, f" {name}"))
        for called in spellings:
            p, p_hist = points(rng, 64)
            if sp:  # the host REAL: what the routine reads
                p, p_hist = (v.astype(np.float32).astype(float) for v in (p, p_hist))
            tau, state = call(target, host, called, p, p_hist)
            want = fl.shear_limit(p, p_hist, params)
            np.testing.assert_allclose(tau, want, rtol=1e-6 if sp else 1e-10, atol=0)
            assert (p < p_hist).sum() > 10 and (p > p_hist).sum() > 10  # both branches
            # its own p_hist: the trial history max(p_hist, p) in the point's state
            np.testing.assert_allclose(state[:, 0], np.maximum(p_hist, p), rtol=1e-7 if sp else 0)
            errs, exits = errors(target, host)
            assert not errs and not exits
    # the other zone's law is not it (the test would see a swap)
    other = fl.shear_limit(p, p_hist, ZA)
    assert np.median(np.abs(other / fl.shear_limit(p, p_hist, ZB) - 1)) > 0.05
    # a name no zone has, and no default law: stop (Abaqus, CalculiX) or refuse (LS-DYNA)
    unknown = "99" if target in NAMES else "Tip"
    tau, state = call(target, host, unknown, p, p_hist)
    errs, exits = errors(target, host)
    if target == "lsdyna":
        assert np.all(call.ierr == -7) and np.all(tau == 0)
        msg = host.zone_message(unknown)
        assert "ZONE = 'Tip'" in msg and "none of this routine's zones (Rim, Flank)" in msg
        return
    arg = {"abaqus-vfric": "surfInt", "abaqus-vfriction": "surfInt"}.get(target, "CINAME")
    arg = "NOSL" if "usrfrc" in target else arg
    assert len(errs) == 1 and f"{arg} = '{unknown}'" in errs[0]
    assert "is none of this routine's zones" in errs[0] and "no default law" in errs[0]
    if "usrfrc" in target:  # no error exit: no friction at all on that interface
        assert exits == 0 and np.all(tau == 0)
        np.testing.assert_array_equal(state[:, 0], p_hist.astype(state.dtype))  # untouched
        call(target, host, unknown, p, p_hist)
        assert errors(target, host) == ([], 0)  # once per process
    else:
        assert exits == 1


@pytest.mark.parametrize("target,prec", [("abaqus-fric", "DP"), ("lsdyna-usrfrc", "DP"),
                                         ("lsdyna", "DP")])  # fmt: skip
def test_the_default_law_takes_every_other_name(tmp_path, files, target, prec):
    na, nb = names(target)
    host = load(tmp_path, target, prec, [(na, files["a"]), (nb, files["b"])], files["d"])
    p, p_hist = points(np.random.default_rng(3), 64)
    for name, params in ((na, ZA), ("7" if target in NAMES else "Land", ZD), (" ", ZD)):
        if name == " " and target in NAMES:
            continue
        tau, _ = call(target, host, name, p, p_hist)
        np.testing.assert_allclose(tau, fl.shear_limit(p, p_hist, params), rtol=1e-10)
        assert errors(target, host) == ([], 0)


def test_a_point_that_changes_zone_runs_the_new_law_on_its_p_hist(tmp_path, files):
    """State variable 4 keeps the cache with its law: under another zone it is recomputed."""
    host = load(tmp_path, "abaqus-fric", "DP", [("Rim", files["a"]), ("Flank", files["b"])])
    rng = np.random.default_rng(9)
    p, p_hist = points(rng, 200)
    _, state = call("abaqus-fric", host, "Rim", p, p_hist)  # committed under Rim (law 1)
    assert np.all(state[:, 3] == 1.0) and np.all(state[:, 1] >= 0)
    p2 = rng.uniform(0.02, 0.9, p.size) * state[:, 0]  # unloaded: on the reload branch
    tau, state2 = call("abaqus-fric", host, "Flank", p2, None, state=state.copy())
    np.testing.assert_allclose(tau, fl.shear_limit(p2, state[:, 0], ZB), rtol=1e-10)
    assert np.all(state2[:, 3] == 2.0) and np.array_equal(state2[:, 0], state[:, 0])
    # the cache now Flank's: -ln alpha1(p_hist) of ZB, not ZA's
    a1 = fl.alpha_first(state[:, 0], ZB)
    np.testing.assert_allclose(state2[:, 1], -np.log(a1), rtol=1e-12)
    assert np.median(np.abs(state2[:, 1] - state[:, 1])) > 0.05
    # with its own cache the law is the same to the last bit; a foreign cache is never read
    again, _ = call("abaqus-fric", host, "Flank", p2, None, state=state2.copy())
    assert np.array_equal(again, tau)
    bogus = state2.copy()
    bogus[:, 1] = 0.5 * state2[:, 1]
    bogus[:, 3] = 1.0  # written by Rim's law
    again, _ = call("abaqus-fric", host, "Flank", p2, None, state=bogus)
    assert np.array_equal(again, tau)
    # DEPVAR = 3 (no record of the cache's law): a zoned routine never reads the cache
    three = bogus[:, :3].copy()
    again, out3 = call("abaqus-fric", host, "Flank", p2, None, state=three)
    assert np.array_equal(again, tau) and out3.shape[1] == 3


def test_each_zone_has_its_own_guards(tmp_path, files):
    """100 H and the calibrated range are the zone's: a VFRIC pressure above ZD's 100 H stops
    under that law only; the range warning names each zone's own p_max."""
    host = load(tmp_path, "abaqus-vfric", "DP", [("Rim", files["a"]), ("Soft", files["d"])])
    p = np.array([70e9])  # above 100 H = 60 GPa of ZD, below ZA's 80 GPa
    tau, _ = call("abaqus-vfric", host, "rim", p, np.zeros(1))
    log = host.log()
    assert [lop for lop, _ in log] == [-1] and "zone 'Rim'" in log[0][1]  # beyond its range
    assert "p_max = 7.6e+08 Pa" in log[0][1] and host.exits() == 0
    call("abaqus-vfric", host, "soft", p, np.zeros(1))
    ((lop, text),) = host.log()
    assert lop == -3 and host.exits() == 1
    assert text.startswith("SBMF friction: zone 'Soft' (zone_d.json): contact pressure ")
    assert "> 100 H = 6e+10 Pa" in text


def test_neutral_entry_version_and_bulk_strain(tmp_path, files):
    host = load(tmp_path, "lsdyna", "DP", [("Rim", files["a"])], files["b"])
    p, p_hist = points(np.random.default_rng(5), 32)
    n = p.size
    st = np.zeros((n, 5))
    st[:, 0] = p_hist
    st[:, 4] = 0.25  # the flattening slot: kept as passed
    du, t0 = np.full((n, 1), 1e3), np.zeros((n, 1))
    out = host.friction("rim", p, st, du, t0, 1e30, deps=0.3, sigy=2e8)
    assert np.all(out["ierr"] == 0) or np.all(out["ierr"] % 10 == 5)  # range warning once
    np.testing.assert_allclose(np.abs(out["t"][:, 0]), fl.shear_limit(p, p_hist, ZA), rtol=1e-10)
    assert np.all(st[:, 4] == 0.25) and np.all(st[:, 3] == 1.0)
    st2 = np.zeros((n, 5))
    st2[:, 0] = p_hist
    bad = host.friction("rim", p, st2, du, t0, 1e30, version=3)
    assert np.all(bad["ierr"] == -8) and np.all(st2[:, 0] == p_hist)
    assert "IVERS = 3, but this routine implements version 2" in host.message(8, 3.0)
    fn = host._lib.sbmf_nstate_
    fn.restype = ctypes.c_int
    assert fn() == 6


def test_header_and_readme_list_every_zone(files):
    out, _ = exp.render(
        "abaqus-fric", files["d"], zones=[("Rim", files["a"]), ("Flank", files["b"])]
    )
    src, readme = out["sbmf_fric.f"], out["README.md"]
    for law, path in (("zone 1 'Rim'", files["a"]), ("zone 2 'Flank'", files["b"]),
                      ("law 3, the default", files["d"])):  # fmt: skip
        assert f"C {law}: parameter file {path.name}" in src
    for path in (files["a"], files["b"], files["d"]):
        sha = hashlib.sha256(path.read_bytes()).hexdigest()
        assert sha in src and sha in readme
    assert "calibrated pressures: 10..760 MPa" not in src  # SI
    assert "calibrated pressures: 1e+07..7.6e+08 Pa" in src
    assert "calibrated pressures: 1e+07..5e+08 Pa" in src
    assert "calibrated pressures: none recorded" in src  # ZD has no range
    assert "zones: 2, chosen by CINAME" in src
    for name in ("`Rim`", "`Flank`", "default law"):
        assert name in readme
    assert "DEPVAR=4" in readme


def test_laws_in_files_of_one_name_are_told_apart(tmp_path, files):
    """Every calibration writes ``params.json``: the README, the header and the messages name
    each law's file with the parent folder that tells it from the others (same name, same
    file: one name)."""
    a, d = tmp_path / "calibration" / "params.json", tmp_path / "mnt-1" / "params.json"
    for path, key in ((a, "a"), (d, "d")):
        path.parent.mkdir()
        path.write_bytes(files[key].read_bytes())
    out, _ = exp.render("calculix", d, zones=[("Rim", a)])
    src, readme = out["sbmf_fric.f"], out["README.md"]
    assert "| `Rim` | 1 | `calibration/params.json` |" in readme
    assert "| any other name | 2 | `mnt-1/params.json` |" in readme
    assert "C zone 1 'Rim': parameter file calibration/params.json" in src
    text = re.sub(r"'\n\s+&\s+// '", "", src).replace("''", "'")  # Fortran's strings joined
    assert "zone 'Rim' (calibration/params.json)" in text
    assert "the default law (mnt-1/params.json)" in text
    out, _ = exp.render("calculix", a, zones=[("Rim", a)])
    assert "| `Rim` | 1 | `params.json` |" in out["README.md"]


@pytest.mark.parametrize(
    "target, zones, extra, match",
    [
        ("ansys-userfric", [("a", "a")], {}, "argument list of ANSYS' userfric is not public"),
        ("abaqus-table", [("a", "a")], {}, "writes a friction table"),
        ("abaqus-fric", [("a", "a"), (" A ", "b")], {}, "are the same when trimmed"),
        ("abaqus-fric", [("  ", "a")], {}, "a zone's name is empty"),
        ("abaqus-fric", [("it's", "a")], {}, "without quotes"),
        ("lsdyna-usrfrc", [("rim", "a")], {}, "must be an integer >= 1"),
        ("lsdyna-usrfrc", [("3", "a"), ("03", "b")], {}, "are the same"),
        ("abaqus-fric", [("a", "a")], {"zone_by": "interface"}, "zone_by"),
        ("calculix", [("a", "a")], {"zone_by": "slave"}, "zone_by"),
        ("abaqus-fric", [], {"zone_by": "slave"}, "applies with"),
        ("abaqus-fric", [("a", "a"), ("b", "flat")], {}, "carries a flattening block"),
    ],
)
def test_bad_zones_refused(files, target, zones, extra, match):
    zones = [(n, files[f]) for n, f in zones]
    with pytest.raises(ValueError, match=match):
        exp.render(target, files["d"], zones=zones, **extra)


@pytest.mark.parametrize(
    "target, zone_by, names_kw",
    [("abaqus-fric", "master", "msname"), ("abaqus-vfric", "slave", "surf_sec")],
)
def test_zone_by_the_surfaces_names(tmp_path, files, target, zone_by, names_kw):
    """``--zone-by slave|master``: the routine compares the surface's name, not the
    interaction's (which then names nothing)."""
    files_, _ = exp.render(
        target, None, zones=[("TOOL-A", files["a"]), ("TOOL-B", files["b"])], zone_by=zone_by
    )
    src = {n: t for n, t in files_.items() if n.endswith(".f")}
    host, _ = exp.target(target).harness.load(src, tmp_path / "zb", name=f"zb_{zone_by}")
    p, p_hist = points(np.random.default_rng(11), 32)
    n = p.size
    for surface, params in (("tool-b", ZB), ("Tool-A ", ZA)):
        st = np.zeros((n, 4))
        st[:, 0] = p_hist
        if target == "abaqus-fric":
            out = host(p, np.full((n, 1), 1e3), np.zeros((n, 1)), st, 1e-3, ciname="X", **{
                names_kw: surface})  # fmt: skip
            tau = np.abs(out["tau"][:, 0])
        else:
            tau = -host(p, np.full(n, 1e300), np.ones(n), st, surf_int="X", **{names_kw: surface})[
                :, 0
            ]
        np.testing.assert_allclose(tau, fl.shear_limit(p, p_hist, params), rtol=1e-10)
    assert all(lop == -1 for lop, _ in host.log()) and host.exits() == 0  # range warnings only
    assert (
        f"chosen by {'MSNAME' if zone_by == 'master' else 'surfSec'}"
        in src[exp.target(target).file]
    )


def test_command_line_zones(tmp_path, files, capsys):
    """Exit 0 with zones and no --params; exit 2 for bad zones, before anything is written."""
    from frictionlaw.export.cli import main

    out = tmp_path / "fric"
    z = ["--zone", f"rim={files['a']}", "--zone", f"flank={files['b']}"]
    assert main(["abaqus-fric", "--out", str(out), "--quiet", *z]) == 0
    assert (out / "sbmf_fric.f").is_file() and "zones: 2, chosen by CINAME" in (
        out / "sbmf_fric.f"
    ).read_text()
    capsys.readouterr()
    for args, match in (
        ([], "give --params"),
        (["--zone", "rim"], "--zone takes NAME=PARAMS.json"),
        (["--zone", f"rim={tmp_path / 'none.json'}"], "none.json"),
        ([*z, "--zone", f"RIM ={files['d']}"], "are the same when trimmed"),
        (["--params", str(files["d"]), "--zone-by", "slave"], "--zone-by applies with --zone"),
        ([*z, "--zone-by", "interface"], "--zone-by must be one of interaction, slave, master"),
    ):
        bad = tmp_path / "bad"
        assert main(["abaqus-fric", "--out", str(bad), *args]) == 2, args
        assert match in capsys.readouterr().err, (args, match)
        assert not bad.exists()
    assert main(["ansys-userfric", "--out", str(tmp_path / "an"), *z]) == 2
    assert "userfric is not public" in capsys.readouterr().err

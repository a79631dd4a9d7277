"""Zoned routines of laws with a flattening block (issues 42 and 43), host emulation.

A zoned export runs each zone's own flattening block (``SBMF_ZFSHR``): the flattened contact
fraction is the workpiece's and travels from zone to zone, a zone with a block reading it
through its own law's ``alpha1`` and growing it, a zone without one running its calibrated law
and passing it on unchanged, as the runtime's :class:`frictionlaw.ZonedLaw` does. Checked
against ``traction_update(ZonedLaw, ..., d_eps=, zone=)`` for the hosts that pass the strain
(the neutral entry, LS-DYNA's usrfrc SMP and MPP, the patched CalculiX's ``FRIC``), and the
hosts that pass none refuse it unless told ``--without-flattening``.
"""

import dataclasses
import re

import numpy as np
import pytest
from test_export_zones import ZA, ZB, ZD

import frictionlaw as fl
import frictionlaw.export as exp
from frictionlaw.export import harness

pytestmark = pytest.mark.skipif(harness.gfortran() is None, reason="gfortran not installed")

#: zone 1 flattens (slope 0.05), zone 2 has no block, the default law flattens (slope 0.1)
FA = dataclasses.replace(ZA, flattening=fl.Flattening(slope=0.05))
FD = dataclasses.replace(ZD, flattening=fl.Flattening(slope=0.1))
#: zone 1 as the two-state model (limit-analysis) instead
FT = dataclasses.replace(ZA, flattening=fl.Flattening(slope=0.05, model="limit-analysis"))
#: ... and with an edge-slope table (flattening.edge_slope: the flank follows it)
FE = dataclasses.replace(
    ZA,
    flattening=fl.Flattening(
        slope=0.05, model="limit-analysis", edge_slope=(0.02, 0.03, 0.05, 0.08, 0.1)
    ),
)
RIMS = {"t": FT, "e": FE}
NAMES = {"lsdyna-usrfrc": ("3", "12"), "lsdyna-usrfrc-mpp": ("3", "12")}


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("zflat")
    out = {}
    for key, params in (("a", FA), ("b", ZB), ("d", FD), ("t", FT), ("e", FE)):
        out[key] = folder / f"zone_{key}.json"
        params.to_json(out[key])
    return out


def _load(tmp_path, target, files, rim_file="a", entry="SBMF_ZFSHR"):
    rim, flank = NAMES.get(target, ("Rim", "Flank"))
    zones = [(rim, files[rim_file]), (flank, files["b"])]
    texts, _ = exp.render(target, files["d"], zones=zones)
    src = {n: t for n, t in texts.items() if n.endswith(".f")}
    assert f"SUBROUTINE {entry}" in src[exp.target(target).file]
    name = re.sub(r"[^a-z0-9]", "_", f"zf_{target}_{rim_file}")
    options, flags = {}, ("-O2",)
    if "usrfrc" in target:  # LS-DYNA's double-precision build: REAL is 8 bytes
        options["dtype"] = np.float64
        flags = (*flags, *harness.HOST_PRECISION_FLAGS["DP"])
    host, warnings = exp.target(target).harness.load(
        src, tmp_path / name, name=name, flags=flags, **options
    )
    assert "Error" not in warnings
    return host, texts, (rim, flank, "99" if "usrfrc" in target else "other")


def _runtime():
    laws = tuple(fl.SBMFLaw(p) for p in (FA, ZB, FD))
    return fl.ZonedLaw(("rim", "flank", "default"), laws)


#: pressures and the increments' strains: each point visits the zones in turn
P = np.array([40e6, 120e6, 250e6, 400e6])
STEPS = [(0.0, 0), (0.004, 0), (0.004, 1), (0.01, 2), (0.01, 1), (0.02, 0)]


def _call(target, host, name, p, state, deps, eps, cycle):
    """One call (one increment / cycle) of every point in zone ``name``; returns |tau|."""
    n = p.size
    if target == "lsdyna":
        out = host.friction(name, p, state, np.full((n, 1), 1e3), np.zeros((n, 1)), 1e30, deps=deps)
        assert np.all(out["ierr"] % 10 != 9)
        return np.abs(out["t"][:, 0])
    if target == "calculix":
        out = host(
            p,
            np.full((n, 1), 1e3),
            np.zeros((n, 1)),
            state,
            1e-3,
            ciname=name,
            predef=np.column_stack([np.full(n, eps), np.full(n, deps)]),
        )
        state[:] = out["statev"]
        return np.abs(out["tau"][:, 0])
    if target == "lsdyna-usrfrc-mpp":
        mu = host(p, state, nosl=int(name), ue=np.full((n, 1), eps), ncycle=cycle)
        return mu[:, 0] * p
    fdat = np.zeros((n, 5))
    d = np.tile([1e3, 0.0, 0.0], (n, 1))
    rn = np.tile([0.0, 0.0, 1.0], (n, 1))
    host(
        np.arange(n), np.arange(n), -p, np.ones(n), np.full(n, 1e30), 1.0, d, rn, fdat,
        np.zeros((n, 3)), state, nosl=int(name), ufeps=np.full((n, 1), eps), ncycle=cycle,
    )  # fmt: skip
    return np.hypot(fdat[:, 2], fdat[:, 3])


@pytest.mark.parametrize("target", ["lsdyna", "calculix", "lsdyna-usrfrc", "lsdyna-usrfrc-mpp"])
def test_each_zone_runs_its_own_flattening_and_the_fraction_travels(tmp_path, files, target):
    host, texts, names = _load(tmp_path, target, files)
    readme = texts["README.md"]
    assert f"zone '{names[0]}' (zone_a.json): asperity flank slope" in readme
    assert "zone_b.json" not in readme.split("## Flattening under bulk strain")[1].split("\n\n")[1]
    zl = _runtime()
    n = P.size
    nsv = 7 if "usrfrc" in target else 5
    state = np.zeros((n, nsv))
    ref = fl.HistoryState(n)
    eps = 0.0
    grew = {0: 0.0, 1: 0.0, 2: 0.0}
    for cycle, (step, zone) in enumerate(STEPS, start=1):
        eps += step
        before = ref.alpha_f.copy()
        tau = _call(target, host, names[zone], P, state, step, eps, cycle)
        res = fl.traction_update(
            zl, P, np.ones(n), np.zeros(n), 1e30, ref, d_eps=step, zone=np.full(n, zone)
        )
        ref.commit()
        np.testing.assert_allclose(state[:, 4], ref.alpha_f, rtol=1e-12, atol=0)
        np.testing.assert_allclose(tau, np.abs(res.traction), rtol=1e-11)
        grew[zone] = max(grew[zone], float(np.max(ref.alpha_f - before)))
    # zones 1 and 3 flattened, zone 2 (no block) passed the fraction on unchanged
    assert grew[0] > 0.05 and grew[2] > 0.05 and grew[1] == 0.0


def test_hosts_without_strain_need_the_users_word(files):
    zones = [("Rim", files["a"]), ("Flank", files["b"])]
    with pytest.raises(ValueError, match="passes no bulk plastic strain"):
        exp.render("abaqus-fric", files["d"], zones=zones)
    texts, _ = exp.render("abaqus-fric", files["d"], zones=zones, without_flattening=True)
    assert "SBMF_ZFSHR" not in texts["sbmf_fric.f"] and "SBMF_GUARD(9" in texts["sbmf_fric.f"]


#: the flank slope's column of each target's state (0-based) and its state count
SLOPE = {"lsdyna": (6, 7), "calculix": (5, 6), "lsdyna-usrfrc": (7, 8), "lsdyna-usrfrc-mpp": (7, 8)}


@pytest.mark.parametrize(
    ("target", "rim"),
    [
        *((t, "t") for t in ("lsdyna", "calculix", "lsdyna-usrfrc", "lsdyna-usrfrc-mpp")),
        ("lsdyna", "e"),
        ("calculix", "e"),
    ],
)
def test_a_two_state_zone_turns_the_slope_and_both_states_travel(tmp_path, files, target, rim):
    """Zone 1 the two-state model (rim ``e``: with an edge-slope table), zone 2 no block, the
    default the one-state model: each visit's fraction and flank slope as the runtime's
    ZonedLaw (1e-12; the one-state zone perfectly plastic and passing the slope on, the plain
    zone passing both on)."""
    host, texts, names = _load(tmp_path, target, files, rim, "SBMF_ZTSHR")
    col, nsv = SLOPE[target]
    assert "flank slope" in texts["README.md"]
    laws = tuple(fl.SBMFLaw(p) for p in (RIMS[rim], ZB, FD))
    zl = fl.ZonedLaw(("rim", "flank", "default"), laws)
    n = P.size
    state = np.zeros((n, nsv))
    ref = fl.HistoryState(n)
    eps = 0.0
    turned = {0: 0.0, 1: 0.0, 2: 0.0}
    for cycle, (step, zone) in enumerate(STEPS, start=1):
        eps += step
        before = ref.slope_f.copy()
        tau = _call(target, host, names[zone], P, state, step, eps, cycle)
        res = fl.traction_update(
            zl, P, np.ones(n), np.zeros(n), 1e30, ref, d_eps=step, zone=np.full(n, zone)
        )
        ref.commit()
        np.testing.assert_allclose(state[:, 4], ref.alpha_f, rtol=1e-12, atol=0)
        np.testing.assert_allclose(state[:, col], ref.slope_f, rtol=1e-12, atol=0)
        np.testing.assert_allclose(tau, np.abs(res.traction), rtol=1e-11)
        turned[zone] = max(turned[zone], float(np.max(np.abs(ref.slope_f - before))))
    # only the two-state zone turned the flank; the others passed it on
    assert turned[0] > 1e-3 and turned[1] == 0.0 and turned[2] == 0.0

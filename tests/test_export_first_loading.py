"""The tabulated first loading in every generated routine and table (issue 37).

Each Fortran target is driven through its host harness as tests/test_export_reload.py drives it
(``call``, ``agreement``: the shear limit itself and, where the host returns it, ``dtau/dp``,
node by node against the runtime's kernel in the routine's units; the routine's own
``-ln alpha1(p_hist)`` cache and "recompute" must give the same numbers bit for bit) on a grid
that spans the first-loading table (tests/reload_tables.py, ``FIRST``; the parameter sets
``first_*`` of tests/test_export_fortran.py): ``p`` below the lowest level (down to the
subnormal 5e-324 Pa), at every level and one ulp either side, between the levels, above the top
level up to 99 ``H`` (1e6 ``H`` for the host-neutral entry), with ``p_hist`` 0, half of ``p``
and ``p`` itself (first loading), and the reload grid of tests/test_export_reload.py, whose
histories now also sit on the first loading's levels, below the lowest and above the top one
(``alpha1(p_hist)`` in the Coulomb line, between the knots, on the power law and capped at 1).

Every target runs one parameter set in one unit system (:data:`ASSIGN`: every set, both unit
systems, both LS-DYNA host precisions; the DP libraries are shared with
tests/test_export_fortran.py). Double precision: ``tau`` within 1e-13 relative, ``dtau/dp``
within 1e-12; LS-DYNA's single-precision builds within 1e-6 (MPP's coefficient 1.2e-7), the
bound of issue 31.
"""

import json

import numpy as np
import pytest
from test_export_fortran import PARAM_SETS
from test_export_reload import (
    RTOL_DTAU,
    RTOL_TAU,
    STOPS_ABOVE_100H,
    TARGETS,
    agreement,
    grid,
    load,
)

import frictionlaw as fl
import frictionlaw.export as exp
from frictionlaw.export import _tables, harness
from frictionlaw.export.cli import main

pytestmark = pytest.mark.skipif(
    harness.gfortran() is None,
    reason="gfortran not installed (.ci/run installs it: apt-get install -y gfortran)",
)

#: (target, host precision) -> (parameter set, units)
ASSIGN = {
    ("abaqus-fric", "DP"): ("first_bump", "mm-t-s"),
    ("calculix", "DP"): ("first_full", "SI"),
    ("abaqus-vfric", "DP"): ("first_one", "mm-t-s"),
    ("abaqus-vfriction", "DP"): ("first_default", "SI"),
    ("lsdyna", "DP"): ("first_pair", "SI"),
    ("ansys-userfric", "DP"): ("first_flat", "mm-t-s"),
    ("lsdyna-usrfrc", "DP"): ("first_default", "mm-t-s"),
    ("lsdyna-usrfrc", "SP"): ("first_bump", "SI"),
    ("lsdyna-usrfrc-mpp", "DP"): ("first_flat", "SI"),
    ("lsdyna-usrfrc-mpp", "SP"): ("first_full", "mm-t-s"),
}


def first_grid(params):
    """``(p, p_hist)`` in Pa on first loading: ``p`` across the first-loading table, ``p_hist``
    0, ``p / 2`` and ``p``."""
    H = params.H
    lv = np.asarray(params.first_loading_table.p)
    p = [5e-324, 1e-310, 1e-300, 1e-200, 1e-3, 1.0, 1e3, 1e-3 * lv[0], 0.5 * lv[0]]
    for a in lv:
        p += [np.nextafter(a, 0), a, np.nextafter(a, 2 * a)]
    for a, b in zip(lv[:-1], lv[1:], strict=True):
        p += [0.5 * (a + b), np.sqrt(a * b), a + 0.01 * (b - a), b - 0.01 * (b - a)]
    p += [1.01 * lv[-1], 0.5 * (lv[-1] + H), np.nextafter(H, 0), H, 2 * H, 10 * H, 99 * H]
    p += [1e3 * H, 1e6 * H]
    p = np.asarray(p)
    return np.concatenate([p, p, p]), np.concatenate([np.zeros_like(p), 0.5 * p, p])


def both_grids(params, target, prec):
    """The reload grid and the first-loading grid, limited to what the host can run."""
    p, ph = grid(params, np.random.default_rng(37))
    p1, ph1 = first_grid(params)
    p, ph = np.concatenate([p, p1]), np.concatenate([ph, ph1])
    if prec == "SP":  # single-precision hosts: pressures a single-precision force can carry
        keep = (np.abs(p) < 1e28) & (ph < 1e28)
        p, ph = p[keep], ph[keep]
    if target in STOPS_ABOVE_100H:
        keep = (p <= 99 * params.H) & (ph <= 99 * params.H)
        p, ph = p[keep], ph[keep]
    return p, ph


def test_every_set_unit_system_and_precision_is_assigned():
    assert set(ASSIGN) == set(TARGETS)
    keys = {k for k, _ in ASSIGN.values()}
    assert keys == {k for k in PARAM_SETS if k.startswith("first_")}
    assert {u for _, u in ASSIGN.values()} == {"SI", "mm-t-s"}
    for key in keys:
        assert PARAM_SETS[key].first_loading_form == "tabulated"


def test_the_grids_reach_every_region_of_the_table():
    """First loading below the lowest level, on the knots, between, above the top (capped and
    not), p -> 0; reloading from histories in the Coulomb line, on the knots and above the top."""
    params = PARAM_SETS["first_default"]
    p, ph = both_grids(params, "lsdyna", "DP")
    lv = np.asarray(params.first_loading_table.p)
    first = (p > 0) & (p >= ph)
    reload = (p > 0) & (p < ph)
    assert np.any(first & (p < lv[0])) and np.any(first & (p == 5e-324))
    assert np.isin(lv, p[first]).all() and np.isin(np.nextafter(lv, 0), p[first]).all()
    inner = first & (p > lv[0]) & (p < lv[-1]) & ~np.isin(p, lv)
    assert inner.sum() > 4 * lv.size
    a_top = fl.alpha_first(p[first & (p > lv[-1])], params)
    assert np.any(a_top < 1.0) and np.any(a_top == 1.0)  # the power law and its cap
    assert np.any(reload & (ph < lv[0])) and np.isin(lv, ph[reload]).all()
    assert np.any(reload & (ph > lv[-1]) & (ph > params.H))


@pytest.mark.parametrize("target,prec", TARGETS)
def test_routine_is_the_runtime_on_the_first_loading_table(tmp_path_factory, target, prec):
    key, units = ASSIGN[(target, prec)]
    host = load(tmp_path_factory, target, key, units, prec)
    params = PARAM_SETS[key]
    p, ph = both_grids(params, target, prec)
    got = agreement(target, host, params, exp.UNIT_SYSTEMS[units], prec, p, ph)
    rtol = 1.2e-7 if (prec == "SP" and target.endswith("mpp")) else RTOL_TAU[prec]
    assert got["tau"] <= rtol, got
    if "dtau" in got:
        assert got["dtau"] <= RTOL_DTAU, got


def test_the_check_tells_the_first_loading_forms_apart(tmp_path_factory, tmp_path):
    """The same file switched to Eq. 24 (its C1, n1 kept) exports a routine that misses the
    tabulated law: the comparison above fails on it."""
    params = PARAM_SETS["first_bump"]
    path = params.replace(first_loading_form="eq24").to_json(tmp_path / "eq24.json")
    files, _ = exp.render("lsdyna", path)
    assert "first-loading form: eq24" in files["sbmf_lsdyna.f"]
    host, _ = exp.target("lsdyna").harness.load(files, tmp_path / "b", name="eq24_of_bump")
    p, ph = both_grids(params, "lsdyna", "DP")
    got = agreement("lsdyna", host, params, exp.UNIT_SYSTEMS["SI"], "DP", p, ph)
    assert got["tau"] > 0.1 and got["dtau"] > 0.1, got


# -- the texts --------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def bump_file(tmp_path_factory):
    return PARAM_SETS["first_bump"].to_json(tmp_path_factory.mktemp("first") / "params.json")


@pytest.mark.parametrize("target", exp.TARGETS)
def test_header_and_readme_name_the_form_and_its_levels(bump_file, target):
    files, _ = exp.render(target, bump_file, units="mm-t-s")
    params = fl.FrictionParams.from_json(bump_file)
    table = params.first_loading_table
    marker = exp.target(target).style.comment
    head = files[exp.target(target).file].replace(f"\n{marker}   ", " ")  # unwrapped
    assert "first-loading form: tabulated (" in head
    levels = "first-loading levels p (MPa): " + ", ".join(f"{v * 1e-6:.10g}" for v in table.p)
    assert levels in head
    assert f"mu_eff=tau_max alpha_0/p_0={params.mu_eff!r}" in head
    assert "C1=" not in head  # Eq. 24's parameters do not run
    readme = files["README.md"]
    assert "First-loading form: `tabulated`" in readme
    for i, (pj, aj) in enumerate(zip(table.p, table.alpha, strict=True)):
        assert f"| {i + 1} | {pj * 1e-6:.6g} | {aj:.6g} |" in readme
    assert f"`mu_eff = tau_max alpha_0 / p_0 = {params.mu_eff:.6g}`" in readme


def test_an_eq24_file_says_so(tmp_path):
    path = PARAM_SETS["default"].to_json(tmp_path / "p.json")
    files, _ = exp.render("abaqus-fric", path)
    assert "first-loading form: eq24 (Eq. 24" in files["sbmf_fric.f"]
    assert "mu_eff=tau_max C1/H=" in files["sbmf_fric.f"]
    assert "First-loading form: `eq24`" in files["README.md"]
    assert "SUBROUTINE SBMF_FTAB" not in files["sbmf_fric.f"]


def test_command_exports_a_tabulated_first_loading(bump_file, tmp_path, capsys):
    out = tmp_path / "x"
    assert main(["ansys-userfric", "--params", str(bump_file), "--out", str(out), "--quiet"]) == 0
    src = (out / "sbmf_userfric.f").read_text()
    assert "SUBROUTINE SBMF_FTAB" in src and "LNA1H = SBMF_LNA1(PH)" in src
    assert "LNA1H = SBMF_SMINL" not in src  # Eq. 24's alpha1(p_hist) is gone


def test_a_one_level_table_is_refused_naming_the_field(bump_file, tmp_path, capsys):
    doc = json.loads(bump_file.read_text())
    law = doc["first_loading_law"]
    law["p"], law["alpha"] = law["p"][:1], law["alpha"][:1]
    path = tmp_path / "one.json"
    path.write_text(json.dumps(doc))
    assert main(["abaqus-fric", "--params", str(path), "--out", str(tmp_path / "x")]) == 2
    err = capsys.readouterr().err
    assert "first_loading_law" in err and "at least 2" in err and "Traceback" not in err


# -- the tables ---------------------------------------------------------------------------------


@pytest.mark.parametrize("key", ["first_default", "first_bump", "first_full", "first_flat"])
@pytest.mark.parametrize("tol", [1e-2, 1e-3])
def test_table_of_the_first_loading_within_tolerance(key, tol):
    params = PARAM_SETS[key]
    t = _tables.build_table(params, tol)
    assert t.max_error <= tol
    rng = np.random.default_rng(2)
    lv = np.asarray(params.first_loading_table.p)
    q = np.concatenate(
        [
            rng.uniform(0, 1.2 * t.p[-1], 20000),
            rng.uniform(0, 50 * t.p[-1], 2000),
            np.geomspace(1e-3 * lv[0], lv[-1], 3000),
            lv,
        ]
    )
    err = np.abs(_tables.table_shear(q, t.p, t.mu, t.cap) - fl.shear_limit(q, 0.0, params))
    assert err.max() <= tol * params.tau_max
    a0 = params.first_loading_table.alpha[0]
    assert t.p[0] == 0.0 and t.mu[0] == params.mu_eff
    assert params.mu_eff == pytest.approx(params.tau_max * a0 / lv[0], rel=1e-15)
    # the cap is the first loading's supremum: tau_max unless the law stays below full contact
    top = params.first_loading_table.alpha[-1]
    want = params.tau_max * (top if key == "first_flat" else 1.0)
    assert t.cap == pytest.approx(want, rel=1e-15)


def test_the_table_follows_the_tabulated_form_not_eq24(tmp_path):
    """The deck holds the tabulated first loading; Eq. 24 of the same file is far from it."""
    params = PARAM_SETS["first_bump"]
    t = _tables.build_table(params, 1e-3)
    eq24 = params.replace(first_loading_form="eq24")
    q = np.linspace(1e6, params.H, 4000)
    off = np.abs(_tables.table_shear(q, t.p, t.mu, t.cap) - fl.shear_limit(q, 0.0, eq24))
    assert off.max() > 0.05 * params.tau_max
    path = params.to_json(tmp_path / "p.json")
    files, table = exp.render("abaqus-table", path, units="mm-t-s")
    deck = files["sbmf_friction_table.inp"]
    assert "** first-loading SBMF law (form tabulated) as mu(contact pressure)" in deck
    rows = [r for r in deck.splitlines() if r and not r.startswith("*")]
    mu = np.array([float(r.split(",")[0]) for r in rows])
    np.testing.assert_allclose(mu, table.mu, rtol=1e-10)
    readme = files["README.md"]
    assert readme.startswith("# `abaqus-table`: SBMF first-loading law (the tabulated form)")
    assert "First-loading form: `tabulated`" in readme and "cannot carry the history" in readme


def test_a_flat_top_is_capped_at_its_supremum(tmp_path):
    """Two equal contact ratios below 1 at the top: the law stays at 0.8 tau_max above it, and
    so does the table (TAUMAX, VC), whose mu held constant beyond its end would climb to
    tau_max."""
    params = PARAM_SETS["first_flat"]
    path = params.to_json(tmp_path / "p.json")
    cap = 0.8 * params.tau_max
    for target, pattern in (("abaqus-table", "TAUMAX="), ("lsdyna-table", "VC = ")):
        files, table = exp.render(target, path)
        assert table.cap == pytest.approx(cap, rel=1e-15)
        deck = files[exp.target(target).file]
        value = float(deck.split(pattern, 1)[1].split()[0])
        assert value == pytest.approx(cap, rel=1e-10)
        assert "the first loading's supremum" in files["README.md"]
    far = np.array([2.0, 10.0, 1e3]) * params.H
    np.testing.assert_allclose(fl.shear_limit(far, 0.0, params), cap, rtol=1e-15)
    mu_cap = table.mu[-1] * far
    assert np.all(mu_cap > 1.2 * cap)  # why the cap must be the supremum, not tau_max

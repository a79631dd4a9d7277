"""frictionlaw-export: CLI contract, provenance header, friction tables against Eq. 24."""

import hashlib
import re

import numpy as np
import pytest
from default_params import DEFAULT
from reload_tables import STRONG

import frictionlaw as fl
import frictionlaw.export as exp
from frictionlaw.export import _tables
from frictionlaw.export.cli import main
from sbmf_cli import MARKER


@pytest.fixture(scope="module")
def params_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("p") / "params.json"
    fl.FrictionParams(**DEFAULT, p_range=(1e7, 6e8)).to_json(path)
    return path


@pytest.mark.parametrize("target", exp.TARGETS)
@pytest.mark.parametrize("units", ["SI", "mm-t-s"])
def test_every_target_writes_source_and_readme(tmp_path, params_file, target, units):
    out = tmp_path / "out"
    assert main([target, "--params", str(params_file), "--out", str(out), "--units", units]) == 0
    names = sorted(p.name for p in out.iterdir() if p.name != MARKER)
    extra = {"calculix": {"ABA_PARAM.INC", "build.sh", "calculix-2.20-user-friction.patch"}}
    assert set(names) - extra.get(target, set()) - {"README.md"} == {
        next(n for n in names if n.endswith((".f", ".inp", ".k")))
    }
    assert "README.md" in names and len(names) == 2 + len(extra.get(target, ()))
    src = next(out / n for n in names if n.endswith((".f", ".inp", ".k"))).read_text()
    sha = hashlib.sha256(params_file.read_bytes()).hexdigest()
    assert sha in src and f"units: {units}" in src
    assert "fit" in src  # fit summary line (none recorded here)
    if target.endswith("-table"):
        assert "cannot" in (out / "README.md").read_text()  # says what a table cannot do
    else:
        assert max(len(line) for line in src.splitlines()) <= 72  # fixed form


def test_constants_in_host_units(tmp_path, params_file):
    files_si, _ = exp.render("abaqus-fric", params_file, units="SI")
    files_mm, _ = exp.render("abaqus-fric", params_file, units="mm-t-s")
    p = fl.FrictionParams.from_json(params_file)

    def const(text, name):
        m = re.search(rf"PARAMETER \({name} = ([-+0-9.D]+)\)", text)
        return float(m.group(1).replace("D", "e"))

    assert const(files_si["sbmf_fric.f"], "TMAX") == p.tau_max
    assert const(files_si["sbmf_fric.f"], "H") == p.H
    assert const(files_mm["sbmf_fric.f"], "TMAX") == p.tau_max * 1e-6
    assert const(files_mm["sbmf_fric.f"], "H") == p.H * 1e-6
    assert const(files_mm["sbmf_fric.f"], "XN1") == p.n1


def test_bad_input_exit_2_and_no_output(tmp_path, params_file, capsys):
    out = tmp_path / "o"
    assert main(["nastran", "--params", str(params_file), "--out", str(out)]) == 2
    assert main(["lsdyna", "--params", str(params_file), "--out", str(out), "--units", "ft"]) == 2
    assert main(["lsdyna", "--params", str(tmp_path / "none.json"), "--out", str(out)]) == 2
    assert main(["lsdyna", "--params", str(params_file), "--out", str(out), "--k-t", "-1"]) == 2
    args = ["abaqus-table", "--params", str(params_file), "--out", str(out)]
    assert main([*args, "--table-tol", "0.5"]) == 2
    assert main([*args, "--k-t", "1e12"]) == 2  # no option silently ignored
    routine = ["calculix", "--params", str(params_file), "--out", str(out)]
    assert main([*routine, "--table-tol", "1e-2"]) == 2  # a routine has no table
    assert not out.exists()
    err = capsys.readouterr().err
    assert "target must be one of" in err and "Traceback" not in err
    assert "--table-tol applies to the table targets only" in err
    assert main(args) == 0
    assert main(args) == 2  # exists
    assert main([*args, "--force"]) == 0


def test_k_t_table_baked_in(tmp_path):
    kt = fl.params.TangentialStiffness(p=(1e7, 1e8), k_t=(1e12, 4e12))
    path = tmp_path / "p.json"
    fl.FrictionParams(**DEFAULT, k_t=kt).to_json(path)
    files, _ = exp.render("lsdyna", path)
    assert "calibrated k_t(p) table" in files["sbmf_lsdyna.f"]
    files, _ = exp.render("lsdyna", path, k_t=3e12)
    assert "constant k_t = 3e+12" in files["sbmf_lsdyna.f"]


@pytest.mark.parametrize(
    "changes",
    [{}, {"n1": 0.5}, {"n1": 20.0, "geo_ratio": 0.4}, {"C1": 5.0, "m": 0.1}],
)
@pytest.mark.parametrize("tol", [1e-2, 1e-3])
def test_table_within_stated_tolerance(changes, tol):
    p = fl.FrictionParams(**{**DEFAULT, **changes})
    t = _tables.build_table(p, tol)
    assert t.max_error <= tol
    # independent check on a different grid (random pressures up to 50x the last point)
    rng = np.random.default_rng(1)
    q = np.concatenate([rng.uniform(0, 1.2 * t.p[-1], 20000), rng.uniform(0, 50 * t.p[-1], 2000)])
    err = np.abs(_tables.table_shear(q, t.p, t.mu, t.cap) - fl.shear_limit(q, 0.0, p))
    assert err.max() <= tol * p.tau_max
    assert t.p[0] == 0.0 and t.mu[0] == pytest.approx(p.mu_eff, rel=1e-14)
    # the table cannot follow Eq. 25: unloading below p_hist it stays on Eq. 24, off by far
    # more than its tolerance (the documented limitation)
    ph = 0.8 * t.p[-1]
    below = ph * np.linspace(0.05, 0.95, 19)
    miss = fl.shear_limit(below, ph, p) - _tables.table_shear(below, t.p, t.mu, t.cap)
    assert np.abs(miss).max() > 3 * tol * p.tau_max


def test_table_decks_hold_the_table(tmp_path, params_file):
    files, t = exp.render("abaqus-table", params_file, units="mm-t-s")
    deck = files["sbmf_friction_table.inp"]
    rows = [r for r in deck.splitlines() if r and not r.startswith("*")]
    assert len(rows) == len(t.p)
    mu, p = zip(*[(float(r.split(",")[0]), float(r.split(",")[2])) for r in rows], strict=True)
    np.testing.assert_allclose(np.array(p), t.p * 1e-6, rtol=1e-10)
    np.testing.assert_allclose(mu, t.mu, rtol=1e-10)
    assert f"TAUMAX={t.tau_max * 1e-6:.10e}" in deck
    files, t2 = exp.render("lsdyna-table", params_file)
    k = files["sbmf_friction_table.k"]
    assert "*DEFINE_TABLE" in k and k.count("*DEFINE_CURVE") == 2 and "FS = -2" in k


@pytest.mark.parametrize("form", ["paper", "tabulated"])
@pytest.mark.parametrize("units", ["SI", "mm-t-s"])
@pytest.mark.parametrize("target", exp.TARGETS)
def test_every_export_names_its_reload_form(tmp_path, target, units, form):
    """Header and README name the reload form; the tabulated one with its levels (host units),
    C2, n2, s2, the interpolation and the rule beyond the levels; a routine bakes in exactly the
    runtime's knots and slopes, as PARAMETER arrays."""
    table = STRONG if form == "tabulated" else None
    params = fl.FrictionParams(**DEFAULT, reload_form=form, reload_table=table)
    params.to_json(tmp_path / "p.json")
    files, _ = exp.render(target, tmp_path / "p.json", units=units)
    src = next(t for n, t in files.items() if n != "README.md")
    header = " ".join(
        line[2:].strip() for line in src.splitlines() if line[:2] in ("C ", "**", "$ ")
    )
    readme = files["README.md"]
    s = exp.UNIT_SYSTEMS[units]
    assert f"reload form: {form}" in header and f"Reload form: `{form}`" in readme
    if target.endswith("-table"):
        assert "lost, whatever the parameter file's reload form" in readme
    if form == "paper":
        assert f"C2={params.C2!r} n2={params.n2!r}" in header and "SBMF_RTAB" not in src
        return
    levels = ", ".join(repr(v * s.stress) for v in STRONG.p_hist)
    assert f"reload levels p_hist ({s.stress_unit}): {levels}" in header
    assert "reload C2: " + ", ".join(map(repr, STRONG.C2)) in header
    assert "reload n2: " + ", ".join(map(repr, STRONG.n2)) in header
    assert f"s2={STRONG.s2!r}" in header and "Fritsch-Carlson" in header
    assert (
        "(the last two levels' secant, at least 0), at most ln 1e6 (p_hist >= H included)" in header
    )
    for p_hist, c2, n2 in zip(STRONG.p_hist, STRONG.C2, STRONG.n2, strict=True):
        assert f"| {p_hist * s.stress:.6g} | {c2:.6g} | {n2:.6g} |" in readme
    assert "Fritsch-Carlson" in readme and "the last level's" in readme
    if target.endswith("-table"):
        return
    # the knots and slopes, as PARAMETER arrays, are the runtime's coefficients bit for bit
    coeffs = fl.law.sbmf_coeffs(params)
    k = len(STRONG.p_hist)
    for i, name in enumerate(("ZK", "LCK", "DLCK", "LNK", "DLNK")):
        m = re.search(rf"PARAMETER \({name} = \(/\n(.*?) /\)\)", src, re.S)
        values = [float(v.strip(" &,\n").replace("D", "e")) for v in m.group(1).split(",\n")]
        assert values == coeffs[10 + i * k : 10 + (i + 1) * k].tolist(), name
    assert re.search(r"^\s*DATA\b", src, re.M) is None

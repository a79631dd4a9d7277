"""Flattening under bulk strain in fe-demo (issue 43 part C): the die nodes' strain to the law.

The surface projection keeps a uniform Gauss-point field and reads a die node's first element
layer; a run with flattening flattens where the die's bulk has flowed (the contact fraction at
the die rises above the law's alpha1(p) and reaches 1, which raises the friction, the mean
die pressure and the force); a cut-back leaves the flattened fraction as committed; the command runs the law
with and without and reports both; bad options are refused before any run (exit 2).
"""

import json

import numpy as np
import pytest

import frictionlaw as fl
from fe_demo.cli import main
from fe_demo.output.flattening import flattening_record
from fe_demo.scenes import run_upsetting
from fe_demo.scenes.laws import EXAMPLE_FLATTENING_PATH, example_params
from fe_demo.solver.contact import DieContact, surface_projection
from fe_demo.solver.element import kinematics
from fe_demo.solver.mesh import cylinder_mesh
from frictionlaw.flattening_limit import table_pressures

FLAT = fl.FrictionParams.from_json(EXAMPLE_FLATTENING_PATH)
KW = dict(nr=8, n_increments=10, reduction=0.4)


def test_surface_projection_keeps_a_uniform_field_and_reads_the_first_layer():
    axi = cylinder_mesh(20e-3, 10e-3, 6, 4)
    x, t = axi.mesh.p.T, axi.mesh.t
    kin = kinematics(x, t)
    nodes = axi.contact_nodes
    uniform = surface_projection(t, kin.N, kin.dV, np.full(kin.dV.shape, 0.3), nodes)
    assert np.allclose(uniform, 0.3, rtol=1e-14)
    # a field linear in z at the Gauss points: a top node reads its first element layer (a
    # convex mean of its Gauss points, 1.25 mm deep), the same at every top node
    zq = np.einsum("an,ae->en", kin.N, x[t, 1])
    top = nodes[x[nodes, 1] == x[:, 1].max()]
    v = surface_projection(t, kin.N, kin.dV, zq, top)
    assert np.all((v < 5e-3) & (v > 5e-3 - 1.25e-3)) and np.ptp(v) < 1e-15


def test_upsetting_with_flattening_flattens_at_the_die_and_raises_the_die_pressure():
    without = run_upsetting("sbmf", params=FLAT, flattening=False, **KW)
    with_ = run_upsetting("sbmf", params=FLAT, flattening=True, **KW)
    assert without.converged and with_.converged
    h0, h1 = without.history, with_.history
    # without: the contact fraction is the law's alpha1(p) alone, nothing flattened
    assert np.all(h0["alpha_f_max"] == 0.0)
    c = without.model.contact
    on = without.model.accepted.p > 0
    assert np.allclose(c.alpha[on], fl.alpha_first(without.model.accepted.p[on], FLAT), rtol=1e-12)
    # with: flattened beyond alpha1(p) wherever the die's bulk flowed, to full contact here
    assert np.all(h1["alpha_die_mean"] >= h0["alpha_die_mean"] - 1e-12)
    assert h1["alpha_die_mean"][0] > h0["alpha_die_mean"][0] + 0.05
    assert h1["alpha_f_max"][-1] == pytest.approx(1.0, abs=1e-12)
    assert np.all(np.diff(h1["alpha_f_max"]) >= 0) and np.all(h1["eps_p_die_mean"] > 0)
    # more friction at the die: a steeper friction hill, a higher mean die pressure throughout
    # (+8 to +11 % here) and a higher force (+3.6 % at the end; the contact area, which the
    # higher friction keeps smaller, takes part of it back: docs/fe_demo.md)
    assert np.all(h1["avg_pressure"] > 1.05 * h0["avg_pressure"])
    assert np.all(h1["force"] > 1.02 * h0["force"])
    assert h1["contact_radius"][-1] < h0["contact_radius"][-1]
    assert with_.info["law_parameters"]["flattening_run"] is True
    # the flattened fraction is carried by the die's state: beyond alpha1(p_hist) at the die
    st = with_.model.contact.state
    hit = st.alpha_f > 0
    assert hit.any() and np.all(st.alpha_f[hit] >= fl.alpha_first(st.p_hist[hit], FLAT) - 1e-12)


def test_a_cut_back_leaves_the_flattened_fraction_as_committed():
    law = fl.SBMFLaw(FLAT)
    die = DieContact(np.arange(3), law, 1e15, 1e15, flattening=True)
    z = np.full(3, 1e-7)  # penetration 1e-7 m: p = 1e8 Pa
    kw = dict(d_eps=np.array([0.0, 0.01, 0.1]), sigma_y=np.full(3, FLAT.sigma_y))
    ev = die.evaluate(z, 0.0, np.zeros(3), np.ones(3), **kw)
    trial = die.state.alpha_f_trial.copy()
    assert trial[0] == 0.0 and 0 < trial[1] < trial[2] <= 1.0
    die.rollback()
    assert np.array_equal(die.state.alpha_f_trial, np.zeros(3))
    die.evaluate(z, 0.0, np.zeros(3), np.ones(3), **kw)
    die.commit(ev)
    assert np.array_equal(die.state.alpha_f, trial)
    with pytest.raises(ValueError, match="d_eps is given exactly when"):
        die.evaluate(z, 0.0, np.zeros(3), np.ones(3))
    # the flattening needs a law with the block
    with pytest.raises(ValueError, match="flattening needs the law sbmf"):
        run_upsetting("sbmf", params=example_params(), flattening=True, **KW)


def test_cli_flattening_runs_with_and_without(tmp_path, capsys):
    out = tmp_path / "ups"
    assert main(["upsetting", "--flattening", *_small(), "--out", str(out), "--quiet"]) == 0
    rec = {}
    for sub in ("without_flattening", "with_flattening"):
        info = json.loads((out / sub / "summary.json").read_text())
        rec[sub] = info["flattening"]
        assert "Flattening under bulk strain" in (out / sub / "report.html").read_text()
        # the block as the file has it, its model named in the report
        assert info["law_parameters"]["flattening"] == FLAT.to_dict()["flattening"]
        assert "flattening block (model layer-yield)" in (out / sub / "report.html").read_text()
        head = (out / sub / "history.csv").read_text().splitlines()[0]
        assert "alpha_die_mean_fraction" in head and "eps_p_die_mean" in head
    r = rec["with_flattening"]
    assert r == rec["without_flattening"]
    assert r["force_end_with_N"] > r["force_end_without_N"] > 0  # the check, small
    assert r["alpha_die_mean_end_with"] > r["alpha_die_mean_end_without"]
    assert (out / "flattening.png").is_file()


def test_cli_flattening_options_are_checked(tmp_path, capsys):
    plain = tmp_path / "plain.json"
    example_params().to_json(plain)
    for argv, msg in (
        (["--params", str(plain)], "has no flattening block"),
        (["--law", "tresca"], "--flattening needs --law sbmf"),
    ):
        code = main(["upsetting", "--flattening", *argv, "--out", str(tmp_path / "x")])
        assert code == 2 and msg in capsys.readouterr().err
        assert not (tmp_path / "x").exists()
    # a file with a block without --flattening: run without it, and said once
    code = main(["upsetting", "--params", str(EXAMPLE_FLATTENING_PATH), *_small()])
    err = capsys.readouterr().err
    assert code == 0 and err.count("carries a flattening block") == 1


def _small():
    return ["--nr", "6", "--increments", "5", "--reduction", "0.3", "--vtu-every", "0"]


def _fitted(flow_curve):
    """The shipped example with a provenance record of beta fitted to a lab sheet."""
    prov = dict(FLAT.provenance)
    rec = dict(prov.get("flattening") or {})
    rec["fit"] = {"beta": 0.5, "flow_curve": flow_curve}
    prov["flattening"] = rec
    return FLAT.replace(provenance=prov)


def test_a_beta_fitted_as_perfectly_plastic_gets_no_hardening_modulus(tmp_path, capsys):
    """beta fitted without the sheet's flow curve absorbs its hardening: the die passes the
    flow stress but no modulus (Eq. F2c would count the slowing twice), and fe-demo says so;
    with the flow curve, or beta not fitted, the modulus goes to the law."""
    from frictionlaw.flattening import beta_absorbs_hardening

    plastic, curved = _fitted(None), _fitted("Swift: K 530 MPa, eps0 0.006, n 0.24")
    assert beta_absorbs_hardening(plastic) and not beta_absorbs_hardening(curved)
    assert not beta_absorbs_hardening(FLAT)
    die = lambda P: DieContact(np.arange(3), fl.SBMFLaw(P), 1e12, 1e12, flattening=True)  # noqa: E731
    assert not die(plastic).pass_hardening
    assert die(curved).pass_hardening and die(FLAT).pass_hardening
    zoned = fl.ZonedLaw(("rim", "face"), (fl.SBMFLaw(FLAT), fl.SBMFLaw(plastic)))
    assert not DieContact(np.arange(3), zoned, 1e12, 1e12, flattening=True).pass_hardening
    path = tmp_path / "fitted.json"
    plastic.to_json(path)
    argv = ["upsetting", "--flattening", "--params", str(path), *_small()]
    assert main([*argv, "--out", str(tmp_path / "o"), "--quiet"]) == 0
    assert "fitted to a sheet taken as perfectly plastic" in capsys.readouterr().err


def test_a_two_state_block_flattens_at_the_die_without_the_hardening_modulus():
    """The two-state model (limit-analysis) takes no hardening modulus (its table is perfectly
    plastic): the die passes the flow stress alone, the nodes carry slope_f, and the run
    flattens at the die and raises the force as the one-state block does."""
    two = FLAT.replace(flattening=fl.Flattening(FLAT.flattening.slope, model="limit-analysis"))
    die = DieContact(np.arange(3), fl.SBMFLaw(two), 1e12, 1e12, flattening=True)
    assert not die.pass_hardening
    without = run_upsetting("sbmf", params=two, flattening=False, **KW)
    with_ = run_upsetting("sbmf", params=two, flattening=True, **KW)
    assert without.converged and with_.converged
    h0, h1 = without.history, with_.history
    assert h1["alpha_die_mean"][-1] > h0["alpha_die_mean"][-1] + 0.05
    assert np.all(np.diff(h1["alpha_f_max"]) >= 0) and h1["alpha_f_max"][-1] <= 1.0
    assert h1["force"][-1] > h0["force"][-1]
    state = with_.model.contact.state
    touched = state.alpha_f > 0
    assert touched.any() and np.all(state.slope_f[touched] > 0)
    # the flanks turned (flatter at most nodes; the table steepens them a little at high p)
    assert np.any(np.abs(state.slope_f[touched] / two.flattening.slope - 1) > 0.05)
    # the die nodes pressed below the table's lowest pressure are counted (at the node's flow
    # stress), the one-state run has no such column
    n = np.asarray(h1["n_below_flattening_table"])
    ev, mdl = with_.model.accepted, with_.model
    act = ev.p > 0
    eps = mdl.surface_plastic_strain()[act]
    lo = table_pressures(two)[0] * mdl.mat.flow_stress(eps) / two.sigma_y
    assert n[-1] == np.count_nonzero(ev.p[act] < lo) and n.max() >= n[-1] >= 0
    # upsetting presses every die node far above the table (8-20 MPa here): two nodes set to
    # 1 kPa are counted, the others not
    from fe_demo.scenes.drive import _die_fraction

    saved = ev.p.copy()
    try:
        ev.p[np.flatnonzero(act)[:2]] = 1e3
        assert _die_fraction(mdl, act)["n_below_flattening_table"] == n[-1] + 2
    finally:
        ev.p[:] = saved
    assert "n_below_flattening_table" not in run_upsetting("sbmf", params=FLAT, **KW).history
    rec = flattening_record(h0, h1)
    assert rec["n_below_flattening_table_max_with"] == int(n.max())


def test_nodes_below_the_two_state_table_are_said_once(tmp_path, capsys):
    """A comparison whose flattening run counted die nodes below the two-state table says so
    on stderr with the largest and the last count; a run without the column says nothing."""
    from types import SimpleNamespace

    from fe_demo.cli.runs import write_flattening
    from sbmf_cli import Console

    def hist(n):
        h = {"force": [1e5, 2e5], "alpha_die_mean": [0.1, 0.3], "eps_p_die_mean": [0.0, 0.1]}
        h |= {"alpha_f_max": [0.0, 0.4], "height_reduction": [0.1, 0.2]}
        return h | ({"n_below_flattening_table": n} if n is not None else {})

    for n, said in (([3, 1], True), (None, False)):
        runs = [("up", (tmp_path / "a", SimpleNamespace(history=hist(None))),
                 (tmp_path / "b", SimpleNamespace(history=hist(n))))]  # fmt: skip
        write_flattening(Console("fe-demo", quiet=True), tmp_path / "out", runs)
        err = capsys.readouterr().err
        assert (
            "up to 3 die contact nodes pressed below" in err and "(1 at the end)" in err
        ) == said

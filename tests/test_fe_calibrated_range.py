"""fe_demo with a calibrated parameter file: the calibrated-range report and the k_t stick stiffness."""

import json

import numpy as np
import pytest

from fe_demo.cli import main
from fe_demo.scenes import run_multistage, run_ring, run_upsetting
from fe_demo.solver.contact import DieContact
from frictionlaw import FrictionParams, SBMFLaw, TangentialStiffness, alpha_first
from halfspace_calib.pipeline.calibration import Scene, calibrate
from halfspace_calib.pipeline.sweep.scene import PAPER_PRESSURES

SMALL = dict(nr=8, n_increments=10, reduction=0.6)  # 0.6: nodes at p >= H too


@pytest.fixture(scope="module")
def calibrated(tmp_path_factory):
    """The paper's pressures (10-600 MPa, ``--pressures paper``) on a 32^2 grid, with k_t.

    The paper's range leaves nodes both between p_max and H (extrapolated) and at p >= H.
    """
    scene = Scene(grid=32, effects=("normal", "tangential"), pressures=PAPER_PRESSURES)
    cal = calibrate(scene, progress=False)
    path = tmp_path_factory.mktemp("cal") / "params.json"
    cal.params.to_json(path)
    return path


@pytest.fixture(scope="module")
def upset(calibrated):
    return run_upsetting("sbmf", params=calibrated, **SMALL)


def test_calibration_records_range_and_k_t(calibrated):
    P = FrictionParams.from_json(calibrated)
    assert P.p_range == (10e6, 600e6)
    assert P.k_t is not None and P.k_t.p[0] >= 10e6 and P.k_t.p[-1] <= 600e6
    # the file explains itself: m is an input, k derived from sigma_y, the range's meaning
    notes = json.loads(calibrated.read_text())["provenance"]["inputs"]
    assert notes["m"].startswith("input, not fitted") and "ring compression" in notes["m"]
    assert P.k == P.sigma_y / 2 and notes["k"].startswith("derived: sigma_y / 2")
    assert "extrapolated" in notes["calibrated_range"]


def test_upsetting_reports_the_nodes_beyond_the_range(upset, calibrated):
    assert upset.converged
    rec = upset.info["calibrated_range"]
    assert (rec["p_min_Pa"], rec["p_max_Pa"]) == (10e6, 600e6)
    # the end record is the final contact state, counted here independently
    p = upset.model.accepted.p
    ph = np.asarray(upset.model.contact.state.p_hist)
    end = rec["end"]
    assert end["n_contact"] == np.count_nonzero(p > 0)
    H = 800e6
    # extrapolated: p_max < p < H only; the nodes at p >= H (the model's limit) apart
    assert end["n_above_range"] == np.count_nonzero((p > 600e6) & (p < H))
    assert end["n_above_H"] == np.count_nonzero(p >= H) > 0
    assert end["n_hist_above_range"] == np.count_nonzero((ph > 600e6) & (ph < H))
    assert end["n_hist_above_H"] == np.count_nonzero(ph >= H)
    # the law's alpha1 at H: the tabulated first loading extrapolates the 600 MPa level's power
    # law, capped at 1 (Eq. 24 stays below 1: tanh(C1**n1)**(1/n1))
    P = FrictionParams.from_json(calibrated)
    assert rec["H_Pa"] == H and rec["alpha1_at_H"] == pytest.approx(float(alpha_first(H, P)))
    assert 0.9 < rec["alpha1_at_H"] <= 1.0
    assert rec["max_over_run"]["n_above_range"] > 0  # some increment had extrapolated nodes
    assert end["p_peak"] == p.max() and end["p_hist_peak"] == ph.max()
    assert end["p_peak_over_p_max"] == pytest.approx(p.max() / 600e6, rel=1e-15)
    # at 60 % reduction the friction hill goes well beyond 600 MPa at the centre
    assert end["p_peak_over_p_max"] > 1.2
    # max over the run: the largest per-increment value of each column, >= the end
    h = upset.history
    for key, v in rec["max_over_run"].items():
        assert v == h[key].max() >= end[key]
    # p_hist never falls, so its peak is the last increment's
    assert rec["max_over_run"]["p_hist_peak"] == end["p_hist_peak"]
    # early increments stay inside the range (the pressure builds up with the reduction)
    assert h["n_above_range"][0] == 0 and h["p_peak_over_p_max"][0] < 1.0


def test_cli_prints_and_writes_the_range_report(calibrated, tmp_path, capsys):
    out = tmp_path / "ups"
    args = ["--nr", "8", "--increments", "10", "--reduction", "0.6", "--no-progress"]
    argv = ["upsetting", "--params", str(calibrated), "--out", str(out), "--vtu-every", "0"]
    assert main([*argv, *args]) == 0
    cap = capsys.readouterr()
    text, err = cap.out, cap.err
    summary = json.loads((out / "summary.json").read_text())
    end = summary["calibrated_range"]["end"]
    # an extrapolated law is a warning: stderr, not the summary on stdout
    w = summary["calibrated_range"]["max_over_run"]
    assert w["n_above_range"] > 0 and end["n_above_H"] > 0
    assert f"at the end {end['n_above_range']} of {end['n_contact']} contact nodes there" in err
    assert "EXTRAPOLATED between p_max and H" in err and "calibrated range 10-600 MPa" in err
    assert "EXTRAPOLATED" not in text
    # the nodes at p >= H are a result line (the model's limit), not a warning
    assert f"at the end {end['n_above_H']} of {end['n_contact']} contact nodes (p up to" in text
    assert "half-space model's limit p >= H = 800 MPa" in text
    assert "k_t(p) of the parameter file" in summary["tangential_stiffness"]["source"]
    assert "stick stiffness k_t(p) from the parameter file" in text
    header = (out / "history.csv").read_text().splitlines()[0].split(",")
    assert {"n_above_range", "n_above_H", "p_peak_Pa", "p_peak_over_p_max"} <= set(header)


def test_ring_and_multistage_report_the_range(calibrated):
    ring = run_ring("sbmf", params=calibrated, nr=4, n_increments=4, reduction=0.3)
    rec = ring.info["calibrated_range"]
    assert ring.converged and rec["end"]["n_contact"] > 0
    p = ring.model.accepted.p
    assert rec["end"]["n_above_range"] == np.count_nonzero((p > 600e6) & (p < 800e6))
    assert rec["end"]["n_above_H"] == np.count_nonzero(p >= 800e6)
    ms = run_multistage("sbmf", params=calibrated, nr=4, n_increments=6)
    rec = ms.info["calibrated_range"]
    assert ms.converged
    # every stage has the columns; during unloading the contact opens (no node above p_max)
    h = ms.history
    assert h["n_above_range"].size == h["stage"].size
    assert np.all(h["n_above_range"][h["stage"] == 2][-1:] == 0)
    assert rec["max_over_run"]["p_hist_peak"] == h["p_hist_peak"].max()


def test_laws_without_a_range_report_nothing_or_say_so():
    tr = run_upsetting("tresca", nr=4, n_increments=2, reduction=0.1)
    assert tr.info["calibrated_range"] is None and "n_above_range" not in tr.history
    ex = run_upsetting("sbmf", nr=4, n_increments=2, reduction=0.1)  # shipped example: no range
    assert "no calibrated_range" in ex.info["calibrated_range"]["note"]
    assert "n_above_range" not in ex.history


def _contact_one_step(law, p_old, slip):
    """DieContact of 3 nodes after an accepted increment at ``p_old``, then a small slip."""
    n = p_old.size
    c = DieContact(np.arange(n), law, eps_n=1e16, eps_t=1e16)
    c.p_old = p_old.copy()
    g = 300e6 / 1e16  # penetration giving p = 300 MPa now
    return c, c.evaluate(np.full(n, g), 0.0, np.full(n, slip), np.ones(n))


def test_stick_traction_uses_k_t_at_the_start_of_increment_pressure(calibrated):
    P = FrictionParams.from_json(calibrated)
    p_old = np.array([0.0, 50e6, 600e6])
    slip = 1e-12  # m: |k_t slip| <= 6 kPa, far below the friction limit (stick)
    c, ev = _contact_one_step(SBMFLaw(P), p_old, slip)
    kt = P.k_t(p_old)
    assert np.all(ev.status == 1)  # STICK
    np.testing.assert_allclose(ev.tau, kt * slip, rtol=1e-14)
    np.testing.assert_allclose(ev.krr, kt, rtol=1e-14)  # unit areas
    # the pressure now (300 MPa) does not enter k_t: it is fixed over the Newton iterations
    assert not np.allclose(kt, P.k_t(300e6))
    # without the table: the penalty eps_t, as before
    c0, ev0 = _contact_one_step(SBMFLaw(P.replace(k_t=None)), p_old, slip)
    np.testing.assert_allclose(ev0.tau, 1e16 * slip, rtol=1e-14)
    assert c0.stiffness_record()["source"].startswith("penalty")


def test_runs_without_k_t_are_unchanged(calibrated):
    """A k_t table equal to the penalty everywhere reproduces the run without k_t bit for bit."""
    P = FrictionParams.from_json(calibrated).replace(k_t=None)
    kw = dict(nr=4, n_increments=4, reduction=0.3)
    plain = run_upsetting("sbmf", params=P, **kw)
    eps = plain.model.contact.eps_n
    assert plain.info["tangential_stiffness"]["eps_t_Pa_per_m"] == eps
    same = run_upsetting(
        "sbmf", params=P.replace(k_t=TangentialStiffness(p=[1e8], k_t=[eps])), **kw
    )
    assert same.info["tangential_stiffness"]["k_t_max_Pa_per_m"] == eps
    for key, v in plain.history.items():
        np.testing.assert_array_equal(same.history[key], v, err_msg=key)
    # a softer table does change the answer (the stiffness is really used)
    soft = run_upsetting(
        "sbmf", params=P.replace(k_t=TangentialStiffness(p=[1e8], k_t=[eps / 1e4])), **kw
    )
    assert not np.array_equal(soft.history["force"], plain.history["force"])

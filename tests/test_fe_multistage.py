"""Upset - unload - reload: where Eq. 25 (p < p_hist) acts, against a law without history."""

import numpy as np
import pytest

from fe_demo.scenes import run_multistage


@pytest.fixture(scope="module")
def runs():
    out = {}
    for reset in (False, True):
        res = run_multistage("sbmf", nr=12, n_increments=20, reset_history=reset)
        assert res.converged, res.message
        out[reset] = res
    return out


def test_contact_opens_and_eq25_acts_only_on_reload(runs):
    h = runs[False].history
    st = h["stage"]
    # stage 1 is first loading: nobody below p_hist
    assert np.all(h["n_reload_eq25"][st == 1] == 0)
    # unloading opens every contact node (springback)
    assert np.any((st == 2) & (h["force"] == 0))
    # re-contact: nodes come back below their p_hist and use Eq. 25, which changes tau
    recontact = (st == 3) & (h["force"] > 0) & (h["height_reduction"] <= 0.3 + 1e-9)
    assert recontact.sum() >= 2
    assert np.all(h["n_reload_eq25"][recontact] > 0)
    assert h["tau_diff_eq25"][recontact].max() > 5e6  # Pa
    # once the pressure exceeds the history again the law is back on Eq. 24
    late = (st == 3) & (h["height_reduction"] > 0.33)
    assert np.all(h["n_reload_eq25"][late] <= 2)


def test_history_changes_reload_but_not_first_loading(runs):
    a, b = runs[False].history, runs[True].history
    np.testing.assert_array_equal(a["height_reduction"], b["height_reduction"])
    s1 = a["stage"] <= 2
    np.testing.assert_allclose(a["force"][s1], b["force"][s1], rtol=1e-10)
    recontact = (a["stage"] == 3) & (a["force"] > 1e3) & (a["height_reduction"] <= 0.3 + 1e-9)
    # without history the re-contact is first loading again
    assert np.all(b["n_reload_eq25"][recontact] == 0)
    rel = (a["force"][recontact] - b["force"][recontact]) / b["force"][recontact]
    # measured: 2.6 %, 2.0 %, 0.05 % higher force with the history (Eq. 25 raises tau at low p
    # here), fading as the pressure climbs back past p_hist onto Eq. 24
    assert np.all(rel > 0) and 5e-3 < rel.max() < 0.05
    assert np.all(np.diff(rel) < 0) and rel[-1] < 0.1 * rel.max()
    # a higher friction limit holds at least as many nodes in stick, and more somewhere
    stick_a, stick_b = a["n_stick"][recontact], b["n_stick"][recontact]
    assert np.all(stick_a >= stick_b) and np.any(stick_a > stick_b)

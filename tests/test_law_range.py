"""The law's range up to H (issue 26, item 5): the default sweep, the bound alpha >= p / H.

Known answers: Eq. 24 with ``n1 = 1`` is ``tanh(C1 p / H)``, whose violation of the bound
``p / H - tanh(C1 p / H)`` is monotone for ``C1 <= 1`` and so largest at the top pressure; the
half-space model satisfies ``alpha >= p / H`` exactly (no local pressure above H), also at
0.95 H where the contact is nearly complete.
"""

import math

import numpy as np
import pytest

from frictionlaw import FrictionParams, alpha_first
from halfspace_calib.cli import build_parser, scene_from_args
from halfspace_calib.pipeline.calibration import Scene, calibrate, load_scene
from halfspace_calib.pipeline.law import fit as F
from halfspace_calib.pipeline.sweep.scene import (
    DEFAULT_PRESSURES,
    PAPER_PRESSURES,
    default_pressures,
)

H = 800e6


def _law(C1, n1):
    return FrictionParams(m=1.0, sigma_y=H, H=H, C1=C1, n1=n1, C2=1.0, n2=1.0)


def test_floor_violation_known_answers():
    # tanh(x / 2) < x on (0, 1]: the violation grows with x and is largest at p_top
    v, p = F.floor_violation(0.5, 1.0, H, H)
    assert v == pytest.approx(1 - math.tanh(0.5), rel=1e-12) and p == H
    v, p = F.floor_violation(0.5, 1.0, H, 0.5 * H)
    assert v == pytest.approx(0.5 - math.tanh(0.25), rel=1e-12) and p == 0.5 * H
    # C1 = 2, n1 = 50: alpha1 = min(2 x, 1) to 1e-15 below H: the bound holds up to H
    assert F.floor_violation(2.0, 50.0, H, 0.99 * H) == (0.0, 0.99 * H)
    # Eq. 24 cannot reach 1 at H: the violation there is 1 - tanh(C1**n1)**(1/n1) > 0
    v, _ = F.floor_violation(1.05, 3.0, H, H)
    assert v == pytest.approx(1 - math.tanh(1.05**3) ** (1 / 3), rel=1e-12) and v > 0


def _data():
    """Half-space-like first loading: alpha = p/H plus a hump, full contact only at H."""
    p = np.array([10, 25, 50, 100, 200, 300, 400, 500, 600]) * 1e6
    x = p / H
    return p, x + 0.06 * x * (1 - x) ** 0.5


def test_bounded_fit_satisfies_the_bound_and_reports_its_cost():
    p, a = _data()
    free = F.fit_first_loading(p, a, H)
    assert F.floor_violation(free.C1, free.n1, H, 0.99 * H)[0] > 0.01  # the bound is needed
    fit = F.fit_first_loading(p, a, H, floor_to=0.99 * H)
    assert fit.floor_active and fit.converged and fit.floor_to == 0.99 * H
    # the bound holds on a grid finer than the one it was imposed on
    q = np.linspace(1e5, 0.99 * H, 20011)
    assert np.min(alpha_first(q, _law(fit.C1, fit.n1)) - q / H) > -1e-9
    # the cost: R^2 falls, and the record says by how much
    assert fit.r_squared_unconstrained == pytest.approx(free.r_squared, rel=1e-12)
    assert 0 < fit.r_squared_unconstrained - fit.r_squared < 0.01
    rec = fit.floor_record()
    assert rec["r_squared_cost"] == pytest.approx(free.r_squared - fit.r_squared, rel=1e-9)
    assert rec["max_violation_to_p_max"] == 0.0 and rec["p_max_Pa"] == 600e6
    assert rec["alpha1_at_H"] == pytest.approx(1 - rec["max_violation_to_H"], abs=1e-12)
    assert fit.summary()["alpha_floor"] == rec


def test_inactive_bound_keeps_the_unconstrained_fit():
    p = np.geomspace(10e6, 700e6, 12)
    a = alpha_first(p, _law(1.3, 4.0))  # above p / H everywhere below 0.99 H
    free = F.fit_first_loading(p, a, H)
    fit = F.fit_first_loading(p, a, H, floor_to=0.99 * H)
    assert not fit.floor_active and (fit.C1, fit.n1) == (free.C1, free.n1)
    assert fit.floor_record()["r_squared_cost"] == 0.0


def test_floor_to_is_validated():
    p, a = _data()
    with pytest.raises(ValueError, match="floor_to must be <= H"):
        F.fit_first_loading(p, a, H, floor_to=1.1 * H)
    with pytest.raises(ValueError, match="floor_to must be a finite number > 0"):
        F.fit_first_loading(p, a, H, floor_to=-1.0)
    with pytest.raises(ValueError, match=r"alpha_floor must be a fraction of H in \(0, 1\)"):
        Scene(alpha_floor=1.0)


def test_default_sweep_reaches_095_H_and_follows_H():
    assert DEFAULT_PRESSURES[-1] == 0.95 * H and DEFAULT_PRESSURES[:-2] == PAPER_PRESSURES
    assert default_pressures(H) == DEFAULT_PRESSURES
    s = Scene(H=650e6)  # the default sweep follows H: no pressure refused
    assert s.pressures[-1] == pytest.approx(0.95 * 650e6) and max(s.pressures) < 650e6
    assert all(p < 0.85 * 650e6 for p in s.pressures[:-2])
    assert Scene(pressures=PAPER_PRESSURES).pressures == PAPER_PRESSURES


def test_paper_pressures_from_the_cli_and_the_scene_file(tmp_path):
    args = build_parser().parse_args(["--pressures", "paper"])
    assert scene_from_args(args).pressures == PAPER_PRESSURES
    f = tmp_path / "s.toml"
    f.write_text('[scene]\ngrid = 16\npressures = "paper"\n')
    assert load_scene(f).pressures == PAPER_PRESSURES
    f.write_text('[scene]\ngrid = 16\npressures = "papers"\n')
    with pytest.raises(ValueError, match="or 'paper'"):
        load_scene(f)


def test_solver_converges_near_full_contact_and_keeps_the_bound():
    """The default sweep on 32^2: every level converges, alpha >= p / H, also at 0.95 H."""
    cal = calibrate(Scene(grid=32), progress=False)
    assert not cal.problems()
    top = cal.sweeps.levels[-1]
    assert top.p_hist == 760e6 and top.loading.converged
    for lv in cal.sweeps.levels:
        r = lv.loading
        assert r.converged and r.max_pressure <= H * (1 + 1e-9)
        assert r.alpha >= lv.p_hist / H - 1e-12
    assert top.loading.alpha < 1.0  # not yet full contact at 0.95 H
    s = cal.summary()
    assert s["alpha_bound_violation_to_p_max"] == 0.0
    assert 0 <= s["alpha_bound_violation_to_H"] < 0.02
    fits = cal.params.provenance["fit"]  # Eq. 24 beside the tabulated first loading that runs
    prov = fits.get("first_loading_eq24", fits["first_loading"])["alpha_floor"]
    assert prov["imposed_to_Pa"] == pytest.approx(0.99 * H) and prov == s["alpha_floor"]

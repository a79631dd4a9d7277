"""Issue 12, item 17: a fit on a bound or one that explains nothing is flagged as degenerate."""

import numpy as np
import pytest

from frictionlaw import FrictionParams, alpha_first, alpha_reload
from halfspace_calib.pipeline.law import fit as F

H = 800e6
TRUE = FrictionParams(m=0.5, sigma_y=H / 2.8, H=H, C1=1.6, n1=2.5, C2=2.4, n2=1.8)
P = np.array([10, 25, 50, 100, 200, 300, 400, 500, 600]) * 1e6


def test_exact_data_is_not_degenerate():
    r = F.fit_first_loading(P, alpha_first(P, TRUE), H)
    assert r.degenerate == "" and r.converged and r.success
    s = r.summary()
    assert s["degenerate"] == "" and s["converged"] is True and s["success"] is True


def test_constant_alpha_is_degenerate():
    r = F.fit_first_loading(P, np.full(P.size, 0.3), H)
    assert r.r_squared == 0.0
    assert "R^2 = 0 < 0.9" in r.degenerate
    assert not r.converged  # whatever the optimiser's own flag says
    assert r.summary()["degenerate"] == r.degenerate and r.summary()["converged"] is False


def test_decreasing_alpha_explains_nothing():
    r = F.fit_first_loading(P, np.linspace(0.6, 0.1, P.size), H)
    assert r.r_squared < 0
    assert f"R^2 = {r.r_squared:.3g} < 0.9" in r.degenerate
    assert "explains" in r.degenerate and not r.converged


def test_parameter_on_its_bound_is_degenerate():
    r = F.fit_first_loading(P, alpha_first(P, TRUE), H, n_bounds=(0.2, 2.0))
    assert r.r_squared > 0.99  # a good curve, but n1 is not fixed by the data within the bounds
    assert "n1 ended on its bound 2" in r.degenerate and not r.converged


def test_reload_fit_flags_flat_curves():
    curves = [(ph, ph * np.array([0.2, 0.5, 0.8]), np.full(3, 0.2)) for ph in (2e8, 4e8)]
    r = F.fit_reload(curves, H, TRUE.C1, TRUE.n1)
    assert r.degenerate and not r.converged
    good = [(ph, ph * np.array([0.2, 0.5, 0.8])) for ph in (2e8, 4e8)]
    good = [(ph, p, alpha_reload(p, ph, TRUE)) for ph, p in good]
    ok = F.fit_reload(good, H, TRUE.C1, TRUE.n1)
    assert ok.degenerate == "" and ok.converged
    assert ok.summary()["degenerate"] == ""


def test_bounds_outside_the_law_range_are_refused():
    a = alpha_first(P, TRUE)
    with pytest.raises(ValueError, match="n_bounds must lie within"):
        F.fit_first_loading(P, a, H, n_bounds=(1e-4, 10.0))
    with pytest.raises(ValueError, match="C_bounds must lie within"):
        F.fit_first_loading(P, a, H, C_bounds=(1e-3, 1e7))

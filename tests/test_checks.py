"""One validation module: the same value gets the same rule and the same words everywhere."""

import numpy as np
import pytest

from halfspace_calib import Materials, Scene, SolverSettings, sigma_y_from_hardness
from halfspace_calib.common.checks import in_range, positive, tolerance, tresca_factor
from halfspace_calib.studies.presliding import presliding_curve


def test_m_has_one_rule():
    for make in (lambda m: Scene(m=m), lambda m: Materials(m=m), tresca_factor):
        for bad in (-0.1, 1.5, float("nan"), None, True, "0.5"):
            with pytest.raises(ValueError, match=r"m must be in \[0, 1\]"):
                make(bad)
        assert make(0.0) is not None and make(1.0) is not None
    # where m = 0 means nothing, (0, 1] with the reason
    with pytest.raises(ValueError, match=r"m must be in \(0, 1\] \(m = 0: no tangential"):
        presliding_curve(np.ones((4, 4)), 1e-6, materials=Materials(m=0.0))


def test_tolerance_and_positive_have_one_rule():
    for make in (lambda t: SolverSettings(tol=t), tolerance):
        for bad in (0.0, 1.0, -1e-8, float("nan"), "1e-8"):
            with pytest.raises(ValueError, match=r"tol must be in \(0, 1\)"):
                make(bad)
    # a scene also refuses what its solver cannot reach (issue 33: --tol 1e-15)
    for bad in (0.0, 1.0, -1e-8, float("nan"), "1e-8", 1e-15):
        with pytest.raises(ValueError, match=r"tol must be in \[1e-12, 1\)"):
            Scene(tol=bad)
    for bad in (0.0, -1.0, float("inf"), None, False, "1"):
        with pytest.raises(ValueError, match=r"H must be a finite number > 0 \(Pa\)"):
            sigma_y_from_hardness(bad)
    assert positive("dx", np.float32(2.0)) == 2.0
    assert in_range("x", 1, 0, 1) == 1.0
    with pytest.raises(ValueError, match=r"x must be in \[0, 1\), got 1"):
        in_range("x", 1, 0, 1, hi_open=True)


def test_bowden_tabor_is_the_default_yield_stress():
    assert sigma_y_from_hardness(800e6) == 800e6 / 2.8
    assert Scene(H=700e6).sigma_y == Materials(H=700e6).sigma_y == 700e6 / 2.8
    assert Scene(H=700e6, sigma_y=300e6).materials.sigma_y == 300e6

"""check_pressure_range: counts and peaks against the calibrated range, exact on small cases."""

import numpy as np
import pytest

from frictionlaw import FrictionParams, RangeCheck, check_pressure_range

BASE = dict(m=0.5, sigma_y=300e6, H=800e6, C1=1.2, n1=2.0, C2=3.0, n2=1.5)
P = FrictionParams(**BASE, p_range=(25e6, 600e6))


def test_counts_peaks_and_ratio():
    p = np.array([0.0, -1e6, 10e6, 25e6, 300e6, 600e6, 900e6, 1.8e9])
    h = np.array([2e9, 0.0, 10e6, 25e6, 700e6, 600e6, 900e6, 1.8e9])
    c = check_pressure_range(P, p, h)
    assert isinstance(c, RangeCheck)
    assert (c.p_min, c.p_max) == (25e6, 600e6)
    # open nodes (p <= 0) are neither in contact nor below the range; the bounds are inside;
    # 900 MPa and 1.8 GPa are at or above H = 800 MPa: the model's limit, not extrapolated
    assert (c.n_contact, c.n_above, c.n_below, c.n_above_H) == (6, 0, 1, 2)
    # every node's history counts, open or not: 700 MPa between p_max and H, three at >= H
    assert (c.n_hist_above, c.n_hist_above_H) == (1, 3)
    assert (c.p_peak, c.p_hist_peak, c.H) == (1.8e9, 2e9, 800e6)
    assert c.ratio == 3.0 and c.beyond and c.at_limit


def test_nodes_at_H_are_counted_apart_from_the_extrapolated_ones():
    """p_max < p < H is extrapolated; p >= H (H itself included) follows the model's limit."""
    p = np.array([599e6, 600e6, 601e6, 799.9e6, 800e6, 801e6, 5e9])
    c = check_pressure_range(P, p, p)
    assert (c.n_above, c.n_above_H) == (2, 3)
    assert (c.n_hist_above, c.n_hist_above_H) == (2, 3)
    only_limit = check_pressure_range(P, [100e6, 800e6, 1e9])
    assert not only_limit.beyond and only_limit.at_limit and only_limit.n_above_H == 2


def test_inside_the_range_and_without_history():
    c = check_pressure_range(P, [30e6, 600e6])
    assert (c.n_above, c.n_hist_above, c.n_below, c.p_hist_peak) == (0, 0, 0, 0.0)
    assert c.ratio == 1.0 and not c.beyond and not c.at_limit
    empty = check_pressure_range(P, np.zeros(0), np.zeros(0))
    assert (empty.n_contact, empty.p_peak, empty.ratio) == (0, 0.0, 0.0)


def test_no_range_is_a_no_op():
    assert check_pressure_range(FrictionParams(**BASE), [1e12]) is None
    assert check_pressure_range(None, [1e12]) is None


def test_worst_is_the_fieldwise_maximum_over_increments():
    a = check_pressure_range(P, [700e6, 10e6], [700e6, 10e6])
    b = check_pressure_range(P, [500e6, 650e6, 800e6], [900e6, 650e6, 800e6])
    w = a.worst(b)
    # 800 MPa = H is at the limit; 650 and 700 MPa are extrapolated
    assert (w.n_contact, w.n_above, w.n_hist_above, w.n_below) == (3, 1, 1, 1)
    assert (w.n_above_H, w.n_hist_above_H) == (1, 2)
    assert (w.p_peak, w.p_hist_peak) == (800e6, 900e6)
    assert w.ratio == pytest.approx(800 / 600, rel=1e-15)
    assert a.worst(None) is a
    other = check_pressure_range(FrictionParams(**BASE, p_range=(1e6, 1e8)), [1.0])
    with pytest.raises(ValueError, match="same calibrated range"):
        a.worst(other)


def test_nan_is_refused():
    with pytest.raises(ValueError, match="p must not contain NaN"):
        check_pressure_range(P, [np.nan])
    with pytest.raises(ValueError, match="p_hist must not contain NaN"):
        check_pressure_range(P, [1.0], [np.nan])

"""The plot checks of the other tests can fail: a blank figure is refused, a drawn one passes."""

import numpy as np
import pytest
from plotcheck import assert_png_drawn, lines

from halfspace_calib.output._files import pyplot, save_png


def test_blank_png_is_refused_and_a_drawn_one_passes(tmp_path):
    plt = pyplot()
    fig = plt.figure(figsize=(6, 4.2))
    save_png(fig, tmp_path / "blank.png")
    with pytest.raises(AssertionError, match="drawn|colours"):
        assert_png_drawn(tmp_path / "blank.png")
    fig, ax = plt.subplots(figsize=(6, 4.2))
    x = np.linspace(0, 1, 50)
    ax.plot(x, x**2, "o-", label="data")
    ax.legend()
    drawn = save_png(fig, tmp_path / "drawn.png")
    assert_png_drawn(tmp_path / "drawn.png")
    ((gx, gy),) = lines(drawn)
    np.testing.assert_array_equal(gx, x)
    np.testing.assert_array_equal(gy, x**2)

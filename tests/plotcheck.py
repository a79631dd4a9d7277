"""Checks of written plots: the PNG decodes to a drawn picture, and the plotted data is the input's."""

import numpy as np


def assert_png_drawn(path, min_ink=0.02, min_colours=8):
    """The PNG at ``path`` decodes, is of plot size and carries ink in several colours."""
    from matplotlib.image import imread

    img = imread(path)
    assert img.ndim == 3 and min(img.shape[:2]) >= 200, f"{path}: shape {img.shape}"
    rgb = img[..., :3]
    ink = float(np.mean(np.any(rgb < 0.9, axis=-1)))
    assert ink > min_ink, f"{path}: only {100 * ink:.2f} % of the pixels are drawn"
    colours = np.unique(np.round(rgb.reshape(-1, 3) * 255).astype(np.uint8), axis=0)
    assert len(colours) >= min_colours, f"{path}: {len(colours)} colours, a blank plot"


def lines(fig, ax=0):
    """``[(x, y), ...]`` of the lines of axes ``ax`` of ``fig``, in plotting order."""
    return [
        (np.asarray(ln.get_xdata(), float), np.asarray(ln.get_ydata(), float))
        for ln in fig.axes[ax].lines
    ]

"""Tabulated reload forms (frictionlaw.reload_form) as inputs of the export tests.

Eight calibrated levels from 100 to 760 MPa below ``H = 800 MPa`` (the default sweep's range):
``STRONG`` has the default scene's shape (``C2`` rises from 4.5 to 84 while ``n2`` falls from
0.95 to 0.29, s2 = 0.7); ``FLAT`` keeps ``C2`` within 10 % and lets ``n2`` fall tenfold and rise
again (7.3 .. 0.61 .. 0.88, s2 = 0.67: the interpolant's flat stretches at a local minimum);
``SINGLE`` is one level (the core's constant branch), ``PAIR`` two (the straight line).
"""

from frictionlaw.reload_form import ReloadTable

__all__ = ["H", "LEVELS", "STRONG", "FLAT", "SINGLE", "PAIR", "levels"]

H = 800e6
LEVELS = (100e6, 200e6, 300e6, 400e6, 500e6, 600e6, 700e6, 760e6)
STRONG = ReloadTable(
    p_hist=LEVELS,
    C2=(4.5, 4.8, 5.1, 5.6, 7.0, 10.0, 20.8, 83.6),
    n2=(0.95, 0.84, 0.75, 0.71, 0.61, 0.51, 0.40, 0.29),
    s2=0.7,
)
FLAT = ReloadTable(
    p_hist=LEVELS,
    C2=(1.65, 1.64, 1.67, 1.69, 1.62, 1.52, 1.54, 1.61),
    n2=(7.3, 4.8, 2.75, 1.55, 0.87, 0.64, 0.61, 0.88),
    s2=0.67,
)
SINGLE = ReloadTable(p_hist=(400e6,), C2=(7.0,), n2=(0.6,), s2=1.3)
PAIR = ReloadTable(p_hist=(150e6, 700e6), C2=(5.0, 40.0), n2=(0.9, 0.3), s2=0.5)


def levels(params):
    """The calibrated levels of ``params``' tabulated reload form (Pa); () for the paper form."""
    if params.reload_form != "tabulated":
        return ()
    return params.reload_table.p_hist

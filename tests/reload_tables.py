"""Tabulated forms (frictionlaw.reload_form, frictionlaw.first_loading) as inputs of the export tests.

Reload: eight calibrated levels from 100 to 760 MPa below ``H = 800 MPa`` (the default sweep's
range): ``STRONG`` has the default scene's shape (``C2`` rises from 4.5 to 84 while ``n2`` falls
from 0.95 to 0.29, s2 = 0.7); ``FLAT`` keeps ``C2`` within 10 % and lets ``n2`` fall tenfold and
rise again (7.3 .. 0.61 .. 0.88, s2 = 0.67: the interpolant's flat stretches at a local
minimum); ``SINGLE`` is one level (the core's constant branch), ``PAIR`` two (the straight line).

First loading (:data:`FIRST`): the computed first loading at 11 levels from 10 to 760 MPa of
the default scene, of a nearly conforming scan in full contact from 100 MPa (``early_full``) and
of a scan whose ``alpha / (p / H)`` rises (``bump``), as tests/test_first_loading_form.py
measured them (128^2); ``full`` is in full contact from its first level, ``pair`` has the two
levels a table needs at least, and ``flat`` ends on two equal contact ratios below 1 (its end
slope is 0: the law stays at ``alpha = 0.8`` above its top level, it never reaches ``tau_max``).
"""

from test_first_loading_form import P_LEVELS, TABLES

from frictionlaw.first_loading import FirstLoadingTable
from frictionlaw.reload_form import ReloadTable

__all__ = ["H", "LEVELS", "STRONG", "FLAT", "SINGLE", "PAIR", "FIRST", "levels"]

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


FIRST = {
    **{name: FirstLoadingTable(p=P_LEVELS, alpha=a) for name, a in TABLES.items()},
    "full": FirstLoadingTable(p=(20e6, 150e6, 600e6), alpha=(1.0, 1.0, 1.0)),
    "pair": FirstLoadingTable(p=(50e6, 400e6), alpha=(0.08, 0.61)),
    "flat": FirstLoadingTable(p=(10e6, 100e6, 400e6, 700e6), alpha=(0.02, 0.2, 0.8, 0.8)),
}


def levels(params):
    """The calibrated levels of ``params``' tabulated forms (Pa), reload and first loading, sorted;
    () when both run the paper's equations."""
    out = set()
    if params.reload_form == "tabulated":
        out.update(params.reload_table.p_hist)
    if params.first_loading_form == "tabulated":
        out.update(params.first_loading_table.p)
    return tuple(sorted(out))

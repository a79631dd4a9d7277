"""``frictionlaw-demo``: print the law over a pressure range (first loading and a reload).

Exit codes: 0 success, 2 bad input (an unreadable parameter file, a negative ``--p-hist``).
"""

import argparse
import math
import sys

from sbmf_cli import (
    Console,
    HelpFormatter,
    add_version,
    light_entry,
    parse,
    refuse_repeats,
)


def default_params():
    """DC04-like demo parameters (Table 1 hardness; C, n of the order the calibration gives)."""
    from . import FrictionParams

    return FrictionParams(m=0.7, sigma_y=800e6 / 2.8, H=800e6, C1=1.0, n1=2.0, C2=2.5, n2=2.0)


def build_parser():
    """The argument parser of ``frictionlaw-demo``."""
    ap = argparse.ArgumentParser(
        prog="frictionlaw-demo",
        description="Print the friction law over 0-1000 MPa: first loading (Eq. 24) and a reload "
        "from p_hist (Eq. 25).",
        formatter_class=HelpFormatter,
    )
    add_version(ap)
    ap.add_argument("--params", help="FrictionParams JSON file (default: built-in demo set)")
    ap.add_argument(
        "--p-hist", type=float, default=400e6, help="history pressure for the reload column (Pa)"
    )
    return refuse_repeats(ap)  # a value option given twice is refused, not the last kept


def run(argv=None):
    """The command; returns 0, or 2 for bad input (:data:`main` is the console script)."""
    import numpy as np

    from . import FrictionParams, alpha_first, reload_jump, shear_limit

    args, code = parse(build_parser(), argv)
    if args is None:
        return code
    con = Console("frictionlaw-demo")
    if not (math.isfinite(args.p_hist) and args.p_hist >= 0):
        return con.error(f"--p-hist must be a finite pressure >= 0 Pa, got {args.p_hist:g}", 2)
    try:
        params = FrictionParams.from_json(args.params) if args.params else default_params()
    except (OSError, ValueError, TypeError, KeyError) as exc:
        return con.error(f"--params {args.params}: {exc}", 2)
    coeffs = []
    if params.first_loading_form == "eq24":
        coeffs.append(f"C1={params.C1:g} n1={params.n1:g}")
    if params.reload_form == "paper":
        coeffs.append(f"C2={params.C2:g} n2={params.n2:g}")
    con.result(
        f"m={params.m:g} k={(params.k or 0.0) / 1e6:.1f} MPa H={params.H / 1e6:.0f} MPa; "
        f"first loading {params.first_loading_form}, reload {params.reload_form}"
        + (f" ({' '.join(coeffs)})" if coeffs else "")
    )
    con.result(
        f"Coulomb slope at p->0: mu_eff = {params.mu_eff:.4f}; cap m k = {params.tau_max / 1e6:.1f} MPa"
    )
    ph = args.p_hist
    con.result(
        f"{'p [MPa]':>8} {'alpha1':>8} {'tau first [MPa]':>15} {f'tau reload, p_hist={ph / 1e6:.0f} MPa':>28}"
    )
    for p in np.linspace(0, 1000e6, 11):
        t1 = shear_limit(p, 0.0, params)
        t2 = shear_limit(p, ph, params)
        con.result(
            f"{p / 1e6:8.0f} {alpha_first(p, params):8.4f} {t1 / 1e6:15.3f} {t2 / 1e6:28.3f}"
        )
    con.result(
        f"Eq. 25 jump at p_hist = {ph / 1e6:.0f} MPa: {reload_jump(params, ph) / 1e6:.3f} MPa"
    )
    if params.flattening is not None:
        _print_flattening(params, con)
    return 0


#: the equivalent plastic strains and pressures (in H) of the flattening table
FLAT_STRAINS = (0.0, 0.005, 0.01, 0.02, 0.05)
FLAT_P_OVER_H = (0.05, 0.1, 0.3, 0.6)


def _print_flattening(params, con):
    """The flattening block and its contact fraction after bulk strain (docs/flattening.md)."""
    from . import flattening_curve

    f = params.flattening
    band = "" if f.beta_band is None else f" [{f.beta_band[0]:.4g}, {f.beta_band[1]:.4g}]"
    con.result(
        f"flattening under bulk strain (model {f.model}): tan(theta) = {f.slope:.4g}, "
        f"beta = {f.beta:.4g}{band}; "
        "contact fraction at constant p after equivalent plastic strains "
        "(a perfectly plastic bulk at the file's sigma_y):"
    )
    con.result(f"{'p / H':>8} " + " ".join(f"{f'eps {e:g}':>10}" for e in FLAT_STRAINS))
    for x in FLAT_P_OVER_H:
        a = flattening_curve(x * params.H, FLAT_STRAINS, params)
        con.result(f"{x:8g} " + " ".join(f"{v:10.3f}" for v in a))


#: the console script: ``--version`` and Ctrl-C handled before NumPy loads
main = light_entry("frictionlaw-demo", "the demo", lambda: run)

if __name__ == "__main__":
    sys.exit(main())

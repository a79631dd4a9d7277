"""``fe-demo ring-fit``: the command around :mod:`fe_demo.analysis.ringfit`."""

from __future__ import annotations

import dataclasses
from pathlib import Path

from frictionlaw import FrictionParams
from sbmf_cli import OutputFolder, version

from ..analysis.ringfit import RingFitError, fit_m, read_ring_tests
from ..output.ring_fit import write_ring_fit
from ..scenes.laws import EXAMPLE_PARAMS_PATH
from ..solver.material import DC04, Material

__all__ = ["add_parser", "run"]


def add_parser(sub, formatter):
    """The ``ring-fit`` subcommand's options."""
    p = sub.add_parser(
        "ring-fit",
        help="fit the friction factor m of the law to measured ring tests",
        formatter_class=formatter,
    )
    p.add_argument(
        "--measured",
        nargs="+",
        required=True,
        type=Path,
        help="CSV file(s) with height_reduction and inner_diameter_change (mid-plane) or "
        "inner_diameter_min_change, both fractions; rows of all files are pooled (required)",
    )
    p.add_argument(
        "--law", choices=("sbmf", "tresca"), default="sbmf", help="law whose m is fitted"
    )
    p.add_argument(
        "--params",
        type=Path,
        default=None,
        help="SBMF parameter JSON whose m is fitted (law sbmf; default: the shipped "
        "illustrative set)",
    )
    p.add_argument(
        "--accept-failed-fit",
        action="store_true",
        help="use a --params file whose calibration failed (refused otherwise)",
    )
    p.add_argument("--geometry", default="18,9,6", help="ring OD,ID,H in mm")
    p.add_argument(
        "--material", type=Path, default=None, help="material JSON (as fe-demo ring; default: DC04)"
    )
    p.add_argument(
        "--band-level", type=float, default=0.9, help="level of the band on m, in (0, 1)"
    )
    p.add_argument("--nr", type=int, default=16, help="elements across the ring's wall")
    p.add_argument("--nz", type=int, default=None, help="elements over h/2 (default: from --nr)")
    p.add_argument("--increments", type=int, default=50, help="increments to the largest reduction")
    p.add_argument(
        "--workers", type=int, default=None, help="processes for the FE runs (default: 2 if free)"
    )
    p.add_argument("--out", type=Path, default=Path("fe_out/ring_fit"), help="output folder")
    p.add_argument("--quiet", action="store_true", help="print no summary")
    return p


def _geometry(text):
    try:
        od, di, h = (float(v) * 1e-3 for v in str(text).split(","))
    except ValueError:
        raise ValueError(f"--geometry must be OD,ID,H in mm (e.g. 18,9,6), got {text!r}") from None
    if not (0 < di < od and h > 0):
        raise ValueError(f"--geometry needs 0 < ID < OD and H > 0 (mm), got {text!r}")
    return od, di, h


def _check(args):
    """Every input check before any FE run; returns the measured tests and the run keywords."""
    if not (0.0 < args.band_level < 1.0):
        raise ValueError(f"--band-level must be in (0, 1), got {args.band_level:g}")
    for name in ("nr", "increments"):
        if getattr(args, name) < 1:
            raise ValueError(f"--{name} must be >= 1, got {getattr(args, name)}")
    if args.workers is not None and args.workers < 1:
        raise ValueError(f"--workers must be >= 1, got {args.workers}")
    if args.law == "tresca" and args.params is not None:
        raise ValueError("--params is not used by --law tresca (the chart's law has no parameters)")
    od, di, h = _geometry(args.geometry)
    test = read_ring_tests(args.measured)
    params = None
    if args.law == "sbmf":
        src = args.params or EXAMPLE_PARAMS_PATH
        params = FrictionParams.from_json(src, accept_failed=args.accept_failed_fit)
    material = Material.from_json(args.material) if args.material else DC04
    kw = {
        "outer_diameter": od,
        "inner_diameter": di,
        "height": h,
        "nr": args.nr,
        "nz": args.nz,
        "n_increments": args.increments,
        "material": material,
    }
    return test, params, kw


def run(args, con):
    """``fe-demo ring-fit``; returns the exit code."""
    try:
        test, params, kw = _check(args)
        folder = OutputFolder(
            args.out,
            command="fe-demo",
            what="fe-demo output",
            inputs=(*args.measured, args.params, args.material),
        )
    except (ValueError, OSError) as exc:
        return con.error(exc, 2)
    with folder:
        try:
            fit = fit_m(
                test,
                args.law,
                params=params,
                band_level=args.band_level,
                workers=args.workers,
                **kw,
            )
            chart = (
                fit
                if args.law == "tresca"
                else fit_m(test, "tresca", band_level=args.band_level, workers=args.workers, **kw)
            )
        except ValueError as exc:  # points no m in [0, 1] can produce
            return con.error(exc, 2)
        except RingFitError as exc:
            return con.error(exc, 1)
        record = _record(args, test, fit, chart, kw)
        write_ring_fit(folder.tmp, test, fit, chart, params, record)
        folder.commit()
    con.result(
        f"ring fit ({args.law}): m = {fit.m:.4f}  [{fit.m_lower:.4f}, {fit.m_upper:.4f}] at "
        f"{100 * fit.band_level:g} %, rmse {100 * fit.rmse:.2f} points of {test.column}, "
        f"{fit.n_points} points, {fit.n_fe_runs} FE runs"
    )
    if args.law == "sbmf":
        con.result(
            f"  a Tresca chart of the same FE model reads m = {chart.m:.4f} from the same data: "
            f"the chart's m is {chart.m - fit.m:+.4f} off the law's"
        )
    con.result(f"output in {args.out}")
    return 0


def _record(args, test, fit, chart, kw):
    od, di, h = (kw[k] for k in ("outer_diameter", "inner_diameter", "height"))
    mat = kw["material"]
    return {
        "law": fit.law,
        "m": fit.m,
        "m_lower": fit.m_lower,
        "m_upper": fit.m_upper,
        "band_level": fit.band_level,
        "band_method": "linearised least squares: m -+ t(N-1) s / sqrt(sum (dd/dm)^2)",
        "rmse": fit.rmse,
        "n_points": fit.n_points,
        "column": test.column,
        "n_fe_runs": fit.n_fe_runs + (0 if chart is fit else chart.n_fe_runs),
        "m_tresca_chart": chart.m,
        "m_tresca_chart_band": [chart.m_lower, chart.m_upper],
        "bias_chart_minus_law": chart.m - fit.m,
        "geometry_m": {"outer_diameter": od, "inner_diameter": di, "height": h},
        "material": dataclasses.asdict(mat) if dataclasses.is_dataclass(mat) else str(mat),
        "mesh": {"nr": kw["nr"], "nz": kw["nz"], "increments": kw["n_increments"]},
        "measured": list(test.sources),
        "software": {"fe-demo": version()},
    }

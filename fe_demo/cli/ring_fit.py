"""``fe-demo ring-fit``: the command around :mod:`fe_demo.analysis.ringfit`.

Every input is checked, and every hint given, before the first FE run: the law's parameter file
(``--params``, required for ``--law sbmf``; ``--illustrative`` fits the shipped illustrative law
instead and says so), the measured files, and the ring and material, from the options or from
the files' ``# geometry:`` / ``# material:`` lines (conflicting statements are refused). The
fitted ``params.json`` records where ``m`` came from (``provenance.ring_test``).
"""

from __future__ import annotations

import dataclasses
import hashlib
import math
from pathlib import Path

from frictionlaw import FrictionParams
from sbmf_cli import OutputFolder, ParameterError, add_common_options, version

from ..analysis.ringfit import RingFitError, fit_m, read_ring_tests
from ..output.ring_fit import input_rows, write_ring_fit
from ..scenes.laws import EXAMPLE_PARAMS_PATH
from ..solver.material import DC04, Material
from .runs import material_file, path_arg

__all__ = ["add_force", "add_parser", "run"]

#: the standard 6:3:2 ring (OD, ID, H in m) when neither the option nor the files state one
STANDARD_RING = (18e-3, 9e-3, 6e-3)
#: relative distance of the calibration's sigma_y from the material's flow stress that is warned
SIGMA_Y_TOLERANCE = 0.3


def add_force(p):
    """``--force``: replace an fe-demo output whose marker names no subcommand."""
    p.add_argument(
        "--force",
        action="store_true",
        help="replace an earlier fe-demo output whose marker names no subcommand (written by "
        "an earlier version); never another subcommand's or command's output, nor files "
        "fe-demo did not write",
    )


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
        help="CSV file(s) with the height reduction and the inner-diameter change (mid-plane, "
        "or of the smallest inner diameter), as fe-demo's history.csv names them or as labs "
        "write them in English or German ('height reduction (%%)', 'Höhenabnahme [%%]', "
        "'ID change', ...), fractions or percent as the header says; rows of all files are "
        "pooled; comma or semicolon separated, '# geometry:' and '# material:' lines state the "
        "test (docs/getting_m.md) (required)",
    )
    p.add_argument(
        "--law", choices=("sbmf", "tresca"), default="sbmf", help="law whose m is fitted"
    )
    p.add_argument(
        "--params",
        type=path_arg,
        default=None,
        help="the calibration's SBMF parameter JSON whose m is fitted (halfspace-calib's "
        "params.json; required for --law sbmf unless --illustrative; default: none)",
    )
    p.add_argument(
        "--illustrative",
        action="store_true",
        help="fit the m of fe-demo's shipped illustrative, uncalibrated SBMF law instead of "
        "--params (a demonstration: the output says 'illustrative')",
    )
    p.add_argument(
        "--accept-failed-fit",
        action="store_true",
        help="use a --params file whose calibration failed (refused otherwise)",
    )
    p.add_argument(
        "--geometry",
        default=None,
        help="ring OD,ID,H in mm (default: the files' '# geometry:' line, else the standard "
        "18,9,6 with a warning)",
    )
    p.add_argument(
        "--material",
        type=path_arg,
        default=None,
        help="material JSON (as fe-demo ring; default: the files' '# material:' line, else DC04)",
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
    add_force(p)
    add_common_options(p)
    return p


@dataclasses.dataclass
class _Inputs:
    """What a ring fit runs on, decided before any FE run."""

    test: object
    params: FrictionParams | None
    params_file: dict | None  # path, sha256, illustrative
    kw: dict
    geometry_source: str
    material_source: str
    warnings: list


def _geometry(text):
    try:
        od, di, h = (float(v) * 1e-3 for v in str(text).split(","))
    except ValueError:
        raise ValueError(f"--geometry must be OD,ID,H in mm (e.g. 18,9,6), got {text!r}") from None
    if not (0 < di < od and h > 0):
        raise ValueError(f"--geometry needs 0 < ID < OD and H > 0 (mm), got {text!r}")
    return od, di, h


def _mm(g):
    return ",".join(f"{1e3 * v:g}" for v in g)


def _choose_geometry(args, test):
    """``((OD, ID, H) in m, source, warning or None)``: the option, the files', or the standard."""
    stated = test.geometry
    files = ", ".join(Path(s).name for s in test.sources)
    if stated is not None:
        stated = (stated["outer_diameter"], stated["inner_diameter"], stated["height"])
    if args.geometry is not None:
        given = _geometry(args.geometry)
        if stated is not None and any(
            not math.isclose(a, b, rel_tol=1e-6) for a, b in zip(given, stated, strict=True)
        ):
            raise ValueError(
                f"--geometry {_mm(given)} mm differs from the ring {files} states "
                f"({_mm(stated)} mm, OD,ID,H): the fit needs the ring that was tested; give the "
                "right one (or drop --geometry to use the file's)"
            )
        return given, "option --geometry", None
    if stated is not None:
        return stated, f"stated in {files}", None
    warning = (
        f"fe-demo: WARNING: the ring's geometry is stated neither by --geometry nor in {files}: "
        f"the standard 6:3:2 ring {_mm(STANDARD_RING)} mm (OD,ID,H) is assumed; a ring of "
        "another geometry gives a wrong m (state it with --geometry OD,ID,H or a "
        "'# geometry: OD = .. mm, ID = .. mm, H = .. mm' line)"
    )
    return STANDARD_RING, "standard 6:3:2 ring (not stated)", warning


def _choose_material(args, test):
    """``(Material, source)``: the option's file, the measured files', or DC04."""
    files = ", ".join(Path(s).name for s in test.sources)
    stated = Material(**test.material) if test.material is not None else None
    if args.material is not None:
        given = material_file(args.material)
        if stated is not None and any(
            not math.isclose(getattr(given, k), getattr(stated, k), rel_tol=1e-6)
            for k in ("E", "nu", "K", "eps0", "n")
        ):
            raise ValueError(
                f"--material {args.material} ({_material_text(given)}) differs from the material "
                f"{files} states ({_material_text(stated)}): give the tested one"
            )
        return given, f"option --material {args.material}"
    if stated is not None:
        return stated, f"stated in {files}"
    return DC04, "DC04 (fe-demo's default)"


def _material_text(mat):
    return (
        f"E {mat.E / 1e9:g} GPa, nu {mat.nu:g}, K {mat.K / 1e6:g} MPa, eps0 {mat.eps0:g}, "
        f"n {mat.n:g}"
    )


def flow_stress_warning(material, params, reduction_max):
    """A warning where the material does not flow at the calibration's ``sigma_y`` (or ``None``).

    The calibration's conditions are its yield stress ``sigma_y`` (the softer body's, with
    ``H``); the ring test strains the material from 0 to the homogeneous strain
    ``ln(1 / (1 - reduction_max))``. Where ``sigma_y`` is more than :data:`SIGMA_Y_TOLERANCE`
    away from every flow stress the material has over that range, the law was calibrated for
    another material (a DC04 calibration with aluminium ring tests).
    """
    lo = float(material.flow_stress(0.0))
    hi = float(material.flow_stress(math.log(1.0 / (1.0 - reduction_max))))
    nearest = min(max(params.sigma_y, lo), hi)
    if abs(params.sigma_y - nearest) <= SIGMA_Y_TOLERANCE * nearest:
        return None
    return (
        f"fe-demo: WARNING: the calibration's sigma_y = {params.sigma_y / 1e6:.4g} MPa "
        f"(H = {params.H / 1e6:.4g} MPa) differs by more than {100 * SIGMA_Y_TOLERANCE:g} % from "
        f"the material's flow stress over the ring test, {lo / 1e6:.4g}-{hi / 1e6:.4g} MPa "
        f"(nearest {nearest / 1e6:.4g} MPa): the law was calibrated for another material; check "
        "--material (or the file's '# material:' line) and --params"
    )


def _file_record(path, illustrative=False):
    path = Path(path)
    digest = hashlib.sha256(path.read_bytes()).hexdigest()
    return {"path": str(path.resolve()), "sha256": digest, "illustrative": illustrative}


def _law_params(args, warnings):
    """The parameter set whose m is fitted (``None`` for the chart's law) and its file record."""
    if args.law == "tresca":
        for name, given in (("--params", args.params), ("--illustrative", args.illustrative)):
            if given:
                raise ValueError(
                    f"{name} is not used by --law tresca (the chart's law has no parameters)"
                )
        return None, None
    if args.params is None and not args.illustrative:
        raise ValueError(
            "--params is required with --law sbmf: the calibration's parameter file "
            "(halfspace-calib's params.json) whose m is fitted; --illustrative fits fe-demo's "
            "shipped illustrative, uncalibrated law instead (a demonstration)"
        )
    if args.params is not None and args.illustrative:
        raise ValueError("give --params or --illustrative, not both")
    if args.illustrative:
        warnings.append(
            "fe-demo: WARNING: --illustrative: m is fitted with fe-demo's shipped illustrative "
            "law (C1 = 2, n1 = 2, C2 = 4, n2 = 2, not calibrated); the params.json written is "
            "marked illustrative, NOT a calibration result"
        )
        return FrictionParams.from_json(EXAMPLE_PARAMS_PATH), _file_record(
            EXAMPLE_PARAMS_PATH, True
        )
    if not args.params.is_file():
        raise ParameterError(f"{{params}} file {args.params} does not exist", "params")
    params = FrictionParams.from_json(args.params, accept_failed=args.accept_failed_fit)
    return params, _file_record(args.params)


def _check(args):
    """Every input check before any FE run (:class:`_Inputs`)."""
    if not (0.0 < args.band_level < 1.0):
        raise ValueError(f"--band-level must be in (0, 1), got {args.band_level:g}")
    for name in ("nr", "increments"):
        if getattr(args, name) < 1:
            raise ValueError(f"--{name} must be >= 1, got {getattr(args, name)}")
    if args.workers is not None and args.workers < 1:
        raise ValueError(f"--workers must be >= 1, got {args.workers}")
    warnings = []
    params, params_file = _law_params(args, warnings)
    test = read_ring_tests(args.measured)
    (od, di, h), geometry_source, hint = _choose_geometry(args, test)
    material, material_source = _choose_material(args, test)
    if hint:
        warnings.append(hint)
    if params is not None:
        hint = flow_stress_warning(material, params, float(test.reduction.max()))
        if hint:
            warnings.append(hint)
    kw = {
        "outer_diameter": od,
        "inner_diameter": di,
        "height": h,
        "nr": args.nr,
        "nz": args.nz,
        "n_increments": args.increments,
        "material": material,
    }
    return _Inputs(test, params, params_file, kw, geometry_source, material_source, warnings)


def run(args, con):
    """``fe-demo ring-fit``; returns the exit code."""
    try:
        inp = _check(args)
        folder = OutputFolder(
            args.out,
            command="fe-demo",
            subcommand="ring-fit",
            what="fe-demo output",
            force=args.force,
            inputs=(*args.measured, args.params, args.material),
        )
    except (ValueError, OSError) as exc:
        return con.error(exc, 2)
    for line in inp.warnings:
        con.warn(line)
    for note in inp.test.notes:
        con.warn(f"fe-demo: note: {note}")
    progress = not (args.quiet or args.no_progress)
    with folder:
        try:
            fit, chart = _fits(args, inp, progress)
        except ValueError as exc:  # points no m in [0, 1] can produce
            return con.error(exc, 2)
        except RingFitError as exc:
            return con.error(exc, 1)
        record = _record(inp, fit, chart)
        _summary(con, args, inp, fit, chart, record)
        try:
            write_ring_fit(
                folder.tmp, inp.test, fit, chart, _fitted_params(inp, fit, record), record
            )
            con.write_summary(folder.tmp)
            folder.commit()
        except OSError as exc:  # writing the outputs (disk full, permissions changed meanwhile)
            return con.error(f"the outputs could not be written, {args.out} is unchanged: {exc}", 1)
    con.result(f"output in {args.out}")
    return 0


def _fits(args, inp, progress):
    """The law's fit and the Tresca chart's (the same fit with ``--law tresca``)."""
    kw = dict(band_level=args.band_level, workers=args.workers, progress=progress, **inp.kw)
    fit = fit_m(inp.test, args.law, params=inp.params, **kw)
    chart = fit if args.law == "tresca" else fit_m(inp.test, "tresca", **kw)
    return fit, chart


def _summary(con, args, inp, fit, chart, record):
    test = inp.test
    runs = (
        f"{record['n_fe_runs']} FE runs"
        if chart is fit
        else f"{record['n_fe_runs']} FE runs ({fit.n_fe_runs} for the law's fit, "
        f"{chart.n_fe_runs} for the chart's)"
    )
    con.result(
        f"ring fit ({args.law}): m = {fit.m:.4f}  [{fit.m_lower:.4f}, {fit.m_upper:.4f}] at "
        f"{100 * fit.band_level:g} %, rmse {100 * fit.rmse:.2f} % (percentage points of "
        f"{test.column}; ring_fit.json rmse_fraction {fit.rmse:.3g}), "
        f"{fit.n_points} points, {runs}"
    )
    if chart is not fit:
        con.result(
            f"  a Tresca chart of the same FE model reads m = {chart.m:.4f} from the same data: "
            f"the chart's m is {chart.m - fit.m:+.4f} off the law's"
        )
    for line in _input_lines(record):
        con.result(f"  {line}")


def _illustrative(inp):
    return bool(inp.params_file and inp.params_file["illustrative"])


def _input_lines(record):
    """What the fit ran on, one line each (console, summary.txt): the report's input rows."""
    return [f"{what}: {value} ({source})" for what, value, source in input_rows(record)]


def _record(inp, fit, chart):
    """The ``ring_fit.json`` record (``provenance.ring_test`` of the fitted params.json)."""
    kw, test = inp.kw, inp.test
    od, di, h = (kw[k] for k in ("outer_diameter", "inner_diameter", "height"))
    mat = kw["material"]
    files = [
        {"path": str(Path(p).resolve()), "sha256": s}
        for p, s in zip(test.sources, test.sha256, strict=True)
    ]
    return {
        "law": fit.law,
        "m": fit.m,
        "m_lower": fit.m_lower,
        "m_upper": fit.m_upper,
        "band_level": fit.band_level,
        "band_method": "linearised least squares: m -+ t(N-1) s / sqrt(sum (dd/dm)^2)",
        "rmse_fraction": fit.rmse,
        "n_points": fit.n_points,
        "column": test.column,
        "n_fe_runs": fit.n_fe_runs + (0 if chart is fit else chart.n_fe_runs),
        "m_tresca_chart": chart.m,
        "m_tresca_chart_band": [chart.m_lower, chart.m_upper],
        "bias_chart_minus_law": chart.m - fit.m,
        "source_params": inp.params_file,
        "illustrative": _illustrative(inp),
        "geometry_m": {"outer_diameter": od, "inner_diameter": di, "height": h},
        "geometry_source": inp.geometry_source,
        "material": dataclasses.asdict(mat),
        "material_source": inp.material_source,
        "mesh": {"nr": kw["nr"], "nz": kw["nz"], "increments": kw["n_increments"]},
        "measured": list(test.sources),
        "measured_files": files,
        "measured_notes": list(test.notes),
        "software": {"fe-demo": version()},
    }


def _fitted_params(inp, fit, record):
    """The law's parameter set with the fitted m, its provenance saying where m came from."""
    if inp.params is None:
        return None
    prov = dict(inp.params.provenance)
    prov["material"] = {**prov.get("material", {}), "m": fit.m}
    names = ", ".join(Path(f["path"]).name for f in record["measured_files"])
    prov["inputs"] = {
        **prov.get("inputs", {}),
        "m": f"fitted to ring-compression tests by fe-demo ring-fit: m = {fit.m:.4f} "
        f"[{fit.m_lower:.4f}, {fit.m_upper:.4f}] at {100 * fit.band_level:g} %, "
        f"{fit.n_points} points of {record['column']} ({names}); see provenance.ring_test",
    }
    prov["ring_test"] = {k: v for k, v in record.items() if k != "software"}
    if _illustrative(inp):
        prov["note"] = (
            "illustrative: m fitted with fe-demo's shipped illustrative law (C1, n1, C2, n2 not "
            "calibrated), NOT a calibration result; fit with --params <calibration> instead"
        )
    return inp.params.replace(m=fit.m, provenance=prov)

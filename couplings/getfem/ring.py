"""Ring compression in GetFEM with the ``frictionlaw`` runtime at the die-contact nodes.

GetFEM (Debian's ``python3-getfem``) supplies the mesh, the finite elements, the
finite-strain J2 plasticity (its ``Simo_Miehe`` brick, displacement / plastic
multiplier / pressure formulation) and the assembly of the bulk tangent and
residual. This script supplies what a host code's contact algorithm does around
a friction user routine: a rigid flat die, a nodal penalty for the normal
pressure, and per contact node a call of :func:`frictionlaw.traction_update` with
the node's :class:`frictionlaw.HistoryState` (``p_hist``). The Newton loop is ours
(GetFEM's ``Model.solve`` cannot call back into Python per iteration): each
iteration GetFEM assembles, the contact terms are added to its tangent and
residual, and the linear system is solved with SciPy.

GetFEM has no axisymmetric finite-strain plasticity, so the ring is a 3D wedge
(one element over ``--sector`` degrees) with symmetry conditions on both cut
faces: ``u_y = 0`` on the ``theta = 0`` face (removed dofs) and a penalty on the
normal displacement of the ``theta = sector`` face. The half height is modelled
(``u_z = 0`` on the mid-plane), as in ``fe-demo ring``.

``p_hist`` lives in one ``HistoryState`` over the candidate nodes (every boundary
node off the mid-plane and the cut faces, as in ``fe-demo``): every Newton
iteration proposes a trial from the committed history; ``commit()`` runs only
after the increment converged (together with GetFEM's
``finite_strain_elastoplasticity_next_iter``), ``rollback()`` on a cut-back, which
also restores every GetFEM variable.

Run it with a Python in which ``import getfem`` works (Debian's ``/usr/bin/python3``
with ``python3-getfem python3-numba python3-scipy``) and the repository root on
``PYTHONPATH``::

    PYTHONPATH=$PWD /usr/bin/python3 couplings/getfem/ring.py --law tresca --m 0.3

It writes ``history.csv`` (``height_reduction_fraction, force_N,
inner_diameter_change_fraction`` first, units in the names as ``fe-demo ring`` writes them;
``stage`` last), ``summary.json`` (with the die-face ``p_hist``
after each stage) and ``summary.txt`` into ``--out``, whole or not at all, under the command
conventions of the other commands (:mod:`sbmf_cli`: an earlier output of this script is
replaced, anything else refused; ``--quiet``, ``--no-progress``, ``--version``).
``--first-reduction R1`` runs press-lift-press (``fe-demo multistage``'s schedule,
:func:`schedule`): Eq. 25 acts on the reload. Exit status 0 when every increment converged, 1
when the run stopped on a failed increment, 2 for bad input, 130/143 when interrupted.
"""

import argparse
import json
import math
import sys
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from couplings.getfem._wedge import (
    Contact,
    build_model,
    element_size,
    elements_over_half_height,
    face_nodes,
    newton,
    nodal_areas,
    node_displacements,
    set_regions,
    wedge_mesh,
)
from sbmf_cli import (
    Console,
    HelpFormatter,
    OutputFolder,
    ParameterError,
    add_common_options,
    add_version,
    column_name,
    flags_of,
    interruptible,
    parse,
    refuse_repeats,
)

__all__ = ["Material", "RingSetup", "run", "main", "HISTORY_COLUMNS"]

HISTORY_COLUMNS = (
    "height_reduction",
    "force",
    "inner_diameter_change",
    "stroke",
    "contact_radius",
    "n_stick",
    "n_slip",
    "n_open",
    "n_reload_eq25",
    "max_p_hist",
    "nit",
    "cutbacks",
    "min_plastic_multiplier",
    "stage",
)
#: the unit of each column, stated in its name as fe-demo's history.csv states it
#: (sbmf_cli.column_name: ``force_N``, ``height_reduction_fraction``)
HISTORY_UNITS = {
    "height_reduction": "fraction",
    "force": "N",
    "inner_diameter_change": "fraction",
    "stroke": "m",
    "contact_radius": "m",
    "max_p_hist": "Pa",
}

_EXAMPLE_PARAMS = Path(__file__).resolve().parents[2] / "fe_demo" / "data" / "sbmf_example.json"


@dataclass(frozen=True)
class Material:
    """Swift-hardening J2 material (SI); the defaults are ``fe-demo``'s DC04-like set."""

    E: float = 210e9
    nu: float = 0.3
    K: float = 530e6
    eps0: float = 0.006
    n: float = 0.24

    def flow_stress(self, eps_p):
        """Swift flow stress ``K (eps0 + eps_p) ** n`` (Pa)."""
        return self.K * (self.eps0 + eps_p) ** self.n


@dataclass
class RingSetup:
    """Geometry, mesh and solver settings of the ring run (SI units)."""

    law: str = "tresca"
    m: float = 0.3
    params: str = ""
    outer_diameter: float = 18e-3
    inner_diameter: float = 9e-3
    height: float = 6e-3
    nr: int = 16
    nz: int = 0  # 0: near-square elements, round(nr * (h/2) / wall) as in fe-demo
    sector_deg: float = 5.0
    reduction: float = 0.5
    increments: int = 50
    penalty_factor: float = 10.0
    rtol: float = 1e-6
    max_iter: int = 25
    max_cutbacks: int = 6
    first_reduction: float = 0.0  # > 0: press to it, lift, press again (Eq. 25 on reload)
    n_unload: int = 4
    lift_factor: float = 3.0
    material: Material = field(default_factory=Material)


def _check(setup):
    """Bad input: a clear error naming the parameter (:class:`sbmf_cli.ParameterError`)."""
    s = setup
    _require("law", s.law, s.law in ("none", "tresca", "sbmf"), "one of 'none', 'tresca', 'sbmf'")
    _require("m", s.m, 0.0 <= s.m <= 1.0, "in [0, 1]")
    _require("reduction", s.reduction, 0.0 < s.reduction < 0.9, "in (0, 0.9)")
    _require("nz", s.nz, int(s.nz) >= 0, ">= 0 (0: near-square elements)")
    _require("nr", s.nr, int(s.nr) >= 1, ">= 1")
    _require("increments", s.increments, int(s.increments) >= 1, ">= 1")
    _require("sector_deg", s.sector_deg, 0.0 < s.sector_deg <= 30.0, "in (0, 30]")
    _require(
        "inner_diameter",
        s.inner_diameter,
        0.0 < s.inner_diameter < s.outer_diameter,
        f"in (0, outer_diameter = {s.outer_diameter!r})",
    )
    _require(
        "first_reduction",
        s.first_reduction,
        0.0 <= s.first_reduction < s.reduction,
        f"in [0, reduction = {s.reduction!r}) (0: one press)",
    )
    _require("n_unload", s.n_unload, int(s.n_unload) >= 1, ">= 1")
    if s.law == "sbmf" and s.params and not Path(s.params).is_file():
        raise ParameterError(f"{{params}}: no such file {s.params!r}", "params")


def _require(name, value, ok, allowed):
    if not ok:
        raise ParameterError(f"{{{name}}} must be {allowed}, got {value!r}", name)


def _law(s, model_height_ratio):
    import frictionlaw as fl

    if s.law == "none":
        return None
    if s.law == "tresca":
        eps = max(math.log(model_height_ratio), 0.0)
        return fl.Tresca(s.m, float(s.material.flow_stress(eps)) / math.sqrt(3.0))
    path = s.params or str(_EXAMPLE_PARAMS)
    return fl.SBMFLaw(fl.FrictionParams.from_json(path))


def run(setup, progress=False):
    """Run the ring; returns ``(converged, message, rows, info)``."""
    _check(setup)
    import getfem as gf

    import frictionlaw as fl

    gf.util_trace_level(0)
    s = setup
    t0 = time.perf_counter()
    mesh, r, z = wedge_mesh(gf, s)
    rg, cand_faces = set_regions(mesh, math.radians(s.sector_deg))
    model = build_model(gf, s, mesh, rg)
    quads = face_nodes(mesh, cand_faces)
    nodes = np.unique(quads)
    h_el = element_size(s)
    eps_n = s.penalty_factor * s.material.E / h_el
    ct = Contact(nodes, quads, None, eps_n, fl.HistoryState(nodes.size), np.zeros((nodes.size, 2)))
    hh0 = s.height / 2
    ri = s.inner_diameter / 2
    inner_mid = int(np.flatnonzero((np.abs(model.X[:, 0] - ri) < 1e-12) & (model.X[:, 2] == 0))[0])
    scale = 2.0 * math.pi / math.radians(s.sector_deg)
    top_area = 0.5 * math.radians(s.sector_deg) * ((s.outer_diameter / 2) ** 2 - ri**2)
    f_ref = 1e-3 * s.material.flow_stress(0.0) * top_area
    z_die = hh0
    rows, log, profiles = [], [], []
    ok, message = True, "converged"
    n_newton = 0
    iu = model.md.interval_of_variable("u")
    iu = slice(iu[0], iu[0] + iu[1])
    for z_end, n_seg, stage in schedule(s):
        dz0 = (z_end - z_die) / n_seg
        sgn = -1.0 if dz0 < 0 else 1.0
        dz = dz0
        du_prev, dz_prev = None, None  # no predictor across a change of direction
        while sgn * (z_end - z_die) > 1e-12 * hh0:
            backup = model.md.from_variables()
            u_start = node_displacements(model, backup)
            area = nodal_areas(model, ct, u_start)
            ct.law = _law(s, hh0 / z_die)
            cut = 0
            while True:
                target = z_die + dz
                target = max(target, z_end) if sgn < 0 else min(target, z_end)
                if du_prev is not None and cut == 0:  # predictor: the last increment's rate
                    guess = backup.copy()
                    guess[iu] += du_prev * ((target - z_die) / dz_prev)
                    model.md.to_variables(guess)
                inc = newton(model, ct, s, target, u_start[ct.nodes], area, f_ref)
                n_newton += inc.nit
                if inc.converged:
                    break
                model.md.to_variables(backup)
                ct.state.rollback()
                cut += 1
                log.append(f"cut-back at die z {target:.6e} m: {inc.message}")
                if cut > s.max_cutbacks:
                    ok = False
                    message = (
                        f"increment failed at height reduction {1 - z_die / hh0:.4f} "
                        f"(stage {stage}) after {s.max_cutbacks} cut-backs: {inc.message}"
                    )
                    break
                dz *= 0.5
            if not ok:
                break
            model.md.finite_strain_elastoplasticity_next_iter(*model.plast_args)
            ct.state.commit()
            ct.t_old = np.where(inc.p[:, None] > 0, inc.t, 0.0)
            v = model.md.from_variables()
            du_prev, dz_prev = v[iu] - backup[iu], target - z_die
            z_die = target
            if cut == 0:  # grow back to at most the nominal step
                dz = sgn * min(2.0 * abs(dz), abs(dz0))
            u_all = node_displacements(model, v)
            row = _row(s, model, ct, inc, u_all, z_die, hh0, inner_mid, scale, cut)
            row["stage"] = stage
            rows.append(row)
            if progress:
                print(
                    f"stage {stage} reduction {row['height_reduction']:.3f} force "
                    f"{row['force']:.4e} N inner {row['inner_diameter_change']:+.4f} "
                    f"nit {inc.nit}",
                    file=sys.stderr,
                )
        if not ok:
            break
        if stage == 2 and rows and rows[-1]["n_open"] < ct.nodes.size:
            ok, message = False, "contact did not open during the lift (raise lift_factor)"
            break
        profiles.append(
            _profile(model, ct, node_displacements(model, model.md.from_variables()), rows)
        )
    info = {
        "code": "GetFEM",
        "getfem_version": _getfem_version(),
        "setup": _jsonable(asdict(s)),
        "n_hexahedra": int(s.nr * elements_over_half_height(s)),
        "n_dof": int(model.n_total),
        "n_contact_candidates": int(nodes.size),
        "newton_iterations": int(n_newton),
        "cutback_log": log,
        "wall_time_s": time.perf_counter() - t0,
        "converged": ok,
        "message": message,
        "schedule": [[z, n, st] for z, n, st in schedule(s)],
    }
    info["p_hist_profiles"] = profiles
    return ok, message, rows, info


def schedule(s):
    """Die targets ``[(z_die, n_increments, stage), ...]`` of a run (half height model).

    One press: ``[(h/2 (1 - reduction), increments, 1)]``. With ``first_reduction > 0``,
    ``fe-demo multistage``'s schedule: press to ``first_reduction`` (stage 1, the share
    ``first_reduction / reduction`` of the increments), lift the die by ``lift_factor``
    times the elastic springback ``sigma_f h / E`` (stage 2, ``n_unload`` increments; every
    node must open), come back to the stage-1 position in ``2 n_unload`` increments and
    press on to ``reduction`` (stage 3: Eq. 25 acts where ``p < p_hist``).
    """
    hh0 = s.height / 2
    z_end = hh0 * (1.0 - s.reduction)
    if not s.first_reduction:
        return [(z_end, int(s.increments), 1)]
    z1 = hh0 * (1.0 - s.first_reduction)
    n1 = max(1, round(s.increments * s.first_reduction / s.reduction))
    sf = float(s.material.flow_stress(math.log(hh0 / z1)))
    lift = s.lift_factor * sf / s.material.E * z1
    n3 = max(1, int(s.increments) - n1)
    n_un = int(s.n_unload)
    return [(z1, n1, 1), (z1 + lift, n_un, 2), (z1, 2 * n_un, 3), (z_end, n3, 3)]


def _profile(model, ct, u_all, rows):
    """Committed ``p_hist`` of the die-face nodes after a stage: reference and current radius."""
    x = model.X[ct.nodes] + u_all[ct.nodes]
    top = model.X[ct.nodes, 2] >= model.X[:, 2].max() - 1e-12
    ph = np.asarray(ct.state.p_hist)
    order = np.argsort(model.X[ct.nodes, 0][top])
    r0 = np.hypot(model.X[ct.nodes, 0], model.X[ct.nodes, 1])[top][order]
    r = np.hypot(x[:, 0], x[:, 1])[top][order]
    return {
        "stage": int(rows[-1]["stage"]) if rows else 0,
        "height_reduction": float(rows[-1]["height_reduction"]) if rows else 0.0,
        "r0": r0.tolist(),
        "r": r.tolist(),
        "p_hist": ph[top][order].tolist(),
    }


def _row(s, model, ct, inc, u_all, z_die, hh0, inner_mid, scale, cut):
    x = model.X + u_all
    active = inc.p > 0
    xc = x[ct.nodes]
    rc = float(np.hypot(xc[active, 0], xc[active, 1]).max()) if active.any() else 0.0
    ph = np.asarray(ct.state.p_hist)
    r0 = model.X[inner_mid, 0]
    return {
        "height_reduction": 1.0 - z_die / hh0,
        "force": float(-inc.force[:, 2].sum() * scale),
        "inner_diameter_change": float((np.hypot(x[inner_mid, 0], x[inner_mid, 1]) - r0) / r0),
        "stroke": 2.0 * (hh0 - z_die),
        "contact_radius": rc,
        "n_stick": int(np.sum(inc.status == 1)),
        "n_slip": int(np.sum(inc.status == 2)),
        "n_open": int(np.sum(inc.status == 0)),
        "n_reload_eq25": int(np.sum(active & (inc.p < ph * (1 - 1e-9)))),
        "max_p_hist": float(ph.max()),
        "nit": inc.nit,
        "cutbacks": cut,
        "min_plastic_multiplier": float(np.min(model.md.variable("ksi"))),
    }


def _getfem_version():
    try:
        from importlib.metadata import version

        return version("getfem")
    except Exception:  # noqa: BLE001 - Debian's package has no metadata
        return "unknown (Debian python3-getfem)"


def _jsonable(d):
    return json.loads(json.dumps(d, default=str))


def write_history_csv(path, rows):
    """One row per accepted increment, units in the names (``force_N`` ...).

    ``height_reduction_fraction, force_N, inner_diameter_change_fraction`` first.
    """
    with open(path, "w") as f:
        f.write(",".join(column_name(c, HISTORY_UNITS.get(c, "1")) for c in HISTORY_COLUMNS) + "\n")
        for r in rows:
            f.write(",".join(_fmt(r[c]) for c in HISTORY_COLUMNS) + "\n")


def _fmt(v):
    return str(v) if isinstance(v, (int, np.integer)) else repr(float(v))


def _write_outputs(out, rows, info, con):
    """History, summary and the console's summary lines into the output folder ``out``."""
    out = Path(out)
    write_history_csv(out / "history.csv", rows)
    (out / "summary.json").write_text(json.dumps(info, indent=2))
    con.write_summary(out)


PROG = "couplings/getfem/ring.py"


def _parser():
    ap = argparse.ArgumentParser(
        prog=PROG,
        description="Ring compression (6:3:2) in GetFEM with frictionlaw at the contact nodes",
        formatter_class=HelpFormatter,
    )
    add_version(ap)
    ap.add_argument("--law", choices=("none", "tresca", "sbmf"), default="tresca", help="law")
    ap.add_argument("--m", type=float, default=None, help="Tresca friction factor (default 0.3)")
    ap.add_argument(
        "--params", default=None, help="SBMF parameter JSON (default: fe-demo's example file)"
    )
    ap.add_argument("--nr", type=int, default=16, help="elements across the ring wall")
    ap.add_argument("--nz", type=int, default=0, help="elements over h/2 (0: near-square)")
    ap.add_argument("--sector", type=float, default=5.0, help="wedge angle in degrees")
    ap.add_argument("--increments", type=int, default=50, help="load increments")
    ap.add_argument("--reduction", type=float, default=0.5, help="final height reduction")
    ap.add_argument(
        "--first-reduction",
        type=float,
        default=0.0,
        help="press-lift-press (fe-demo multistage's schedule): press to this reduction, lift "
        "the die until every node opens, press again to --reduction (0: one press)",
    )
    ap.add_argument(
        "--unload", type=int, default=4, help="increments of the lift (press-lift-press)"
    )
    ap.add_argument("--out", default="getfem_out/ring", help="output folder")
    add_common_options(ap)
    return refuse_repeats(ap)  # a value option given twice is refused, not the last kept


def _setup(a):
    """The :class:`RingSetup` of the options; options the law does not use are refused."""
    if a.m is not None and a.law != "tresca":
        raise ParameterError(f"{{m}} applies to --law tresca only, not {a.law!r}", "m")
    if a.params is not None and a.law != "sbmf":
        raise ParameterError(f"{{params}} applies to --law sbmf only, not {a.law!r}", "params")
    setup = RingSetup(
        law=a.law,
        m=0.3 if a.m is None else a.m,
        params=a.params or "",
        nr=a.nr,
        nz=a.nz,
        sector_deg=a.sector,
        increments=a.increments,
        reduction=a.reduction,
        first_reduction=a.first_reduction,
        n_unload=a.unload,
    )
    _check(setup)
    return setup


@interruptible(PROG, "the GetFEM ring run")
def main(argv=None):
    """Command line; exit 0 success, 1 failed run, 2 bad input, 130/143 interrupted."""
    parser = _parser()
    a, code = parse(parser, argv)
    if a is None:
        return code
    con = Console(
        PROG, quiet=a.quiet, flags=flags_of(parser, sector_deg="--sector", n_unload="--unload")
    )
    try:
        setup = _setup(a)
        import getfem  # noqa: F401
    except ImportError as exc:
        return con.error(f"GetFEM is not importable from {sys.executable}: {exc}", 2)
    except ValueError as exc:
        return con.error(exc, 2)
    try:
        folder = OutputFolder(a.out, command=PROG, what="GetFEM ring output", inputs=(a.params,))
    except ValueError as exc:
        return con.error(exc, 2)
    with folder:
        ok, message, rows, info = run(setup, progress=not (a.quiet or a.no_progress))
        con.result(f"{message}; {len(rows)} increments, {info['wall_time_s']:.1f} s -> {a.out}")
        try:
            _write_outputs(folder.tmp, rows, info, con)
            folder.commit()
        except OSError as exc:
            return con.error(f"the outputs could not be written, {a.out} is unchanged: {exc}", 1)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())

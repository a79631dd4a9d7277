"""The flattening under bulk strain in the Fortran routines (issue 43; private).

:class:`FlatSpec` holds what ``core/sbmf_flat.f`` (the law's flattening routines, a port of
:mod:`frictionlaw._kernels_flattening`) is rendered with, in the host's units; each target's
:class:`~frictionlaw.export.Routine` says how its host gives the bulk strain (``flattening``) or
why it cannot (its kind-9 message, written once per process, and the law then runs without).
"""

from dataclasses import dataclass

import numpy as np

from .._flattening_block import LIMIT_MODEL
from ..flattening import HARDENING_SINK, STRETCH_PER_EQUIVALENT_STRAIN, flattening_data

__all__ = [
    "FlatSpec",
    "flat_spec",
    "LimitSpec",
    "limit_spec",
    "flat_states",
    "FlowSpec",
    "flow_spec",
]

#: a DATA statement's continuation lines (Fortran 77's limit is 19)
_DATA_LINES = 18


def fortran_short(v):
    """``v`` as the shortest double-precision literal that reads back to the same float64.

    Python's ``repr`` is the shortest decimal that rounds to ``v``, and a Fortran compiler
    rounds a decimal literal correctly, so the literal is ``v`` bit for bit.
    """
    text = repr(float(v))
    mant, _, exp = text.partition("e")
    return f"{mant}D{int(exp or 0):d}"


def data_statements(name, values, index="I", start=1):
    """Fixed-form ``DATA (name(I), I = a, b) / ... /`` statements holding ``values``.

    Python ints are written as integers, other values by :func:`fortran_short`.
    As many values a line as fit in column 72, at most :data:`_DATA_LINES` continuation lines
    a statement (one statement per chunk: Fortran 77 allows 19 continuations).
    """
    words = [str(v) if isinstance(v, int) else fortran_short(v) for v in values]
    lines: list[list[str]] = []
    cur: list[str] = []
    for w in words:
        if cur and len("     &  " + ", ".join([*cur, w]) + " /") > 72:
            lines.append(cur)
            cur = []
        cur.append(w)
    lines.append(cur)
    out, first = [], start
    for k in range(0, len(lines), _DATA_LINES):
        chunk = lines[k : k + _DATA_LINES]
        last = first + sum(len(c) for c in chunk) - 1
        body = ",\n".join("     &  " + ", ".join(c) for c in chunk)
        out.append(f"      DATA ({name}({index}), {index} = {first}, {last}) /\n{body} /")
        first = last + 1
    return tuple(out)


@dataclass(frozen=True)
class LimitSpec:
    """The two-state model's rate table and rules as ``core/sbmf_limit.f`` carries them.

    Attributes
    ----------
    pressures, a, ln_s : tuple of float
        The table's ``p / H_P``, its rows' contact fractions and its slopes' logarithms
        (``frictionlaw._limit_table.RateTable``; dimensionless: no unit conversion).
    data : tuple of str
        The DATA statements of the row offsets ``OFF``, ``AR``, ``LS`` and the rates ``DA``,
        ``DS`` (row-major, as the runtime's arrays).
    step, s_floor, prandtl : float
        The integration's stretch step, the slope's floor and ``2 + pi`` (the kernels').
    """

    pressures: tuple
    a: tuple
    ln_s: tuple
    data: tuple
    step: float
    s_floor: float
    prandtl: float


def limit_spec():
    """The :class:`LimitSpec` of the shipped table (it depends on no parameter file)."""
    from .._limit_table import PRANDTL_FACTOR, S_FLOOR, STEP, rate_table

    t = rate_table()
    data = (
        *data_statements("OFF", [int(v) for v in t.offsets]),
        *data_statements("AR", t.a),
        *data_statements("LS", t.ln_s),
        *data_statements("DA", t.dA.ravel()),
        *data_statements("DS", t.ds.ravel()),
    )
    return LimitSpec(
        tuple(float(v) for v in t.pressures),
        tuple(float(v) for v in t.a),
        tuple(float(v) for v in t.ln_s),
        data,
        float(STEP),
        float(S_FLOOR),
        float(PRANDTL_FACTOR),
    )


@dataclass(frozen=True)
class FlatSpec:
    """A law's flattening block as the Fortran routines carry it (host units).

    Attributes
    ----------
    slope, beta : float
        ``tan(theta)`` and ``beta`` of the block.
    stretch : float
        The stretch across the ridges per unit equivalent plastic strain, ``sqrt(3) / 2``
        (:data:`frictionlaw.flattening.STRETCH_PER_EQUIVALENT_STRAIN`).
    s0 : float
        The layer's flow stress ``2 k`` of the file (host stress unit).
    sigma_y : float
        The file's ``sigma_y`` (host stress unit): a host's flow stress scales ``s0`` by it.
    cap : float
        The pressure from which ``alpha1`` is 1 to rounding (host stress unit), the runtime's.
    p_min : float
        ``1e-12 H``: below it nothing flattens (host stress unit).
    gx, gw : tuple of float
        The 2-, 4- and 8-point Gauss-Legendre nodes and weights, one after the other.
    width, narrow : float, (float, float)
        The widest panel in ``v`` and the widest interval of the 2- and 4-point rules.
    limit : LimitSpec or None
        The two-state model's table (``"model": "limit-analysis"``); None for the one-state
        model.
    edge : tuple of float
        The two-state block's ``edge_slope`` (empty: its one slope); ``edge_data`` its DATA
        statements (``EDG``).
    sink : float
        The sinking per half-spacing a hardening bulk holds, times ``h / p``, ``3 / 4`` (Eq.
        F2d, :data:`frictionlaw.flattening.HARDENING_SINK`).
    """

    slope: float
    beta: float
    stretch: float
    s0: float
    sigma_y: float
    cap: float
    p_min: float
    gx: tuple
    gw: tuple
    width: float
    narrow: tuple
    limit: "LimitSpec | None" = None
    edge: tuple = ()
    edge_data: tuple = ()
    sink: float = HARDENING_SINK


def flat_spec(params, units):
    """The :class:`FlatSpec` of ``params`` in ``units`` (None without a flattening block).

    ``ValueError`` for ``m = 0`` (``tau_max = 0``: no friction to flatten; the routines read
    ``alpha1`` as the first loading's shear over ``tau_max``).
    """
    data = flattening_data(params)
    if data.size == 0:
        return None
    from .. import _kernels_flattening as K  # the rules the kernels integrate by (numba loads)
    from .. import _kernels_flattening_quad as Q

    if not params.tau_max > 0:
        raise ValueError(
            "a flattening block with m = 0: the law has no friction to flatten; export the "
            "file without its flattening block"
        )
    s = units.stress
    slope, beta, s0, sigma_y, cap = (float(v) for v in data[: K.FLAT_HEAD])
    edge = tuple(float(v) for v in params.flattening.edge_slope or ())
    H = params.H * s
    return FlatSpec(
        slope,
        beta,
        STRETCH_PER_EQUIVALENT_STRAIN,
        s0 * s,
        sigma_y * s,
        cap * s,
        float(np.float64(K.P_MIN_RATIO) * np.float64(H)),
        tuple(float(x) for x in Q._GX),
        tuple(float(w) for w in Q._GW),
        float(Q._WIDTH),
        tuple(float(x) for x in Q._NARROW),
        limit_spec() if params.flattening.model == LIMIT_MODEL else None,
        edge,
        data_statements("EDG", edge) if edge else (),
    )


@dataclass(frozen=True)
class FlowSpec:
    """The workpiece's flow curve baked into a routine, in the host's stress unit.

    For a host that passes only the total plastic strain (LS-DYNA's ``usrfrc``,
    ``--flow-curve``).

    Attributes
    ----------
    form : str
        ``"swift"`` (``K``, ``eps0``, ``n``) or ``"table"`` (``strain``, ``stress``: joined by
        straight lines, the last segment continued beyond the last strain, as LS-DYNA continues
        its load curves).
    describe : str
        The curve in words (SI), for the header and README.
    """

    form: str
    describe: str
    K: float = 0.0
    eps0: float = 0.0
    n: float = 0.0
    strain: tuple = ()
    stress: tuple = ()


def flow_spec(curve, units):
    """The :class:`FlowSpec` of a :mod:`frictionlaw.flow_curve` curve in ``units``."""
    s = units.stress
    d = curve.to_dict()
    if d["form"] == "swift":
        return FlowSpec("swift", curve.describe(), K=d["K_Pa"] * s, eps0=d["eps0"], n=d["n"])
    return FlowSpec(
        "table",
        curve.describe(),
        strain=tuple(d["strain"]),
        stress=tuple(v * s for v in d["sigma_y_Pa"]),
    )


def flat_states(form, flat):
    """The state count a routine's flattening needs (its last slot).

    The host-neutral entry (``form.status``): 5 (``STATE(5)`` the fraction; 6 the optional
    hardening modulus), 7 for the two-state model (``STATE(7)`` the flank slope). The implicit
    host (the patched CalculiX, ``STATEV``): 5, 6 with the slope. LS-DYNA's ``usrfrc``
    (history 5-7 the fraction, the element's plastic strain and the cycle of the last call): 7,
    8 with the slope.
    """
    two = flat.limit is not None
    if form.status:
        return 7 if two else 5
    if form.implicit:
        return 6 if two else 5
    return 8 if two else 7

"""The limit-analysis table between its pressures: each inner pressure held out (issue 43, a study).

``flattening_limit_law.py`` evaluates its table only at the truth's six pressures. A runtime must
read it at any ``p / H``. This script holds each inner pressure of the table out (0.05, 0.1, 0.2,
0.3 and 0.45 H; 0.05 H from the low table's 0.02 H, ``flattening_limit_low.py``, and 0.1 H, and
again from the low table's 0.035 H and 0.1 H), builds its rates from the two neighbouring
pressures alone, and holds the curves to the
truth at the held-out pressure (``flattening_truth.csv``) and to the curves of the pressure's own
table (``flattening_limit_law.csv``), nothing fitted. Two ways to pair the neighbours' states:

- **same A**: both neighbours read at the node's ``A`` and ``s`` (each clamped to its own grid:
  below the higher neighbour's smallest ``A``, its rates at that ``A``);
- **same excess**: both read at the same share of the way from the pressure's collapse fraction
  ``a0 = 1.01 p / H`` (the table's smallest ``A``, where pressing alone collapses the asperity and
  the rates grow without bound) to full contact, ``(A - a0) / (1 - a0)``, so that each
  neighbour's collapse sits where the held-out pressure's does.

Each weights the neighbours linearly in ``p / H`` or in ``ln p``. Writes ``results/flattening_limit_pressure.md`` /
``.csv``.

Run: python benchmarks/flattening_limit_pressure.py (after flattening_limit_law.py and
flattening_limit_low.py)
"""

import math

import numpy as np
from _provenance import RESULTS, read_rows, run_record, write_report
from flattening_limit import curve
from flattening_limit_law import PRESSURES, STEP, TABLE, Rates, _read, collapse_fraction
from flattening_limit_low import BETWEEN_PRESSURES, LOW_PRESSURES, LOW_TABLE

#: the pressures with a truth: the table's and the low table's below them
#: (``flattening_limit_low.py``), so that 0.05 H is held out too, from 0.02 and 0.1 H
ALL_PRESSURES = LOW_PRESSURES + PRESSURES
#: ``(lo, held out, hi)``: each inner pressure with a truth from its neighbours with a truth
NEIGHBOURS = tuple(tuple(ALL_PRESSURES[k - 1 : k + 2]) for k in range(1, len(ALL_PRESSURES) - 1))
#: and then from the low table's pressures without a truth (0.035, 0.07 H) and the next two:
#: closer neighbours below 0.1 H
HELD_OUT = (
    NEIGHBOURS
    + tuple((b, *[ph for ph in ALL_PRESSURES if ph > b][:2]) for b in BETWEEN_PRESSURES)
    # 0.05 H from its neighbours in the runtime's shipped table (frictionlaw/data)
    + ((BETWEEN_PRESSURES[0], 0.05, BETWEEN_PRESSURES[1]),)
)

PAIRINGS = ("same A", "same excess")
WEIGHTS = ("p", "ln p")
SCHEMES = tuple(f"{a}, linear in {w}" for a in PAIRINGS for w in WEIGHTS)


class Between:
    """The rates at ``ph`` from the tables at ``lo`` and ``hi`` (``scheme``: one of ``SCHEMES``)."""

    def __init__(self, rows, lo, hi, ph, scheme):
        if scheme not in SCHEMES:
            raise ValueError(f"scheme must be one of {SCHEMES}, got {scheme!r}")
        self.lo, self.hi = Rates(rows, lo), Rates(rows, hi)
        lin = scheme.endswith("linear in p")
        self.t = (ph - lo) / (hi - lo) if lin else math.log(ph / lo) / math.log(hi / lo)
        self.ph, self.p_lo, self.p_hi, self.scheme = ph, lo, hi, scheme

    def _paired(self, p, A):
        """The state of the table at ``p`` that the scheme pairs with ``A`` at ``self.ph``."""
        if self.scheme.startswith("same A"):
            return A
        a0, a = collapse_fraction(self.ph), collapse_fraction(p)
        return a + (A - a0) / (1.0 - a0) * (1.0 - a)

    def __call__(self, A, s):
        r1 = self.lo(self._paired(self.p_lo, A), s)
        r2 = self.hi(self._paired(self.p_hi, A), s)
        return tuple((1 - self.t) * u + self.t * v for u, v in zip(r1, r2, strict=True))


def compare(rows):
    truth = read_rows(RESULTS / "flattening_truth.csv")
    own = {
        (r["profile"], float(r["p_over_H"]), float(r["strain"])): float(r["alpha_limit"])
        for r in read_rows(RESULTS / "flattening_limit_law.csv")
    }
    profiles = sorted({(r["profile"], float(r["slope_deg"])) for r in truth}, key=lambda k: k[1])
    out = []
    for lo, ph, hi in HELD_OUT:
        for scheme in SCHEMES:
            rate = Between(rows, lo, hi, ph, scheme)
            for name, deg in profiles:
                pts = sorted(
                    (float(r["strain"]), float(r["alpha_truth"]))
                    for r in truth
                    if r["profile"] == name and float(r["p_over_H"]) == ph
                )
                alpha = curve(
                    rate, pts[0][1], math.tan(math.radians(deg)), [e for e, _ in pts], STEP
                )
                out += [
                    {
                        "profile": name,
                        "p_over_H": ph,
                        "from": f"{lo:g} and {hi:g}",
                        "scheme": scheme,
                        "strain": e,
                        "alpha_truth": at,
                        "alpha_own_table": own[(name, ph, e)],
                        "alpha_between": round(a, 4),
                    }
                    for (e, at), (a, _) in zip(pts, alpha, strict=True)
                ]
    return out


def summary(out):
    lines = [
        "| p/H (from) | scheme | largest miss against the truth: own table | between | "
        "largest change from the own table |",
        "|---|---|---|---|---|",
    ]
    for lo, ph, hi in HELD_OUT:
        for scheme in SCHEMES:
            sel = [
                r
                for r in out
                if (r["p_over_H"], r["from"], r["scheme"]) == (ph, f"{lo:g} and {hi:g}", scheme)
            ]
            m_own = max(abs(r["alpha_own_table"] - r["alpha_truth"]) for r in sel)
            m_bet = max(abs(r["alpha_between"] - r["alpha_truth"]) for r in sel)
            d = max(abs(r["alpha_between"] - r["alpha_own_table"]) for r in sel)
            lines.append(
                f"| {ph:g} ({sel[0]['from']}) | {scheme} | {m_own:.3f} | {m_bet:.3f} | {d:.3f} |"
            )
    inner = {f"{lo:g} and {hi:g}" for lo, _, hi in NEIGHBOURS}
    for scheme in SCHEMES:  # over the pressures held out from their neighbours with a truth
        sel = [r for r in out if r["scheme"] == scheme and r["from"] in inner]
        rms = math.sqrt(np.mean([(r["alpha_between"] - r["alpha_truth"]) ** 2 for r in sel]))
        rms_own = math.sqrt(np.mean([(r["alpha_own_table"] - r["alpha_truth"]) ** 2 for r in sel]))
        d = max(abs(r["alpha_between"] - r["alpha_own_table"]) for r in sel)
        lines.append(
            f"| all {len(ALL_PRESSURES) - 2} | {scheme} | RMS {rms_own:.3f} | RMS {rms:.3f} | {d:.3f} |"
        )
    return lines


def main():
    rows = _read(LOW_TABLE) + _read(TABLE)
    out = compare(rows)
    lines = [
        "# The limit-analysis table between its pressures (each inner pressure held out)",
        "",
        "`benchmarks/flattening_limit_pressure.py`: the rates at each inner pressure of the table "
        "built from its two neighbours alone (0.05 H from the low table's 0.02 H and 0.1 H, "
        "from its 0.035 H and 0.1 H, and from 0.035 H and 0.07 H, its neighbours in the "
        "runtime's shipped table; 0.1 H also from 0.07 H and 0.2 H), the "
        "truth's curves there "
        "(`flattening_truth.csv`) integrated as `flattening_limit_law.py` integrates them, beside "
        "the curves of the pressure's own table; nothing fitted.",
        "",
        *summary(out),
    ]
    write_report("flattening_limit_pressure", out, lines)


if __name__ == "__main__":
    with run_record(__file__):
        main()

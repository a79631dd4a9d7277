"""The two-state law started from the truth's pressed flank (issue 43, a study of the mechanism).

The two-state law (``flattening_limit_law.py``) starts every curve from the truth's pressing-alone
contact fraction and the wedge's virgin flank slope. The truth's pressing also reshapes the flank:
its fitted slope after pressing alone (``flattening_flank``'s fit between 10 % and 90 % of the free
flank) is steeper than the virgin one at high pressure. This script measures that slope for every
wedge at every pressure of the table (``flattening_flank.run`` to a stretch of 0.002: 64 x 32, the
first record is the pressing's end) and integrates the law's curve from it, beside the curve from
the virgin slope and the truth (``flattening_truth.csv``). The pressed slope is the truth's
geometry before any stretch, not a parameter fitted to its strain columns; no runtime has it (a law
would need a model of the pressing's flank). Writes ``results/flattening_limit_pressed.md`` /
``.csv``.

Run: python benchmarks/flattening_limit_pressed.py (about 10 min on the shared 2-core machine)
"""

import math

from _provenance import RESULTS, read_rows, run_record, write_report
from flattening_flank import run
from flattening_limit import curve
from flattening_limit_law import PRESSURES, STEP, TABLE, Rates, _read
from flattening_truth import curve_misses

SLOPES = (3.0, 5.0, 7.0, 10.0)


def pressed_slope(deg, ph):
    """The truth's fitted flank slope after pressing alone, over the virgin ``tan(theta)``."""
    _, _, _, s, _, _ = run(deg, ph, e_max=0.002)
    return float(s[0]) / math.tan(math.radians(deg))


def wedge_truth(truth, deg, ph):
    """The FE truth's ``(strain, alpha)`` of the ``deg`` wedge at ``p/H = ph``, by strain
    (``truth``: the rows of ``flattening_truth.csv``)."""
    return sorted(
        (float(r["strain"]), float(r["alpha_truth"]))
        for r in truth
        if r["profile"] == f"wedge {deg:g} deg" and float(r["p_over_H"]) == ph
    )


def compare(rows):
    truth = read_rows(RESULTS / "flattening_truth.csv")
    out = []
    for ph in PRESSURES:
        rate = Rates(rows, ph)
        for deg in SLOPES:
            ratio = pressed_slope(deg, ph)
            pts = wedge_truth(truth, deg, ph)
            strains = [e for e, _ in pts]
            t = math.tan(math.radians(deg))
            virgin = curve(rate, pts[0][1], t, strains, STEP)
            pressed = curve(rate, pts[0][1], ratio * t, strains, STEP)
            out += [
                {
                    "slope_deg": deg,
                    "p_over_H": ph,
                    "pressed_slope_ratio": round(ratio, 4),
                    "strain": e,
                    "alpha_truth": at,
                    "alpha_virgin": round(v[0], 4),
                    "alpha_pressed": round(q[0], 4),
                }
                for (e, at), v, q in zip(pts, virgin, pressed, strict=True)
            ]
            print(out[-1], flush=True)
    return out


def summary(out):
    lines = [
        "| p/H | pressed slope / virgin (3, 5, 7, 10 deg) | largest miss: virgin slope | "
        "pressed slope | curves within 0.05: virgin | pressed |",
        "|---|---|---|---|---|---|",
    ]
    for ph in (*PRESSURES, None):
        sel = [r for r in out if ph is None or r["p_over_H"] == ph]
        m = {
            c: curve_misses(sel, c, ("slope_deg", "p_over_H"))
            for c in ("alpha_virgin", "alpha_pressed")
        }
        ratios = (
            ", ".join(
                f"{next(r['pressed_slope_ratio'] for r in sel if r['slope_deg'] == d):.2f}"
                for d in SLOPES
            )
            if ph is not None
            else ""
        )
        lines.append(
            f"| {'all' if ph is None else f'{ph:g}'} | {ratios} | "
            f"{m['alpha_virgin'][0]:.3f} | {m['alpha_pressed'][0]:.3f} | "
            f"{m['alpha_virgin'][2]} of {m['alpha_virgin'][3]} | {m['alpha_pressed'][2]} |"
        )
    rms = {
        c: curve_misses(out, c, ("slope_deg", "p_over_H"))[1]
        for c in ("alpha_virgin", "alpha_pressed")
    }
    lines += ["", f"RMS: virgin {rms['alpha_virgin']:.3f}, pressed {rms['alpha_pressed']:.3f}."]
    return lines


def main():
    out = compare(_read(TABLE))
    lines = [
        "# The two-state law started from the truth's pressed flank",
        "",
        "`benchmarks/flattening_limit_pressed.py`: the wedges' 24 curves of the truth, the "
        "two-state law (`flattening_limit_law.py`'s table) from the truth's pressing-alone "
        "fraction and the virgin flank slope, and from the flank slope the truth's pressing "
        "leaves (fitted between 10 % and 90 % of the free flank, 64 x 32); nothing fitted to "
        "the strain columns.",
        "",
        *summary(out),
    ]
    write_report("flattening_limit_pressed", out, lines)


if __name__ == "__main__":
    with run_record(__file__):
        main()

"""The measured row's flattening with its edge slope in the one-state law, a study (issue 43).

With Eq. F2c's factor ``1 - A`` the one-state law's largest miss on every hardening truth is the
measured row's (``flattening_hardening.py``): at 0.2 and 0.45 H its early rise is too slow. The
row's contact meets its shallow flanks first, which one RMS slope does not carry; the two-state
model reads the workpiece's edge slope against the contact fraction for this
(docs/flattening.md, "The edge slope"), the one-state runtime does not. This study asks what the
one-state law would give with it: Eqs. F1-F3 with the flank slope ``E(A)`` at the contact edge in
place of ``tan(theta)`` (``dA / d eps = (c + c_E) / E(A)``, ``c = min(1 + E (1 - A), 6 p (1 - A)
/ h)``), F2d's bound as the sinking height the hardening holds, ``int_{alpha1(p)}^A E dA <= 3 p /
(4 h)`` (the plateaus must sink that far to reach ``A``), ``E`` the block's 51-fraction table
of the row as a calibration writes it (``flattening_limit_rows.block_edges``). Integrated in
``A`` by ``flattening_hardening.candidate_curve`` (the study's ODE of the runtime's law), with
the RMS slope beside it (the runtime's law to the ODE's error), against the hardening truths the
CSVs of ``flattening_hardening.py`` hold (DC04 on 64 x 32 and 128 x 48, Swift curves of ``n``
0.1-0.4) and against the perfectly plastic truth's row (``asperity_flattening.csv``, 0.05-0.6 H,
no modulus). Nothing fitted; not in the runtime (a study: a one-state block carries no table).

At 0.02 H the truths are ``flattening_hardening_low.py``'s (128 x 48; DC04's ``fine`` run 256 x 64).

Run: python benchmarks/flattening_hardening_edges.py (about 10 s). Writes
benchmarks/results/flattening_hardening_edges.csv and .md (run record: .run.json).
"""

import math
from pathlib import Path

import flattening_hardening as fh
import numpy as np
from _provenance import RESULTS, read_rows, run_record, write_rows
from asperity_flattening import profiles
from flattening_limit_rows import block_edges
from flattening_truth import law_of, law_strain, read_truth

import frictionlaw as fl

#: the hardening truths: results stem, the Swift curve (None: DC04) and a label
TRUTHS = (
    ("flattening_hardening", None, "DC04 (n 0.24)"),
    ("flattening_hardening_fine", None, "DC04, 128 x 48"),
    ("flattening_hardening_n01", "259e6,0.006,0.1", "n 0.1"),
    ("flattening_hardening_n02", "496144200,0.003,0.2", "n 0.2"),
    ("flattening_hardening_n03", "585164264,0.012,0.3", "n 0.3"),
    ("flattening_hardening_n04", "742e6,0.02,0.4", "n 0.4"),
)


def _low_cell(stem, name, key, H, mat, truth, laws, rows, label):
    """The row's largest misses at 0.02 H (``flattening_hardening_low.py``'s truth of the same
    curve; ``alpha1`` its pressing-alone fractions there and the table's at 0.05-0.45 H), RMS
    slope / edge slope, or "-" where that truth was not run."""
    path = RESULTS / (stem.replace("flattening_hardening", "flattening_hardening_low") + ".csv")
    if not path.exists():
        return "-"
    low = [r for r in read_rows(path) if r["profile"] == name]
    ph = float(low[0]["p_over_H"])
    a_t = np.array([float(r["alpha_hardening"]) for r in low])
    table = {q: {0.0: float(truth[(name, q)][0][0])} for q in fh.P_OVER_H} | {ph: {0.0: a_t[0]}}
    P = law_of(table, key[1], H)
    got = {k: fh.candidate_curve(P, ph * H, f, fh.STRAINS, mat) for k, f in laws.items()}
    for i, e in enumerate(fh.STRAINS):
        rows.append(
            {"truth": label, "p_over_H": ph, "strain": e, "alpha_truth": a_t[i]}
            | {f"alpha_{k.split()[0].lower()}": round(float(v[i]), 5) for k, v in got.items()}
        )
    return " / ".join(f"{np.abs(v - a_t).max():.3f}" for v in got.values())


def main():
    pp, H = read_truth(RESULTS / "asperity_flattening.csv")
    profs = profiles()
    name = next(n for n in profs if n.startswith("matrix-3"))
    x, z, rms_deg, _ = profs[name]
    table = np.array(block_edges(x, z))
    at = np.linspace(0.0, 1.0, table.size)
    rms = math.tan(math.radians(rms_deg))
    key = next(k for k in pp if k[0] == name)
    laws = {"RMS slope": rms, "edge slope": lambda a: float(np.interp(a, at, table))}
    rows, lines = [], []
    for stem, material, label in TRUTHS:
        if not (RESULTS / f"{stem}.csv").exists():
            continue
        mat, truth = fh._material(material), fh._stored_truth(stem)
        P = law_of({ph: {0.0: float(truth[(name, ph)][0][0])} for ph in fh.P_OVER_H}, key[1], H)
        cells = [_low_cell(stem, name, key, H, mat, truth, laws, rows, label)]
        for ph in fh.P_OVER_H:
            a_t = truth[(name, ph)][0]
            got = {k: fh.candidate_curve(P, ph * H, f, fh.STRAINS, mat) for k, f in laws.items()}
            for i, e in enumerate(fh.STRAINS):
                rows.append(
                    {"truth": label, "p_over_H": ph, "strain": e, "alpha_truth": a_t[i]}
                    | {
                        f"alpha_{k.split()[0].lower()}": round(float(v[i]), 5)
                        for k, v in got.items()
                    }
                )
            cells.append(" / ".join(f"{np.abs(v - a_t).max():.3f}" for v in got.values()))
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    # the perfectly plastic truth's row, its six pressures
    P = law_of(pp[key], key[1], H)
    pp_cells = []
    for ph in sorted(pp[key]):
        strains = sorted(pp[key][ph])
        a_t = np.array([pp[key][ph][e] for e in strains])
        got = {k: fh.candidate_curve(P, ph * H, f, strains, None) for k, f in laws.items()}
        runtime = fl.flattening_curve(ph * H, law_strain(strains), P)
        check = float(np.abs(got["RMS slope"] - runtime).max())
        pp_cells.append(
            f"{ph:g} H "
            + " / ".join(f"{np.abs(v - a_t).max():.3f}" for v in got.values())
            + f" (ODE against the runtime {check:.1e})"
        )
        for i, e in enumerate(strains):
            rows.append(
                {"truth": "perfectly plastic", "p_over_H": ph, "strain": e, "alpha_truth": a_t[i]}
                | {f"alpha_{k.split()[0].lower()}": round(float(v[i]), 5) for k, v in got.items()}
            )
    write_rows(RESULTS / "flattening_hardening_edges.csv", rows)
    text = "\n".join(
        [
            "# The measured row with its edge slope in the one-state law (issue 43 study)",
            "",
            "`benchmarks/flattening_hardening_edges.py`: the matrix-3 row of the FE truth, its "
            f"RMS slope {rms:.4f} and its edge table ({table.size} fractions, "
            f"{table.min():.4f}-{table.max():.4f}, mean {table.mean():.4f}); the one-state law "
            "(F2c with `1 - A`, F2d as the sinking height) integrated in `A` with either; "
            "nothing fitted. Largest miss over strains 0-0.2, RMS slope / edge slope:",
            "",
            "| hardening truth | 0.02 H (`flattening_hardening_low.py`) | 0.05 H | 0.2 H | 0.45 H |",
            "|---|---|---|---|---|",
            *lines,
            "",
            "At 0.02 H the DC04 row is the truth on 128 x 48 in the first line and on 256 x 64 in "
            "the second (`flattening_hardening_low_fine.csv`).",
            "",
            "Perfectly plastic truth (strains 0-0.5), RMS slope / edge slope: "
            + "; ".join(pp_cells)
            + ".",
        ]
    )
    Path(RESULTS / "flattening_hardening_edges.md").write_text(text + "\n", encoding="utf-8")
    print(text)


if __name__ == "__main__":
    with run_record(__file__):
        main()

"""The optional effects as objects in one explicit registry: :data:`REGISTRY`.

Each effect (``"tangential"``, ``"inclined"``, ``"sliding"``; ``"normal"`` is the always-on sweep
itself) answers the same five questions:

- ``run(scene, sweeps, surfaces, progress)``: compute it, an :class:`~.effects.EffectOutcome`;
- ``record(outcome)``: its JSON-ready record (``summary.json`` and the parameter file);
- ``problems(outcome)``: what makes the run fail (one sentence each);
- ``write(outcome, cal, out)``: its files, under ``out`` (through :mod:`halfspace_calib.output`);
- ``print(outcome, out)``: its lines in the command's report.

A new effect is one class here, one name in :data:`~.effects.EFFECTS` and its study in
:mod:`halfspace_calib.studies`.
"""

from __future__ import annotations

from pathlib import Path

from ...output.effects import write_tangential_outputs
from ...output.geometric import write_geometric_outputs
from ...output.sliding import write_sliding_outputs
from . import effects as _eff

__all__ = ["Effect", "REGISTRY"]


class Effect:
    """One optional effect of a calibration (see the module docstring)."""

    name = ""
    #: how the command names it when it is skipped
    label = ""

    def run(self, scene, sweeps, surfaces, progress):
        """Compute the effect for ``scene``; return its outcome (``skipped`` set if it cannot)."""
        raise NotImplementedError

    def record(self, outcome):
        """JSON-ready record of the outcome."""
        if outcome.skipped is not None:
            return {"skipped": outcome.skipped}
        return self._record(outcome)

    def _record(self, outcome):
        raise NotImplementedError

    def problems(self, outcome):
        """Why this effect makes the run fail (empty if it does not)."""
        return []

    def write(self, outcome, cal, out):
        """Write the effect's files under ``out`` (nothing for a skipped effect)."""

    def lines(self, outcome, out):
        """The command's report lines for this effect."""
        if outcome.skipped is not None:
            return [f"  {self.label} skipped: {outcome.skipped}"]
        return self._lines(outcome, Path(out))

    def _lines(self, outcome, out):
        raise NotImplementedError

    def print(self, outcome, out):
        """Print :meth:`lines`."""
        for line in self.lines(outcome, out):
            print(line)


class Tangential(Effect):
    """Pre-sliding curves and the tangential stiffness ``k_t`` (Sec. 2.2)."""

    name = "tangential"
    label = "tangential (pre-sliding)"

    def run(self, scene, sweeps, surfaces, progress):
        if scene.m == 0:
            return _eff.TangentialOutcome(
                self.name,
                skipped="m = 0: the Tresca bound (Eq. 18) is zero, no "
                "tangential traction and no stiffness",
            )
        return _eff.TangentialOutcome(
            self.name,
            seconds=sum(lv.tangential_seconds for lv in sweeps.levels),
            summary=_eff.summarize_tangential(sweeps.levels),
        )

    def _record(self, outcome):
        return dict(outcome.summary, seconds=outcome.seconds)

    def problems(self, outcome):
        if outcome.summary is None:
            return []
        s = outcome.summary
        out = [f"tangential solve at {e['p_mean']:g} Pa failed: {e['error']}" for e in s["errors"]]
        out += [
            f"tangential solve at {r['p_mean']:g} Pa did not converge"
            for r in s["rows"]
            if not r["converged"]
        ]
        return out

    def write(self, outcome, cal, out):
        if outcome.summary is not None:
            write_tangential_outputs(cal.sweeps.levels, outcome.summary, Path(out) / "tangential")

    def _lines(self, outcome, out):
        s = outcome.summary
        lines = [f"  tangential (pre-sliding, {outcome.seconds:.1f} s) -> {out / 'tangential'}"]
        for r in s["rows"]:
            lines.append(
                f"    {r['p_mean'] / 1e6:5.0f} MPa: k_t0 = {r['k_t0']:.3e}, k_eq = {r['k_eq']:.3e}, "
                f"k_sec = {r['k_sec']:.3e} Pa/m, full sliding at {r['delta_full'] * 1e9:.1f} nm"
                + ("" if r["converged"] else "  [NOT converged]")
            )
        for err in s["errors"]:
            lines.append(f"    WARNING: tangential at {err['p_mean']:g} Pa failed: {err['error']}")
        lines.append(f"    {s['recommendation']}")
        return lines


class Inclined(Effect):
    """Geometric shear of inclined patches and Eq. 26's ``geo_ratio`` (Sec. 3.2)."""

    name = "inclined"
    label = "inclined patches"

    def run(self, scene, sweeps, surfaces, progress):
        measured = (surfaces.measured_workpiece, surfaces.measured_tool, surfaces.block)
        return _eff.run_inclined(scene, measured=measured)

    def _record(self, outcome):
        d = outcome.decision
        return {
            "geo_ratio": d.geo_ratio,
            "applied": d.applied,
            "ratio_mean": d.ratio_mean,
            "threshold": d.threshold,
            "reason": d.reason,
            "method": d.method,
            "fit": d.fit,
            "study": outcome.result.summary(),
            "seconds": outcome.seconds,
        }

    def problems(self, outcome):
        if outcome.result is not None and not outcome.result.all_converged:
            return ["an inclined-patch normal solve did not converge"]
        return []

    def write(self, outcome, cal, out):
        if outcome.result is not None:
            write_geometric_outputs(outcome.result, Path(out) / "geometric")

    def _lines(self, outcome, out):
        return [
            f"  inclined patches (Eqs. 19-23, {outcome.seconds:.1f} s) -> {out / 'geometric'}",
            f"    {outcome.decision.reason}",
        ]

    @staticmethod
    def geo_ratio(outcome):
        """The ``geo_ratio`` the parameters get (0 unless the decision applied it)."""
        return 0.0 if outcome.decision is None else outcome.decision.geo_ratio


class Sliding(Effect):
    """The sliding study of Sec. 3.3: ``W_def / W_adh`` (reported, changes no parameter)."""

    name = "sliding"
    label = "sliding (Sec. 3.3)"

    def run(self, scene, sweeps, surfaces, progress):
        return _eff.run_sliding(scene, progress=progress, tool=surfaces.tool)

    def _record(self, outcome):
        st = outcome.study
        return dict(
            st.summary(),
            errors={str(k): v.splitlines()[0] for k, v in st.errors.items()},
            seconds=outcome.seconds,
        )

    def problems(self, outcome):
        if outcome.study is None:
            return []
        return [
            f"sliding at {p:g} Pa failed: {e.splitlines()[0]}"
            for p, e in outcome.study.errors.items()
        ]

    def write(self, outcome, cal, out):
        if outcome.study is not None:
            write_sliding_outputs(outcome.study, Path(out) / "sliding")

    def _lines(self, outcome, out):
        study = outcome.study
        s = study.summary()
        lines = [
            f"  sliding (Sec. 3.3, {outcome.seconds:.1f} s) -> {out / 'sliding' / 'sliding.csv'}"
        ]
        for row in s["rows"]:
            lines.append(
                f"    {row['p_mean'] / 1e6:5.0f} MPa: W_def / W_adh mean {row['ratio_mean']:.4f}, "
                f"max {row['ratio_max']:.4f} (positions >= 1; paper: < 0.008)"
                + ("" if row["converged"] else "  [NOT all positions converged]")
            )
        for p, err in study.errors.items():
            lines.append(f"    WARNING: sliding at {p:g} Pa failed: {err.splitlines()[0]}")
        return lines


#: the optional effects by name, in the order they run (:data:`~.effects.EFFECTS` without "normal")
REGISTRY = {e.name: e for e in (Tangential(), Inclined(), Sliding())}

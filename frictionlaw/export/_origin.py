"""Where the exported law's m and surfaces came from, read from the parameter file (private).

The provenance header and the README of every export say it (issue 33, item 6): ``m`` fitted
to ring-compression tests by ``fe-demo ring-fit`` (``provenance.ring_test``: the fit, its band,
the ring-test files with their sha256, the ring, the material, the source calibration), marked
when that fit ran on fe-demo's illustrative law, or else the calibration's own note on ``m``
(``provenance.inputs.m``: an input, not fitted); and the surfaces that shaped ``C1 .. n2``
(``provenance.extra.files``: measured files with their sha256, or ``provenance.surfaces``:
the generator, preset and seed of synthetic ones). The provenance is the file's free-form
record: a missing or odd entry is said to be missing, never an error.
"""

from dataclasses import dataclass

__all__ = ["MOrigin", "m_origin"]


@dataclass(frozen=True)
class MOrigin:
    """What the export says about the origin of ``m`` and of the surfaces.

    Attributes
    ----------
    m : tuple of str
        Lines on ``m`` (the first is the summary), for the header and the README.
    surfaces : tuple of str
        Lines on the surfaces, one per file or synthetic surface.
    illustrative : bool
        The ring fit ran on fe-demo's illustrative law: not a calibration result.
    """

    m: tuple
    surfaces: tuple
    illustrative: bool = False

    def header(self):
        """The provenance header's lines."""
        return [*self.m, *self.surfaces]


def _get(d, *keys):
    """``d[k0][k1]...`` or None where a level is missing or not a dict."""
    for k in keys:
        if not isinstance(d, dict):
            return None
        d = d.get(k)
    return d


def _num(v, fmt):
    return format(v, fmt) if isinstance(v, (int, float)) and not isinstance(v, bool) else "?"


def _files(entries):
    """``name (sha256 ...)`` of each ``{path, sha256}`` entry, with the full path."""
    out = []
    for f in entries if isinstance(entries, list) else []:
        if isinstance(f, dict) and f.get("path"):
            out.append(f"{f['path']} (sha256 {f.get('sha256', '?')})")
    return out


def _ring(rt):
    g = rt.get("geometry_m")
    if not isinstance(g, dict):
        return "ring: not recorded"
    dims = ", ".join(
        f"{label} {_num(1e3 * g[k], '.4g') if isinstance(g.get(k), (int, float)) else '?'} mm"
        for label, k in (("OD", "outer_diameter"), ("ID", "inner_diameter"), ("H", "height"))
    )
    return f"ring: {dims} ({rt.get('geometry_source', 'source not recorded')})"


def _material(rt):
    mat = rt.get("material")
    if not isinstance(mat, dict):
        return "ring material: not recorded"
    parts = []
    for k, scale, unit in (("E", 1e-9, " GPa"), ("nu", 1, ""), ("K", 1e-6, " MPa")):
        v = mat.get(k)
        if isinstance(v, (int, float)):
            parts.append(f"{k} {v * scale:.4g}{unit}")
    for k in ("eps0", "n"):
        if isinstance(mat.get(k), (int, float)):
            parts.append(f"{k} {mat[k]:.4g}")
    src = rt.get("material_source", "source not recorded")
    return f"ring material: {', '.join(parts) or 'not recorded'} ({src})"


def _ring_fit(m, rt):
    """Lines on an ``m`` fitted by ``fe-demo ring-fit`` (``rt``: ``provenance.ring_test``)."""
    illustrative = bool(rt.get("illustrative")) or bool(_get(rt, "source_params", "illustrative"))
    level = rt.get("band_level")
    band = (
        f"[{_num(rt.get('m_lower'), '.4f')}, {_num(rt.get('m_upper'), '.4f')}] at "
        f"{_num(100 * level, 'g') if isinstance(level, (int, float)) else '?'} %"
    )
    lines = [
        f"m = {m:.6g} fitted to ring-compression tests by fe-demo ring-fit: "
        f"{rt.get('n_points', '?')} points of {rt.get('column', '?')}, band {band}"
    ]
    if illustrative:
        lines[0] += (
            "; ILLUSTRATIVE, NOT a calibration result (fitted with fe-demo's shipped "
            "illustrative law, not a calibrated one)"
        )
    fit_m = rt.get("m")
    if isinstance(fit_m, (int, float)) and abs(fit_m - m) > 1e-12 * max(abs(m), 1.0):
        lines.append(f"the ring fit gave m = {fit_m:.6g}; this parameter file's m differs")
    files = _files(rt.get("measured_files"))
    lines.append("ring tests: " + ("; ".join(files) if files else "not recorded"))
    lines += [_ring(rt), _material(rt)]
    src = rt.get("source_params")
    if isinstance(src, dict) and src.get("path"):
        lines.append(f"source calibration: {src['path']} (sha256 {src.get('sha256', '?')})")
    elif illustrative:
        lines.append("source calibration: none (fe-demo's illustrative law)")
    else:
        lines.append("source calibration: not recorded")
    return lines, illustrative


def _surfaces(prov):
    """Lines on the surfaces: measured files (path, sha256) or synthetic (generator, seed)."""
    files = _get(prov, "extra", "files")
    out = []
    for f in files if isinstance(files, list) else []:
        if isinstance(f, dict) and f.get("path"):
            who = " ".join(str(f[k]) for k in ("sample", "role") if f.get(k))
            out.append(f"surface {who or 'file'}: {f['path']} (sha256 {f.get('sha256', '?')})")
    if out:
        return out
    surfaces = _get(prov, "surfaces")
    for role in ("workpiece", "tool"):
        s = _get(surfaces, role)
        if isinstance(s, dict):
            if s.get("path"):
                out.append(f"surface {role}: {s['path']} (sha256 {s.get('sha256', '?')})")
            else:
                out.append(
                    f"surface {role}: synthetic, generator {s.get('generator', '?')}, preset "
                    f"{s.get('preset', '?')}, seed {s.get('seed', '?')}"
                )
    if not out and isinstance(_get(surfaces, "note"), str):
        out.append(f"surfaces: {surfaces['note']}")
    return out or ["surfaces: not recorded in the parameter file"]


def m_origin(params):
    """The :class:`MOrigin` of ``params`` (a :class:`frictionlaw.FrictionParams`)."""
    prov = params.provenance if isinstance(params.provenance, dict) else {}
    rt = prov.get("ring_test")
    if isinstance(rt, dict):
        lines, illustrative = _ring_fit(params.m, rt)
    else:
        note = _get(prov, "inputs", "m")
        illustrative = False
        if isinstance(note, str):
            lines = [f"m = {params.m:.6g}: {note}"]
        else:
            lines = [f"m = {params.m:.6g}: its origin is not recorded in the parameter file"]
        top = prov.get("note")
        if isinstance(top, str) and "NOT a calibration result" in top:
            lines.append(f"parameter file: {top}")
            illustrative = True
    return MOrigin(tuple(lines), tuple(_surfaces(prov)), illustrative)

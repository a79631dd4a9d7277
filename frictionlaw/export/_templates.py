"""The export's template files and how they are rendered (private).

The Fortran, the READMEs and the table decks are files shipped with the package, one folder per
host beside this module (``abaqus/``, ``lsdyna/``, ``ansys/``, ``calculix/``, ``neutral/`` for
the host-neutral entry), plus ``core/`` (the law core every Fortran target includes),
``readme/`` (the README frames) and ``shims/`` (the host emulation of
:mod:`frictionlaw.export.harness`). They are Jinja templates: a template names another by its
path below this folder (``{% include "core/sbmf_core.f" %}``); a record may also name one by an
absolute path (a target defined outside the package).

The values the law core is rendered with come from one function,
:func:`frictionlaw.export._law.core_context`; a new law form changes it and ``core/sbmf_core.f``,
nothing per target.
"""

from pathlib import Path

import jinja2

__all__ = [
    "ROOT",
    "template_path",
    "render_template",
    "fortran_double",
    "fortran_chunks",
    "comment_block",
    "check_columns",
]

#: the folder the template names are relative to (this package)
ROOT = Path(__file__).resolve().parent


def fortran_double(v):
    """``v`` as a double-precision literal that reads back to the same float64."""
    s = f"{float(v):.17e}"
    mant, exp = s.split("e")
    return f"{mant}D{int(exp):+d}"


def fortran_chunks(text, width=56):
    """``text`` as pieces of a Fortran character literal, quotes doubled, each ``<= width``.

    A template writes each piece as ``'piece'`` on a continuation line joined by ``//``, so that
    a long message fits fixed form's 72 columns; no doubled quote is split.
    """
    out, cur = [], ""
    for ch in str(text):
        piece = "''" if ch == "'" else ch
        if len(cur) + len(piece) > width:
            out.append(cur)
            cur = ""
        cur += piece
    if cur or not out:
        out.append(cur)
    return out


def template_path(name):
    """The file of template ``name`` (a path below :data:`ROOT`, or an absolute path)."""
    path = Path(name)
    return path if path.is_absolute() else ROOT / path


def _load(name):
    path = template_path(name)
    if not path.is_file():
        return None
    mtime = path.stat().st_mtime
    return path.read_text(encoding="utf-8"), str(path), lambda: path.stat().st_mtime == mtime


_ENV = jinja2.Environment(
    loader=jinja2.FunctionLoader(_load),
    # a tag alone on its line leaves no blank line; text is kept byte for byte otherwise
    trim_blocks=True,
    lstrip_blocks=True,
    keep_trailing_newline=True,
    undefined=jinja2.StrictUndefined,
    autoescape=False,
)
_ENV.filters["double"] = fortran_double
_ENV.filters["fchunks"] = fortran_chunks
_ENV.filters["fmt"] = format


def render_template(template, /, **context):
    """Template ``template`` rendered with ``context`` (a missing name in it is an error)."""
    return _ENV.get_template(str(template)).render(**context)


def _wrap(lines, width):
    out = []
    for line in lines:
        while len(line) > width:
            cut = line.rfind(" ", 0, width)
            cut = cut if cut > 0 else width
            out.append(line[:cut])
            line = "  " + line[cut:].lstrip()
        out.append(line)
    return out


def comment_block(lines, marker, columns):
    """``lines`` as comment lines ``marker line``, wrapped (indented by 2) to ``columns``."""
    return "".join(f"{marker} {line}\n" for line in _wrap(lines, columns - len(marker) - 1))


def check_columns(text, columns, what):
    """``text`` if no line is longer than ``columns`` (fixed-form Fortran: 72), else ValueError."""
    for i, line in enumerate(text.splitlines(), 1):
        if len(line) > columns:
            raise ValueError(f"{what}: generated line {i} exceeds {columns} columns: {line!r}")
    return text

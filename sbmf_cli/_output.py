"""Output folders that appear whole or not at all and belong to the command that wrote them."""

from __future__ import annotations

import json
import os
import secrets
import shutil
from pathlib import Path

from ._errors import ParameterError
from ._options import version

__all__ = ["MARKER", "OutputFolder", "read_marker"]

#: the file by which a command marks a folder as its own output (JSON: command, version, files)
MARKER = ".sbmf-output.json"

#: the command layer's own parameters read as the options they are, also where a library
#: function (``frictionlaw.export.export``) takes them as ``out`` and ``force``
_PYTHON = {"out": "--out", "force": "--force"}


def _listing(folder):
    """Every file and symlink below ``folder`` as sorted POSIX paths relative to it."""
    folder = Path(folder)
    found = []
    for dirpath, dirnames, filenames in os.walk(folder):
        base = Path(dirpath)
        found += [(base / n).relative_to(folder).as_posix() for n in filenames]
        found += [
            (base / n).relative_to(folder).as_posix() for n in dirnames if (base / n).is_symlink()
        ]
    return sorted(found)


def read_marker(folder):
    """The ownership record of ``folder`` (a dict), or ``None`` where it has none or a bad one."""
    try:
        doc = json.loads((Path(folder) / MARKER).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    ok = (
        isinstance(doc, dict)
        and isinstance(doc.get("command"), str)
        and isinstance(doc.get("files"), list)
        and all(isinstance(f, str) for f in doc["files"])
    )
    return doc if ok else None


def _some(names, n=5):
    shown = ", ".join(names[:n])
    return shown + (f" and {len(names) - n} more" if len(names) > n else "")


def _fresh_folder(parent, prefix):
    """A new folder ``parent/<prefix><random>`` with the mode any new folder gets (umask)."""
    for _ in range(100):
        path = Path(parent) / f"{prefix}{secrets.token_hex(4)}"
        try:
            path.mkdir(mode=0o777)
        except FileExistsError:
            continue
        return path
    raise FileExistsError(f"no free temporary name in {parent}")  # pragma: no cover


def _refuse(template, *names):
    return ParameterError(template, "out", *names, python=_PYTHON)


class OutputFolder:
    """An output folder that appears whole or not at all, replaced only by the command that wrote it.

    The run writes into :attr:`tmp`, a fresh hidden folder beside ``out``; :meth:`commit` writes
    the ownership marker (:data:`MARKER`: the command, its version and every file it wrote) and
    moves the folder into place, replacing an earlier output as a whole (renamed aside, then
    deleted), so that no file of an earlier run survives beside the new ones. Leaving the
    ``with`` block without :meth:`commit` deletes :attr:`tmp` and leaves ``out`` as it was. The
    folders get the mode any new folder gets (``0777`` less the umask).

    An existing ``out`` is replaced only when it is empty, or when its marker names this command
    and it holds nothing but the files that marker lists: another command's output, a folder
    without a marker, a user's file beside (or below) an earlier output, and a folder holding one
    of the run's inputs are refused, naming what is in the way.

    Parameters
    ----------
    out : path
        The output folder.
    command : str
        The command's name as the marker records it (``"fe-demo"``, ``"halfspace-calib"``, ...).
    what : str
        What the command writes (for messages), e.g. ``"calibration output"``.
    force : bool
        Needed to replace even the command's own earlier output (commands that write into other
        programs' trees, such as ``frictionlaw-export``, replace nothing without it). It never
        lets a run delete files the command did not write, nor its input.
    require_force : bool
        Whether replacing the command's own earlier output needs ``force``.
    inputs : sequence of path
        Files the run reads; an ``out`` that contains one of them is refused.

    Raises
    ------
    ParameterError
        ``out`` is a file or a folder the command may not replace (see above), or its parent
        cannot be written; raised before any work (a ``ValueError``).
    """

    def __init__(self, out, *, command, what, force=False, require_force=False, inputs=()):
        self.out = Path(out)
        self.command = str(command)
        self.committed = False
        if self.out.exists() and not self.out.is_dir():
            raise _refuse(f"{{out}} {self.out} exists and is not a folder")
        here = self.out.resolve()
        for path in inputs:
            if path is None:
                continue
            p = Path(path).resolve()
            if p == here or here in p.parents:
                raise _refuse(
                    f"{{out}} {self.out} holds the input {path}: a run replaces its whole output "
                    f"folder, so write to a new folder, e.g. {self.out / 'out'} or another path"
                )
        if self.out.is_dir() and any(self.out.iterdir()):
            self._check_replaceable(force, require_force, what)
        try:
            self.out.parent.mkdir(parents=True, exist_ok=True)
            self.tmp = _fresh_folder(self.out.parent, f".{self.out.name}.tmp-")
        except OSError as exc:
            raise _refuse(f"{{out}} {self.out} is not writable ({exc.strerror or exc})") from None

    def _check_replaceable(self, force, require_force, what):
        hint = "give a new folder (or a subfolder of this one) to {out}"
        marker = read_marker(self.out)
        if marker is None:
            names = sorted(p.name + ("/" if p.is_dir() else "") for p in self.out.iterdir())
            raise _refuse(
                f"{{out}} {self.out} is a non-empty folder that holds no {what} (it holds "
                f"{_some(names)}); a run replaces its whole output folder, so {hint}"
            )
        if marker["command"] != self.command:
            raise _refuse(
                f"{{out}} {self.out} holds the output of {marker['command']}, not of "
                f"{self.command}; {self.command} will not replace it: {hint}"
            )
        foreign = sorted(set(_listing(self.out)) - set(marker["files"]) - {MARKER})
        if foreign:
            raise _refuse(
                f"{{out}} {self.out} is an earlier {what} but also holds files {self.command} did "
                f"not write ({_some(foreign)}); move them away or {hint}"
            )
        if require_force and not force:
            raise _refuse(
                f"{{out}} {self.out} holds an earlier {what}; add {{force}} to replace it, or "
                f"{hint}",
                "force",
            )

    def commit(self):
        """Mark the output as this command's and move it into place (replacing an earlier one)."""
        files = [f for f in _listing(self.tmp) if f != MARKER]
        record = {"command": self.command, "version": version(), "files": files}
        (self.tmp / MARKER).write_text(json.dumps(record, indent=1) + "\n", encoding="utf-8")
        old = None
        if self.out.exists():
            old = _fresh_folder(self.out.parent, f".{self.out.name}.old-")
            os.replace(self.out, old / "set")
        os.replace(self.tmp, self.out)
        self.committed = True
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)

    def discard(self):
        """Delete the temporary folder (``out`` is unchanged)."""
        if not self.committed:
            shutil.rmtree(self.tmp, ignore_errors=True)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.discard()
        return False

"""Atomic file writes (parameter and restart files) and the parameter file's table objects."""

import os
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import IO, Any, TypeVar

_T = TypeVar("_T")


def read_versioned(
    doc: dict, where: str, version: int, units: dict[str, str], build: Callable[[dict], _T]
) -> _T:
    """``build(doc)`` after checking the object's ``version`` and ``units``.

    ``ValueError`` naming the field (``where.version``, ``where.<key>``) for another version, a
    unit other than ``units`` gives, a missing key or a value ``build`` refuses. A unit the
    object does not state is taken as the expected one.
    """
    given: Any = doc.get("version")
    if type(given) is not int or given != version:
        raise ValueError(
            f"{where}.version: unsupported version {given!r}; this runtime reads {version}"
        )
    stated = doc.get("units", {})
    if not isinstance(stated, dict):
        raise ValueError(f"{where}.units must be a JSON object")
    for key, unit in units.items():
        if stated.get(key, unit) != unit:
            raise ValueError(f"{where}.{key} must be given in {unit!r}")
    try:
        return build(doc)
    except KeyError as exc:
        raise ValueError(f"{where}: missing {exc.args[0]!r}") from None
    except ValueError as exc:
        raise ValueError(f"{where}: {exc}") from None


def atomic_write(path: str | os.PathLike[str], write: Callable[[IO[bytes]], object]) -> Path:
    """Write a file atomically: ``write(fileobj)`` fills a temporary file that replaces ``path``.

    Readers see either the old file or the complete new one, never a partial write. The
    file gets the mode any new file gets (``0666`` less the process's umask).
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        os.fchmod(fd, 0o666 & ~_umask())  # mkstemp makes 0600; a new file follows the umask
        with os.fdopen(fd, "wb") as fh:
            write(fh)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path


def _umask() -> int:
    """The process's file-creation mask (read from /proc where possible: no race)."""
    try:
        with open("/proc/self/status", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError):
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return mask

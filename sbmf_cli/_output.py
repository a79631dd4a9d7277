"""Output folders that appear whole or not at all and belong to the command that wrote them."""

from __future__ import annotations

import json
import os
import secrets
import shutil
import socket
import sys
import time
from pathlib import Path

from ._errors import ParameterError
from ._options import version

__all__ = ["MARKER", "OutputFolder", "read_marker", "lock_path"]

#: the file by which a command marks a folder as its own output (JSON: command, subcommand,
#: version, files)
MARKER = ".sbmf-output.json"
#: a lock file without a readable record is taken for one being written for this long (s)
LOCK_GRACE = 60.0

#: the lock files held by the OutputFolders alive in this process
_HELD: set[str] = set()

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


def lock_path(out):
    """The lock file of output folder ``out``: ``.<name>.lock`` beside it."""
    out = Path(out)
    return out.parent / f".{out.name}.lock"


def _read_lock(path):
    try:
        doc = json.loads(Path(path).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    return doc if isinstance(doc, dict) else {}


def _pid_alive(pid):
    """Whether process ``pid`` of this host is running (a zombie is not)."""
    if os.name == "nt":  # pragma: no cover - Windows: os.kill(pid, 0) would end the process
        import ctypes

        kernel = ctypes.windll.kernel32  # type: ignore[attr-defined]
        handle = kernel.OpenProcess(0x1000, False, pid)  # PROCESS_QUERY_LIMITED_INFORMATION
        if not handle:
            return False
        code = ctypes.c_ulong()
        kernel.GetExitCodeProcess(handle, ctypes.byref(code))
        kernel.CloseHandle(handle)
        return code.value == 259  # STILL_ACTIVE
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's process
        return True
    if sys.platform.startswith("linux"):
        try:
            state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
        except (OSError, IndexError):
            return True
        return state not in ("Z", "X")
    return True


def _holder_alive(path, holder):
    """Whether the run that wrote lock record ``holder`` may still be writing."""
    pid = holder.get("pid")
    if not isinstance(pid, int):  # being written, or left unreadable
        try:
            return time.time() - path.stat().st_mtime < LOCK_GRACE
        except OSError:
            return False
    if holder.get("host") != socket.gethostname():
        return True  # another machine's process: it cannot be checked from here
    if pid == os.getpid():
        return str(path) in _HELD
    return _pid_alive(pid)


def _holder_text(holder):
    who = f"{holder.get('command', 'a command')}"
    if holder.get("subcommand"):
        who += f" {holder['subcommand']}"
    if not isinstance(holder.get("pid"), int):
        return f"{who} (its lock record is being written)"
    started = holder.get("started")
    since = f", started {time.strftime('%Y-%m-%d %H:%M:%S', time.localtime(started))}"
    return f"{who} (process {holder['pid']} on {holder.get('host')}{since if started else ''})"


class _Lock:
    """The lock of an output folder: a file beside it naming the process that writes it.

    Created atomically; a lock whose process has ended (or whose record stayed unreadable for
    :data:`LOCK_GRACE` seconds) is stale and taken over, and the temporary folder that process
    left is deleted.
    """

    def __init__(self, out, command, subcommand):
        self.out = Path(out)
        self.path = lock_path(out)
        self.record = {
            "pid": os.getpid(),
            "host": socket.gethostname(),
            "command": command,
            "subcommand": subcommand,
            "started": time.time(),
            "token": secrets.token_hex(8),
        }

    def acquire(self):
        for _ in range(3):
            try:
                fd = os.open(self.path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
            except FileExistsError:
                holder = _read_lock(self.path)
                if _holder_alive(self.path, holder):
                    raise _refuse(
                        f"{{out}} {self.out} is being written by another run: "
                        f"{_holder_text(holder)}; wait for it to end or give another folder "
                        f"(if that run is gone for good, delete {self.path})"
                    ) from None
                self._clear(holder)  # stale: the run that held it has ended
                continue
            with os.fdopen(fd, "w", encoding="utf-8") as fh:
                json.dump(self.record, fh)
            _HELD.add(str(self.path))
            return
        raise _refuse(f"{{out}} {self.out}: could not take over the stale lock {self.path}")

    def _clear(self, holder):
        """Delete a stale lock and the temporary folder its run left beside ``out``."""
        tmp = holder.get("tmp")
        if isinstance(tmp, str):
            tmp = Path(tmp)
            if tmp.parent == self.out.parent and tmp.name.startswith(f".{self.out.name}.tmp-"):
                shutil.rmtree(tmp, ignore_errors=True)
        try:
            self.path.unlink()
        except FileNotFoundError:
            pass

    def note(self, tmp):
        """Record the run's temporary folder in the lock (a taker-over deletes it)."""
        self.record["tmp"] = str(tmp)
        self.path.write_text(json.dumps(self.record), encoding="utf-8")

    def release(self):
        if str(self.path) not in _HELD:
            return
        _HELD.discard(str(self.path))
        if _read_lock(self.path).get("token") == self.record["token"]:
            try:
                self.path.unlink()
            except OSError:
                pass


class OutputFolder:
    """An output folder that appears whole or not at all, replaced only by the command that wrote it.

    The run writes into :attr:`tmp`, a fresh hidden folder beside ``out``; :meth:`commit` writes
    the ownership marker (:data:`MARKER`: the command, its version and every file it wrote) and
    moves the folder into place, replacing an earlier output as a whole (renamed aside, then
    deleted), so that no file of an earlier run survives beside the new ones. Leaving the
    ``with`` block without :meth:`commit` deletes :attr:`tmp` and leaves ``out`` as it was. The
    folders get the mode any new folder gets (``0777`` less the umask).

    An existing ``out`` is replaced only when it is empty, or when its marker names this command
    (and subcommand) and it holds nothing but the files that marker lists: another command's or
    subcommand's output, a folder without a marker, a user's file beside (or below) an earlier
    output, and a folder holding one of the run's inputs are refused, naming what is in the way.
    An output of a command with subcommands whose marker names none (written before markers named
    it) is replaced only with ``force``.

    While the run writes, a lock file beside ``out`` (:func:`lock_path`) names its process; a
    second run on the same ``out`` is refused, naming that process, as long as it is alive (a
    lock left by a process that has ended is taken over).

    Parameters
    ----------
    out : path
        The output folder.
    command : str
        The command's name as the marker records it (``"fe-demo"``, ``"halfspace-calib"``, ...).
    what : str
        What the command writes (for messages), e.g. ``"calibration output"``.
    subcommand : str, optional
        The subcommand (``"upsetting"``, ``"ring-fit"``), recorded in the marker: each
        subcommand owns only its own output.
    force : bool
        Needed to replace even the command's own earlier output (commands that write into other
        programs' trees, such as ``frictionlaw-export``, replace nothing without it), and an
        earlier output whose marker names no subcommand. It never lets a run delete files the
        command did not write, another (sub)command's output, nor its input.
    require_force : bool
        Whether replacing the command's own earlier output needs ``force``.
    inputs : sequence of path
        Files the run reads; an ``out`` that contains one of them is refused.
    products : sequence of str
        Files (paths relative to ``out``) that a later step of the workflow may add to the
        output, such as the program a shipped build script links there: they count as the
        command's own when the folder is replaced.

    Raises
    ------
    ParameterError
        ``out`` is a file, a folder the command may not replace (see above), one another running
        command writes, or its parent cannot be written; raised before any work (a
        ``ValueError``).
    """

    def __init__(
        self,
        out,
        *,
        command,
        what,
        subcommand=None,
        force=False,
        require_force=False,
        inputs=(),
        products=(),
    ):
        self.out = Path(out)
        self.command = str(command)
        self.products = frozenset(products)
        self.subcommand = subcommand
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
        try:
            self.out.parent.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise _refuse(f"{{out}} {self.out} is not writable ({exc.strerror or exc})") from None
        self._lock = _Lock(self.out, self.command, subcommand)
        self._lock.acquire()
        try:
            if self.out.is_dir() and any(self.out.iterdir()):
                self._check_replaceable(force, require_force, what)
            self.tmp = _fresh_folder(self.out.parent, f".{self.out.name}.tmp-")
            self._lock.note(self.tmp)
        except OSError as exc:
            self._lock.release()
            raise _refuse(f"{{out}} {self.out} is not writable ({exc.strerror or exc})") from None
        except BaseException:
            self._lock.release()
            raise

    def _name(self, command, subcommand):
        return f"{command} {subcommand}" if subcommand else command

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
        self._check_subcommand(marker, force, hint)
        foreign = sorted(set(_listing(self.out)) - set(marker["files"]) - {MARKER} - self.products)
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

    def _check_subcommand(self, marker, force, hint):
        """Each subcommand owns its output; a marker naming none is replaced only with force."""
        if self.subcommand is None:
            return
        theirs = marker.get("subcommand")
        mine = self._name(self.command, self.subcommand)
        if theirs is None and not force:
            raise _refuse(
                f"{{out}} {self.out} holds an output of {self.command} whose marker names no "
                f"subcommand (written by an earlier version): it may be another subcommand's; "
                f"add {{force}} to replace it with the {mine} output, or {hint}",
                "force",
            )
        if theirs is not None and theirs != self.subcommand:
            raise _refuse(
                f"{{out}} {self.out} holds the output of {self._name(self.command, theirs)}, not "
                f"of {mine}; {mine} will not replace it: {hint}"
            )

    def commit(self):
        """Mark the output as this command's and move it into place (replacing an earlier one)."""
        files = [f for f in _listing(self.tmp) if f != MARKER]
        record: dict[str, object] = {"command": self.command}
        if self.subcommand is not None:
            record["subcommand"] = self.subcommand
        record |= {"version": version(), "files": files}
        (self.tmp / MARKER).write_text(json.dumps(record, indent=1) + "\n", encoding="utf-8")
        old = None
        if self.out.exists():
            old = _fresh_folder(self.out.parent, f".{self.out.name}.old-")
            os.replace(self.out, old / "set")
        os.replace(self.tmp, self.out)
        self.committed = True
        self._lock.release()
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)

    def discard(self):
        """Delete the temporary folder (``out`` is unchanged) and release the lock."""
        if not self.committed:
            shutil.rmtree(self.tmp, ignore_errors=True)
        self._lock.release()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.discard()
        return False

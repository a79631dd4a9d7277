"""Conventions shared by the four command lines of the project.

``halfspace-calib``, ``fe-demo``, ``frictionlaw-export`` and ``frictionlaw-demo`` use this module
(it lives in ``frictionlaw``, the layer the other two packages may import) so that they agree:

- ``--version`` prints the installed distribution's version and exits 0;
- ``--quiet`` hides the progress bar and the summary; ``--no-progress`` hides only the progress
  bar; warnings and errors still reach stderr with either;
- results go to stdout, warnings and errors to stderr (:class:`Console`);
- every option's help shows its default (:class:`HelpFormatter`), and ``--help`` carries no
  reStructuredText markup;
- output folders appear whole or not at all (:class:`OutputFolder`): a run writes into a fresh
  hidden folder beside ``--out`` and moves it into place at the end; it replaces only an earlier
  output of the same command (its marker file says so) that holds nothing else; any other
  non-empty folder, or one holding the run's input, is refused (exit 2), ``--force`` included.

Exit codes: 0 success, 1 the run failed, 2 bad input (no traceback).
"""

from __future__ import annotations

import argparse
import contextlib
import ctypes
import functools
import json
import os
import shutil
import signal
import sys
import tempfile
import threading
from concurrent.futures import ProcessPoolExecutor
from importlib import metadata
from pathlib import Path

from ._io import _umask

__all__ = [
    "Console",
    "Interrupted",
    "interruptible",
    "HelpFormatter",
    "MARKER",
    "OutputFolder",
    "add_common_options",
    "parse",
    "process_pool",
    "read_marker",
    "worker_ignores_interrupts",
    "version",
]

#: the distribution whose version ``--version`` prints
DISTRIBUTION = "sbmf-friction"


def version():
    """The installed version of the ``sbmf-friction`` distribution (``"unknown"`` if not installed)."""
    try:
        return metadata.version(DISTRIBUTION)
    except metadata.PackageNotFoundError:
        return "unknown (not installed as a distribution)"


class HelpFormatter(argparse.HelpFormatter):
    """Help that shows each option's default unless its help text already states one.

    Flags (``store_true``/``store_false``) are off/on by default and say nothing more; an option
    whose default is ``None`` must state in its help what applies when it is omitted.
    """

    def _get_help_string(self, action):
        text = action.help or ""
        if (
            not action.option_strings
            or "default" in text
            or action.default in (None, argparse.SUPPRESS)
            or isinstance(action.default, bool)
            or action.nargs == 0
        ):
            return text
        return f"{text} (default: %(default)s)"


def add_common_options(parser, *, quiet=True, progress=True):
    """Add ``--quiet`` and/or ``--no-progress`` (see the module docstring).

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The parser (or sub-parser) to add to.
    quiet : bool
        Add ``--quiet`` (hide progress and the summary on stdout).
    progress : bool
        Add ``--no-progress`` (hide only the progress bar).
    """
    if quiet:
        parser.add_argument(
            "--quiet",
            action="store_true",
            help="print no summary and no progress bar (warnings and errors still go to stderr)",
        )
    if progress:
        parser.add_argument(
            "--no-progress", action="store_true", help="hide the progress bar, keep the summary"
        )


class Interrupted(BaseException):
    """SIGTERM (or another handled signal) turned into an exception, like KeyboardInterrupt."""

    def __init__(self, signum):
        super().__init__(signum)
        self.signum = signum


def _raise_interrupted(signum, frame):
    raise Interrupted(signum)


def interruptible(prog, what):
    """Decorate a command's ``main`` so that SIGINT and SIGTERM end it cleanly.

    Ctrl-C (SIGINT, to the process group or to this process alone) and SIGTERM raise in the
    main process (SIGTERM through :class:`Interrupted`); the run's own cleanup runs on the way
    out (its temporary output folder is deleted, an earlier output is left as it was, worker
    processes are ended by the job runner), and the command prints one line and returns
    ``128 + signal number`` (130 for SIGINT, 143 for SIGTERM), without a traceback.
    """

    def wrap(main):
        @functools.wraps(main)
        def run(argv=None):
            in_main = threading.current_thread() is threading.main_thread()
            old = signal.signal(signal.SIGTERM, _raise_interrupted) if in_main else None
            try:
                return main(argv)
            except (KeyboardInterrupt, Interrupted) as exc:
                signum = getattr(exc, "signum", signal.SIGINT)
                name = signal.Signals(signum).name
                print(
                    f"{prog}: interrupted by {name} during {what}; the output folder was not "
                    "written (an earlier output there is unchanged)",
                    file=sys.stderr,
                )
                return 128 + int(signum)
            finally:
                if in_main:
                    signal.signal(signal.SIGTERM, old)

        return run

    return wrap


def worker_ignores_interrupts():
    """Set up a worker process of a command's pool so that interrupts stay the main process's.

    Ctrl-C reaches the whole process group: the worker ignores SIGINT (no traceback of its own)
    and is ended by the main process (:func:`process_pool`). SIGTERM ends it at once (the default
    action, not an inherited handler), and on Linux the kernel sends it SIGTERM when the main
    process dies (``PR_SET_PDEATHSIG``), so that no worker outlives its run.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    if sys.platform.startswith("linux"):
        try:
            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(1, int(signal.SIGTERM))  # PR_SET_PDEATHSIG = 1
        except (OSError, AttributeError):  # pragma: no cover - no prctl here
            pass


def _init_pool_worker(initializer, initargs):
    worker_ignores_interrupts()
    if initializer is not None:
        initializer(*initargs)


@contextlib.contextmanager
def process_pool(max_workers, initializer=None, initargs=()):
    """A ``ProcessPoolExecutor`` that an interrupt ends at once, workers included.

    On the way out of the block with an exception (Ctrl-C, SIGTERM as :class:`Interrupted`, a
    failed job) the pending jobs are cancelled and the running workers terminated: the
    executor's own ``shutdown(wait=True)`` would wait for workers that keep computing. Without an
    exception the pool is shut down normally. The workers run :func:`worker_ignores_interrupts`
    before ``initializer(*initargs)``.
    """
    pool = ProcessPoolExecutor(
        max_workers=max_workers, initializer=_init_pool_worker, initargs=(initializer, initargs)
    )
    try:
        yield pool
    except BaseException:
        procs = list((getattr(pool, "_processes", None) or {}).values())
        pool.shutdown(wait=False, cancel_futures=True)
        for p in procs:
            if p.is_alive():
                p.terminate()
        for p in procs:
            p.join(timeout=5)
            if p.is_alive():
                p.kill()
        raise
    pool.shutdown(wait=True)


def add_version(parser):
    """Add ``--version`` (prints ``<prog> <version>`` and exits 0)."""
    parser.add_argument(
        "--version", action="version", version=f"%(prog)s {version()}", help="print the version"
    )


def parse(parser, argv=None):
    """``(args, None)``, or ``(None, exit code)`` where argparse exits.

    argparse exits 2 for a bad option (its message already on stderr) and 0 for ``--help`` and
    ``--version``; a command returns that code instead of raising ``SystemExit``.
    """
    try:
        args, extra = parser.parse_known_args(argv)
        if extra:  # a typo in a subcommand's option: that subcommand's usage, not the top level's
            _subparser(parser, args).error(f"unrecognized arguments: {' '.join(extra)}")
        return args, None
    except SystemExit as exc:
        return None, exc.code if isinstance(exc.code, int) else 2


def _subparser(parser, args):
    """The subcommand parser ``args`` came through, or ``parser`` itself."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            chosen = getattr(args, action.dest, None)
            return parser if chosen is None else action.choices.get(chosen, parser)
    return parser


class Console:
    """Where a command's lines go: results on stdout (unless quiet), the rest on stderr.

    Parameters
    ----------
    prog : str
        The command's name, prefixed to errors and warnings.
    quiet : bool
        Suppress :meth:`result` lines.
    """

    def __init__(self, prog, quiet=False):
        self.prog = prog
        self.quiet = bool(quiet)

    def result(self, line=""):
        """A line of the summary (stdout; hidden by ``--quiet``)."""
        if not self.quiet:
            try:
                print(line, file=sys.stdout, flush=True)
            except BrokenPipeError:  # the reader went away (``| head``): stop writing, no traceback
                sys.stdout = open(os.devnull, "w")  # noqa: SIM115
                self.quiet = True

    def warn(self, line):
        """A warning (stderr, always)."""
        print(line, file=sys.stderr)

    def error(self, msg, code):
        """Print ``<prog>: error: msg`` to stderr and return the exit code ``code``."""
        print(f"{self.prog}: error: {msg}", file=sys.stderr)
        return code


#: the file by which a command marks a folder as its own output (JSON: command, version, files)
MARKER = ".sbmf-output.json"


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
    products : sequence of str
        Files (paths relative to ``out``) that a later step of the workflow may add to the
        output, such as the program a shipped build script links there: they count as the
        command's own when the folder is replaced.

    Raises
    ------
    ValueError
        ``out`` is a file or a folder the command may not replace (see above), or its parent
        cannot be written; raised before any work.
    """

    def __init__(
        self, out, *, command, what, force=False, require_force=False, inputs=(), products=()
    ):
        self.out = Path(out)
        self.command = str(command)
        self.products = frozenset(products)
        if self.out.exists() and not self.out.is_dir():
            raise ValueError(f"--out {self.out} exists and is not a folder")
        here = self.out.resolve()
        for path in inputs:
            if path is None:
                continue
            p = Path(path).resolve()
            if p == here or here in p.parents:
                raise ValueError(
                    f"--out {self.out} holds the input {path}: a run replaces its whole output "
                    f"folder, so write to a new folder, e.g. {self.out / 'out'} or another path"
                )
        if self.out.is_dir() and any(self.out.iterdir()):
            self._check_replaceable(force, require_force, what)
        try:
            self.out.parent.mkdir(parents=True, exist_ok=True)
            self.tmp = Path(tempfile.mkdtemp(prefix=f".{self.out.name}.tmp-", dir=self.out.parent))
            os.chmod(self.tmp, 0o777 & ~_umask())  # mkdtemp makes 0700; follow the umask
        except OSError as exc:
            raise ValueError(f"--out {self.out} is not writable ({exc.strerror or exc})") from None
        self.committed = False

    def _check_replaceable(self, force, require_force, what):
        hint = "give a new folder (or a subfolder of this one) to --out"
        marker = read_marker(self.out)
        if marker is None:
            names = sorted(p.name + ("/" if p.is_dir() else "") for p in self.out.iterdir())
            raise ValueError(
                f"--out {self.out} is a non-empty folder that holds no {what} (it holds "
                f"{_some(names)}); a run replaces its whole output folder, so {hint}"
            )
        if marker["command"] != self.command:
            raise ValueError(
                f"--out {self.out} holds the output of {marker['command']}, not of "
                f"{self.command}; {self.command} will not replace it: {hint}"
            )
        foreign = sorted(set(_listing(self.out)) - set(marker["files"]) - {MARKER} - self.products)
        if foreign:
            raise ValueError(
                f"--out {self.out} is an earlier {what} but also holds files {self.command} did "
                f"not write ({_some(foreign)}); move them away or {hint}"
            )
        if require_force and not force:
            raise ValueError(
                f"--out {self.out} holds an earlier {what}; add --force to replace it, or {hint}"
            )

    def commit(self):
        """Mark the output as this command's and move it into place (replacing an earlier one)."""
        files = [f for f in _listing(self.tmp) if f != MARKER]
        record = {"command": self.command, "version": version(), "files": files}
        (self.tmp / MARKER).write_text(json.dumps(record, indent=1) + "\n", encoding="utf-8")
        old = None
        if self.out.exists():
            old = Path(tempfile.mkdtemp(prefix=f".{self.out.name}.old-", dir=self.out.parent))
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

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
  hidden folder beside ``--out`` and moves it into place at the end, replacing an earlier output
  of the same command as a whole; a non-empty folder that holds no such output is refused (exit
  2) unless the command has an explicit ``--force``.

Exit codes: 0 success, 1 the run failed, 2 bad input (no traceback).
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
import tempfile
from importlib import metadata
from pathlib import Path

__all__ = [
    "Console",
    "HelpFormatter",
    "OutputFolder",
    "add_common_options",
    "parse",
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
        return parser.parse_args(argv), None
    except SystemExit as exc:
        return None, exc.code if isinstance(exc.code, int) else 2


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
            print(line, file=sys.stdout)

    def warn(self, line):
        """A warning (stderr, always)."""
        print(line, file=sys.stderr)

    def error(self, msg, code):
        """Print ``<prog>: error: msg`` to stderr and return the exit code ``code``."""
        print(f"{self.prog}: error: {msg}", file=sys.stderr)
        return code


class OutputFolder:
    """An output folder that appears whole or not at all.

    The run writes into :attr:`tmp`, a fresh hidden folder beside ``out``; :meth:`commit` moves it
    into place, replacing an earlier output as a whole (renamed aside, then deleted), so that no
    file of an earlier run survives beside the new ones. Leaving the ``with`` block without
    :meth:`commit` deletes :attr:`tmp` and leaves ``out`` as it was.

    Parameters
    ----------
    out : path
        The output folder.
    markers : sequence of str
        Glob patterns (relative to ``out``) of files that mark ``out`` as an earlier output of the
        same command; such a folder, an empty one or a missing one is accepted.
    what : str
        What the command writes (for the refusal message), e.g. ``"calibration output"``.
    force : bool
        Accept any existing folder (a command's explicit ``--force``).

    Raises
    ------
    ValueError
        ``out`` is a file, a non-empty folder without a marker (and not ``force``), or its
        parent cannot be written; raised before any work.
    """

    def __init__(self, out, *, markers, what, force=False):
        self.out = Path(out)
        if self.out.exists() and not self.out.is_dir():
            raise ValueError(f"--out {self.out} exists and is not a folder")
        if not force and self.out.is_dir() and any(self.out.iterdir()):
            if not any(any(self.out.glob(m)) for m in markers):
                raise ValueError(
                    f"--out {self.out} is a non-empty folder that holds no {what}; a run "
                    "replaces its whole output folder, so give a new or an earlier output folder"
                )
        try:
            self.out.parent.mkdir(parents=True, exist_ok=True)
            self.tmp = Path(tempfile.mkdtemp(prefix=f".{self.out.name}.tmp-", dir=self.out.parent))
        except OSError as exc:
            raise ValueError(f"--out {self.out} is not writable ({exc.strerror or exc})") from None
        self.committed = False

    def commit(self):
        """Move the finished output into place (replacing an earlier one whole)."""
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

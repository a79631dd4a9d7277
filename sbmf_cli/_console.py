"""Where a command's lines go: results on stdout, warnings and errors on stderr."""

from __future__ import annotations

import os
import sys
from pathlib import Path

from ._errors import ParameterError, Worded

__all__ = ["Console"]


class Console:
    """Where a command's lines go: results on stdout (unless quiet), the rest on stderr.

    It keeps the result lines (:attr:`lines`, shown or not) for the run's ``summary.txt``
    (:meth:`write_summary`).

    Parameters
    ----------
    prog : str
        The command's name, prefixed to errors and warnings.
    quiet : bool
        Suppress :meth:`result` lines on stdout.
    flags : dict, optional
        ``{Python name: flag}`` (:func:`sbmf_cli.flags_of`): how :meth:`error` words a
        :class:`sbmf_cli.ParameterError`.
    """

    def __init__(self, prog, quiet=False, flags=None):
        self.prog = prog
        self.quiet = bool(quiet)
        self.flags = dict(flags or {})
        self.lines = []

    def result(self, line=""):
        """A line of the summary (stdout; hidden by ``--quiet``, kept for ``summary.txt``)."""
        self.lines.append(line)
        if not self.quiet:
            try:
                print(line, file=sys.stdout, flush=True)
            except BrokenPipeError:  # the reader went away (``| head``): stop writing, no traceback
                sys.stdout = open(os.devnull, "w")  # noqa: SIM115
                self.quiet = True

    def warn(self, line):
        """A warning (stderr, always)."""
        print(line, file=sys.stderr)

    def text(self, error):
        """A message in the command's words (its flags for a ParameterError or a Worded text)."""
        if isinstance(error, ParameterError | Worded):
            return error.render(self.flags)
        return str(error)

    def error(self, error, code):
        """Print ``<prog>: error: <message>`` to stderr and return the exit code ``code``.

        ``error`` is a message or an exception (a :class:`sbmf_cli.ParameterError` is worded
        with the command's flags).
        """
        print(f"{self.prog}: error: {self.text(error)}", file=sys.stderr)
        return code

    def write_summary(self, folder, name="summary.txt"):
        """Write the result lines so far into ``folder/name`` (what stdout showed, or would)."""
        Path(folder, name).write_text("\n".join(self.lines) + "\n", encoding="utf-8")

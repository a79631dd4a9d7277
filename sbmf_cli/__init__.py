"""The command layer of the ``sbmf-friction`` distribution: what every command line shares.

``halfspace-calib``, ``fe-demo`` (``ring-fit`` included), ``frictionlaw-export``,
``frictionlaw-demo`` and the GetFEM coupling (``couplings/getfem/ring.py``) use this package so
that they agree:

- ``--version`` prints the installed distribution's version and exits 0;
- ``--quiet`` hides the progress bar and the summary; ``--no-progress`` hides only the progress
  bar; warnings and errors still reach stderr with either (:func:`add_common_options`);
- results go to stdout, warnings and errors to stderr (:class:`Console`, which also keeps the
  summary for ``summary.txt``);
- every option's help shows its default (:class:`HelpFormatter`), and ``--help`` carries no
  reStructuredText markup;
- library code raises :class:`ParameterError` naming its parameters by their Python names, and a
  command words the message with its own flags (:func:`flags_of`, :meth:`Console.error`);
- output folders appear whole or not at all (:class:`OutputFolder`): a run writes into a fresh
  hidden folder beside ``--out`` and moves it into place at the end; it replaces only an earlier
  output of the same command (its marker file says so) that holds nothing else; any other
  non-empty folder, or one holding the run's input, is refused (exit 2), ``--force`` included;
- Ctrl-C and SIGTERM end a run cleanly (:func:`interruptible`), workers of a local pool included
  (:func:`process_pool`), on the CPUs the process may use (:func:`available_cpus`);
- reports are self-contained HTML pages (:mod:`sbmf_cli.htmlpage`);
- every output names a column with its unit (:func:`column_name`: ``force_N``,
  ``height_reduction_fraction``), and readers take old and new names (:func:`column_key`).

Exit codes: 0 success, 1 the run failed, 2 bad input (no traceback).

A package of its own, standard library only and importing nothing of the project: the bottom
floor every package may import, and outside the runtime law's import path (``import
frictionlaw`` does not load it; an FE code that calls the law per node never carries it).
"""

from ._console import Console
from ._errors import ParameterError, Worded
from ._options import (
    DISTRIBUTION,
    HelpFormatter,
    add_common_options,
    add_version,
    flags_of,
    parse,
    print_version,
    version,
)
from ._output import MARKER, OutputFolder, lock_path, read_marker
from ._processes import (
    Interrupted,
    available_cpus,
    interruptible,
    process_pool,
    process_seconds,
    worker_ignores_interrupts,
)
from ._units import UNIT_SUFFIXES, column_key, column_name

__all__ = [
    "Console",
    "DISTRIBUTION",
    "HelpFormatter",
    "Interrupted",
    "MARKER",
    "OutputFolder",
    "ParameterError",
    "UNIT_SUFFIXES",
    "Worded",
    "add_common_options",
    "add_version",
    "available_cpus",
    "column_key",
    "column_name",
    "flags_of",
    "interruptible",
    "lock_path",
    "parse",
    "print_version",
    "process_pool",
    "process_seconds",
    "read_marker",
    "version",
    "worker_ignores_interrupts",
]

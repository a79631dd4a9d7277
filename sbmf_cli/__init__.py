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
- a value option given twice is refused rather than the last kept (:func:`refuse_repeats`,
  every command), and an empty file path is refused naming its option
  (:func:`file_path`);
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

The names are imported on first use (PEP 562): a command's light entry point
(:func:`light_entry`) loads only what it needs before it handles Ctrl-C.
"""

from ._entry import lazy_names

#: the public names and the module each comes from (imported on first use)
_SOURCES = {
    "add_common_options": "._options",
    "add_version": "._options",
    "available_cpus": "._processes",
    "column_key": "._units",
    "column_name": "._units",
    "Console": "._console",
    "DISTRIBUTION": "._options",
    "existing_file": "._options",
    "file_path": "._options",
    "flags_of": "._options",
    "HelpFormatter": "._options",
    "Interrupted": "._processes",
    "interruptible": "._processes",
    "light_entry": "._entry",
    "lock_path": "._output",
    "MARKER": "._output",
    "OutputFolder": "._output",
    "ParameterError": "._errors",
    "parse": "._options",
    "print_version": "._options",
    "process_pool": "._processes",
    "process_seconds": "._processes",
    "read_marker": "._output",
    "refuse_repeats": "._options",
    "UNIT_SUFFIXES": "._units",
    "version": "._options",
    "Worded": "._errors",
    "worker_ignores_interrupts": "._processes",
}

__all__ = sorted([*_SOURCES, "lazy_names"], key=str.lower)

__getattr__, __dir__ = lazy_names(__name__, _SOURCES)

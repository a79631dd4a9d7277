"""Light console-script entry points: interrupts handled and ``--version`` answered first.

A command's modules load NumPy, SciPy, matplotlib and numba, seconds on a cold start. Its console
script enters through a light module (``halfspace_calib.__main__``, ``fe_demo.__main__``) whose
``main`` is :func:`light_entry`'s: Ctrl-C during those imports is already one line and exit 130,
and ``--version`` answers without them. The package itself imports its names on first use
(:func:`lazy_names`), so that importing the light module loads nothing heavy.
"""

from __future__ import annotations

import importlib
import os
import signal
import sys

__all__ = ["lazy_names", "light_entry"]

#: the exit codes of an interrupted command (128 + SIGINT, 128 + SIGTERM)
_INTERRUPTED = (128 + int(signal.SIGINT), 128 + int(signal.SIGTERM))


def light_entry(prog, what, command):
    """A console script's ``main``: ``command()`` (which imports the command) under interrupts.

    Parameters
    ----------
    prog : str
        The command's name (``--version`` prints it, the interrupt line starts with it).
    what : str
        What an interrupt stops (``"the calibration"``).
    command : callable
        ``command() -> main``: imports the command's module and returns its ``main(argv)``.

    An interrupted command (exit 130 or 143, its cleanup done) ends the process at once with
    that status (``os._exit``), so that no state an interrupted import left behind turns it into
    a death by the signal.
    """

    def run(argv):
        from ._options import print_version
        from ._processes import interruptible

        if print_version(prog, argv):
            return 0
        return interruptible(prog, what)(lambda a: command()(a))(argv)

    def main(argv=None):
        try:  # the command layer's own modules load here too, before interruptible handles it
            code = run(argv)
        except KeyboardInterrupt:
            from ._errors import interrupted_line

            print(interrupted_line(prog, what, signal.SIGINT), file=sys.stderr)
            code = 128 + int(signal.SIGINT)
        if code in _INTERRUPTED:
            # The run's cleanup is done (its temporary folder deleted, workers ended). End here:
            # an interrupt that arrived inside a C extension's own evaluation of Python code
            # during the imports (PyRun_*) leaves the interpreter's "unhandled Ctrl-C" flag set
            # though the exception was handled, and the normal exit would then re-raise SIGINT
            # (exit status -2 instead of 130, about half the runs interrupted at 0.8 s).
            sys.stdout.flush()
            sys.stderr.flush()
            os._exit(code)
        return code

    main.__doc__ = f"Entry point of ``{prog}``: its command, with interrupts handled first."
    return main


def lazy_names(package, sources, subpackages=()):
    """``(__getattr__, __dir__)`` of a package that imports its public names on first use (PEP 562).

    ``sources``: ``{name: relative module}`` (``{"calibrate": ".pipeline.calibration"}``);
    ``subpackages``: names reachable as attributes (``halfspace_calib.pipeline``), imported on
    first use too.
    """
    namespace = importlib.import_module(package).__dict__

    def __getattr__(name):
        if name in sources:
            value = getattr(importlib.import_module(sources[name], package), name)
            namespace[name] = value
            return value
        if name in subpackages:
            return importlib.import_module(f".{name}", package)
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    def __dir__():
        return sorted(set(namespace) | set(sources) | set(subpackages))

    return __getattr__, __dir__

"""``fe-demo`` (and ``python -m fe_demo``): the entry point, light enough to handle Ctrl-C at once.

The command's modules load NumPy, SciPy, matplotlib and numba (seconds on a cold start); they are
imported here inside :func:`sbmf_cli.interruptible`, so that Ctrl-C at any moment after the
interpreter has started ends the command with one line and exit 130, and ``--version`` answers
without them.
"""

import sys

from sbmf_cli import light_entry


def _command():
    """The command's ``main`` (imports the command: NumPy, SciPy, numba)."""
    from .cli import main as command

    return command


main = light_entry("fe-demo", "the FE run", _command)

if __name__ == "__main__":
    sys.exit(main())

"""``fe-demo`` (and ``python -m fe_demo``): the entry point, light enough to handle Ctrl-C at once.

The command's modules load NumPy, SciPy, matplotlib and numba (seconds on a cold start); they are
imported here inside :func:`sbmf_cli.interruptible`, so that Ctrl-C at any moment after the
interpreter has started ends the command with one line and exit 130, and ``--version`` answers
without them.
"""

import sys

from sbmf_cli import interruptible, print_version


@interruptible("fe-demo", "the FE run")
def main(argv=None):
    """Entry point of ``fe-demo``: :func:`fe_demo.cli.main` once interrupts are handled."""
    if print_version("fe-demo", argv):
        return 0
    from .cli import main as command

    return command(argv)


if __name__ == "__main__":
    sys.exit(main())

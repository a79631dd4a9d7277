"""``frictionlaw-export`` and ``python -m frictionlaw.export``: ``cli.main`` behind ``light_entry``.

``sbmf_cli.light_entry`` answers ``--version`` and handles Ctrl-C before the command's module
(and NumPy with it) is imported.
"""

import sys

from sbmf_cli import light_entry


def _command():
    from .cli import main

    return main


main = light_entry("frictionlaw-export", "the export", _command)

if __name__ == "__main__":
    sys.exit(main())

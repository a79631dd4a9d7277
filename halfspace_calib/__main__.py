"""``halfspace-calib`` and ``python -m halfspace_calib``: :func:`halfspace_calib.cli.main` behind ``sbmf_cli.light_entry``."""

import sys

from sbmf_cli import light_entry


def _command():
    from .cli import main

    return main


main = light_entry("halfspace-calib", "the calibration", _command)

if __name__ == "__main__":
    sys.exit(main())

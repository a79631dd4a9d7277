"""``python -m halfspace_calib``: the calibration command line (same as ``halfspace-calib``)."""

import sys

from .cli import main

if __name__ == "__main__":
    sys.exit(main())

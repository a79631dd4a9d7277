"""``python -m fe_demo``: same as the ``fe-demo`` console script."""

import sys

from .cli import main

if __name__ == "__main__":
    sys.exit(main())

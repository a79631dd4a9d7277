"""``fe-demo`` and ``python -m fe_demo``: :func:`fe_demo.cli.main` behind ``sbmf_cli.light_entry``."""

import sys

from sbmf_cli import light_entry


def _command():
    from .cli import main

    return main


main = light_entry("fe-demo", "the FE run", _command)

if __name__ == "__main__":
    sys.exit(main())

"""Where the tests find the real instrument files (tests/data/README.md).

Three ship in ``tests/data/``; the rest of the public set is read from ``../shared/surfaces/``,
where the project's CI puts it beside the project. A test that needs a file that is in neither
place skips, saying so; an instrument format also needs the optional SurfaceTopography reader.
"""

from pathlib import Path

import pytest

from halfspace_calib.topography._formats import layout_for

DATA = Path(__file__).resolve().parent / "data"
SHARED = Path(__file__).resolve().parents[1].parent / "shared" / "surfaces"


def real_file(name):
    """Path of the real file ``name`` (skips the test where it is not available)."""
    p = DATA / name if (DATA / name).is_file() else SHARED / name
    if not p.is_file():
        pytest.skip(
            f"{name} is not shipped in tests/data (size budget) and {SHARED} is not there "
            "(the project's CI puts the full set beside the project)"
        )
    if layout_for(p) == "instrument":
        pytest.importorskip("SurfaceTopography")
    return p

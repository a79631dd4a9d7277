"""Where the tests find the real instrument files (tests/data/README.md).

Three ship in ``tests/data/``; the rest of the public set is read from ``../shared/surfaces/``,
where the project's CI puts it beside the project. A test that needs a file that is in neither
place skips, saying so; an instrument format also needs the optional SurfaceTopography reader.

A test that reads a file of ``../shared/surfaces/`` carries the mark ``shared_surfaces``
(:func:`needs_shared`, :func:`file_params`), and :func:`real_file` fails a test that reads one
without it: the README's count of the tests that skip without the folder is the count of the
mark (``tests/test_readme.py``).
"""

from pathlib import Path

import pytest

from halfspace_calib.topography._formats import layout_for

DATA = Path(__file__).resolve().parent / "data"
SHARED = Path(__file__).resolve().parents[1].parent / "shared" / "surfaces"
#: the mark of a test that reads a file of ../shared/surfaces/ (skips without the folder)
needs_shared = pytest.mark.shared_surfaces
#: the test being run (set by tests/conftest.py), whose marks real_file checks
CURRENT = None


def shipped(name):
    """Whether the real file ``name`` ships in ``tests/data/``."""
    return (DATA / name).is_file()


def file_params(names):
    """``pytest.param`` per file name, marked :data:`needs_shared` where it does not ship."""
    return [pytest.param(n, marks=() if shipped(n) else needs_shared, id=n) for n in names]


def real_file(name):
    """Path of the real file ``name`` (skips the test where it is not available)."""
    if not shipped(name) and CURRENT is not None:
        if CURRENT.get_closest_marker("shared_surfaces") is None:
            pytest.fail(
                f"{CURRENT.nodeid} reads {name} of {SHARED} but is not marked shared_surfaces "
                "(realfiles.needs_shared): the README counts the tests that skip without it"
            )
    p = DATA / name if shipped(name) else SHARED / name
    if not p.is_file():
        pytest.skip(
            f"{name} is not shipped in tests/data (size budget) and {SHARED} is not there "
            "(the project's CI puts the full set beside the project)"
        )
    if layout_for(p) == "instrument":
        pytest.importorskip("SurfaceTopography")
    return p

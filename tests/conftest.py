"""Test-session hooks: the test being run, for ``realfiles.real_file``'s check of its marks."""

import pytest
import realfiles


@pytest.fixture(autouse=True)
def _current_test(request):
    realfiles.CURRENT = request.node
    yield
    realfiles.CURRENT = None

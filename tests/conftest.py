import os

import pytest


def pytest_collection_modifyitems(config, items):
    if os.environ.get("SBMF_XSLOW") == "1":
        return
    skip = pytest.mark.skip(reason="xslow: set SBMF_XSLOW=1 to run")
    for item in items:
        if "xslow" in item.keywords:
            item.add_marker(skip)

"""Test-session hooks: the test being run, for ``realfiles.real_file``'s check of its marks;
and no test may leave the process's SIGINT or SIGTERM handler changed (the commands install
theirs for a run and must put back what was there)."""

import signal

import pytest
import realfiles


@pytest.fixture(autouse=True)
def _current_test(request):
    realfiles.CURRENT = request.node
    yield
    realfiles.CURRENT = None


@pytest.fixture(autouse=True)
def _signal_handlers_restored():
    before = {sig: signal.getsignal(sig) for sig in (signal.SIGINT, signal.SIGTERM)}
    yield
    after = {sig: signal.getsignal(sig) for sig in before}
    for sig, handler in before.items():
        if after[sig] is not handler:
            signal.signal(sig, handler)  # for the tests after this one
    changed = [signal.Signals(s).name for s in before if after[s] is not before[s]]
    assert not changed, f"the test left the handler of {', '.join(changed)} changed"

"""Settings for the whole test session."""

import signal

import pytest


@pytest.fixture(autouse=True, scope="session")
def _sigint_as_from_a_terminal():
    """The tests send SIGINT to child processes as a terminal's Ctrl-C would. A test run
    started as a background job of a non-interactive shell (``bash .ci/run &``) inherits
    SIGINT ignored, every child would inherit that too, and bkwaves rightly leaves an
    ignored SIGINT ignored (python/bkwaves/_signals.py), so those tests would measure the
    launcher, not bkwaves. Python's own handler here makes children start with SIGINT at
    its default, as from a terminal."""
    old = signal.getsignal(signal.SIGINT)
    if old == signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    if old == signal.SIG_IGN:
        signal.signal(signal.SIGINT, old)

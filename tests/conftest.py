"""Shared fixtures and paths for the test suite."""

import signal
from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings

# The Ctrl-C tests start `hairbed` and send it SIGINT, as a user's terminal would. A launcher
# that ignores SIGINT (a shell's background job, a pytest-xdist worker) passes SIG_IGN on to
# every child, whose Python then never raises KeyboardInterrupt. A Python-level handler is
# reset to the default at exec, so restoring it here gives the children a terminal's SIGINT.
if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    try:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    except ValueError:  # not the main thread: nothing to restore from here
        pass

TESTS = Path(__file__).resolve().parent
DATA = TESTS / "data"

#: The fuzzer's fixed budget (tests/test_fuzz.py): examples per fuzzed argument, drawn in the
#: same order on every run (derandomized, no example database), so that `make test` does the
#: same work every time.
FUZZ_EXAMPLES = 8
settings.register_profile(
    "fuzz",
    max_examples=FUZZ_EXAMPLES,
    derandomize=True,
    database=None,
    deadline=None,
    print_blob=False,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)


@pytest.fixture(scope="session")
def data_dir() -> Path:
    return DATA

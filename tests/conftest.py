"""Shared fixtures and paths for the test suite."""

from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings

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

"""Shared fixtures and paths for the test suite."""

from pathlib import Path

import pytest

TESTS = Path(__file__).resolve().parent
DATA = TESTS / "data"
SHARED_REFERENCE = TESTS.parent.parent / "shared" / "reference" / "reference_cases.json"


@pytest.fixture(scope="session")
def data_dir() -> Path:
    return DATA

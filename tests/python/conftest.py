"""The module under test is the one the build made: PYTHONPATH=BUILD/python (ctest sets it)."""
import os

import pytest


@pytest.fixture
def cli():
    """The hsr command of the same build, for outputs that must match the CLI's byte for byte."""
    path = os.environ.get("HSR_CLI")
    if not path:
        pytest.fail("HSR_CLI is not set: run through ctest, which sets it")
    return path

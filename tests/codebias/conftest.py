"""Fixtures of the code-bias map tests."""

import pytest
from _synthetic import synthetic_passes


@pytest.fixture(scope="module")
def passes():
    return synthetic_passes()

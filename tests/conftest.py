"""Shared fixtures: the location of the real data in ../shared (tests skip without it)."""

from __future__ import annotations

from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
SHARED = Path(__file__).resolve().parents[2] / "shared"


@pytest.fixture(scope="session")
def shared() -> Path:
    """Path of ../shared; skips the test when the real data are not beside the checkout."""
    if not (SHARED / "data" / "MANIFEST.md").exists():
        pytest.skip("../shared (real data) is not available")
    return SHARED


@pytest.fixture(scope="session")
def shared_data(shared: Path) -> Path:
    """Path of ../shared/data."""
    return shared / "data"

"""Shared fixtures: the location of the real data in ../shared.

Without the real data the tests that need it are skipped, and the summary at the end says how
many and why; under CI (environment ``CI=true``) they fail instead, so that a CI job without
the data cannot pass by skipping them. ``LEOPOD_SHARED`` overrides the location (default: the
directory ``shared`` beside the checkout).
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("LEOPOD_SHARED") or Path(__file__).resolve().parents[2] / "shared")
_MISSING = f"real data not found: {SHARED / 'data' / 'MANIFEST.md'} does not exist"


def _under_ci() -> bool:
    return os.environ.get("CI", "").strip().lower() in ("true", "1", "yes")


@pytest.fixture(scope="session")
def shared() -> Path:
    """Path of ../shared; skips the test without the real data (fails it under CI=true)."""
    if not (SHARED / "data" / "MANIFEST.md").exists():
        if _under_ci():
            pytest.fail(f"{_MISSING} (CI=true: tests that need ../shared must not be skipped; "
                        "set LEOPOD_SHARED to its location)", pytrace=False)
        pytest.skip(_MISSING)
    return SHARED


@pytest.fixture(scope="session")
def shared_data(shared: Path) -> Path:
    """Path of ../shared/data."""
    return shared / "data"


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    """Say how many tests were skipped for lack of the real data."""
    skipped = [r for r in terminalreporter.stats.get("skipped", [])
               if isinstance(r.longrepr, tuple) and _MISSING in str(r.longrepr[-1])]
    if skipped:
        terminalreporter.write_sep("=", "real data missing", yellow=True)
        terminalreporter.write_line(
            f"{len(skipped)} tests skipped: {_MISSING}. Put the data set beside the checkout "
            "as ../shared or set LEOPOD_SHARED to its location to run them.")

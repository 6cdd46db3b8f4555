"""Helpers shared by the reader tests: broken files and the checks of FormatError."""

from __future__ import annotations

from pathlib import Path


def write_lines(tmp_path: Path, lines: list[str], name: str) -> Path:
    """Write ``lines`` (newline-terminated) to ``tmp_path / name`` and return the path."""
    path = tmp_path / name
    path.write_text("\n".join(lines) + "\n")
    return path


def assert_format_error(excinfo, path: Path, line: int | None, field: str) -> None:
    """The FormatError names the file, the 1-based line and the field."""
    err = excinfo.value
    assert path.name in str(err)
    assert err.line == line
    assert err.field == field

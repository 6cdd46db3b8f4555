"""Shared helpers for the text-format readers: opening compressed files and precise errors.

Every reader in :mod:`leopod.io` reads its file through :func:`read_lines` and reports bad
input with :class:`FormatError`, so a user always learns *which file, which line and which
field* is wrong instead of seeing a traceback from deep inside numpy.

Compression is recognised from the file's first bytes, not its name: gzip (``.gz``), Unix
compress (``.Z``, through ``unlzw3``) and Compact RINEX / Hatanaka (through ``hatanaka``),
in any combination (e.g. ``.crx.gz`` or ``.10D.Z``).
"""

from __future__ import annotations

import gzip
import math
from pathlib import Path

__all__ = ["FormatError", "read_lines", "parse_float", "parse_int", "fixed_float"]

_GZIP_MAGIC = b"\x1f\x8b"
_COMPRESS_MAGIC = b"\x1f\x9d"
_CRX_MARK = b"COMPACT RINEX FORMAT"


class FormatError(ValueError):
    """A file does not follow its format.

    Parameters
    ----------
    path : str or Path
        The file that is wrong.
    line : int or None
        1-based line number in the (decompressed) text, or None if the problem is not
        tied to one line (e.g. a missing header record).
    field : str
        Name of the field or record that is wrong (e.g. ``"P1"``, ``"END OF HEADER"``).
    message : str
        What is wrong, in words a user can act on.
    """

    def __init__(self, path: str | Path, line: int | None, field: str, message: str):
        self.path = str(path)
        self.line = line
        self.field = field
        self.message = message
        where = f"{self.path}:{line}" if line is not None else self.path
        super().__init__(f"{where}: field '{field}': {message}")


def _decompress(raw: bytes, path: Path) -> bytes:
    """Undo gzip / compress / Hatanaka layers until plain text remains."""
    for _ in range(4):  # at most a few nested layers (e.g. .crx.Z)
        if raw[:2] == _GZIP_MAGIC:
            try:
                raw = gzip.decompress(raw)
            except (OSError, EOFError) as err:
                raise FormatError(path, None, "gzip", f"corrupt or truncated gzip stream ({err})")
        elif raw[:2] == _COMPRESS_MAGIC:
            import unlzw3

            try:
                raw = unlzw3.unlzw(raw)
            except Exception as err:  # unlzw3 raises bare exceptions on corrupt input
                raise FormatError(path, None, "compress", f"corrupt .Z stream ({err})")
        elif _CRX_MARK in raw[:200]:
            import hatanaka

            try:
                raw = hatanaka.decompress(raw)
            except Exception as err:  # hatanaka wraps the C decoder's messages
                raise FormatError(path, None, "Compact RINEX", f"cannot decompress ({err})")
        else:
            return raw
    return raw


def read_lines(path: str | Path) -> list[str]:
    """Read a (possibly compressed) text file into a list of lines without line ends.

    Parameters
    ----------
    path : str or Path
        File to read; gzip, compress (.Z) and Hatanaka layers are removed automatically.

    Returns
    -------
    list of str
        The lines, ``\\r`` and ``\\n`` stripped.

    Raises
    ------
    FormatError
        If the file is empty, a compression layer is corrupt, or the text is not ASCII/Latin-1.
    FileNotFoundError
        If the file does not exist.
    """
    path = Path(path)
    raw = path.read_bytes()
    if not raw:
        raise FormatError(path, None, "file", "the file is empty")
    text = _decompress(raw, path).decode("latin-1")
    if "\x00" in text[:4096]:
        raise FormatError(path, None, "file", "binary content where text was expected")
    return text.splitlines()


def parse_float(text: str, path: str | Path, line: int, field: str, *, allow_blank=False):
    """Parse one numeric field, raising :class:`FormatError` with its location on failure.

    Fortran ``D`` exponents are accepted. NaN and infinities are rejected: no format we
    read uses them, so they always mean a corrupt file.

    Parameters
    ----------
    text : str
        The characters of the field.
    path, line, field
        Location used in the error message (1-based line).
    allow_blank : bool
        If True a blank field returns ``math.nan`` instead of raising.

    Returns
    -------
    float
    """
    s = text.strip()
    if not s:
        if allow_blank:
            return math.nan
        raise FormatError(path, line, field, "value is missing")
    try:
        value = float(s.replace("D", "E").replace("d", "e"))
    except ValueError:
        raise FormatError(path, line, field, f"'{s}' is not a number") from None
    if not math.isfinite(value):
        raise FormatError(path, line, field, f"'{s}' is not a finite number")
    return value


def parse_int(text: str, path: str | Path, line: int, field: str) -> int:
    """Parse one integer field, raising :class:`FormatError` with its location on failure."""
    s = text.strip()
    if not s:
        raise FormatError(path, line, field, "value is missing")
    try:
        return int(s)
    except ValueError:
        raise FormatError(path, line, field, f"'{s}' is not an integer") from None


def fixed_float(line_text: str, start: int, stop: int, path, line: int, field: str,
                *, allow_blank=False) -> float:
    """Parse the fixed-width field ``line_text[start:stop]`` (0-based, stop exclusive)."""
    return parse_float(line_text[start:stop], path, line, field, allow_blank=allow_blank)

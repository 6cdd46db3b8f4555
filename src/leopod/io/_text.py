"""Shared helpers for the text-format readers: opening compressed files and precise errors.

Every reader in :mod:`leopod.io` reads its file through :func:`read_lines` and reports bad
input with :class:`FormatError`, so a user always learns *which file, which line and which
field* is wrong instead of seeing a traceback from deep inside numpy.

Compression is recognised from the file's first bytes, not its name: gzip (``.gz``), Unix
compress (``.Z``, through ``unlzw3``) and Compact RINEX / Hatanaka (through ``hatanaka``),
in any combination (e.g. ``.crx.gz`` or ``.10D.Z``).
"""

from __future__ import annotations

import datetime as _dt
import gzip
import os
import zlib
from pathlib import Path

import numpy as np

from leopod.io import _fields

__all__ = [
    "FormatError",
    "Lines",
    "calendar_epoch_ns",
    "creation_time",
    "fixed_float",
    "parse_float",
    "parse_floats",
    "parse_int",
    "read_lines",
    "time_system_to_gps",
    "write_text",
]

#: Time-system identifiers of the SP3-c/d ``%c`` line and the RINEX clock 3.04 ``TIME SYSTEM
#: ID`` record (the GNSS times of RINEX 3.04 Table A2 plus TAI and UTC).
PRODUCT_TIME_SYSTEMS = ("GPS", "GLO", "GAL", "QZS", "BDT", "IRN", "TAI", "UTC")

_GZIP_MAGIC = b"\x1f\x8b"
_COMPRESS_MAGIC = b"\x1f\x9d"
_CRX_MARK = b"COMPACT RINEX FORMAT"
_UNIX0 = _dt.datetime(1970, 1, 1)


def creation_time(created: _dt.datetime | None = None) -> _dt.datetime:
    """The creation time written into a file header (UTC, naive).

    ``created`` if given; else ``SOURCE_DATE_EPOCH`` (seconds since 1970, the reproducible-
    builds convention) if that environment variable is set; else the wall clock. Writers of
    products whose content is fully determined by their inputs pass a time derived from the
    data, so that identical inputs give bit-identical files.
    """
    if created is not None:
        return created if created.tzinfo is None else \
            created.astimezone(_dt.UTC).replace(tzinfo=None)
    epoch = os.environ.get("SOURCE_DATE_EPOCH")
    if epoch:
        return _UNIX0 + _dt.timedelta(seconds=int(epoch))
    return _dt.datetime.now(_dt.UTC).replace(tzinfo=None)


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
            except (OSError, EOFError, zlib.error) as err:
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


class Lines(list):
    """The lines of a text file (a ``list`` of str) and whether the file ended with a line
    end (``final_newline``), which tells a complete last record from one cut short."""

    final_newline: bool = True


def read_lines(path: str | Path) -> Lines:
    """Read a (possibly compressed) text file into a list of lines without line ends.

    Parameters
    ----------
    path : str or Path
        File to read; gzip, compress (.Z) and Hatanaka layers are removed automatically.

    Returns
    -------
    Lines
        The lines (ended by LF, CR LF or CR), line ends stripped; ``.final_newline`` tells
        whether the text ended with a line end.

    Raises
    ------
    FormatError
        If the file or its decompressed text is empty or blank, a compression layer is
        corrupt, or the text is binary.
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
    if not text.strip():
        raise FormatError(path, None, "file", "the file holds no text (empty payload)")
    if "\r" in text:
        text = text.replace("\r\n", "\n").replace("\r", "\n")
    # only CR/LF end a line (str.splitlines also splits at form feeds, \x1c-\x1e and NEL
    # \x85, which would shift every later line number away from what an editor shows)
    lines = Lines(text.split("\n"))
    lines.final_newline = text.endswith("\n")
    if lines.final_newline:
        lines.pop()
    return lines


def parse_float(text: str, path: str | Path, line: int, field: str, *, allow_blank=False,
                kind: str | None = None, lo: float | None = None, hi: float | None = None):
    """Parse one numeric field under the reader contract (:func:`leopod.io._fields.number`).

    Fortran ``D`` exponents are accepted; underscores, NaN and infinities are not (no format
    we read writes them). ``kind``/``lo``/``hi`` give the field's physical range.

    Parameters
    ----------
    text : str
        The characters of the field.
    path, line, field
        Location used in the error message (1-based line).
    allow_blank : bool
        If True a blank field returns ``math.nan`` instead of raising.
    kind, lo, hi
        Range of the field (:data:`leopod.io._fields.RANGES` key, explicit bounds).

    Returns
    -------
    float
    """
    return _fields.number(text, path, line, field, kind=kind, lo=lo, hi=hi,
                          allow_blank=allow_blank)


def parse_int(text: str, path: str | Path, line: int, field: str, *, lo: int | None = None,
              hi: int | None = None) -> int:
    """Parse one integer field (:func:`leopod.io._fields.integer`), optionally in [lo, hi]."""
    return _fields.integer(text, path, line, field, lo=lo, hi=hi)


def fixed_float(line_text: str, start: int, stop: int, path, line: int, field: str,
                *, allow_blank=False, kind: str | None = None) -> float:
    """Parse the fixed-width field ``line_text[start:stop]`` (0-based, stop exclusive)."""
    return parse_float(line_text[start:stop], path, line, field, allow_blank=allow_blank,
                       kind=kind)


def parse_floats(texts, line_nos, field, path, *, allow_blank: bool = False,
                 kind: str | None = None, lo: float | None = None,
                 hi: float | None = None) -> np.ndarray:
    """Convert many numeric field texts to float64, fast, with exact error locations.

    :func:`leopod.io._fields.numbers`: numpy converts the whole list at once; only when that
    fails (bad syntax, a value out of range) are the texts parsed one by one, raising at the
    first bad one. Fortran ``D`` exponents are accepted.

    Parameters
    ----------
    texts : sequence of str, shape (N,)
        Field texts.
    line_nos : sequence of int, shape (N,)
        1-based line number of each text.
    field : str, sequence of str or callable
        Field name for error messages: one name, one per text, or ``field(i)``.
    path : str or Path
        File, for error messages.
    allow_blank : bool
        Blank fields become NaN instead of an error.
    kind, lo, hi
        Range of the fields.

    Returns
    -------
    numpy.ndarray, shape (N,)
    """
    return _fields.numbers(texts, line_nos, field, path, kind=kind, lo=lo, hi=hi,
                           allow_blank=allow_blank)


def calendar_epoch_ns(ymdhm: tuple[int, int, int, int, int], seconds: float, path,
                      line: int) -> int:
    """Nanoseconds since 1970-01-01 of a calendar epoch, validating every part.

    Raises
    ------
    FormatError
        Naming ``epoch`` for an impossible date/time or a year outside 1900-2199
        (:data:`leopod.io._fields.YEARS`, well inside datetime64[ns]), or ``second``
        outside [0, 60).
    """
    return _fields.epoch_ns(*ymdhm, seconds, path, line)


def write_text(path: str | Path, text: str) -> Path:
    """Write an ASCII text file atomically (no partial file on failure); ``.gz`` is compressed.

    Parameters
    ----------
    path : str or Path
        Output file; a name ending in ``.gz`` is gzip-compressed.
    text : str
        File content (ASCII).

    Returns
    -------
    Path
    """
    from leopod.io.netcdf import atomic_path

    path = Path(path)
    data = text.encode("ascii")
    with atomic_path(path) as tmp:
        tmp.write_bytes(gzip.compress(data, compresslevel=6, mtime=0)
                        if path.suffix == ".gz" else data)
    return path


def time_system_to_gps(times: np.ndarray, system: str, path, line: int | None,
                       field: str) -> np.ndarray:
    """Epoch labels of a file in GPS time, or a :class:`FormatError` naming where the
    file's time system was given.

    Parameters
    ----------
    times : ndarray of datetime64[ns], shape (n,)
        Labels in ``system``.
    system : str
        The file's time system (``GPS``, ``GAL``, ``BDT``, ``TAI``, ``UTC``;
        :func:`leopod.time.scales.to_gps_time`).
    path, line, field
        Where the time system was read (``line`` None when the format's default applied).

    Returns
    -------
    ndarray of datetime64[ns], shape (n,)
        GPS-time labels (exact integer-nanosecond offsets; leap seconds for UTC).
    """
    from leopod.time.scales import to_gps_time

    try:
        return to_gps_time(times, system)
    except ValueError as err:
        raise FormatError(path, line, field, f"{err}; cannot convert the epochs to GPS "
                          "time") from None

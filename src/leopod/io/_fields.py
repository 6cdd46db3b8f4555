"""The reader contract in one place: numeric and date fields, physical ranges, record checks.

Every reader of :mod:`leopod.io` converts the text of a field through this module, so that one
set of rules holds for all formats (issue 24):

* **Number syntax.** ``[+-]digits[.digits][E|D[+-]digits]`` in ASCII, blanks around it
  allowed. Python's ``float``/``int`` and numpy also accept ``1_000``, ``nan``, ``inf``,
  ``0x``-free hex floats in some paths and non-ASCII digits: none of the formats we read
  writes them, so they mean a corrupt file. A format that has a marker for "no value" (a
  blank field, SP3's ``999999.999999``, CRD's ``na``) handles it *before* calling the parser.
* **Finite and in range.** Every value must lie in the physical range of its field
  (:data:`RANGES`, or explicit ``lo``/``hi``); ``1e308`` is a number but not a position, and
  would become infinite after a unit conversion.
* **Dates** are proleptic-Gregorian calendar dates with years 1900-2199 (:data:`YEARS`), well
  inside datetime64[ns] (1677-09-21 to 2262-04-11), so that no epoch overflows or wraps; a
  format's own "open" marker (e.g. SINEX ``00:000:00000``) is handled by its reader.
* **Counts and sizes** from a header are integers in a stated range, and arrays are sized by
  what the file holds, never by a header count alone.
* **Errors** are :class:`leopod.io._text.FormatError` naming file, 1-based line and field.

The record-level rules (damaged compression, an empty payload, a final line cut short, counts
checked against headers, loops that always advance) are enforced in
:func:`leopod.io._text.read_lines` and in each reader; :func:`require_line_end` and
:func:`check_count` are the shared helpers.
"""

from __future__ import annotations

import datetime as _dt
import math
import re
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

__all__ = [
    "RANGES",
    "YEARS",
    "check_count",
    "check_range",
    "day_of_year_ns",
    "epoch_ns",
    "is_number",
    "number",
    "numbers",
    "integer",
    "integers",
    "iso_epoch_ns",
    "is_digits",
    "is_letters",
    "require_line_end",
]

#: The syntax of a number in every format we read (Fortran ``D`` exponents included).
_NUMBER = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[EeDd][+-]?[0-9]+)?")
_INTEGER = re.compile(r"[+-]?[0-9]+")  # ASCII digits: Python's \d also matches other scripts
#: Bytes a number field may hold (NUL: the padding of numpy's fixed-width strings).
_ALLOWED_BYTES = np.zeros(256, dtype=bool)
_ALLOWED_BYTES[list(b"0123456789+-.EeDd \t\x00")] = True
_EXPONENT_D = np.zeros(256, dtype=bool)
_EXPONENT_D[list(b"Dd")] = True

#: Years a date field may hold (no GNSS, SLR, gravity or space-weather record predates 1900;
#: the upper bound keeps every epoch far inside datetime64[ns], whose last year is 2262).
YEARS = (1900, 2199)
_UNIX0 = _dt.datetime(1970, 1, 1)

#: Physical ranges (lo, hi) of the kinds of field the readers convert, in the unit of the file
#: field as written (the reader converts to SI afterwards). Wide enough for every real product
#: (lunar laser ranging, GEO satellites, degree-10800 gravity models), narrow enough that an
#: edited exponent cannot pass as a value. Sources: the formats' own field widths and the
#: physics (an Earth-orbiting position is below 1e6 km; a clock offset of a GNSS satellite or
#: station below 1 s, with margin for example files; an instrumental bias below 1 ms).
RANGES: dict[str, tuple[float, float]] = {
    "position_km": (-1.0e6, 1.0e6),
    "position_m": (-1.0e9, 1.0e9),
    "velocity_dm_s": (-1.0e6, 1.0e6),
    "velocity_m_s": (-1.0e5, 1.0e5),
    "clock_s": (-1.0e3, 1.0e3),  # real clocks stay below 1 s; example files write 1.23 s
    "clock_us": (-1.0e6, 1.0e6),
    "bias_ns": (-1.0e6, 1.0e6),
    "bias_cycles": (-1.0e6, 1.0e6),
    "sigma_s": (0.0, 1.0),
    "sigma_ns": (0.0, 1.0e6),
    "antenna_mm": (-1.0e5, 1.0e5),
    "angle_deg": (-360.0, 360.0),
    "phase_deg": (-360.0, 360.0),
    "loading_amplitude_m": (0.0, 1.0),
    "stokes": (-10.0, 10.0),
    "stokes_sigma": (0.0, 10.0),
    "tide_stokes_1e-11": (-1.0e6, 1.0e6),
    "time_of_flight_s": (0.0, 10.0),
    "range_m": (-1.0e9, 1.0e9),
    "pressure_hpa": (0.0, 2000.0),
    "temperature_k": (0.0, 400.0),
    "humidity_pct": (0.0, 100.0),
    "percent": (0.0, 100.0),
    "seconds_of_day": (0.0, 86_401.0),
    "interval_s": (0.0, 1.0e6),  # 11.6 days: weekly products fit
    "statistic": (-1.0e6, 1.0e6),
    "index": (-1.0e6, 1.0e6),
    "acceleration_m_s2": (-1.0e3, 1.0e3),
    "velocity_change_m_s": (-1.0e4, 1.0e4),
    "gm_m3_s2": (1.0e5, 1.0e21),
    "radius_m": (1.0e3, 1.0e9),
}


def _error(path, line, field, message):
    from leopod.io._text import FormatError

    return FormatError(path, line, field, message)


def _limits(kind: str | None, lo: float | None, hi: float | None) -> tuple[float, float]:
    if kind is not None:
        klo, khi = RANGES[kind]
        lo = klo if lo is None else lo
        hi = khi if hi is None else hi
    return (-math.inf if lo is None else lo, math.inf if hi is None else hi)


def is_digits(text: str) -> bool:
    """True if ``text`` is one or more ASCII digits (``str.isdigit`` also accepts "²")."""
    return text.isascii() and text.isdigit()


def is_letters(text: str) -> bool:
    """True if ``text`` is one or more ASCII letters (``str.isalpha`` also accepts "é")."""
    return text.isascii() and text.isalpha()


def is_number(text: str) -> bool:
    """True if ``text`` (blanks around it allowed) is a number of the contract's syntax."""
    return _NUMBER.fullmatch(text.strip()) is not None


def number(text: str, path: str | Path, line: int | None, field: str, *,
           kind: str | None = None, lo: float | None = None, hi: float | None = None,
           allow_blank: bool = False) -> float:
    """One numeric field, checked against the contract.

    Parameters
    ----------
    text : str
        The characters of the field.
    path, line, field
        Where the field is (file, 1-based line, field name) for the error message.
    kind : str, optional
        Key of :data:`RANGES` giving the physical range of the field.
    lo, hi : float, optional
        Explicit bounds (inclusive), overriding those of ``kind``.
    allow_blank : bool
        A blank field gives NaN instead of an error.

    Returns
    -------
    float

    Raises
    ------
    FormatError
        The field is blank (unless allowed), not a number of the contract's syntax, or
        outside its range.
    """
    s = text.strip()
    if not s:
        if allow_blank:
            return math.nan
        raise _error(path, line, field, "value is missing")
    if _NUMBER.fullmatch(s) is None:
        if s.lstrip("+-").lower() in ("nan", "inf", "infinity"):
            raise _error(path, line, field, f"'{s}' is not a finite number")
        raise _error(path, line, field, f"'{s}' is not a number")
    value = float(s.replace("D", "E").replace("d", "e"))
    low, high = _limits(kind, lo, hi)
    if math.isinf(value):
        raise _error(path, line, field, f"'{s}' is not a finite number (overflow)")
    if not low <= value <= high:
        raise _error(path, line, field, f"{s} outside the range [{low:g}, {high:g}] of the "
                     "field")
    return value


def integer(text: str, path: str | Path, line: int | None, field: str, *,
            lo: int | None = None, hi: int | None = None) -> int:
    """One integer field (ASCII digits with an optional sign), optionally within [lo, hi].

    Raises
    ------
    FormatError
        Blank, not an integer, or outside [lo, hi].
    """
    s = text.strip()
    if not s:
        raise _error(path, line, field, "value is missing")
    if _INTEGER.fullmatch(s) is None:
        raise _error(path, line, field, f"'{s}' is not an integer")
    value = int(s)
    if (lo is not None and value < lo) or (hi is not None and value > hi):
        raise _error(path, line, field, f"{value} outside the range [{lo}, {hi}] of the field")
    return value


def numbers(texts: Sequence[str], line_nos: Sequence[int], field: str | Sequence[str] |
            Callable[[int], str], path: str | Path, *, kind: str | None = None,
            lo: float | None = None, hi: float | None = None,
            allow_blank: bool = False) -> np.ndarray:
    """Many numeric fields at once (vectorised), with the rules and errors of :func:`number`.

    Parameters
    ----------
    texts : sequence of str, shape (N,)
        Field texts.
    line_nos : sequence of int, shape (N,)
        1-based line of each text.
    field : str, sequence of str or callable
        Name for error messages: one name, one per text, or ``field(i)``.
    path : str or Path
        File, for error messages.
    kind, lo, hi, allow_blank
        As :func:`number`.

    Returns
    -------
    numpy.ndarray of float64, shape (N,)
    """
    if len(texts) == 0:
        return np.empty(0)
    low, high = _limits(kind, lo, hi)
    values = None
    try:  # the characters of every text at once, as bytes (non-ASCII text: slow path)
        raw = np.asarray(texts, dtype=str).astype("S")
    except UnicodeEncodeError:
        raw = None
    if raw is not None and _ALLOWED_BYTES[np.frombuffer(raw.tobytes(), np.uint8)].all():
        if (_EXPONENT_D[np.frombuffer(raw.tobytes(), np.uint8)]).any():
            raw = np.char.translate(raw, bytes.maketrans(b"Dd", b"Ee"))
        try:
            values = raw.astype(np.float64)
        except ValueError:
            values = None
    if values is not None:
        with np.errstate(invalid="ignore"):
            ok = np.isfinite(values) & (values >= low) & (values <= high)
        if allow_blank:
            ok |= np.char.strip(np.asarray(texts, dtype=str)) == ""
        if ok.all():
            return values
    if callable(field):
        name = field
    elif isinstance(field, str):
        def name(i):
            return field
    else:
        name = field.__getitem__
    return np.array([number(t, path, n, name(i), lo=low, hi=high, allow_blank=allow_blank)
                     for i, (t, n) in enumerate(zip(texts, line_nos))], dtype=np.float64)


def integers(texts: Sequence[str], line_nos: Sequence[int], field: str, path: str | Path, *,
             lo: int | None = None, hi: int | None = None) -> np.ndarray:
    """Many integer fields at once (int64), with the rules and errors of :func:`integer`."""
    if len(texts) == 0:
        return np.empty(0, dtype=np.int64)
    if set("".join(texts)) <= set("0123456789+- "):
        try:
            values = np.asarray(texts, dtype=str).astype(np.int64)
        except (ValueError, OverflowError):
            values = None
        if values is not None and (lo is None or values.min() >= lo) and \
                (hi is None or values.max() <= hi):
            return values
    return np.array([integer(t, path, n, field, lo=lo, hi=hi) for t, n in zip(texts, line_nos)],
                    dtype=np.int64)


def check_range(values: np.ndarray, line_nos: Sequence[int], field: str, path: str | Path, *,
                kind: str | None = None, lo: float | None = None,
                hi: float | None = None) -> np.ndarray:
    """Raise a FormatError at the first value (NaN excepted) outside its range; return
    ``values``."""
    low, high = _limits(kind, lo, hi)
    v = np.asarray(values, dtype=float)
    with np.errstate(invalid="ignore"):
        bad = ~np.isnan(v) & ~((v >= low) & (v <= high))
    if bad.any():
        k = int(np.flatnonzero(bad.ravel())[0])
        ln = line_nos[k] if len(line_nos) == v.size else None
        raise _error(path, ln, field, f"{v.ravel()[k]:g} outside the range [{low:g}, "
                     f"{high:g}] of the field")
    return values


def epoch_ns(year: int, month: int, day: int, hour: int, minute: int, seconds: float,
             path: str | Path, line: int | None, field: str = "epoch", *,
             leap_second: bool = False) -> int:
    """Nanoseconds since 1970-01-01 of a calendar epoch, every part checked.

    Parameters
    ----------
    year, month, day, hour, minute : int
        Calendar date and time (year with four digits).
    seconds : float
        Seconds of the minute, in [0, 60) (or [0, 61) with ``leap_second``).
    path, line, field
        Location for the error message.

    Returns
    -------
    int

    Raises
    ------
    FormatError
        An impossible date or time, seconds out of range, or a year outside :data:`YEARS`.
    """
    if not YEARS[0] <= year <= YEARS[1]:
        raise _error(path, line, field, f"year {year} outside {YEARS[0]}-{YEARS[1]}, the "
                     "years leopod accepts (datetime64[ns] holds 1678-2261)")
    try:
        dt = _dt.datetime(year, month, day, hour, minute)
    except (ValueError, OverflowError) as err:
        raise _error(path, line, field, f"invalid date or time ({err})") from None
    top = 61.0 if leap_second else 60.0
    if not 0.0 <= seconds < top:
        raise _error(path, line, "second" if field == "epoch" else field,
                     f"seconds {seconds} outside [0, {top:g})")
    delta = dt - _UNIX0
    return (delta.days * 86_400 + delta.seconds) * 1_000_000_000 + round(seconds * 1e9)


_ISO = re.compile(r"([0-9]{4})-([0-9]{2})-([0-9]{2})T([0-9]{2}):([0-9]{2}):([0-9]{2})"
                  r"(?:\.([0-9]{1,9}))?")


def iso_epoch_ns(text: str, path: str | Path, line: int | None, field: str) -> int:
    """Nanoseconds since 1970 of ``YYYY-MM-DDThh:mm:ss[.fffffffff]`` (the rules of
    :func:`epoch_ns`; numpy's own parser wraps years outside datetime64[ns] silently, e.g.
    3000-01-01 to 1830-11-23, and reads "NaT")."""
    m = _ISO.fullmatch(text.strip())
    if m is None:
        raise _error(path, line, field, f"'{text.strip()}' is not an ISO 8601 epoch "
                     "YYYY-MM-DDThh:mm:ss[.fffffffff]")
    y, mo, d, h, mi, sec = (int(g) for g in m.groups()[:6])
    ns = epoch_ns(y, mo, d, h, mi, float(sec), path, line, field)
    return ns + int((m.group(7) or "").ljust(9, "0"))


def day_of_year_ns(year: int, doy: int, seconds: float, path: str | Path, line: int | None,
                   field: str) -> int:
    """Nanoseconds since 1970 of ``year``, day of year ``doy`` and ``seconds`` of the day
    (0..86400 inclusive: SINEX writes 86400 for the end of a day)."""
    if not YEARS[0] <= year <= YEARS[1]:
        raise _error(path, line, field, f"year {year} outside {YEARS[0]}-{YEARS[1]}")
    ndays = 366 if year % 4 == 0 and (year % 100 != 0 or year % 400 == 0) else 365
    if not 1 <= doy <= ndays:
        raise _error(path, line, field, f"day of year {doy} outside 1-{ndays}")
    if not 0 <= seconds <= 86_400:
        raise _error(path, line, field, f"second of day {seconds} outside 0-86400")
    delta = _dt.datetime(year, 1, 1) - _UNIX0
    return ((delta.days + doy - 1) * 86_400) * 1_000_000_000 + round(seconds * 1e9)


def check_count(announced: int, found: int, path: str | Path, line: int | None, field: str,
                what: str, *, complete: bool, log=None) -> None:
    """A header count against the records found.

    A file that ended early (``complete`` False: no trailer, last block open) is refused; a
    complete file whose count disagrees is read, with a warning in ``log`` (real products
    carry such counts, e.g. CODE's 2021 OSB files).
    """
    if announced == found:
        return
    message = f"the header announces {announced} {what}, the file holds {found}"
    if not complete:
        raise _error(path, line, field, f"{message} (file truncated?)")
    if log is not None:
        log.warning("%s:%s: %s: %s; the file is complete, all records are read", path, line,
                    field, message)


def require_line_end(lines, path: str | Path, field: str = "record") -> None:
    """Refuse a file whose last line has no line end, for formats of free-format records,
    where a cut inside the last number cannot be told from a shorter number."""
    if getattr(lines, "final_newline", True) or not lines:
        return
    last = lines[-1]
    if last.strip():
        raise _error(path, len(lines), field, "the last line has no line end: the file ends "
                     "inside its last record (cut short?)")

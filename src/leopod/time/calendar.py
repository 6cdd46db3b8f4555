"""Calendar helpers for GPS time labels: day of year, GPS week, seconds of arcs.

Epochs are ``numpy.datetime64[ns]`` values holding GPS-time readings (the time system is
recorded beside them, never mixed). Computations use float64 seconds relative to a reference
epoch close to the data (e.g. the start of the day), which keeps 1e-11 s resolution.

Time-scale conversions (UTC, TAI, TT, UT1 with leap seconds and EOP) belong to the dynamics
engine; this module only handles GPS calendar arithmetic.
"""

from __future__ import annotations

import datetime as _dt

import numpy as np

__all__ = [
    "GPS_EPOCH", "J2000_TT", "parse_date_id", "date_id", "gps_week_dow", "template_fields",
    "seconds_since", "from_seconds", "days_between",
]

#: Start of GPS time, 1980-01-06 00:00:00 GPST (IS-GPS-200, 3.3.4).
GPS_EPOCH = np.datetime64("1980-01-06T00:00:00", "ns")

#: J2000.0 = 2000-01-01 12:00:00 TT, as a TT-scale label (IERS Conventions 2010, ch. 5).
J2000_TT = np.datetime64("2000-01-01T12:00:00", "ns")


def parse_date_id(date: str) -> _dt.date:
    """Parse a day identifier ``YYYY-DDD`` (day of year) or ``YYYY-MM-DD`` into a date.

    Raises
    ------
    ValueError
        If the text is neither form or the day does not exist; the message quotes it.
    """
    try:
        if len(date) == 8 and date[4] == "-":
            year, doy = int(date[:4]), int(date[5:])
            if not 1 <= doy <= (366 if _is_leap(year) else 365):
                raise ValueError
            return _dt.date(year, 1, 1) + _dt.timedelta(days=doy - 1)
        return _dt.date.fromisoformat(date)
    except ValueError:
        raise ValueError(f"'{date}' is not a day 'YYYY-DDD' or 'YYYY-MM-DD'") from None


def _is_leap(year: int) -> bool:
    return year % 4 == 0 and (year % 100 != 0 or year % 400 == 0)


def date_id(day: _dt.date) -> str:
    """Day identifier ``YYYY-DDD`` used in leopod file names."""
    return f"{day.year:04d}-{day.timetuple().tm_yday:03d}"


def gps_week_dow(day: _dt.date) -> tuple[int, int]:
    """GPS week and day of week (0 = Sunday) of a calendar day."""
    days = (day - _dt.date(1980, 1, 6)).days
    return days // 7, days % 7


def template_fields(day: _dt.date) -> dict[str, str]:
    """Placeholders of file-name templates for one day.

    Returns
    -------
    dict
        ``yyyy`` (2007), ``yy`` (07), ``doy`` (080), ``gpsweek`` (1419), ``dow`` (3),
        ``date`` (2007-080), ``month`` (03), ``day`` (21).
    """
    week, dow = gps_week_dow(day)
    return {
        "yyyy": f"{day.year:04d}", "yy": f"{day.year % 100:02d}",
        "doy": f"{day.timetuple().tm_yday:03d}", "gpsweek": f"{week:04d}", "dow": f"{dow:d}",
        "date": date_id(day), "month": f"{day.month:02d}", "day": f"{day.day:02d}",
    }


def days_between(start: str, end: str) -> list[str]:
    """All day identifiers ``YYYY-DDD`` from start to end inclusive (ISO or YYYY-DDD input)."""
    d0, d1 = parse_date_id(start), parse_date_id(end)
    if d1 < d0:
        raise ValueError(f"end date {end} is before start date {start}")
    return [date_id(d0 + _dt.timedelta(days=k)) for k in range((d1 - d0).days + 1)]


def seconds_since(times, ref) -> np.ndarray:
    """Seconds [s] from ``ref`` to ``times`` (datetime64), as float64, exact to 1 ns."""
    delta = np.asarray(times, dtype="datetime64[ns]") - np.datetime64(ref, "ns")
    return delta.astype("int64") * 1e-9


def from_seconds(seconds, ref) -> np.ndarray:
    """Inverse of :func:`seconds_since`: datetime64[ns] epochs ``ref + seconds`` (rounded to 1 ns)."""
    ns = np.round(np.asarray(seconds, dtype=float) * 1e9).astype("int64")
    return np.datetime64(ref, "ns") + ns.astype("timedelta64[ns]")

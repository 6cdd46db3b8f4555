"""Read the CelesTrak space-weather file (``SW-All.csv``) and derive the inputs of MSIS.

Specification: T. S. Kelso, "Space Weather Data Documentation", CelesTrak
(https://celestrak.org/SpaceData/SpaceWx-format.php, CSV format). One row per UTC day (and,
at the end of the file, one row per month of long-term predictions, ``PRM``) with the fields::

    DATE,BSRN,ND,KP1..KP8,KP_SUM,AP1..AP8,AP_AVG,CP,C9,ISN,
    F10.7_OBS,F10.7_ADJ,F10.7_DATA_TYPE,F10.7_OBS_CENTER81,F10.7_OBS_LAST81,
    F10.7_ADJ_CENTER81,F10.7_ADJ_LAST81

Kp values are given multiplied by 10 and rounded (``37`` = 3.7 ≈ 4−); the 3-hourly ap and the
daily Ap are in units of 2 nT; F10.7 is in solar flux units (1 sfu = 1e-22 W m⁻² Hz⁻¹),
"OBS" at the Sun–Earth distance and "ADJ" adjusted to 1 AU; ``*_CENTER81`` is the 81-day
average centred on the day, ``*_LAST81`` the average of the last 81 days. The F10.7 data
type is ``OBS`` (observed), ``INT`` (interpolated), ``PRD`` (45-day prediction) or ``PRM``
(monthly prediction, geomagnetic fields blank).

Dataset returned by :func:`read_space_weather`
----------------------------------------------
Coordinates
    ``date`` (date,) datetime64[ns] -- start of the UTC day (of the month for PRM rows)
    ``slot_start_h`` (slot,) float [h] -- start of the 3-hour intervals: 0, 3, ..., 21 UT
Data variables (NaN where the file leaves a field blank)
    ``bartels_rotation``, ``bartels_day`` (date,) int -- Bartels solar rotation number and day
    ``kp`` (date, slot) float [1] -- 3-hourly planetary Kp (file value / 10)
    ``kp_sum`` (date,) float [1] -- sum of the 8 Kp of the day (file value / 10)
    ``ap`` (date, slot) float [2 nT] -- 3-hourly planetary equivalent amplitude ap
    ``ap_daily`` (date,) float [2 nT] -- daily Ap (mean of the 8 ap)
    ``cp``, ``c9`` (date,) float [1] -- daily planetary character figures
    ``isn`` (date,) float [1] -- international sunspot number
    ``f107_obs_sfu``, ``f107_adj_sfu`` (date,) float [sfu] -- observed / 1-AU-adjusted F10.7
    ``f107_data_type`` (date,) str -- OBS, INT, PRD or PRM
    ``f107_obs_center81_sfu``, ``f107_obs_last81_sfu``, ``f107_adj_center81_sfu``,
    ``f107_adj_last81_sfu`` (date,) float [sfu] -- 81-day averages
Attributes
    ``filename``, ``time_system`` ("UTC"), ``source``.

Errors
------
:class:`leopod.io.FormatError` (file, line, field) for a header that is not the CelesTrak CSV
header, a row with the wrong number of fields, an invalid, blank or non-increasing date (years
1900-2199), a non-numeric value or one outside +-1e6, a Kp outside 0..9, a negative ap/Ap or
F10.7, a Bartels rotation outside 0..99999 or day outside 0..27, an unknown F10.7 type, and a
file whose last line has no line end (cut inside its last row).

MSIS inputs
-----------
:func:`msis_inputs` returns, for UTC epochs, what NRLMSISE-00 / MSIS 2.x need (Picone et al.
2002, JGR 107(A12) 1468; ``pymsis.calculate(dates, lons, lats, alts, f107s, f107as, aps)``):
the observed F10.7 of the previous day, the observed 81-day centred average, and the 7-element
ap array: (0) daily Ap, (1) ap of the 3-hour interval containing the epoch, (2)–(4) ap 3, 6 and
9 hours before, (5) mean of the eight ap from 12 to 33 hours before, (6) mean of the eight ap
from 36 to 57 hours before (intervals counted from the one containing the epoch). Observed,
not adjusted, F10.7 is used, as the MSIS models expect the flux at the Earth's distance.
"""

from __future__ import annotations

import logging
import re
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.io._fields import YEARS, epoch_ns, require_line_end
from leopod.io._text import FormatError, parse_floats, read_lines

__all__ = ["F107_BURST_THRESHOLD_SFU", "msis_inputs", "read_space_weather"]

logger = logging.getLogger(__name__)

_HEADER = ("DATE,BSRN,ND,KP1,KP2,KP3,KP4,KP5,KP6,KP7,KP8,KP_SUM,AP1,AP2,AP3,AP4,AP5,AP6,AP7,"
           "AP8,AP_AVG,CP,C9,ISN,F10.7_OBS,F10.7_ADJ,F10.7_DATA_TYPE,F10.7_OBS_CENTER81,"
           "F10.7_OBS_LAST81,F10.7_ADJ_CENTER81,F10.7_ADJ_LAST81")
_FIELDS = _HEADER.split(",")
_N_FIELDS = len(_FIELDS)
_COL = {name: i for i, name in enumerate(_FIELDS)}
_TYPES = ("OBS", "INT", "PRD", "PRM")
_SLOT_S = 10_800  # length of a 3-hour ap interval [s]
_NS_PER_S = 1_000_000_000

#: Daily observed F10.7 above this value [sfu] is taken as a solar radio burst (flare
#: emission that does not heat the thermosphere) and replaced by the 81-day average in
#: :func:`msis_inputs`; the same guard and threshold as pymsis.utils (version 0.13).
F107_BURST_THRESHOLD_SFU = 400.0

# (variable, CSV field, scale, units, long_name) of the daily float variables
_DAILY = (
    ("kp_sum", "KP_SUM", 0.1, "1", "sum of the eight 3-hourly Kp of the day"),
    ("ap_daily", "AP_AVG", 1.0, "2 nT", "daily planetary equivalent amplitude Ap"),
    ("cp", "CP", 1.0, "1", "daily planetary character figure Cp"),
    ("c9", "C9", 1.0, "1", "daily planetary character figure C9"),
    ("isn", "ISN", 1.0, "1", "international sunspot number"),
    ("f107_obs_sfu", "F10.7_OBS", 1.0, "sfu", "observed 10.7-cm solar radio flux"),
    ("f107_adj_sfu", "F10.7_ADJ", 1.0, "sfu", "10.7-cm solar radio flux adjusted to 1 AU"),
    ("f107_obs_center81_sfu", "F10.7_OBS_CENTER81", 1.0, "sfu",
     "81-day centred average of the observed F10.7"),
    ("f107_obs_last81_sfu", "F10.7_OBS_LAST81", 1.0, "sfu",
     "average of the observed F10.7 over the last 81 days"),
    ("f107_adj_center81_sfu", "F10.7_ADJ_CENTER81", 1.0, "sfu",
     "81-day centred average of the adjusted F10.7"),
    ("f107_adj_last81_sfu", "F10.7_ADJ_LAST81", 1.0, "sfu",
     "average of the adjusted F10.7 over the last 81 days"),
)


_DATE = re.compile(r"\d{4}-\d\d-\d\d")


def _split_rows(lines: list[str], path: Path) -> tuple[np.ndarray, list[int]]:
    """Check the header and split the data rows into fields (1-based line numbers kept)."""
    if not lines or lines[0].strip() != _HEADER:
        raise FormatError(path, 1, "header", "not the CelesTrak SW-All CSV header")
    rows, line_nos = [], []
    for no, text in enumerate(lines[1:], start=2):
        if not text.strip():
            continue
        fields = text.split(",")
        if len(fields) != _N_FIELDS:
            raise FormatError(path, no, "row", f"{len(fields)} fields instead of {_N_FIELDS}")
        rows.append(fields)
        line_nos.append(no)
    if not rows:
        raise FormatError(path, None, "DATE", "the file has no data rows")
    return np.array(rows), line_nos


def _dates(texts: list[str], line_nos: list[int], path: Path) -> np.ndarray:
    """Parse ISO dates, checking validity and strict increase."""
    malformed = [k for k, text in enumerate(texts) if not _DATE.fullmatch(text)]
    if malformed:
        k = malformed[0]
        raise FormatError(path, line_nos[k], "DATE", f"'{texts[k]}' is not a date YYYY-MM-DD")
    try:
        dates = np.asarray(texts, dtype="datetime64[D]")
    except ValueError:  # an impossible date: find it, with its line (io._fields rules)
        for text, no in zip(texts, line_nos):
            y, m, d = (int(p) for p in text.split("-"))
            epoch_ns(y, m, d, 0, 0, 0.0, path, no, "DATE")
        raise  # pragma: no cover - numpy failed on the list but on no single text
    years = dates.astype("datetime64[Y]").astype(np.int64) + 1970
    out = np.flatnonzero((years < YEARS[0]) | (years > YEARS[1]))
    if out.size:
        k = out[0]
        raise FormatError(path, line_nos[k], "DATE", f"year {years[k]} outside "
                          f"{YEARS[0]}-{YEARS[1]}")
    bad = np.flatnonzero(np.diff(dates) <= np.timedelta64(0, "D"))
    if bad.size:
        no = line_nos[bad[0] + 1]
        raise FormatError(path, no, "DATE", "dates must increase from row to row")
    return dates


def _column(rows: np.ndarray, line_nos: list[int], name: str, path: Path,
            allow_blank: bool = True, lo: float = -1e6, hi: float = 1e6) -> np.ndarray:
    """One numeric column as float64 (blank → NaN if allowed), with exact error locations."""
    texts = np.char.strip(rows[:, _COL[name]])
    filled = texts != ""
    if not allow_blank and not filled.all():
        raise FormatError(path, line_nos[np.flatnonzero(~filled)[0]], name, "value is missing")
    values = np.full(len(rows), np.nan)
    values[filled] = parse_floats(texts[filled], np.asarray(line_nos)[filled], name, path,
                                  lo=lo, hi=hi)
    return values


def _check_range(values: np.ndarray, line_nos, name: str, path: Path, low: float,
                 high: float) -> None:
    """Raise FormatError at the first finite value outside [low, high]."""
    bad = np.flatnonzero((values < low) | (values > high))
    if bad.size:
        i = bad[0]
        raise FormatError(path, line_nos[i], name,
                          f"value {values[i]:g} outside the range [{low:g}, {high:g}]")


def read_space_weather(path: str | Path) -> xr.Dataset:
    """Read a CelesTrak space-weather CSV file (``SW-All.csv``, ``SW-Last5Years.csv``).

    Parameters
    ----------
    path : str or Path
        The CSV file (optionally gzip-compressed).

    Returns
    -------
    xarray.Dataset
        Indexed by ``date`` (and ``slot`` for the 3-hourly indices); see the module docstring.

    Raises
    ------
    FormatError
        Naming the line and field of the first bad value.
    """
    path = Path(path)
    lines = read_lines(path)
    require_line_end(lines, path)
    rows, line_nos = _split_rows(lines, path)
    dates = _dates(list(np.char.strip(rows[:, 0])), line_nos, path)
    with np.errstate(invalid="ignore"):  # NaN (blank) compare False
        kp = np.stack([_column(rows, line_nos, f"KP{k}", path) for k in range(1, 9)], axis=1)
        ap = np.stack([_column(rows, line_nos, f"AP{k}", path) for k in range(1, 9)], axis=1)
        for k in range(8):
            _check_range(kp[:, k], line_nos, f"KP{k + 1}", path, 0.0, 90.0)
            _check_range(ap[:, k], line_nos, f"AP{k + 1}", path, 0.0, 400.0)
        daily = {}
        for var, field, scale, units, long_name in _DAILY:
            values = _column(rows, line_nos, field, path)
            if field == "AP_AVG" or field.startswith("F10.7"):
                _check_range(values, line_nos, field, path, 0.0, np.inf)
            daily[var] = (("date",), values * scale, {"units": units, "long_name": long_name})
    types = np.char.strip(rows[:, _COL["F10.7_DATA_TYPE"]])
    unknown = np.flatnonzero(~np.isin(types, _TYPES))
    if unknown.size:
        i = unknown[0]
        raise FormatError(path, line_nos[i], "F10.7_DATA_TYPE",
                          f"'{types[i]}' is not one of {', '.join(_TYPES)}")
    types = types.astype("U3")
    bartels = {
        name: (("date",), _column(rows, line_nos, field, path, False, 0, hi).astype(np.int64),
               {"units": "1", "long_name": long_name})
        for name, field, long_name, hi in (
            ("bartels_rotation", "BSRN", "Bartels solar rotation number", 99_999),
            ("bartels_day", "ND", "day of the Bartels rotation", 27))
    }
    data_vars = {
        **bartels,
        "kp": (("date", "slot"), kp * 0.1, {"units": "1", "long_name": "3-hourly planetary Kp"}),
        "ap": (("date", "slot"), ap,
               {"units": "2 nT", "long_name": "3-hourly planetary equivalent amplitude ap"}),
        **daily,
        "f107_data_type": (("date",), types,
                           {"long_name": "F10.7 data type (OBS, INT, PRD, PRM)"}),
    }
    coords = {"date": dates.astype("datetime64[ns]"),
              "slot_start_h": ("slot", np.arange(0.0, 24.0, 3.0), {"units": "h"})}
    attrs = {"filename": path.name, "time_system": "UTC",
             "source": "CelesTrak space weather data (SW-All CSV format)"}
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def _day_rows(sw: xr.Dataset, day: np.ndarray) -> np.ndarray:
    """Row numbers of the UTC days ``day`` (datetime64[D]); ValueError for missing days."""
    dates = sw["date"].values.astype("datetime64[D]")
    idx = np.searchsorted(dates, day)
    found = idx < dates.size
    found[found] = dates[idx[found]] == day[found]
    if not found.all():
        missing = day[~found][0]
        raise ValueError(f"space weather: no daily record for {missing} (needed for MSIS); "
                         f"the file covers {dates[0]} to {dates[-1]}")
    return idx


def msis_inputs(sw: xr.Dataset, times_utc) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Solar and geomagnetic inputs of NRLMSISE-00 / MSIS 2.x at UTC epochs.

    Parameters
    ----------
    sw : xarray.Dataset
        From :func:`read_space_weather`.
    times_utc : datetime64 or array of datetime64, shape (n,)
        UTC epochs.

    Returns
    -------
    f107_sfu : ndarray, shape (n,)
        Observed F10.7 of the previous UTC day [sfu] (replaced by the 81-day average when above
        :data:`F107_BURST_THRESHOLD_SFU`, i.e. a radio burst).
    f107a_sfu : ndarray, shape (n,)
        Observed F10.7, 81-day average centred on the day of the epoch [sfu].
    ap : ndarray, shape (n, 7)
        The NRLMSISE-00 ap array [2 nT]: daily Ap; ap of the current 3-hour interval and of
        the three before; means of the eight ap 12–33 h and 36–57 h before (module docstring).

    Raises
    ------
    ValueError
        If a needed day (the three days before the epoch and the epoch's day) is missing from
        the file, is a monthly prediction, or lacks a value.
    """
    t_ns = np.atleast_1d(np.asarray(times_utc, dtype="datetime64[ns]")).astype(np.int64)
    day_ns = 86_400 * _NS_PER_S
    day_num = t_ns // day_ns  # days since 1970-01-01
    slot = (t_ns - day_num * day_ns) // (_SLOT_S * _NS_PER_S)  # 0..7
    back = np.arange(4)[None, :]  # the epoch's day and the three before
    days = (day_num[:, None] - back[:, ::-1]).astype("datetime64[D]")  # (n, 4): d-3..d
    rows = _day_rows(sw, days.ravel()).reshape(days.shape)
    ap_days = sw["ap"].values[rows].reshape(len(t_ns), 32)  # 3-hourly ap of days d-3..d
    current = 24 + slot  # index of the current 3-hour interval in ap_days
    lag = current[:, None] - np.arange(20)[None, :]  # intervals 0..19 back
    ap_hist = np.take_along_axis(ap_days, lag, axis=1)
    f107_prev = sw["f107_obs_sfu"].values[rows[:, 2]]
    f107a = sw["f107_obs_center81_sfu"].values[rows[:, 3]]
    prev81 = sw["f107_obs_center81_sfu"].values[rows[:, 2]]
    f107 = np.where(f107_prev > F107_BURST_THRESHOLD_SFU, prev81, f107_prev)
    ap = np.column_stack([sw["ap_daily"].values[rows[:, 3]], ap_hist[:, :4],
                          ap_hist[:, 4:12].mean(axis=1), ap_hist[:, 12:20].mean(axis=1)])
    if not (np.isfinite(ap).all() and np.isfinite(f107).all() and np.isfinite(f107a).all()):
        raise ValueError("space weather: blank F10.7 or ap values in the days needed for MSIS")
    kinds = sw["f107_data_type"].values[rows]
    if np.isin(kinds, ("PRD", "PRM")).any():
        logger.warning("space weather: predicted (not observed) indices used for MSIS")
    return f107, f107a, ap

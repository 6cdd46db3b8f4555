"""Reader of CODE's monthly differential code bias (DCB) files (P1-C1, P2-C2, P1-P2).

Format: the plain-text DCB files of the Center for Orbit Determination in Europe (CODE,
AIUB Bern, ftp.aiub.unibe.ch/CODE/), written by the Bernese GNSS Software. There is no separate
format document: the layout below is the one the files declare in their own column header,
checked on CODE's ``P1C10810_RINEX.DCB`` and ``P2C20810_RINEX.DCB``. Example
(``P1C10810_RINEX.DCB``)::

    CODE'S MONTHLY GNSS P1-C1 DCB SOLUTION, YEAR 2008, MONTH 10      20-APR-12 17:09
    --------------------------------------------------------------------------------

    DIFFERENTIAL (P1-C1) CODE BIASES FOR SATELLITES AND RECEIVERS:

    PRN / STATION NAME        VALUE (NS)  RMS (NS)
    ***   ****************    *****.***   *****.***
    G01                          -0.916       0.139
    R     ZIM2                   -2.694       0.040

Data columns (0-based, end exclusive): PRN or system letter 0:3, station name 6:22 (the
"RINEX" variant ``*_RINEX.DCB`` gives the 4-character RINEX marker name; the Bernese variant
adds the DOMES number), value 22:35 [ns], RMS 35:47 [ns]. Satellite rows have a blank station
field. Only the first ``DIFFERENTIAL (...)`` block is read; anything after it (e.g. the
``INTER-FREQ`` receiver block of daily files) is skipped with a log message, and characters
after column 47 (per-row validity stamps of daily files) are ignored.

Sign: DCB(P1-C1) = bias(P1) - bias(C1), i.e. with Bias-SINEX OSBs (CODE ``code.bia``
comment): P1-C1 DCB = OSB(C1W) - OSB(C1C).

Dataset schema
--------------
dims
    ``sv`` (satellites, ``G01`` ...), ``receiver`` (station rows; absent rows -> length 0).
coordinates
    ``sv``; ``station`` (receiver) - station name as written; ``system`` (receiver) - the
    system letter of the station bias.
data variables
    ``dcb_s`` (sv) [s], ``dcb_sigma_s`` (sv) [s], ``station_dcb_s`` (receiver) [s],
    ``station_dcb_sigma_s`` (receiver) [s].
attrs
    ``dcb_type`` (e.g. "P1-C1"), ``title`` (first line), ``year`` and ``month`` and
    ``period_start``/``period_end`` (ISO dates, end exclusive) when the title names a month,
    ``time_system`` ("GPS", implied by the CODE products).

Errors: :class:`leopod.io.FormatError` naming file, line and field for a missing block or
column header, a row that is neither a satellite nor a station, a value outside +-1e6 ns or a
negative RMS (reader contract, :mod:`leopod.io._fields`), and a row that ends before column 47
where its right-justified RMS ends (a file cut inside its last number).
"""

from __future__ import annotations

import logging
import re
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.io._fields import is_letters
from leopod.io._text import FormatError, parse_float, read_lines

__all__ = ["read_code_dcb"]

log = logging.getLogger(__name__)

_NS_TO_S = 1e-9
_BLOCK = re.compile(r"^DIFFERENTIAL \((P\d-[PC]\d)\) CODE BIASES")
_TITLE_TYPE = re.compile(r"\b(P\d-[PC]\d)\b")
_YEAR_MONTH = re.compile(r"YEAR\s+(\d{4}),\s*MONTH\s+(\d{1,2})")
_SV = re.compile(r"^[A-Z]\d\d$")


def read_code_dcb(path: str | Path) -> xr.Dataset:
    """Read a CODE monthly DCB file (plain, .gz or .Z).

    Parameters
    ----------
    path : str or Path
        ``P1C1yymm[_RINEX].DCB``, ``P2C2yymm[_RINEX].DCB`` or ``P1P2yymm[_ALL].DCB``.

    Returns
    -------
    xarray.Dataset
        Satellite and station DCBs in seconds (schema in the module docstring).

    Raises
    ------
    FormatError
        If the ``DIFFERENTIAL (...) CODE BIASES`` line or the ``PRN / STATION NAME`` column
        header is missing, a row is neither a satellite nor a station row, a value is
        missing, non-numeric or non-finite, or a satellite/station appears twice.
    """
    path = Path(path)
    lines = read_lines(path)
    attrs = _title(lines[0])
    k, dcb_type = _find_block(lines, path)
    if attrs.setdefault("dcb_type", dcb_type) != dcb_type:
        raise FormatError(path, k, "DIFFERENTIAL", f"block is {dcb_type}, the title line "
                          f"says {attrs['dcb_type']}")
    k = _find_column_header(lines, k, path)
    sats: dict[str, tuple[float, float]] = {}
    stations: dict[tuple[str, str], tuple[float, float]] = {}
    for i in range(k, len(lines)):
        line = lines[i]
        if not line.strip():
            continue
        if line.startswith("DIFFERENTIAL"):
            log.info("%s:%d: ignoring the further block '%s'", path.name, i + 1, line.strip())
            break
        _row(line, i + 1, path, sats, stations)
    if not sats and not stations:
        raise FormatError(path, None, "PRN / STATION NAME", "the file holds no DCB row")
    return _dataset(sats, stations, attrs)


def _title(line: str) -> dict:
    attrs: dict = {"title": line.strip(), "time_system": "GPS"}
    found = _TITLE_TYPE.search(line)
    if found:
        attrs["dcb_type"] = found.group(1)
    ym = _YEAR_MONTH.search(line)
    if ym and 1 <= int(ym.group(2)) <= 12:
        year, month = int(ym.group(1)), int(ym.group(2))
        start = np.datetime64(f"{year:04d}-{month:02d}", "M")
        attrs.update(year=year, month=month, period_start=str(start.astype("datetime64[D]")),
                     period_end=str((start + 1).astype("datetime64[D]")))
    return attrs


def _find_block(lines, path) -> tuple[int, str]:
    """Index after the first ``DIFFERENTIAL (Xn-Yn) CODE BIASES`` line, and its DCB type."""
    for k, line in enumerate(lines):
        found = _BLOCK.match(line)
        if found:
            return k + 1, found.group(1)
    raise FormatError(path, None, "DIFFERENTIAL (..) CODE BIASES",
                      "mandatory block title missing")


def _find_column_header(lines, k, path) -> int:
    """Index of the first data row, after ``PRN / STATION NAME`` and its ``***`` line."""
    for j in range(k, len(lines)):
        if lines[j].startswith("PRN / STATION NAME"):
            if j + 1 < len(lines) and lines[j + 1].startswith("***"):
                return j + 2
            raise FormatError(path, j + 2, "***", "column marker line missing after the "
                              "PRN / STATION NAME header")
        if lines[j].strip():
            break
    raise FormatError(path, None, "PRN / STATION NAME", "mandatory column header missing")


def _row(line, lineno, path, sats, stations) -> None:
    """Parse one data row into ``sats`` or ``stations`` (values in ns)."""
    head = line[0:3].strip()
    name = line[6:22].strip()
    if len(line.rstrip()) < 47:  # RMS is right-justified, its last digit in column 47
        raise FormatError(path, lineno, "RMS (NS)", f"the row ends in column "
                          f"{len(line.rstrip())}, before column 47 where its RMS ends (line "
                          "cut short?)")
    value = parse_float(line[22:35], path, lineno, "VALUE (NS)", kind="bias_ns")
    rms = parse_float(line[35:47], path, lineno, "RMS (NS)", kind="sigma_ns")
    if not name and _SV.match(head) and not line[3:6].strip():
        if head in sats:
            raise FormatError(path, lineno, "PRN", f"satellite {head} appears twice")
        sats[head] = (value, rms)
    elif name and len(head) == 1 and is_letters(head) and not line[1:6].strip():
        if (head, name) in stations:
            raise FormatError(path, lineno, "STATION NAME",
                              f"station {name} ({head}) appears twice")
        stations[(head, name)] = (value, rms)
    else:
        raise FormatError(path, lineno, "PRN / STATION NAME",
                          f"'{line[:22].rstrip()}' is neither a satellite (sNN) nor a "
                          "station row (system letter + name)")


def _dataset(sats, stations, attrs) -> xr.Dataset:
    sv = sorted(sats)
    sat_values = np.array([sats[s] for s in sv], dtype=float).reshape(-1, 2) * _NS_TO_S
    rx = list(stations)
    rx_values = np.array([stations[r] for r in rx], dtype=float).reshape(-1, 2) * _NS_TO_S
    what = f"{attrs['dcb_type']} differential code bias"
    ds = xr.Dataset(
        {
            "dcb_s": ("sv", sat_values[:, 0], {"units": "s", "long_name": f"satellite {what}"}),
            "dcb_sigma_s": ("sv", sat_values[:, 1],
                            {"units": "s", "long_name": f"RMS of the satellite {what}"}),
            "station_dcb_s": ("receiver", rx_values[:, 0],
                              {"units": "s", "long_name": f"station {what}"}),
            "station_dcb_sigma_s": ("receiver", rx_values[:, 1],
                                    {"units": "s", "long_name": f"RMS of the station {what}"}),
        },
        coords={"sv": sv, "station": ("receiver", [r[1] for r in rx]),
                "system": ("receiver", [r[0] for r in rx])},
    )
    ds.attrs.update(attrs)
    return ds

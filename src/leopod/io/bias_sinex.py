"""Reader of Bias-SINEX files (GNSS code and phase biases: OSB, DSB, ISB).

Format: "SINEX_BIAS - Solution (Software/technique) INdependent EXchange Format for GNSS
Biases, Version 1.00", S. Schaer, IGS, 7 December 2016
(files.igs.org/pub/data/format/sinex_bias_100.pdf); summary in
ftp.aiub.unibe.ch/bcwg/format/draft/sinex_bias_1.00_summary.txt.

Columns of a ``+BIAS/SOLUTION`` record (0-based, end exclusive), as in the block's header line
``*BIAS SVN_ PRN STATION__ OBS1 OBS2 BIAS_START____ BIAS_END______ UNIT
__ESTIMATED_VALUE____ _STD_DEV___ __ESTIMATED_SLOPE____ _STD_DEV___``::

    1:5 BIAS   6:10 SVN   11:14 PRN   15:24 STATION   25:29 OBS1   30:34 OBS2
    35:49 BIAS_START   50:64 BIAS_END   65:69 UNIT   70:91 VALUE   92:103 STD_DEV
    104:125 SLOPE   126:137 SLOPE_STD_DEV

Times are ``YYYY:DOY:SSSSS`` in the file's ``TIME_SYSTEM``; ``0000:000:00000`` is an open
bound (stored as NaT). A record with a blank ``BIAS_END`` is a time stamp (the spec assumes
piecewise-linear interpolation between stamps); a file uses either windows or stamps, which
:func:`read_bias_sinex` records in ``attrs["bias_timing"]``. Values in ``ns`` are converted to
seconds; phase biases in ``cyc`` are converted with the carrier frequency of ``OBS1``
(:mod:`leopod.signals`). The slope is read as bias unit per second (the unit the
specification gives it, to be confirmed on a file that has slopes: none of the test files does).

Sign (spec; comment block of CODE's ``code.bia``): a bias is *subtracted* from the
observation it belongs to, e.g. ``C1C_corrected = C1C - OSB(C1C)``.

Dataset schema
--------------
dims
    ``bias`` - one entry per ``+BIAS/SOLUTION`` record, in file order.
coordinates (bias)
    ``bias_type`` (OSB/DSB/ISB), ``svn``, ``prn`` (``G05``; for a station bias the system
    letter), ``station`` ("" for satellite biases), ``obs1``, ``obs2`` (RINEX 3 codes, ""
    when blank), ``unit`` (the file's unit: ``ns`` or ``cyc``), ``start``, ``end``
    (datetime64[ns], NaT = open or, for ``end``, time stamp).
data variables (bias)
    ``value_s`` [s], ``value_m`` (= value_s * c) [m], ``sigma_s`` [s], ``sigma_m`` [m],
    ``slope_s_per_s`` ["s s-1"], ``slope_sigma_s_per_s`` ["s s-1"]; NaN where the file leaves
    the field blank.
attrs
    ``format_version``, ``file_agency``, ``creation_time``, ``data_agency``, ``data_start``,
    ``data_end``, ``bias_mode_flag`` (A/R), ``n_estimates``, ``bias_timing``
    ("window"/"epoch"), ``time_system``, the ``+BIAS/DESCRIPTION`` keywords in lower case
    (``observation_sampling`` [s], ``parameter_spacing`` [s], ``determination_method``,
    ``bias_mode``, ``satellite_clock_reference_observables_G`` ...), and the
    ``+FILE/REFERENCE`` entries as ``reference_<info_type>``.
"""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.constants import C_LIGHT_M_S
from leopod.io._fields import check_count, day_of_year_ns
from leopod.io._text import FormatError, parse_float, parse_int, read_lines
from leopod.signals import frequency_hz

__all__ = ["osb", "read_bias_sinex"]

_LOG = logging.getLogger(__name__)
_NS_TO_S = 1e-9
_BIAS_TYPES = {"OSB", "DSB", "ISB"}
_TIME_SYSTEMS = {"G": "GPS", "R": "GLONASS", "E": "GAL", "C": "BDT", "J": "QZSS"}
_INT_KEYWORDS = {"OBSERVATION_SAMPLING", "PARAMETER_SPACING"}
_PER_SYSTEM_KEYWORDS = {"SATELLITE_CLOCK_REFERENCE_OBSERVABLES",
                        "RECEIVER_CLOCK_REFERENCE_OBSERVABLES"}
_NAT = np.datetime64("NaT", "ns")

# (name, start, stop, blank allowed, lo, hi) of the numeric fields of a solution record; the
# ranges are those of io._fields.RANGES "bias_ns"/"sigma_ns" (ns or cycles; 1e6 ns = 300 km).
_NUMBER_FIELDS = (("ESTIMATED_VALUE", 70, 91, False, -1e6, 1e6),
                  ("STD_DEV", 92, 103, True, 0.0, 1e6),
                  ("ESTIMATED_SLOPE", 104, 125, True, -1e6, 1e6),
                  ("SLOPE_STD_DEV", 126, 137, True, 0.0, 1e6))
# 0-based columns that are blank in every solution record (between the fields).
_SEPARATORS = (0, 5, 10, 14, 24, 29, 34, 49, 64, 69, 91, 103, 125)
# (name, start, stop) of the text fields of a solution record.
_TEXT_FIELDS = (("BIAS", 1, 5), ("SVN", 6, 10), ("PRN", 11, 14), ("STATION", 15, 24),
                ("OBS1", 25, 29), ("OBS2", 30, 34))


def read_bias_sinex(path: str | Path) -> xr.Dataset:
    """Read a Bias-SINEX 1.00 file (plain, .gz or .Z).

    Parameters
    ----------
    path : str or Path
        The ``.BIA``/``.bia`` file.

    Returns
    -------
    xarray.Dataset
        One entry per bias record, values in seconds and metres (schema in the module
        docstring).

    Raises
    ------
    FormatError
        If the ``%=BIA`` header line, the ``+BIAS/SOLUTION`` block or the closing ``%=ENDBIA``
        line is missing or a block unclosed, a field is not numeric, not finite or outside
        its range, a time is invalid, a unit is unknown, or windows and time stamps are mixed.
        A complete file (closed by ``%=ENDBIA``) whose record count differs from the
        ``%=BIA`` line's is read with a logged warning: real CODE 2021 OSB products announce
        6888 records and hold 6844.
    """
    path = Path(path)
    lines = read_lines(path)
    attrs = _first_line(lines[0], path)
    blocks = _blocks(lines, path)
    if "BIAS/SOLUTION" not in blocks:
        raise FormatError(path, None, "+BIAS/SOLUTION", "mandatory block missing")
    if "FILE/REFERENCE" in blocks:
        attrs.update(_file_reference(lines, *blocks["FILE/REFERENCE"]))
    if "BIAS/DESCRIPTION" in blocks:
        attrs.update(_description(lines, *blocks["BIAS/DESCRIPTION"], path))
    system = attrs.get("time_system_code", "G")
    attrs["time_system"] = _TIME_SYSTEMS.get(system, system)
    ds = _solution(lines, *blocks["BIAS/SOLUTION"], path)
    complete = any(line.startswith("%=ENDBIA") for line in lines[blocks["BIAS/SOLUTION"][1]:])
    if not complete:
        raise FormatError(path, len(lines), "%=ENDBIA", "no %=ENDBIA line after the "
                          "+BIAS/SOLUTION block (file truncated?)")
    check_count(attrs["n_estimates"], ds.sizes["bias"], path, 1, "number of estimates",
                "bias records (%=BIA line)", complete=True, log=_LOG)
    ds.attrs.update(attrs)
    return ds


def osb(ds: xr.Dataset, prn: str, code: str, epoch) -> float:
    """Satellite observable-specific bias of one signal at one epoch [m].

    Parameters
    ----------
    ds : xarray.Dataset
        Output of :func:`read_bias_sinex`.
    prn : str
        Satellite (``"G05"``).
    code : str
        RINEX 3 observation code (``"C1W"``, ``"L2W"``).
    epoch : numpy.datetime64, datetime or ISO str
        Epoch in the file's time system.

    Returns
    -------
    float
        The OSB [m] valid at ``epoch`` (window files: the record with
        ``start <= epoch < end``, open bounds unlimited; time-stamp files: linear
        interpolation between the stamps). Subtract it from the observation.

    Raises
    ------
    KeyError
        If no record of ``prn``/``code`` covers ``epoch`` (message names all three).
    ValueError
        If several windows cover ``epoch``.
    """
    t = np.datetime64(epoch, "ns")
    sel = ((ds["bias_type"] == "OSB") & (ds["prn"] == prn) & (ds["obs1"] == code)
           & (ds["station"] == "")).values
    where = f"no OSB for {prn} {code} at {t}"
    if not sel.any():
        raise KeyError(f"{where}: the file has no OSB record of {prn} {code}")
    start = ds["start"].values[sel]
    value = ds["value_m"].values[sel]
    if ds.attrs["bias_timing"] == "epoch":
        order = np.argsort(start)
        start, value = start[order], value[order]
        if not start[0] <= t <= start[-1]:
            raise KeyError(f"{where}: time stamps span {start[0]} .. {start[-1]}")
        x = (start - start[0]) / np.timedelta64(1, "ns")
        return float(np.interp((t - start[0]) / np.timedelta64(1, "ns"), x, value))
    end = ds["end"].values[sel]
    inside = (np.isnat(start) | (start <= t)) & (np.isnat(end) | (t < end))
    if not inside.any():
        raise KeyError(f"{where}: no validity window of {prn} {code} contains it")
    if inside.sum() > 1:
        raise ValueError(f"{inside.sum()} OSB windows of {prn} {code} contain {t}")
    return float(value[inside][0])


def _first_line(line: str, path: Path) -> dict:
    """Parse ``%=BIA 1.00 AGY YYYY:DDD:SSSSS AGY YYYY:DDD:SSSSS YYYY:DDD:SSSSS M NNNNNNNN``."""
    if not line.startswith("%=BIA"):
        raise FormatError(path, 1, "%=BIA", "the file does not start with the %=BIA line")
    parts = line.split()
    if len(parts) != 9:
        raise FormatError(path, 1, "%=BIA", f"expected 9 fields, found {len(parts)}")
    return {
        "format_version": parts[1],
        "file_agency": parts[2],
        "creation_time": _iso(_sinex_time(parts[3], path, 1, "creation time")),
        "data_agency": parts[4],
        "data_start": _iso(_sinex_time(parts[5], path, 1, "data start")),
        "data_end": _iso(_sinex_time(parts[6], path, 1, "data end")),
        "bias_mode_flag": parts[7],
        "n_estimates": parse_int(parts[8], path, 1, "number of estimates", lo=0, hi=10**7),
    }


def _iso(t: np.datetime64) -> str:
    return "" if np.isnat(t) else str(t)


def _blocks(lines: list[str], path: Path) -> dict[str, tuple[int, int]]:
    """Map block name -> (index of its first content line, index of its ``-`` line)."""
    blocks: dict[str, tuple[int, int]] = {}
    name, first = None, 0
    for k, line in enumerate(lines):
        if line.startswith("+"):
            if name is not None:
                raise FormatError(path, k + 1, f"-{name}",
                                  f"block +{name} (line {first}) is not closed")
            name, first = line[1:].strip(), k + 1
        elif line.startswith("-"):
            if name is not None and line[1:].strip() != name and name == "FILE/COMMENT":
                # SINEX_BIAS 1.00: comment lines start with "*" or a blank; DLR's MGEX DSB
                # files start a sentence of +FILE/COMMENT with "- ": read as comment text
                _LOG.warning("%s:%d: line starting with '-' inside +FILE/COMMENT read as a "
                             "comment", path, k + 1)
                continue
            if line[1:].strip() != name:
                raise FormatError(path, k + 1, line.strip(), "closes a block that is not open")
            blocks[name] = (first, k)
            name = None
        elif line.startswith("%=ENDBIA"):
            break
    if name is not None:
        raise FormatError(path, len(lines), f"-{name}",
                          f"block +{name} (line {first}) is not closed (file truncated?)")
    return blocks


def _file_reference(lines, first, stop) -> dict:
    out: dict[str, str] = {}
    for line in lines[first:stop]:
        if line.startswith("*") or not line.strip():
            continue
        key = "reference_" + line[1:19].strip().lower()
        out[key] = "; ".join(filter(None, (out.get(key, ""), line[20:].strip())))
    return out


def _description(lines, first, stop, path) -> dict:
    out: dict = {}
    for k in range(first, stop):
        line = lines[k]
        if line.startswith("*") or not line.strip():
            continue
        keyword, value = line[1:40].strip(), line[40:].strip()
        if keyword in _INT_KEYWORDS:
            out[keyword.lower()] = parse_int(value, path, k + 1, keyword, lo=0, hi=10**6)
        elif keyword == "TIME_SYSTEM":
            out["time_system_code"] = value
        elif keyword in _PER_SYSTEM_KEYWORDS:
            system, _, observables = value.partition(" ")
            out[f"{keyword.lower()}_{system}"] = " ".join(observables.split())
        else:
            out[keyword.lower()] = value
    return out


def _solution(lines, first, stop, path) -> xr.Dataset:
    """Parse the records of +BIAS/SOLUTION into the Dataset (without file attrs)."""
    text: dict[str, list[str]] = {name: [] for name, _, _ in _TEXT_FIELDS}
    units, starts, ends, values = [], [], [], []
    times: dict[str, np.datetime64] = {}
    stamp_lines = window_lines = 0
    for k in range(first, stop):
        line = lines[k]
        if line.startswith("*") or not line.strip():
            continue
        lineno = k + 1
        if len(line) < 91:
            raise FormatError(path, lineno, "ESTIMATED_VALUE",
                              f"record of {len(line)} characters ends before the value "
                              "(columns 71-91)")
        fields = {name: line[a:b].strip() for name, a, b in _TEXT_FIELDS}
        if fields["BIAS"] not in _BIAS_TYPES:
            raise FormatError(path, lineno, "BIAS", f"unknown bias type '{fields['BIAS']}'")
        if not fields["OBS1"]:
            raise FormatError(path, lineno, "OBS1", "observation code missing")
        for name, _, _ in _TEXT_FIELDS:
            text[name].append(fields[name])
        start_text, end_text = line[35:49].strip(), line[50:64].strip()
        starts.append(_cached_time(start_text, times, path, lineno, "BIAS_START"))
        if end_text:
            window_lines = window_lines or lineno
            ends.append(_cached_time(end_text, times, path, lineno, "BIAS_END"))
        else:
            stamp_lines = stamp_lines or lineno
            ends.append(_NAT)
        unit = line[65:69].strip()
        units.append(unit)
        _check_separators(line, path, lineno)
        raw = [parse_float(line[a:b], path, lineno, name, allow_blank=blank_ok, lo=lo, hi=hi)
               for name, a, b, blank_ok, lo, hi in _NUMBER_FIELDS]
        scale = _to_seconds(unit, fields["PRN"], fields["OBS1"], path, lineno)
        values.append([v * scale for v in raw])
    if stamp_lines and window_lines:
        raise FormatError(path, max(stamp_lines, window_lines), "BIAS_END",
                          f"time windows (line {window_lines}) and time stamps with blank "
                          f"BIAS_END (line {stamp_lines}) are mixed in one file")
    v = np.array(values, dtype=float).reshape(-1, 4)
    coords = {
        "bias_type": ("bias", text["BIAS"]), "svn": ("bias", text["SVN"]),
        "prn": ("bias", text["PRN"]), "station": ("bias", text["STATION"]),
        "obs1": ("bias", text["OBS1"]), "obs2": ("bias", text["OBS2"]),
        "unit": ("bias", units),
        "start": ("bias", np.array(starts, dtype="datetime64[ns]")),
        "end": ("bias", np.array(ends, dtype="datetime64[ns]")),
    }
    data = {
        "value_s": ("bias", v[:, 0], {"units": "s", "long_name": "bias"}),
        "value_m": ("bias", v[:, 0] * C_LIGHT_M_S, {"units": "m", "long_name": "bias"}),
        "sigma_s": ("bias", v[:, 1], {"units": "s", "long_name": "bias standard deviation"}),
        "sigma_m": ("bias", v[:, 1] * C_LIGHT_M_S,
                    {"units": "m", "long_name": "bias standard deviation"}),
        "slope_s_per_s": ("bias", v[:, 2], {"units": "s s-1", "long_name": "bias slope"}),
        "slope_sigma_s_per_s": ("bias", v[:, 3],
                                {"units": "s s-1", "long_name": "bias slope standard deviation"}),
    }
    ds = xr.Dataset(data, coords=coords)
    ds.attrs["bias_timing"] = "epoch" if stamp_lines else "window"
    return ds


def _check_separators(line: str, path, lineno: int) -> None:
    """The blank columns between the fields of a solution record (a record with shifted
    columns would otherwise be read with a wrong value)."""
    for col in _SEPARATORS:
        if col < len(line) and line[col] != " ":
            name = next((n for n, a, _ in _TEXT_FIELDS if a > col), "ESTIMATED_VALUE")
            raise FormatError(path, lineno, name, f"column {col + 1} must be blank (fixed "
                              "columns of the SINEX_BIAS 1.00 solution record; shifted?)")


def _to_seconds(unit: str, prn: str, obs1: str, path, lineno) -> float:
    """Factor converting a value in ``unit`` to seconds."""
    if unit == "ns":
        return _NS_TO_S
    if unit == "cyc":
        if obs1[0] != "L":
            raise FormatError(path, lineno, "UNIT", f"unit 'cyc' for code observable {obs1}")
        try:
            return 1.0 / frequency_hz(prn[:1], obs1)
        except KeyError:
            raise FormatError(path, lineno, "UNIT",
                              f"cannot convert cycles of {prn[:1]} {obs1} to seconds: carrier "
                              "frequency unknown (GLONASS FDMA or unsupported system)") from None
    raise FormatError(path, lineno, "UNIT", f"unsupported unit '{unit}' (expected ns or cyc)")


def _cached_time(text, cache, path, lineno, field) -> np.datetime64:
    if text not in cache:
        cache[text] = _sinex_time(text, path, lineno, field)
    return cache[text]


def _sinex_time(text: str, path, lineno: int, field: str) -> np.datetime64:
    """``YYYY:DOY:SSSSS`` (or ``YY:DOY:SSSSS``) -> datetime64[ns]; all zeros -> NaT (open)."""
    parts = text.split(":")
    if len(parts) != 3:
        raise FormatError(path, lineno, field, f"'{text}' is not YYYY:DOY:SSSSS")
    year, doy, sec = (parse_int(p, path, lineno, field, lo=0) for p in parts)
    if year == doy == sec == 0:
        return _NAT
    if len(parts[0]) == 2:
        year += 2000 if year < 50 else 1900
    return np.datetime64(day_of_year_ns(year, doy, sec, path, lineno, field), "ns")

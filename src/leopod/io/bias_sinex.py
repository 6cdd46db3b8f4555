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

from pathlib import Path

import numpy as np
import xarray as xr

from leopod.constants import C_LIGHT_M_S
from leopod.io._text import FormatError, parse_float, parse_int, read_lines, write_text
from leopod.signals import frequency_hz

__all__ = ["osb", "read_bias_sinex", "write_bias_sinex"]

_NS_TO_S = 1e-9
_BIAS_TYPES = {"OSB", "DSB", "ISB"}
_TIME_SYSTEMS = {"G": "GPS", "R": "GLONASS", "E": "GAL", "C": "BDT", "J": "QZSS"}
_INT_KEYWORDS = {"OBSERVATION_SAMPLING", "PARAMETER_SPACING"}
_PER_SYSTEM_KEYWORDS = {"SATELLITE_CLOCK_REFERENCE_OBSERVABLES",
                        "RECEIVER_CLOCK_REFERENCE_OBSERVABLES"}
_NAT = np.datetime64("NaT", "ns")

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
        If the ``%=BIA`` header line or the ``+BIAS/SOLUTION`` block is missing or unclosed,
        the number of records differs from the header's count, a field is not numeric or not
        finite, a time is invalid, a unit is unknown, or windows and time stamps are mixed.
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
    if attrs["n_estimates"] != ds.sizes["bias"]:
        raise FormatError(path, 1, "number of estimates",
                          f"the %=BIA line announces {attrs['n_estimates']} bias records, "
                          f"+BIAS/SOLUTION holds {ds.sizes['bias']} (file truncated?)")
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
        "n_estimates": parse_int(parts[8], path, 1, "number of estimates"),
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
            out[keyword.lower()] = parse_int(value, path, k + 1, keyword)
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
        raw = [_number(line, a, b, path, lineno, name, blank_ok)
               for name, a, b, blank_ok in (("ESTIMATED_VALUE", 70, 91, False),
                                            ("STD_DEV", 92, 103, True),
                                            ("ESTIMATED_SLOPE", 104, 125, True),
                                            ("SLOPE_STD_DEV", 126, 137, True))]
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


def _number(line, a, b, path, lineno, name, blank_ok) -> float:
    return parse_float(line[a:b], path, lineno, name, allow_blank=blank_ok)


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
    year, doy, sec = (parse_int(p, path, lineno, field) for p in parts)
    if year == doy == sec == 0:
        return _NAT
    if len(parts[0]) == 2:
        year += 2000 if year < 50 else 1900
    if not (1 <= doy <= 366 and 0 <= sec <= 86400):
        raise FormatError(path, lineno, field, f"'{text}': day of year or second out of range")
    return (np.datetime64(f"{year:04d}-01-01", "ns") + np.timedelta64(doy - 1, "D")
            + np.timedelta64(sec, "s"))


# --------------------------------------------------------------------------------------------
# Writer

_SEPARATOR = "*" + "-" * 79
_SOLUTION_HEADER = ("*BIAS SVN_ PRN STATION__ OBS1 OBS2 BIAS_START____ BIAS_END______ UNIT "
                    "__ESTIMATED_VALUE____ _STD_DEV___ __ESTIMATED_SLOPE____ _STD_DEV___")
_TIME_SYSTEM_CODES = {name: code for code, name in _TIME_SYSTEMS.items()}
_NAT_INT = _NAT.view("int64")
# +BIAS/DESCRIPTION keywords written from the attrs of :func:`read_bias_sinex`, in the order of
# the CODE files (integer keywords right-aligned in columns 42-53, text from column 42).
_DESCRIPTION_ORDER = ("OBSERVATION_SAMPLING", "PARAMETER_SPACING", "DETERMINATION_METHOD",
                      "BIAS_MODE", "APC_MODEL", "TIME_SYSTEM", "RECEIVER_CLOCK_REFERENCE_GNSS",
                      "RECEIVER_CLOCK_REFERENCE_OBSERVABLES",
                      "SATELLITE_CLOCK_REFERENCE_OBSERVABLES")


def write_bias_sinex(ds: xr.Dataset, path: str | Path, *, decimals: int = 6,
                     comments: tuple[str, ...] = ()) -> None:
    """Write a Bias-SINEX 1.00 file that :func:`read_bias_sinex` reads back to ``ds``.

    The layout is that of the real CODE and WHU files (header line, ``+FILE/REFERENCE``,
    optional ``+FILE/COMMENT``, ``+BIAS/DESCRIPTION``, ``+BIAS/SOLUTION``, ``%=ENDBIA``);
    record columns as in the module docstring. Values are written in each record's ``unit``
    (``ns``, or ``cyc`` for phase biases, converted with the carrier frequency of ``OBS1``)
    with ``decimals`` decimals (default 6: 1e-6 ns, 0.3 µm; real files use 3-5). A blank
    ``sigma_s``/slope (NaN) leaves the field blank. Sign as in the reader: the bias is
    subtracted from the observation. A name ending in ``.gz`` is gzip-compressed; the file is
    written atomically.

    Parameters
    ----------
    ds : xarray.Dataset
        The schema of :func:`read_bias_sinex`: on dim ``bias`` the coordinates ``bias_type``,
        ``svn``, ``prn``, ``station``, ``obs1``, ``obs2``, ``start``, ``end`` (NaT: open bound
        ``0000:000:00000``, or a time stamp when ``attrs["bias_timing"] == "epoch"``), optional
        ``unit`` (default ``ns``), data ``value_s`` [s] and optional ``sigma_s`` [s],
        ``slope_s_per_s``, ``slope_sigma_s_per_s``. Header attrs (defaults in brackets):
        ``file_agency`` [LEO], ``data_agency`` [file_agency], ``creation_time``
        [data_end, for reproducible files], ``data_start``/``data_end`` [first start/last end
        of the records], ``bias_mode_flag`` [A], ``time_system_code`` (or ``time_system``)
        [G], the ``+BIAS/DESCRIPTION`` keywords in lower case (``observation_sampling``,
        ``parameter_spacing``, ``determination_method``, ``bias_mode``, ``apc_model``,
        ``receiver_clock_reference_gnss``, ``satellite_clock_reference_observables_<sys>``,
        ``receiver_clock_reference_observables_<sys>``) and ``reference_<info_type>`` entries
        ("; " separates several lines of one type).
    path : str or Path
        Output file.
    decimals : int
        Decimals of the values and standard deviations.
    comments : tuple of str
        Lines of a ``+FILE/COMMENT`` block (at most 79 characters each).

    Raises
    ------
    ValueError
        If a required variable is missing, a value is not finite, a text field or comment is
        too long, a unit is not ns/cyc, or a time cannot be written as ``YYYY:DOY:SSSSS``.
    """
    for name in ("value_s", "bias_type", "prn", "obs1", "start", "end"):
        if name not in ds.variables:
            raise ValueError(f"the Dataset has no '{name}' variable")
    if any(len(c) > 79 for c in comments):
        raise ValueError("a +FILE/COMMENT line is longer than 79 characters")
    records = _solution_records(ds, decimals)
    attrs = ds.attrs
    agency = str(attrs.get("file_agency", "LEO"))
    starts = ds["start"].values
    ends = ds["end"].values
    data_start = attrs["data_start"] if "data_start" in attrs else _bound(starts, np.min)
    data_end = attrs["data_end"] if "data_end" in attrs else _bound(ends, np.max)
    header = (f"%=BIA 1.00 {agency:3.3s} {_format_time(attrs.get('creation_time') or data_end)} "
              f"{attrs.get('data_agency', agency)!s:3.3s} {_format_time(data_start)} "
              f"{_format_time(data_end)} {attrs.get('bias_mode_flag', 'A')!s} "
              f"{len(records):08d}")
    lines = [header, _SEPARATOR,
             "* Bias Solution INdependent EXchange Format (Bias-SINEX)", _SEPARATOR]
    lines += _reference_block(attrs)
    if comments:
        lines += ["+FILE/COMMENT", "*PRODUCT_REFERENCE" + "_" * 62, *(f" {c}" for c in comments),
                  "-FILE/COMMENT", _SEPARATOR]
    lines += _description_block(attrs)
    lines += ["+BIAS/SOLUTION", _SOLUTION_HEADER, *records, "-BIAS/SOLUTION", "%=ENDBIA"]
    write_text(path, "\n".join(lines) + "\n")


def _bound(times: np.ndarray, pick) -> str:
    """First or last finite time of the records ("" if all are open)."""
    finite = times[~np.isnat(times)]
    return str(pick(finite)) if finite.size else ""


def _reference_block(attrs) -> list[str]:
    lines = []
    for key, value in attrs.items():
        if key.startswith("reference_"):
            info_type = key[len("reference_"):].upper()
            lines += [f" {info_type:<18.18s} {part}"[:80] for part in str(value).split("; ")]
    if not lines:
        return []
    return ["+FILE/REFERENCE", "*INFO_TYPE_________ INFO" + "_" * 56, *lines,
            "-FILE/REFERENCE", _SEPARATOR]


def _description_block(attrs) -> list[str]:
    lines = []
    for keyword in _DESCRIPTION_ORDER:
        key = keyword.lower()
        if keyword in _PER_SYSTEM_KEYWORDS:
            for attr in sorted(k for k in attrs if k.startswith(key + "_")):
                system = attr[len(key) + 1:]
                observables = "  ".join(str(attrs[attr]).split())
                lines.append(f" {keyword:<39s} {system}  {observables}".rstrip())
        elif keyword == "TIME_SYSTEM":
            code = attrs.get("time_system_code") or _TIME_SYSTEM_CODES.get(
                str(attrs.get("time_system", "GPS")), "G")
            lines.append(f" {keyword:<39s} {code}")
        elif key in attrs:
            value = attrs[key]
            text = f"{int(value):>12d}" if keyword in _INT_KEYWORDS else str(value)
            lines.append(f" {keyword:<39s} {text}")
    return ["+BIAS/DESCRIPTION", "*KEYWORD" + "_" * 32 + " VALUE(S)" + "_" * 31, *lines,
            "-BIAS/DESCRIPTION", _SEPARATOR]


def _solution_records(ds: xr.Dataset, decimals: int) -> list[str]:
    n = ds.sizes["bias"]

    def column(name, default):
        return ds[name].values if name in ds.variables else np.full(n, default)

    text = {name: [str(v) for v in column(name.lower(), "")]
            for name in ("BIAS_TYPE", "SVN", "PRN", "STATION", "OBS1", "OBS2")}
    units = [str(u) for u in column("unit", "ns")]
    values = np.stack([column(name, np.nan) for name in
                       ("value_s", "sigma_s", "slope_s_per_s", "slope_sigma_s_per_s")], axis=-1)
    stamps = ds.attrs.get("bias_timing") == "epoch"
    starts, ends = ds["start"].values, ds["end"].values
    # format each distinct time once (keyed by its integer value: NaT compares unequal)
    keys = {int(i): t for t, i in zip(np.concatenate([starts, ends]),
                                      np.concatenate([starts, ends]).view("int64"))}
    times = {i: _format_time(t) for i, t in keys.items()}
    starts, ends = starts.view("int64"), ends.view("int64")
    out = []
    for k in range(n):
        fields = {name: text[name][k] for name in text}
        for name, width in (("BIAS_TYPE", 4), ("SVN", 4), ("PRN", 3), ("STATION", 9),
                            ("OBS1", 4), ("OBS2", 4), ):
            if len(fields[name]) > width:
                raise ValueError(f"record {k}: {name} '{fields[name]}' is longer than {width}")
        if not np.isfinite(values[k, 0]):
            raise ValueError(f"record {k} ({fields['PRN']} {fields['OBS1']}): value is not "
                             "finite")
        scale = _from_seconds(units[k], fields["PRN"], fields["OBS1"], k)
        start = times[int(starts[k])]
        end = "" if stamps and ends[k] == _NAT_INT else times[int(ends[k])]
        v = values[k] * scale
        numbers = (f"{v[0]:21.{decimals}f} {_blank_or(v[1], 11, decimals)} "
                   f"{_blank_or(v[2], 21, decimals)} {_blank_or(v[3], 11, decimals)}")
        out.append(f" {fields['BIAS_TYPE']:<4s} {fields['SVN']:<4s} {fields['PRN']:<3s} "
                   f"{fields['STATION']:<9s} {fields['OBS1']:<4s} {fields['OBS2']:<4s} "
                   f"{start:<14s} {end:<14s} {units[k]:<4s} {numbers}".rstrip())
    return out


def _blank_or(value: float, width: int, decimals: int) -> str:
    return f"{value:{width}.{decimals}f}" if np.isfinite(value) else " " * width


def _from_seconds(unit: str, prn: str, obs1: str, k: int) -> float:
    """Factor converting seconds to ``unit`` (inverse of the reader's ``_to_seconds``)."""
    if unit == "ns":
        return 1.0 / _NS_TO_S
    if unit == "cyc" and obs1.startswith("L"):
        return frequency_hz(prn[:1], obs1)
    raise ValueError(f"record {k} ({prn} {obs1}): cannot write unit '{unit}' (ns, or cyc "
                     "for phase)")


def _format_time(value) -> str:
    """datetime64 / ISO text -> ``YYYY:DOY:SSSSS``; NaT or "" -> ``0000:000:00000``."""
    if isinstance(value, str) and not value:
        return "0000:000:00000"
    t = np.datetime64(value, "ns")
    if np.isnat(t):
        return "0000:000:00000"
    day = t.astype("datetime64[D]")
    seconds = (t - day) / np.timedelta64(1, "s")
    if seconds != int(seconds):
        raise ValueError(f"time {t} is not a whole second (Bias-SINEX times are YYYY:DOY:SSSSS)")
    year = day.astype("datetime64[Y]")
    doy = int((day - year) / np.timedelta64(1, "D")) + 1
    return f"{int(str(year)):04d}:{doy:03d}:{int(seconds):05d}"

"""Reader of RINEX clock files (versions 2.00 and 3.00 to 3.04).

Specification: J. Ray, W. Gurtner, M. Coleman, "RINEX Extensions to Handle Clock Information",
version 3.04 (8 July 2017, files.igs.org/pub/data/format/rinex_clock304.txt), which also
documents 2.00 and 3.00-3.02. Up to 3.02 the header label sits in columns 61-80 and the clock
name of a data record is A4 (columns 4-7); from 3.04 on the label sits in columns 66-85 and the
name is A9 (columns 4-12), shifting the rest of the record by five columns. The epoch, the
number of values and the values of a record are read as blank-separated fields after the name.

Dataset returned by :func:`read_rinex_clock`
--------------------------------------------
One ``time`` axis, the union of the epochs of the requested record types (so satellite ``AS``
and station ``AR`` clocks of one file share it; missing combinations are NaN).

Coordinates
    ``time`` (time,) datetime64[ns] -- epochs in the file's time system (``attrs["time_system"]``)
    ``sv`` (sv,) str -- satellites with ``AS`` records, sorted ("G01", ...); only with "AS"
    ``station`` (station,) str -- receivers with ``AR`` records, sorted; only with "AR"
Data variables (only for the requested kinds)
    ``clk_s`` (time, sv) float64 [s] -- satellite clock bias (AS)
    ``clk_sigma_s`` (time, sv) float64 [s] -- its standard deviation, NaN when absent
    ``clk_station_s`` (time, station) float64 [s] -- receiver clock bias (AR)
    ``clk_station_sigma_s`` (time, station) float64 [s] -- its standard deviation, NaN if absent
    Rates and accelerations (values 3 to 6 of a record) are checked but not returned.
Attributes
    ``rinex_version`` (float), ``time_system`` ("GPS" when the header has no TIME SYSTEM ID;
    "GPS" with ``time_system_file`` the file's when read with ``gps_time=True``),
    ``analysis_center`` (3-character id, e.g. "COD"), ``analysis_center_name``, ``data_types``
    (e.g. "AR AS"), ``pcv_applied`` / ``dcb_applied`` (text of the SYS / PCVS / DCBS APPLIED
    records, "; "-joined; only when present), ``leap_seconds`` (int, when present),
    ``interval_s`` (median spacing of the AS epochs, else of all epochs; 0.0 for one epoch),
    ``filename``.

Errors
------
:class:`leopod.io.FormatError` (file, line, field) for a missing ``RINEX VERSION / TYPE``,
``# / TYPES OF DATA`` or ``END OF HEADER`` record, a file that is not a clock file, a bad
epoch, a bad or non-finite value (field ``"<name> clock bias"`` / ``"<name> clock sigma"``),
a record whose number of values disagrees with the values present (e.g. truncated), and two
records of one clock at one epoch. A single-line record with more values than it announces
(peer files write a trailing flag, or a sigma after a count of 1) is read with the announced
values and a logged warning. Values and sigmas lie within +-1000 s (io._fields "clock_s").
"""

from __future__ import annotations

import logging
import re
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.io._fields import RANGES, is_number
from leopod.io._text import (
    PRODUCT_TIME_SYSTEMS,
    FormatError,
    calendar_epoch_ns,
    parse_float,
    parse_floats,
    parse_int,
    read_lines,
    time_system_to_gps,
)

__all__ = ["read_rinex_clock"]

_LOG = logging.getLogger(__name__)

_NS = 1_000_000_000
_KINDS = ("AS", "AR")
_RECORD_TYPES = ("AR", "AS", "CR", "DR", "MS")
# a complete E19.12 value (a value cut by truncation loses exponent digits)
_E_VALUE = re.compile(r"[+-]?\d*\.\d*[EeDd][+-]?\d{2,3}")
_VAR_NAMES = {"AS": ("sv", "clk_s", "clk_sigma_s", "satellite clock"),
              "AR": ("station", "clk_station_s", "clk_station_sigma_s", "receiver clock")}


def _to_float(texts: list[str], line_nos: list[int], fields: list[str], path: Path,
              kind: str = "clock_s") -> np.ndarray:
    """Convert E19.12 value texts to float64; fast numpy path, exact FormatError otherwise.

    Blank texts become NaN (an absent optional value). A text without a complete exponent
    (e.g. cut by truncation) is an error, as it would otherwise give a wrong number.
    """
    if not texts:
        return np.empty(0)
    match = _E_VALUE.fullmatch
    for k, text in enumerate(texts):
        if text and not match(text):
            parse_float(text, path, line_nos[k], fields[k])  # raises if not a number at all
            raise FormatError(path, line_nos[k], fields[k], f"'{text}' is not an E19.12 "
                              "value (incomplete exponent: truncated?)")
    return parse_floats(texts, line_nos, fields, path, allow_blank=True, kind=kind)


def _epoch_ns(text: str, path: Path, line_no: int) -> int:
    """ns since 1970-01-01 of a "yyyy mm dd hh mm ss.ssssss" epoch text."""
    parts = text.split()
    if len(parts) != 6:
        raise FormatError(path, line_no, "epoch", f"'{text.strip()}' is not an epoch "
                          "(year month day hour minute second)")
    names = ("year", "month", "day", "hour", "minute")
    ints = [parse_int(p, path, line_no, n, lo=0) for p, n in zip(parts, names)]
    seconds = parse_float(parts[5], path, line_no, "second")
    return calendar_epoch_ns(tuple(ints), seconds, path, line_no)


def _parse_header(lines: list[str], path: Path) -> tuple[dict, int, bool]:
    """Header attributes, the index of the first data line and whether the layout is 3.04+."""
    first = lines[0] if lines else ""
    if "RINEX VERSION / TYPE" not in first:
        raise FormatError(path, 1, "RINEX VERSION / TYPE", "the first line must be the "
                          "'RINEX VERSION / TYPE' record")
    version = parse_float(first[:9], path, 1, "format version")
    wide = version >= 3.04
    label_col = first.index("RINEX VERSION / TYPE")  # 60 up to 3.02, 65 from 3.04
    kind = first[9:label_col].split()
    if not kind or not kind[0].upper().startswith("C"):
        raise FormatError(path, 1, "file type", "not a RINEX clock file (file type "
                          f"'{kind[0] if kind else ''}', expected 'C')")
    attrs: dict = {"rinex_version": version, "time_system": "GPS"}
    applied: dict[str, list[str]] = {"pcv_applied": [], "dcb_applied": []}
    for i in range(1, len(lines)):
        text = lines[i]
        label = text[label_col:].strip()
        content = text[:label_col]
        if label == "END OF HEADER":
            if "data_types" not in attrs:
                raise FormatError(path, None, "# / TYPES OF DATA",
                                  "the mandatory header record is missing")
            for key, values in applied.items():
                if values:
                    attrs[key] = "; ".join(values)
            return attrs, i + 1, wide
        if label == "TIME SYSTEM ID" and content.strip():
            code = content.split()[0]
            if code not in PRODUCT_TIME_SYSTEMS:
                raise FormatError(path, i + 1, "TIME SYSTEM ID", f"'{code}' is not a RINEX "
                                  f"clock time system ({', '.join(PRODUCT_TIME_SYSTEMS)})")
            attrs.update(time_system=code, _time_system_line=i + 1)
        elif label == "LEAP SECONDS":
            attrs["leap_seconds"] = parse_int(content[:6], path, i + 1, "LEAP SECONDS", lo=0,
                                              hi=99)
        elif label == "ANALYSIS CENTER":
            attrs["analysis_center"] = content[:3].strip()
            attrs["analysis_center_name"] = content[5:].strip()
        elif label == "# / TYPES OF DATA":
            n = parse_int(content[:6], path, i + 1, "# / TYPES OF DATA", lo=0, hi=99)
            types = content[6:].split()
            if len(types) != n:
                raise FormatError(path, i + 1, "# / TYPES OF DATA", f"{n} types declared, "
                                  f"{len(types)} listed")
            attrs["data_types"] = " ".join(types)
        elif label in ("SYS / PCVS APPLIED", "PCVS APPLIED"):
            applied["pcv_applied"].append(" ".join(content.split()))
        elif label in ("SYS / DCBS APPLIED", "DCBS APPLIED"):
            applied["dcb_applied"].append(" ".join(content.split()))
    raise FormatError(path, None, "END OF HEADER", "the mandatory header record is missing")


class _Collected:
    """Raw fields of the records of one kind (AS or AR)."""

    def __init__(self):
        self.names: list[str] = []
        self.epoch_texts: list[str] = []
        self.line_nos: list[int] = []
        self.bias: list[str] = []
        self.sigma: list[str] = []


def _scan(lines: list[str], first: int, wide: bool, kinds: tuple[str, ...], path: Path
          ) -> dict[str, _Collected]:
    """Collect the records of the requested kinds, checking each record's value count."""
    name_stop, epoch_stop = (12, 39) if wide else (7, 34)
    out = {k: _Collected() for k in kinds}
    i = first
    n_lines = len(lines)
    while i < n_lines:
        text = lines[i]
        kind = text[:2]
        if kind not in _RECORD_TYPES:
            if text.strip():
                raise FormatError(path, i + 1, "record type", f"unexpected line "
                                  f"'{text[:20]}' (expected one of {', '.join(_RECORD_TYPES)})")
            i += 1
            continue
        rest = text[epoch_stop:].split()
        if not rest:
            raise FormatError(path, i + 1, "number of values", "the record is truncated")
        n_values = parse_int(rest[0], path, i + 1, "number of values")
        if not 1 <= n_values <= 6:
            raise FormatError(path, i + 1, "number of values", f"{n_values} is not in 1..6")
        values = rest[1:]
        n_cont = 0 if n_values <= 2 else (n_values - 2 + 3) // 4
        if i + n_cont >= n_lines:
            raise FormatError(path, n_lines, "continuation line", f"the record of line {i + 1} "
                              f"announces {n_values} values but the file ends: truncated")
        for j in range(1, n_cont + 1):
            values = values + lines[i + j].split()
        if n_cont == 0 and len(values) > n_values:
            # extra tokens after the announced values of a single-line record (peer files
            # write a trailing flag "E", or a sigma after a count of 1): the announced values
            # are unambiguous, the rest is ignored with a warning
            _LOG.warning("%s:%d: the record announces %d values and has %d; the first %d "
                         "are read", path, i + 1, n_values, len(values), n_values)
            values = values[:n_values]
        if len(values) != n_values:
            raise FormatError(path, i + 1 + n_cont, "number of values", f"the record announces "
                              f"{n_values} values but has {len(values)}")
        if kind in out:
            rec = out[kind]
            rec.names.append(text[3:name_stop].strip())
            rec.epoch_texts.append(text[name_stop:epoch_stop])
            rec.line_nos.append(i + 1)
            rec.bias.append(values[0])
            rec.sigma.append(values[1] if n_values > 1 else "")
        record_no = i + 1
        i += 1 + n_cont
        if kind not in _KINDS:
            # records leopod does not read (CR, DR, MS): numeric continuation lines that the
            # count does not announce (georust's USNO1.txt) are skipped with a warning
            while i < n_lines and lines[i][:1] == " " and lines[i].split() and \
                    all(is_number(t) for t in lines[i].split()):
                _LOG.warning("%s:%d: continuation line of the %s record of line %d not "
                             "announced by its count; skipped (record type not read)", path,
                             i + 1, kind, record_no)
                i += 1
    return out


def _epochs(recs: dict[str, _Collected], path: Path) -> dict[str, np.ndarray]:
    """ns epochs of every collected record, parsing each distinct epoch text once."""
    cache: dict[str, int] = {}
    out = {}
    for kind, rec in recs.items():
        ns = np.empty(len(rec.epoch_texts), dtype=np.int64)
        for k, (text, line_no) in enumerate(zip(rec.epoch_texts, rec.line_nos)):
            value = cache.get(text)
            if value is None:
                value = cache[text] = _epoch_ns(text, path, line_no)
            ns[k] = value
        out[kind] = ns
    return out


def _check_interval(interval_s: float, recs: dict, epochs: dict, kinds, path: Path) -> None:
    """The median epoch spacing is an epoch interval (io._fields "interval_s": up to 1e6 s,
    11.6 days); a larger one means a date of the file is wrong (e.g. one digit of a year
    changed): the error names the first record after the largest gap."""
    low, high = RANGES["interval_s"]
    if interval_s <= high:
        return
    ns = np.concatenate([epochs[k] for k in kinds])
    lines = np.concatenate([np.asarray(recs[k].line_nos, dtype=np.int64) for k in kinds])
    order = np.argsort(ns, kind="stable")
    k = order[int(np.argmax(np.diff(ns[order]))) + 1]
    raise FormatError(path, int(lines[k]), "epoch", f"the epochs are {interval_s:.3g} s apart "
                      f"(median), more than an epoch interval can be ({high:g} s): a wrong "
                      "date?")


def read_rinex_clock(path: str | Path, kinds: tuple[str, ...] = ("AS",), *,
                     gps_time: bool = False) -> xr.Dataset:
    """Read a RINEX clock file (2.00, 3.00-3.04; plain, .gz or .Z).

    Parameters
    ----------
    path : str or Path
        The clock file.
    kinds : tuple of str
        Record types to return: "AS" (satellite clocks) and/or "AR" (receiver clocks).
    gps_time : bool
        Convert the epochs from the file's ``TIME SYSTEM ID`` (RINEX clock 3.04; GPS when
        absent) to GPS time (:func:`leopod.time.scales.to_gps_time`: BDT, GAL, TAI, UTC);
        ``attrs["time_system"]`` becomes "GPS", ``attrs["time_system_file"]`` keeps the
        file's. False: epochs as written.

    Returns
    -------
    xarray.Dataset
        ``clk_s``/``clk_sigma_s`` (time, sv) [s] for "AS", ``clk_station_s`` /
        ``clk_station_sigma_s`` (time, station) [s] for "AR"; see the module docstring.

    Raises
    ------
    FormatError
        If the file does not follow the format (see the module docstring), or, with
        ``gps_time``, its time system (GLO, QZS, IRN) has no conversion to GPS time.
    ValueError
        If ``kinds`` is empty or names a type other than "AS" and "AR".
    """
    kinds = tuple(dict.fromkeys(kinds))
    if not kinds or any(k not in _KINDS for k in kinds):
        raise ValueError(f"kinds must be a non-empty subset of {_KINDS}, got {kinds}")
    path = Path(path)
    lines = read_lines(path)
    attrs, first, wide = _parse_header(lines, path)
    tsys_line = attrs.pop("_time_system_line", None)
    recs = _scan(lines, first, wide, kinds, path)
    epochs = _epochs(recs, path)
    all_ns = np.unique(np.concatenate([epochs[k] for k in kinds]))
    times = all_ns.astype("datetime64[ns]")
    if gps_time:
        times = time_system_to_gps(times, attrs["time_system"], path, tsys_line,
                                   "TIME SYSTEM ID")
        attrs.update(time_system_file=attrs["time_system"], time_system="GPS")
    data, coords = {}, {"time": times}
    for kind in kinds:
        rec = recs[kind]
        dim, var, sigma_var, what = _VAR_NAMES[kind]
        names, name_idx = np.unique(np.asarray(rec.names, dtype=str), return_inverse=True)
        t_idx = np.searchsorted(all_ns, epochs[kind])
        key = t_idx.astype(np.int64) * max(len(names), 1) + name_idx
        order = np.argsort(key, kind="stable")
        dup = np.nonzero(np.diff(key[order]) == 0)[0]
        if dup.size:
            k = order[dup[0] + 1]
            raise FormatError(path, rec.line_nos[k], "clock name", f"second {kind} record of "
                              f"'{rec.names[k]}' at the same epoch")
        bias = _to_float(rec.bias, rec.line_nos, [f"{n} clock bias" for n in rec.names], path)
        blank = np.isnan(bias)
        if blank.any():
            k = int(np.argmax(blank))
            raise FormatError(path, rec.line_nos[k], f"{rec.names[k]} clock bias",
                              "value is missing")
        sigma = _to_float(rec.sigma, rec.line_nos, [f"{n} clock sigma" for n in rec.names],
                          path, "clock_s")  # peers write negative sigmas (example1.txt)
        grids = []
        for values in (bias, sigma):
            grid = np.full((all_ns.size, names.size), np.nan)
            grid[t_idx, name_idx] = values
            grids.append(grid)
        coords[dim] = names
        data[var] = (("time", dim), grids[0], {"units": "s", "long_name": f"{what} bias"})
        data[sigma_var] = (("time", dim), grids[1],
                           {"units": "s", "long_name": f"{what} bias standard deviation"})
    main = epochs["AS"] if "AS" in kinds and epochs["AS"].size else all_ns
    steps = np.diff(np.unique(main))
    attrs["interval_s"] = float(np.median(steps)) / 1e9 if steps.size else 0.0
    _check_interval(attrs["interval_s"], recs, epochs, kinds, path)
    attrs["filename"] = path.name
    return xr.Dataset(data, coords=coords, attrs=attrs)

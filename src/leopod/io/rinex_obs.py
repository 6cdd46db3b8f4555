"""Reader of RINEX observation files (versions 2.xx, 3.00-3.05, 4.00).

Why one module of 633 lines: one reader of RINEX 2, 3 and 4 whose header parser and two
data-section scanners share the header state (observation types, which epoch flag 4 may redefine
mid-file); the writer is leopod.io.rinex_obs_write.

Specifications: "RINEX: The Receiver Independent Exchange Format Version 2.11" (Gurtner and
Estey, 2007/2012, with the 2.20 spaceborne-receiver extension for types such as ``LA``/``SA``),
"RINEX Version 3.04" (IGS/RTCM-SC104, 2018) and 3.05 / 4.00 (whose observation records are
those of 3.04). Compressed files (gzip, ``.Z``, Hatanaka/Compact RINEX) are opened by
:func:`leopod.io._text.read_lines`.

Dataset returned by :func:`read_rinex_obs` (and accepted by
:func:`leopod.io.rinex_obs_write.write_rinex_obs`)
-----------------------------------------------------------------------------------------
Coordinates
    ``time`` (time) datetime64[ns]: epoch readings as written, in the file's time system
    (``attrs["time_system"]``); file order, epochs of flag 0 or 1 only.
    ``sv`` (sv) str: satellite ``"G05"``, ``"C21"``, ... sorted. RINEX 2 blank system = GPS.
Observations, one float64 variable per observation code as written in the file
(RINEX 2: ``C1 P1 P2 L1 L2 LA SA S1 ...``; RINEX 3: ``C1C L1C C5P ...``), dims (time, sv),
NaN where the observation is absent:
    code/pseudorange ``C*``/``P*`` [m], units "m"; carrier phase ``L*`` [cycles], units "1";
    Doppler ``D*`` [Hz], units "Hz"; signal strength ``S*`` as written: units "dB-Hz" for
    RINEX 3/4, "1" (receiver-dependent) for RINEX 2; other types (``X`` channel ...) units "1".
    In mixed RINEX 3 files a code missing from one system's list is NaN for its satellites.
Indicators, for every observation code, int8, dims (time, sv):
    ``<code>_lli`` loss-of-lock indicator (0-7; 0 where blank), ``<code>_ssi`` signal strength
    indicator (1-9; 0 where blank). Both are -1 where the observation itself is absent
    (indicators written beside a blank observation are dropped).
Per epoch:
    ``epoch_flag`` (time) int8: 0 = OK, 1 = power failure since the previous epoch.
    ``rx_clock_offset_s`` (time) float64 [s]: receiver clock offset of the epoch record, NaN
    where not written.
Attributes
    ``rinex_version`` (float), ``file_system`` (header system letter, "M" = mixed),
    ``marker_name``, ``marker_number``, ``marker_type``, ``observer``, ``agency``,
    ``receiver_number``, ``receiver_type``, ``receiver_version``, ``antenna_number``,
    ``antenna_type`` (str, "" when absent), ``approx_position_xyz_m`` and
    ``antenna_delta_hen_m`` (str of three numbers in m, "" when absent), ``interval_s`` (float:
    INTERVAL record, else median epoch spacing, NaN for fewer than two epochs),
    ``time_system`` (TIME OF FIRST OBS: GPS, GLO, GAL, QZS, BDT or IRN; when blank the
    file system's own, RINEX 3.04 Table A2: BDT for C files, GAL for E, GLO for R, GPS for G
    and S, and GPS for mixed files, where the field is compulsory: a warning is logged),
    ``time_system_line`` (1-based line of TIME OF FIRST OBS that gave it, 0 = default),
    ``obs_types_<sys>`` (space-joined header codes per system; in RINEX 2 the one list repeated
    for every system present), ``n_events`` (epochs with flags 2-5, skipped with their special
    records), ``n_cycle_slip_epochs`` (flag-6 epochs, skipped), ``filename``.

Epoch flag 4 records that redefine the observation types (``# / TYPES OF OBSERV`` or
``SYS / # / OBS TYPES``) are applied to the following epochs. Observation scale factors
(RINEX 2.11 ``OBS SCALE FACTOR``, RINEX 3 ``SYS / SCALE FACTOR``: "factor to divide stored
observations with before use") are applied to the header's types: every value is the stored
one divided by its factor; ``attrs["scale_factors_applied"]`` lists them (``"LA/10 S1/100"``,
``"R L1C/1000"``, "" when none). A scale-factor record inside a flag-4 event is refused.
"""

from __future__ import annotations

import datetime as _dt
import logging
import math
import re
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.io._fields import YEARS, is_digits, is_number
from leopod.io._text import FormatError, fixed_float, parse_float, parse_int, read_lines

__all__ = ["read_rinex_obs"]

log = logging.getLogger(__name__)

_W = 16  # width of one observation field: F14.3 value, I1 LLI, I1 SSI
_V2_OBS_PER_LINE = 5
_V2_SATS_PER_LINE = 12
_SAT_SYSTEMS = "GRECJIS"
_OWN_TIME_SYSTEM = {"G": "GPS", "R": "GLO", "E": "GAL", "C": "BDT", "J": "QZS", "I": "IRN",
                    "S": "GPS", "M": "GPS"}
#: Time-system identifiers of 'TIME OF FIRST OBS' (RINEX 3.04 Table A2; RINEX 2.11 Table A1).
_TIME_SYSTEM_CODES = ("GPS", "GLO", "GAL", "QZS", "BDT", "IRN")
_TYPES_V2 = "# / TYPES OF OBSERV"
_TYPES_V3 = "SYS / # / OBS TYPES"
_SCALE_LABELS = ("OBS SCALE FACTOR", "SYS / SCALE FACTOR")
#: Observation codes: RINEX 2.11 Table A1 (type C/P/L/D/S, frequency 1-8; the 2.20 spaceborne
#: extension adds frequency "A", e.g. LA, SA) and RINEX 3.04 sec. 5.1 (type C/L/D/S, band
#: 1-9, attribute letter; "X" channel numbers).
_OBS_CODE = {2: re.compile(r"[CPLDS][1-8A]"),
             3: re.compile(r"[CLDS][1-9][A-Z]|X[0-9][A-Z0-9]")}
_XYZ_RECORDS = {"APPROX POSITION XYZ": "approx_position_xyz_m",
                "ANTENNA: DELTA H/E/N": "antenna_delta_hen_m"}

#: Character classes of an observation value field (F14.3): digits, blank, sign, point.
_VALUE_CHARS = np.zeros(256, dtype=bool)
_VALUE_CHARS[[ord(c) for c in "0123456789 .-+"]] = True
#: Indicator characters: blank (0) or one digit.
_INDICATOR_CHARS = np.zeros(256, dtype=bool)
_INDICATOR_CHARS[[ord(c) for c in "0123456789 "]] = True


# --------------------------------------------------------------------------------- header


@dataclass
class _Header:
    """What the data section needs from the header."""

    version: float
    system: str
    types: dict[str, tuple[str, ...]]  # RINEX 2: one key "" for every system
    attrs: dict
    end: int  # 0-based index of the first line after END OF HEADER
    scale: dict = None  # (system key, code) -> factor; system "" = every system (RINEX 2)


def _text_attrs(line: str, label: str) -> dict:
    """Free-text header records -> attributes (empty dict for other labels)."""
    if label == "MARKER NAME":
        return {"marker_name": line[:60].strip()}
    if label == "MARKER NUMBER":
        return {"marker_number": line[:20].strip()}
    if label == "MARKER TYPE":
        return {"marker_type": line[:20].strip()}
    if label == "OBSERVER / AGENCY":
        return {"observer": line[:20].strip(), "agency": line[20:60].strip()}
    if label == "REC # / TYPE / VERS":
        return {"receiver_number": line[:20].strip(), "receiver_type": line[20:40].strip(),
                "receiver_version": line[40:60].strip()}
    if label == "ANT # / TYPE":
        return {"antenna_number": line[:20].strip(), "antenna_type": line[20:40].strip()}
    return {}


def _three_floats(line: str, path, lineno: int, label: str) -> str:
    """Three F14.4 fields of a header record -> "x y z" string [m].

    A record whose numbers are shifted out of their columns (georinex's demo.10o) but are
    three numbers all the same is read from its blank-separated fields with a warning: the
    values are unambiguous and only informative (attributes)."""
    try:
        values = [fixed_float(line, 14 * k, 14 * (k + 1), path, lineno, label,
                              kind="position_m") for k in range(3)]
    except FormatError:
        tokens = line[:60].split()
        if len(tokens) != 3 or not all(is_number(t) for t in tokens):
            raise
        log.warning("%s:%d: %s not in its F14.4 columns; read from its 3 numbers", path,
                    lineno, label)
        values = [parse_float(t, path, lineno, label, kind="position_m") for t in tokens]
    return " ".join(f"{v:.4f}" for v in values)


def _parse_scale_factors(records: list[tuple[int, str]], types: dict, path) -> dict:
    """Observation scale factors of 'OBS SCALE FACTOR' (RINEX 2.11: I6 factor, I6 number of
    types, 8(4X,A2) types) or 'SYS / SCALE FACTOR' (RINEX 3.04: A1 system, 1X, I4 factor, 2X,
    I2 number of types, 12(1X,A3) types; continuation lines with the first 10 columns blank).

    "Factor to divide stored observations with before use"; no types listed (0 or blank)
    means every type of the system. Returns ``{(system key, code): factor}``.
    """
    groups: list[list] = []  # [system, factor, announced count, codes, line]
    for lineno, line in records:
        label = line[60:].strip()
        v2 = label == "OBS SCALE FACTOR"
        head = line[:12] if v2 else line[:10]
        if not head.strip():
            if not groups:
                raise FormatError(path, lineno, label, "continuation line without a "
                                  "preceding record giving the factor")
            groups[-1][3].extend(line[12 if v2 else 10:60].split())
            continue
        system = "" if v2 else line[:1]
        if not v2 and system not in _SAT_SYSTEMS:
            raise FormatError(path, lineno, label, f"unknown satellite system '{system}'")
        factor = parse_int(line[:6] if v2 else line[2:6], path, lineno, label, lo=1, hi=10**6)
        count_text = line[6:12] if v2 else line[8:10]
        count = parse_int(count_text, path, lineno, label, lo=0, hi=99) \
            if count_text.strip() else 0
        groups.append([system, factor, count, list(line[12 if v2 else 10:60].split()), lineno])
    out = {}
    for system, factor, count, codes, lineno in groups:
        if len(codes) != count:
            raise FormatError(path, lineno, records[0][1][60:].strip(), f"announces {count} "
                              f"observation types but lists {len(codes)}")
        known = types.get(system, ())
        for code in codes or known:
            if code not in known:
                raise FormatError(path, lineno, records[0][1][60:].strip(), f"'{code}' is "
                                  "not an observation type of the header")
            out[(system, code)] = factor
    return out


def _parse_obs_types(records: list[tuple[int, str]], path) -> dict[str, tuple[str, ...]]:
    """Parse '# / TYPES OF OBSERV' (RINEX 2) or 'SYS / # / OBS TYPES' (RINEX 3) records.

    Parameters
    ----------
    records : list of (int, str)
        (1-based line number, line) of the records, continuation lines included, in order.

    Returns
    -------
    dict
        System letter (``""`` for RINEX 2) -> tuple of observation codes.
    """
    groups: list[list] = []  # [key, announced count, codes, line number]
    for lineno, line in records:
        label = line[60:].strip()
        if label == _TYPES_V2:
            start, key, count_text, codes_text = line[:6].strip(), "", line[:6], line[6:60]
        else:
            start, key, count_text, codes_text = line[:1].strip(), line[:1], line[3:6], line[7:60]
        if start:
            count = parse_int(count_text, path, lineno, label)
            groups.append([key, count, [], lineno])
        elif not groups:
            raise FormatError(path, lineno, label, "continuation line without a preceding "
                              "record giving the number of observation types")
        groups[-1][2].extend(codes_text.split())
    label = records[0][1][60:].strip() if records else _TYPES_V3
    width = 2 if label == _TYPES_V2 else 3
    types = {}
    for key, count, codes, lineno in groups:
        if len(codes) != count:
            raise FormatError(path, lineno, label, f"announces {count} observation types "
                              f"but lists {len(codes)}")
        bad = [c for c in codes if not _OBS_CODE[width].fullmatch(c)]
        if bad:
            raise FormatError(path, lineno, label, f"'{bad[0]}' is not an observation code")
        if width == 3 and key not in _SAT_SYSTEMS:
            raise FormatError(path, lineno, label, f"unknown satellite system '{key}'")
        types[key] = tuple(codes)
    return types


def _time_system(line: str, path, lineno: int, label: str) -> dict:
    """Time system of a 'TIME OF FIRST OBS' record (A3 at columns 49-51, RINEX 2.11 and
    3.04 Table A2) -> ``{"time_system", "time_system_line"}``; empty dict if blank."""
    code = line[48:51].strip()
    if not code:
        return {}
    if code not in _TIME_SYSTEM_CODES:
        raise FormatError(path, lineno, f"{label} time system", f"'{code}' is not a RINEX "
                          f"time system ({', '.join(_TIME_SYSTEM_CODES)})")
    return {"time_system": code, "time_system_line": lineno}


def _parse_header(lines: list[str], path) -> _Header:
    """Read the header section (up to END OF HEADER)."""
    first = lines[0] if lines else ""
    if first[60:].strip() != "RINEX VERSION / TYPE":
        raise FormatError(path, 1, "RINEX VERSION / TYPE", "the first line is not the "
                          "'RINEX VERSION / TYPE' record: not a RINEX file")
    version = fixed_float(first, 0, 9, path, 1, "RINEX VERSION / TYPE")
    if not 2.0 <= version < 5.0:
        raise FormatError(path, 1, "RINEX VERSION / TYPE", f"unsupported version {version}")
    if first[20:21] != "O":
        raise FormatError(path, 1, "RINEX VERSION / TYPE", f"file type '{first[20:21]}' is "
                          "not an observation file ('O')")
    system = first[40:41].strip() or "G"
    types_label = _TYPES_V2 if version < 3 else _TYPES_V3
    attrs = {key: "" for key in ("marker_name", "marker_number", "marker_type", "observer",
                                 "agency", "receiver_number", "receiver_type",
                                 "receiver_version", "antenna_number", "antenna_type",
                                 "approx_position_xyz_m", "antenna_delta_hen_m")}
    attrs.update(rinex_version=float(version), file_system=system)
    type_records, scale_records = [], []
    for i in range(1, len(lines)):
        line, lineno = lines[i], i + 1
        label = line[60:].strip()
        if label == "END OF HEADER":
            break
        if label == types_label:
            type_records.append((lineno, line))
        elif label in _XYZ_RECORDS:
            attrs[_XYZ_RECORDS[label]] = _three_floats(line, path, lineno, label)
        elif label == "INTERVAL":
            attrs["interval_s"] = fixed_float(line, 0, 10, path, lineno, label)
        elif label == "TIME OF FIRST OBS":
            attrs.update(_time_system(line, path, lineno, label))
        elif label in _SCALE_LABELS:
            scale_records.append((lineno, line))
        else:
            attrs.update(_text_attrs(line, label))
    else:
        raise FormatError(path, None, "END OF HEADER", "the header has no 'END OF HEADER' "
                          "record (file truncated or not RINEX)")
    if not type_records:
        raise FormatError(path, None, types_label, f"the header has no '{types_label}' record")
    if "time_system" not in attrs:
        attrs["time_system"] = _OWN_TIME_SYSTEM.get(system, "GPS")
        attrs["time_system_line"] = 0
        if system == "M":
            log.warning("%s: mixed file without a time system in 'TIME OF FIRST OBS' (the "
                        "field is compulsory in mixed files, RINEX 3.04 Table A2): GPS "
                        "time assumed", path)
    types = _parse_obs_types(type_records, path)
    scale = _parse_scale_factors(scale_records, types, path)
    scaled = {f"{k[0]}{' ' if k[0] else ''}{k[1]}": f for k, f in scale.items() if f != 1}
    attrs["scale_factors_applied"] = " ".join(f"{k}/{f}" for k, f in scaled.items())
    return _Header(float(version), system, types, attrs, i + 1, scale)


# ------------------------------------------------------------------------------ data section


@dataclass
class _Scan:
    """Everything collected while walking through the data section."""

    base: list  # datetime of each epoch, whole minutes
    sec_ns: list  # seconds of the minute [ns]
    flag: list
    clock: list
    rec_epoch: list  # per kept satellite record: epoch index
    rec_sv: list  # satellite id
    rec_line: list  # 0-based index of the record's first line
    rec_group: list  # index into groups
    groups: dict  # observation-code tuple -> group index
    texts: list  # per group: list of fixed-width record texts
    n_events: int = 0
    n_slip_epochs: int = 0


def _epoch_time(line: str, lineno: int, path, v2: bool) -> tuple[_dt.datetime, int]:
    """Epoch date of an epoch record -> (datetime to the minute, seconds in ns)."""
    cols = ((1, 3), (4, 6), (7, 9), (10, 12), (13, 15), (15, 26)) if v2 else \
        ((2, 6), (7, 9), (10, 12), (13, 15), (16, 18), (18, 29))
    names = ("year", "month", "day", "hour", "minute")
    y, mo, d, h, mi = (parse_int(line[a:b], path, lineno, n) for (a, b), n in zip(cols, names))
    sec = fixed_float(line, *cols[5], path, lineno, "second")
    if v2:
        y += 2000 if y < 80 else 1900
    if not YEARS[0] <= y <= YEARS[1]:  # the contract's years, inside datetime64[ns]
        raise FormatError(path, lineno, "year", f"{y} is outside {YEARS[0]}-{YEARS[1]}")
    for value, low, high, name in ((mo, 1, 12, "month"), (h, 0, 23, "hour"),
                                   (mi, 0, 59, "minute")):
        if not low <= value <= high:
            raise FormatError(path, lineno, name, f"{value} is out of range {low}-{high}")
    if not 0.0 <= sec < 61.0:
        raise FormatError(path, lineno, "second", f"{sec} is out of range 0-60.9999999")
    try:
        base = _dt.datetime(y, mo, d, h, mi)
    except ValueError:
        raise FormatError(path, lineno, "day", f"{y:04d}-{mo:02d}-{d:02d} is not a date") \
            from None
    return base, round(sec * 1e9)


def _epoch_flag(line: str, col: int, lineno: int, path) -> int:
    """The epoch flag (0-6) at 0-based column ``col``."""
    flag = parse_int(line[col:col + 1], path, lineno, "epoch flag")
    if flag > 6:
        raise FormatError(path, lineno, "epoch flag", f"{flag} is not an epoch flag (0-6)")
    return flag


def _count(text: str, path, lineno: int) -> int:
    """The satellite (or special-record) count of an epoch record: an integer >= 0 (a
    negative count would make the scanner stand still)."""
    count = parse_int(text, path, lineno, "number of satellites")
    if count < 0:
        raise FormatError(path, lineno, "number of satellites", f"{count} is negative")
    return count


class _SatIds:
    """Normalise satellite identifiers ("G 5", " 5", "G05" -> "G05"), with a cache."""

    def __init__(self, path, v2: bool):
        self.path, self.v2, self.cache = path, v2, {}

    def __call__(self, raw: str, lineno: int) -> str:
        sv = self.cache.get(raw)
        if sv is None:
            if len(raw) != 3:
                raise FormatError(self.path, lineno, "satellite",
                                  f"'{raw}' is not a satellite identifier")
            system = raw[0] if raw[0] != " " or not self.v2 else "G"
            prn = raw[1:3]
            if system not in _SAT_SYSTEMS or len(raw) != 3 or not is_digits(raw[2]) \
                    or not (is_digits(raw[1]) or raw[1] == " "):
                raise FormatError(self.path, lineno, "satellite",
                                  f"'{raw}' is not a satellite identifier")
            sv = self.cache[raw] = f"{system}{int(prn):02d}"
        return sv


def _truncated(path, lineno: int, n_lines: int, what: str):
    return FormatError(path, lineno, "epoch record", f"the file ends after line {n_lines} "
                       f"in the middle of this epoch record ({what}); truncated file?")


def _skip_event(lines, i: int, count: int, flag: int, path, types: dict, v2: bool) -> int:
    """Skip an event (flags 2-5) and its special records; apply header changes of flag 4.

    Returns the index of the line after the event.
    """
    end = i + 1 + count
    if end > len(lines):
        raise _truncated(path, i + 1, len(lines), f"{count} special records announced")
    label = _TYPES_V2 if v2 else _TYPES_V3
    if flag == 4:
        for k in range(i + 1, end):
            if lines[k][60:].strip() in _SCALE_LABELS:
                raise FormatError(path, k + 1, lines[k][60:].strip(), "scale factors "
                                  "redefined inside the data section are not supported")
        records = [(k + 1, lines[k]) for k in range(i + 1, end) if lines[k][60:].strip() == label]
        if records:
            types.update(_parse_obs_types(records, path))
            log.info("%s: observation types redefined at line %d", path, i + 1)
    return end


def _add_record(scan: _Scan, codes: tuple, epoch: int, sv: str, first: int, text: str):
    """Store one satellite record (its fixed-width observation text)."""
    group = scan.groups.get(codes)
    if group is None:
        group = scan.groups[codes] = len(scan.texts)
        scan.texts.append([])
    scan.texts[group].append(text)
    scan.rec_epoch.append(epoch)
    scan.rec_sv.append(sv)
    scan.rec_line.append(first)
    scan.rec_group.append(group)


def _add_epoch(scan: _Scan, line: str, lineno: int, path, flag: int, v2: bool) -> int:
    """Store the time, flag and clock of an epoch record; return the epoch index."""
    base, sec_ns = _epoch_time(line, lineno, path, v2)
    clock = fixed_float(line, *((68, 80) if v2 else (41, 56)), path, lineno,
                        "receiver clock offset", allow_blank=True)
    scan.base.append(base)
    scan.sec_ns.append(sec_ns)
    scan.flag.append(flag)
    scan.clock.append(clock)
    return len(scan.base) - 1


def _scan_v2(lines: list[str], hdr: _Header, keep, path) -> _Scan:
    """Walk through a RINEX 2 data section."""
    scan = _Scan([], [], [], [], [], [], [], [], {}, [])
    sat_id = _SatIds(path, True)
    types = dict(hdr.types)
    n, i = len(lines), hdr.end
    while i < n:
        line = lines[i]
        if not line.strip():
            i += 1
            continue
        lineno = i + 1
        flag = _epoch_flag(line, 28, lineno, path)
        count = _count(line[29:32], path, lineno)
        if 2 <= flag <= 5:
            scan.n_events += 1
            i = _skip_event(lines, i, count, flag, path, types, True)
            continue
        n_epoch_lines = 1 + max(count - 1, 0) // _V2_SATS_PER_LINE
        codes = types[""]
        per_sat = -(-len(codes) // _V2_OBS_PER_LINE)
        if i + n_epoch_lines + count * per_sat > n:
            raise _truncated(path, lineno, n, f"{count} satellites announced")
        sat_text = "".join(lines[k][32:68].ljust(36) for k in range(i, i + n_epoch_lines))
        raw_ids = [sat_text[3 * k:3 * k + 3] for k in range(count)]
        if any(not r.strip() for r in raw_ids) or sat_text[3 * count:].strip():
            listed = len(sat_text.split())
            raise FormatError(path, lineno, "number of satellites", f"the epoch announces "
                              f"{count} satellites but lists {listed}")
        first = i + n_epoch_lines
        i = first + count * per_sat
        if flag == 6:
            scan.n_slip_epochs += 1
            continue
        epoch = _add_epoch(scan, line, lineno, path, flag, True)
        width = _W * len(codes)
        for k, raw in enumerate(raw_ids):
            sv = sat_id(raw, lineno)
            if keep is not None and sv[0] not in keep:
                continue
            start = first + k * per_sat
            text = "".join(lines[j][:80].ljust(80) for j in range(start, start + per_sat))
            _add_record(scan, codes, epoch, sv, start, text[:width])
    return scan


def _scan_v3(lines: list[str], hdr: _Header, keep, path) -> _Scan:
    """Walk through a RINEX 3/4 data section."""
    scan = _Scan([], [], [], [], [], [], [], [], {}, [])
    sat_id = _SatIds(path, False)
    types = dict(hdr.types)
    n, i = len(lines), hdr.end
    while i < n:
        line = lines[i]
        if not line.strip():
            i += 1
            continue
        lineno = i + 1
        if line[0] != ">":
            raise FormatError(path, lineno, "epoch record", "expected an epoch record "
                              "starting with '>' (more satellite records than announced?)")
        flag = _epoch_flag(line, 31, lineno, path)
        count = _count(line[32:35], path, lineno)
        if 2 <= flag <= 5:
            scan.n_events += 1
            i = _skip_event(lines, i, count, flag, path, types, False)
            continue
        if i + 1 + count > n:
            raise _truncated(path, lineno, n, f"{count} satellites announced")
        for k in range(i + 1, i + 1 + count):
            if lines[k][:1] == ">":
                raise FormatError(path, k + 1, "number of satellites", f"the epoch at line "
                                  f"{lineno} announces {count} satellites but only "
                                  f"{k - i - 1} records follow")
        first, i = i + 1, i + 1 + count
        if flag == 6:
            scan.n_slip_epochs += 1
            continue
        epoch = _add_epoch(scan, line, lineno, path, flag, False)
        for k in range(first, i):
            rec = lines[k]
            sv = sat_id(rec[:3], k + 1)
            if keep is not None and sv[0] not in keep:
                continue
            codes = types.get(sv[0])
            if codes is None:
                raise FormatError(path, k + 1, "satellite", f"{sv}: system '{sv[0]}' has no "
                                  f"'{_TYPES_V3}' record in the header")
            width = _W * len(codes)
            _add_record(scan, codes, epoch, sv, k, rec[3:3 + width].ljust(width))
    return scan


def _bad_value(path, lineno: int, code: str, sv: str, text: str):
    """FormatError for a non-numeric observation field."""
    s = text.strip()
    what = "is not a finite number" if s.lower().lstrip("+-") in ("nan", "inf", "infinity") \
        else "is not a number"
    return FormatError(path, lineno, code, f"satellite {sv}: '{s}' {what}")


def _parse_block(texts: list[str], codes: tuple, lines0: np.ndarray, svs: list, path, v2: bool):
    """Decode the fixed-width observation texts of one group of records at once.

    Parameters
    ----------
    texts : list of str, each ``16 * len(codes)`` characters
    codes : tuple of str, the observation codes of the columns
    lines0 : ndarray of int, 0-based first line of each record (for error messages)
    svs : list of str, satellite of each record (for error messages)

    Returns
    -------
    values : ndarray (nrec, ncode) float64, NaN where blank
    lli, ssi : ndarray (nrec, ncode) int8, -1 where the value is blank
    """
    nrec, ncode = len(texts), len(codes)
    raw = np.frombuffer("".join(texts).encode("latin-1"), dtype=np.uint8)
    raw = raw.reshape(nrec, ncode, _W)

    def where(r, j):  # 1-based line of field j of record r
        return int(lines0[r]) + 1 + (j // _V2_OBS_PER_LINE if v2 else 0)

    value_chars = raw[:, :, :14]
    blank = (value_chars == 32).all(axis=2)
    bad = ~_VALUE_CHARS[value_chars].all(axis=2)
    if bad.any():
        r, j = np.argwhere(bad)[0]
        text = value_chars[r, j].tobytes().decode("latin-1")
        raise _bad_value(path, where(r, j), codes[j], svs[r], text)
    fields = np.ascontiguousarray(value_chars).view("S14")[:, :, 0]
    values = np.full((nrec, ncode), np.nan)
    present = ~blank
    try:
        values[present] = fields[present].astype(np.float64)
    except ValueError:  # e.g. "12 3.4" or "1.2.3": find the field for the message
        for r, j in np.argwhere(present):
            try:
                float(fields[r, j])
            except ValueError:
                raise _bad_value(path, where(r, j), codes[j], svs[r],
                                 fields[r, j].decode("latin-1")) from None
    indicators = []
    for col, name in ((14, "LLI"), (15, "SSI")):
        chars = raw[:, :, col]
        bad = ~_INDICATOR_CHARS[chars]
        if bad.any():
            r, j = np.argwhere(bad)[0]
            raise FormatError(path, where(r, j), f"{codes[j]} {name}", f"satellite {svs[r]}: "
                              f"'{chr(chars[r, j])}' is not an indicator digit")
        ind = np.where(chars == 32, 0, chars.astype(np.int16) - 48).astype(np.int8)
        ind[blank] = -1
        indicators.append(ind)
    return values, indicators[0], indicators[1]


def _apply_scale(values: np.ndarray, codes: tuple, svs: list, scale: dict, v2: bool) -> None:
    """Divide the stored values by their scale factor (in place)."""
    if not scale:
        return
    systems = np.array([sv[0] for sv in svs])
    for j, code in enumerate(codes):
        if v2:
            factor = scale.get(("", code), 1)
            if factor != 1:
                values[:, j] /= factor
            continue
        for system in set(systems.tolist()):
            factor = scale.get((system, code), 1)
            if factor != 1:
                values[systems == system, j] /= factor


def _obs_attrs(code: str, v2: bool) -> dict:
    """units and long_name of an observation variable."""
    kind = code[0]
    if kind in "CP":
        return {"units": "m", "long_name": f"pseudorange {code} [m]"}
    if kind == "L":
        return {"units": "1", "long_name": f"carrier phase {code} [cycles]"}
    if kind == "D":
        return {"units": "Hz", "long_name": f"Doppler {code} [Hz]"}
    if kind == "S":
        if v2:
            return {"units": "1", "long_name": f"signal strength {code} as written by the "
                                               "receiver (receiver-dependent units)"}
        return {"units": "dB-Hz", "long_name": f"carrier-to-noise density {code} [dB-Hz]"}
    return {"units": "1", "long_name": f"observation {code} as written"}


def _check_unique(ti: np.ndarray, si: np.ndarray, nsv: int, scan: _Scan, path) -> None:
    """A satellite must not appear twice in one epoch."""
    key = ti.astype(np.int64) * nsv + si
    order = np.argsort(key, kind="stable")
    dup = np.nonzero(np.diff(key[order]) == 0)[0]
    if dup.size:
        r = order[dup[0] + 1]
        raise FormatError(path, scan.rec_line[r] + 1, "satellite",
                          f"{scan.rec_sv[r]} appears twice in the same epoch")


def _build_dataset(scan: _Scan, hdr: _Header, keep, path) -> xr.Dataset:
    """Assemble the Dataset from the scanned records (``keep``: kept systems or None)."""
    v2 = hdr.version < 3
    times = np.array(scan.base, dtype="datetime64[ns]") + \
        np.array(scan.sec_ns, dtype="timedelta64[ns]")
    svs = sorted(set(scan.rec_sv))
    sv_index = {sv: k for k, sv in enumerate(svs)}
    nt, ns = len(times), len(svs)
    ti = np.array(scan.rec_epoch, dtype=np.int64)
    si = np.array([sv_index[sv] for sv in scan.rec_sv], dtype=np.int64)
    _check_unique(ti, si, ns, scan, path)
    group_of = np.array(scan.rec_group, dtype=np.int64)
    rec_line = np.array(scan.rec_line, dtype=np.int64)

    all_codes = [c for key, types in hdr.types.items()
                 if keep is None or key in keep or key == "" for c in types]
    all_codes += [c for codes in scan.groups for c in codes]
    all_codes = list(dict.fromkeys(all_codes))
    values = {c: np.full((nt, ns), np.nan) for c in all_codes}
    lli = {c: np.full((nt, ns), -1, dtype=np.int8) for c in all_codes}
    ssi = {c: np.full((nt, ns), -1, dtype=np.int8) for c in all_codes}
    for codes, g in scan.groups.items():
        rows = np.nonzero(group_of == g)[0]
        block_svs = [scan.rec_sv[r] for r in rows]
        v, li, ss = _parse_block(scan.texts[g], codes, rec_line[rows], block_svs, path, v2)
        _apply_scale(v, codes, block_svs, hdr.scale, v2)
        t, s = ti[rows], si[rows]
        for j, code in enumerate(codes):
            values[code][t, s] = v[:, j]
            lli[code][t, s] = li[:, j]
            ssi[code][t, s] = ss[:, j]

    data = {}
    for code in all_codes:
        data[code] = (("time", "sv"), values[code], _obs_attrs(code, v2))
        data[f"{code}_lli"] = (("time", "sv"), lli[code], {
            "units": "1", "long_name": f"loss of lock indicator of {code} (bit 0: lost lock, "
            "bit 1: half-wavelength/opposite wavelength factor, bit 2: half-cycle ambiguity "
            "or anti-spoofing; 0 = blank, -1 = no observation)"})
        data[f"{code}_ssi"] = (("time", "sv"), ssi[code], {
            "units": "1", "long_name": f"signal strength indicator of {code} (1 = minimum, "
            "9 = maximum; 0 = blank or unknown, -1 = no observation)"})
    data["epoch_flag"] = (("time",), np.array(scan.flag, dtype=np.int8), {
        "units": "1", "long_name": "epoch flag (0 = OK, 1 = power failure since the "
                                   "previous epoch)"})
    data["rx_clock_offset_s"] = (("time",), np.array(scan.clock, dtype=np.float64), {
        "units": "s", "long_name": "receiver clock offset from the epoch record"})
    coords = {"time": ("time", times), "sv": ("sv", np.array(svs, dtype=str))}
    return xr.Dataset(data, coords=coords, attrs=_final_attrs(scan, hdr, times, svs, path))


def _final_attrs(scan: _Scan, hdr: _Header, times: np.ndarray, svs: list, path) -> dict:
    """Header attributes plus interval, observation-type lists and counters."""
    attrs = dict(hdr.attrs)
    if "interval_s" not in attrs:
        steps = np.diff(times).astype("timedelta64[ns]").astype(np.int64)
        attrs["interval_s"] = float(np.median(steps)) * 1e-9 if steps.size else math.nan
    if hdr.version < 3:
        systems = sorted({sv[0] for sv in svs} | ({hdr.system} - {"M"}))
        attrs.update({f"obs_types_{s}": " ".join(hdr.types[""]) for s in systems})
    else:
        attrs.update({f"obs_types_{s}": " ".join(c) for s, c in hdr.types.items()})
    attrs.update(n_events=scan.n_events, n_cycle_slip_epochs=scan.n_slip_epochs,
                 filename=Path(path).name)
    if np.any(np.diff(times) <= np.timedelta64(0, "ns")):
        log.warning("%s: epochs are not in strictly increasing time order", path)
    return attrs


def _check_last_line(lines, hdr: _Header, path) -> None:
    """A file without a final line end whose last observation line ends inside an F14.3 value
    (RINEX 2.11/3.04: values right-justified in 14 columns, then LLI and SSI) was cut inside
    that number, which would be read with a wrong value."""
    if getattr(lines, "final_newline", True) or len(lines) <= hdr.end:
        return
    last = lines[-1].rstrip()
    v3 = hdr.version >= 3
    if not last or (v3 and last[0] == ">"):
        return
    offset = 3 if v3 else 0
    if (len(last) - offset) % _W in range(1, 14):
        raise FormatError(path, len(lines), "observation", "the file ends inside an F14.3 "
                          "observation value (no line end after it): cut short?")


def read_rinex_obs(path: str | Path, systems: Iterable[str] | None = None) -> xr.Dataset:
    """Read a RINEX 2.10-2.20, 3.0x or 4.00 observation file (plain, .gz, .Z or Hatanaka).

    Parameters
    ----------
    path : str or Path
        The observation file.
    systems : iterable of str, optional
        System letters to keep (e.g. ``"GC"`` or ``["G"]``); records of other systems are
        skipped without being decoded. Default: all.

    Returns
    -------
    xarray.Dataset
        Dims (time, sv); observations in m (code), cycles (phase), Hz (Doppler), signal
        strength as written; LLI/SSI indicators; see the module docstring for the schema.

    Raises
    ------
    FormatError
        Missing mandatory header record, not an observation file, bad epoch record,
        satellite count not matching, non-numeric or non-finite observation, truncation in
        the middle of an epoch record.
    """
    keep = None
    if systems is not None:
        keep = set(systems)
        unknown = keep - set(_SAT_SYSTEMS)
        if unknown:
            raise ValueError(f"unknown satellite systems {sorted(unknown)} (known: "
                             f"{', '.join(_SAT_SYSTEMS)})")
    lines = read_lines(path)
    hdr = _parse_header(lines, path)
    _check_last_line(lines, hdr, path)
    scan = (_scan_v2 if hdr.version < 3 else _scan_v3)(lines, hdr, keep, path)
    ds = _build_dataset(scan, hdr, keep, path)
    log.debug("%s: %d epochs, %d satellites", path, ds.sizes["time"], ds.sizes["sv"])
    return ds

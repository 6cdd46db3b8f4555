"""ILRS Consolidated laser Ranging Data (CRD): read normal points and full-rate ranges.

Why one module of 557 lines: one reader of both CRD versions, whose record scan and vectorised
column assembly share the session state; a sixth of it is this docstring with its schema table
(the writer is leopod.io.crd_write).

Specification: "Consolidated Laser Ranging Data Format (CRD) Version 1.01" (Ricklefs & Moore,
ILRS 2009) and "ILRS CRD 2.01" (Ricklefs et al., ILRS 2019/2021). Version 2 records are
free format (fields separated by blanks, ``na`` for "not available", record identifiers in
either case); version 1 records are fixed format but their fields are also separated by blanks,
so both versions are read by splitting at blanks. Station and target names therefore must not
contain blanks (true of all ILRS names).

Structure of a file (several sessions, stations and satellites may follow each other)::

    H1 format header   H2 station   H3 target   H4 session (pass) header   [H5 prediction]
    C0..C7 configuration   10/11/12 ranges   20/21 meteorology   30 angles   40/41/42
    calibration   50 statistics   60 compatibility   00 comments   9x user records
    H8 end of session ... H9 end of file

Every H4 starts a new session (``pass_id`` 0, 1, ... in file order); H2/H3/C0 values stay in
force until replaced or until the next H1. Records 00 and 90-99 are skipped; any other unknown
record identifier is an error. Records that this reader does not use (H5, C1-C7, 12, 21, 30,
40-42, 50, 60) are only checked for their number of fields.

Epochs. A record's epoch is the H4 start *date* plus its seconds of day. Passes cross
midnight without a date change in the records, so every epoch is put into the 24-h window
[H4 start - 10 h, H4 start + 14 h) by adding or removing one day (meteorological and
calibration records may precede the session start; sessions are shorter than 14 h). The
station epoch time scale (H2 field 6: 3 = UTC(USNO), 4 = UTC(GPS), 7 = UTC(BIH/BIPM),
10 = UTC(station time scale); note it is in H2, not H4) is stored per point in ``time_scale``;
all are realisations of UTC, so ``attrs["time_system"] = "UTC"``. Other codes are an error.

Sessions not closed by H8 (a file cut after a complete record, or concatenated files) are
kept and a warning is logged; a record cut in the middle (too few fields) is an error.

Dataset schema returned by :func:`read_crd` (dimension ``point`` in file order; record 11 for
``record="normal_point"``, record 10 for ``record="full_rate"``):

==========================  ==========  =====================================================
variable                    units       meaning
==========================  ==========  =====================================================
time (coordinate)           -           epoch of the range (datetime64[ns], UTC, see above)
tof_s                       s           two-way time of flight as written (record 10/11)
range_m                     m           convenience only: tof_s * c / 2, c = 299792458 m/s,
                                        no correction of any kind applied
pass_id                     1           index of the H4 session in the file (0-based)
data_type                   1           H4 data type: 0 full rate, 1 normal points,
                                        2 sampled engineering
station                     1           CDP pad ID, 4 digits (H2), e.g. "7839"
station_name                1           station name (H2), e.g. "GRZL"
system_number               1           CDP system number (H2)
occupancy_number            1           CDP occupancy sequence number (H2)
time_scale                  1           station epoch time scale code (H2)
satellite                   1           target name (H3), e.g. "lageos1"
ilrs_id                     1           ILRS satellite id, 7 digits YYXXXPP (H3)
cospar_id                   1           COSPAR id derived from ilrs_id, e.g. "1976-039A"
                                        ("" when ilrs_id does not encode one)
norad_id                    1           NORAD catalogue number (H3), -1 if "na"
data_release                1           H4 data release flag
range_type                  1           H4 range type: 0 no ranges, 1 one-way, 2 two-way,
                                        3 receive times only, 4 mixed
refraction_applied          1           H4 flag (0/1): tropospheric refraction applied
com_applied                 1           H4 flag: centre-of-mass correction applied
amplitude_corr_applied      1           H4 flag: receive amplitude correction applied
station_delay_applied       1           H4 flag: station system delay applied
spacecraft_delay_applied    1           H4 flag: spacecraft system delay applied
data_quality_alert          1           H4 data quality alert indicator
system_config               1           system configuration id of the record
wavelength_nm               nm          transmit wavelength of that configuration (C0),
                                        NaN if no C0 names it
epoch_event                 1           epoch event indicator (record 10/11 field 4)
detector_channel            1           detector channel (-1 if "na")
pressure_hpa                hPa         surface pressure   } record 20, linear in time
temperature_k               K           surface temperature} between the session's records,
humidity_pct                percent     relative humidity  } nearest value outside, NaN if none
-- record 11 only --
np_window_s                 s           normal point window length
n_raw                       1           number of raw ranges in the normal point (-1 if "na")
bin_rms_s                   s           bin RMS from the mean of the raw ranges (ps -> s)
bin_skew                    1           bin skew
bin_kurtosis                1           bin kurtosis
bin_peak_minus_mean_s       s           bin peak - mean (ps -> s)
return_rate_pct             percent     return rate
snr                         1           signal-to-noise ratio (CRD 2 only, NaN otherwise)
-- record 10 only --
filter_flag                 1           0 unknown, 1 noise, 2 data
stop_number                 1           stop number (multiple-stop systems)
receive_amplitude           1           receive amplitude (-1 if "na")
transmit_amplitude          1           transmit amplitude (CRD 2 only, -1 otherwise)
==========================  ==========  =====================================================

Optional numeric fields written ``na`` become NaN (floats) or -1 (integers); version-1
placeholders such as ``-1.000`` are kept as written. attrs: ``format``, ``crd_versions``
(e.g. "1" or "1,2"), ``record``, ``time_system``, ``time_scale_codes``, ``n_sessions``.

:func:`leopod.io.crd_write.write_crd` writes normal points.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.constants import C_LIGHT_M_S
from leopod.io._fields import epoch_ns, integers, is_digits, numbers, require_line_end
from leopod.io._text import FormatError, parse_float, parse_int, read_lines

__all__ = ["ilrs_id_to_cospar", "read_crd"]

_LOG = logging.getLogger(__name__)

_NS = 1_000_000_000
_DAY_NS = 86_400 * _NS
_BEFORE_START_NS = 10 * 3600 * _NS
_AFTER_START_NS = _DAY_NS - _BEFORE_START_NS
_NA = ("na", "-na")

#: Station epoch time scales (H2 field 6), CRD 1.01 and 2.01.
TIME_SCALES = {3: "UTC(USNO)", 4: "UTC(GPS)", 7: "UTC(BIH/BIPM)", 10: "UTC(station time scale)"}

#: Minimum number of fields after the record identifier (the CRD 1.01 layout; CRD 2 only
#: appends fields). Record 42 exists in CRD 2 only; its sod, tof, system and target ids are
#: required.
_MIN_FIELDS = {
    "H1": 6, "H2": 5, "H3": 6, "H4": 21, "H5": 5, "H8": 0, "H9": 0,
    "C0": 3, "C1": 9, "C2": 13, "C3": 7, "C4": 10, "C5": 6, "C6": 11, "C7": 9,
    "10": 8, "11": 12, "12": 6, "20": 5, "21": 8, "30": 6,
    "40": 15, "41": 15, "42": 4, "50": 6, "60": 3,
}
_SESSION_RECORDS = ("10", "11", "20")
_RECORD_OF = {"normal_point": "11", "full_rate": "10"}
_COSPAR_LETTERS = "ABCDEFGHJKLMNPQRSTUVWXYZ"  # COSPAR piece letters skip I and O


@dataclass
class _Session:
    """One H4 session with the header values that apply to its records."""

    index: int
    line: int
    station: dict
    target: dict
    data_type: int
    start_ns: int
    day_ns: int
    release: int
    flags: tuple
    range_type: int
    quality: int
    wavelength_nm: dict = field(default_factory=dict)
    closed: bool = False


@dataclass
class _Scan:
    """Everything collected in one pass over the lines."""

    sessions: list = field(default_factory=list)
    rows: dict = field(default_factory=lambda: {r: [] for r in _SESSION_RECORDS})
    versions: set = field(default_factory=set)


def ilrs_id_to_cospar(ilrs_id: str) -> str:
    """COSPAR international designator of an ILRS satellite id.

    Parameters
    ----------
    ilrs_id : str
        ILRS id ``YYXXXPP`` (launch year, launch number, piece), e.g. ``"7603901"``.

    Returns
    -------
    str
        e.g. ``"1976-039A"``; ``""`` if the id does not encode a launch (piece 00, not 7 digits).
        Years 57-99 are 19YY, 00-56 are 20YY; pieces 1-24 are A-Z without I and O, then AA...
    """
    s = str(ilrs_id).strip()
    if len(s) != 7 or not is_digits(s) or int(s[5:]) == 0:
        return ""
    yy, launch, piece = int(s[:2]), s[2:5], int(s[5:])
    year = 1900 + yy if yy >= 57 else 2000 + yy
    letters = ""
    while piece > 0:
        piece, rem = divmod(piece - 1, len(_COSPAR_LETTERS))
        letters = _COSPAR_LETTERS[rem] + letters
    return f"{year}-{launch}{letters}"


# ----------------------------------------------------------------------------------- reading
def read_crd(path: str | Path, record: str = "normal_point") -> xr.Dataset:
    """Read the normal points (record 11) or full-rate ranges (record 10) of a CRD file.

    Parameters
    ----------
    path : str or Path
        CRD file, version 1 or 2 (may be gzip/compress compressed).
    record : {"normal_point", "full_rate"}
        Which range records to return.

    Returns
    -------
    xarray.Dataset
        Dimension ``point`` (possibly of length 0, with a logged warning), schema in the
        module docstring.

    Raises
    ------
    FormatError
        Unknown record, too few fields, non-numeric / NaN field, seconds of day outside
        [0, 86401), bad H1-H4 values, a range or meteorological record before any H4 or
        after H8, an H4 without preceding H1, H2 or H3.
    ValueError
        If ``record`` is not one of the two names.
    """
    if record not in _RECORD_OF:
        raise ValueError(f"record must be 'normal_point' or 'full_rate', not {record!r}")
    path = Path(path)
    lines = read_lines(path)
    require_line_end(lines, path)
    scan = _scan(path, lines)
    rid = _RECORD_OF[record]
    rows = scan.rows[rid]
    if not rows:
        _LOG.warning("%s: no record %s (%s) in the file", path, rid, record)
    sessions = scan.sessions
    sidx = np.array([r[0] for r in rows], dtype=np.int64)
    lines = [r[1] for r in rows]
    fields = [r[2] for r in rows]
    time_ns = _epochs(path, rid, sessions, sidx, lines, fields)
    tof = _floats(path, f"{rid} time of flight", fields, lines, 2, kind="time_of_flight_s")
    data = _range_columns(path, rid, fields, lines)
    syscfg = np.array([f[3] for f in fields], dtype=str)
    met = _meteo(path, scan, sessions, sidx, time_ns)
    ds = _assemble(sessions, sidx, time_ns, tof, syscfg, data, met)
    ds.attrs.update({
        "format": "ILRS CRD",
        "crd_versions": ",".join(str(v) for v in sorted(scan.versions)),
        "record": record,
        "time_system": "UTC",
        "time_scale_codes": "; ".join(f"{k} = {v}" for k, v in TIME_SCALES.items()),
        "n_sessions": len(sessions),
        "source": path.name,
    })
    return ds


def _scan(path: Path, lines: list[str]) -> _Scan:
    """One pass over the lines: parse headers, collect range/met records per session."""
    scan = _Scan()
    version = None
    station = target = None
    wavelengths: dict = {}
    session = None
    for ln, text in enumerate(lines, start=1):
        tokens = text.split()
        if not tokens:
            continue
        rid = tokens[0].upper()
        if rid == "00" or (len(rid) == 2 and rid[0] == "9" and is_digits(rid[1])):
            continue
        nmin = _MIN_FIELDS.get(rid)
        if nmin is None:
            raise FormatError(path, ln, tokens[0], f"unknown record type '{tokens[0]}'")
        if len(tokens) - 1 < nmin:
            raise FormatError(path, ln, rid, f"record has {len(tokens) - 1} fields, at least "
                              f"{nmin} expected (line cut short?)")
        if rid in _SESSION_RECORDS:  # the bulk of the lines: test first
            if session is None or session.closed:
                where = "after H8" if session is not None else "before any H4 session header"
                raise FormatError(path, ln, "H4", f"record {rid} {where}")
            scan.rows[rid].append((session.index, ln, tokens))
        elif rid == "H1":
            _check_closed(path, session)
            version = _parse_h1(path, ln, tokens)
            scan.versions.add(version)
            station = target = session = None
            wavelengths = {}
        elif rid == "H2":
            station = _parse_h2(path, ln, tokens)
        elif rid == "H3":
            target = _parse_h3(path, ln, tokens)
        elif rid == "H4":
            _check_closed(path, session)
            for name, value in (("H1", version), ("H2", station), ("H3", target)):
                if value is None:
                    raise FormatError(path, ln, name, f"H4 session header without a preceding "
                                      f"{name} record")
            session = _parse_h4(path, ln, tokens, len(scan.sessions), station, target)
            session.wavelength_nm = dict(wavelengths)
            scan.sessions.append(session)
        elif rid in ("H8", "H9"):
            if rid == "H8" and (session is None or session.closed):
                raise FormatError(path, ln, "H8", "end of session without an open H4 session")
            if session is not None:
                session.closed = True
        elif rid == "C0":
            cfg, wl = _parse_c0(path, ln, tokens)
            wavelengths[cfg] = wl
            if session is not None and not session.closed:
                session.wavelength_nm[cfg] = wl
    _check_closed(path, session)
    if not scan.versions:
        raise FormatError(path, None, "H1", "no H1 format header record in the file")
    return scan


def _check_closed(path: Path, session: _Session | None) -> None:
    """Warn once about a session that is not terminated by H8."""
    if session is not None and not session.closed:
        _LOG.warning("%s: session starting at line %d is not closed by H8 (file cut or "
                     "concatenated?); its records are kept", path, session.line)
        session.closed = True


def _parse_h1(path: Path, ln: int, t: list[str]) -> int:
    if t[1].upper() != "CRD":
        raise FormatError(path, ln, "H1", f"format literal is '{t[1]}', expected 'CRD'")
    version = parse_int(t[2], path, ln, "H1 format version", lo=0, hi=99)
    if version not in (1, 2):
        raise FormatError(path, ln, "H1 format version", f"CRD version {version} not supported "
                          "(1 or 2)")
    return version


def _parse_h2(path: Path, ln: int, t: list[str]) -> dict:
    pad = t[2]
    if not (is_digits(pad) and len(pad) <= 4):
        raise FormatError(path, ln, "H2 CDP pad id", f"'{pad}' is not a CDP pad id (4 digits)")
    scale = parse_int(t[5], path, ln, "H2 epoch time scale", lo=0, hi=99)
    if scale not in TIME_SCALES:
        raise FormatError(path, ln, "H2 epoch time scale", f"time scale code {scale} is not one "
                          f"of {sorted(TIME_SCALES)}")
    return {"name": t[1], "pad": pad.zfill(4),
            "system": parse_int(t[3], path, ln, "H2 CDP system number", lo=0, hi=99),
            "occupancy": parse_int(t[4], path, ln, "H2 CDP occupancy number", lo=0, hi=99),
            "time_scale": scale}


def _parse_h3(path: Path, ln: int, t: list[str]) -> dict:
    ilrs = t[2]
    if not (is_digits(ilrs) and len(ilrs) <= 7):
        raise FormatError(path, ln, "H3 ILRS id", f"'{ilrs}' is not an ILRS satellite id")
    ilrs = ilrs.zfill(7)
    norad = -1 if t[4].lower() in _NA else parse_int(t[4], path, ln, "H3 NORAD id", lo=0,
                                                     hi=2**31 - 1)
    return {"name": t[1], "ilrs": ilrs, "cospar": ilrs_id_to_cospar(ilrs), "norad": norad}


def _parse_h4(path: Path, ln: int, t: list[str], index: int, station: dict,
              target: dict) -> _Session:
    ints = [parse_int(v, path, ln, f"H4 field {k}", lo=0, hi=9999)
            for k, v in enumerate(t[1:8], start=1)]
    if ints[0] > 2:
        raise FormatError(path, ln, "H4 field 1", f"data type {ints[0]} is not 0, 1 or 2")
    start_ns = epoch_ns(*ints[1:6], float(ints[6]), path, ln, "H4 start")
    names = ("data release", "refraction applied", "CoM applied", "amplitude corr applied",
             "station delay applied", "spacecraft delay applied", "range type",
             "data quality alert")
    flags = [parse_int(v, path, ln, f"H4 {n}", lo=0, hi=99) for n, v in zip(names, t[14:22])]
    return _Session(index=index, line=ln, station=station, target=target,
                    data_type=ints[0], start_ns=start_ns,
                    day_ns=start_ns - start_ns % _DAY_NS, release=flags[0],
                    flags=tuple(flags[1:6]), range_type=flags[6], quality=flags[7])


def _parse_c0(path: Path, ln: int, t: list[str]) -> tuple[str, float]:
    parse_int(t[1], path, ln, "C0 detail type", lo=0, hi=9)
    wl = parse_float(t[2], path, ln, "C0 transmit wavelength", lo=0.0, hi=1e5)
    if wl <= 0:
        raise FormatError(path, ln, "C0 transmit wavelength", f"{wl} nm is not positive")
    return t[3], wl


# -------------------------------------------------------------------- vectorised columns
def _floats(path: Path, name: str, fields: list, lines: list, col: int, *,
            optional: bool = False, kind: str | None = None, lo: float | None = None,
            hi: float | None = None) -> np.ndarray:
    """Column ``col`` of the records as float64 in its range (io._fields); ``na`` (optional
    fields only) -> NaN."""
    texts = [f[col] if col < len(f) else "na" for f in fields]
    missing = np.array([optional and s.lower() in _NA for s in texts], dtype=bool)
    values = np.full(len(texts), np.nan)
    keep = np.flatnonzero(~missing)
    values[keep] = numbers([texts[k] for k in keep], [lines[k] for k in keep], name, path,
                           kind=kind, lo=lo, hi=hi)
    return values


def _ints(path: Path, name: str, fields: list, lines: list, col: int, *,
          optional: bool = False, lo: int = -1, hi: int = 2**31 - 1) -> np.ndarray:
    """Column ``col`` of the records as int64 in [lo, hi] (-1, "not available" in files,
    allowed); ``na`` (optional fields only)
    -> -1."""
    texts = [f[col] if col < len(f) else "na" for f in fields]
    missing = np.array([optional and s.lower() in _NA for s in texts], dtype=bool)
    values = np.full(len(texts), -1, dtype=np.int64)
    keep = np.flatnonzero(~missing)
    values[keep] = integers([texts[k] for k in keep], [lines[k] for k in keep], name, path,
                            lo=lo, hi=hi)
    return values


def _epochs(path: Path, rid: str, sessions: list, sidx: np.ndarray, lines: list,
            fields: list) -> np.ndarray:
    """Epochs [ns since 1970] of records ``rid`` from their seconds of day and session."""
    name = f"{rid} seconds of day"
    sod = _floats(path, name, fields, lines, 1, kind="seconds_of_day")
    bad = np.flatnonzero((sod < 0) | (sod >= 86_401))
    if bad.size:
        k = bad[0]
        raise FormatError(path, lines[k], name, f"{fields[k][1]} is outside [0, 86401) s")
    day = np.array([s.day_ns for s in sessions], dtype=np.int64)[sidx]
    start = np.array([s.start_ns for s in sessions], dtype=np.int64)[sidx]
    t = day + np.rint(sod * _NS).astype(np.int64)
    delta = t - start
    t += _DAY_NS * ((delta < -_BEFORE_START_NS).astype(np.int64)
                    - (delta >= _AFTER_START_NS).astype(np.int64))
    return t


def _range_columns(path: Path, rid: str, fields: list, lines: list) -> dict:
    """Record-specific columns of records 11 or 10, converted to SI."""
    f, i = _floats, _ints
    if rid == "11":
        return {
            "epoch_event": i(path, "11 epoch event", fields, lines, 4, hi=9),
            "np_window_s": f(path, "11 window length", fields, lines, 5, optional=True,
                             kind="interval_s"),
            "n_raw": i(path, "11 number of raw ranges", fields, lines, 6, optional=True),
            "bin_rms_s": f(path, "11 bin RMS", fields, lines, 7, optional=True,
                           kind="statistic") * 1e-12,
            "bin_skew": f(path, "11 bin skew", fields, lines, 8, optional=True,
                          kind="statistic"),
            "bin_kurtosis": f(path, "11 bin kurtosis", fields, lines, 9, optional=True,
                              kind="statistic"),
            "bin_peak_minus_mean_s": f(path, "11 bin peak-mean", fields, lines, 10,
                                       optional=True, kind="statistic") * 1e-12,
            "return_rate_pct": f(path, "11 return rate", fields, lines, 11, optional=True,
                                 kind="statistic"),
            "detector_channel": i(path, "11 detector channel", fields, lines, 12, optional=True,
                                  hi=999),
            "snr": f(path, "11 signal to noise", fields, lines, 13, optional=True,
                     kind="statistic"),
        }
    return {
        "epoch_event": i(path, "10 epoch event", fields, lines, 4, hi=9),
        "filter_flag": i(path, "10 filter flag", fields, lines, 5, hi=9),
        "detector_channel": i(path, "10 detector channel", fields, lines, 6, optional=True,
                              hi=999),
        "stop_number": i(path, "10 stop number", fields, lines, 7, optional=True, hi=999),
        "receive_amplitude": i(path, "10 receive amplitude", fields, lines, 8, optional=True,
                               hi=999_999),
        "transmit_amplitude": i(path, "10 transmit amplitude", fields, lines, 9, optional=True,
                                hi=999_999),
    }


def _meteo(path: Path, scan: _Scan, sessions: list, sidx: np.ndarray,
           time_ns: np.ndarray) -> dict:
    """Pressure, temperature, humidity of record 20 at the range epochs (per session)."""
    rows = scan.rows["20"]
    msidx = np.array([r[0] for r in rows], dtype=np.int64)
    lines = [r[1] for r in rows]
    fields = [r[2] for r in rows]
    mt = _epochs(path, "20", sessions, msidx, lines, fields)
    names = {"pressure_hpa": 2, "temperature_k": 3, "humidity_pct": 4}
    cols = {k: _floats(path, f"20 {k.split('_')[0]}", fields, lines, c, optional=True, kind=k)
            for k, c in names.items()}
    _ints(path, "20 origin of values", fields, lines, 5, hi=9)  # checked, not returned
    out = {k: np.full(time_ns.shape, np.nan) for k in names}
    for s in np.unique(sidx):
        here = sidx == s
        there = msidx == s
        if not there.any():
            continue
        order = np.argsort(mt[there], kind="stable")
        tm = (mt[there][order] - sessions[s].start_ns) * 1e-9
        tp = (time_ns[here] - sessions[s].start_ns) * 1e-9
        for k, v in cols.items():
            vv = v[there][order]
            ok = np.isfinite(vv)
            if ok.any():
                out[k][here] = np.interp(tp, tm[ok], vv[ok])
    return out


def _assemble(sessions: list, sidx: np.ndarray, time_ns: np.ndarray, tof: np.ndarray,
              syscfg: np.ndarray, data: dict, met: dict) -> xr.Dataset:
    """Build the Dataset of the module docstring."""

    def per_session(fn, dtype):
        return np.array([fn(s) for s in sessions], dtype=dtype)[sidx]

    wl = np.array([sessions[s].wavelength_nm.get(c, np.nan) for s, c in zip(sidx, syscfg)],
                  dtype=float)
    flag_names = ("refraction_applied", "com_applied", "amplitude_corr_applied",
                  "station_delay_applied", "spacecraft_delay_applied")
    flag_titles = ("tropospheric refraction applied", "centre-of-mass correction applied",
                   "receive amplitude correction applied", "station system delay applied",
                   "spacecraft system delay applied")
    v = {
        "tof_s": (tof, "s", "two-way time of flight (record 10/11)"),
        "range_m": (tof * (C_LIGHT_M_S / 2.0), "m",
                    "convenience range tof_s*c/2, no correction applied"),
        "pass_id": (sidx.astype(np.int32), "1", "index of the H4 session in the file"),
        "data_type": (per_session(lambda s: s.data_type, np.int8), "1",
                      "H4 data type (0 full rate, 1 normal point, 2 sampled engineering)"),
        "station": (per_session(lambda s: s.station["pad"], str), "1", "CDP pad id (H2)"),
        "station_name": (per_session(lambda s: s.station["name"], str), "1",
                         "station name (H2)"),
        "system_number": (per_session(lambda s: s.station["system"], np.int32), "1",
                          "CDP system number (H2)"),
        "occupancy_number": (per_session(lambda s: s.station["occupancy"], np.int32), "1",
                             "CDP occupancy sequence number (H2)"),
        "time_scale": (per_session(lambda s: s.station["time_scale"], np.int8), "1",
                       "station epoch time scale code (H2): " +
                       "; ".join(f"{k} = {n}" for k, n in TIME_SCALES.items())),
        "satellite": (per_session(lambda s: s.target["name"], str), "1", "target name (H3)"),
        "ilrs_id": (per_session(lambda s: s.target["ilrs"], str), "1", "ILRS satellite id"),
        "cospar_id": (per_session(lambda s: s.target["cospar"], str), "1",
                      "COSPAR id derived from the ILRS id"),
        "norad_id": (per_session(lambda s: s.target["norad"], np.int64), "1",
                     "NORAD catalogue number (-1 if not available)"),
        "data_release": (per_session(lambda s: s.release, np.int16), "1",
                         "H4 data release flag"),
        "range_type": (per_session(lambda s: s.range_type, np.int8), "1",
                       "H4 range type (0 none, 1 one-way, 2 two-way, 3 receive only, 4 mixed)"),
        "data_quality_alert": (per_session(lambda s: s.quality, np.int8), "1",
                               "H4 data quality alert indicator"),
        "system_config": (syscfg, "1", "system configuration id"),
        "wavelength_nm": (wl, "nm", "transmit wavelength of the system configuration (C0)"),
    }
    for k, (name, title) in enumerate(zip(flag_names, flag_titles)):
        v[name] = (per_session(lambda s, k=k: s.flags[k], np.int8), "1", f"H4 flag: {title}")
    units = {"np_window_s": ("s", "normal point window length"),
             "n_raw": ("1", "number of raw ranges in the normal point (-1 if not available)"),
             "bin_rms_s": ("s", "bin RMS from the mean of the raw ranges"),
             "bin_skew": ("1", "bin skew from the mean of the raw ranges"),
             "bin_kurtosis": ("1", "bin kurtosis from the mean of the raw ranges"),
             "bin_peak_minus_mean_s": ("s", "bin peak minus mean"),
             "return_rate_pct": ("percent", "return rate"),
             "snr": ("1", "signal to noise ratio (CRD 2)"),
             "epoch_event": ("1", "epoch event indicator"),
             "detector_channel": ("1", "detector channel (-1 if not available)"),
             "filter_flag": ("1", "filter flag (0 unknown, 1 noise, 2 data)"),
             "stop_number": ("1", "stop number"),
             "receive_amplitude": ("1", "receive amplitude (-1 if not available)"),
             "transmit_amplitude": ("1", "transmit amplitude (-1 if not available)")}
    for name, values in data.items():
        v[name] = (values, *units[name])
    v["pressure_hpa"] = (met["pressure_hpa"], "hPa", "surface pressure (record 20)")
    v["temperature_k"] = (met["temperature_k"], "K", "surface temperature (record 20)")
    v["humidity_pct"] = (met["humidity_pct"], "percent", "relative humidity (record 20)")
    ds = xr.Dataset(
        {name: ("point", values, {"units": u, "long_name": title})
         for name, (values, u, title) in v.items()},
        coords={"time": ("point", time_ns.astype("datetime64[ns]"),
                         {"long_name": "epoch of the range record (UTC, see time_scale)"})},
    )
    for name in ("pressure_hpa", "temperature_k", "humidity_pct"):
        ds[name].attrs["comment"] = ("linear in time between the session's record-20 values, "
                                     "nearest value outside them, NaN if none")
    return ds

"""ILRS Consolidated laser Ranging Data (CRD): read normal points and full-rate ranges, write NPs.

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

:func:`write_crd` writes normal points (H1-H4, C0, 11, 20, H8 per session, H9 at the end).
"""

from __future__ import annotations

import datetime as _dt
import logging
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.constants import C_LIGHT_M_S
from leopod.io._text import FormatError, parse_float, parse_int, read_lines, write_text

__all__ = ["ilrs_id_to_cospar", "read_crd", "write_crd"]

_LOG = logging.getLogger(__name__)

_NS = 1_000_000_000
_DAY_NS = 86_400 * _NS
_BEFORE_START_NS = 10 * 3600 * _NS
_AFTER_START_NS = _DAY_NS - _BEFORE_START_NS
_MAX_WRITE_SESSION_NS = 12 * 3600 * _NS
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
    if len(s) != 7 or not s.isdigit() or int(s[5:]) == 0:
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
    scan = _scan(path, read_lines(path))
    rid = _RECORD_OF[record]
    rows = scan.rows[rid]
    if not rows:
        _LOG.warning("%s: no record %s (%s) in the file", path, rid, record)
    sessions = scan.sessions
    sidx = np.array([r[0] for r in rows], dtype=np.int64)
    lines = [r[1] for r in rows]
    fields = [r[2] for r in rows]
    time_ns = _epochs(path, rid, sessions, sidx, lines, fields)
    tof = _floats(path, f"{rid} time of flight", fields, lines, 2)
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
        if rid == "00" or (len(rid) == 2 and rid[0] == "9" and rid[1].isdigit()):
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
    version = parse_int(t[2], path, ln, "H1 format version")
    if version not in (1, 2):
        raise FormatError(path, ln, "H1 format version", f"CRD version {version} not supported "
                          "(1 or 2)")
    return version


def _parse_h2(path: Path, ln: int, t: list[str]) -> dict:
    pad = t[2]
    if not (pad.isdigit() and len(pad) <= 4):
        raise FormatError(path, ln, "H2 CDP pad id", f"'{pad}' is not a CDP pad id (4 digits)")
    scale = parse_int(t[5], path, ln, "H2 epoch time scale")
    if scale not in TIME_SCALES:
        raise FormatError(path, ln, "H2 epoch time scale", f"time scale code {scale} is not one "
                          f"of {sorted(TIME_SCALES)}")
    return {"name": t[1], "pad": pad.zfill(4),
            "system": parse_int(t[3], path, ln, "H2 CDP system number"),
            "occupancy": parse_int(t[4], path, ln, "H2 CDP occupancy number"),
            "time_scale": scale}


def _parse_h3(path: Path, ln: int, t: list[str]) -> dict:
    ilrs = t[2]
    if not (ilrs.isdigit() and len(ilrs) <= 7):
        raise FormatError(path, ln, "H3 ILRS id", f"'{ilrs}' is not an ILRS satellite id")
    ilrs = ilrs.zfill(7)
    norad = -1 if t[4].lower() in _NA else parse_int(t[4], path, ln, "H3 NORAD id")
    return {"name": t[1], "ilrs": ilrs, "cospar": ilrs_id_to_cospar(ilrs), "norad": norad}


def _parse_h4(path: Path, ln: int, t: list[str], index: int, station: dict,
              target: dict) -> _Session:
    ints = [parse_int(v, path, ln, f"H4 field {k}") for k, v in enumerate(t[1:8], start=1)]
    try:
        start = _dt.datetime(*ints[1:7])
    except ValueError as err:
        raise FormatError(path, ln, "H4 start", f"invalid start epoch ({err})") from None
    start_ns = int(np.datetime64(start, "ns").astype(np.int64))
    names = ("data release", "refraction applied", "CoM applied", "amplitude corr applied",
             "station delay applied", "spacecraft delay applied", "range type",
             "data quality alert")
    flags = [parse_int(v, path, ln, f"H4 {n}") for n, v in zip(names, t[14:22])]
    return _Session(index=index, line=ln, station=station, target=target,
                    data_type=ints[0], start_ns=start_ns,
                    day_ns=start_ns - start_ns % _DAY_NS, release=flags[0],
                    flags=tuple(flags[1:6]), range_type=flags[6], quality=flags[7])


def _parse_c0(path: Path, ln: int, t: list[str]) -> tuple[str, float]:
    parse_int(t[1], path, ln, "C0 detail type")
    wl = parse_float(t[2], path, ln, "C0 transmit wavelength")
    if wl <= 0:
        raise FormatError(path, ln, "C0 transmit wavelength", f"{wl} nm is not positive")
    return t[3], wl


# -------------------------------------------------------------------- vectorised columns
def _floats(path: Path, name: str, fields: list, lines: list, col: int, *,
            optional: bool = False) -> np.ndarray:
    """Column ``col`` of the records as float64; ``na`` (optional fields only) -> NaN."""
    texts = [f[col] if col < len(f) else "na" for f in fields]
    missing = np.array([optional and s.lower() in _NA for s in texts], dtype=bool)
    try:
        values = np.array(["nan" if m else s for s, m in zip(texts, missing)], dtype=float)
        good = bool(np.isfinite(values[~missing]).all())
    except ValueError:
        good = False
    if not good:  # slow path: find the offending line (or accept Fortran D exponents)
        values = np.array([math.nan if m else parse_float(s, path, ln, name)
                           for s, m, ln in zip(texts, missing, lines)], dtype=float)
    return values


def _ints(path: Path, name: str, fields: list, lines: list, col: int, *,
          optional: bool = False) -> np.ndarray:
    """Column ``col`` of the records as int64; ``na`` (optional fields only) -> -1."""
    texts = [f[col] if col < len(f) else "na" for f in fields]
    clean = ["-1" if optional and s.lower() in _NA else s for s in texts]
    try:
        return np.array(clean, dtype=np.int64)
    except (ValueError, OverflowError):
        return np.array([parse_int(s, path, ln, name) for s, ln in zip(clean, lines)],
                        dtype=np.int64)


def _epochs(path: Path, rid: str, sessions: list, sidx: np.ndarray, lines: list,
            fields: list) -> np.ndarray:
    """Epochs [ns since 1970] of records ``rid`` from their seconds of day and session."""
    name = f"{rid} seconds of day"
    sod = _floats(path, name, fields, lines, 1)
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
            "epoch_event": i(path, "11 epoch event", fields, lines, 4),
            "np_window_s": f(path, "11 window length", fields, lines, 5, optional=True),
            "n_raw": i(path, "11 number of raw ranges", fields, lines, 6, optional=True),
            "bin_rms_s": f(path, "11 bin RMS", fields, lines, 7, optional=True) * 1e-12,
            "bin_skew": f(path, "11 bin skew", fields, lines, 8, optional=True),
            "bin_kurtosis": f(path, "11 bin kurtosis", fields, lines, 9, optional=True),
            "bin_peak_minus_mean_s": f(path, "11 bin peak-mean", fields, lines, 10,
                                       optional=True) * 1e-12,
            "return_rate_pct": f(path, "11 return rate", fields, lines, 11, optional=True),
            "detector_channel": i(path, "11 detector channel", fields, lines, 12, optional=True),
            "snr": f(path, "11 signal to noise", fields, lines, 13, optional=True),
        }
    return {
        "epoch_event": i(path, "10 epoch event", fields, lines, 4),
        "filter_flag": i(path, "10 filter flag", fields, lines, 5),
        "detector_channel": i(path, "10 detector channel", fields, lines, 6, optional=True),
        "stop_number": i(path, "10 stop number", fields, lines, 7, optional=True),
        "receive_amplitude": i(path, "10 receive amplitude", fields, lines, 8, optional=True),
        "transmit_amplitude": i(path, "10 transmit amplitude", fields, lines, 9, optional=True),
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
    cols = {k: _floats(path, f"20 {k.split('_')[0]}", fields, lines, c, optional=True)
            for k, c in names.items()}
    _ints(path, "20 origin of values", fields, lines, 5)  # checked, not returned
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


# ----------------------------------------------------------------------------------- writing
#: Formats of the statistics that differ between versions: CRD 1 is fixed format (F9.1 ps,
#: F5.1 %, F4.0 %), CRD 2 is free format and keeps more decimals.
_NUMBER_FORMATS = {1: {"ps": "9.1f", "rate": "5.1f", "humidity": "4.0f"},
                   2: {"ps": "9.3f", "rate": "6.2f", "humidity": "5.1f"}}
_V1_WIDTHS = {"station_name": 10, "satellite": 10, "system_config": 4}
_WRITE_REQUIRED = ("time", "tof_s", "pass_id", "station", "satellite", "ilrs_id",
                   "wavelength_nm")
_WRITE_DEFAULTS = {
    "station_name": None, "system_number": 1, "occupancy_number": 1, "time_scale": 4,
    "norad_id": -1, "data_release": 0, "range_type": 2, "data_quality_alert": 0,
    "refraction_applied": 0, "com_applied": 0, "amplitude_corr_applied": 0,
    "station_delay_applied": 1, "spacecraft_delay_applied": 0, "system_config": "std",
    "epoch_event": 2, "np_window_s": np.nan, "n_raw": -1, "bin_rms_s": np.nan,
    "bin_skew": np.nan, "bin_kurtosis": np.nan, "bin_peak_minus_mean_s": np.nan,
    "return_rate_pct": np.nan, "detector_channel": 0, "snr": np.nan,
    "pressure_hpa": np.nan, "temperature_k": np.nan, "humidity_pct": np.nan,
}


def write_crd(ds: xr.Dataset, path: str | Path, version: int = 2, *,
              production_time: _dt.datetime | None = None) -> None:
    """Write normal points as a CRD file that :func:`read_crd` reads back.

    One block H1, H2, H3, H4, C0 (one per system configuration), then per point a record 11
    and, where pressure, temperature and humidity are all finite, a record 20 at the same
    epoch (origin 1, "interpolated"), H8; H9 at the end. Epochs are written to 1 ns (12
    decimals of the seconds of day), times of flight to 1 ps (12 decimals), pressure and
    temperature to 0.01; bin RMS and peak-mean to 0.001 ps, return rate and SNR to 0.01,
    humidity to 0.1 % in CRD 2; the CRD 1 fixed widths (0.1 ps, 0.1 %, 1 % humidity) in CRD 1.
    ``pass_id`` is not written: reading the file back numbers the sessions 0, 1, ... in
    the order of the input's ``pass_id`` values.

    Parameters
    ----------
    ds : xarray.Dataset
        Dimension ``point`` with at least ``time``, ``tof_s`` [s], ``pass_id``, ``station``
        (4-digit CDP pad id), ``satellite``, ``ilrs_id`` and ``wavelength_nm`` [nm]. Any other
        variable of the :func:`read_crd` schema is used when present, otherwise defaults:
        station_name = station, system/occupancy number 1, time_scale 4 (UTC(GPS)),
        range_type 2, station_delay_applied 1, other H4 flags 0, system_config "std",
        epoch_event 2, detector_channel 0, statistics "na" (CRD 2) or -1 (CRD 1).
        H3 is written with SIC "na" (CRD 1: 0), spacecraft time scale 0, target type 1
        (passive retro-reflector) and (CRD 2) location 1 (Earth orbit).
    path : str or Path
        Output file.
    version : {1, 2}
        CRD version of the output (both use blank-separated fields in the CRD 1 order).
    production_time : datetime, optional
        H1 production date and hour; default the current UTC time.

    Raises
    ------
    ValueError
        Missing required variable, NaT time, non-finite time of flight or wavelength, a
        station id that is not 4 digits, a name containing blanks, a session longer than
        12 h (it could not be read back unambiguously), unsupported version.
    """
    if version not in (1, 2):
        raise ValueError(f"CRD version must be 1 or 2, not {version}")
    missing = [name for name in _WRITE_REQUIRED if name not in ds.variables]
    if missing:
        raise ValueError(f"write_crd needs the variables {missing}")
    cols = _write_columns(ds)
    if version == 1:
        for name, width in _V1_WIDTHS.items():
            bad = [v for v in cols[name] if len(v) > width]
            if bad:
                raise ValueError(f"write_crd: CRD 1 allows {width} characters for {name}, "
                                 f"'{bad[0]}' is longer")
    prod = production_time or _dt.datetime.now(_dt.UTC)
    out = []
    for pid in np.unique(cols["pass_id"]):
        idx = np.flatnonzero(cols["pass_id"] == pid)
        idx = idx[np.argsort(cols["time"][idx], kind="stable")]
        out += _session_lines(cols, idx, version, prod)
    out.append("H9")
    write_text(path, "\n".join(out) + "\n")


def _write_columns(ds: xr.Dataset) -> dict:
    """Per-point numpy arrays of every field written, with defaults, checked."""
    n = ds.sizes.get("point", 0)
    cols = {name: np.asarray(ds[name].values) for name in _WRITE_REQUIRED}
    for name, default in _WRITE_DEFAULTS.items():
        if name in ds.variables:
            cols[name] = np.asarray(ds[name].values)
        elif default is None:
            cols[name] = cols["station"]
        else:
            cols[name] = np.full(n, default)
    time = cols["time"].astype("datetime64[ns]")
    if np.isnat(time).any():
        raise ValueError("write_crd: time contains NaT")
    cols["time"] = time.astype(np.int64)
    for name in ("tof_s", "wavelength_nm"):
        if not np.isfinite(cols[name].astype(float)).all():
            raise ValueError(f"write_crd: {name} must be finite")
    for name in ("station", "station_name", "satellite", "ilrs_id", "system_config"):
        cols[name] = cols[name].astype(str)
        bad = [s for s in cols[name] if not s or any(c.isspace() for c in s)]
        if bad:
            raise ValueError(f"write_crd: {name} '{bad[0]}' is empty or contains blanks")
    bad = [s for s in cols["station"] if not (s.isdigit() and len(s) == 4)]
    if bad:
        raise ValueError(f"write_crd: station '{bad[0]}' is not a 4-digit CDP pad id")
    return cols


def _fmt(value: float, spec: str, version: int) -> str:
    """A number, or the "not available" token of the version (na / -1) for NaN or -1 ints."""
    if isinstance(value, (int, np.integer)):
        if value == -1:
            return "na" if version == 2 else "-1"
        return format(int(value), spec)
    if not np.isfinite(value):
        return "na" if version == 2 else "-1"
    return format(float(value), spec)


def _sod_text(sod_ns: int) -> str:
    """Seconds of day with 12 decimals from an integer number of nanoseconds."""
    sec, ns = divmod(int(sod_ns), _NS)
    return f"{sec:5d}.{ns:09d}000"


def _session_lines(c: dict, idx: np.ndarray, version: int, prod: _dt.datetime) -> list[str]:
    """The records of one session (points ``idx`` sorted by time)."""
    t = c["time"][idx]
    start = int(t[0]) - int(t[0]) % _NS
    stop = int(t[-1]) + (-int(t[-1])) % _NS
    if stop - start >= _MAX_WRITE_SESSION_NS:
        hours = (stop - start) / 3.6e12
        raise ValueError(f"write_crd: pass {c['pass_id'][idx[0]]} spans {hours:.1f} h; "
                         "sessions must be shorter than 12 h")
    day = start - start % _DAY_NS
    k = idx[0]
    d0 = _ns_to_datetime(start)
    d1 = _ns_to_datetime(stop)
    fl = [int(c[n][k]) for n in ("data_release", "refraction_applied", "com_applied",
                                 "amplitude_corr_applied", "station_delay_applied",
                                 "spacecraft_delay_applied", "range_type",
                                 "data_quality_alert")]
    norad = _fmt(int(c["norad_id"][k]), "8d", version)
    sic = "na" if version == 2 else "0"
    out = [
        f"H1 CRD {version:2d} {prod.year:4d} {prod.month:2d} {prod.day:2d} {prod.hour:2d}",
        f"H2 {c['station_name'][k]:<10s} {c['station'][k]} {int(c['system_number'][k]):2d} "
        f"{int(c['occupancy_number'][k]):2d} {int(c['time_scale'][k]):2d}"
        + (" na" if version == 2 else ""),
        f"H3 {c['satellite'][k]:<10s} {c['ilrs_id'][k]:>8s} {sic:>4s} {norad:>8s} 0 1"
        + (" 1" if version == 2 else ""),
        "H4  1 " + _h4_epoch(d0) + " " + _h4_epoch(d1) + f" {fl[0]:2d} "
        + " ".join(str(f) for f in fl[1:]),
    ]
    configs = dict.fromkeys(c["system_config"][idx])
    for cfg in configs:
        wl = c["wavelength_nm"][idx][c["system_config"][idx] == cfg][0]
        out.append(f"C0 0 {float(wl):.3f} {cfg}")
    f = _NUMBER_FORMATS[version]
    for j, tj in zip(idx, t):
        sod = _sod_text((int(tj) - day) % _DAY_NS)
        rec = (f"11 {sod:>18s} {float(c['tof_s'][j]):18.12f} {c['system_config'][j]} "
               f"{int(c['epoch_event'][j])} {_fmt(c['np_window_s'][j], '6.1f', version)} "
               f"{_fmt(int(c['n_raw'][j]), '6d', version)} "
               f"{_fmt(c['bin_rms_s'][j] * 1e12, f['ps'], version)} "
               f"{_fmt(c['bin_skew'][j], '7.3f', version)} "
               f"{_fmt(c['bin_kurtosis'][j], '7.3f', version)} "
               f"{_fmt(c['bin_peak_minus_mean_s'][j] * 1e12, f['ps'], version)} "
               f"{_fmt(c['return_rate_pct'][j], f['rate'], version)} "
               f"{_fmt(int(c['detector_channel'][j]), 'd', version)}")
        if version == 2:
            rec += f" {_fmt(c['snr'][j], f['rate'], version)}"
        out.append(rec)
        met = [float(c[n][j]) for n in ("pressure_hpa", "temperature_k", "humidity_pct")]
        if all(np.isfinite(met)):
            out.append(f"20 {sod:>18s} {met[0]:7.2f} {met[1]:6.2f} "
                       f"{format(met[2], f['humidity'])} 1")
    out.append("H8")
    return out


def _ns_to_datetime(t_ns: int) -> _dt.datetime:
    return _dt.datetime(1970, 1, 1) + _dt.timedelta(microseconds=t_ns // 1000)


def _h4_epoch(d: _dt.datetime) -> str:
    return f"{d.year:4d} {d.month:2d} {d.day:2d} {d.hour:2d} {d.minute:2d} {d.second:2d}"

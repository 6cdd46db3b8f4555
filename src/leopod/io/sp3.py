"""Reader of SP3 precise orbit files (SP3-a, -b, -c and -d).

Specification: S. Hilla, "The Extended Standard Product 3 Orbit Format (SP3-d)", NGS/NOAA,
21 February 2016 (files.igs.org/pub/data/format/sp3d.pdf), and its predecessor "SP3-c"
(Hilla, 17 August 2010), whose fixed columns the reader also accepts. SP3-a numeric satellite
ids ("  1") are read as GPS ("G01").

Dataset returned by :func:`read_sp3` (and accepted by :func:`leopod.io.sp3_write.write_sp3`)
-------------------------------------------------------------------------------------------
Coordinates
    ``time``  (time,) datetime64[ns] -- epochs in the file's time system (``attrs["time_system"]``)
    ``sv``    (sv,) str -- satellite ids of the header list, in header order ("G01", "R24", "L47")
    ``xyz``   (xyz,) str -- ``["x", "y", "z"]``
Data variables
    ``pos_m``       (time, sv, xyz) float64 [m]   position (file km x 1000); NaN where the file
                    has the "bad or absent" value 0.000000 in all three components, or no record
    ``clk_s``       (time, sv) float64 [s]        clock correction (file microseconds x 1e-6);
                    NaN for 999999.999999 (bad or absent) or a blank field
    ``vel_m_s``     (time, sv, xyz) float64 [m s-1] velocity (file dm/s x 0.1); only when the
                    file has V records; NaN where all three components are 0.000000
    ``clk_rate_s_s`` (time, sv) float64 [s s-1]   clock rate (file 1e-4 microseconds/s x 1e-10);
                    only with V records; NaN for 999999.999999 or blank
    ``pos_sigma_m`` (time, sv, xyz) float64 [m]   record standard deviation base**n mm; and
    ``clk_sigma_s`` (time, sv) float64 [s]        base**n ps -- both only when the P records carry
                    accuracy exponents and the ``%f`` line gives a non-zero base; NaN when blank
    ``orbit_accuracy_m`` (sv,) float64 [m]        header accuracy 2**n mm ("++" lines); NaN for 0
                    (unknown)
    ``clock_event_flag``, ``manoeuvre_flag`` (time, sv) int8  1 where a P record sets the clock
                    event flag "E" (column 75) or the manoeuvre flag "M" (column 79); each
                    only when the file sets it somewhere
Attributes
    ``sp3_version`` ("a".."d"), ``pv_flag`` ("P" or "V"), ``data_used``, ``coordinate_system``,
    ``orbit_type``, ``agency``, ``interval_s`` (float, header epoch interval), ``time_system``
    ("GPS" when the file does not say, as in SP3-a/b; "GPS" with ``time_system_file`` the
    file's when read with ``gps_time=True``), ``file_type`` ("G", "M", "L", ...; "" if
    absent), ``comments`` (the ``/*`` lines joined by newlines), ``filename``.

Errors
------
Bad input raises :class:`leopod.io.FormatError` naming file, line and field: a malformed first
or second header line, a missing satellite list, an unreadable epoch (``*``) line, a bad numeric
field of a P/V record (field ``"<sv> x|y|z|clock"``, ``"<sv> vx|vy|vz|clock rate"``), a satellite
absent from the header list, two records of one satellite at one epoch, epochs out of order,
fewer epochs than the header declares in a file without ``EOF`` (truncated), and a file
without ``EOF`` whose last epoch lacks some satellites. A file complete to its ``EOF`` whose
epoch count disagrees with the header is read with a logged warning (GFZ's MGEX rapid orbits
kept by gnss_lib_py declare 288 epochs and hold 3). Fields follow the reader contract
(:mod:`leopod.io._fields`): positions within 1e6 km, clocks within 1e6 µs (999999.999999 is
the "bad" marker), a satellite count of 1..999.
"""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.io._fields import check_range, is_digits, is_letters
from leopod.io._text import (
    PRODUCT_TIME_SYSTEMS,
    FormatError,
    calendar_epoch_ns,
    fixed_float,
    parse_float,
    parse_floats,
    parse_int,
    read_lines,
    time_system_to_gps,
)

__all__ = ["read_sp3"]

logger = logging.getLogger(__name__)

_NS = 1_000_000_000
_BAD_CLOCK = 999_999.0  # "bad or absent" clock values are 999999.999999 (>= this)
#: Event flags of a P record: variable, 0-based column, character, long name (SP3-d, Hilla
#: 2016: column 75 clock event flag "E", column 79 manoeuvre flag "M").
_FLAGS = (("clock_event_flag", 74, "E", "clock event (discontinuity) flag of the record"),
          ("manoeuvre_flag", 78, "M", "orbit manoeuvre flag of the record"))
_XYZ = ("x", "y", "z")
# 0-based [start, stop) columns of a P or V record (SP3-d table "Position and Clock Record")
_REC_COLS = ((4, 18), (18, 32), (32, 46), (46, 60))
_EXP_COLS = ((61, 63), (64, 66), (67, 69), (70, 73))


# --------------------------------------------------------------------------------------------
# small parsing helpers


def _sat_id(text: str, path: Path, line_no: int) -> str:
    """Normalise a 3-character SP3 satellite id ("G01", "G 1", SP3-a "  1") to "G01"."""
    system = text[:1]
    number = text[1:3]
    if system == " " or is_digits(system):  # SP3-a: I3 PRN, GPS implied
        system, number = "G", text[:3]
    if not is_letters(system) or not is_digits(number.strip()):
        raise FormatError(path, line_no, "satellite id", f"'{text}' is not a satellite id")
    return f"{system.upper()}{int(number):02d}"


# --------------------------------------------------------------------------------------------
# reader


def _parse_header(lines: list[str], path: Path) -> tuple[dict, list[str], np.ndarray, int]:
    """Parse the SP3 header.

    Returns
    -------
    attrs : dict
        Header attributes of the Dataset, plus private keys ``_n_epochs``, ``_base_pos``,
        ``_base_clk``.
    sats : list of str
        Satellite ids in header order.
    accuracy_m : numpy.ndarray
        Header accuracy per satellite [m], NaN where unknown, shape (nsat,).
    first_data : int
        0-based index of the first epoch line.
    """
    line1 = lines[0] if lines else ""
    if not (line1.startswith("#") and line1[1:2] in ("a", "b", "c", "d")):
        raise FormatError(path, 1, "version", "the first line must start with '#a', '#b', '#c' "
                          f"or '#d' (SP3 version), found '{line1[:3]}'")
    if line1[2:3] not in ("P", "V"):
        raise FormatError(path, 1, "pos/vel flag", f"column 3 must be 'P' or 'V', "
                          f"found '{line1[2:3]}'")
    if len(line1.rstrip()) < 39:
        raise FormatError(path, 1, "number of epochs", "the first header line is truncated")
    attrs = {
        "sp3_version": line1[1],
        "pv_flag": line1[2],
        "data_used": line1[40:45].strip(),
        "coordinate_system": line1[46:51].strip(),
        "orbit_type": line1[52:55].strip(),
        "agency": line1[56:60].strip(),
        "_n_epochs": parse_int(line1[32:39], path, 1, "number of epochs", lo=0),
    }
    line2 = lines[1] if len(lines) > 1 else ""
    if not line2.startswith("##"):
        raise FormatError(path, 2, "##", "the second header line must start with '##'")
    attrs["interval_s"] = fixed_float(line2, 24, 38, path, 2, "epoch interval",
                                      kind="interval_s")

    i = 2
    plus = []
    while i < len(lines) and lines[i].startswith("+ "):
        plus.append(i)
        i += 1
    if not plus:
        raise FormatError(path, 3, "+", "the satellite list ('+' lines) is missing")
    n_sat = parse_int(lines[plus[0]][3:6], path, plus[0] + 1, "number of satellites", lo=1,
                      hi=999)
    sats = []
    for k in plus:
        text = lines[k]
        for c in range(9, 60, 3):
            if len(sats) < n_sat:
                sats.append((text[c:c + 3], k + 1))
    if len(sats) < n_sat or any(not s.strip() or s.strip() == "0" for s, _ in sats):
        raise FormatError(path, plus[-1] + 1, "+", f"the header declares {n_sat} satellites "
                          "but lists fewer ids")
    sat_ids = [_sat_id(s, path, n) for s, n in sats]
    if len(set(sat_ids)) != len(sat_ids):
        raise FormatError(path, plus[0] + 1, "+", "a satellite is listed twice")

    exps = np.zeros(n_sat)
    k_sat = 0
    while i < len(lines) and lines[i].startswith("++"):
        for c in range(9, 60, 3):
            if k_sat < n_sat:
                field = lines[i][c:c + 3]
                # 2**29 mm = 537 km: no orbit product is announced less accurate
                exps[k_sat] = parse_int(field, path, i + 1, "accuracy", lo=0, hi=29) \
                    if field.strip() else 0
                k_sat += 1
        i += 1
    with np.errstate(over="ignore"):
        accuracy = np.where(exps > 0, 2.0 ** exps * 1e-3, np.nan)

    attrs.update(file_type="", time_system="GPS", _base_pos=0.0, _base_clk=0.0)
    comments = []
    seen_c = seen_f = False
    while i < len(lines) and not lines[i].startswith("*"):
        text = lines[i]
        if text.startswith("%c") and not seen_c:
            seen_c = True
            attrs["file_type"] = text[3:5].strip().replace("c", "")
            tsys = text[9:12].strip()
            if tsys and tsys != "ccc" and attrs["sp3_version"] in ("c", "d"):
                if tsys not in PRODUCT_TIME_SYSTEMS:
                    raise FormatError(path, i + 1, "time system", f"'{tsys}' is not an SP3 "
                                      f"time system ({', '.join(PRODUCT_TIME_SYSTEMS)})")
                attrs["time_system"] = tsys
                attrs["_time_system_line"] = i + 1
        elif text.startswith("%f") and not seen_f:
            seen_f = True
            attrs["_base_pos"] = parse_float(text[3:13], path, i + 1, "base pos/vel",
                                             allow_blank=True, lo=0.0, hi=10.0)
            attrs["_base_clk"] = parse_float(text[14:26], path, i + 1, "base clk/rate",
                                             allow_blank=True, lo=0.0, hi=10.0)
        elif text.startswith("/*"):
            comments.append(text[2:].strip())
        elif text.startswith("%/*"):  # ILRS combination files (Orekit issue 895): a comment
            logger.warning("%s:%d: '%%/*' header line read as a comment", path, i + 1)
            comments.append(text[3:].strip())
        elif not text.startswith(("%c", "%f", "%i")) and text.strip():
            raise FormatError(path, i + 1, "header", f"unexpected header line '{text[:20]}'")
        i += 1
    if i >= len(lines):
        raise FormatError(path, len(lines), "*", "the file has no epoch ('*') record")
    attrs["comments"] = "\n".join(c for c in comments if c)
    return attrs, sat_ids, accuracy, i


def _parse_epoch_line(text: str, path: Path, line_no: int, last: bool = True) -> int:
    """Epoch of a ``*`` line in ns since 1970-01-01.

    The line has 31 columns (seconds F11.8). A shorter line is refused as cut when it is the
    last line of the file; inside the file (``last`` False) a seconds field that ends early
    is read as written (EMR's SP3-a files of 1997 write ``.0000000`` ending in column 30).
    Hour 24 is refused: Orekit's issue-895 file writes ``2016  7  7 24  0`` for 7 July 00:00,
    which ISO 8601 would read as 8 July.
    """
    length = len(text.rstrip())
    if length < 31 and (last or length < 22):
        raise FormatError(path, line_no, "epoch", "the epoch ('*') record is truncated: "
                          f"'{text.rstrip()}' (31 columns expected)")
    parts = [parse_int(text[3:7], path, line_no, "year", lo=0),
             parse_int(text[8:10], path, line_no, "month", lo=0),
             parse_int(text[11:13], path, line_no, "day", lo=0),
             parse_int(text[14:16], path, line_no, "hour", lo=0),
             parse_int(text[17:19], path, line_no, "minute", lo=0)]
    seconds = fixed_float(text, 20, 31, path, line_no, "second")
    return calendar_epoch_ns(tuple(parts), seconds, path, line_no)


class _Records:
    """Lines of one record type (P or V) with their epoch and satellite indices."""

    def __init__(self):
        self.texts: list[str] = []
        self.line_nos: list[int] = []
        self.epoch: list[int] = []
        self.sat: list[int] = []

    def add(self, text: str, line_no: int, epoch: int, sat: int) -> None:
        self.texts.append(text)
        self.line_nos.append(line_no)
        self.epoch.append(epoch)
        self.sat.append(sat)


def _check_record_length(text: str, sv: str, names: tuple[str, ...], path: Path,
                         line_no: int) -> None:
    """Reject a P/V record cut inside one of its four numeric fields."""
    length = len(text.rstrip())
    for (start, stop), name in zip(_REC_COLS, names):
        if length < stop and (name != names[3] or length > start):
            raise FormatError(path, line_no, f"{sv} {name}", "the record is truncated "
                              f"(ends at column {length}, field ends at column {stop})")


def _scan_data(lines: list[str], first: int, sat_index: dict[str, int], path: Path):
    """Walk the data section: epoch times and the P and V record lines.

    Returns
    -------
    epochs : list of int
        ns since 1970 of each epoch.
    epoch_lines : list of int
        1-based line number of each epoch record.
    pos, vel : _Records
    eof : bool
        Whether an ``EOF`` line was found.
    """
    epochs, epoch_lines = [], []
    pos, vel = _Records(), _Records()
    sats = list(sat_index)
    for i in range(first, len(lines)):
        text = lines[i]
        kind = text[:1]
        if kind == "*":
            epochs.append(_parse_epoch_line(text, path, i + 1, last=i + 1 == len(lines)))
            epoch_lines.append(i + 1)
        elif kind in ("P", "V"):
            sv = _sat_id(text[1:4], path, i + 1)
            k = sat_index.get(sv)
            if k is None:
                raise FormatError(path, i + 1, "satellite", f"'{sv}' is not in the header "
                                  f"satellite list ({' '.join(sats[:5])} ...)")
            names = ("x", "y", "z", "clock") if kind == "P" else ("vx", "vy", "vz", "clock rate")
            _check_record_length(text, sv, names, path, i + 1)
            (pos if kind == "P" else vel).add(text, i + 1, len(epochs) - 1, k)
        elif text.startswith("EOF"):
            return epochs, epoch_lines, pos, vel, True
        elif text.startswith(("EP", "EV")) or not text.strip():
            continue  # correlation records are not read; blank lines are tolerated
        else:
            raise FormatError(path, i + 1, "record", f"unexpected line '{text[:20]}' in the "
                              "data section (expected '*', 'P', 'V', 'EP', 'EV' or 'EOF')")
    return epochs, epoch_lines, pos, vel, False


def _record_arrays(rec: _Records, sats: list[str], names: tuple[str, ...], path: Path):
    """Numeric columns of P or V records: values (N, 4) and exponents (N, 4), NaN if blank."""
    values = np.empty((len(rec.texts), 4))
    exps = np.empty((len(rec.texts), 4))
    # ranges of io._fields.RANGES in the file's units: km and µs (P), dm/s and 1e-4 µs/s (V);
    # the clock range holds the 999999.999999 "bad or absent" marker
    kinds = ("position_km",) * 3 + ("clock_us",) if names[0] == "x" else \
        ("velocity_dm_s",) * 3 + ("clock_us",)
    for j, ((start, stop), name) in enumerate(zip(_REC_COLS, names)):
        values[:, j] = parse_floats([t[start:stop] for t in rec.texts], rec.line_nos,
                                    lambda i, name=name: f"{sats[rec.sat[i]]} {name}", path,
                                    allow_blank=(j == 3), kind=kinds[j])
    for j, ((start, stop), name) in enumerate(zip(_EXP_COLS, names)):
        exps[:, j] = parse_floats([t[start:stop] for t in rec.texts], rec.line_nos,
                                  lambda i, name=name: f"{sats[rec.sat[i]]} {name} exponent",
                                  path, allow_blank=True, lo=0, hi=999)
    return values, exps


def _check_duplicates(rec: _Records, n_sat: int, sats: list[str], path: Path) -> None:
    """Reject two records of one satellite at one epoch."""
    key = np.asarray(rec.epoch, dtype=np.int64) * n_sat + np.asarray(rec.sat, dtype=np.int64)
    order = np.argsort(key, kind="stable")
    dup = np.nonzero(np.diff(key[order]) == 0)[0]
    if dup.size:
        i = order[dup[0] + 1]
        raise FormatError(path, rec.line_nos[i], "satellite", f"second record of "
                          f"{sats[rec.sat[i]]} at the same epoch")


def _grid(rec: _Records, values: np.ndarray, n_time: int, n_sat: int) -> np.ndarray:
    """Scatter per-record rows (N, k) onto a (time, sv, k) NaN grid."""
    out = np.full((n_time, n_sat, values.shape[1]), np.nan)
    out[np.asarray(rec.epoch, dtype=np.intp), np.asarray(rec.sat, dtype=np.intp)] = values
    return out


def _check_epochs(attrs: dict, epochs: list[int], epoch_lines: list[int], pos: _Records,
                  vel: _Records, eof: bool, n_sat: int, path: Path, n_lines: int) -> None:
    """Epoch order, declared vs actual number of epochs, and completeness without EOF."""
    ep = np.asarray(epochs, dtype=np.int64)
    bad = np.nonzero(np.diff(ep) <= 0)[0]
    if bad.size:
        raise FormatError(path, epoch_lines[bad[0] + 1], "epoch",
                          "epochs are not in increasing order")
    declared = attrs["_n_epochs"]
    if len(epochs) < declared and not eof:
        raise FormatError(path, n_lines, "number of epochs", f"the header declares {declared} "
                          f"epochs but the file has {len(epochs)}: the file is truncated")
    if len(epochs) != declared:  # a complete file (closed by EOF): io._fields.check_count
        logger.warning("%s: header declares %d epochs, file has %d and ends with EOF; all "
                       "are read", path, declared, len(epochs))
    if not eof:
        last = len(epochs) - 1
        n_pos = sum(1 for e in pos.epoch if e == last)
        n_vel = sum(1 for e in vel.epoch if e == last)
        if n_pos < n_sat or (attrs["pv_flag"] == "V" and n_vel < n_sat):
            raise FormatError(path, n_lines, "EOF", "the file ends without 'EOF' and its last "
                              f"epoch is incomplete ({n_pos} of {n_sat} satellites): truncated")
        records = pos if not vel.line_nos or pos.line_nos[-1] > vel.line_nos[-1] else vel
        if records.line_nos and records.line_nos[-1] == n_lines and \
                len(records.texts[-1].rstrip()) < _REC_COLS[3][1]:
            # issue 24: a file cut before the clock column of its last record (the clock is
            # optional) would be read with the clock missing
            raise FormatError(path, n_lines, "EOF", "the file ends without 'EOF' inside its "
                              "last record, before the clock column: truncated")


def read_sp3(path: str | Path, *, gps_time: bool = False) -> xr.Dataset:
    """Read an SP3-a/b/c/d orbit file (plain, .gz or .Z).

    Parameters
    ----------
    path : str or Path
        The SP3 file.
    gps_time : bool
        Convert the epochs from the file's time system (``%c`` line, columns 10-12; SP3-d
        table) to GPS time (:func:`leopod.time.scales.to_gps_time`: BDT, GAL, TAI, UTC);
        ``attrs["time_system"]`` becomes "GPS" and ``attrs["time_system_file"]`` keeps the
        file's. False: epochs as written.

    Returns
    -------
    xarray.Dataset
        Positions ``pos_m`` (time, sv, xyz) [m], clocks ``clk_s`` (time, sv) [s] and, when the
        file has them, velocities ``vel_m_s`` [m s-1], clock rates ``clk_rate_s_s`` and
        standard deviations; see the module docstring for the full schema.

    Raises
    ------
    FormatError
        If the file does not follow the SP3 format (see the module docstring), or, with
        ``gps_time``, its time system (GLO, QZS, IRN) has no conversion to GPS time.
    """
    path = Path(path)
    lines = read_lines(path)
    attrs, sats, accuracy, first = _parse_header(lines, path)
    tsys_line = attrs.pop("_time_system_line", None)
    n_sat = len(sats)
    sat_index = {sv: k for k, sv in enumerate(sats)}
    epochs, epoch_lines, pos, vel, eof = _scan_data(lines, first, sat_index, path)
    _check_epochs(attrs, epochs, epoch_lines, pos, vel, eof, n_sat, path, len(lines))
    _check_duplicates(pos, n_sat, sats, path)
    _check_duplicates(vel, n_sat, sats, path)
    n_time = len(epochs)

    p_values, p_exps = _record_arrays(pos, sats, ("x", "y", "z", "clock"), path)
    xyz_km = p_values[:, :3]
    xyz_km[(xyz_km == 0.0).all(axis=1)] = np.nan
    clk_us = p_values[:, 3]
    clk_us[np.abs(clk_us) >= _BAD_CLOCK] = np.nan
    times = np.asarray(epochs, dtype=np.int64).astype("datetime64[ns]")
    if gps_time:
        times = time_system_to_gps(times, attrs["time_system"], path, tsys_line,
                                   "time system")
        attrs.update(time_system_file=attrs["time_system"], time_system="GPS")
    coords = {"time": times, "sv": np.asarray(sats, dtype=str), "xyz": list(_XYZ)}
    grid = _grid(pos, np.column_stack([xyz_km * 1e3, clk_us * 1e-6]), n_time, n_sat)
    data = {
        "pos_m": (("time", "sv", "xyz"), grid[:, :, :3],
                  {"units": "m", "long_name": "satellite position"}),
        "clk_s": (("time", "sv"), grid[:, :, 3],
                  {"units": "s", "long_name": "satellite clock correction"}),
    }
    base_pos, base_clk = attrs.pop("_base_pos"), attrs.pop("_base_clk")
    if np.isfinite(p_exps).any() and base_pos > 0 and base_clk > 0:
        sig = np.column_stack([base_pos ** p_exps[:, :3] * 1e-3, base_clk ** p_exps[:, 3] * 1e-12])
        # the standard deviations a base and an exponent give must be physical (io._fields)
        check_range(sig[:, :3].ravel(), np.repeat(pos.line_nos, 3), "position std-dev "
                    "exponent", path, lo=0.0, hi=1e6)
        check_range(sig[:, 3], pos.line_nos, "clock std-dev exponent", path, lo=0.0, hi=1.0)
        sig = _grid(pos, sig, n_time, n_sat)
        data["pos_sigma_m"] = (("time", "sv", "xyz"), sig[:, :, :3],
                               {"units": "m", "long_name": "position standard deviation"})
        data["clk_sigma_s"] = (("time", "sv"), sig[:, :, 3],
                               {"units": "s", "long_name": "clock standard deviation"})
    if vel.texts:
        v_values, _ = _record_arrays(vel, sats, ("vx", "vy", "vz", "clock rate"), path)
        v_dm = v_values[:, :3]
        v_dm[(v_dm == 0.0).all(axis=1)] = np.nan
        rate = v_values[:, 3]
        rate[np.abs(rate) >= _BAD_CLOCK] = np.nan
        grid = _grid(vel, np.column_stack([v_dm * 0.1, rate * 1e-10]), n_time, n_sat)
        data["vel_m_s"] = (("time", "sv", "xyz"), grid[:, :, :3],
                           {"units": "m s-1", "long_name": "satellite velocity"})
        data["clk_rate_s_s"] = (("time", "sv"), grid[:, :, 3],
                                {"units": "s s-1", "long_name": "satellite clock rate"})
    # event flags of the P records (SP3-d, columns 75 and 79): only when the file sets one
    for name, col, char, text in _FLAGS:
        flag = np.array([t[col:col + 1] == char for t in pos.texts], dtype=bool)
        if flag.any():
            grid = np.zeros((n_time, n_sat), dtype=np.int8)
            grid[np.asarray(pos.epoch, dtype=np.intp)[flag],
                 np.asarray(pos.sat, dtype=np.intp)[flag]] = 1
            data[name] = (("time", "sv"), grid, {"units": "1", "long_name": text})
    data["orbit_accuracy_m"] = (("sv",), accuracy,
                                {"units": "m", "long_name": "header orbit accuracy (2**n mm)"})
    attrs.pop("_n_epochs")
    attrs["filename"] = path.name
    return xr.Dataset(data, coords=coords, attrs=attrs)

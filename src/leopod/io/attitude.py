"""Readers of attitude quaternion files: GRACE SCA1B ASCII and leopod's CSV / netCDF layout.

Every reader returns the same schema: ``quat`` (time, q) — unit quaternions from the inertial
frame (GCRF/J2000) to the satellite body frame, scalar first (``q`` = q0, q1, q2, q3), the
convention of :mod:`leopod.frames.quaternion` — with GPS-time labels.

**GRACE SCA1B ASCII** (Case et al. 2010, the SCA1B product and sec. 1.5 conventions): a
header of ``KEY : value`` records up to ``END OF HEADER`` (``TIME EPOCH (GPS TIME) : 2000-01-01
12:00:00``, ``NUMBER OF DATA RECORDS``), then one record a line: ``gps_time GRACE_id sca_id
quatangle quaticoeff quatjcoeff quatkcoeff qual_rss qualflg`` — integer seconds of GPS time past
the epoch, the satellite letter, the star-camera id, the quaternion (scalar ``quatangle`` first)
rotating the inertial frame into the satellite reference frame SRF (origin at the accelerometer
proof mass, +X towards the K-band horn, +Z to the Earth side, nadir-ish), the RSS of the
star-camera residuals and 8 quality bits (printed most significant first). The direction of the
rotation was checked on the data (:mod:`leopod.frames.quaternion`). The attitude does not
depend on the SRF origin; offsets of the antennas and the retro-reflector stay relative to the
centre of mass as configured. Binary ``.dat`` files are not read (convert them to ASCII with
the GRACE read software first).

**leopod attitude CSV** (written by :func:`leopod.io.attitude_write.write_attitude_csv`)::

    # leopod attitude 1.0
    # satellite: grace-a
    # time system: GPS
    # rotation: inertial (GCRF/J2000) -> body; quaternion scalar first (q0 = cos(angle/2))
    time,q0,q1,q2,q3
    2003-09-14T00:00:00.000000000,0.6001211159413961,-0.2133887325030409,...

Lines starting with ``#`` are comments (the first must be the ``# leopod attitude`` line);
``time`` is ISO 8601 in GPS time (up to nanoseconds); epochs strictly increasing; quaternions of
unit norm (within 1e-3; normalised on reading) and any sign (``q`` and ``−q`` are one rotation).

**leopod attitude netCDF**: the schema above written by :func:`leopod.io.netcdf.write_netcdf`
(:func:`leopod.io.attitude_write.write_attitude_netcdf`).
"""

from __future__ import annotations

import logging
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from leopod.frames.leo_attitude import LeoAttitude
from leopod.frames.quaternion import QuaternionSeries
from leopod.io._fields import is_digits, iso_epoch_ns, require_line_end
from leopod.io._text import FormatError, parse_float, parse_int, read_lines

__all__ = ["CSV_MAGIC", "attitude_dataset", "attitude_series", "load_leo_attitude",
           "read_attitude", "read_attitude_csv", "read_attitude_netcdf", "read_sca1b"]

logger = logging.getLogger(__name__)

#: First line of leopod's attitude CSV.
CSV_MAGIC = "# leopod attitude"
CSV_COLUMNS = ("time", "q0", "q1", "q2", "q3")
#: GRACE Level-1 time epoch (GPS time; Case et al. 2010, sec. 1.5.2).
GRACE_EPOCH = np.datetime64("2000-01-01T12:00:00", "ns")
_NORM_TOL = 1e-3
_Q_MAX = 1.0 + _NORM_TOL  # a component of a unit quaternion (io._fields contract)
_FRAME = "inertial (GCRF/J2000) -> body"


def attitude_dataset(times, quat: np.ndarray, *, source: str = "",
                     satellite: str = "", extra: Mapping[str, tuple] | None = None) -> xr.Dataset:
    """The attitude schema: ``quat`` (time, q) with its attributes.

    Parameters
    ----------
    times : array_like of datetime64, shape (n,)
        GPS-time labels.
    quat : ndarray, shape (n, 4)
        Inertial -> body quaternions, scalar first.
    source, satellite : str
        File name(s) and satellite, kept as attributes.
    extra : mapping, optional
        More ``{name: (dims, values, attrs)}`` variables.
    """
    ds = xr.Dataset(
        {"quat": (("time", "q"), np.asarray(quat, dtype=float),
                  {"units": "1", "long_name": "attitude quaternion, rotation from the inertial "
                   "frame (GCRF/J2000) to the satellite body frame, scalar first"}),
         **dict(extra or {})},
        coords={"time": np.asarray(times, dtype="datetime64[ns]"),
                "q": ["q0", "q1", "q2", "q3"]},
        attrs={"time_system": "GPS", "reference_frame": _FRAME,
               "quaternion_convention": "scalar first; columns of R(q) are the body axes in "
               "inertial coordinates (v_inertial = R(q) v_body)"})
    if source:
        ds.attrs["filename"] = source
    if satellite:
        ds.attrs["satellite"] = satellite
    return ds


def _unit(q: np.ndarray) -> np.ndarray:
    """Quaternions normalised where their norm is off by more than 1e-12 (the others kept as
    written, so that a file reads back bit-identical)."""
    norm = np.linalg.norm(q, axis=1, keepdims=True)
    return np.where(np.abs(norm - 1.0) > 1e-12, q / norm, q)


def _check_records(path: Path, t_ns: np.ndarray, quat: np.ndarray, lines: list[int]) -> None:
    bad = np.flatnonzero(np.diff(t_ns) <= 0)
    if bad.size:
        raise FormatError(path, lines[bad[0] + 1], "time", "epochs are not strictly increasing")
    norm = np.linalg.norm(quat, axis=1)
    bad = np.flatnonzero(np.abs(norm - 1.0) > _NORM_TOL)
    if bad.size:
        raise FormatError(path, lines[bad[0]], "quaternion",
                          f"norm {norm[bad[0]]:.6g} is not 1 (tolerance {_NORM_TOL:g})")


def read_sca1b(path: str | Path) -> xr.Dataset:
    """Read a GRACE SCA1B ASCII file (module docstring).

    Parameters
    ----------
    path : str or Path
        ``SCA1B_<yyyy>-<mm>-<dd>_<A|B>_<version>.asc`` (gzip accepted).

    Returns
    -------
    xarray.Dataset
        ``quat`` (time, q) normalised; ``sca_id`` (time), ``qual_rss`` (time) [1], ``qualflg``
        (time, the 8 bits as an integer); attrs ``satellite`` (``GRACE A``), ``filename``.

    Raises
    ------
    FormatError
        For a missing ``END OF HEADER`` or time epoch other than 2000-01-01 12:00:00, a
        record without 9 fields, a bad number, a quaternion not of unit norm, epochs out of
        order, or a record count other than the header's.
    """
    path = Path(path)
    lines = read_lines(path)
    end = next((k for k, text in enumerate(lines) if text.startswith("END OF HEADER")), None)
    if end is None:
        raise FormatError(path, None, "END OF HEADER", "no header end: not a GRACE Level-1B "
                          "ASCII file")
    header = {}
    for text in lines[:end]:
        key, sep, value = text.partition(":")
        if sep:
            header.setdefault(key.strip(), value.strip())
    epoch = header.get("TIME EPOCH (GPS TIME)", "")
    if not epoch.startswith("2000-01-01 12:00:00"):
        raise FormatError(path, None, "TIME EPOCH (GPS TIME)",
                          f"'{epoch}' is not 2000-01-01 12:00:00 (the GRACE Level-1 epoch)")
    satellite = header.get("SATELLITE NAME", "")
    t_s, quat, sca, rss, flags, line_nos = [], [], [], [], [], []
    for k in range(end + 1, len(lines)):
        text = lines[k]
        if not text.strip():
            continue
        no = k + 1
        parts = text.split()
        if len(parts) != 9:
            raise FormatError(path, no, "record", f"expected 9 fields (gps_time GRACE_id "
                              f"sca_id 4 quaternion components qual_rss qualflg), found "
                              f"{len(parts)}")
        # seconds past 2000-01-01 12:00 up to the contract's last year (2199)
        t_s.append(parse_int(parts[0], path, no, "gps_time", lo=0, hi=6_279_000_000))
        sca.append(parse_int(parts[2], path, no, "sca_id", lo=0, hi=99))
        quat.append([parse_float(parts[3 + j], path, no, name, lo=-_Q_MAX, hi=_Q_MAX)
                     for j, name in enumerate(("quatangle", "quaticoeff", "quatjcoeff",
                                               "quatkcoeff"))])
        rss.append(parse_float(parts[7], path, no, "qual_rss", lo=0.0, hi=1e6))
        if len(parts[8]) != 8 or set(parts[8]) - {"0", "1"}:
            raise FormatError(path, no, "qualflg", f"'{parts[8]}' is not 8 bits")
        flags.append(int(parts[8], 2))
        line_nos.append(no)
    if not t_s:
        raise FormatError(path, None, "record", "no data records")
    count = header.get("NUMBER OF DATA RECORDS")
    if count is not None and count.split() and is_digits(count.split()[0]) and \
            int(count.split()[0]) != len(t_s):
        raise FormatError(path, None, "NUMBER OF DATA RECORDS",
                          f"header says {count.split()[0]}, the file has {len(t_s)} records "
                          "(truncated?)")
    t_ns = np.array(t_s, dtype=np.int64) * 1_000_000_000
    q = np.array(quat)
    _check_records(path, t_ns, q, line_nos)
    times = GRACE_EPOCH + t_ns.astype("timedelta64[ns]")
    logger.info("read %d SCA1B quaternions %s to %s from %s", times.size, times[0], times[-1],
                path)
    return attitude_dataset(
        times, _unit(q), source=path.name,
        satellite=satellite,
        extra={"sca_id": ("time", np.array(sca, dtype=np.int16),
                          {"units": "1", "long_name": "star camera id (SCA1B sca_id)"}),
               "qual_rss": ("time", np.array(rss),
                            {"units": "1", "long_name": "RSS of star-camera residuals"}),
               "qualflg": ("time", np.array(flags, dtype=np.int16),
                           {"units": "1", "long_name": "SCA1B quality bits (bit 0 = LSB)"})})


def read_attitude_csv(path: str | Path) -> xr.Dataset:
    """Read leopod's attitude CSV (module docstring).

    Raises
    ------
    FormatError
        For a missing ``# leopod attitude`` first line or column line, a record without 5
        fields, a bad epoch or number, a quaternion not of unit norm, epochs out of order.
    """
    path = Path(path)
    lines = read_lines(path)
    require_line_end(lines, path)
    if not lines[0].startswith(CSV_MAGIC):
        raise FormatError(path, 1, "header", f"first line is not '{CSV_MAGIC} <version>'")
    meta, t_ns, quat, line_nos, columns = {}, [], [], [], False
    for k, text in enumerate(lines, start=1):
        s = text.strip()
        if not s:
            continue
        if s.startswith("#"):
            key, sep, value = s[1:].partition(":")
            if sep:
                meta[key.strip()] = value.strip()
            continue
        parts = [p.strip() for p in s.split(",")]
        if not columns:
            if tuple(parts) != CSV_COLUMNS:
                raise FormatError(path, k, "columns", f"expected '{','.join(CSV_COLUMNS)}', "
                                  f"got '{s}'")
            columns = True
            continue
        if len(parts) != 5:
            raise FormatError(path, k, "record", f"expected 5 comma-separated fields, found "
                              f"{len(parts)}")
        t_ns.append(iso_epoch_ns(parts[0], path, k, "time"))
        quat.append([parse_float(parts[1 + j], path, k, f"q{j}", lo=-_Q_MAX, hi=_Q_MAX)
                     for j in range(4)])
        line_nos.append(k)
    if meta.get("time system", "GPS") != "GPS":
        raise FormatError(path, None, "time system", f"'{meta['time system']}': only GPS time "
                          "is read")
    if not t_ns:
        raise FormatError(path, None, "record", "no data records")
    t = np.array(t_ns, dtype=np.int64)
    q = np.array(quat)
    _check_records(path, t, q, line_nos)
    return attitude_dataset(t.astype("datetime64[ns]"),
                            _unit(q), source=path.name,
                            satellite=meta.get("satellite", ""))


def read_attitude_netcdf(path: str | Path) -> xr.Dataset:
    """Read leopod's attitude netCDF (the schema of :func:`attitude_dataset`).

    Raises
    ------
    FormatError
        If the file has no ``quat`` (time, q) variable, its time system is not GPS, or a
        quaternion is not of unit norm or the epochs are out of order (line: None).
    """
    path = Path(path)
    try:
        with xr.open_dataset(path) as ds:
            ds = ds.load()
    except (OSError, ValueError, RuntimeError, KeyError) as err:  # damaged or not netCDF
        raise FormatError(path, None, "netCDF", f"cannot open the file ({err})") from None
    if "quat" not in ds or ds["quat"].dims != ("time", "q") or ds.sizes["q"] != 4:
        raise FormatError(path, None, "quat", "no quat (time, q=4) variable")
    if ds.attrs.get("time_system", "GPS") != "GPS":
        raise FormatError(path, None, "time_system", f"'{ds.attrs['time_system']}': only GPS "
                          "time is read")
    t = ds.time.values.astype("datetime64[ns]").astype(np.int64)
    q = ds["quat"].values.astype(float)
    _check_records(path, t, q, [None] * t.size)
    return attitude_dataset(t.astype("datetime64[ns]"),
                            _unit(q), source=path.name,
                            satellite=str(ds.attrs.get("satellite", "")))


def _sniff(path: Path) -> str:
    with open(path, "rb") as f:
        head = f.read(4096)
    if head[:4] in (b"\x89HDF", b"CDF\x01", b"CDF\x02"):
        return "netcdf"
    text = "\n".join(read_lines(path)[:40])
    if text.startswith(CSV_MAGIC):
        return "csv"
    if "SCA1B" in text and "END OF HEADER" in text:
        return "sca1b"
    raise FormatError(path, 1, "format", "not an attitude file leopod reads (GRACE SCA1B "
                      f"ASCII, '{CSV_MAGIC}' CSV or attitude netCDF)")


def read_attitude(path: str | Path, fmt: str = "auto") -> xr.Dataset:
    """Read an attitude file of any supported format (``auto``: from its first bytes)."""
    path = Path(path)
    fmt = _sniff(path) if fmt == "auto" else fmt
    readers = {"sca1b": read_sca1b, "csv": read_attitude_csv, "netcdf": read_attitude_netcdf}
    if fmt not in readers:
        raise ValueError(f"unknown attitude file format '{fmt}' (known: {', '.join(readers)})")
    return readers[fmt](path)


def attitude_series(datasets: Iterable[xr.Dataset], *, max_gap_s: float,
                    source: str = "") -> QuaternionSeries:
    """One quaternion series from attitude datasets (e.g. consecutive days).

    Records are put in time order; an epoch repeated in two files is kept once (the first).
    """
    parts = list(datasets)
    t = np.concatenate([d.time.values.astype("datetime64[ns]") for d in parts])
    q = np.concatenate([d["quat"].values for d in parts])
    order = np.argsort(t, kind="stable")
    t, q = t[order], q[order]
    keep = np.concatenate([[True], np.diff(t.astype(np.int64)) > 0])
    return QuaternionSeries(t[keep], q[keep], float(max_gap_s), source)


def load_leo_attitude(section: Mapping[str, Any] | LeoAttitude | None,
                      files: Iterable[str | Path] | str | Path | None = ()) -> LeoAttitude:
    """The attitude law of a satellite with its attitude files read (script boundary).

    Parameters
    ----------
    section : mapping, LeoAttitude or None
        ``satellites.<sat>`` (or its attitude keys, or a law).
    files : path or iterable of paths
        The attitude files of the job's days (the rule's ``attitude`` input); read only by
        the ``file`` law.

    Returns
    -------
    LeoAttitude
        The law; for ``file`` with its :class:`QuaternionSeries` attached.

    Raises
    ------
    ValueError
        For the ``file`` law without files.
    """
    law = LeoAttitude.of(section)
    paths = [files] if isinstance(files, str | Path) else list(files or ())
    if law.attitude != "file":
        return law
    if not paths:
        raise ValueError(f"attitude 'file' ({law.attitude_file.path}): the step has no "
                         "attitude file")
    data = [read_attitude(p, law.attitude_file.format) for p in paths]
    names = ", ".join(Path(p).name for p in paths)
    series = attitude_series(data, max_gap_s=law.attitude_file.max_gap_s, source=names)
    logger.info("attitude from %d file(s) (%s): %d records %s to %s", len(paths), names,
                series.times.size, series.times[0], series.times[-1])
    return law.with_series(series)

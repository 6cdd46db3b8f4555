"""Readers of the GRACE reference orbits and K-band range of the LEOGPS example (2010-07-27).

Files in ``../shared/data/grace-b_2010-208`` (origin: repo ``sammmlow/LEOGPS``):

``grca_truth.csv``, ``grcb_truth.csv``
    ``date,time,x,y,z,vx,vy,vz`` per line, no header: ``27/7/2010,00:00:10,...`` (day/month/
    year), position in km, velocity in dm/s; 10-s orbits of GRACE-A/B from a Bernese 5.2
    POD by CODE.
``grc_kb_rng.csv``
    ``date,time,range`` with the A–B distance in metres, integrated from the K-band range
    rate and initialised with a POD position fix (``reference_README.txt``).

What the files do not say, and how it was verified (tests in ``tests/io/test_grace_orbit_csv.py``):

- **Units**: the central difference of the positions matches the velocity scaled by 0.1
  (dm/s → m/s) to 0.15 mm/s RMS; speeds are 7.63 km/s and radii 6833 km (an altitude of
  ~455 km), as expected for GRACE in 2010.
- **Frame: Earth-fixed.** The second difference of the positions is matched to 0.1 mm/s² by
  point-mass + J2 gravity plus the Coriolis and centrifugal accelerations of a frame rotating
  at the Earth rate, while without them (an inertial frame) the residual is 0.56 m/s² — the
  Coriolis term ``2 ω × v`` ≈ 1.1 m/s². Single point positioning from the GRACE-B onboard
  code (``GRCB2080.10D``) with the CODE orbits and clocks (IGS05, Earth-fixed) lands 1.4 m
  (median) from ``grcb_truth.csv``; an inertial frame would put it hundreds of km away. The
  frame is thus that of the CODE products, IGS05 (ITRF2005) in 2010.
- **Time scale: GPS time.** The same SPP solution (RINEX epochs in GPS time) is 7.6 km from
  the truth orbit if the labels are shifted by 1 s and 114 km for 15 s (GPS − UTC in 2010);
  the least-squares timing offset of the truth against it is 7 µs. The K-band range agrees
  with ``|r_A − r_B|`` to 1 cm RMS at zero shift and the least-squares timing offset between
  them is 1.2 ms (range rate up to 2 m/s), so the K-band labels are GPS time as well.

The position records have 1e-6 km (1 mm) resolution, the velocities 1e-5 dm/s (1 µm/s).
"""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.io._fields import integer, number, require_line_end
from leopod.io._text import FormatError, calendar_epoch_ns, parse_floats, read_lines
from leopod.io.netcdf import atomic_path

__all__ = ["read_grace_orbit_csv", "read_kband_range_csv", "write_kband_range_csv"]

logger = logging.getLogger(__name__)

#: File units to SI: position km → m, velocity dm/s → m/s.
_KM_TO_M = 1000.0
_DM_S_TO_M_S = 0.1
_ORBIT_FIELDS = ("x", "y", "z", "vx", "vy", "vz")
_RANGE_FIELDS = ("range",)
#: Physical range of each field (io._fields.RANGES) in the file's units (km, dm/s, m).
_KINDS = {"x": "position_km", "y": "position_km", "z": "position_km",
          "vx": "velocity_dm_s", "vy": "velocity_dm_s", "vz": "velocity_dm_s",
          "range": "range_m"}


def _epoch_ns(date: str, clock: str, path: Path, line: int) -> int:
    """Nanoseconds since 1970 of ``d/m/yyyy`` and ``hh:mm:ss[.f]``."""
    day = date.strip().split("/")
    hms = clock.strip().split(":")
    if len(day) != 3 or len(hms) != 3:
        raise FormatError(path, line, "epoch", f"expected d/m/yyyy,hh:mm:ss, got "
                          f"'{date},{clock}'")
    d, m, y, hh, mm = (integer(t, path, line, "epoch") for t in (*day, *hms[:2]))
    sec = number(hms[2], path, line, "epoch", lo=0.0, hi=60.0)
    return calendar_epoch_ns((y, m, d, hh, mm), sec, path, line)


def _read_table(path: str | Path, fields: tuple[str, ...]) -> tuple[np.ndarray, np.ndarray]:
    """Epochs (datetime64[ns], (n,)) and values ((n, len(fields))) of a CSV of this family."""
    path = Path(path)
    lines = read_lines(path)
    require_line_end(lines, path)
    n_col = 2 + len(fields)
    epochs, texts, line_nos = [], [], []
    for k, text in enumerate(lines, start=1):
        if not text.strip():
            continue
        parts = text.split(",")
        if len(parts) != n_col:
            raise FormatError(path, k, "record", f"expected {n_col} comma-separated fields, "
                              f"found {len(parts)}")
        epochs.append(_epoch_ns(parts[0], parts[1], path, k))
        texts.append(parts[2:])
        line_nos.append(k)
    if not epochs:
        raise FormatError(path, None, "record", "no data lines")
    t = np.array(epochs, dtype=np.int64)
    bad = np.nonzero(np.diff(t) <= 0)[0]
    if bad.size:
        raise FormatError(path, line_nos[bad[0] + 1], "epoch",
                          "epochs are not strictly increasing")
    cols = np.array(texts, dtype=object)
    values = np.column_stack([parse_floats(list(cols[:, j]), line_nos, name, path,
                                           kind=_KINDS[name])
                              for j, name in enumerate(fields)])
    return t.astype("datetime64[ns]"), values


def read_grace_orbit_csv(path: str | Path) -> xr.Dataset:
    """Read ``grca_truth.csv`` / ``grcb_truth.csv`` into the orbit schema.

    Parameters
    ----------
    path : str or Path
        The CSV file (``date,time,x,y,z,vx,vy,vz``; km and dm/s).

    Returns
    -------
    xarray.Dataset
        ``pos_itrf_m`` (time, xyz) [m] and ``vel_itrf_m_s`` (time, xyz) [m/s], Earth-fixed;
        ``time`` GPS-time labels; attrs ``time_system="GPS"``, ``reference_frame``,
        ``filename``.

    Raises
    ------
    FormatError
        For a line without 8 fields, a bad date/time or number, or epochs out of order.
    """
    t, v = _read_table(path, _ORBIT_FIELDS)
    frame = {"reference_frame": "ITRF (IGS05, Earth-fixed; CODE Bernese 5.2 orbit)"}
    logger.info("read %d GRACE orbit epochs %s to %s from %s", t.size, t[0], t[-1], path)
    return xr.Dataset(
        {"pos_itrf_m": (("time", "xyz"), v[:, :3] * _KM_TO_M,
                        {"units": "m", "long_name": "centre-of-mass position", **frame}),
         "vel_itrf_m_s": (("time", "xyz"), v[:, 3:] * _DM_S_TO_M_S,
                          {"units": "m s-1", "long_name": "Earth-fixed velocity", **frame})},
        coords={"time": t, "xyz": ["x", "y", "z"]},
        attrs={"time_system": "GPS", **frame, "filename": Path(path).name})


def read_kband_range_csv(path: str | Path) -> xr.Dataset:
    """Read ``grc_kb_rng.csv``: the GRACE A–B distance derived from the K-band range rate.

    Parameters
    ----------
    path : str or Path
        The CSV file (``date,time,range``; metres).

    Returns
    -------
    xarray.Dataset
        ``range_m`` (time) [m] with GPS-time labels; attrs ``time_system="GPS"``,
        ``filename``. The range is the integral of the K-band range rate started from a POD
        position fix, so it carries the fix's error as a constant and an integration drift.

    Raises
    ------
    FormatError
        For a line without 3 fields, a bad date/time or number, or epochs out of order.
    """
    t, v = _read_table(path, _RANGE_FIELDS)
    logger.info("read %d K-band range epochs from %s", t.size, path)
    return xr.Dataset(
        {"range_m": ("time", v[:, 0], {"units": "m", "long_name": "GRACE-A to GRACE-B "
                                       "distance from the integrated K-band range rate"})},
        coords={"time": t}, attrs={"time_system": "GPS", "filename": Path(path).name})


def write_kband_range_csv(ds: xr.Dataset, path: str | Path, decimals: int = 6) -> None:
    """Write an inter-satellite range series in the ``grc_kb_rng.csv`` layout.

    Parameters
    ----------
    ds : xarray.Dataset
        ``range_m`` (time) [m], GPS-time labels on whole or fractional seconds.
    path : str or Path
        File to write (atomically).
    decimals : int
        Digits after the decimal point of the range (6: 1 µm, the K-band ranging precision;
        the LEOGPS file has 4).
    """
    t = ds.time.values.astype("datetime64[ns]")
    day = t.astype("datetime64[D]")
    ymd = [str(d).split("-") for d in day]
    ns = (t - day).astype(np.int64)
    lines = []
    for (y, m, d), n, r in zip(ymd, ns, ds.range_m.values, strict=True):
        hh, rem = divmod(int(n), 3_600_000_000_000)
        mm, rem = divmod(rem, 60_000_000_000)
        sec = f"{rem // 1_000_000_000:02d}" + (f".{rem % 1_000_000_000:09d}".rstrip("0")
                                                if rem % 1_000_000_000 else "")
        lines.append(f"{int(d)}/{int(m)}/{y},{hh:02d}:{mm:02d}:{sec},{r:.{decimals}f}\n")
    with atomic_path(path) as tmp:
        Path(tmp).write_text("".join(lines))

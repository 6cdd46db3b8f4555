"""Writers of SINEX 2.02 files: station coordinates (minimal) and station eccentricities.

:func:`write_sinex_stations` writes SITE/ID, SOLUTION/EPOCHS and SOLUTION/ESTIMATE, read back by
:func:`leopod.io.sinex.read_sinex_stations`.

:func:`write_sinex_eccentricities` writes a SITE/ECCENTRICITY file (ILRS ``ecc_xyz.snx``
layout), read back by :func:`leopod.io.sinex.read_sinex_eccentricities`: a ``%=SNX 2.02``
header, the SITE/ECCENTRICITY block in the fixed columns of SINEX 2.02 (site code, point code,
solution, observation technique, validity interval, reference system ``UNE`` or ``XYZ``, three
components [m] in slots of 9 characters (a blank and F8.4 below 1 km; larger values take the
whole slot with fewer decimals, as the ILRS file does), and the ILRS CDP system-occupation
designator after column 80 when given) and ``%ENDSNX``.
"""

from __future__ import annotations

import datetime as _dt
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.io._text import creation_time, write_text
from leopod.io.sinex import _XYZ

__all__ = ["write_sinex_eccentricities", "write_sinex_stations"]


def _sinex_epoch(t) -> str:
    """``YY:DOY:SSSSS`` of a datetime64 (rounded to 1 s); ``00:000:00000`` for NaT."""
    t = np.datetime64(t, "ns")
    if np.isnat(t):
        return "00:000:00000"
    d = (t + np.timedelta64(500, "ms")).astype("datetime64[s]").astype(_dt.datetime)
    if not 1950 <= d.year <= 2049:
        raise ValueError(f"{t} cannot be written as a SINEX epoch (years 1950-2049)")
    sec = d.hour * 3600 + d.minute * 60 + d.second
    return f"{d.year % 100:02d}:{d.timetuple().tm_yday:03d}:{sec:05d}"


def write_sinex_stations(ds: xr.Dataset, path: str | Path, *, agency: str = "LEO",
                         technique: str = "L", created: _dt.datetime | None = None) -> None:
    """Write station coordinates as a minimal SINEX 2.02 file.

    Blocks SITE/ID, SOLUTION/EPOCHS and SOLUTION/ESTIMATE (STAX/Y/Z, and VELX/Y/Z where
    ``vel_m_y`` is finite) — enough for :func:`read_sinex_stations` to read it back
    (positions to 15 significant digits, epochs to 1 s).

    Parameters
    ----------
    ds : xarray.Dataset
        Dimension ``solution`` with ``site``, ``pos_m`` (solution, xyz) [m] and
        ``ref_epoch``; optional ``pt`` ("A"), ``soln`` (1), ``domes`` (""), ``description``
        (""), ``approx_*`` (blank), ``sigma_pos_m`` (0), ``vel_m_y``, ``sigma_vel_m_y``,
        ``valid_from``/``valid_to`` (open).
    path : str or Path
        Output file.
    agency : str
        3-character agency code of the header line.
    technique : str
        Observation technique code of SITE/ID ("L" SLR, "P" GNSS, "R" VLBI, "D" DORIS).
    created : datetime, optional
        Creation time of the header line (UTC); default
        :func:`leopod.io._text.creation_time` (``SOURCE_DATE_EPOCH`` or the wall clock).

    Raises
    ------
    ValueError
        Missing variable, no solution, non-finite position, NaT reference epoch, epoch outside 1950-2049,
        site code longer than 4 characters.
    """
    for name in ("site", "pos_m", "ref_epoch"):
        if name not in ds.variables:
            raise ValueError(f"write_sinex_stations needs the variable '{name}'")
    n = ds.sizes.get("solution", 0)
    if n == 0:
        raise ValueError("write_sinex_stations: the dataset has no solution to write")

    def get(name, default):
        return np.asarray(ds[name].values) if name in ds.variables else np.full(n, default)

    site = get("site", "").astype(str)
    pt = get("pt", "A").astype(str)
    soln = get("soln", 1).astype(int)
    pos = ds["pos_m"].transpose("solution", "xyz").values
    sig = (ds["sigma_pos_m"].transpose("solution", "xyz").values
           if "sigma_pos_m" in ds.variables else np.zeros((n, 3)))
    vel = (ds["vel_m_y"].transpose("solution", "xyz").values
           if "vel_m_y" in ds.variables else np.full((n, 3), np.nan))
    sigv = (ds["sigma_vel_m_y"].transpose("solution", "xyz").values
            if "sigma_vel_m_y" in ds.variables else np.zeros((n, 3)))
    ref = get("ref_epoch", np.datetime64("NaT")).astype("datetime64[ns]")
    start = get("valid_from", np.datetime64("NaT")).astype("datetime64[ns]")
    end = get("valid_to", np.datetime64("NaT")).astype("datetime64[ns]")
    if not np.isfinite(pos).all():
        raise ValueError("write_sinex_stations: pos_m must be finite")
    if np.isnat(ref).any():
        raise ValueError("write_sinex_stations: ref_epoch contains NaT")
    bad = [s for s in site if not s or len(s) > 4 or " " in s]
    if bad:
        raise ValueError(f"write_sinex_stations: site code '{bad[0]}' is not 1-4 characters")

    site_lines = _site_id_lines(site, pt, get, technique)
    epoch_lines = [f" {s:>4s} {p:>2s} {k:4d} C {_sinex_epoch(a)} {_sinex_epoch(b)} "
                   f"{_sinex_epoch(r)}" for s, p, k, a, b, r in
                   zip(site, pt, soln, start, end, ref)]
    est_lines = []
    for i in range(n):
        params = [(f"STA{c.upper()}", "m", pos[i, k], sig[i, k]) for k, c in enumerate(_XYZ)]
        if np.isfinite(vel[i]).all():
            params += [(f"VEL{c.upper()}", "m/y", vel[i, k], sigv[i, k])
                       for k, c in enumerate(_XYZ)]
        for ptype, unit, value, sigma in params:
            sigma = 0.0 if not np.isfinite(sigma) else sigma
            est_lines.append(f" {len(est_lines) + 1:5d} {ptype:<6s} {site[i]:>4s} {pt[i]:>2s} "
                             f"{soln[i]:4d} {_sinex_epoch(ref[i])} {unit:<4s} 2 "
                             f"{value:21.14E} {sigma:11.5E}")
    first = np.concatenate([start[~np.isnat(start)], ref]).min()
    last = np.concatenate([end[~np.isnat(end)], ref]).max()
    now = _sinex_epoch(np.datetime64(creation_time(created)))
    head = (f"%=SNX 2.02 {agency:<3.3s} {now} {agency:<3.3s} {_sinex_epoch(first)} "
            f"{_sinex_epoch(last)} C {len(est_lines):05d} 2 S")
    out = [head]
    out += _block("SITE/ID", "*CODE PT __DOMES__ T _STATION DESCRIPTION__ APPROX_LON_ "
                  "APPROX_LAT_ _APP_H_", site_lines)
    out += _block("SOLUTION/EPOCHS", "*CODE PT SOLN T _DATA_START_ __DATA_END__ _MEAN_EPOCH_",
                  epoch_lines)
    out += _block("SOLUTION/ESTIMATE", "*INDEX TYPE__ CODE PT SOLN _REF_EPOCH__ UNIT S "
                  "__ESTIMATED VALUE____ _STD_DEV___", est_lines)
    out.append("%ENDSNX")
    write_text(path, "\n".join(out) + "\n")


def _block(title: str, columns: str, lines: list[str]) -> list[str]:
    return [f"+{title}", columns, *lines, f"-{title}"]


def _site_id_lines(site, pt, get, technique: str) -> list[str]:
    """SITE/ID lines, one per site/point (first occurrence)."""
    domes = get("domes", "").astype(str)
    desc = get("description", "").astype(str)
    lon = get("approx_lon_deg", np.nan).astype(float)
    lat = get("approx_lat_deg", np.nan).astype(float)
    h = get("approx_height_m", np.nan).astype(float)
    out, seen = [], set()
    for i in range(len(site)):
        if (site[i], pt[i]) in seen:
            continue
        seen.add((site[i], pt[i]))
        height = f"{h[i]:7.1f}" if np.isfinite(h[i]) else " " * 7
        out.append(f" {site[i]:>4s} {pt[i]:>2s} {domes[i]:<9.9s} {technique:1.1s} "
                   f"{desc[i]:<22.22s} "
                   f"{_dms_text(lon[i] % 360.0 if np.isfinite(lon[i]) else lon[i])} "
                   f"{_dms_text(lat[i])} {height}")
    return out


def _dms_text(deg: float) -> str:
    """``ddd mm ss.s`` (11 characters) of an angle in degrees; blank if NaN."""
    if not np.isfinite(deg):
        return " " * 11
    tenths = round(abs(deg) * 36_000)
    d, rest = divmod(tenths, 36_000)
    m, s = divmod(rest, 600)
    sign = "-" if deg < 0 else ""
    return f"{sign + str(d):>3s} {m:2d} {s / 10:4.1f}"


# ------------------------------------------------------------------------------ eccentricities
_SLOT = 9
"""Characters per eccentricity component (SINEX 2.02 SITE/ECCENTRICITY: 1X, F8.4)."""
_MAX_ECC_M = 1e5


def _component(value: float) -> str:
    """The value in a 9-character slot with as many decimals (<= 4) as fit."""
    for decimals in range(4, -1, -1):
        text = f"{value:{_SLOT}.{decimals}f}"
        if len(text) <= _SLOT:
            return text
    raise ValueError(f"eccentricity {value} m does not fit the SINEX field")


def write_sinex_eccentricities(ds: xr.Dataset, path: str | Path, *, agency: str = "LEO",
                               technique: str = "L") -> None:
    """Write eccentricities in the schema of :func:`leopod.io.sinex.read_sinex_eccentricities`.

    Parameters
    ----------
    ds : xarray.Dataset
        Dimension ``record`` with ``site``, ``ref_system`` ("UNE" or "XYZ") and ``ecc_m``
        (record, component) [m]; optional ``pt`` ("A"), ``soln`` (1), ``valid_from``,
        ``valid_to`` (open), ``cdp_sod`` ("").
    path : str or Path
        Output file.
    agency : str
        3-character agency code of the header line.
    technique : str
        Observation technique code ("L" SLR).

    Raises
    ------
    ValueError
        Missing variable, no record, non-finite or too large (>= 100 km) eccentricity,
        unknown reference system, site code longer than 4 characters.
    """
    for name in ("site", "ref_system", "ecc_m"):
        if name not in ds.variables:
            raise ValueError(f"write_sinex_eccentricities needs the variable '{name}'")
    n = ds.sizes.get("record", 0)
    if n == 0:
        raise ValueError("write_sinex_eccentricities: no record to write")

    def get(name, default):
        return np.asarray(ds[name].values) if name in ds.variables else np.full(n, default)

    site = get("site", "").astype(str)
    system = get("ref_system", "").astype(str)
    ecc = np.asarray(ds["ecc_m"].values, dtype=float).reshape(n, 3)
    start = get("valid_from", np.datetime64("NaT")).astype("datetime64[ns]")
    end = get("valid_to", np.datetime64("NaT")).astype("datetime64[ns]")
    if not (np.isfinite(ecc).all() and np.all(np.abs(ecc) < _MAX_ECC_M)):
        raise ValueError("write_sinex_eccentricities: ecc_m must be finite and below 100 km")
    bad = [s for s in system if s not in ("UNE", "XYZ")]
    if bad:
        raise ValueError(f"write_sinex_eccentricities: reference system '{bad[0]}' is neither "
                         "UNE nor XYZ")
    bad = [s for s in site if not s or len(s) > 4 or " " in s]
    if bad:
        raise ValueError(f"write_sinex_eccentricities: site code '{bad[0]}' is not 1-4 "
                         "characters")
    lines = [f" {s:>4s} {p:>2s} {k:4d} {technique:1.1s} {_sinex_epoch(a)} {_sinex_epoch(b)} "
             f"{sys}" + "".join(_component(v) for v in e) + (f"        {sod}" if sod else "")
             for s, p, k, a, b, sys, e, sod in zip(
                 site, get("pt", "A").astype(str), get("soln", 1).astype(int), start, end,
                 system, ecc, get("cdp_sod", "").astype(str))]
    known = np.concatenate([start[~np.isnat(start)], end[~np.isnat(end)]])
    first = known.min() if known.size else np.datetime64("NaT")
    last = known.max() if known.size else np.datetime64("NaT")
    head = (f"%=SNX 2.02 {agency:<3.3s} {_sinex_epoch(first)} {agency:<3.3s} "
            f"{_sinex_epoch(first)} {_sinex_epoch(last)} {technique:1.1s} {n:05d} 0 X")
    out = [head, "+SITE/ECCENTRICITY",
           "*SITE PT SOLN T DATA_START__ DATA_END____ AXE MARKER->REFERENCE POINT (M)",
           *lines, "-SITE/ECCENTRICITY", "%ENDSNX"]
    write_text(path, "\n".join(out) + "\n")

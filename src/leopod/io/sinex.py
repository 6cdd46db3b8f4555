"""SINEX station coordinates, velocities and eccentricities: reader and lookups.

Specification: "SINEX - Solution (Software/technique) INdependent EXchange Format, Version
2.02" (IERS, 2006; 2.00 and 2.01 read the same way). Only the blocks needed for station
positions are read: SITE/ID, SOLUTION/EPOCHS, SOLUTION/ESTIMATE (parameter types STAX, STAY,
STAZ, VELX, VELY, VELZ; other types such as EOP are skipped) and SITE/ECCENTRICITY. Data
lines are read in the fixed columns of the specification; lines starting with ``*`` are
comments, and a column-title line without the ``*`` as first line of a block (ILRS daily
files) is skipped.

SINEX epochs ``YY:DOY:SSSSS``: YY < 50 is 20YY, otherwise 19YY; ``00:000:00000`` is an open
bound (NaT). Validity bounds with day of year 000 are also read as open (SLRF2014 writes
``50:000:00000`` for "no end"); a reference epoch must be a real date. Epochs are nominally
UTC (the format does not say; the difference is irrelevant for station coordinates), 1 s
resolution. Velocities are per Julian year (365.25 d), as in ITRF.

Dataset of :func:`read_sinex_stations`, dimension ``solution`` (one row per site code +
point code + solution number found in SOLUTION/ESTIMATE), coordinate ``xyz = [x, y, z]``:

=================  ================  ==================================================
variable           units             meaning
=================  ================  ==================================================
site               1                 4-character site code (CDP pad id for SLR)
pt                 1                 point code ("A")
soln               1                 solution number (int)
domes              1                 DOMES number (SITE/ID; "" if the site is not listed)
description        1                 station description (SITE/ID)
approx_lon_deg     degree_east       approximate longitude (SITE/ID; NaN if absent)
approx_lat_deg     degree_north      approximate latitude
approx_height_m    m                 approximate height
pos_m              m                 (solution, xyz) position at ref_epoch
sigma_pos_m        m                 (solution, xyz) standard deviation
vel_m_y            m yr-1            (solution, xyz) velocity; NaN where the file has none
sigma_vel_m_y      m yr-1            (solution, xyz)
ref_epoch          -                 datetime64[ns] reference epoch of the position
valid_from         -                 datetime64[ns] SOLUTION/EPOCHS data start (NaT = open)
valid_to           -                 datetime64[ns] SOLUTION/EPOCHS data end (NaT = open)
=================  ================  ==================================================

In ITRF/SLRF files the SOLUTION/EPOCHS interval is the validity of the solution (between
discontinuities); in weekly/daily combinations it is the span of the data used.

Dataset of :func:`read_sinex_eccentricities`, dimension ``record`` (one per line of
SITE/ECCENTRICITY; a site/point/solution may have several lines with different intervals):
``site``, ``pt``, ``soln``, ``ref_system`` ("UNE" = up/north/east or "XYZ"), ``ecc_m``
(record, component) [m] from the marker to the reference point, ``valid_from``,
``valid_to``, ``cdp_sod`` (the ILRS CDP system-occupation designator after column 80, "" if
absent). ``component`` is ``[x, y, z]`` or ``[u, n, e]`` when all lines share one system,
``[x|u, y|n, z|e]`` when they are mixed; ``attrs["ref_system"]`` is "XYZ", "UNE" or "mixed".

attrs of both: ``format`` ("SINEX 2.02"), ``agency``, ``creation_epoch``, ``data_start``,
``data_end`` (ISO strings, "" if open), ``n_estimates`` (of the header line, when given),
``time_system`` ("UTC"), ``source``.

The ``%=SNX`` header line is read in its fixed columns (SINEX 2.02: blank agency fields, as in
JAXA's MGEX files, do not shift the epochs). A SOLN field of dashes (``----``, SINEX 2.02
Appendix I: a field without a value is filled with "-"; IGS combinations write it in
SOLUTION/EPOCHS and SITE/ECCENTRICITY) is read as :data:`ANY_SOLUTION` (-1), a record that
holds for every solution of the site. A header estimate count that disagrees with
SOLUTION/ESTIMATE of the complete file is logged as a warning. Values follow the reader
contract (:mod:`leopod.io._fields`): positions within 1e9 m, velocities within 1e5 m/y.
"""

from __future__ import annotations

import logging
import math
import re
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.io._fields import check_count, is_digits
from leopod.io._text import (
    FormatError,
    parse_float,
    parse_int,
    read_lines,
)

__all__ = [
    "ANY_SOLUTION",
    "read_sinex_eccentricities",
    "read_sinex_stations",
    "station_eccentricities",
    "station_eccentricity",
    "station_position",
    "station_positions",
]

_LOG = logging.getLogger(__name__)

#: Solution number of a record whose SOLN field is "----" (SINEX 2.02 Appendix I: a field
#: without a value is filled with "-"; IGS combinations write it in SOLUTION/EPOCHS and
#: SITE/ECCENTRICITY, meaning the record holds for every solution of the site).
ANY_SOLUTION = -1
_DATE = re.compile(r"^(\d{2}):(\d{3}):(\d{5})$")
_JULIAN_YEAR_NS = 365.25 * 86_400e9
_STA = {"STAX": 0, "STAY": 1, "STAZ": 2}
_VEL = {"VELX": 0, "VELY": 1, "VELZ": 2}
_XYZ = ["x", "y", "z"]


# ------------------------------------------------------------------------------- structure
def _blocks(path: Path, lines: list[str]) -> tuple[dict, dict]:
    """Split a SINEX file into its blocks.

    Returns
    -------
    header : dict
        Fields of the ``%=SNX`` line.
    blocks : dict
        Block title (e.g. ``"SOLUTION/ESTIMATE"``, ``"SOLUTION/MATRIX_ESTIMATE L COVA"``) ->
        list of (1-based line number, text) of its data lines.
    """
    if not lines or not lines[0].startswith("%=SNX"):
        raise FormatError(path, 1, "%=SNX", "the first line is not a SINEX header '%=SNX ...'")
    header = _header(path, lines[0])
    blocks: dict = {}
    current = None
    ended = False
    for ln, text in enumerate(lines[1:], start=2):
        if not text.strip() or text.startswith("*"):
            continue
        if text.startswith("%ENDSNX"):
            ended = True
            break
        if text.startswith("+"):
            if current is not None:
                raise FormatError(path, ln, text.split()[0], f"block starts inside block "
                                  f"'{current}' (missing -{current})")
            current = text[1:].strip()
            if current in blocks:
                raise FormatError(path, ln, current, "block appears twice")
            blocks[current] = []
        elif text.startswith("-"):
            title = text[1:].strip()
            if title != current:
                raise FormatError(path, ln, title, f"end of block '{title}' does not match "
                                  f"the open block '{current}'")
            current = None
        elif current is None:
            raise FormatError(path, ln, "line", "data line outside any +BLOCK/-BLOCK")
        elif not text.startswith(" ") and not blocks[current]:
            _LOG.debug("%s:%d: untagged column-title line in %s skipped", path, ln, current)
        else:
            blocks[current].append((ln, text))
    if current is not None:
        raise FormatError(path, len(lines), f"-{current}", f"block '{current}' is not closed "
                          "at the end of the file (file cut short?)")
    if not ended:
        raise FormatError(path, len(lines), "%ENDSNX", "no %ENDSNX line at the end of the "
                          "file (file cut short?)")
    return header, blocks


def _header(path: Path, text: str) -> dict:
    """Agency, creation and data-span epochs of the ``%=SNX`` header line.

    Read in the fixed columns of SINEX 2.02 (section "Header line": agency 12-14, creation
    epoch 16-27, data agency 29-31, data start 33-44, data end 46-57), so that a blank agency
    field (JAXA's MGEX files) does not shift the epochs; a line that does not follow the
    columns is read split on blanks.
    """
    columns = (text[11:14], text[15:27], text[32:44], text[45:57], text[60:65])
    if _DATE.match(columns[1].strip()) and all(text[k:k + 1] in (" ", "") for k in (10, 14)):
        agency, created, first, last, count = (c.strip() for c in columns)
    else:
        t = text.split()
        if len(t) < 7 or t[0] != "%=SNX":
            raise FormatError(path, 1, "%=SNX", "header line has too few fields")
        agency, created, first, last = t[2], t[3], t[5], t[6]
        count = t[8] if len(t) > 8 else ""
    start = _epoch(path, 1, "%=SNX data start", first, open_ok=True)
    end = _epoch(path, 1, "%=SNX data end", last, open_ok=True)
    return {
        "format": f"SINEX {text[6:10].strip()}",
        "agency": agency,
        "creation_epoch": _iso(_epoch(path, 1, "%=SNX creation epoch", created, open_ok=True)),
        "data_start": _iso(start),
        "data_end": _iso(end),
        **({"n_estimates": parse_int(count, path, 1, "%=SNX number of estimates", lo=0)}
           if is_digits(count) else {}),
    }


def _iso(t: np.datetime64) -> str:
    return "" if np.isnat(t) else str(t.astype("datetime64[s]"))


def _epoch(path: Path, ln: int, field: str, text: str, *, open_ok: bool) -> np.datetime64:
    """A SINEX epoch ``YY:DOY:SSSSS`` as datetime64[ns] (NaT for an open bound)."""
    m = _DATE.match(text.strip())
    if m is None:
        raise FormatError(path, ln, field, f"'{text.strip()}' is not an epoch YY:DOY:SSSSS")
    yy, doy, sec = (int(g) for g in m.groups())
    if doy == 0 and sec == 0 and open_ok:
        return np.datetime64("NaT", "ns")
    year = 2000 + yy if yy < 50 else 1900 + yy
    ndays = 366 if year % 4 == 0 and (year % 100 != 0 or year % 400 == 0) else 365
    if not (1 <= doy <= ndays and sec <= 86_400):
        raise FormatError(path, ln, field, f"'{text.strip()}' is not a valid epoch "
                          f"(day {doy} of {year}, second {sec})")
    return (np.datetime64(f"{year:04d}-01-01", "ns") + np.timedelta64(doy - 1, "D")
            + np.timedelta64(sec, "s"))


def _require(path: Path, blocks: dict, name: str) -> list:
    if name not in blocks:
        raise FormatError(path, None, name, f"mandatory block +{name} is missing")
    return blocks[name]


def _field(text: str, start: int, stop: int) -> str:
    return text[start:stop].strip()


def _soln_key(path: Path, ln: int, text: str, code_col: int = 1) -> tuple[str, str, int]:
    """(site, pt, soln) of a data line whose site code starts at ``code_col``."""
    site = _field(text, code_col, code_col + 4)
    if not site:
        raise FormatError(path, ln, "CODE", "site code is blank")
    pt = _field(text, code_col + 5, code_col + 7)
    soln_text = text[code_col + 8:code_col + 12].strip()
    if soln_text and set(soln_text) == {"-"}:
        return site, pt, ANY_SOLUTION  # SINEX 2.02 Appendix I: empty fields are "-"-filled
    soln = parse_int(soln_text, path, ln, "SOLN", lo=0)
    return site, pt, soln


# ---------------------------------------------------------------------------------- stations
def read_sinex_stations(path: str | Path) -> xr.Dataset:
    """Read station positions and velocities of a SINEX file.

    Parameters
    ----------
    path : str or Path
        SINEX 2.x file (may be compressed).

    Returns
    -------
    xarray.Dataset
        Dimension ``solution``; schema in the module docstring.

    Raises
    ------
    FormatError
        Missing header, SITE/ID or SOLUTION/ESTIMATE block, unclosed block, missing
        ``%ENDSNX``, a bad epoch/number/unit, a parameter given twice, a solution with a
        position component missing, or velocity components given only partly.
    """
    path = Path(path)
    header, blocks = _blocks(path, read_lines(path))
    sites = _site_ids(path, _require(path, blocks, "SITE/ID"))
    rows = _require(path, blocks, "SOLUTION/ESTIMATE")
    if "n_estimates" in header:  # the file ends with %ENDSNX: complete
        check_count(header["n_estimates"], len(rows), path, 1, "%=SNX number of estimates",
                    "estimates", complete=True, log=_LOG)
    est = _estimates(path, rows)
    epochs = _solution_epochs(path, blocks.get("SOLUTION/EPOCHS", []))
    keys = list(est)
    n = len(keys)
    pos = np.full((n, 3), np.nan)
    sig = np.full((n, 3), np.nan)
    vel = np.full((n, 3), np.nan)
    sigv = np.full((n, 3), np.nan)
    ref = np.full(n, np.datetime64("NaT", "ns"))
    for i, key in enumerate(keys):
        e = est[key]
        for name, k in _STA.items():
            if name not in e:
                raise FormatError(path, e["line"], name, f"site {key[0]} point {key[1]} "
                                  f"solution {key[2]} has no {name}")
            pos[i, k], sig[i, k], epoch, _ = e[name]
        ref[i] = epoch
        present = [name for name in _VEL if name in e]
        if present and len(present) < 3:
            raise FormatError(path, e["line"], "VELX/VELY/VELZ", f"site {key[0]} solution "
                              f"{key[2]} has only {present}")
        for name in present:
            vel[i, _VEL[name]], sigv[i, _VEL[name]] = e[name][:2]
    nat = np.datetime64("NaT", "ns")
    info = [sites.get(k[:2], ("", "", math.nan, math.nan, math.nan)) for k in keys]
    span = [epochs.get(k) or epochs.get((k[0], k[1], ANY_SOLUTION), (nat, nat)) for k in keys]

    def var(values, units, title, dims=("solution",)):
        return dims, values, {"units": units, "long_name": title}

    ds = xr.Dataset(
        {
            "site": var(np.array([k[0] for k in keys], dtype=str), "1", "site code"),
            "pt": var(np.array([k[1] for k in keys], dtype=str), "1", "point code"),
            "soln": var(np.array([k[2] for k in keys], dtype=np.int32), "1",
                        "solution number"),
            "domes": var(np.array([s[0] for s in info], dtype=str), "1", "DOMES number"),
            "description": var(np.array([s[1] for s in info], dtype=str), "1",
                               "station description"),
            "approx_lon_deg": var(np.array([s[2] for s in info]), "degree_east",
                                  "approximate longitude"),
            "approx_lat_deg": var(np.array([s[3] for s in info]), "degree_north",
                                  "approximate latitude"),
            "approx_height_m": var(np.array([s[4] for s in info]), "m",
                                   "approximate ellipsoidal height"),
            "pos_m": var(pos, "m", "station position at ref_epoch", ("solution", "xyz")),
            "sigma_pos_m": var(sig, "m", "standard deviation of pos_m", ("solution", "xyz")),
            "vel_m_y": var(vel, "m yr-1", "station velocity (per Julian year of 365.25 d)",
                           ("solution", "xyz")),
            "sigma_vel_m_y": var(sigv, "m yr-1", "standard deviation of vel_m_y",
                                 ("solution", "xyz")),
            "ref_epoch": var(ref, "", "reference epoch of the position"),
            "valid_from": var(np.array([s[0] for s in span], dtype="datetime64[ns]"), "",
                              "start of the solution interval (NaT = open)"),
            "valid_to": var(np.array([s[1] for s in span], dtype="datetime64[ns]"), "",
                            "end of the solution interval (NaT = open)"),
        },
        coords={"xyz": ("xyz", _XYZ)},
    )
    for name in ("ref_epoch", "valid_from", "valid_to"):
        del ds[name].attrs["units"]  # datetime64: units are set by the netCDF encoding
    ds.attrs.update(header)
    ds.attrs.update({"time_system": "UTC", "source": path.name})
    return ds


def _site_ids(path: Path, rows: list) -> dict:
    """(site, pt) -> (domes, description, lon_deg, lat_deg, height_m) of SITE/ID."""
    out: dict = {}
    for ln, text in rows:
        site = _field(text, 1, 5)
        pt = _field(text, 6, 8)
        if (site, pt) in out:  # ILRS files repeat a site once per occupation
            continue
        lon = _dms(path, ln, "APPROX_LON", text[44:55])
        lat = _dms(path, ln, "APPROX_LAT", text[56:67])
        h = parse_float(text[68:75], path, ln, "APP_H", allow_blank=True, lo=-1e4, hi=1e5)
        out[(site, pt)] = (_field(text, 9, 18), _field(text, 21, 43), lon, lat, h)
    return out


_DMS = re.compile(r"\s*(-?[0-9.]+)\s*(-?[0-9.]+)\s*(-?[0-9.]+)\s*")


def _dms(path: Path, ln: int, field: str, text: str) -> float:
    """Degrees, minutes, seconds (``ddd mm ss.s``) as decimal degrees; NaN if blank.

    The sign is negative if any of the three parts carries a minus (SLRF files write
    ``-29 -2-47.3`` for -29 deg 2 min 47.3 s).
    """
    if not text.strip():
        return math.nan
    m = _DMS.fullmatch(text)
    if m is None:
        raise FormatError(path, ln, field, f"'{text.strip()}' is not 'deg min sec'")
    d, mi, s = (parse_float(g, path, ln, field, lo=-360.0, hi=360.0) for g in m.groups())
    value = abs(d) + abs(mi) / 60.0 + abs(s) / 3600.0
    return -value if "-" in text else value


def _estimates(path: Path, rows: list) -> dict:
    """(site, pt, soln) -> {TYPE: (value, sigma, ref_epoch, line), "line": first line}."""
    out: dict = {}
    for ln, text in rows:
        ptype = _field(text, 7, 13)
        if ptype not in _STA and ptype not in _VEL:
            continue
        key = _soln_key(path, ln, text, code_col=14)
        unit = _field(text, 40, 44)
        expected = "m" if ptype in _STA else "m/y"
        if unit != expected:
            raise FormatError(path, ln, "UNIT", f"{ptype} in '{unit}', expected '{expected}'")
        kind = "position_m" if ptype in _STA else "velocity_m_s"
        value = parse_float(text[47:68], path, ln, f"{ptype} ESTIMATED VALUE", kind=kind)
        sigma = parse_float(text[69:80], path, ln, f"{ptype} STD_DEV", allow_blank=True,
                            lo=0.0, hi=1e9)
        epoch = _epoch(path, ln, "REF_EPOCH", text[27:39], open_ok=False)
        entry = out.setdefault(key, {"line": ln})
        if ptype in entry:
            raise FormatError(path, ln, ptype, f"site {key[0]} point {key[1]} solution {key[2]}"
                              f" has {ptype} twice (first at line {entry[ptype][3]})")
        entry[ptype] = (value, sigma, epoch, ln)
    return out


def _solution_epochs(path: Path, rows: list) -> dict:
    """(site, pt, soln) -> (data start, data end) of SOLUTION/EPOCHS."""
    out: dict = {}
    for ln, text in rows:
        key = _soln_key(path, ln, text)
        start = _epoch(path, ln, "DATA_START", text[16:28], open_ok=True)
        end = _epoch(path, ln, "DATA_END", text[29:41], open_ok=True)
        if not (np.isnat(start) or np.isnat(end)) and end < start:
            raise FormatError(path, ln, "DATA_END", "data end is before data start")
        out[key] = (start, end)
    return out


# ---------------------------------------------------------------------------- eccentricities
def read_sinex_eccentricities(path: str | Path) -> xr.Dataset:
    """Read the SITE/ECCENTRICITY block of a SINEX file.

    Parameters
    ----------
    path : str or Path
        SINEX file with a SITE/ECCENTRICITY block (e.g. the ILRS ``ecc_xyz.snx``).

    Returns
    -------
    xarray.Dataset
        Dimension ``record``; schema in the module docstring.

    Raises
    ------
    FormatError
        Missing block, bad epoch or number, reference system other than UNE/XYZ.
    """
    path = Path(path)
    header, blocks = _blocks(path, read_lines(path))
    rows = _require(path, blocks, "SITE/ECCENTRICITY")
    keys, systems, ecc, start, end, sod = [], [], [], [], [], []
    for ln, text in rows:
        keys.append(_soln_key(path, ln, text))
        system = _field(text, 42, 45)
        if system not in ("UNE", "XYZ"):
            raise FormatError(path, ln, "REF SYSTEM", f"'{system}' is neither UNE nor XYZ")
        systems.append(system)
        ecc.append([parse_float(text[a:a + 9], path, ln, f"ECCENTRICITY {c}", lo=-1e4, hi=1e4)
                    for a, c in zip((45, 54, 63), "123")])
        start.append(_epoch(path, ln, "DATA_START", text[16:28], open_ok=True))
        end.append(_epoch(path, ln, "DATA_END", text[29:41], open_ok=True))
        sod.append(_field(text, 72, 100))
    kinds = sorted(set(systems))
    labels = {("XYZ",): ["x", "y", "z"], ("UNE",): ["u", "n", "e"]}.get(
        tuple(kinds), ["x|u", "y|n", "z|e"])

    def var(values, units, title, dims=("record",)):
        return dims, values, {"units": units, "long_name": title}

    ds = xr.Dataset(
        {
            "site": var(np.array([k[0] for k in keys], dtype=str), "1", "site code"),
            "pt": var(np.array([k[1] for k in keys], dtype=str), "1", "point code"),
            "soln": var(np.array([k[2] for k in keys], dtype=np.int32), "1",
                        "solution number"),
            "ref_system": var(np.array(systems, dtype=str), "1",
                              "UNE (up, north, east) or XYZ (Earth-fixed)"),
            "ecc_m": var(np.array(ecc, dtype=float).reshape(-1, 3), "m",
                         "eccentricity from the marker to the reference point",
                         ("record", "component")),
            "valid_from": var(np.array(start, dtype="datetime64[ns]"), "",
                              "start of validity (NaT = open)"),
            "valid_to": var(np.array(end, dtype="datetime64[ns]"), "",
                            "end of validity (NaT = open)"),
            "cdp_sod": var(np.array(sod, dtype=str), "1",
                           "CDP system occupation designator (ILRS files), '' if absent"),
        },
        coords={"component": ("component", labels)},
    )
    for name in ("valid_from", "valid_to"):
        del ds[name].attrs["units"]
    ds.attrs.update(header)
    ds.attrs.update({"ref_system": kinds[0] if len(kinds) == 1 else "mixed",
                     "time_system": "UTC", "source": path.name})
    return ds


# ----------------------------------------------------------------------------------- lookups
def _covering_rows(ds: xr.Dataset, sites, epochs, pt: str | None) -> np.ndarray:
    """Index (n,) of the last row of each of the n ``sites`` whose validity covers its one of
    the n ``epochs`` (datetime64), −1 if none."""
    sites = np.asarray(sites, dtype=str)
    t = np.asarray(epochs, dtype="datetime64[ns]")
    if np.isnat(t).any():
        raise ValueError("epoch is NaT")
    rows = np.full(sites.size, -1)
    candidates = ds["site"].values.astype(str)
    if pt is not None:
        candidates = np.where(ds["pt"].values == pt, candidates, "")
    start, end = ds["valid_from"].values, ds["valid_to"].values
    for site in np.unique(sites):
        mine = np.flatnonzero(candidates == site)                     # (k,) in file order
        if not mine.size:
            continue
        points = np.flatnonzero(sites == site)
        tp = t[points, None]
        cover = ((np.isnat(start[mine]) | (start[mine] <= tp))
                 & (np.isnat(end[mine]) | (tp <= end[mine])))        # (m, k)
        last = mine[mine.size - 1 - np.argmax(cover[:, ::-1], axis=1)]
        rows[points] = np.where(cover.any(axis=1), last, -1)
    return rows


def _covering(ds: xr.Dataset, site: str, epoch, pt: str | None) -> int:
    """Index of the last row of ``site`` whose validity covers ``epoch``."""
    t = np.datetime64(epoch, "ns")
    i = int(_covering_rows(ds, [site], [t], pt)[0])
    if i < 0:
        where = "" if pt is None else f" point {pt}"
        raise KeyError(f"no entry for site {site}{where} valid at {t.astype('datetime64[s]')}"
                       f" in {ds.attrs.get('source', 'the dataset')}")
    return i


def station_positions(ds: xr.Dataset, sites, epochs, pt: str | None = None) -> np.ndarray:
    """:func:`station_position` of many (site, epoch) pairs at once; NaN rows for a site
    without a solution at its epoch.

    Parameters
    ----------
    sites : array_like of str, shape (n,)
    epochs : array_like of datetime64, shape (n,)

    Returns
    -------
    ndarray, shape (n, 3)
        Earth-fixed positions [m].
    """
    i = _covering_rows(ds, sites, epochs, pt)
    found = i >= 0
    out = np.full((i.size, 3), np.nan)
    out[found] = _propagated(ds, i[found], np.asarray(epochs, dtype="datetime64[ns]")[found])
    return out


def _propagated(ds: xr.Dataset, rows: np.ndarray, epochs: np.ndarray) -> np.ndarray:
    """Positions (n, 3) [m] of the solutions ``rows`` at ``epochs`` (datetime64[ns], (n,)):
    ``pos + vel * (epoch − ref_epoch)`` in Julian years, no velocity = constant."""
    dt_years = (epochs - ds["ref_epoch"].values[rows]).astype(np.int64) / _JULIAN_YEAR_NS
    vel = np.nan_to_num(ds["vel_m_y"].values[rows], nan=0.0)
    return ds["pos_m"].values[rows] + vel * dt_years[:, None]


def station_eccentricities(ds: xr.Dataset, sites, epochs,
                           pt: str | None = None) -> tuple[np.ndarray, np.ndarray]:
    """:func:`station_eccentricity` of many (site, epoch) pairs at once.

    Returns
    -------
    ecc_m : ndarray, shape (n, 3)
        Eccentricities [m] (NaN rows where no line covers the epoch).
    ref_system : ndarray of str, shape (n,)
        "UNE" or "XYZ"; "" where no line covers the epoch.
    """
    i = _covering_rows(ds, sites, epochs, pt)
    found = i >= 0
    ecc = np.full((i.size, 3), np.nan)
    ecc[found] = ds["ecc_m"].values[i[found]]
    return ecc, np.where(found, ds["ref_system"].values[np.maximum(i, 0)].astype(str), "")


def station_position(ds: xr.Dataset, site: str, epoch, pt: str | None = None) -> np.ndarray:
    """Position of a station at an epoch from a :func:`read_sinex_stations` Dataset.

    The solution whose [valid_from, valid_to] covers ``epoch`` is used (the last one in the
    file if several do) and propagated linearly: ``pos + vel * (epoch - ref_epoch)``, with
    the time difference in Julian years. A solution without velocity is held constant.

    Parameters
    ----------
    ds : xarray.Dataset
        From :func:`read_sinex_stations`.
    site : str
        Site code, e.g. ``"7090"``.
    epoch : datetime64, datetime or str
        Epoch (same time scale as the file, nominally UTC).
    pt : str, optional
        Point code; any point if None.

    Returns
    -------
    ndarray, shape (3,)
        Earth-fixed position [m].

    Raises
    ------
    KeyError
        If no solution of the site covers the epoch (the message names site and epoch).
    """
    i = _covering(ds, site, epoch, pt)
    return _propagated(ds, np.array([i]), np.array([epoch], dtype="datetime64[ns]"))[0]


def station_eccentricity(ds: xr.Dataset, site: str, epoch,
                         pt: str | None = None) -> tuple[np.ndarray, str]:
    """Eccentricity of a station valid at an epoch (:func:`read_sinex_eccentricities`).

    Returns
    -------
    ecc_m : ndarray, shape (3,)
        Eccentricity [m], components in the returned system.
    ref_system : str
        "UNE" (up, north, east) or "XYZ" (Earth-fixed).

    Raises
    ------
    KeyError
        If no line of the site covers the epoch (the message names site and epoch).
    """
    i = _covering(ds, site, epoch, pt)
    return ds["ecc_m"].values[i].copy(), str(ds["ref_system"].values[i])

"""GNSS orbit, clock and satellite-antenna products as leopod netCDF files, and back.

The ``gnss_products`` rule parses a day's SP3 orbits, RINEX clocks and ANTEX satellite
antennas once (``scripts/gnss_products.py``) and writes them here; ingest and the POD steps
read these files instead of parsing the text formats again, job after job. The readers also
take the original text files (chosen by the name: ``.nc`` is netCDF, anything else the text
format), so that a product can be read by hand from either; both give the same values.

Orbit and clock files
---------------------
The Datasets of :func:`leopod.io.sp3.read_sp3` and :func:`leopod.io.clock.read_rinex_clock`
unchanged (variables, coordinates, values, the reader's attributes), written by
:func:`leopod.io.netcdf.write_netcdf` (which adds its provenance attributes). The writer reads
the file back and refuses one that does not give the same values (e.g. an epoch that the
float64 time encoding cannot hold to the nanosecond).

Satellite-antenna file (:func:`satellite_antenna_dataset`)
----------------------------------------------------------
The satellite entries of an ANTEX file of some GNSS whose validity overlaps a time window,
with every number of the entries, so that :func:`antex_from_dataset` rebuilds an
:class:`~leopod.io.antex.AntexFile` whose PCO and PCV are bit-identical to the ANTEX file's.

dims
    ``antenna`` (one per entry, in file order), ``frequency`` (ANTEX codes ``sNN`` of all
    entries, in order of first appearance), ``xyz``, ``nadir`` (index of the nadir grid,
    as long as the longest one), ``azimuth`` (index of the azimuth rows; only when an entry
    has ``DAZI > 0``).
coordinates
    ``frequency``, ``xyz``; along ``antenna``: ``prn`` (``sNN``), ``antenna_type``, ``svn``,
    ``cospar_id``, ``sinex_code``, ``calibration_method``, ``calibrated_by`` (str, "" when
    absent), ``valid_from``, ``valid_until`` (ISO text of GPS time to the nanosecond, ""
    when open: ANTEX epochs such as 23:59:59.9999999 do not fit the float64 seconds of
    netCDF times exactly).
data variables
    ``pco_m`` (antenna, frequency, xyz) [m] body-frame offset, NaN for a frequency the entry
    lacks; ``frequency_order`` (antenna, frequency) [1] rank of the frequency in the entry's
    file order, -1 when absent; ``nadir_deg`` (antenna, nadir) [degree] the entry's nadir
    grid, NaN-padded; ``dazi_deg`` (antenna) [degree]; ``pcv_noazi_m`` (antenna, frequency,
    nadir) [m], NaN-padded; ``pcv_m`` (antenna, frequency, azimuth, nadir) [m], NaN-padded,
    only when an entry has ``DAZI > 0``.
attributes
    ``antex_version``, ``satellite_system``, ``pcv_type``, ``reference_antenna`` (the ANTEX
    header), ``antex_file`` (its name), ``systems`` (the GNSS letters kept), ``window_start``,
    ``window_end`` (ISO, GPS time; "" when unbounded): :meth:`AntexFile.satellite` of the
    rebuilt file refuses epochs outside the window, since entries valid only then were left
    out.

Errors
------
A netCDF file that cannot be opened or lacks a variable of its schema raises
:class:`leopod.io.FormatError` naming the file and the variable.
"""

from __future__ import annotations

import logging
from collections.abc import Iterable
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.io._text import time_system_to_gps
from leopod.io.antex import AntennaPattern, AntexFile, read_antex
from leopod.io.clock import read_rinex_clock
from leopod.io.netcdf import atomic_path, load_netcdf, write_netcdf
from leopod.io.sp3 import read_sp3

__all__ = [
    "antex_from_dataset",
    "read_antenna_product",
    "read_clock_product",
    "read_orbit_product",
    "satellite_antenna_dataset",
    "write_product",
]

log = logging.getLogger(__name__)

_ORBIT_VARS = ("pos_m", "clk_s")
_CLOCK_VARS = ("clk_s",)
_ANTENNA_VARS = ("pco_m", "frequency_order", "nadir_deg", "dazi_deg", "pcv_noazi_m", "prn",
                 "antenna_type", "svn", "cospar_id", "sinex_code", "calibration_method",
                 "calibrated_by", "valid_from", "valid_until")
_ANTENNA_STR = ("antenna_type", "svn", "cospar_id", "sinex_code", "calibration_method",
                "calibrated_by")
_NAT = np.datetime64("NaT", "ns")


def is_netcdf(path: str | Path) -> bool:
    """True if ``path`` names a netCDF product (suffix ``.nc``)."""
    return Path(path).suffix == ".nc"


def _gps_product(ds: xr.Dataset, path: str | Path) -> xr.Dataset:
    """A netCDF product with its ``time`` in GPS time (converted if its ``time_system``
    attribute names another system; FormatError if that has no conversion)."""
    system = str(ds.attrs.get("time_system", "GPS"))
    if system == "GPS":
        return ds
    times = time_system_to_gps(ds.time.values, system, path, None, "time_system")
    ds = ds.assign_coords(time=times)
    ds.attrs.update(time_system_file=system, time_system="GPS")
    return ds


def read_orbit_product(path: str | Path) -> xr.Dataset:
    """GNSS orbits: a netCDF product (``.nc``) or an SP3 file (:func:`read_sp3`).

    Returns
    -------
    xarray.Dataset
        The schema of :func:`leopod.io.sp3.read_sp3` (``pos_m`` [m], ``clk_s`` [s], ...),
        ``time`` in GPS time (``time_system_file`` keeps the file's when converted).
    """
    if is_netcdf(path):
        return _gps_product(load_netcdf(path, "GNSS orbit", _ORBIT_VARS), path)
    return read_sp3(path, gps_time=True)


def read_clock_product(path: str | Path) -> xr.Dataset:
    """GNSS clocks: a netCDF product (``.nc``) or a RINEX clock file (:func:`read_rinex_clock`,
    satellite records).

    Returns
    -------
    xarray.Dataset
        The schema of :func:`leopod.io.clock.read_rinex_clock` (``clk_s`` [s], ...),
        ``time`` in GPS time (``time_system_file`` keeps the file's when converted).
    """
    if is_netcdf(path):
        return _gps_product(load_netcdf(path, "GNSS clock", _CLOCK_VARS), path)
    return read_rinex_clock(path, gps_time=True)


def read_antenna_product(path: str | Path) -> AntexFile:
    """GNSS satellite antennas: a netCDF product (``.nc``, :func:`antex_from_dataset`) or an
    ANTEX file (:func:`leopod.io.antex.read_antex`)."""
    if not is_netcdf(path):
        return read_antex(path)
    return antex_from_dataset(load_netcdf(path, "satellite antenna", _ANTENNA_VARS), path)


def write_product(ds: xr.Dataset, path: str | Path, *, inputs: Iterable[str | Path],
                  title: str, reference_frame: str | None = None) -> Path:
    """Write a product Dataset (orbit, clock or satellite antennas) as netCDF and check that
    it reads back with the same values.

    Parameters
    ----------
    ds : xarray.Dataset
        :func:`read_sp3`, :func:`read_rinex_clock` or :func:`satellite_antenna_dataset` output.
    path : str or Path
        Destination; written atomically (:func:`leopod.io.netcdf.write_netcdf`).
    inputs : iterable of path
        The files the product was read from (provenance).
    title : str
    reference_frame : str, optional

    Raises
    ------
    ValueError
        If the file does not give back every coordinate and variable of ``ds`` bit for bit
        (the file is removed).
    """
    path = Path(path)
    with atomic_path(path) as tmp:          # checked before it takes the product's name
        write_netcdf(ds, tmp, step="gnss_products", inputs=inputs,
                     time_system=str(ds.attrs.get("time_system", "GPS")),
                     reference_frame=reference_frame, title=title)
        back = xr.load_dataset(tmp, engine="netcdf4")
        for name, var in ds.variables.items():
            if name not in back.variables or not _same_values(var.values, back[name].values):
                raise ValueError(f"{path}: '{name}' does not read back identically from "
                                 "netCDF (no file written)")
    return path


def _same_values(a: np.ndarray, b: np.ndarray) -> bool:
    if a.shape != b.shape:
        return False
    if a.dtype.kind in "fcmM":
        return bool(np.array_equal(a, b, equal_nan=True))
    return bool(np.array_equal(a.astype(str) if a.dtype.kind in "OUS" else a,
                               b.astype(str) if b.dtype.kind in "OUS" else b))


# --- satellite antennas --------------------------------------------------------------------


def _overlaps(entry: AntennaPattern, start, end) -> bool:
    """True if the validity of ``entry`` overlaps ``[start, end]`` (None: unbounded)."""
    after_start = (start is None or np.isnat(entry.valid_until)
                   or entry.valid_until >= start)
    before_end = end is None or np.isnat(entry.valid_from) or entry.valid_from <= end
    return after_start and before_end


def satellite_antenna_dataset(antex: AntexFile, systems: Iterable[str] | None = None,
                              start=None, end=None) -> xr.Dataset:
    """The satellite antennas of an ANTEX file as one Dataset (schema: module docstring).

    Parameters
    ----------
    antex : AntexFile
        The ANTEX file read (:func:`leopod.io.antex.read_antex`).
    systems : iterable of str, optional
        GNSS letters whose satellites are kept (None: all).
    start, end : datetime-like, optional
        GPS-time window: entries valid at some epoch of ``[start, end]`` are kept, and the
        rebuilt file (:func:`antex_from_dataset`) answers for epochs inside it only.

    Returns
    -------
    xarray.Dataset
    """
    start = None if start is None else np.datetime64(start, "ns")
    end = None if end is None else np.datetime64(end, "ns")
    systems = None if systems is None else sorted(set(systems))
    entries = [a for a in antex.antennas if a.kind == "satellite"
               and (systems is None or a.serial[:1] in systems) and _overlaps(a, start, end)]
    if not entries:
        log.warning("%s: no satellite antenna of %s valid in %s .. %s", antex.path.name,
                    "".join(systems or []) or "any system", start, end)
    freqs = list(dict.fromkeys(f for a in entries for f in a.frequencies))
    n, n_f = len(entries), len(freqs)
    n_zen = max((len(a.zenith_deg) for a in entries), default=0)
    n_az = max((len(a.azimuth_deg) for a in entries if a.dazi_deg > 0), default=0)
    pco = np.full((n, n_f, 3), np.nan)
    order = np.full((n, n_f), -1, dtype=np.int32)
    nadir = np.full((n, n_zen), np.nan)
    noazi = np.full((n, n_f, n_zen), np.nan)
    grid = np.full((n, n_f, n_az, n_zen), np.nan)
    for i, a in enumerate(entries):
        nz = len(a.zenith_deg)
        nadir[i, :nz] = a.zenith_deg
        for rank, f in enumerate(a.frequencies):
            j = freqs.index(f)
            order[i, j] = rank
            pco[i, j] = a.pco[f]
            noazi[i, j, :nz] = a.noazi[f]
            if a.dazi_deg > 0:
                grid[i, j, :a.grid[f].shape[0], :nz] = a.grid[f]
    data = {
        "pco_m": (("antenna", "frequency", "xyz"), pco,
                  {"units": "m", "long_name": "phase centre offset in the satellite body frame"}),
        "frequency_order": (("antenna", "frequency"), order,
                            {"units": "1", "long_name": "rank of the frequency in the entry "
                             "(ANTEX file order), -1 when absent"}),
        "nadir_deg": (("antenna", "nadir"), nadir,
                      {"units": "degree", "long_name": "nadir angles of the pattern"}),
        "dazi_deg": (("antenna",), np.array([a.dazi_deg for a in entries], dtype=float),
                     {"units": "degree", "long_name": "azimuth increment (0: none)"}),
        "pcv_noazi_m": (("antenna", "frequency", "nadir"), noazi,
                        {"units": "m", "long_name":
                         "azimuth-independent phase centre variation vs nadir angle"}),
    }
    if n_az:
        data["pcv_m"] = (("antenna", "frequency", "azimuth", "nadir"), grid,
                         {"units": "m", "long_name":
                          "phase centre variation vs azimuth and nadir angle"})
    strings = {"prn": [a.serial for a in entries],
               **{k: [_entry_text(a, k) for a in entries] for k in _ANTENNA_STR}}
    coords = {"frequency": freqs, "xyz": ["x", "y", "z"],
              **{k: ("antenna", np.array(v, dtype=str)) for k, v in strings.items()},
              # ISO text, not netCDF times: ANTEX gives 23:59:59.9999999, which float64
              # seconds since 1980 cannot hold to the nanosecond
              **{k: ("antenna", np.array([_iso(getattr(a, k)) for a in entries], dtype=str),
                     {"long_name": f"{k.replace('_', ' ')} (ISO, GPS time; '': open)"})
                 for k in ("valid_from", "valid_until")}}
    ds = xr.Dataset(data, coords=coords)
    ds.attrs.update(
        antex_version=float(antex.attrs["antex_version"]),
        satellite_system=str(antex.attrs.get("satellite_system", "")),
        pcv_type=str(antex.attrs["pcv_type"]),
        reference_antenna=str(antex.attrs.get("reference_antenna", "")),
        antex_file=antex.path.name, systems="".join(systems or []),
        window_start="" if start is None else str(start),
        window_end="" if end is None else str(end), time_system="GPS")
    return ds


def _iso(t: np.datetime64) -> str:
    return "" if np.isnat(t) else str(np.datetime64(t, "ns"))


def _time(text: str) -> np.datetime64:
    return np.datetime64(text, "ns") if text else _NAT


def _entry_text(a: AntennaPattern, key: str) -> str:
    """A text field of an entry: type, SVN, COSPAR id or one of its ``meta`` strings."""
    if key in ("antenna_type", "svn", "cospar_id"):
        return getattr(a, key)
    return str(a.meta.get(key, ""))


def antex_from_dataset(ds: xr.Dataset, path: str | Path = "satellite antennas") -> AntexFile:
    """The :class:`AntexFile` of a :func:`satellite_antenna_dataset` (its satellites only).

    Parameters
    ----------
    ds : xarray.Dataset
    path : str or Path
        Name of the file (messages of the AntexFile name it).

    Returns
    -------
    AntexFile
        Satellite entries with the stored numbers (PCO, PCV and grids bit-identical to those
        of the ANTEX file) and the window of the Dataset.
    """
    path = Path(path)
    freqs = [str(f) for f in ds.frequency.values]
    order = ds.frequency_order.values
    pco, nadir, noazi = ds.pco_m.values, ds.nadir_deg.values, ds.pcv_noazi_m.values
    dazi = ds.dazi_deg.values
    grid = ds.pcv_m.values if "pcv_m" in ds else None
    meta_file = {"antex_version": float(ds.attrs["antex_version"]),
                 "pcv_type": str(ds.attrs["pcv_type"]),
                 "reference_antenna": str(ds.attrs.get("reference_antenna", "")),
                 "source_file": str(ds.attrs.get("antex_file", path.name))}
    text = {k: [str(v) for v in ds[k].values]
            for k in ("prn", *_ANTENNA_STR, "valid_from", "valid_until")}
    entries = []
    for i in range(ds.sizes["antenna"]):
        nz = int(np.isfinite(nadir[i]).sum())
        present = sorted((int(order[i, j]), j) for j in range(len(freqs)) if order[i, j] >= 0)
        codes = tuple(freqs[j] for _, j in present)
        pattern_grid = {}
        if dazi[i] > 0:
            n_az = int(round(360.0 / dazi[i])) + 1
            pattern_grid = {freqs[j]: grid[i, j, :n_az, :nz].copy() for _, j in present}
        entries.append(AntennaPattern(
            kind="satellite", antenna_type=text["antenna_type"][i], serial=text["prn"][i],
            svn=text["svn"][i], cospar_id=text["cospar_id"][i],
            valid_from=_time(text["valid_from"][i]), valid_until=_time(text["valid_until"][i]),
            zenith_deg=nadir[i, :nz].copy(), dazi_deg=float(dazi[i]), frequencies=codes,
            pco={freqs[j]: pco[i, j].copy() for _, j in present},
            noazi={freqs[j]: noazi[i, j, :nz].copy() for _, j in present},
            grid=pattern_grid,
            meta={"sinex_code": text["sinex_code"][i],
                  "calibration_method": text["calibration_method"][i],
                  "calibrated_by": text["calibrated_by"][i], **meta_file}))
    attrs = {"antex_version": meta_file["antex_version"],
             "satellite_system": str(ds.attrs.get("satellite_system", "")),
             "pcv_type": meta_file["pcv_type"],
             "reference_antenna": meta_file["reference_antenna"]}
    start, end = (str(ds.attrs.get(k, "")) for k in ("window_start", "window_end"))
    window = None
    if start or end:
        window = (np.datetime64(start or "1900-01-01", "ns"),
                  np.datetime64(end or "2200-01-01", "ns"))
    return AntexFile(path, attrs, entries, window=window)

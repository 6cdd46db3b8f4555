"""Reference orbits of any origin in the orbit schema, and the daily comparison of a POD arc.

Formats (by file name): SP3 (``.sp3``, ``.eph``, ``.sp3c``, compressed or not), leopod netCDF
(``.nc``, the orbit schema of :mod:`leopod.estimation.outputs`), and the GRACE Bernese orbit
CSV of ../shared/data (``.csv``, :func:`leopod.io.grace_orbit_csv.read_grace_orbit_csv`).
Several files (days) are merged; epochs shared by consecutive files are kept once.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.io.grace_orbit_csv import read_grace_orbit_csv
from leopod.io.netcdf import merge_days
from leopod.io.sp3 import read_sp3
from leopod.time.calendar import parse_date_id
from leopod.validation.compare import compare_orbits, orbit_from_sp3
from leopod.validation.orbit_statistics import orbit_statistics

__all__ = ["compare_day", "read_reference_orbit"]

_SP3_SUFFIXES = (".sp3", ".eph", ".sp3c", ".sp3d")


def _kind(path: Path) -> str:
    name = path.name.lower().removesuffix(".gz").removesuffix(".z")
    if name.endswith(_SP3_SUFFIXES):
        return "sp3"
    if name.endswith(".nc"):
        return "netcdf"
    if name.endswith(".csv"):
        return "csv"
    raise ValueError(f"{path}: unknown reference-orbit format (SP3, .nc or GRACE .csv)")


def _one(path: Path, sv: str | None) -> xr.Dataset:
    kind = _kind(path)
    if kind == "csv":
        return read_grace_orbit_csv(path)
    if kind == "netcdf":       # only the orbit is read (a simulated truth file holds more)
        with xr.open_dataset(path) as ds:
            if "pos_itrf_m" not in ds or "time" not in ds.coords:
                raise ValueError(f"{path}: no orbit variable pos_itrf_m (time, xyz) [m]; a "
                                 "leopod orbit file is <step>/<sat>/<day>_orbit.nc")
            return ds[[v for v in ("pos_itrf_m", "vel_itrf_m_s") if v in ds]].load()
    sp3 = read_sp3(path)
    ids = [str(s) for s in sp3.sv.values]
    if sv is None:
        if len(ids) != 1:
            raise ValueError(f"{path}: {len(ids)} satellites ({' '.join(ids)}); name the "
                             "reference satellite (reference_id)")
        sv = ids[0]
    elif sv not in ids:
        raise ValueError(f"{path}: no satellite {sv} (has {' '.join(ids)})")
    return orbit_from_sp3(sp3, sv)


def read_reference_orbit(paths: Sequence[str | Path], *, sv: str | None = None
                         ) -> xr.Dataset:
    """Reference orbit from one or several files.

    Parameters
    ----------
    paths : sequence of path
        Files in time order.
    sv : str, optional
        Satellite id inside SP3 files (default: the only one).

    Returns
    -------
    xarray.Dataset
        ``pos_itrf_m`` (and ``vel_itrf_m_s`` if given) (time, xyz) [m, m/s]; attrs
        ``time_system`` (of the first file, default GPS).
    """
    return merge_days([_one(Path(p), sv) for p in paths])


def compare_day(orbit: xr.Dataset, reference: xr.Dataset, date: str, *,
                time_system: str | None = None, time_offset_s: float = 0.0,
                helmert: int | None = None) -> xr.Dataset:
    """Differences of a POD arc and a reference over the day ``date`` (00:00–24:00 GPS).

    Parameters
    ----------
    orbit : xarray.Dataset
        POD orbit (its arc may extend into neighbouring days).
    reference : xarray.Dataset
        From :func:`read_reference_orbit`.
    date : str
        ``YYYY-DDD``.
    time_system, time_offset_s, helmert
        See :func:`leopod.validation.compare.compare_orbits`.

    Returns
    -------
    xarray.Dataset
        :func:`~leopod.validation.compare.compare_orbits` output (``diff_rtn_m``,
        ``diff_3d_m``) merged with the day's statistics (``mean_m``, ``std_m``, ``rms_m``
        (period, component), ``n_epochs``).
    """
    day = np.datetime64(parse_date_id(date), "ns")
    end = day + np.timedelta64(86_400, "s") - np.timedelta64(1, "ns")
    diff = compare_orbits(orbit, reference, reference_time_system=time_system,
                          time_offset_s=time_offset_s, helmert=helmert, start=day, end=end)
    ok = np.isfinite(diff.diff_rtn_m.values).all(axis=1)
    if not ok.any():
        raise ValueError(f"the reference orbit does not cover {date}")
    return xr.merge([diff, orbit_statistics(diff.isel(time=np.flatnonzero(ok)), daily=False)],
                    combine_attrs="override")

"""Multipath samples of a period from the quality outputs, split by attitude mode.

The quality step (:func:`leopod.gnss.quality.assess_quality`) stores per observation the code
multipath ``mp_<code>_m`` (Peng et al. 2021, eq. (1), pass mean removed), the antenna-frame
``el_deg``/``az_deg`` and the continuous-phase ``pass_id``. The pass mean does not matter to
the map estimation, which has its own offset per pass. The multipath is free of the
per-frequency antenna terms (LEO PCO per band, GNSS PCO/PCV per frequency) when the quality
step removed them (its ``antenna_*`` attributes, carried to the maps by
:func:`leopod.codebias.period.estimate_period`).

Attitude modes (Jiang et al. 2023, sec. "Code multipath analysis"): a satellite that flips its yaw
by 180° (HY-2D at a Sun-angle threshold) sees the near-field environment of its antenna from the
other side, so the maps of some signals differ before and after a flip. Given the flip epochs,
an observation belongs to mode ``(number of flips before it) mod 2``: periods 1 and 3 share a
mode, as do 2 and 4.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import xarray as xr

from leopod.io.netcdf import on_grid

__all__ = ["MpSamples", "attitude_mode", "load_quality", "mp_samples"]

#: Quality variables the maps need besides the multipath series.
_GEOMETRY = ("el_deg", "az_deg", "pass_id")


@dataclass
class MpSamples:
    """Multipath observations of one code (flat arrays of equal length n).

    Attributes
    ----------
    az_deg, el_deg : ndarray
        Antenna-frame direction [deg].
    mp_m : ndarray
        Multipath combination [m].
    pass_key : ndarray of int
        Pass, unique over the days of the period.
    mode : ndarray of int
        Attitude mode.
    """

    az_deg: np.ndarray
    el_deg: np.ndarray
    mp_m: np.ndarray
    pass_key: np.ndarray
    mode: np.ndarray

    def select(self, mask: np.ndarray) -> MpSamples:
        """The samples where ``mask`` is true."""
        return MpSamples(*(getattr(self, f)[mask] for f in
                           ("az_deg", "el_deg", "mp_m", "pass_key", "mode")))


def attitude_mode(times: np.ndarray, yaw_flips=None) -> np.ndarray:
    """Attitude mode of epochs: number of yaw flips at or before the epoch, modulo 2.

    Parameters
    ----------
    times : ndarray of datetime64
    yaw_flips : sequence of datetime-like, optional
        Flip epochs (same time scale); none: mode 0 everywhere.

    Returns
    -------
    ndarray of int, shape of ``times``
    """
    times = np.asarray(times, dtype="datetime64[ns]")
    if not yaw_flips:
        return np.zeros(times.shape, dtype=np.int64)
    flips = np.sort(np.array([np.datetime64(t, "ns") for t in yaw_flips]))
    return np.searchsorted(flips, times, side="right") % 2


def mp_samples(quality_days: list[xr.Dataset], code: str, *, yaw_flips=None,
               min_elevation_deg: float = 0.0) -> MpSamples:
    """Multipath samples of ``code`` from the quality outputs of a period.

    Parameters
    ----------
    quality_days : list of xarray.Dataset
        Quality outputs (``mp_<code>_m``, ``el_deg``, ``az_deg``, ``pass_id`` on (time, sv)).
    code : str
        RINEX 3 code, e.g. ``"C1W"``.
    yaw_flips : sequence of datetime-like, optional
        Yaw-flip epochs (:func:`attitude_mode`).
    min_elevation_deg : float
        Lowest antenna elevation used [deg].

    Returns
    -------
    MpSamples

    Raises
    ------
    KeyError
        If a quality dataset has no multipath of ``code`` (naming the dataset's title).
    """
    parts = []
    key_offset = 0
    for ds in quality_days:
        name = f"mp_{code}_m"
        if name not in ds:
            raise KeyError(f"{ds.attrs.get('title', 'quality dataset')}: no variable {name} "
                           f"(codes assessed: {ds.attrs.get('codes', '?')})")
        mp = ds[name].values
        el, az = ds.el_deg.values, ds.az_deg.values
        pid = ds.pass_id.values.astype(np.int64)
        ok = np.isfinite(mp) & np.isfinite(el) & np.isfinite(az) & (pid >= 0)
        ok &= el >= min_elevation_deg
        ep, _ = np.nonzero(ok)
        mode = attitude_mode(ds.time.values[ep], yaw_flips)
        parts.append((az[ok], el[ok], mp[ok], pid[ok] + key_offset, mode))
        key_offset += int(pid.max()) + 1 if pid.size else 0
    if not parts:
        empty = np.zeros(0)
        return MpSamples(empty, empty, empty, empty.astype(np.int64), empty.astype(np.int64))
    return MpSamples(*(np.concatenate(c) for c in zip(*parts, strict=True)))


def load_quality(path, codes=None, step_s: float | None = None) -> xr.Dataset:
    """Read only what the maps need from a quality output (geometry, passes, multipath).

    Parameters
    ----------
    path : str or Path
        Quality netCDF file.
    codes : sequence of str, optional
        Codes whose multipath is read; None = all.
    step_s : float, optional
        Only the epochs on this time grid [s] are read (config ``code_bias.sampling_s``,
        :func:`leopod.io.netcdf.on_grid`); None = every epoch.
    """
    with xr.open_dataset(path) as ds:
        names = [*_GEOMETRY, *(v for v in ds.data_vars if v.startswith("mp_")
                               and (codes is None or v[3:-2] in codes))]
        out = ds[names]
        if step_s is not None:
            out = out.isel(time=np.flatnonzero(on_grid(ds.time.values, step_s)))
        return out.load()

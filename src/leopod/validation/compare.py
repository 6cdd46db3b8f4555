"""Orbit comparison in the radial, along-track and cross-track frame.

Used for orbit overlaps of consecutive or sub-arcs (seed 002 sec. 4.3: the self-consistency
of the POD) and for comparisons with external orbits (seed 001 sec. 3.3, the precise science
orbits). Differences are ``orbit − reference`` rotated into the RTN axes of the reference
(:func:`leopod.dynamics.empirical.rtn_matrix`; radial, along-track, cross-track), at the
common epochs.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from leopod.dynamics.empirical import rtn_matrix

__all__ = ["difference_rtn", "rms_rtn"]


def difference_rtn(orbit: xr.Dataset, reference: xr.Dataset, *, pos: str = "pos_itrf_m",
                   vel: str = "vel_itrf_m_s", start=None, end=None) -> xr.Dataset:
    """Position differences ``orbit − reference`` in the reference's RTN axes.

    Parameters
    ----------
    orbit, reference : xarray.Dataset
        Orbits with ``time`` and ``pos``/``vel`` (time, xyz) in the same frame [m, m/s].
    pos, vel : str
        Variable names.
    start, end : datetime64, optional
        Restrict to this window (inclusive).

    Returns
    -------
    xarray.Dataset
        ``diff_rtn_m`` (time, rtn) at the common epochs [m].
    """
    common = np.intersect1d(orbit.time.values, reference.time.values)
    if start is not None:
        common = common[common >= np.datetime64(start, "ns")]
    if end is not None:
        common = common[common <= np.datetime64(end, "ns")]
    if common.size == 0:
        raise ValueError("the orbits have no common epochs in the window")
    a = orbit[pos].sel(time=common).values
    ref = reference.sel(time=common)
    rtn = rtn_matrix(ref[pos].values, ref[vel].values)
    diff = np.einsum("nij,nj->ni", rtn, a - ref[pos].values)
    return xr.Dataset({"diff_rtn_m": (("time", "rtn"), diff,
                                      {"units": "m", "long_name": "orbit minus reference in "
                                       "radial, along-track, cross-track"})},
                      coords={"time": common, "rtn": ["R", "T", "N"]})


def rms_rtn(diff: xr.Dataset) -> dict[str, float]:
    """RMS of R, T, N and 3D [m] of a :func:`difference_rtn` result (finite rows)."""
    d = diff.diff_rtn_m.values
    d = d[np.isfinite(d).all(axis=1)]
    r = np.sqrt(np.mean(d**2, axis=0))
    return {"R": float(r[0]), "T": float(r[1]), "N": float(r[2]),
            "3D": float(np.sqrt(np.sum(r**2)))}

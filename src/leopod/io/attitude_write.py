"""Writers of leopod's attitude files (layout: :mod:`leopod.io.attitude`)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from leopod.io._text import write_text
from leopod.io.attitude import CSV_COLUMNS, CSV_MAGIC, attitude_dataset
from leopod.io.netcdf import write_netcdf

__all__ = ["write_attitude_csv", "write_attitude_netcdf"]


def _checked(times, quat) -> tuple[np.ndarray, np.ndarray]:
    t = np.asarray(times, dtype="datetime64[ns]")
    q = np.asarray(quat, dtype=float)
    if t.ndim != 1 or q.shape != (t.size, 4):
        raise ValueError(f"attitude: need (n,) epochs and (n, 4) quaternions, got {t.shape} "
                         f"and {q.shape}")
    if np.any(np.diff(t.astype(np.int64)) <= 0):
        raise ValueError("attitude: epochs are not strictly increasing")
    norm = np.linalg.norm(q, axis=1)
    if not np.all(np.abs(norm - 1.0) <= 1e-9):
        raise ValueError("attitude: quaternions are not of unit norm")
    return t, q


def write_attitude_csv(path: str | Path, times, quat, *, satellite: str = "") -> Path:
    """Write inertial -> body quaternions as leopod's attitude CSV.

    Parameters
    ----------
    path : str or Path
        Output file (``.gz``: compressed); written atomically.
    times : array_like of datetime64, shape (n,)
        Strictly increasing GPS-time epochs (written to the nanosecond).
    quat : array_like, shape (n, 4)
        Unit quaternions, scalar first, inertial (GCRF/J2000) -> body
        (:func:`leopod.frames.quaternion.quaternion_from_body_axes`); written with 17
        significant digits, so the file reads back bit-identical.
    satellite : str
        Satellite name for the header.

    Raises
    ------
    ValueError
        For epochs out of order or quaternions not of unit norm.
    """
    t, q = _checked(times, quat)
    lines = [f"{CSV_MAGIC} 1.0", f"# satellite: {satellite}", "# time system: GPS",
             "# rotation: inertial (GCRF/J2000) -> body; quaternion scalar first "
             "(q0 = cos(angle/2)); v_inertial = R(q) v_body",
             ",".join(CSV_COLUMNS)]
    lines += [f"{np.datetime_as_string(ti, unit='ns')}," + ",".join(f"{v:.17g}" for v in qi)
              for ti, qi in zip(t, q)]
    return write_text(path, "\n".join(lines) + "\n")


def write_attitude_netcdf(path: str | Path, times, quat, *, satellite: str = "",
                          step: str = "attitude") -> Path:
    """Write inertial -> body quaternions as leopod's attitude netCDF (same arguments)."""
    t, q = _checked(times, quat)
    ds = attitude_dataset(t, q, satellite=satellite)
    return write_netcdf(ds, path, step=step, time_system="GPS",
                        title=f"attitude quaternions {satellite}".strip())

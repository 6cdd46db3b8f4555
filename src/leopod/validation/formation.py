"""Baselines of a formation pair against each other, the simulated truth and a measured range.

A baseline solution (reduced-dynamic, :mod:`leopod.estimation.baseline`, or kinematic,
:mod:`leopod.estimation.kinematic_baseline`) is an ITRF vector follower − leader per epoch; two
solutions or a solution and the truth are compared as the difference vector in the leader's
radial, along-track, cross-track frame (Zhang et al. 2024, Table 6: dynamic − kinematic).
Against an inter-satellite range (K-band ranging of GRACE; Kroes et al. 2005), the length
``|Δr|`` of a baseline is compared with the range at the same epochs: a check along the line of
sight only, independent of GNSS.
"""

from __future__ import annotations

import numpy as np

from leopod.frames.earth_rotation import itrf_to_gcrf
from leopod.frames.rtn import rtn_matrix
from leopod.io.sp3 import read_sp3

__all__ = ["difference_rtn", "range_residuals", "rms_rtn", "truth_baseline_itrf"]


def truth_baseline_itrf(sp3_a, sp3_b, times: np.ndarray) -> np.ndarray:
    """True baseline B − A (ITRF) [m], shape (m, 3), from the truth SP3 files of a simulated
    pair at ``times`` (epochs of the files, GPS time)."""
    pos = [read_sp3(p, gps_time=True).pos_m.isel(sv=0).sel(time=times).values
           for p in (sp3_a, sp3_b)]
    return pos[1] - pos[0]


def difference_rtn(baseline_itrf_m: np.ndarray, reference_itrf_m: np.ndarray,
                   times: np.ndarray, leader_gcrf: np.ndarray) -> np.ndarray:
    """``baseline − reference`` in the leader's R, T, N [m], shape (m, 3).

    Parameters
    ----------
    baseline_itrf_m, reference_itrf_m : ndarray, shape (m, 3)
        Two baselines (ITRF) [m].
    times : ndarray of datetime64, shape (m,)
    leader_gcrf : ndarray, shape (m, 6)
        Leader's GCRF position [m] and velocity [m/s] (defines R, T, N).
    """
    d_gcrf, _ = itrf_to_gcrf(times, baseline_itrf_m - reference_itrf_m)   # a rotation
    return np.einsum("mij,mj->mi", rtn_matrix(leader_gcrf[:, :3], leader_gcrf[:, 3:]), d_gcrf)


def rms_rtn(diff_rtn_m: np.ndarray) -> dict[str, float]:
    """RMS per component and 3D [m] over the finite rows of (m, 3) differences, and their
    count: keys ``R``, ``T``, ``N``, ``3D``, ``n``."""
    ok = np.isfinite(diff_rtn_m).all(axis=1)
    if not ok.any():
        return {"R": np.nan, "T": np.nan, "N": np.nan, "3D": np.nan, "n": 0}
    rms = np.sqrt(np.mean(diff_rtn_m[ok] ** 2, axis=0))
    return {"R": float(rms[0]), "T": float(rms[1]), "N": float(rms[2]),
            "3D": float(np.sqrt(np.sum(rms**2))), "n": int(ok.sum())}


def range_residuals(baseline_itrf_m: np.ndarray, times: np.ndarray,
                    range_m: np.ndarray, range_times: np.ndarray) -> np.ndarray:
    """``|Δr| − range`` [m] at the baseline epochs that the range series has (m,), NaN
    elsewhere or where the baseline is NaN.

    Parameters
    ----------
    baseline_itrf_m : ndarray, shape (m, 3)
        Baseline vectors [m] (any frame: the length is compared).
    times : ndarray of datetime64, shape (m,)
    range_m : ndarray, shape (r,)
        Measured or simulated range [m].
    range_times : ndarray of datetime64, shape (r,)
        Its epochs (same time scale as ``times``).
    """
    rt = np.asarray(range_times, dtype="datetime64[ns]")
    t = np.asarray(times, dtype="datetime64[ns]")
    k = np.clip(np.searchsorted(rt, t), 0, max(rt.size - 1, 0))
    out = np.full(t.size, np.nan)
    if rt.size == 0:
        return out
    hit = rt[k] == t
    out[hit] = np.linalg.norm(baseline_itrf_m[hit], axis=1) - range_m[k[hit]]
    return out

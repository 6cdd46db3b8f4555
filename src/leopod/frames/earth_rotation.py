"""ITRF <-> GCRF transformation, IAU 2006/2000A CIO-based, with its time derivative.

``r_gcrf = Q(t) R(t) W(t) r_itrf`` (IERS Conventions 2010, eq. 5.1) with

- ``Q = (c2ixys(X + dX, Y + dY, s))^T``: CIP coordinates X, Y and CIO locator s of the IAU
  2006/2000A model (``erfa.xys06a``, eqs. 5.7, 5.10) plus the IERS celestial pole offsets;
- ``R = R3(-ERA)``: Earth rotation angle of UT1 (``erfa.era00``, eq. 5.15);
- ``W = (pom00(x_p, y_p, s'))^T``: polar motion with the TIO locator s' (``erfa.sp00``,
  eq. 5.13).

X, Y, s (the costly part: ~20 µs per epoch) are computed on a regular TT grid (1 h by default)
and interpolated with 6-point Lagrange polynomials; the interpolation error is ~3e-16 rad
(tested against direct evaluation at 10-s epochs over 30 h), far below the model accuracy.
10 800 epochs (30 h at 10 s) take ~0.1 s in total.

The derivative ``dR/dt = Q' R W + Q R' W + Q R W'`` is complete: ``R' = dERA/dt Ω R`` with
dERA/dt from the rate of the interpolated UT1 (i.e. including LOD and the sub-daily tidal
UT1 terms), and Q', W' and the UT1 rate by central differences over ±60 s (truncation error
< 1e-18 rad/s). For a LEO, dropping the precession-nutation and polar-motion rates would cost
~2.6e-5 m/s; with them the velocities agree with finite differences of the positions to
< 5e-8 m/s (tested), the limit set by the ~3e-14 rad resolution of ``erfa.era00``.

The rotation matrix is re-orthonormalised (one Newton step of the polar decomposition), so
ITRF -> GCRF -> ITRF returns a 7000-km position to ~1 nm RMS (float64 resolution).
"""

from __future__ import annotations

import erfa
import numpy as np

from leopod.constants import ERA_RATE_RAD_S, GPST_MINUS_TAI_S, TT_MINUS_TAI_S
from leopod.numerics.interpolate import interpolate_table
from leopod.time.eop import EarthOrientation, EopValues, default_earth_orientation, jd_ut1
from leopod.time.scales import jd_tt

__all__ = ["cip_xys", "gcrf_from_itrf_matrices", "gcrf_to_itrf", "itrf_to_gcrf"]


#: Half step of the central differences for the slow rotation rates [s].
_RATE_STEP_S = 60.0
#: Number of grid nodes of the X, Y, s interpolation (degree 5).
_XYS_NODES = 6
#: TT - GPST [ns] (= 32.184 s + 19 s, exact).
_TT_MINUS_GPST_NS = round((TT_MINUS_TAI_S - GPST_MINUS_TAI_S) * 1e9)


def _as_times(times) -> np.ndarray:
    return np.atleast_1d(np.asarray(times, dtype="datetime64[ns]"))


def cip_xys(times, *, step_s: float | None = 3600.0):
    """CIP coordinates X, Y and CIO locator s, IAU 2006/2000A (without dX, dY).

    Parameters
    ----------
    times : array_like of datetime64, shape (n,)
        GPS-time labels.
    step_s : float or None
        Spacing of the TT grid on which ``erfa.xys06a`` is evaluated before Lagrange
        interpolation [s]; ``None`` (or a grid with >= n nodes) evaluates every epoch.

    Returns
    -------
    x_rad, y_rad, s_rad : ndarray, shape (n,)
    """
    t = _as_times(times)
    if step_s is None:
        return erfa.xys06a(*jd_tt(t))
    tt_ns = t.astype(np.int64) + _TT_MINUS_GPST_NS
    step_ns = round(step_s * 1e9)
    half = _XYS_NODES // 2
    k0, k1 = tt_ns.min() // step_ns - half, -(-tt_ns.max() // step_ns) + half
    if k1 - k0 + 1 >= t.size:
        return erfa.xys06a(*jd_tt(t))
    nodes_ns = np.arange(k0, k1 + 1, dtype=np.int64) * step_ns
    node_times = (nodes_ns - _TT_MINUS_GPST_NS).astype("datetime64[ns]")
    xys = np.column_stack(erfa.xys06a(*jd_tt(node_times)))
    values, _ = interpolate_table((nodes_ns - nodes_ns[0]) * 1e-9, xys,
                                  (tt_ns - nodes_ns[0]) * 1e-9, order=_XYS_NODES - 1)
    return values[:, 0], values[:, 1], values[:, 2]


def _transpose(m: np.ndarray) -> np.ndarray:
    return np.swapaxes(m, -1, -2)


def _q_and_w(times: np.ndarray, eop: EopValues, step_s: float | None):
    """Q (CIRS->GCRS) and W (ITRS->TIRS) matrices, shape (n, 3, 3) each."""
    x, y, s = cip_xys(times, step_s=step_s)
    q = _transpose(erfa.c2ixys(x + eop.dx_rad, y + eop.dy_rad, s))
    w = _transpose(erfa.pom00(eop.xp_rad, eop.yp_rad, erfa.sp00(*jd_tt(times))))
    return q, w


def _orthonormalise(rot: np.ndarray) -> np.ndarray:
    """One Newton step of the polar decomposition, ``R (3I - R^T R) / 2``.

    Brings ``R^T R - I`` from ~1e-15 (three chained products) to the rounding level ~4e-16,
    so that a 7000-km position survives ITRF -> GCRF -> ITRF to a few nanometres (3 ulp).
    """
    return 0.5 * rot @ (3.0 * np.eye(3) - _transpose(rot) @ rot)


def _rotation_minus_era(era_rad: np.ndarray) -> np.ndarray:
    """R3(-ERA) (TIRS -> CIRS), shape (n, 3, 3)."""
    c, s = np.cos(era_rad), np.sin(era_rad)
    r = np.zeros(era_rad.shape + (3, 3))
    r[:, 0, 0], r[:, 0, 1], r[:, 1, 0], r[:, 1, 1], r[:, 2, 2] = c, -s, s, c, 1.0
    return r


def gcrf_from_itrf_matrices(times, eop: EarthOrientation | None = None, *,
                            xys_step_s: float | None = 3600.0):
    """ITRF -> GCRF rotation matrices and their time derivatives.

    ``r_gcrf = R @ r_itrf`` and ``v_gcrf = R @ v_itrf + dR_dt @ r_itrf``.

    Parameters
    ----------
    times : array_like of datetime64, shape (n,)
        GPS-time labels.
    eop : EarthOrientation, optional
        EOP source (default: :func:`leopod.time.eop.default_earth_orientation`).
    xys_step_s : float or None
        Grid spacing for X, Y, s (see :func:`cip_xys`) [s].

    Returns
    -------
    R : ndarray, shape (n, 3, 3)
        Rotation matrix Q R W (IERS Conventions 2010, eq. 5.1).
    dR_dt : ndarray, shape (n, 3, 3)
        Its time derivative [1/s].
    """
    t = _as_times(times)
    n = t.size
    h = np.timedelta64(int(_RATE_STEP_S * 1e9), "ns")
    all_t = np.concatenate([t - h, t, t + h])
    vals = (default_earth_orientation() if eop is None else eop).at(all_t)
    q, w = _q_and_w(all_t, vals, xys_step_s)
    now, before, after = slice(n, 2 * n), slice(0, n), slice(2 * n, 3 * n)
    era = erfa.era00(*jd_ut1(t, vals.subset(now)))
    r3 = _rotation_minus_era(era)
    ut1_rate = (vals.ut1_minus_tai_s[after] - vals.ut1_minus_tai_s[before]) / (2 * _RATE_STEP_S)
    era_rate = ERA_RATE_RAD_S * (1.0 + ut1_rate)
    omega_hat = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
    dq = (q[after] - q[before]) / (2 * _RATE_STEP_S)
    dw = (w[after] - w[before]) / (2 * _RATE_STEP_S)
    q, w = q[now], w[now]
    rot = _orthonormalise(q @ r3 @ w)
    d_rot = (dq @ r3 @ w + era_rate[:, None, None] * (q @ omega_hat @ r3 @ w)
             + q @ r3 @ dw)
    return rot, d_rot


def itrf_to_gcrf(times, pos_m, vel_m_s=None, *, eop: EarthOrientation | None = None,
                 matrices=None):
    """Transform ITRF positions (and velocities) to the GCRF.

    Parameters
    ----------
    times : array_like of datetime64, shape (n,)
        GPS-time labels.
    pos_m : array_like, shape (n, 3)
        ITRF positions [m].
    vel_m_s : array_like, shape (n, 3), optional
        ITRF (Earth-fixed) velocities [m/s].
    eop : EarthOrientation, optional
        EOP source (default: installed IERS data).
    matrices : tuple of ndarray, optional
        ``gcrf_from_itrf_matrices(times, eop)`` when the caller has them already.

    Returns
    -------
    pos_gcrf_m : ndarray, shape (n, 3)
    vel_gcrf_m_s : ndarray, shape (n, 3) or None
        Inertial velocity ``R v + dR/dt r``; None if ``vel_m_s`` is None.
    """
    rot, d_rot = gcrf_from_itrf_matrices(times, eop) if matrices is None else matrices
    pos = np.asarray(pos_m, dtype=float)
    pos_out = np.einsum("nij,nj->ni", rot, pos)
    if vel_m_s is None:
        return pos_out, None
    vel = np.asarray(vel_m_s, dtype=float)
    return pos_out, np.einsum("nij,nj->ni", rot, vel) + np.einsum("nij,nj->ni", d_rot, pos)


def gcrf_to_itrf(times, pos_m, vel_m_s=None, *, eop: EarthOrientation | None = None,
                 matrices=None):
    """Transform GCRF positions (and velocities) to the ITRF (inverse of :func:`itrf_to_gcrf`).

    Parameters
    ----------
    times : array_like of datetime64, shape (n,)
        GPS-time labels.
    pos_m : array_like, shape (n, 3)
        GCRF positions [m].
    vel_m_s : array_like, shape (n, 3), optional
        GCRF (inertial) velocities [m/s].
    eop : EarthOrientation, optional
        EOP source (default: installed IERS data).
    matrices : tuple of ndarray, optional
        ``gcrf_from_itrf_matrices(times, eop)`` when the caller has them already.

    Returns
    -------
    pos_itrf_m : ndarray, shape (n, 3)
    vel_itrf_m_s : ndarray, shape (n, 3) or None
        Earth-fixed velocity ``R^T v + (dR/dt)^T r``; None if ``vel_m_s`` is None.
    """
    rot, d_rot = gcrf_from_itrf_matrices(times, eop) if matrices is None else matrices
    pos = np.asarray(pos_m, dtype=float)
    pos_out = np.einsum("nji,nj->ni", rot, pos)
    if vel_m_s is None:
        return pos_out, None
    vel = np.asarray(vel_m_s, dtype=float)
    return pos_out, np.einsum("nji,nj->ni", rot, vel) + np.einsum("nji,nj->ni", d_rot, pos)

"""Yaw about the nadir axis: Sun angles of an orbit, the ideal yaw-steering angle, the axes.

Geometry shared by the attitude laws of GNSS satellites (:mod:`leopod.gnss.attitude`) and of
yaw-steering LEOs (:mod:`leopod.frames.leo_attitude`). The yaw ψ is the rotation about +Z
(nadir) from the along-track direction T to +X, so that ``X = cos ψ T − sin ψ N`` with N the
orbit normal r × v; ideal yaw steering keeps +Y (the solar-array axis) perpendicular to the Sun
(Bar-Sever 1996; Kouba 2009, GPS Solut.).
"""

from __future__ import annotations

import numpy as np

__all__ = ["nominal_yaw_rad", "orbit_angles", "yaw_body_axes"]


def orbit_angles(pos_m: np.ndarray, vel_m_s: np.ndarray, sun_m: np.ndarray):
    """Sun elevation above the orbit plane, orbit angle from midnight and its rate.

    Parameters
    ----------
    pos_m, vel_m_s : ndarray, shape (..., 3)
        Satellite position [m] and inertial velocity [m/s] (in an Earth-fixed frame: the
        velocity plus ω × r).
    sun_m : ndarray, shape (..., 3)
        Sun position in the same frame [m].

    Returns
    -------
    beta_rad, mu_rad, mu_dot_rad_s : ndarray, shape (...)
        β (positive towards the orbit normal r × v), μ in (−π, π] from the midnight point in
        the direction of motion (noon at ±π), dμ/dt = |r × v| / r² (Kouba 2009, sec. 2).
    """
    h = np.cross(pos_m, vel_m_s)
    r2 = np.sum(pos_m * pos_m, axis=-1)
    n = h / np.linalg.norm(h, axis=-1, keepdims=True)
    s = sun_m - pos_m
    s = s / np.linalg.norm(s, axis=-1, keepdims=True)
    sn = np.sum(s * n, axis=-1)
    beta = np.arcsin(np.clip(sn, -1.0, 1.0))
    r_hat = pos_m / np.sqrt(r2)[..., None]
    t_hat = np.cross(n, r_hat)
    # μ from midnight: Sun in-plane components s·R = −cosβ cosμ, s·T = cosβ sinμ
    mu = np.arctan2(np.sum(s * t_hat, axis=-1), -np.sum(s * r_hat, axis=-1))
    return beta, mu, np.linalg.norm(h, axis=-1) / r2


def nominal_yaw_rad(beta_rad, mu_rad):
    """Nominal yaw ψ = atan2(−tan β, sin μ) [rad] (Kouba 2009, eq. 1; Bar-Sever 1996).

    ψ is the rotation about +Z (nadir) from the along-track direction to +X (IGS convention,
    +X to the Sun-lit side, Montenbruck et al. 2015), so ``X = cos ψ T − sin ψ N``.
    """
    return np.arctan2(-np.tan(beta_rad), np.sin(mu_rad))


def yaw_body_axes(pos_m: np.ndarray, vel_m_s: np.ndarray, yaw_rad: np.ndarray) -> np.ndarray:
    """Body axes (rows X, Y, Z), shape (..., 3, 3), for a yaw angle about the nadir axis.

    ``Z = −r̂``, ``X = cos ψ T − sin ψ N`` (T along track, N = r × v / |r × v|), ``Y = Z × X``;
    ψ = :func:`nominal_yaw_rad` gives the yaw-steering axes (Y ⊥ Sun, X to the Sun-lit side),
    ψ = 0 the nominal LEO axes of :func:`leopod.frames.attitude.nominal_axes_inertial`.
    """
    r_hat = pos_m / np.linalg.norm(pos_m, axis=-1, keepdims=True)
    n = np.cross(pos_m, vel_m_s)
    n = n / np.linalg.norm(n, axis=-1, keepdims=True)
    t_hat = np.cross(n, r_hat)
    c, s = np.cos(yaw_rad)[..., None], np.sin(yaw_rad)[..., None]
    ex = c * t_hat - s * n
    ez = -r_hat
    return np.stack([ex, np.cross(ez, ex), ez], axis=-2)

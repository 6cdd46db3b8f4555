"""Nominal LEO attitude and line-of-sight angles in the antenna (body) frame.

Nominal attitude (Peng et al. 2021, sec. II-A; GRACE SRF): +Z points to the geocentre, +X along the
inertial velocity (made orthogonal to Z), +Y = Z × X completes the right-handed frame (it
points opposite to the orbit normal). The inertial velocity expressed in Earth-fixed axes is
``v_ef + ω × r``; using the Earth-fixed velocity instead would yaw the frame by up to ~3.5°
at the equator.

Antenna-frame angles: the antenna looks along −Z (zenith). Elevation is the angle of the
line of sight above the body X–Y plane (90° = along −Z); azimuth is measured from +X
(flight direction) towards +Y, in degrees in [0, 360) — the convention of Peng et al. (2021)
Figs. 7–9. The attitude law of a satellite (nominal or yaw steering) is picked by
:mod:`leopod.frames.leo_attitude`.
"""

from __future__ import annotations

import numpy as np

from leopod.constants import OMEGA_EARTH_RAD_S

__all__ = ["antenna_angles", "body_to_ef", "inertial_velocity_ef", "nominal_axes_inertial",
           "nominal_body_axes"]


def nominal_body_axes(pos_m: np.ndarray, vel_ef_m_s: np.ndarray) -> np.ndarray:
    """Body axes of the nominal attitude expressed in Earth-fixed coordinates.

    Parameters
    ----------
    pos_m : ndarray, shape (n, 3)
        Earth-fixed position [m].
    vel_ef_m_s : ndarray, shape (n, 3)
        Earth-fixed velocity [m/s].

    Returns
    -------
    ndarray, shape (n, 3, 3)
        Rows are the unit vectors X, Y, Z of the body frame in Earth-fixed coordinates, i.e.
        the rotation matrix from Earth-fixed to body: ``v_body = R @ v_ef``.
    """
    return nominal_axes_inertial(pos_m, inertial_velocity_ef(pos_m, vel_ef_m_s))


def inertial_velocity_ef(pos_m: np.ndarray, vel_ef_m_s: np.ndarray) -> np.ndarray:
    """Inertial velocity in Earth-fixed axes, ``v_ef + ω × r`` [m/s], shape (n, 3)."""
    return (np.asarray(vel_ef_m_s, dtype=float)
            + np.cross([0.0, 0.0, OMEGA_EARTH_RAD_S], np.asarray(pos_m, dtype=float)))


def body_to_ef(rot_ef_to_body: np.ndarray, vec_body: np.ndarray) -> np.ndarray:
    """Rotate body-frame vectors (n, 3) or one (3,) into Earth-fixed axes."""
    return np.einsum("...ji,...j->...i", rot_ef_to_body, vec_body)


def antenna_angles(rot_ef_to_body: np.ndarray, los_ef: np.ndarray):
    """Elevation and azimuth of lines of sight in the antenna frame.

    Parameters
    ----------
    rot_ef_to_body : ndarray, shape (n, 3, 3)
        Earth-fixed -> body rotation per epoch (from :func:`nominal_body_axes`).
    los_ef : ndarray, shape (n, s, 3)
        Receiver-to-transmitter vectors in Earth-fixed coordinates (any length).

    Returns
    -------
    el_deg, az_deg : ndarray, shape (n, s)
        Elevation above the body X–Y plane towards −Z [deg] and azimuth from +X towards +Y
        in [0, 360) [deg].
    """
    los = np.asarray(los_ef, dtype=float)
    unit = los / np.linalg.norm(los, axis=-1, keepdims=True)
    body = np.einsum("nij,nsj->nsi", rot_ef_to_body, unit)
    el = np.degrees(np.arcsin(np.clip(-body[..., 2], -1.0, 1.0)))
    az = np.degrees(np.arctan2(body[..., 1], body[..., 0])) % 360.0
    return el, az


def nominal_axes_inertial(pos_m: np.ndarray, vel_m_s: np.ndarray) -> np.ndarray:
    """Nominal body axes (rows X, Y, Z), shape (n, 3, 3), from inertial position/velocity."""
    pos_m = np.asarray(pos_m, dtype=float)
    z = -pos_m / np.linalg.norm(pos_m, axis=-1, keepdims=True)
    y = np.cross(z, vel_m_s)
    y /= np.linalg.norm(y, axis=-1, keepdims=True)
    return np.stack([np.cross(y, z), y, z], axis=-2)

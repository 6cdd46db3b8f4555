"""Nominal LEO attitude and line-of-sight angles in the antenna (body) frame.

Nominal attitude (Peng et al. 2021, sec. II-A; GRACE SRF): +Z points to the geocentre, +X along the
inertial velocity (made orthogonal to Z), +Y = Z × X completes the right-handed frame (it
points opposite to the orbit normal). The inertial velocity expressed in Earth-fixed axes is
``v_ef + ω × r``; using the Earth-fixed velocity instead would yaw the frame by up to ~3.5°
at the equator.

Antenna-frame angles (one definition, :func:`antenna_el_az`, used by the simulator, ingest,
quality, code-bias maps, POD and the LEO antenna model): the antenna frame has north ``N``,
east ``E`` and up (boresight) ``U`` axes given in the body frame, right-handed as ANTEX's
north/east/up (``E = N × U``, so that ``E × N = U``). The elevation is the angle of the line of
sight above the antenna's N–E plane (90° = along ``U``; zenith angle = 90° − elevation); the
azimuth counts from ``N`` towards ``E`` (clockwise from north seen from above the antenna, the
receiver azimuth of ANTEX 1.4, sec. 3), in degrees in [0, 360). The default frame is
``N = +X`` (flight direction), ``U = −Z`` (away from the geocentre), hence ``E = +X × −Z =
+Y``: elevation above the body X–Y plane towards −Z and azimuth from +X towards +Y, the
convention of Peng et al. (2021) Figs. 7–9. The attitude law of a satellite (nominal or yaw steering) is picked by
:mod:`leopod.frames.leo_attitude`.
"""

from __future__ import annotations

import numpy as np

from leopod.constants import OMEGA_EARTH_RAD_S

__all__ = ["DEFAULT_ANTENNA_FRAME", "antenna_angles", "antenna_el_az", "antenna_frame",
           "body_to_ef", "inertial_velocity_ef", "nominal_axes_inertial",
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


#: Rows N, E, U of the default antenna frame in body coordinates (module docstring).
DEFAULT_ANTENNA_FRAME = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]])
_FRAME_TOLERANCE = 1e-6


def antenna_frame(north_body, up_body) -> np.ndarray:
    """The antenna frame from its north and up (boresight) axes in the body frame.

    Parameters
    ----------
    north_body, up_body : array_like, shape (3,)
        Unit vectors of the antenna's north and up axes in body coordinates (normalised here;
        they must be orthogonal to within 1e-6).

    Returns
    -------
    ndarray, shape (3, 3)
        Rows ``N``, ``E = N × U``, ``U`` in body coordinates: the body -> antenna rotation
        (``v_ant = F @ v_body``).

    Raises
    ------
    ValueError
        If an axis is zero or the two are not orthogonal.
    """
    n = np.asarray(north_body, dtype=float).reshape(3)
    u = np.asarray(up_body, dtype=float).reshape(3)
    if np.linalg.norm(n) == 0.0 or np.linalg.norm(u) == 0.0:
        raise ValueError(f"antenna frame: zero axis (north_body {n.tolist()}, up_body "
                         f"{u.tolist()})")
    n, u = n / np.linalg.norm(n), u / np.linalg.norm(u)
    if abs(float(n @ u)) > _FRAME_TOLERANCE:
        raise ValueError(f"antenna frame: north_body {n.tolist()} and up_body {u.tolist()} "
                         f"are not orthogonal (cosine {float(n @ u):.3g})")
    return np.stack([n, np.cross(n, u), u])


def antenna_el_az(los_body: np.ndarray, frame: np.ndarray | None = None):
    """Elevation and azimuth of unit lines of sight given in the body frame.

    Parameters
    ----------
    los_body : ndarray, shape (..., 3)
        Unit receiver-to-transmitter vectors in body coordinates.
    frame : ndarray, shape (3, 3), optional
        Antenna frame of :func:`antenna_frame` (rows N, E, U in body coordinates); None:
        :data:`DEFAULT_ANTENNA_FRAME`.

    Returns
    -------
    el_deg, az_deg : ndarray, shape (...)
        Elevation above the antenna's N–E plane towards ``U`` [deg] (zenith angle = 90° − el)
        and azimuth from ``N`` towards ``E`` in [0, 360) [deg].
    """
    los_body = np.asarray(los_body, dtype=float)
    if frame is None:       # N = +X, E = +Y, U = −Z (exactly, without the products)
        n, e, u = los_body[..., 0], los_body[..., 1], -los_body[..., 2]
    else:
        ant = np.einsum("ij,...j->...i", np.asarray(frame, dtype=float), los_body)
        n, e, u = ant[..., 0], ant[..., 1], ant[..., 2]
    el = np.degrees(np.arcsin(np.clip(u, -1.0, 1.0)))
    az = np.degrees(np.arctan2(e, n)) % 360.0
    return el, az


def antenna_angles(rot_ef_to_body: np.ndarray, los_ef: np.ndarray,
                   frame: np.ndarray | None = None):
    """Elevation and azimuth of lines of sight in the antenna frame.

    Parameters
    ----------
    rot_ef_to_body : ndarray, shape (n, 3, 3)
        Earth-fixed -> body rotation per epoch (from :func:`nominal_body_axes`).
    los_ef : ndarray, shape (n, s, 3)
        Receiver-to-transmitter vectors in Earth-fixed coordinates (any length).
    frame : ndarray, shape (3, 3), optional
        Antenna frame in the body frame (:func:`antenna_frame`); None: the default
        (N = +X, E = +Y, U = −Z).

    Returns
    -------
    el_deg, az_deg : ndarray, shape (n, s)
        Elevation above the antenna horizon [deg] and azimuth from north towards east in
        [0, 360) [deg] (:func:`antenna_el_az`); with the default frame the elevation above
        the body X–Y plane towards −Z and the azimuth from +X towards +Y.
    """
    los = np.asarray(los_ef, dtype=float)
    unit = los / np.linalg.norm(los, axis=-1, keepdims=True)
    body = np.einsum("nij,nsj->nsi", rot_ef_to_body, unit)
    return antenna_el_az(body, frame)


def nominal_axes_inertial(pos_m: np.ndarray, vel_m_s: np.ndarray) -> np.ndarray:
    """Nominal body axes (rows X, Y, Z), shape (n, 3, 3), from inertial position/velocity."""
    pos_m = np.asarray(pos_m, dtype=float)
    z = -pos_m / np.linalg.norm(pos_m, axis=-1, keepdims=True)
    y = np.cross(z, vel_m_s)
    y /= np.linalg.norm(y, axis=-1, keepdims=True)
    return np.stack([np.cross(y, z), y, z], axis=-2)

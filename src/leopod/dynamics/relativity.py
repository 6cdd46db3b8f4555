"""Relativistic corrections to the acceleration of an Earth satellite (GCRF).

IERS Conventions 2010, eq. (10.12), with the PPN parameters β = γ = 1:

* Schwarzschild: ``GM/(c² r³) [(4 GM/r − v²) r + 4 (r·v) v]``
* Lense–Thirring: ``2 GM/(c² r³) [3/r² (r × v)(r · J) + v × J]`` with ``J`` the Earth's
  angular momentum per unit mass (|J| = 9.8e8 m²/s, IERS 2010 sec. 10.3)
* de Sitter (geodesic precession): ``3 [(−GM_S/(c² R³)) (Ṙ × R)] × v`` with ``R``, ``Ṙ`` the
  position and velocity of the Earth with respect to the Sun.

For a LEO the Schwarzschild term is ~1e-8 m/s² (a few cm over a day), the others ~1e-10.
The partial derivatives with respect to position and velocity are neglected (relative size
< 1e-9 of the gravity gradient), as is usual in POD (Montenbruck & Gill 2000, sec. 3.7.3).
"""

from __future__ import annotations

import numpy as np

from leopod.constants import C_LIGHT_M_S, EARTH_ANGULAR_MOMENTUM_M2_S, GM_EARTH_M3_S2, GM_SUN_M3_S2

__all__ = ["relativistic_acceleration", "EARTH_ANGULAR_MOMENTUM_M2_S"]



def relativistic_acceleration(pos_m, vel_m_s, sun_m=None, sun_vel_m_s=None, *,
                              gm_sun_m3_s2: float | None = None, lense_thirring: bool = True):
    """Relativistic acceleration of IERS Conventions 2010 eq. (10.12) [m/s²].

    Parameters
    ----------
    pos_m, vel_m_s : ndarray, shape (..., 3)
        Geocentric GCRF position [m] and velocity [m/s] of the satellite.
    sun_m, sun_vel_m_s : ndarray, shape (..., 3), optional
        Geocentric GCRF position [m] and velocity [m/s] of the Sun; when given, the de Sitter
        term is added (the Earth's heliocentric state is their negative).
    gm_sun_m3_s2 : float, optional
        Heliocentric gravitational constant (default IERS 2010 value).
    lense_thirring : bool
        Include the Lense–Thirring term.

    Returns
    -------
    ndarray, shape (..., 3)
    """
    r = np.asarray(pos_m, dtype=float)
    v = np.asarray(vel_m_s, dtype=float)
    c2 = C_LIGHT_M_S**2
    gm = GM_EARTH_M3_S2
    rn = np.linalg.norm(r, axis=-1, keepdims=True)
    rv = np.sum(r * v, axis=-1, keepdims=True)
    vv = np.sum(v * v, axis=-1, keepdims=True)
    acc = gm / (c2 * rn**3) * ((4.0 * gm / rn - vv) * r + 4.0 * rv * v)
    if lense_thirring:
        j = np.array([0.0, 0.0, EARTH_ANGULAR_MOMENTUM_M2_S])
        rj = np.sum(r * j, axis=-1, keepdims=True)
        acc = acc + 2.0 * gm / (c2 * rn**3) * (3.0 / rn**2 * np.cross(r, v) * rj + np.cross(v, j))
    if sun_m is not None:
        gms = GM_SUN_M3_S2 if gm_sun_m3_s2 is None else gm_sun_m3_s2
        big_r = -np.asarray(sun_m, dtype=float)          # Earth w.r.t. Sun
        big_v = -np.asarray(sun_vel_m_s, dtype=float)
        rn_s = np.linalg.norm(big_r, axis=-1, keepdims=True)
        omega = -gms / (c2 * rn_s**3) * np.cross(big_v, big_r)
        acc = acc + 3.0 * np.cross(omega, v)
    return acc

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

:class:`Relativity` is the force of the orbit integrator (compiled kernel, Sun interpolated
on the grid of :class:`leopod.dynamics.environment.ArcEnvironment`).
"""

from __future__ import annotations

import numba
import numpy as np

from leopod.constants import C_LIGHT_M_S, EARTH_ANGULAR_MOMENTUM_M2_S, GM_EARTH_M3_S2, GM_SUN_M3_S2
from leopod.dynamics.environment import ArcEnvironment
from leopod.dynamics.forces import Force
from leopod.numerics.interpolate import lagrange_equidistant

__all__ = ["Relativity", "relativistic_acceleration", "EARTH_ANGULAR_MOMENTUM_M2_S"]



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


@numba.njit(cache=True)
def _cross(a, b):  # pragma: no cover - numba
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                     a[0] * b[1] - a[1] * b[0]])


@numba.njit(cache=True)
def _relativity_kernel(t, pos, vel, body_grid, lense_thirring, de_sitter):  # pragma: no cover
    """IERS Conventions 2010 eq. (10.12), β = γ = 1 (see the module docstring)."""
    c2 = C_LIGHT_M_S * C_LIGHT_M_S
    gm = GM_EARTH_M3_S2
    r = np.sqrt(pos[0] ** 2 + pos[1] ** 2 + pos[2] ** 2)
    rv = pos[0] * vel[0] + pos[1] * vel[1] + pos[2] * vel[2]
    vv = vel[0] ** 2 + vel[1] ** 2 + vel[2] ** 2
    k = gm / (c2 * r**3)
    acc = k * ((4.0 * gm / r - vv) * pos + 4.0 * rv * vel)
    if lense_thirring:
        j = np.array([0.0, 0.0, EARTH_ANGULAR_MOMENTUM_M2_S])
        acc += 2.0 * k * (3.0 / r**2 * pos[2] * j[2] * _cross(pos, vel) + _cross(vel, j))
    if de_sitter:
        bodies = np.empty(9)
        lagrange_equidistant(t, body_grid[0], body_grid[1], body_grid[2], body_grid[3], bodies)
        big_r = -bodies[0:3]                                   # Earth w.r.t. the Sun
        big_v = -bodies[3:6]
        nr = np.sqrt(big_r[0] ** 2 + big_r[1] ** 2 + big_r[2] ** 2)
        omega = -GM_SUN_M3_S2 / (c2 * nr**3) * _cross(big_v, big_r)
        acc += 3.0 * _cross(omega, vel)
    return acc


class Relativity(Force):
    """Relativistic corrections of IERS Conventions 2010 eq. (10.12), partials neglected.

    Parameters
    ----------
    env : ArcEnvironment
    lense_thirring, de_sitter : bool
        Include these terms (Schwarzschild always).
    """

    def __init__(self, env: ArcEnvironment, lense_thirring: bool = True, de_sitter: bool = True):
        self.env = env
        self.lense_thirring, self.de_sitter = bool(lense_thirring), bool(de_sitter)
        self.parameters = []

    def kernel_data(self) -> tuple:
        """``(Sun grid, lense_thirring, de_sitter)`` (compiled force model)."""
        return self.env.body_grid.args(), self.lense_thirring, self.de_sitter

    def evaluate(self, t_s, pos_m, vel_m_s, params):
        self.env.check(t_s)
        acc = _relativity_kernel(float(t_s), np.ascontiguousarray(pos_m, dtype=float),
                                 np.ascontiguousarray(vel_m_s, dtype=float),
                                 self.env.body_grid.args(), self.lense_thirring, self.de_sitter)
        return acc, np.zeros((3, 3)), np.zeros((3, 3)), np.zeros((3, 0))

"""Sun and Moon as point masses: the third-body acceleration and its gradient.

The positions of the bodies come from :mod:`leopod.astro.ephemeris` (JPL DE421).

Acceleration of a satellite at ``r`` by a body at ``s`` (geocentric), including the indirect
term (the acceleration of the Earth by the body), Montenbruck & Gill (2000) eq. (3.37):
``a = GM (s − r)/|s − r|³ − GM s/|s|³``; its gradient
``∂a/∂r = GM (3 d dᵀ/|d|⁵ − I/|d|³)`` with ``d = s − r``.

:class:`ThirdBodies` is the force of the orbit integrator (compiled kernel, Sun and Moon
interpolated on the grid of :class:`leopod.dynamics.environment.ArcEnvironment`).
"""

from __future__ import annotations

import numba
import numpy as np

from leopod.constants import GM_MOON_M3_S2, GM_SUN_M3_S2
from leopod.dynamics.environment import ArcEnvironment
from leopod.dynamics.forces import Force
from leopod.numerics.interpolate import lagrange_equidistant

__all__ = ["GM_SUN_M3_S2", "GM_MOON_M3_S2", "ThirdBodies", "third_body_acceleration"]


def third_body_acceleration(pos_m: np.ndarray, body_m: np.ndarray, gm_m3_s2: float,
                            with_gradient: bool = True):
    """Point-mass perturbation of a third body, with the indirect term.

    Parameters
    ----------
    pos_m : ndarray, shape (..., 3)
        Geocentric satellite position [m].
    body_m : ndarray, shape (..., 3)
        Geocentric position of the body [m] (broadcast against ``pos_m``).
    gm_m3_s2 : float
        Gravitational constant of the body [m³/s²].
    with_gradient : bool
        Also return ``∂a/∂r``.

    Returns
    -------
    acc : ndarray, shape (..., 3)
        Acceleration [m/s²].
    grad : ndarray, shape (..., 3, 3), only if ``with_gradient``
        ``∂a/∂r`` [1/s²].
    """
    d = body_m - pos_m
    nd = np.linalg.norm(d, axis=-1, keepdims=True)
    ns = np.linalg.norm(body_m, axis=-1, keepdims=True)
    acc = gm_m3_s2 * (d / nd**3 - body_m / ns**3)
    if not with_gradient:
        return acc
    eye = np.eye(3)
    grad = gm_m3_s2 * (3.0 * d[..., :, None] * d[..., None, :] / nd[..., None] ** 5
                       - eye / nd[..., None] ** 3)
    return acc, grad


@numba.njit(cache=True)
def _third_body_kernel(t, pos, body_grid, gm, acc, grad):  # pragma: no cover - numba
    """Sun (gm[0]) and Moon (gm[1]; 0 = off) point masses with the indirect term,
    M&G (2000) eq. 3.37, and the gradient ``GM (3 d dᵀ/|d|⁵ − I/|d|³)``, d = s − r."""
    bodies = np.empty(9)
    lagrange_equidistant(t, body_grid[0], body_grid[1], body_grid[2], body_grid[3], bodies)
    acc[:] = 0.0
    grad[:, :] = 0.0
    for b in range(2):
        if gm[b] == 0.0:
            continue
        s = bodies[6 * b:6 * b + 3]
        d = s - pos
        nd = np.sqrt(d[0] ** 2 + d[1] ** 2 + d[2] ** 2)
        ns = np.sqrt(s[0] ** 2 + s[1] ** 2 + s[2] ** 2)
        k3, ks3 = gm[b] / nd**3, gm[b] / ns**3
        for i in range(3):
            acc[i] += k3 * d[i] - ks3 * s[i]
            for j in range(3):
                grad[i, j] += 3.0 * k3 * d[i] * d[j] / (nd * nd) - (k3 if i == j else 0.0)


class ThirdBodies(Force):
    """Sun and Moon as point masses (DE421 via ``env``), M&G (2000) eq. 3.37.

    Parameters
    ----------
    env : ArcEnvironment
    sun, moon : bool
        Include the body.
    """

    def __init__(self, env: ArcEnvironment, sun: bool = True, moon: bool = True):
        self.env = env
        self.parameters = []
        self._gm = np.array([GM_SUN_M3_S2 if sun else 0.0, GM_MOON_M3_S2 if moon else 0.0])

    def kernel_data(self) -> tuple:
        """``(Sun and Moon grid, GM of Sun and Moon (0 = off))`` (compiled force model)."""
        return self.env.body_grid.args(), self._gm

    def evaluate(self, t_s, pos_m, vel_m_s, params):
        self.env.check(t_s)
        acc = np.empty(3)
        grad = np.empty((3, 3))
        _third_body_kernel(float(t_s), np.ascontiguousarray(pos_m, dtype=float),
                           self.env.body_grid.args(), self._gm, acc, grad)
        return acc, grad, np.zeros((3, 3)), np.zeros((3, 0))

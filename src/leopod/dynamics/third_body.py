"""Sun and Moon as point masses: the third-body acceleration and its gradient.

The positions of the bodies come from :mod:`leopod.astro.ephemeris` (JPL DE421).

Acceleration of a satellite at ``r`` by a body at ``s`` (geocentric), including the indirect
term (the acceleration of the Earth by the body), Montenbruck & Gill (2000) eq. (3.37):
``a = GM (s − r)/|s − r|³ − GM s/|s|³``; its gradient
``∂a/∂r = GM (3 d dᵀ/|d|⁵ − I/|d|³)`` with ``d = s − r``.
"""

from __future__ import annotations

import numpy as np

from leopod.constants import GM_MOON_M3_S2, GM_SUN_M3_S2

__all__ = ["GM_SUN_M3_S2", "GM_MOON_M3_S2", "third_body_acceleration"]


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

"""Thin-shell ionosphere of the simulator: slant TEC as a smooth function of the receiver
position and the line of sight.

The electrons above a LEO sit in a thin shell ``h`` above it (the default 400 km). The slant
TEC of a line of sight is the vertical TEC times the thin-shell obliquity factor (the single
layer model, Schaer 1999)::

    STEC = VTEC / cos z',   sin z' = r / (r + h) · cos e

``e`` the elevation of the line of sight above the receiver's local horizontal (normal to the
geocentric radius), ``r`` the receiver's geocentric distance; the vertical TEC follows the Sun,
``V_night + (V_day − V_night) max(0, r̂·ŝ)`` (``ŝ`` the direction of the Sun). Nothing in it
depends on which receiver looks: two receivers ``d`` apart see a difference that is of first
order in ``d`` (a formation's double-difference ionosphere is small, as for Lutan-1, Zhang et
al. 2024, whose few-km baselines are processed like short baselines):

* the day/night factor changes by at most ``|Δr̂| ≤ d / r``, so ``|ΔVTEC| ≤ (V_day − V_night)
  d / r``;
* the elevation changes by at most ``d / r`` (the local vertical turns) plus ``d / ρ`` (the
  line of sight to a transmitter at distance ρ turns), and the obliquity factor
  ``F = (1 − k² cos² e)^(−1/2)``, ``k = r/(r + h)``, by ``|dF/de| = k² cos e sin e F³`` per
  radian.

For ``d`` = 1 km at 607 km altitude (``d/r`` = 1.4e-4) the first-order delay on L1 (0.162 m per
TECU) then differs by at most a few tenths of a millimetre to about a millimetre
(tests/simulate/test_formation.py evaluates the bound and the simulated difference).
"""

from __future__ import annotations

import numpy as np

__all__ = ["slant_tec_tecu", "thin_shell_stec_tecu"]


def thin_shell_stec_tecu(radius_m, local_el_deg, sun_cos, vtec_tecu: tuple[float, float],
                         shell_height_m: float) -> np.ndarray:
    """Slant TEC [TECU] from the receiver radius, local elevation and Sun cosine.

    Parameters
    ----------
    radius_m : ndarray, shape (n, 1) or broadcastable
        Geocentric distance of the receiver [m].
    local_el_deg : ndarray, shape (n, s)
        Elevation of the line of sight above the local horizontal [deg].
    sun_cos : ndarray, shape (n,)
        Cosine of the Sun's zenith angle at the receiver (``r̂·ŝ``).
    vtec_tecu : tuple of float
        Night and day vertical TEC [TECU].
    shell_height_m : float
        Height of the shell above the receiver [m].

    Returns
    -------
    ndarray, shape (n, s)
    """
    sin_z = radius_m / (radius_m + shell_height_m) * np.cos(np.radians(local_el_deg))
    night, day = vtec_tecu
    vtec = night + (day - night) * np.clip(np.asarray(sun_cos), 0.0, None)[:, None]
    return vtec / np.sqrt(1.0 - np.clip(sin_z, 0.0, 0.999) ** 2)


def slant_tec_tecu(receiver_m: np.ndarray, transmitter_m: np.ndarray, sun_m: np.ndarray,
                   vtec_tecu: tuple[float, float], shell_height_m: float) -> np.ndarray:
    """Slant TEC [TECU] of the lines of sight from receivers to transmitters (module
    docstring).

    Parameters
    ----------
    receiver_m : ndarray, shape (n, 3)
        Receiver positions (any geocentric frame) [m].
    transmitter_m : ndarray, shape (n, s, 3)
        Transmitter positions in the same frame [m].
    sun_m : ndarray, shape (n, 3)
        Sun positions in the same frame [m].
    vtec_tecu : tuple of float
        Night and day vertical TEC [TECU].
    shell_height_m : float
        Height of the shell above the receiver [m].

    Returns
    -------
    ndarray, shape (n, s)
    """
    rx = np.asarray(receiver_m, dtype=float)
    radius = np.linalg.norm(rx, axis=-1, keepdims=True)
    up = rx / radius
    los = np.asarray(transmitter_m, dtype=float) - rx[:, None, :]
    los /= np.linalg.norm(los, axis=-1, keepdims=True)
    local_el = np.degrees(np.arcsin(np.clip(np.einsum("nsi,ni->ns", los, up), -1.0, 1.0)))
    sun = np.asarray(sun_m, dtype=float)
    sun_cos = np.sum(up * sun / np.linalg.norm(sun, axis=-1, keepdims=True), axis=-1)
    return thin_shell_stec_tecu(radius, local_el, sun_cos, vtec_tecu, shell_height_m)

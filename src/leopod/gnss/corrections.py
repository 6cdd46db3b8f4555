"""Small physical corrections of undifferenced GNSS observations.

All functions are vectorised over observations and frame-agnostic (inputs in one common
Cartesian frame).

* Phase wind-up (Wu et al. 1993, Manuscripta Geodaetica 18:91-98; IERS Conventions 2010
  is silent, the formulation is that of Kouba 2009, "A guide to using IGS products", sec. 5.3).
* Shapiro (gravitational) signal delay (IERS Conventions 2010, eq. 11.17, γ = 1).
* Periodic relativistic correction of the satellite clock (IS-GPS-200, sec. 20.3.3.3.3.1;
  IERS Conventions 2010, eq. 10.17): ``Δt = −2 r·v / c²``, to be added to a clock product
  that does not contain it (all IGS clock products).
"""

from __future__ import annotations

import numpy as np

from leopod.constants import C_LIGHT_M_S, GM_EARTH_M3_S2

__all__ = ["relativistic_clock_s", "shapiro_delay_distances_m", "shapiro_delay_m", "unwrap_windup",
           "windup_cycles"]


def _dipole(x: np.ndarray, y: np.ndarray, k: np.ndarray, sign: float) -> np.ndarray:
    """Effective dipole ``x − k (k·x) ± k × y`` (Kouba 2009, eq. 5.3)."""
    return x - k * np.sum(k * x, axis=-1, keepdims=True) + sign * np.cross(k, y)


def windup_cycles(k_unit: np.ndarray, rx_x: np.ndarray, rx_y: np.ndarray,
                  sv_x: np.ndarray, sv_y: np.ndarray) -> np.ndarray:
    """Phase wind-up of a right-circularly polarised signal, wrapped to (−0.5, 0.5] cycles.

    Parameters
    ----------
    k_unit : ndarray, shape (n, 3)
        Unit vector from the transmitter to the receiver.
    rx_x, rx_y : ndarray, shape (n, 3)
        Receiver antenna dipole axes: unit vectors with ``rx_x × rx_y`` along the antenna
        boresight (for a ground antenna north and west, boresight up).
    sv_x, sv_y : ndarray, shape (n, 3)
        Transmitter body axes X and Y (``sv_x × sv_y`` = boresight towards the Earth).

    Returns
    -------
    ndarray, shape (n,)
        ``Δφ = sign(k·(D_s × D_r)) arccos(D_s·D_r / |D_s||D_r|) / 2π`` [cycles]; to be
        *added* to the modelled carrier phase (in cycles; times λ in metres), then made
        continuous with :func:`unwrap_windup`.
    """
    d_rx = _dipole(rx_x, rx_y, k_unit, +1.0)
    d_sv = _dipole(sv_x, sv_y, k_unit, -1.0)
    cos = np.sum(d_sv * d_rx, axis=-1) / (np.linalg.norm(d_sv, axis=-1)
                                          * np.linalg.norm(d_rx, axis=-1))
    angle = np.arccos(np.clip(cos, -1.0, 1.0))
    sign = np.sign(np.sum(k_unit * np.cross(d_sv, d_rx), axis=-1))
    return np.where(sign < 0, -angle, angle) / (2.0 * np.pi)


def unwrap_windup(windup_cyc: np.ndarray, track: np.ndarray, order: np.ndarray) -> np.ndarray:
    """Make wind-up continuous along each track (satellite) in time order.

    Parameters
    ----------
    windup_cyc : ndarray, shape (n,)
        Wrapped wind-up [cycles] (:func:`windup_cycles`).
    track : ndarray of int, shape (n,)
        Track (e.g. satellite index) of each observation.
    order : ndarray of int, shape (n,)
        Time order key (e.g. epoch index) of each observation.

    Returns
    -------
    ndarray, shape (n,)
        Wind-up [cycles] without jumps of whole cycles between consecutive observations of
        a track (the first value of each track stays in (−0.5, 0.5]).
    """
    out = np.asarray(windup_cyc, dtype=float).copy()
    idx = np.lexsort((order, track))
    w = out[idx]
    same = track[idx][1:] == track[idx][:-1]
    step = np.diff(w)
    step = np.where(same, step - np.round(step), 0.0)
    jumps = np.concatenate([[0.0], step])
    starts = np.concatenate([[True], ~same])
    # cumulative sum restarted at the start of each track
    total = np.cumsum(jumps)
    seg = np.cumsum(starts) - 1
    base = total[starts][seg]
    out[idx] = w[starts][seg] + (total - base)
    return out


def shapiro_delay_distances_m(r1_m, r2_m, rho_m):
    """Gravitational delay of one light path in the Earth's field [m].

    ``Δ = (1 + γ) GM/c² ln((r1 + r2 + ρ) / (r1 + r2 − ρ))`` with γ = 1 (IERS Conventions 2010,
    eq. 11.17, Earth term only: in the geocentric frame the Sun's term is not applied).

    Parameters
    ----------
    r1_m, r2_m : array_like
        Geocentric distances of the two ends of the path [m].
    rho_m : array_like
        Length of the path [m].
    """
    r12 = np.asarray(r1_m, dtype=float) + np.asarray(r2_m, dtype=float)
    rho = np.asarray(rho_m, dtype=float)
    return 2.0 * GM_EARTH_M3_S2 / C_LIGHT_M_S**2 * np.log((r12 + rho) / (r12 - rho))


def shapiro_delay_m(pos_tx_m: np.ndarray, pos_rx_m: np.ndarray) -> np.ndarray:
    """Gravitational signal delay [m], shape (n,), between geocentric positions (n, 3)."""
    return shapiro_delay_distances_m(np.linalg.norm(pos_tx_m, axis=-1),
                                     np.linalg.norm(pos_rx_m, axis=-1),
                                     np.linalg.norm(pos_tx_m - pos_rx_m, axis=-1))


def relativistic_clock_s(pos_m: np.ndarray, vel_m_s: np.ndarray) -> np.ndarray:
    """Periodic relativistic clock correction ``−2 r·v / c²`` [s], shape (n,).

    Valid in an Earth-fixed or inertial frame alike (``r·(ω × r) = 0``).
    """
    return -2.0 * np.sum(pos_m * vel_m_s, axis=-1) / C_LIGHT_M_S**2

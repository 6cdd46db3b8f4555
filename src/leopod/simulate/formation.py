"""A follower satellite defined relative to a leader by relative orbital elements (ROE).

ROE (quasi-nonsingular, D'Amico & Montenbruck 2006; D'Amico 2010, ch. 2), follower
minus leader, ``u`` the argument of latitude, ``e_x = e cos ω``, ``e_y = e sin ω``::

    δa = (a_f − a_l)/a_l          δλ = (u_f − u_l) + (Ω_f − Ω_l) cos i_l
    δe = (e_x,f − e_x,l, e_y,f − e_y,l)
    δi = (i_f − i_l, (Ω_f − Ω_l) sin i_l)

Configured scaled by the leader's semi-major axis, in metres (``a δa``, ``a δλ``, …,
``satellites.<sat>.formation``). For near-circular orbits the linearised relative motion in
the leader's RTN frame (the Hill–Clohessy–Wiltshire solution written in ROE, D'Amico &
Montenbruck 2006; D'Amico 2010, ch. 2) is::

    ρ_R / a = δa − δe_x cos u − δe_y sin u
    ρ_T / a = −(3/2) δa (u − u_0) + δλ + 2 δe_x sin u − 2 δe_y cos u
    ρ_N / a = δi_x sin u − δi_y cos u

so the along-track separation averages ``a δλ`` (for δa = 0), the radial and cross-track
separations oscillate once per revolution with amplitudes ``a |δe|`` and ``a |δi|`` (the
along-track one with ``2 a |δe|``); parallel δe and δi vectors give the passively safe helix
of TanDEM-X (D'Amico & Montenbruck 2006).

Initial state of the follower: the leader's osculating GCRF state plus the linear relative
position and velocity at the leader's argument of latitude (velocity in the rotating RTN frame
plus ``ω × ρ``, ω the leader's orbital rate about N). The Earth's flattening would then make
the formation drift: across a few km along the track the J2 potential changes the osculating
semi-major axis by tens of metres while the *mean* one, which sets the drift
``−(3/2) n δa``, is what the ROE mean. The follower's speed is therefore corrected along its
velocity so that its energy, with the J2 potential, is that of the leader plus the configured
``δa`` and ``δi_x``: to first order in J2 the energy of an orbit is its mean Hamiltonian
``E = −μ/(2ā) − R̄``, ``R̄ = μ J2 R² (1/2 − (3/4) sin² ī)/ā³`` the secular J2 potential of a
near-circular orbit (Brouwer 1959), so equal ``E − (dE/dī) δi_x`` means equal mean ``ā``
(tests/simulate/test_formation.py measures the drift that remains).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Self

import numpy as np

from leopod.constants import GM_EARTH_M3_S2, R_EARTH_EQUATOR_M
from leopod.frames.rtn import rtn_matrix
from leopod.settings import Settings, frozen_value
from leopod.simulate.world import _J2

__all__ = ["FormationSettings", "follower_initial_state", "relative_motion_rtn",
           "relative_rtn"]

_ROE_KEYS = ("a_da_m", "a_dlambda_m", "a_dex_m", "a_dey_m", "a_dix_m", "a_diy_m")


@dataclass(frozen=True)
class FormationSettings(Settings):
    """A follower of a leader (``satellites.<sat>.formation``).

    Attributes
    ----------
    leader : str
        Satellite id of the leader (a simulated satellite of the campaign).
    a_da_m, a_dlambda_m, a_dex_m, a_dey_m, a_dix_m, a_diy_m : float
        ROE scaled by the leader's semi-major axis [m] (module docstring).
    manoeuvres : tuple of dict
        Daily burns of the follower: ``time_of_day`` (HH:MM:SS, GPS), ``duration_s`` [s],
        ``dv_rtn_m_s`` (3,) [m/s] (:func:`leopod.simulate.manoeuvres.daily_manoeuvres`).
    truth_correlation : float
        Correlation ρ of the follower's truth stochastic accelerations and drag-scale noise
        with the leader's (:mod:`leopod.simulate.truth_forces`, Formations) [1].
    """

    SCHEMA_DEF = "simulate_formation"

    leader: str
    a_da_m: float
    a_dlambda_m: float
    a_dex_m: float
    a_dey_m: float
    a_dix_m: float
    a_diy_m: float
    manoeuvres: tuple
    truth_correlation: float

    @classmethod
    def from_config(cls, section: Mapping[str, Any]) -> Self:
        """From the validated section; the manoeuvres become plain dicts."""
        base = super().from_config(section)
        burns = tuple({k: frozen_value(v) for k, v in dict(b).items()}
                      for b in base.manoeuvres)
        return cls(**{**{k: getattr(base, k) for k in ("leader", *_ROE_KEYS,
                                                        "truth_correlation")},
                      "manoeuvres": burns})

    def roe(self, a_m: float) -> np.ndarray:
        """Dimensionless ROE (δa, δλ, δe_x, δe_y, δi_x, δi_y), shape (6,)."""
        return np.array([getattr(self, k) for k in _ROE_KEYS]) / a_m


def relative_motion_rtn(roe: np.ndarray, a_m: float, u_rad, du_rad=0.0):
    """Linearised relative position and velocity in the leader's RTN frame (module
    docstring; D'Amico & Montenbruck 2006).

    Parameters
    ----------
    roe : ndarray, shape (6,)
        Dimensionless ROE (δa, δλ, δe_x, δe_y, δi_x, δi_y).
    a_m : float
        Leader's semi-major axis [m].
    u_rad : float or ndarray, shape (n,)
        Leader's argument of latitude [rad].
    du_rad : float or ndarray, shape (n,)
        ``u − u_0`` [rad], the angle travelled since the ROE epoch (the δa drift).

    Returns
    -------
    pos_rtn : ndarray, shape (..., 3)
        Position of the follower relative to the leader in R, T, N [m].
    vel_rtn : ndarray, shape (..., 3)
        Its rate in the rotating RTN frame [m/s] (times the mean motion ``n = sqrt(μ/a³)``).
    """
    da, dl, dex, dey, dix, diy = np.asarray(roe, dtype=float)
    u = np.asarray(u_rad, dtype=float)
    c, s = np.cos(u), np.sin(u)
    n = np.sqrt(GM_EARTH_M3_S2 / a_m**3)
    pos = a_m * np.stack([da - dex * c - dey * s,
                          -1.5 * da * np.asarray(du_rad) + dl + 2 * dex * s - 2 * dey * c,
                          dix * s - diy * c], axis=-1)
    vel = a_m * n * np.stack([dex * s - dey * c,
                              -1.5 * da + 2 * dex * c + 2 * dey * s,
                              dix * c + diy * s], axis=-1)
    return pos, vel


def _argument_of_latitude(pos: np.ndarray, vel: np.ndarray) -> float:
    """Argument of latitude [rad] of a state in a frame whose z axis is the pole."""
    e_n = np.cross(pos, vel)
    e_n /= np.linalg.norm(e_n)
    node = np.cross([0.0, 0.0, 1.0], e_n)
    node /= np.linalg.norm(node)
    r_hat = pos / np.linalg.norm(pos)
    return float(np.arctan2(np.dot(np.cross(node, r_hat), e_n), np.dot(node, r_hat)))


def _energy_j2(pos: np.ndarray, vel: np.ndarray) -> float:
    """Specific energy with the J2 potential [m²/s²] (z axis: the pole):
    ``v²/2 − μ/r + μ J2 R² (3 sin²φ − 1)/(2 r³)``."""
    r = np.linalg.norm(pos)
    sin_phi = pos[2] / r
    return float(0.5 * vel @ vel - GM_EARTH_M3_S2 / r
                 + GM_EARTH_M3_S2 * _J2 * R_EARTH_EQUATOR_M**2 * (3 * sin_phi**2 - 1)
                 / (2 * r**3))


def follower_initial_state(leader_state: np.ndarray, roe: np.ndarray,
                           pole_to_gcrf: np.ndarray) -> np.ndarray:
    """GCRF state of the follower at the leader's epoch (module docstring).

    Parameters
    ----------
    leader_state : ndarray, shape (6,)
        Leader's GCRF position [m] and velocity [m/s].
    roe : ndarray, shape (6,)
        Dimensionless ROE.
    pole_to_gcrf : ndarray, shape (3, 3)
        Rotation from a frame whose z axis is the Earth's pole (the celestial intermediate
        frame, :func:`leopod.simulate.truth_orbit.intermediate_to_gcrf_matrix`) to the GCRF.

    Returns
    -------
    ndarray, shape (6,)
        Follower's GCRF position [m] and velocity [m/s].
    """
    q = np.asarray(pole_to_gcrf, dtype=float)
    pos, vel = q.T @ leader_state[:3], q.T @ leader_state[3:]
    r = np.linalg.norm(pos)
    a = 1.0 / (2.0 / r - vel @ vel / GM_EARTH_M3_S2)
    m = rtn_matrix(pos, vel)
    rho, rho_dot = relative_motion_rtn(roe, a, _argument_of_latitude(pos, vel))
    omega = np.linalg.norm(np.cross(pos, vel)) / r**2
    pos_f = pos + m.T @ rho
    vel_f = vel + m.T @ (rho_dot + np.array([-omega * rho[1], omega * rho[0], 0.0]))
    inc = np.arccos(m[2, 2])
    target = (_energy_j2(pos, vel) + GM_EARTH_M3_S2 * roe[0] / (2 * a)
              + 1.5 * GM_EARTH_M3_S2 * _J2 * R_EARTH_EQUATOR_M**2 / a**3
              * np.sin(inc) * np.cos(inc) * roe[4])
    speed = np.linalg.norm(vel_f)
    vel_f = vel_f * (1.0 + (target - _energy_j2(pos_f, vel_f)) / speed**2)
    return np.concatenate([q @ pos_f, q @ vel_f])


def relative_rtn(leader_pos: np.ndarray, leader_vel: np.ndarray,
                 follower_pos: np.ndarray) -> np.ndarray:
    """Follower minus leader position in the leader's RTN frame [m], shape (n, 3) (inertial
    states)."""
    m = rtn_matrix(leader_pos, leader_vel)
    return np.einsum("nij,nj->ni", m, follower_pos - leader_pos)

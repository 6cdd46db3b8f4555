"""Attitude law of a LEO from its settings: nominal, or yaw steering with yaw-fixed mode and flips.

``satellites.<sat>.attitude`` picks the law (:class:`LeoAttitude`), and every step that needs the
LEO body frame — simulator, observation model, antenna-frame angles of the quality and code-bias
maps, LEO antenna range terms, SLR retro-reflector offset — calls :func:`leo_body_axes` (inertial
or any frame with the inertial velocity) or :func:`leo_body_axes_ef` (Earth-fixed state), so all
use the same attitude.

* ``nominal`` (:mod:`leopod.frames.attitude`): +Z to the geocentre, +X along the inertial
  velocity; the yaw ψ of :mod:`leopod.frames.yaw` is 0.
* ``yaw_steering`` (HY-2D, Jiang et al. 2023, sec. 2): +Z to the geocentre and the solar-array
  axis +Y kept perpendicular to the Sun — the ideal yaw ψₙ = atan2(−tan β, sin μ) of yaw-steering
  GNSS satellites (Bar-Sever 1996; Kouba 2009, GPS Solut., eq. 1), β the Sun elevation above the
  orbit plane, μ the orbit angle from midnight — while |β| ≤ ``beta_max_deg`` (75°). Beyond it the
  satellite is yaw-fixed at ±90° (+X along ±N, the value the ideal law tends to as |β| → 90°).
  The yaw has two solutions 180° apart (Y ⊥ Sun either way); the satellite flips between them,
  about +Z, when β crosses ``flip_beta_deg`` (−1.5°, set by the manufacturer).

  **Which branch is which** — an assumption: the paper gives the threshold and one flip epoch
  (2021-07-14 18:21, β decreasing from 25° to −14°), not the side. With
  ``x_sunward_above_flip: true`` (the default) +X points to the Sun-lit side (ψ = ψₙ, the GNSS
  convention of Montenbruck et al. 2015) while β > β_flip and away from it (ψ = ψₙ + 180°) below.
  Then the law is continuous through β = 0 (ψₙ is, away from noon and midnight), and in both
  yaw-fixed regimes (β > 75° and β < −75°) +X points along the same orbit-normal side +N.
  ``false`` swaps the branches (a flip of the whole law by 180°).

  **Yaw rate**: the law is ideal, with no rate limit. Near noon and midnight ψₙ turns by 180°
  within ``|μ| ≲ |β|`` of orbit angle, at a peak rate μ̇ / tan|β| (2.2 °/s at |β| = 1.5° for a
  957 km orbit, μ̇ = 0.058 °/s; instantaneous at β = 0). The model turns the axes as fast as the
  law says; the phase wind-up of the simulator and of the estimator follows the same axes, and
  any real satellite's smoother turn within those minutes is not modelled.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from leopod.astro.sun import sun_position_ef
from leopod.frames.attitude import inertial_velocity_ef, nominal_axes_inertial
from leopod.frames.yaw import nominal_yaw_rad, orbit_angles, yaw_body_axes
from leopod.settings import Settings

__all__ = ["LAWS", "LeoAttitude", "YawSteering", "beta_angle_ef", "leo_body_axes",
           "leo_body_axes_ef", "leo_yaw_rad", "yaw_flip_epochs"]

#: Attitude laws of ``satellites.<sat>.attitude``.
LAWS = ("nominal", "yaw_steering")


@dataclass(frozen=True)
class YawSteering(Settings):
    """Yaw-steering thresholds (``satellites.<sat>.yaw_steering``; Jiang et al. 2023).

    Attributes
    ----------
    beta_max_deg : float
        Yaw steering while |β| ≤ this, yaw-fixed (±90°) beyond [deg].
    flip_beta_deg : float
        β at which the satellite flips by 180° about +Z [deg].
    x_sunward_above_flip : bool
        +X to the Sun-lit side while β > ``flip_beta_deg`` (away from it below); false swaps.
    """

    SCHEMA_DEF = "yaw_steering"

    beta_max_deg: float
    flip_beta_deg: float
    x_sunward_above_flip: bool


@dataclass(frozen=True)
class LeoAttitude(Settings):
    """The LEO attitude law of a satellite (``satellites.<sat>``: ``attitude``, ``yaw_steering``).

    Attributes
    ----------
    attitude : str
        One of :data:`LAWS`.
    yaw_steering : YawSteering
        Thresholds of the ``yaw_steering`` law (a mapping of the section is converted).
    """

    SCHEMA_DEF = "satellite"

    attitude: str
    yaw_steering: YawSteering

    def __post_init__(self):
        if self.attitude not in LAWS:
            raise ValueError(f"satellites.<sat>.attitude: unknown law '{self.attitude}' "
                             f"(known: {', '.join(LAWS)})")
        if isinstance(self.yaw_steering, Mapping):
            object.__setattr__(self, "yaw_steering", YawSteering.from_config(self.yaw_steering))

    @classmethod
    def of(cls, satellite: Mapping[str, Any] | LeoAttitude | None) -> LeoAttitude:
        """The law of a satellite section (or a law, returned as is); None: schema defaults."""
        if isinstance(satellite, LeoAttitude):
            return satellite
        return cls.from_config(dict(satellite or {}))


def leo_yaw_rad(beta_rad, mu_rad, settings: YawSteering) -> np.ndarray:
    """Yaw ψ [rad] of the yaw-steering law (module docstring), in (−π, π].

    Parameters
    ----------
    beta_rad, mu_rad : array_like, shape (...)
        Sun elevation above the orbit plane and orbit angle from midnight
        (:func:`leopod.frames.yaw.orbit_angles`) [rad].
    settings : YawSteering
    """
    beta = np.asarray(beta_rad, dtype=float)
    psi = np.where(np.abs(beta) > np.radians(settings.beta_max_deg),
                   -np.sign(beta) * np.pi / 2, nominal_yaw_rad(beta, mu_rad))
    below = beta < np.radians(settings.flip_beta_deg)
    away = below if settings.x_sunward_above_flip else ~below
    return np.where(away, np.where(psi > 0, psi - np.pi, psi + np.pi), psi)


def leo_body_axes(attitude: LeoAttitude | None, pos_m: np.ndarray, vel_m_s: np.ndarray,
                  sun_m: np.ndarray | None) -> np.ndarray:
    """Body axes (rows X, Y, Z) of the LEO under its law, in the frame of the inputs.

    Parameters
    ----------
    attitude : LeoAttitude or None
        The satellite's law; None: ``nominal``.
    pos_m, vel_m_s : ndarray, shape (n, 3)
        Position [m] and inertial velocity [m/s] (GCRF, or Earth-fixed axes with ω × r added).
    sun_m : ndarray, shape (n, 3) or None
        Sun position in the same frame [m] (unused by ``nominal``).

    Returns
    -------
    ndarray, shape (n, 3, 3)
        Rows X, Y, Z of the body frame: the rotation from the input frame to the body frame.
    """
    pos = np.asarray(pos_m, dtype=float)
    vel = np.asarray(vel_m_s, dtype=float)
    if attitude is None or attitude.attitude == "nominal":
        return nominal_axes_inertial(pos, vel)
    beta, mu, _ = orbit_angles(pos, vel, np.asarray(sun_m, dtype=float))
    return yaw_body_axes(pos, vel, leo_yaw_rad(beta, mu, attitude.yaw_steering))


def leo_body_axes_ef(attitude: LeoAttitude | None, times, pos_m: np.ndarray,
                     vel_ef_m_s: np.ndarray) -> np.ndarray:
    """:func:`leo_body_axes` from an Earth-fixed state (Sun of :mod:`leopod.astro.sun`).

    Parameters
    ----------
    attitude : LeoAttitude or None
    times : array_like of datetime64, shape (n,)
        Epochs (GPS time) of the states.
    pos_m, vel_ef_m_s : ndarray, shape (n, 3)
        Earth-fixed position [m] and Earth-fixed velocity [m/s].

    Returns
    -------
    ndarray, shape (n, 3, 3)
        Earth-fixed -> body rotation (rows X, Y, Z), as :func:`leopod.frames.attitude.
        nominal_body_axes`.
    """
    vel_in = inertial_velocity_ef(pos_m, vel_ef_m_s)
    nominal = attitude is None or attitude.attitude == "nominal"
    sun = None if nominal else sun_position_ef(times)
    return leo_body_axes(attitude, pos_m, vel_in, sun)


def beta_angle_ef(times, pos_m: np.ndarray, vel_ef_m_s: np.ndarray) -> np.ndarray:
    """Sun elevation β above the orbit plane [rad], shape (n,), from Earth-fixed states."""
    return orbit_angles(np.asarray(pos_m, float), inertial_velocity_ef(pos_m, vel_ef_m_s),
                        sun_position_ef(times))[0]


def yaw_flip_epochs(times, beta_rad: np.ndarray, settings: YawSteering) -> np.ndarray:
    """Epochs at which β crosses the flip threshold: the 180° yaw flips of the law.

    Parameters
    ----------
    times : array_like of datetime64, shape (n,)
        Increasing epochs.
    beta_rad : ndarray, shape (n,)
        β at the epochs (e.g. :func:`beta_angle_ef`) [rad].
    settings : YawSteering

    Returns
    -------
    ndarray of datetime64[ns], shape (k,)
        Crossings, linearly interpolated between the bracketing epochs (β changes by < 0.01°
        in a minute), for the ``yaw_flips`` of the code-bias maps per attitude mode.
    """
    t = np.asarray(times, dtype="datetime64[ns]")
    d = np.asarray(beta_rad, dtype=float) - np.radians(settings.flip_beta_deg)
    i = np.flatnonzero((d[:-1] < 0) != (d[1:] < 0))
    frac = d[i] / (d[i] - d[i + 1])
    step = (t[i + 1] - t[i]).astype("int64")
    return t[i] + (frac * step).round().astype("int64").astype("timedelta64[ns]")

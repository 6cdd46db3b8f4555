"""Attitude law of a LEO from its settings: nominal, yaw steering, or quaternions from a file.

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
* ``file``: measured or planned quaternions (inertial -> body, :mod:`leopod.frames.quaternion`)
  read from attitude files (``satellites.<sat>.attitude_file``: GRACE SCA1B or leopod's CSV /
  netCDF layout, :mod:`leopod.io.attitude`), interpolated by slerp to any epoch. An epoch
  outside the records or in a gap longer than ``max_gap_s`` is an error, unless
  ``outside: nominal`` asks for the modelled ``nominal`` law (with the offset below) there.
  The step's script loads the files (:func:`leopod.io.attitude.load_leo_attitude`), which
  attaches the series to the law (:meth:`LeoAttitude.with_series`).

**Modelled offsets** (``satellites.<sat>.attitude_offset``): a constant rotation of the body
frame relative to a modelled law, the aerospace yaw–pitch–roll sequence about the law's own
axes: first yaw ψ about +Z (nadir; +X turns towards +Y), then pitch θ about the new +Y (+X turns
up, away from the Earth), then roll φ about the new +X. With ``L`` the law's axes (rows), the
body axes are ``B = R₁(φ) R₂(θ) R₃(ψ) L`` (``Rₖ`` the frame rotations about axis k). Flying
backwards (+X against the velocity) is ψ = 180°. GRACE points the K-band horns of the two
satellites at each other (Case et al. 2010; Tapley et al. 2004), so +X of both is pitched down
by half the angle the ~220 km separation subtends at the geocentre, about −0.9°: the SCA1B
quaternions of 2003-09-14 give θ = −0.88° for GRACE-A (the leading satellite, flying backwards:
ψ = 180°) and −0.7° for GRACE-B (``tests/io/test_attitude_files.py``). The offset applies to
``nominal`` and ``yaw_steering`` (and to the nominal fall-back of ``file``), not to the
quaternions of a file, which are the attitude itself.
"""

from __future__ import annotations

import copy
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from leopod.astro.sun import sun_position_ef
from leopod.frames.attitude import inertial_velocity_ef, nominal_axes_inertial
from leopod.frames.earth_rotation import gcrf_from_itrf_matrices
from leopod.frames.quaternion import QuaternionSeries
from leopod.frames.yaw import nominal_yaw_rad, orbit_angles, yaw_body_axes
from leopod.settings import Settings

__all__ = ["LAWS", "AttitudeFile", "AttitudeOffset", "LeoAttitude", "YawSteering",
           "below_flip", "beta_angle_ef", "leo_body_axes", "leo_body_axes_ef", "leo_yaw_rad",
           "offset_rotation", "yaw_flip_epochs"]

#: Attitude laws of ``satellites.<sat>.attitude``.
LAWS = ("nominal", "yaw_steering", "file")
#: Formats of ``satellites.<sat>.attitude_file.format`` (:mod:`leopod.io.attitude`).
FILE_FORMATS = ("auto", "sca1b", "csv", "netcdf")


def _check_choice(key: str, value: str, known) -> None:
    """A ValueError naming ``satellites.<sat>.<key>`` unless ``value`` is one of ``known``."""
    if value not in known:
        raise ValueError(f"satellites.<sat>.{key}: unknown '{value}' (known: "
                         f"{', '.join(known)})")


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
class AttitudeOffset(Settings):
    """Constant rotation of the body frame from a modelled law (``satellites.<sat>.
    attitude_offset``; module docstring: yaw, then pitch, then roll).

    Attributes
    ----------
    yaw_deg : float
        Rotation about +Z (nadir), +X towards +Y [deg]; 180 = flying backwards.
    pitch_deg : float
        Rotation about the yawed +Y, +X up (away from the Earth) [deg].
    roll_deg : float
        Rotation about the yawed and pitched +X, +Y down [deg].
    """

    SCHEMA_DEF = "attitude_offset"

    yaw_deg: float
    pitch_deg: float
    roll_deg: float

    @property
    def is_zero(self) -> bool:
        return self.yaw_deg == 0.0 and self.pitch_deg == 0.0 and self.roll_deg == 0.0


@dataclass(frozen=True)
class AttitudeFile(Settings):
    """Attitude files of the ``file`` law (``satellites.<sat>.attitude_file``).

    Attributes
    ----------
    path : str or None
        Path template of the daily attitude file (placeholders of the campaign's templates).
    format : str
        One of :data:`FILE_FORMATS` (``auto``: from the file's first line).
    max_gap_s : float
        Records farther apart are a gap that is not interpolated [s]; epochs up to half of
        it beyond the first or last record are extrapolated.
    outside : str
        ``error``: an epoch outside the records or in a gap stops the step; ``nominal``: the
        ``nominal`` law (with ``attitude_offset``) there.
    """

    SCHEMA_DEF = "attitude_file"

    path: str | None
    format: str
    max_gap_s: float
    outside: str

    def __post_init__(self):
        _check_choice("attitude_file.format", self.format, FILE_FORMATS)
        _check_choice("attitude_file.outside", self.outside, ("error", "nominal"))


@dataclass(frozen=True)
class LeoAttitude(Settings):
    """The LEO attitude law of a satellite (``satellites.<sat>``: ``attitude``,
    ``yaw_steering``, ``attitude_offset``, ``attitude_file``).

    Attributes
    ----------
    attitude : str
        One of :data:`LAWS`.
    yaw_steering : YawSteering
        Thresholds of the ``yaw_steering`` law (a mapping of the section is converted).
    attitude_offset : AttitudeOffset
        Constant rotation from the modelled law (a mapping is converted).
    attitude_file : AttitudeFile
        Files of the ``file`` law (a mapping is converted). The quaternions themselves are
        attached by :meth:`with_series` (:func:`leopod.io.attitude.load_leo_attitude`).
    """

    SCHEMA_DEF = "satellite"

    attitude: str
    yaw_steering: YawSteering
    attitude_offset: AttitudeOffset
    attitude_file: AttitudeFile

    def __post_init__(self):
        _check_choice("attitude", self.attitude, LAWS)
        for name, cls in (("yaw_steering", YawSteering), ("attitude_offset", AttitudeOffset),
                          ("attitude_file", AttitudeFile)):
            if isinstance(getattr(self, name), Mapping):
                object.__setattr__(self, name, cls.from_config(getattr(self, name)))
        has_path = self.attitude_file.path is not None
        if (self.attitude == "file") != has_path:
            raise ValueError("satellites.<sat>: attitude 'file' needs attitude_file.path, and "
                             "attitude_file.path is only read with attitude 'file' (attitude "
                             f"is '{self.attitude}', path {self.attitude_file.path!r})")

    @property
    def series(self) -> QuaternionSeries | None:
        """The quaternions of the ``file`` law (None until :meth:`with_series`)."""
        return getattr(self, "_series", None)

    def with_series(self, series: QuaternionSeries) -> LeoAttitude:
        """A copy of the ``file`` law with its quaternions attached."""
        if self.attitude != "file":
            raise ValueError(f"attitude law '{self.attitude}' takes no attitude file")
        out = copy.copy(self)
        object.__setattr__(out, "_series", series)
        return out

    @property
    def needs_epochs(self) -> bool:
        """True if the law needs the epochs (and the frame's rotation to GCRF)."""
        return self.attitude == "file"

    def describe(self) -> str:
        """One line for logs and file attributes."""
        if self.attitude == "file":
            src = self.series.source if self.series is not None else self.attitude_file.path
            text = f"file ({src}; gaps > {self.attitude_file.max_gap_s:g} s: " \
                f"{self.attitude_file.outside})"
        else:
            text = self.attitude
        o = self.attitude_offset
        if not o.is_zero:
            text += f", offset yaw {o.yaw_deg:g} pitch {o.pitch_deg:g} roll {o.roll_deg:g} deg"
        return text

    @classmethod
    def of(cls, satellite: Mapping[str, Any] | LeoAttitude | None) -> LeoAttitude:
        """The law of a satellite section (or a law, returned as is); None: schema defaults."""
        if isinstance(satellite, LeoAttitude):
            return satellite
        return cls.from_config(dict(satellite or {}))


def below_flip(beta_rad, settings: YawSteering) -> np.ndarray:
    """True where β is below the flip threshold: the branch of the law after a downward
    crossing (module docstring), the attitude mode a simulated ``yaw_branch`` map follows.

    Parameters
    ----------
    beta_rad : array_like, shape (...)
        Sun elevation above the orbit plane (:func:`leopod.frames.yaw.orbit_angles`) [rad].
    settings : YawSteering
    """
    return np.asarray(beta_rad, dtype=float) < np.radians(settings.flip_beta_deg)


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
    below = below_flip(beta, settings)
    away = below if settings.x_sunward_above_flip else ~below
    return np.where(away, np.where(psi > 0, psi - np.pi, psi + np.pi), psi)


def offset_rotation(offset: AttitudeOffset) -> np.ndarray:
    """``R₁(φ) R₂(θ) R₃(ψ)``, shape (3, 3): body axes from a law's axes (module docstring)."""
    psi, theta, phi = np.radians([offset.yaw_deg, offset.pitch_deg, offset.roll_deg])
    c, s = np.cos(psi), np.sin(psi)
    r3 = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])
    c, s = np.cos(theta), np.sin(theta)
    r2 = np.array([[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]])
    c, s = np.cos(phi), np.sin(phi)
    r1 = np.array([[1.0, 0.0, 0.0], [0.0, c, s], [0.0, -s, c]])
    return r1 @ r2 @ r3


def _modelled_axes(attitude: LeoAttitude | None, pos: np.ndarray, vel: np.ndarray,
                   sun_m, law: str) -> np.ndarray:
    """Axes of a modelled law (``nominal`` or ``yaw_steering``) with the satellite's offset."""
    if law == "nominal":
        axes = nominal_axes_inertial(pos, vel)
    else:
        if sun_m is None:
            raise ValueError("the yaw_steering attitude law needs the Sun position")
        beta, mu, _ = orbit_angles(pos, vel, np.asarray(sun_m, dtype=float))
        axes = yaw_body_axes(pos, vel, leo_yaw_rad(beta, mu, attitude.yaw_steering))
    if attitude is not None and not attitude.attitude_offset.is_zero:
        axes = np.einsum("ij,njk->nik", offset_rotation(attitude.attitude_offset), axes)
    return axes


def leo_body_axes(attitude: LeoAttitude | None, pos_m: np.ndarray, vel_m_s: np.ndarray,
                  sun_m: np.ndarray | None, *, times=None,
                  gcrf_from_frame: np.ndarray | None = None) -> np.ndarray:
    """Body axes (rows X, Y, Z) of the LEO under its law, in the frame of the inputs.

    Parameters
    ----------
    attitude : LeoAttitude or None
        The satellite's law; None: ``nominal``.
    pos_m, vel_m_s : ndarray, shape (n, 3)
        Position [m] and inertial velocity [m/s] (GCRF, or Earth-fixed axes with ω × r added).
    sun_m : ndarray, shape (n, 3) or None
        Sun position in the same frame [m] (used by ``yaw_steering`` only).
    times : array_like of datetime64, shape (n,), optional
        Epochs (GPS time) of the states; needed by the ``file`` law.
    gcrf_from_frame : ndarray, shape (n, 3, 3), optional
        Rotation from the frame of the inputs to the GCRF (``v_gcrf = M v``), for the ``file``
        law with inputs in another frame (e.g. the ITRF); None: the inputs are GCRF.

    Returns
    -------
    ndarray, shape (n, 3, 3)
        Rows X, Y, Z of the body frame: the rotation from the input frame to the body frame.

    Raises
    ------
    ValueError
        For the ``file`` law without epochs or without its quaternions
        (:meth:`LeoAttitude.with_series`).
    leopod.frames.quaternion.AttitudeCoverageError
        For epochs the file does not cover (with ``attitude_file.outside: error``).
    """
    pos = np.asarray(pos_m, dtype=float)
    vel = np.asarray(vel_m_s, dtype=float)
    law = "nominal" if attitude is None else attitude.attitude
    if law != "file":
        return _modelled_axes(attitude, pos, vel, sun_m, law)
    if times is None:
        raise ValueError("the attitude 'file' law needs the epochs of the states (times=)")
    if attitude.series is None:
        raise ValueError(f"attitude file {attitude.attitude_file.path} not loaded: the step "
                         "must attach it (leopod.io.attitude.load_leo_attitude)")
    fallback = attitude.attitude_file.outside == "nominal"
    axes = attitude.series.body_axes(times, allow_uncovered=fallback)    # GCRF -> body
    if gcrf_from_frame is not None:
        axes = np.einsum("nij,njk->nik", axes, np.asarray(gcrf_from_frame, dtype=float))
    bad = ~np.isfinite(axes).all(axis=(1, 2))
    if bad.any():
        axes[bad] = _modelled_axes(attitude, pos[bad], vel[bad], None, "nominal")
    return axes


def leo_body_axes_ef(attitude: LeoAttitude | None, times, pos_m: np.ndarray,
                     vel_ef_m_s: np.ndarray, *, sun_m: np.ndarray | None = None,
                     eop=None) -> np.ndarray:
    """:func:`leo_body_axes` from an Earth-fixed state (Sun of :mod:`leopod.astro.sun`).

    Parameters
    ----------
    attitude : LeoAttitude or None
    times : array_like of datetime64, shape (n,)
        Epochs (GPS time) of the states.
    pos_m, vel_ef_m_s : ndarray, shape (n, 3)
        Earth-fixed position [m] and Earth-fixed velocity [m/s].
    sun_m : ndarray, shape (n, 3), optional
        Earth-fixed Sun position [m] if the caller has it (else computed for yaw steering).
    eop : leopod.time.eop.EarthOrientation, optional
        EOP of the ITRF -> GCRF rotation of the ``file`` law (default: installed IERS data).

    Returns
    -------
    ndarray, shape (n, 3, 3)
        Earth-fixed -> body rotation (rows X, Y, Z), as :func:`leopod.frames.attitude.
        nominal_body_axes`.
    """
    vel_in = inertial_velocity_ef(pos_m, vel_ef_m_s)
    law = "nominal" if attitude is None else attitude.attitude
    if law == "yaw_steering" and sun_m is None:
        sun_m = sun_position_ef(times)
    rot = None
    if law == "file":
        rot, _ = gcrf_from_itrf_matrices(np.asarray(times, dtype="datetime64[ns]"), eop)
    return leo_body_axes(attitude, pos_m, vel_in, sun_m, times=times, gcrf_from_frame=rot)


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

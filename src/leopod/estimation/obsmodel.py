"""Observation model of undifferenced ionosphere-free code and phase of a LEO receiver.

For each (epoch, GNSS satellite) pair the model computes, in the GCRF:

* the true reception time ``t = t_nominal − dt_rx`` (receiver clock from the previous
  iteration; the LEO moves 7.5 mm per ns of clock error);
* the LEO antenna phase centre: centre of mass plus the body-frame ionosphere-free PCO
  rotated with the satellite's attitude law (:mod:`leopod.frames.leo_attitude`: nominal, +Z
  to the geocentre and +X along the inertial velocity, or yaw steering), as the simulator;
  with an ANTEX antenna (:mod:`leopod.gnss.leo_antenna`) the ionosphere-free PCV of the LEO
  at the antenna-frame angles is added to code and phase (ANTEX 1.4, sec. 3);
* the transmission time by light-time iteration; the GNSS position of the product (ITRF,
  centre of mass, :class:`leopod.gnss.products.GnssProducts`) at the transmission time is
  taken into the GCRF of the reception time with ``R(t) R3(ω τ)`` (the Earth rotation during
  the travel time τ: the Sagnac effect), plus the satellite's ionosphere-free PCO (yaw-steering
  attitude, or the published eclipse/turn laws of each block when ``products.attitude`` holds
  the families, :mod:`leopod.gnss.attitude`) and nadir-dependent PCV from ANTEX;
* the satellite clock at the transmission time (linear between product samples) with the
  periodic relativistic correction, and the Shapiro delay
  (:mod:`leopod.gnss.corrections`);
* for phase, the wind-up (ionosphere-free: ``λ_NL φ`` with ``λ_NL = c/(f1+f2)``,
  Kouba 2009 sec. 5.3), with receiver dipole axes ``x = body X``, ``y = −body Y`` (so that
  ``x × y`` is the boresight −Z).

The receiver clock is not modelled here (it is pre-eliminated in the estimator).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from leopod.constants import C_LIGHT_M_S, OMEGA_EARTH_RAD_S
from leopod.frames.attitude import antenna_el_az, nominal_axes_inertial
from leopod.frames.leo_attitude import LeoAttitude, leo_body_axes
from leopod.gnss.attitude import gnss_attitude_axes
from leopod.gnss.corrections import (
    relativistic_clock_s,
    shapiro_delay_m,
    unwrap_windup,
    windup_cycles,
)
from leopod.gnss.products import GnssProducts
from leopod.time.calendar import from_seconds

__all__ = ["ModelResult", "Pairs", "ReceiverAntenna", "compute_model", "nominal_axes_inertial"]

_LIGHT_TIME_ITERATIONS = 3


@dataclass
class Pairs:
    """Observed (epoch, satellite) pairs, flattened.

    Attributes
    ----------
    epoch : ndarray of int, shape (n,)
        Index into the epoch axis.
    isv : ndarray of int, shape (n,)
        Index into the product satellite axis (:meth:`GnssProducts.sv_index`).
    sat : ndarray of int, shape (n,)
        Index into the satellite axis of the observation file (for PCO tables).
    """

    epoch: np.ndarray
    isv: np.ndarray
    sat: np.ndarray


@dataclass
class ModelResult:
    """Modelled quantities per pair.

    Attributes
    ----------
    code_m, phase_m : ndarray, shape (n,)
        Modelled ionosphere-free code and phase without receiver clock and ambiguity [m].
    los_gcrf : ndarray, shape (n, 3)
        Unit vector receiver -> transmitter (GCRF).
    el_deg, az_deg : ndarray, shape (n,)
        Antenna-frame elevation and azimuth from north towards east [deg]
        (:func:`leopod.frames.attitude.antenna_el_az`; default frame: elevation above the
        body X-Y plane towards -Z, azimuth from +X to +Y).
    z_body_gcrf : ndarray, shape (n, 3)
        Body +Z axis at the epoch (GCRF), for the PCO-Z partial.
    valid : ndarray of bool, shape (n,)
        False where the products give no orbit or clock.
    """

    code_m: np.ndarray
    phase_m: np.ndarray
    los_gcrf: np.ndarray
    el_deg: np.ndarray
    az_deg: np.ndarray
    z_body_gcrf: np.ndarray
    valid: np.ndarray


@dataclass(frozen=True)
class ReceiverAntenna:
    """What the ionosphere-free model needs of a LEO ANTEX antenna
    (:func:`leopod.estimation.inputs.receiver_antenna`).

    Attributes
    ----------
    frame : ndarray, shape (3, 3) or None
        Rows north, east, up of the antenna frame in the body frame
        (:func:`leopod.frames.attitude.antenna_frame`); None: north +X, up -Z.
    pcv_if_m : callable or None
        ``f(sat_index (n,), el_deg (n,), az_deg (n,)) -> (n,)`` [m]: ionosphere-free PCV of
        the signal pair of each observation-file satellite's system at the antenna-frame
        angles; None: no PCV.
    """

    frame: np.ndarray | None
    pcv_if_m: object


def _rot3(angle_rad: np.ndarray, vec: np.ndarray) -> np.ndarray:
    """Coordinates of ``vec`` in axes rotated by ``angle`` about Z (R3(angle) @ vec)."""
    c, s = np.cos(angle_rad), np.sin(angle_rad)
    return np.stack([c * vec[:, 0] + s * vec[:, 1], -s * vec[:, 0] + c * vec[:, 1],
                     vec[:, 2]], axis=-1)


def compute_model(pairs: Pairs, t_rx_s: np.ndarray, pos_leo_gcrf_m: np.ndarray,
                  vel_leo_gcrf_m_s: np.ndarray, rot_gcrf_itrf: np.ndarray,
                  products: GnssProducts, sun_itrf_m: np.ndarray, *,
                  leo_pco_body_m: np.ndarray | None = None,
                  sat_pco_body_m: np.ndarray | None = None,
                  sat_pcv_m=None, nl_wavelength_m: float | np.ndarray = 0.0,
                  leo_attitude: LeoAttitude | None = None,
                  leo_antenna: ReceiverAntenna | None = None) -> ModelResult:
    """Model ionosphere-free code and phase (module docstring).

    Parameters
    ----------
    pairs : Pairs
    t_rx_s : ndarray, shape (m,)
        True reception times of the epochs [s since ``products.ref``, GPS time].
    pos_leo_gcrf_m, vel_leo_gcrf_m_s : ndarray, shape (m, 3)
        LEO centre of mass at the true reception times (GCRF) [m, m/s].
    rot_gcrf_itrf : ndarray, shape (m, 3, 3)
        ITRF -> GCRF rotation at the epochs.
    products : GnssProducts
    sun_itrf_m : ndarray, shape (m, 3)
        Earth-fixed Sun position at the epochs [m] (GNSS yaw attitude).
    leo_pco_body_m : ndarray, shape (3,) or (s_obs, 3), optional
        Ionosphere-free LEO antenna PCO in the body frame [m]; one per observation-file
        satellite (``pairs.sat``) when systems with different signal pairs are combined.
    sat_pco_body_m : ndarray, shape (s_obs, 3), optional
        Ionosphere-free transmitter PCO per observation-file satellite (``pairs.sat``) [m].
    sat_pcv_m : callable, optional
        ``sat_pcv_m(sat_index, nadir_deg) -> m``: ionosphere-free transmitter PCV.
    nl_wavelength_m : float or ndarray, shape (s_obs,)
        Narrow-lane wavelength ``c/(f1+f2)`` scaling the wind-up [m] (0: no wind-up), or one
        per observation-file satellite (the signal pair of its system).
    leo_attitude : LeoAttitude, optional
        Attitude law of the LEO (:func:`leopod.frames.leo_attitude.leo_body_axes`, the Sun
        rotated to the GCRF); None: nominal.
    leo_antenna : ReceiverAntenna, optional
        Antenna frame of the LEO (the angles) and its ionosphere-free PCV per observation-file
        satellite, added to code and phase; None: north +X, up -Z, no PCV.

    Returns
    -------
    ModelResult
    """
    ep, isv = pairs.epoch, pairs.isv
    sun_gcrf = np.einsum("mij,mj->mi", rot_gcrf_itrf, sun_itrf_m)
    times = None
    if leo_attitude is not None and leo_attitude.needs_epochs:    # attitude from a file
        times = from_seconds(t_rx_s, products.ref)
    axes = leo_body_axes(leo_attitude, pos_leo_gcrf_m, vel_leo_gcrf_m_s, sun_gcrf,
                         times=times)                                     # (m, 3, 3)
    rx = pos_leo_gcrf_m[ep]
    if leo_pco_body_m is not None:
        pco = np.asarray(leo_pco_body_m, dtype=float)
        rx = rx + (np.einsum("nij,i->nj", axes[ep], pco) if pco.ndim == 1
                   else np.einsum("nij,ni->nj", axes[ep], pco[pairs.sat]))
    rot = rot_gcrf_itrf[ep]
    t_rx = t_rx_s[ep]
    rx_itrf = np.einsum("nji,nj->ni", rot, rx)                               # R^T rx
    tau = np.full(ep.size, 0.075)
    for _ in range(_LIGHT_TIME_ITERATIONS):
        sv_itrf, sv_vel_itrf, _ = products.position(isv, t_rx - tau)
        sv_now = _rot3(OMEGA_EARTH_RAD_S * tau, sv_itrf)
        tau = np.linalg.norm(sv_now - rx_itrf, axis=-1) / C_LIGHT_M_S
    valid = np.isfinite(sv_itrf).all(axis=-1)
    # placeholders for pairs without products (flagged invalid), keeping the arithmetic finite
    sv_itrf = np.where(valid[:, None], sv_itrf, 3.0 * rx_itrf)
    sv_vel_itrf = np.where(valid[:, None], sv_vel_itrf, 0.0)
    families = getattr(products, "attitude", None)
    if families is not None:
        families = np.asarray(families, dtype=object)[isv]
        # inertial velocity in Earth-fixed axes (orbit normal of the yaw laws)
        sv_vel_in = sv_vel_itrf + np.cross([0.0, 0.0, OMEGA_EARTH_RAD_S], sv_itrf)
    else:
        sv_vel_in = sv_vel_itrf
    sv_axes_itrf = gnss_attitude_axes(sv_itrf, sv_vel_in, sun_itrf_m[ep], families)
    if sat_pco_body_m is not None:
        sv_itrf = sv_itrf + np.einsum("nij,ni->nj", sv_axes_itrf, sat_pco_body_m[pairs.sat])
        sv_now = _rot3(OMEGA_EARTH_RAD_S * tau, sv_itrf)
    vec_itrf = sv_now - rx_itrf
    rho = np.linalg.norm(vec_itrf, axis=-1)
    los_itrf = vec_itrf / np.where(rho > 0, rho, 1.0)[:, None]
    los = np.einsum("nij,nj->ni", rot, los_itrf)
    clk = products.clock(isv, t_rx - tau)
    valid &= np.isfinite(clk)
    clk = np.where(valid, clk, 0.0)
    clk = clk + relativistic_clock_s(sv_itrf, sv_vel_itrf)
    geometric = rho + shapiro_delay_m(sv_now, rx_itrf) - C_LIGHT_M_S * clk
    if sat_pcv_m is not None:
        nadir = np.degrees(np.arccos(np.clip(
            -np.sum(los_itrf * sv_axes_itrf[:, 2], axis=-1), -1.0, 1.0)))
        geometric = geometric + np.where(valid, sat_pcv_m(pairs.sat, nadir), 0.0)
    body = np.einsum("nij,nj->ni", axes[ep], los)
    frame = None if leo_antenna is None else leo_antenna.frame
    el, az = antenna_el_az(body, frame)
    if leo_antenna is not None and leo_antenna.pcv_if_m is not None:
        # observed range = range to the mean phase centre + PCV (ANTEX 1.4, sec. 3)
        pcv = leo_antenna.pcv_if_m(pairs.sat, el, az)
        geometric = geometric + np.where(valid, pcv, 0.0)
    phase = geometric.copy()
    nl = np.asarray(nl_wavelength_m, dtype=float)
    if np.any(nl):
        sv_axes = np.einsum("nij,nkj->nki", rot, sv_axes_itrf)               # GCRF rows
        wind = windup_cycles(-los, axes[ep, 0], -axes[ep, 1], sv_axes[:, 0], sv_axes[:, 1])
        wind[valid] = unwrap_windup(wind[valid], isv[valid], ep[valid])
        phase += (nl if nl.ndim == 0 else nl[pairs.sat]) * wind
    return ModelResult(code_m=geometric, phase_m=phase, los_gcrf=los, el_deg=el, az_deg=az,
                       z_body_gcrf=axes[ep, 2], valid=valid)

"""Computed satellite laser ranging (SLR) observable: light time, troposphere, relativity.

A normal point is a two-way time of flight: a pulse leaves the station at the transmit epoch
``t_t`` (the CRD epoch, epoch event 2), is reflected by the retro-reflector at the bounce epoch
``t_b = t_t + τ_up`` and comes back at ``t_r = t_b + τ_down``. The computed value is

``c (t_r − t_t) = ρ_up + ρ_down + Δ_trop,up + Δ_trop,down + Δ_rel,up + Δ_rel,down``

with ρ the straight-line (vacuum) lengths of the two legs in an inertial frame, Δ_trop the
Mendes–Pavlis tropospheric delay with the FCULa mapping function (IERS Conventions 2010,
sec. 9.2.1; Mendes & Pavlis 2004; Mendes et al. 2002) and Δ_rel the Shapiro delay of the
Earth's field (IERS Conventions 2010, eq. 11.17, γ = 1). The "one-way range" of SLR residuals
is ``c (t_r − t_t) / 2`` (:attr:`SlrRange.range_m`).
The tropospheric delay is computed by :mod:`leopod.validation.slr_troposphere`.

Frames. Station and reflector positions are ITRF (Earth-fixed) Cartesian coordinates [m]. The
light time is solved in the inertial frame that coincides with the ITRF axes at the transmit
epoch (uplink) or the bounce epoch (downlink): a point with ITRF coordinates ``x`` at epoch
``t`` has, in the ITRF axes frozen at ``t'``, the coordinates ``R3(−ω (t − t'))·x`` (an
eastward rotation by ``ω (t − t')``; ``ω`` = nominal Earth rotation rate, IERS Conventions
2010, Table 1.1). Over the < 30 ms of a LEO pass this reproduces the full ITRF→GCRF
transformation to better than 1 µm: the rotation-rate (LOD) variations (~1e-8 relative),
the offset of the rotation axis from the ITRF Z axis (polar motion, < 3e-6 rad) and
precession–nutation over 30 ms change the ~3 m Earth-rotation (Sagnac) displacement of the
station by < 1e-5 m. Time ``t`` is any uniform time scale in seconds (GPS time in leopod);
the time of flight of the station clock is taken equal to coordinate time (ITRF and orbits are
TT-compatible, so no scale factor enters).

Not modelled here (the caller adds them to the station position or the reflector callable):
station displacements (solid Earth, ocean loading and pole tides), eccentricities, the
retro-reflector array's range correction (signature). The light time is that of the vacuum
path: the tropospheric delay would shift the bounce epoch by Δ/c and the range by ρ̇ Δ/c,
< 0.3 mm at 10° elevation (Δ ≈ 13 m, ρ̇ ≈ 6.5 km/s).

References
----------
1. Petit, G. & Luzum, B. (eds.) (2010). IERS Conventions (2010), IERS Technical Note 36.
2. Montenbruck, O. & Gill, E. (2000). Satellite Orbits, ch. 6 (light-time iteration).

The troposphere's references (Mendes & Pavlis 2004; Mendes et al. 2002; Giacomo 1982) are
given in :mod:`leopod.validation.slr_troposphere`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import erfa
import numpy as np
import xarray as xr

from leopod.constants import (
    C_LIGHT_M_S,
    OMEGA_EARTH_RAD_S,
    WGS84_A_M,
    WGS84_INV_F,
)
from leopod.frames.attitude import body_to_ef
from leopod.frames.leo_attitude import LeoAttitude, leo_body_axes_ef
from leopod.gnss.corrections import shapiro_delay_distances_m as shapiro_delay_m
from leopod.numerics.interpolate import interpolate_table
from leopod.validation.slr_troposphere import mendes_pavlis_delay_m

__all__ = [
    "LightTime",
    "OrbitReflector",
    "SlrRange",
    "elevation_rad",
    "geodetic_lat_height",
    "shapiro_delay_m",
    "slr_range",
    "two_way_light_time",
]

# ----------------------------------------------------------------------------- relativity
# ------------------------------------------------------------------------------- geometry
def geodetic_lat_height(pos_m):
    """Geodetic latitude [rad] and ellipsoidal height [m] of Earth-fixed positions (n, 3).

    WGS 84 ellipsoid (``erfa.gc2gde``); GRS 80 (ITRF) differs by < 1e-9 rad and 0.1 mm.
    """
    _, lat, h = erfa.gc2gde(WGS84_A_M, 1.0 / WGS84_INV_F, np.asarray(pos_m, dtype=float))
    return lat, h


def _up(pos_m: np.ndarray) -> np.ndarray:
    """Unit ellipsoidal normals (n, 3) at Earth-fixed positions."""
    lon, lat, _ = erfa.gc2gde(WGS84_A_M, 1.0 / WGS84_INV_F, pos_m)
    cl = np.cos(lat)
    return np.stack([cl * np.cos(lon), cl * np.sin(lon), np.sin(lat)], axis=-1)


def elevation_rad(pos_station_m, los_m):
    """Geometric elevation of lines of sight above the station's ellipsoidal horizon.

    Parameters
    ----------
    pos_station_m : array_like, shape (n, 3) or (3,)
        Earth-fixed station position [m].
    los_m : array_like, shape (n, 3)
        Station-to-target vectors in the same axes [m] (any length).

    Returns
    -------
    ndarray, shape (n,)
        Elevation [rad].
    """
    los = np.atleast_2d(np.asarray(los_m, dtype=float))
    sta = np.broadcast_to(np.asarray(pos_station_m, dtype=float), los.shape)
    sin_el = np.einsum("ni,ni->n", _up(sta), los) / np.linalg.norm(los, axis=-1)
    return np.arcsin(np.clip(sin_el, -1.0, 1.0))


def _rotate_z(vec: np.ndarray, angle_rad: np.ndarray) -> np.ndarray:
    """Active rotation of vectors (n, 3) about Z by angles (n,) (counter-clockwise)."""
    c, s = np.cos(angle_rad), np.sin(angle_rad)
    x, y = vec[:, 0], vec[:, 1]
    return np.stack([c * x - s * y, s * x + c * y, vec[:, 2]], axis=-1)


# ------------------------------------------------------------------------------ light time
@dataclass(frozen=True)
class LightTime:
    """Geometry of two-way laser ranges (vacuum, straight lines), arrays over n points.

    Attributes
    ----------
    tau_up_s, tau_down_s : ndarray, shape (n,)
        Light times of the uplink (transmit → bounce) and downlink (bounce → receive) [s].
    pos_reflector_m : ndarray, shape (n, 3)
        ITRF reflector position at the bounce epoch [m].
    los_up_m : ndarray, shape (n, 3)
        Station (transmit epoch) → reflector (bounce epoch), in the ITRF axes of the transmit
        epoch [m]; its length is ``c τ_up``.
    los_down_m : ndarray, shape (n, 3)
        Station (receive epoch) → reflector (bounce epoch), in the ITRF axes of the receive
        epoch [m]; its length is ``c τ_down``.
    """

    tau_up_s: np.ndarray
    tau_down_s: np.ndarray
    pos_reflector_m: np.ndarray
    los_up_m: np.ndarray
    los_down_m: np.ndarray

    @property
    def tof_s(self) -> np.ndarray:
        """Geometric two-way time of flight τ_up + τ_down [s]."""
        return self.tau_up_s + self.tau_down_s


def _norm(v: np.ndarray) -> np.ndarray:
    return np.sqrt(np.einsum("ni,ni->n", v, v))


def _converged(change_s: np.ndarray, tol_m: float) -> bool:
    """True when every finite light-time change is below the tolerance (NaN = no data)."""
    return not np.any(change_s * C_LIGHT_M_S > tol_m)


def _not_converged(leg: str, change_s: np.ndarray, tol_m: float, max_iter: int) -> str:
    """Message of a light-time iteration that did not converge."""
    change_m = change_s * C_LIGHT_M_S
    bad = change_m > tol_m
    return (f"{leg} light time did not converge in {max_iter} iterations: {int(bad.sum())} of "
            f"{bad.size} points still change by up to {np.nanmax(change_m):.2e} m "
            f"(tolerance {tol_m:.0e} m)")


def two_way_light_time(t_transmit_s, pos_station_m,
                       reflector_pos_m: Callable[[np.ndarray], np.ndarray], *,
                       tol_m: float = 1e-6, max_iter: int = 10) -> LightTime:
    """Solve the uplink and downlink light times of two-way ranges from fixed stations.

    Uplink (fixed-point iteration, Montenbruck & Gill 2000, ch. 6):
    ``c τ_up = |R3(−ω τ_up) r_refl(t_t + τ_up) − r_sta|`` in the ITRF axes of ``t_t``;
    downlink: ``c τ_down = |r_refl(t_b) − R3(−ω τ_down) r_sta|`` in the ITRF axes of ``t_b``
    (``R3(−α)`` = eastward rotation by α; see the module docstring for the frame argument).
    Each iteration reduces the error by ~|ρ̇|/c ≈ 3e-5: three evaluations of the reflector
    callable reach 1e-8 m. Below ~1e-7 m the rounding of the interpolated orbit (nodes of
    ~7e6 m) makes some points alternate between two values, so the default tolerance is
    1 µm, three orders of magnitude below the precision of normal points.

    Parameters
    ----------
    t_transmit_s : array_like, shape (n,)
        Transmit epochs [s] on the time axis of ``reflector_pos_m``.
    pos_station_m : array_like, shape (n, 3) or (3,)
        ITRF station position (reference point of the ranges) [m].
    reflector_pos_m : callable
        ``f(t_s) -> (m, 3)`` ITRF position of the retro-reflector [m] at epochs ``t_s`` (m,)
        [s]; NaN where unknown (the results are then NaN).
    tol_m : float
        Stop when no light time changes by more than ``tol_m / c`` [m] (default 1 µm).
    max_iter : int
        Maximum number of iterations per leg.

    Returns
    -------
    LightTime

    Raises
    ------
    RuntimeError
        If the iteration does not converge within ``max_iter`` steps.
    """
    t = np.atleast_1d(np.asarray(t_transmit_s, dtype=float))
    sta = np.broadcast_to(np.asarray(pos_station_m, dtype=float), t.shape + (3,))
    tau_up = _norm(reflector_pos_m(t) - sta) / C_LIGHT_M_S
    for _ in range(max_iter):
        pos_b = reflector_pos_m(t + tau_up)
        los_up = _rotate_z(pos_b, OMEGA_EARTH_RAD_S * tau_up) - sta
        new = _norm(los_up) / C_LIGHT_M_S
        change, tau_up = np.abs(new - tau_up), new
        if _converged(change, tol_m):
            break
    else:
        raise RuntimeError(_not_converged("uplink", change, tol_m, max_iter))
    tau_down = tau_up.copy()
    for _ in range(max_iter):
        new = _norm(pos_b - _rotate_z(sta, OMEGA_EARTH_RAD_S * tau_down)) / C_LIGHT_M_S
        change, tau_down = np.abs(new - tau_down), new
        if _converged(change, tol_m):
            break
    else:
        raise RuntimeError(_not_converged("downlink", change, tol_m, max_iter))
    los_down = _rotate_z(pos_b, -OMEGA_EARTH_RAD_S * tau_down) - sta
    return LightTime(tau_up, tau_down, pos_b, los_up, los_down)


# --------------------------------------------------------------------------- full model
@dataclass(frozen=True)
class SlrRange:
    """Computed two-way laser ranges and their parts, arrays over n points.

    Attributes
    ----------
    light_time : LightTime
        Vacuum geometry.
    elevation_rad : ndarray, shape (n,)
        Geometric elevation of the uplink at the station [rad].
    tropo_m : ndarray, shape (n,)
        Tropospheric delay, mean of the two legs [m] (zero without meteorological data).
    relativity_m : ndarray, shape (n,)
        Shapiro delay, mean of the two legs [m].
    """

    light_time: LightTime
    elevation_rad: np.ndarray
    tropo_m: np.ndarray
    relativity_m: np.ndarray

    @property
    def geometric_range_m(self) -> np.ndarray:
        """Vacuum one-way range ``c (τ_up + τ_down) / 2`` [m]."""
        return 0.5 * C_LIGHT_M_S * self.light_time.tof_s

    @property
    def range_m(self) -> np.ndarray:
        """One-way range ``c · tof / 2`` incl. troposphere and relativity [m]."""
        return self.geometric_range_m + self.tropo_m + self.relativity_m

    @property
    def tof_s(self) -> np.ndarray:
        """Computed two-way time of flight [s] (what a CRD record 11 holds)."""
        return 2.0 * self.range_m / C_LIGHT_M_S


def slr_range(t_transmit_s, pos_station_m, reflector_pos_m: Callable[[np.ndarray], np.ndarray],
              *, pressure_hpa=None, temperature_k=None, humidity_pct=None,
              wavelength_um: float = 0.532, relativity: bool = True) -> SlrRange:
    """Computed SLR ranges: light time + Mendes–Pavlis troposphere + Shapiro delay.

    Each leg gets the tropospheric delay at its own elevation and the Shapiro delay of its
    own length (IERS Conventions 2010, sec. 9.2.1 and eq. 11.17); :class:`SlrRange` holds
    their means, i.e. one-way quantities.

    Parameters
    ----------
    t_transmit_s : array_like, shape (n,)
        Transmit epochs [s] on the time axis of ``reflector_pos_m``.
    pos_station_m : array_like, shape (n, 3) or (3,)
        ITRF station positions [m].
    reflector_pos_m : callable
        ITRF reflector position ``f(t_s) -> (m, 3)`` [m] (see :func:`two_way_light_time`).
    pressure_hpa, temperature_k, humidity_pct : array_like, shape (n,) or scalar, optional
        Surface meteorological data [hPa, K, %]; all three or none (no troposphere).
    wavelength_um : float
        Laser wavelength [µm].
    relativity : bool
        Apply the Shapiro delay.

    Returns
    -------
    SlrRange

    Raises
    ------
    ValueError
        If only some of the meteorological values are given.
    """
    meteo = (pressure_hpa, temperature_k, humidity_pct)
    if any(v is None for v in meteo) and not all(v is None for v in meteo):
        raise ValueError("give pressure_hpa, temperature_k and humidity_pct together, or none")
    lt = two_way_light_time(t_transmit_s, pos_station_m, reflector_pos_m)
    n = lt.tau_up_s.size
    sta = np.broadcast_to(np.asarray(pos_station_m, dtype=float), (n, 3))
    el_up = elevation_rad(sta, lt.los_up_m)
    tropo = np.zeros(n)
    if pressure_hpa is not None:
        el_down = elevation_rad(sta, lt.los_down_m)
        lat, h = geodetic_lat_height(sta)
        delays = [mendes_pavlis_delay_m(el, lat, h, pressure_hpa, temperature_k, humidity_pct,
                                        wavelength_um) for el in (el_up, el_down)]
        tropo = 0.5 * (delays[0] + delays[1])
    rel = np.zeros(n)
    if relativity:
        r_sta, r_refl = _norm(sta), _norm(lt.pos_reflector_m)
        rel = 0.5 * (shapiro_delay_m(r_sta, r_refl, C_LIGHT_M_S * lt.tau_up_s)
                     + shapiro_delay_m(r_sta, r_refl, C_LIGHT_M_S * lt.tau_down_s))
    return SlrRange(lt, el_up, tropo, rel)


# ------------------------------------------------------------------- reflector trajectory
class OrbitReflector:
    """Retro-reflector trajectory from a tabulated Earth-fixed centre-of-mass orbit.

    ``r_refl(t) = r_com(t) + R(t)ᵀ d`` with ``R`` the Earth-fixed → body rotation of the
    satellite's attitude law (:func:`leopod.frames.leo_attitude.leo_body_axes_ef`) and ``d`` the
    reflector offset from the centre of mass in the body frame. Position and velocity are
    Lagrange-interpolated (:func:`leopod.numerics.interpolate.interpolate_table`). Calling the
    object with seconds since :attr:`t0` gives positions (m, 3) [m]; NaN outside the table.

    Parameters
    ----------
    orbit : xarray.Dataset
        Coordinate ``time`` (datetime64[ns], GPS time), ``pos_itrf_m`` and ``vel_itrf_m_s``
        (time, xyz) [m, m/s], centre of mass in the ITRF.
    offset_body_m : array_like, shape (3,)
        Reflector offset from the centre of mass in the body frame [m].
    order : int
        Interpolation order (default 10).
    attitude : LeoAttitude, optional
        Attitude law of the satellite; None: nominal.
    """

    def __init__(self, orbit: xr.Dataset, offset_body_m, order: int = 10,
                 attitude: LeoAttitude | None = None):
        times = orbit["time"].values.astype("datetime64[ns]")
        self.t0 = times[0]
        self.t_nodes_s = (times - self.t0).astype(np.int64) / 1e9
        pos = orbit["pos_itrf_m"].transpose("time", "xyz").values
        vel = orbit["vel_itrf_m_s"].transpose("time", "xyz").values
        self._table = np.concatenate([pos, vel], axis=1)
        self.offset_body_m = np.asarray(offset_body_m, dtype=float)
        self.order = order
        self.attitude = attitude

    def seconds(self, times) -> np.ndarray:
        """Seconds since :attr:`t0` of GPS-time epochs (datetime64)."""
        t = np.atleast_1d(np.asarray(times, dtype="datetime64[ns]"))
        return (t - self.t0).astype(np.int64) / 1e9

    def centre_of_mass(self, t_s) -> tuple[np.ndarray, np.ndarray]:
        """Interpolated centre-of-mass position [m] and velocity [m/s], each (m, 3)."""
        val, _ = interpolate_table(self.t_nodes_s, self._table, t_s, self.order)
        return val[:, :3], val[:, 3:]

    def __call__(self, t_s) -> np.ndarray:
        pos, vel = self.centre_of_mass(t_s)
        if not np.any(self.offset_body_m):
            return pos
        times = self.t0 + np.round(np.asarray(t_s) * 1e9).astype("timedelta64[ns]")
        rot = leo_body_axes_ef(self.attitude, times, pos, vel)
        return pos + body_to_ef(rot, self.offset_body_m)

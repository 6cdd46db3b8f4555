"""Atmospheric drag: cannonball and flat-plate models, Harris–Priester and MSIS densities.

Acceleration (Montenbruck & Gill 2000, sec. 3.5.1), with the estimated drag scale
factor s::

    a = −½ s ρ (C_D A/m) |v_r| v_r,      v_r = v − ω × r

The atmosphere co-rotates with the Earth: ``ω`` is the Earth's angular velocity in GCRF, by
default ``ω_E ẑ`` (IERS 2010 nominal rate along the GCRF Z axis; the CIP is off the GCRF
pole by precession–nutation, ≈ 0.05° in 2007 and 0.15° in 2026, which changes v_r by
≲ 1.5 m/s, 2e-4 relative). Pass the exact vector (``R_gcrf→itrfᵀ ω_E ẑ``) to remove that
approximation. Winds are neglected.

Flat-plate (macro) model: each plate of area A_i, outward normal n_i and drag coefficient
C_D,i facing the flow (n_i·v_r > 0) adds its projected area, the force staying along v_r
(no lift)::

    a = −½ s (ρ/m) (wᵀ v_r) v_r,     w = Σ_{n_i·v_r > 0} C_D,i A_i n_i

Partial derivatives: ``∂a/∂v`` analytic (the set of plates facing the flow held fixed, exact
almost everywhere); ``∂a/∂r = −(∂a/∂v)[ω×] + a ∇ρᵀ/ρ`` with the density gradient ∇ρ from
the density model; ``∂a/∂s = a/s`` (returned as the unscaled acceleration).

Density models (both callables ``model(t_tt_s, pos_m, rot_gcrf_to_ef, sun_m) → (ρ, ∇ρ)``,
with ``t_tt_s`` TT seconds since J2000.0, GCRF positions [m], the GCRF → ITRF rotation
matrix and the GCRF gradient [kg/m⁴]):

* :class:`HarrisPriesterDensity` — modified Harris–Priester model (M&G sec. 3.5.2,
  Table 3.8, mean solar activity), with the diurnal bulge lagging the Sun
  by 30° in right ascension; analytic gradient. Used when no space-weather data are given.
* :class:`MsisDensity` — NRLMSISE-00 (Picone et al. 2002, JGR 107(A12) 1468) or MSIS 2.x
  (Emmert et al. 2021) through ``pymsis``, fed with F10.7 and ap from the CelesTrak file
  (:mod:`leopod.io.space_weather`); the gradient is the geodetic-vertical derivative from a
  central difference over ±1 km (horizontal gradients, on scales of 1000s of km, neglected).

Density along a reference orbit (:class:`DensityAlongOrbit`): for the compiled force model
(:mod:`leopod.dynamics.compiled`) the density model is evaluated once per arc, vectorised, at
equidistant nodes of a reference orbit (e.g. the previous iteration's), and extended to nearby
positions by ``ln ρ(t, r) = L(t) + G(t)·(r − R(t))`` with ``L = ln ρ``, ``G = ∇ρ/ρ`` and the
reference position R interpolated in time (Lagrange, 8 points): exact for an exponential
atmosphere along G. For MSIS the gradient is vertical (above), so a deviation of δ from the
reference orbit errs by about (δ/H)²/2 × |dH/dh| in ln ρ (H ≈ 60 km at 500 km: ~3e-7 for
δ = 100 m). The 3-hourly ap and daily F10.7 steps of MSIS are smoothed over ± 4 nodes.

:class:`Drag` is the force of the orbit integrator (cannonball or plates), a scale factor per
interval.
"""

from __future__ import annotations

import erfa
import numba
import numpy as np
import xarray as xr

from leopod.constants import GPST_MINUS_TAI_S, OMEGA_EARTH_RAD_S, TT_MINUS_TAI_S
from leopod.dynamics.forces import _Scaled
from leopod.dynamics.srp import absent_plates
from leopod.numerics.interpolate import lagrange_equidistant
from leopod.time.calendar import J2000_TT
from leopod.time.scales import tai_minus_utc_s

__all__ = [
    "DensityAlongOrbit",
    "Drag",
    "HarrisPriesterDensity",
    "MsisDensity",
    "drag_cannonball",
    "drag_plates",
    "harris_priester_density",
]

_OMEGA_Z = np.array([0.0, 0.0, OMEGA_EARTH_RAD_S])
_ERFA_WGS84 = 1  # ellipsoid identifier of erfa.gc2gd (SOFA iau_GC2GD: 1 = WGS84)

# Modified Harris–Priester density table for mean solar activity, M&G (2000) Table 3.8:
# height [km], minimum (antapex) and maximum (apex) density [g/km³ = 1e-12 kg/m³].
_HP_H_KM = np.array([
    100, 120, 130, 140, 150, 160, 170, 180, 190, 200, 210, 220, 230, 240, 250, 260, 270, 280,
    290, 300, 320, 340, 360, 380, 400, 420, 440, 460, 480, 500, 520, 540, 560, 580, 600, 620,
    640, 660, 680, 700, 720, 740, 760, 780, 800, 840, 880, 920, 960, 1000], dtype=float)
_HP_MIN = 1e-12 * np.array([
    4.974e+05, 2.490e+04, 8.377e+03, 3.899e+03, 2.122e+03, 1.263e+03, 8.008e+02, 5.283e+02,
    3.617e+02, 2.557e+02, 1.839e+02, 1.341e+02, 9.949e+01, 7.488e+01, 5.709e+01, 4.403e+01,
    3.430e+01, 2.697e+01, 2.139e+01, 1.708e+01, 1.099e+01, 7.214e+00, 4.824e+00, 3.274e+00,
    2.249e+00, 1.558e+00, 1.091e+00, 7.701e-01, 5.474e-01, 3.916e-01, 2.819e-01, 2.042e-01,
    1.488e-01, 1.092e-01, 8.070e-02, 6.012e-02, 4.519e-02, 3.430e-02, 2.632e-02, 2.043e-02,
    1.607e-02, 1.281e-02, 1.036e-02, 8.496e-03, 7.069e-03, 4.680e-03, 3.200e-03, 2.210e-03,
    1.560e-03, 1.150e-03])
_HP_MAX = 1e-12 * np.array([
    4.974e+05, 2.490e+04, 8.710e+03, 4.059e+03, 2.215e+03, 1.344e+03, 8.758e+02, 6.010e+02,
    4.297e+02, 3.162e+02, 2.396e+02, 1.853e+02, 1.455e+02, 1.157e+02, 9.308e+01, 7.555e+01,
    6.182e+01, 5.095e+01, 4.226e+01, 3.526e+01, 2.511e+01, 1.819e+01, 1.337e+01, 9.955e+00,
    7.492e+00, 5.684e+00, 4.355e+00, 3.362e+00, 2.612e+00, 2.042e+00, 1.605e+00, 1.267e+00,
    1.005e+00, 7.997e-01, 6.390e-01, 5.123e-01, 4.121e-01, 3.325e-01, 2.691e-01, 2.185e-01,
    1.779e-01, 1.452e-01, 1.190e-01, 9.776e-02, 8.059e-02, 5.741e-02, 4.210e-02, 3.130e-02,
    2.360e-02, 1.810e-02])
#: Lag of the diurnal bulge apex behind the Sun in right ascension [rad] (M&G sec. 3.5.2: 30°).
HP_BULGE_LAG_RAD = np.radians(30.0)


# ----------------------------------------------------------------------------- accelerations


def _skew(w: np.ndarray) -> np.ndarray:
    """Cross-product matrix [w×] (``[w×] x = w × x``)."""
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


@numba.njit(cache=True)
def _drag_kernel(vrel, rho, grad_rho, w, cannonball, coef, omega_skew):
    """Unscaled drag acceleration and its partials for either model.

    cannonball: a = −½ ρ coef |v_r| v_r;  plates: a = −½ ρ coef (wᵀ v_r) v_r (coef = 1/m).
    """
    speed = np.sqrt(vrel[0] ** 2 + vrel[1] ** 2 + vrel[2] ** 2)
    half = 0.5 * rho * coef
    da_dv = np.empty((3, 3))
    if cannonball:
        acc = -half * speed * vrel
        for i in range(3):
            for j in range(3):
                da_dv[i, j] = -half * ((speed if i == j else 0.0) + vrel[i] * vrel[j] / speed)
    else:
        proj = w[0] * vrel[0] + w[1] * vrel[1] + w[2] * vrel[2]
        acc = -half * proj * vrel
        for i in range(3):
            for j in range(3):
                da_dv[i, j] = -half * (vrel[i] * w[j] + (proj if i == j else 0.0))
    da_dr = -(da_dv @ omega_skew)
    if rho > 0.0:
        for i in range(3):
            for j in range(3):
                da_dr[i, j] += acc[i] * grad_rho[j] / rho
    return acc, da_dr, da_dv


def _relative_velocity(pos: np.ndarray, vel: np.ndarray, omega: np.ndarray) -> np.ndarray:
    """Velocity relative to the co-rotating atmosphere, v − ω × r [m/s]."""
    return vel - np.array([omega[1] * pos[2] - omega[2] * pos[1],
                           omega[2] * pos[0] - omega[0] * pos[2],
                           omega[0] * pos[1] - omega[1] * pos[0]])


def _drag(pos, vel, density_kg_m3, grad_density_kg_m4, w, cannonball, coef, scale, omega):
    """Scaled acceleration and partials (acc, ∂a/∂r, ∂a/∂v, ∂a/∂s) of either drag model."""
    grad = np.zeros(3) if grad_density_kg_m4 is None else np.asarray(grad_density_kg_m4, float)
    acc0, dr0, dv0 = _drag_kernel(_relative_velocity(pos, vel, omega), float(density_kg_m3),
                                  grad, w, cannonball, coef, _skew(omega))
    return scale * acc0, scale * dr0, scale * dv0, acc0.reshape(3, 1).copy()


def _state(pos_m, vel_m_s, omega_rad_s):
    omega = _OMEGA_Z if omega_rad_s is None else np.asarray(omega_rad_s, dtype=float)
    return np.asarray(pos_m, dtype=float), np.asarray(vel_m_s, dtype=float), omega


def drag_cannonball(pos_m, vel_m_s, density_kg_m3: float, grad_density_kg_m4,
                    cd_area_mass_m2_kg: float, scale: float = 1.0, *, omega_rad_s=None):
    """Drag on a sphere-like satellite of constant C_D A/m (M&G 2000, sec. 3.5.1).

    Parameters
    ----------
    pos_m, vel_m_s : ndarray, shape (3,)
        GCRF position [m] and velocity [m/s].
    density_kg_m3 : float
        Atmospheric density ρ at the satellite [kg/m³].
    grad_density_kg_m4 : ndarray, shape (3,), or None
        GCRF gradient ∇ρ [kg/m⁴] (None: zero).
    cd_area_mass_m2_kg : float
        Ballistic coefficient C_D A/m [m²/kg].
    scale : float
        Drag scale factor s [1].
    omega_rad_s : ndarray, shape (3,), optional
        Angular velocity of the atmosphere in GCRF [rad/s]; default ω_E along GCRF Z.

    Returns
    -------
    acc : ndarray, shape (3,)
        Acceleration [m/s²].
    da_dr : ndarray, shape (3, 3)
        ∂a/∂r [1/s²].
    da_dv : ndarray, shape (3, 3)
        ∂a/∂v [1/s].
    da_dscale : ndarray, shape (3, 1)
        ∂a/∂s [m/s²].
    """
    pos, vel, omega = _state(pos_m, vel_m_s, omega_rad_s)
    return _drag(pos, vel, density_kg_m3, grad_density_kg_m4, np.zeros(3), True,
                 float(cd_area_mass_m2_kg), scale, omega)


def drag_plates(pos_m, vel_m_s, density_kg_m3: float, grad_density_kg_m4, normals, model,
                scale: float = 1.0, *, omega_rad_s=None):
    """Drag on a flat-plate macro model (projected area of the plates facing the flow).

    Parameters
    ----------
    pos_m, vel_m_s, density_kg_m3, grad_density_kg_m4, scale, omega_rad_s
        As :func:`drag_cannonball`.
    normals : ndarray, shape (k, 3)
        GCRF outward unit normals of the plates (:func:`leopod.dynamics.srp.plate_normals`).
    model : leopod.dynamics.srp.MacroModel
        Areas, drag coefficients and mass.

    Returns
    -------
    acc, da_dr, da_dv, da_dscale
        As :func:`drag_cannonball`.
    """
    pos, vel, omega = _state(pos_m, vel_m_s, omega_rad_s)
    w = _facing_area(np.ascontiguousarray(normals, dtype=float),
                     _relative_velocity(pos, vel, omega), model.drag_coefficient, model.area_m2)
    return _drag(pos, vel, density_kg_m3, grad_density_kg_m4, w, False,
                 1.0 / float(model.mass_kg), scale, omega)


@numba.njit(cache=True)
def _facing_area(normals, vrel, cd, area):  # pragma: no cover - numba
    """``w = Σ C_D,i A_i n_i`` over the plates facing the flow (n_i·v_r > 0) [m²]."""
    w = np.zeros(3)
    for p in range(normals.shape[0]):
        if normals[p, 0] * vrel[0] + normals[p, 1] * vrel[1] + normals[p, 2] * vrel[2] > 0.0:
            for i in range(3):
                w[i] += cd[p] * area[p] * normals[p, i]
    return w


# ---------------------------------------------------------------------------- geodetic helper


def _geodetic_ef(pos_ef_m: np.ndarray):
    """WGS84 longitude [rad], latitude [rad], height [m] and unit up vector of Earth-fixed
    positions (3,) or (n, 3) [m] (up: shape (3,) or (n, 3))."""
    lon, lat, h = erfa.gc2gd(_ERFA_WGS84, pos_ef_m)
    up = np.stack([np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)], axis=-1)
    return lon, lat, h, up


# --------------------------------------------------------------------------- Harris–Priester


def harris_priester_density(height_m, cos_psi, exponent: float = 6.0):
    """Modified Harris–Priester density and its derivatives (M&G 2000, sec. 3.5.2).

    ``ρ = ρ_m(h) + (ρ_M(h) − ρ_m(h)) cos^n(ψ/2)``, ρ_m and ρ_M interpolated exponentially in
    the Table 3.8 (mean solar activity), ψ the angle between the satellite and the apex of the
    diurnal bulge, ``cos^n(ψ/2) = ((1 + cos ψ)/2)^(n/2)``.

    Parameters
    ----------
    height_m : float or array_like, shape (n,)
        Height above the ellipsoid [m], 100–1000 km (0 is returned above 1000 km).
    cos_psi : float or array_like, shape (n,)
        Cosine of the angle between the position and the bulge apex.
    exponent : float
        n: 2 for low-inclination, 6 for polar orbits (M&G sec. 3.5.2).

    Returns
    -------
    rho : float or ndarray, shape (n,)
        Density [kg/m³].
    drho_dh : float or ndarray, shape (n,)
        ∂ρ/∂h [kg/m⁴].
    drho_dcos : float or ndarray, shape (n,)
        ∂ρ/∂cos ψ [kg/m³].

    Raises
    ------
    ValueError
        Below 100 km (outside the model).
    """
    scalar = np.ndim(height_m) == 0 and np.ndim(cos_psi) == 0
    h_km, cos = np.broadcast_arrays(np.atleast_1d(np.asarray(height_m, dtype=float)) / 1000.0,
                                    np.atleast_1d(np.asarray(cos_psi, dtype=float)))
    if np.any(h_km < _HP_H_KM[0]):
        raise ValueError(f"Harris-Priester: height {h_km.min():.1f} km below 100 km")
    inside = h_km < _HP_H_KM[-1]
    i = np.minimum(np.searchsorted(_HP_H_KM, h_km, side="right") - 1, _HP_H_KM.size - 2)
    dh = _HP_H_KM[i] - _HP_H_KM[i + 1]
    scale_min_km = dh / np.log(_HP_MIN[i + 1] / _HP_MIN[i])
    scale_max_km = dh / np.log(_HP_MAX[i + 1] / _HP_MAX[i])
    rho_min = _HP_MIN[i] * np.exp((_HP_H_KM[i] - h_km) / scale_min_km)
    rho_max = _HP_MAX[i] * np.exp((_HP_H_KM[i] - h_km) / scale_max_km)
    half = 0.5 * exponent
    c2 = np.maximum(0.5 + 0.5 * cos, 0.0)  # cos²(ψ/2)
    weight = c2**half
    rho = rho_min + (rho_max - rho_min) * weight
    drho_dh = -(rho_min / scale_min_km * (1.0 - weight) + rho_max / scale_max_km * weight) / 1e3
    lit = c2 > 0.0
    drho_dcos = np.where(lit, (rho_max - rho_min) * half * np.where(lit, c2, 1.0) ** (half - 1.0)
                         * 0.5, 0.0)
    out = tuple(np.where(inside, x, 0.0) for x in (rho, drho_dh, drho_dcos))
    return tuple(float(x[0]) for x in out) if scalar else out


class HarrisPriesterDensity:
    """Modified Harris–Priester atmosphere (M&G 2000, sec. 3.5.2) as a density model.

    Parameters
    ----------
    exponent : float
        n of ``cos^n(ψ/2)``: 2 for low-inclination orbits, 6 for polar orbits.
    """

    def __init__(self, exponent: float = 6.0):
        self.exponent = float(exponent)

    def __call__(self, t_tt_s: float, pos_m, rot_gcrf_to_ef, sun_m):
        """Density [kg/m³] and its GCRF gradient [kg/m⁴] at the satellite.

        Parameters
        ----------
        t_tt_s : float
            TT seconds since J2000.0 (unused: the model is static but for the Sun).
        pos_m : ndarray, shape (3,)
            GCRF position [m].
        rot_gcrf_to_ef : ndarray, shape (3, 3)
            GCRF → ITRF rotation (for the geodetic height).
        sun_m : ndarray, shape (3,)
            GCRF Sun position [m] (its right ascension + 30° and declination give the apex).
        """
        rho, grad = self.many([t_tt_s], np.reshape(pos_m, (1, 3)),
                              np.reshape(rot_gcrf_to_ef, (1, 3, 3)), np.reshape(sun_m, (1, 3)))
        return float(rho[0]), grad[0]

    def many(self, t_tt_s, pos_m, rot_gcrf_to_ef, sun_m):
        """:meth:`__call__` at n epochs: ρ (n,) [kg/m³] and ∇ρ (n, 3) [kg/m⁴]."""
        pos = np.asarray(pos_m, dtype=float)
        rot = np.asarray(rot_gcrf_to_ef, dtype=float)
        _, _, height, up_ef = _geodetic_ef(np.einsum("nij,nj->ni", rot, pos))
        sun = np.asarray(sun_m, dtype=float)
        cl, sl = np.cos(HP_BULGE_LAG_RAD), np.sin(HP_BULGE_LAG_RAD)
        apex = np.stack([cl * sun[:, 0] - sl * sun[:, 1], sl * sun[:, 0] + cl * sun[:, 1],
                         sun[:, 2]], axis=-1)
        apex /= np.linalg.norm(apex, axis=1)[:, None]
        rn = np.linalg.norm(pos, axis=1)
        cos_psi = np.sum(pos * apex, axis=1) / rn
        rho, drho_dh, drho_dcos = harris_priester_density(height, cos_psi, self.exponent)
        grad = (drho_dh[:, None] * np.einsum("ni,nij->nj", up_ef, rot)
                + drho_dcos[:, None] * (apex - cos_psi[:, None] * pos / rn[:, None])
                / rn[:, None])
        return rho, grad


# ------------------------------------------------------------------------------------- MSIS


def _tt_to_utc(t_tt_s: float, cache: dict) -> np.datetime64:
    """UTC epoch of TT seconds since J2000.0 (TAI−UTC from :mod:`leopod.time.scales`, cached
    per day because it sits on the integrator's hot path)."""
    tai = J2000_TT + np.timedelta64(round((t_tt_s - TT_MINUS_TAI_S) * 1e9), "ns")
    day = tai.astype("datetime64[D]")
    if day not in cache:
        gps = tai + np.timedelta64(round(GPST_MINUS_TAI_S * 1e9), "ns")
        cache[day] = np.timedelta64(round(float(tai_minus_utc_s(gps)[0]) * 1e9), "ns")
    return tai - cache[day]


class MsisDensity:
    """NRLMSISE-00 / MSIS 2.x densities through pymsis, driven by CelesTrak space weather.

    Parameters
    ----------
    space_weather : xarray.Dataset
        From :func:`leopod.io.space_weather.read_space_weather`.
    version : float or str
        MSIS version for pymsis: 0 (NRLMSISE-00, default), 2.0 or 2.1.
    storm_time_ap : bool
        Use the 3-hourly ap history (NRLMSISE-00 switch 9 = −1) instead of the daily Ap.
    gradient_step_m : float
        Half-width of the central difference of ρ along the geodetic vertical [m].
    """

    def __init__(self, space_weather: xr.Dataset, version: float | str = 0,
                 storm_time_ap: bool = True, gradient_step_m: float = 1000.0):
        import pymsis

        from leopod.io.space_weather import msis_inputs

        self._calculate = pymsis.calculate
        self._msis_inputs = msis_inputs
        self.space_weather = space_weather
        self.version = version
        self.options = pymsis.msis.create_options(geomagnetic_activity=-1 if storm_time_ap else 1)
        self.step_km = gradient_step_m / 1000.0
        self._leap_cache: dict = {}
        self._slot = None
        self._inputs = None

    def indices(self, t_utc: np.datetime64):
        """F10.7 [sfu], F10.7a [sfu] and the ap array (7,) at a UTC epoch (cached per 3 h)."""
        slot = int(np.datetime64(t_utc, "ns").astype(np.int64) // (10_800 * 1_000_000_000))
        if slot != self._slot:
            f107, f107a, ap = self._msis_inputs(self.space_weather, t_utc)
            self._inputs = (float(f107[0]), float(f107a[0]), ap[0])
            self._slot = slot
        return self._inputs

    def density_geodetic(self, t_utc: np.datetime64, lon_deg, lat_deg, alt_m):
        """Total mass density [kg/m³] at WGS84 geodetic points and one UTC epoch.

        Parameters
        ----------
        t_utc : numpy.datetime64
            UTC epoch.
        lon_deg, lat_deg, alt_m : array_like, shape (n,)
            Geodetic longitude, latitude [deg] and height [m] (WGS84), broadcast together.

        Returns
        -------
        ndarray, shape (n,)
        """
        lon, lat, alt = np.broadcast_arrays(*(np.atleast_1d(np.asarray(x, dtype=float))
                                              for x in (lon_deg, lat_deg, alt_m)))
        n = alt.size
        f107, f107a, ap = self.indices(t_utc)
        out = self._calculate(np.full(n, np.datetime64(t_utc, "ns")), lon, lat, alt / 1000.0,
                              np.full(n, f107), np.full(n, f107a), np.tile(ap, (n, 1)),
                              options=self.options, version=self.version)
        return out[:, 0].astype(float)

    def __call__(self, t_tt_s: float, pos_m, rot_gcrf_to_ef, sun_m=None):
        """Density [kg/m³] and its GCRF gradient [kg/m⁴] at the satellite.

        Parameters
        ----------
        t_tt_s : float
            TT seconds since J2000.0 (converted to UTC for MSIS).
        pos_m : ndarray, shape (3,)
            GCRF position [m].
        rot_gcrf_to_ef : ndarray, shape (3, 3)
            GCRF → ITRF rotation.
        sun_m : ignored
            For the common density-model signature.
        """
        rot = np.asarray(rot_gcrf_to_ef, dtype=float)
        lon, lat, height, up_ef = _geodetic_ef(rot @ np.asarray(pos_m, dtype=float))
        t_utc = _tt_to_utc(float(t_tt_s), self._leap_cache)
        dh = self.step_km
        alts_km = height / 1000.0 + np.array([-dh, 0.0, dh])
        f107, f107a, ap = self.indices(t_utc)
        out = self._calculate(np.full(3, t_utc), np.full(3, np.degrees(lon)),
                              np.full(3, np.degrees(lat)), alts_km, np.full(3, f107),
                              np.full(3, f107a), np.tile(ap, (3, 1)), options=self.options,
                              version=self.version)
        rho = out[:, 0].astype(float)
        drho_dh = (rho[2] - rho[0]) / (2.0 * dh * 1000.0)
        return float(rho[1]), drho_dh * (up_ef @ rot)

    def many(self, t_tt_s, pos_m, rot_gcrf_to_ef, sun_m=None):
        """:meth:`__call__` at n epochs in one pymsis call: ρ (n,) [kg/m³], ∇ρ (n, 3) [kg/m⁴]."""
        rot = np.asarray(rot_gcrf_to_ef, dtype=float)
        pos_ef = np.einsum("nij,nj->ni", rot, np.asarray(pos_m, dtype=float))
        lon, lat, height, up_ef = _geodetic_ef(pos_ef)
        t_utc = np.array([_tt_to_utc(float(t), self._leap_cache) for t in t_tt_s])
        f107, f107a, ap = self._msis_inputs(self.space_weather, t_utc)
        dh = self.step_km
        alts_km = height[:, None] / 1000.0 + np.array([-dh, 0.0, dh])[None, :]
        out = self._calculate(np.repeat(t_utc, 3), np.repeat(np.degrees(lon), 3),
                              np.repeat(np.degrees(lat), 3), alts_km.ravel(),
                              np.repeat(f107, 3), np.repeat(f107a, 3), np.repeat(ap, 3, axis=0),
                              options=self.options, version=self.version)
        rho = out[:, 0].astype(float).reshape(-1, 3)
        drho_dh = (rho[:, 2] - rho[:, 0]) / (2.0 * dh * 1000.0)
        return rho[:, 1].copy(), drho_dh[:, None] * np.einsum("ni,nij->nj", up_ef, rot)


_TABLE_POINTS = 8          # Lagrange points of the density along an orbit (degree 7)


@numba.njit(cache=True)
def _density_at(t, pos, table):  # pragma: no cover - numba
    """ρ [kg/m³] and ∇ρ (3,) [kg/m⁴] at (t, pos) from a :class:`DensityAlongOrbit` table."""
    row = np.empty(7)
    lagrange_equidistant(t, table[0], table[1], table[2], table[3], row)
    ln_rho = row[0]
    for i in range(3):
        ln_rho += row[1 + i] * (pos[i] - row[4 + i])
    rho = np.exp(ln_rho)
    grad = np.empty(3)
    for i in range(3):
        grad[i] = rho * row[1 + i]
    return rho, grad


class DensityAlongOrbit:
    """A density model tabulated along a reference orbit (module docstring).

    Parameters
    ----------
    density : HarrisPriesterDensity or MsisDensity
        Model with the vectorised ``many(t_tt_j2000_s, pos_gcrf_m, rot_gcrf_to_itrf, sun_gcrf_m)
        -> (ρ (n,), ∇ρ (n, 3))``.
    env : ArcEnvironment
        Earth rotation and Sun at the nodes.
    t_s : ndarray, shape (n,)
        Equidistant node epochs [TT s since the reference epoch of ``env``], n ≥ 8.
    pos_m : ndarray, shape (n, 3)
        GCRF positions of the reference orbit at ``t_s`` [m].
    """

    def __init__(self, density, env, t_s: np.ndarray, pos_m: np.ndarray):
        t = np.asarray(t_s, dtype=float)
        pos = np.asarray(pos_m, dtype=float)
        if t.size < _TABLE_POINTS or pos.shape != (t.size, 3) or not np.isfinite(pos).all():
            raise ValueError(f"density along an orbit: need >= {_TABLE_POINTS} finite "
                             f"positions (n, 3) at the node epochs, got {pos.shape}")
        rot = np.swapaxes(env.rotation(t), 1, 2)
        rho, grad = density.many(env.tt_j2000_s(t), pos, rot, env.sun_m(t))
        if np.any(rho <= 0.0):
            raise ValueError("density along an orbit: the model gives rho <= 0 (above its "
                             "top, e.g. Harris-Priester over 1000 km)")
        values = np.column_stack([np.log(rho), grad / rho[:, None], pos])
        step = float(t[1] - t[0])
        self._args = (float(t[0]), step, _TABLE_POINTS, np.ascontiguousarray(values))

    def args(self) -> tuple:
        """``(t_first, step, n_points, values (n, 7))`` for :func:`_density_at` (jitted code)."""
        return self._args

    def __call__(self, t_s: float, pos_m: np.ndarray) -> tuple[float, np.ndarray]:
        """ρ [kg/m³] and GCRF ∇ρ (3,) [kg/m⁴] at one epoch [TT s] and GCRF position [m]."""
        rho, grad = _density_at(float(t_s), np.ascontiguousarray(pos_m, dtype=float),
                                self._args)
        return float(rho), grad


class Drag(_Scaled):
    """Atmospheric drag on a cannonball or on the plates of a macro model, one scale factor
    per interval (M&G 2000, sec. 3.5).

    ``a = −½ s_k ρ (C_D A/m) |v_r| v_r`` (cannonball) or ``a = −½ s_k (ρ/m) (wᵀ v_r) v_r``
    (plates, :func:`drag_plates`), ``v_r = v − ω × r`` with ω the Earth's rotation about the
    CIP (``ω_E R ẑ``, R the ITRF -> GCRF matrix); ρ and ∇ρ from ``density``
    (:class:`leopod.dynamics.drag.HarrisPriesterDensity` or ``MsisDensity``).

    Parameters
    ----------
    env : ArcEnvironment
    density : callable
        ``density(t_tt_j2000_s, pos_gcrf_m, rot_gcrf_to_itrf, sun_gcrf_m) -> (ρ, ∇ρ)``.
    cd_area_mass_m2_kg : float
        C_D A/m [m²/kg] of the cannonball (unused with ``plates``).
    edges_s : array_like, shape (n + 1,)
        Interval boundaries [s] of the scale factors ``drag_scale_k``.
    plates : leopod.dynamics.plates.Plates, optional
        Macro model and attitude (None: cannonball).
    apriori, estimate, sigma
        A priori scale, whether it is estimated, a priori constraint (None: free).
    """

    def __init__(self, env, density, cd_area_mass_m2_kg: float, edges_s, *, plates=None,
                 **kwargs):
        super().__init__(env, edges_s, "drag_scale", plates=plates, **kwargs)
        self.density = density
        self.cd_area_mass_m2_kg = float(cd_area_mass_m2_kg)
        self.along_orbit: DensityAlongOrbit | None = None

    def follow(self, positions, step_s: float = 30.0) -> None:
        """Take the density (and the attitude of the plates) along a reference orbit from now
        on (:class:`DensityAlongOrbit`, :class:`leopod.dynamics.plates.Plates`).

        Parameters
        ----------
        positions : callable
            ``positions(t_s (n,)) -> (n, 3)`` GCRF positions [m] over the arc of ``env``.
        step_s : float
            Largest node spacing [s] (nodes from the start to the end of the arc).
        """
        lo, hi = self.env.t_start_s, self.env.t_end_s
        n = max(int(np.ceil((hi - lo) / step_s - 1e-9)), _TABLE_POINTS - 1) + 1
        t = np.linspace(lo, hi, n)
        self.along_orbit = DensityAlongOrbit(self.density, self.env, t, positions(t))
        super().follow(positions)

    @property
    def ready(self) -> bool:
        """True once the density (and the plates' attitude) follow a reference orbit."""
        return self.along_orbit is not None and super().ready

    def kernel_data(self) -> tuple:
        """``(edges_s, C_D A/m, density table, plates?, plate data)`` for the compiled force
        model (needs :meth:`follow` first)."""
        if self.along_orbit is None:
            raise ValueError("drag: no reference orbit to take the density along (follow())")
        plates = absent_plates() if self.plates is None else self.plates.kernel_data()
        return (self.edges_s, self.cd_area_mass_m2_kg, self.along_orbit.args(),
                self.plates is not None, plates)

    def _unscaled(self, t_s, pos, vel, scale):
        rot = self.env.rotation(t_s)[0]
        bodies = self.env.body_grid(t_s)[0]
        if self.along_orbit is not None:
            rho, grad_rho = self.along_orbit(t_s, pos)
        else:
            rho, grad_rho = self.density(self.env.tt_j2000_ref_s + t_s, pos, rot.T,
                                         bodies[0:3])
        omega = OMEGA_EARTH_RAD_S * rot[:, 2]
        if self.plates is None:
            return drag_cannonball(pos, vel, rho, grad_rho, self.cd_area_mass_m2_kg, scale,
                                   omega_rad_s=omega)
        return drag_plates(pos, vel, rho, grad_rho, self.plates.normals(t_s, pos, bodies[0:3]),
                           self.plates.model, scale, omega_rad_s=omega)

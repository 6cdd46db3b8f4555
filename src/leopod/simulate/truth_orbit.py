"""Truth LEO orbit of the closed-loop simulator, integrated with the dynamics engine.

The truth is a sun-synchronous, near-circular orbit (by default HY-2B-like: 971 km, LTAN
18:00, i.e. a dawn–dusk orbit) integrated in the GCRF with
:func:`leopod.dynamics.integrator.integrate` under the force model of
:mod:`leopod.simulate.truth_forces`, which deliberately differs from what an estimator will use
(the per-interval drag scales and stochastic accelerations enter the integration as the
force-model parameter vector, so they are exact and stored with the orbit).

Time: the force model's reference epoch is the arc start ``t_start`` (a GPS-time label) and
its time argument is TT seconds since then, which equal GPS seconds since ``t_start`` (TT − GPST
is constant; :func:`leopod.time.seconds_since`).

Drag: the compiled force model (:mod:`leopod.dynamics.compiled`) takes the MSIS density along
a reference orbit; the truth is therefore integrated twice, first without drag (drag scales 0,
10-s steps) to give that reference, then with it. At 971 km drag moves the orbit by metres over
days, far below what the density's first-order extension along its gradient handles.
"""

from __future__ import annotations

import logging
import time as _time
from collections.abc import Mapping, Sequence
from pathlib import Path

import erfa
import numpy as np
import xarray as xr

from leopod.astro.ephemeris import Ephemeris
from leopod.constants import (
    GM_EARTH_M3_S2,
    GPST_MINUS_TAI_S,
    R_EARTH_EQUATOR_M,
    SECONDS_PER_DAY,
    TT_MINUS_TAI_S,
)
from leopod.dynamics.force_config import ForceModelSettings, build_force_model
from leopod.dynamics.forces import circular_orbit
from leopod.dynamics.integrator import DEFAULT_ORDER, DEFAULT_STEP_S, integrate
from leopod.frames.earth_rotation import cip_xys, gcrf_to_itrf
from leopod.io.manoeuvre import Manoeuvre
from leopod.io.netcdf import write_netcdf
from leopod.io.sp3_write import write_sp3
from leopod.simulate.manoeuvres import with_manoeuvres
from leopod.simulate.truth_forces import _RTN, TruthDynamics, TruthForces, truth_force_config
from leopod.simulate.world import _J2, CircularOrbit
from leopod.time.calendar import J2000_TT, from_seconds, seconds_since
from leopod.time.eop import EarthOrientation

__all__ = [
    "HY2B_ALTITUDE_M", "HY2B_LTAN_H", "SUN_SYNCHRONOUS_NODE_RATE_RAD_S",
    "initial_state_sun_synchronous", "intermediate_to_gcrf_matrix", "simulate_truth_orbit",
    "sun_synchronous_inclination_deg", "write_truth_files",
]

log = logging.getLogger(__name__)

#: HY-2B mean altitude [m]: 971 km (ILRS mission page HY-2B; Peng et al. 2021, sec. II-A:
#: "about 970 km").
HY2B_ALTITUDE_M = 971.0e3
#: HY-2B local time of the ascending node [h]: dawn–dusk orbit with the descending node at
#: 06:00 (HY-2 series, eoPortal "HY-2A"; not confirmed for HY-2B by a primary source).
HY2B_LTAN_H = 18.0
#: Tropical year [s], 365.2421897 d (Vallado, Fundamentals of Astrodynamics and Applications,
#: 4th ed. 2013, ch. 3, time systems).
TROPICAL_YEAR_S = 365.2421897 * SECONDS_PER_DAY
#: Node rate of a sun-synchronous orbit, 360° per tropical year [rad/s] (Vallado 2013,
#: ch. 11, sun-synchronous orbits; ≈ 0.9856°/d).
SUN_SYNCHRONOUS_NODE_RATE_RAD_S = 2.0 * np.pi / TROPICAL_YEAR_S
#: Hours of local solar time per radian of right ascension.
_HOURS_PER_RAD = 12.0 / np.pi
_NOON_H = 12.0
_TT_MINUS_GPST_S = TT_MINUS_TAI_S - GPST_MINUS_TAI_S
_XYZ = ["x", "y", "z"]


# ----------------------------------------------------------------------- initial state


def sun_synchronous_inclination_deg(a_m: float, eccentricity: float = 0.0) -> float:
    """Inclination [deg] whose secular J2 node rate equals the Sun's mean motion.

    ``Ω̇ = −(3/2) n J2 (R/p)² cos i`` (secular J2 node rate, Vallado 2013, eq. 9-41),
    ``n = sqrt(GM/a³)``, ``p = a (1 − e²)``, set equal to
    :data:`SUN_SYNCHRONOUS_NODE_RATE_RAD_S` (Vallado 2013, ch. 11, sun-synchronous orbits).

    Parameters
    ----------
    a_m : float
        Semi-major axis [m].
    eccentricity : float
        Eccentricity.

    Returns
    -------
    float
        Inclination [deg] (retrograde, > 90°).

    Raises
    ------
    ValueError
        If no inclination gives the rate (a above ~12 350 km for a circular orbit).
    """
    n = np.sqrt(GM_EARTH_M3_S2 / a_m**3)
    p = a_m * (1.0 - eccentricity**2)
    cos_i = -SUN_SYNCHRONOUS_NODE_RATE_RAD_S / (1.5 * n * _J2 * (R_EARTH_EQUATOR_M / p) ** 2)
    if abs(cos_i) > 1.0:
        raise ValueError(f"no sun-synchronous inclination for a = {a_m} m")
    return float(np.degrees(np.arccos(cos_i)))


def _tt_j2000_s(epoch) -> np.ndarray:
    """TT seconds since J2000.0 of GPS-time labels."""
    return seconds_since(np.atleast_1d(epoch), J2000_TT) + _TT_MINUS_GPST_S


def intermediate_to_gcrf_matrix(epoch) -> np.ndarray:
    """Rotation Q (3, 3) from the celestial intermediate frame (equator of the CIP, origin at
    the CIO) to the GCRF at a GPS epoch: ``Q = c2ixys(X, Y, s)ᵀ`` with the IAU 2006/2000A X, Y,
    s (IERS Conventions 2010, eqs. 5.7, 5.10; celestial pole offsets dX, dY < 1 mas ignored)."""
    x, y, s = cip_xys(np.atleast_1d(np.datetime64(epoch, "ns")), step_s=None)
    return erfa.c2ixys(x[0], y[0], s[0]).T


def initial_state_sun_synchronous(epoch, altitude_m: float = HY2B_ALTITUDE_M,
                                  ltan_h: float = HY2B_LTAN_H, *,
                                  inclination_deg: float | None = None, u0_deg: float = 0.0,
                                  ephemeris: Ephemeris | None = None) -> np.ndarray:
    """GCRF state of a circular sun-synchronous orbit at an epoch.

    The orbit is set up on the true equator of date (of the CIP, about which J2 makes the node
    precess; the CIP is ~0.1° off the GCRF pole in 2019, which would change the node rate by
    up to ±1.5% if ignored) and rotated to the GCRF with :func:`intermediate_to_gcrf_matrix`.
    Radius ``a = R_E + altitude`` (R_E equatorial, IERS 2010), circular speed ``sqrt(GM/a)``
    (an osculating circular state: J2 then gives the orbit an eccentricity of ~1e-3, like real
    HY-2B's 0.00117), inclination from :func:`sun_synchronous_inclination_deg` unless given,
    node from the local time of the ascending node: ``Ω = α_sun + (LTAN − 12 h)·15°/h`` with
    α_sun the right ascension of the Sun on the same equator (so the LTAN is apparent solar
    time, within the equation of time, ≤ 16.5 min, of mean solar time). The rotation of the
    equator (~1e-11 rad/s) is neglected in the velocity.

    Parameters
    ----------
    epoch : datetime64
        Epoch (GPS-time label).
    altitude_m : float
        Altitude above the equatorial radius [m].
    ltan_h : float
        Local time of the ascending node [h] (6: dawn, 18: dusk ascending node).
    inclination_deg : float, optional
        Inclination to the true equator [deg] (default: sun-synchronous).
    u0_deg : float
        Argument of latitude at the epoch [deg] (0: at the ascending node).
    ephemeris : Ephemeris, optional
        Sun ephemeris (default DE421).

    Returns
    -------
    ndarray, shape (6,)
        GCRF position [m] and velocity [m/s].
    """
    a_m = R_EARTH_EQUATOR_M + float(altitude_m)
    inc = sun_synchronous_inclination_deg(a_m) if inclination_deg is None else inclination_deg
    q = intermediate_to_gcrf_matrix(epoch)
    sun = q.T @ (ephemeris or Ephemeris()).sun_m(_tt_j2000_s(epoch))[0]
    raan_rad = np.arctan2(sun[1], sun[0]) + (ltan_h - _NOON_H) / _HOURS_PER_RAD
    orbit = CircularOrbit(a_m, float(inc), float(np.degrees(raan_rad) % 360.0), float(u0_deg),
                          j2=False)
    pos, vel = orbit.inertial(0.0)
    return np.concatenate([q @ pos, q @ vel])


# ----------------------------------------------------------------------------- forces


# ------------------------------------------------------------------------------ orbit


def _field_label(field_source) -> str:
    if isinstance(field_source, xr.Dataset):
        return str(field_source.attrs.get("modelname", "gravity field Dataset"))
    return Path(field_source).name


def _force_attrs(forces: TruthForces, dyn: TruthDynamics, integrator_step_s: float) -> dict:
    """Global attributes describing the truth forces (netCDF-compatible values)."""
    cfg = forces.config
    ocean = cfg["tides"]["ocean"]
    return {
        "gravity_field": _field_label(cfg["gravity"]["field"]),
        "gravity_max_degree": int(dyn.gravity_degree),
        "tides": "solid Earth (IERS 2010 steps 1-2), solid Earth pole, ocean pole"
                 + (f", ocean ({Path(ocean).name}, degree 30)" if ocean is not None else ""),
        "third_body": "Sun and Moon point masses (DE421)",
        "relativity": "IERS 2010 eq. 10.12 (Schwarzschild, Lense-Thirring, de Sitter)",
        "drag": "cannonball, NRLMSISE-00 (pymsis) along a drag-free first pass, space "
                "weather " + Path(cfg["drag"]["space_weather"]).name,
        "drag_cd_area_mass_m2_kg": dyn.drag_coefficient * dyn.drag_area_m2 / dyn.mass_kg,
        "drag_interval_s": dyn.drag_interval_s,
        "drag_scale_model": (f"1 + {dyn.drag_scale_amplitude} sin(2 pi t_mid / "
                             f"{dyn.drag_scale_period_s} s) + N(0, {dyn.drag_scale_sigma}^2)"),
        "srp": "cannonball, conical Earth shadow, scale 1",
        "srp_cr_area_mass_m2_kg": (dyn.reflectivity_coefficient * dyn.srp_area_m2
                                   / dyn.mass_kg),
        "stochastic_acceleration": "piecewise constant in R, T, N, N(0, sigma^2) per interval",
        "stochastic_interval_s": dyn.stochastic_interval_s,
        "stochastic_sigma_rtn_m_s2": np.asarray(dyn.stochastic_sigma_rtn_m_s2, dtype=float),
        "integrator": (f"Gauss-Jackson order {DEFAULT_ORDER} (PEC), step {integrator_step_s} s, "
                       "restarts at interval boundaries, compiled force model"),
        "earth_orientation": "IAU 2006/2000A, EOP of astropy-iers-data",
    }


def simulate_truth_orbit(t_start, t_end, *, seed: int, step_s: float = 10.0,
                         altitude_m: float = HY2B_ALTITUDE_M, ltan_h: float = HY2B_LTAN_H,
                         inclination_deg: float | None = None, u0_deg: float = 0.0,
                         dynamics: TruthDynamics | None = None,
                         models: Mapping[str, object] | None = None,
                         integrator_step_s: float = DEFAULT_STEP_S,
                         eop: EarthOrientation | None = None,
                         state0: np.ndarray | None = None,
                         manoeuvres: Sequence[Manoeuvre] = (),
                         common_seed: int | None = None,
                         correlation: float = 0.0) -> xr.Dataset:
    """Integrate the truth orbit over [t_start, t_end] (module docstring).

    Parameters
    ----------
    t_start, t_end : datetime64
        Arc (GPS-time labels); the initial state is at ``t_start``.
    seed : int
        Seed of the random truth parameters
        (:func:`leopod.simulate.truth_forces.truth_force_config`).
    step_s : float
        Output sampling [s]; epochs ``t_start + k step_s`` up to ``t_end``.
    altitude_m, ltan_h, inclination_deg, u0_deg
        Initial orbit (:func:`initial_state_sun_synchronous`).
    dynamics : TruthDynamics, optional
        Force settings.
    models : mapping, optional
        Model files (:func:`leopod.simulate.truth_forces.truth_force_config`).
    integrator_step_s : float
        Gauss–Jackson step [s] (5 s resolves a degree-150 field even at 400 km).
    eop : EarthOrientation, optional
        EOP (default: installed IERS data).
    state0 : ndarray, shape (6,), optional
        GCRF initial state at ``t_start`` [m, m/s] instead of the one of the orbit keys (a
        formation follower, :func:`leopod.simulate.formation.follower_initial_state`).
    manoeuvres : sequence of Manoeuvre
        Burns (constant RTN accelerations) added to the stochastic accelerations
        (:func:`leopod.simulate.manoeuvres.with_manoeuvres`), listed in the variables
        ``manoeuvre_start``, ``manoeuvre_end`` and ``manoeuvre_acc_rtn_m_s2``.
    common_seed : int, optional
        Seed of the random field a formation shares (its leader's ``seed``), mixed with this
        satellite's own draws with ``correlation`` (ρ in [0, 1];
        :func:`leopod.simulate.truth_forces.truth_force_config`); None: own draws only.
    correlation : float
        ρ of that mix (attributes ``truth_common_seed`` and ``truth_correlation``).

    Returns
    -------
    xarray.Dataset
        Coordinates ``time`` (GPS), ``xyz``, ``rtn``, ``drag_interval_start`` and
        ``stochastic_interval_start`` (GPS); variables ``pos_gcrf_m``, ``vel_gcrf_m_s``,
        ``pos_itrf_m``, ``vel_itrf_m_s`` (time, xyz), ``drag_scale`` (drag_interval_start),
        ``stochastic_acc_rtn_m_s2`` (stochastic_interval_start, rtn); attributes describing
        the initial orbit and the forces. Ready for :func:`leopod.io.netcdf.write_netcdf`.
    """
    t0 = np.datetime64(t_start, "ns")
    span_s = float(seconds_since(np.datetime64(t_end, "ns"), t0))
    if not span_s > 0.0 or not step_s > 0.0:
        raise ValueError(f"need t_end > t_start and step_s > 0 (got {t_start}, {t_end}, "
                         f"{step_s})")
    dyn = TruthDynamics.from_config({}) if dynamics is None else dynamics
    forces = truth_force_config(span_s, seed=seed, dynamics=dyn, models=models,
                                common_seed=common_seed, correlation=correlation)
    model = build_force_model(ForceModelSettings.from_config(forces.config), t0, 0.0, span_s, eop=eop)
    model, params = with_manoeuvres(model, forces.parameter_vector(model), manoeuvres, t0)
    if state0 is None:
        state0 = initial_state_sun_synchronous(t0, altitude_m, ltan_h,
                                               inclination_deg=inclination_deg, u0_deg=u0_deg)
    t_out = step_s * np.arange(int(np.floor(span_s / step_s + 1e-9)) + 1)
    clock = _time.perf_counter()
    drag = np.array([name.startswith("drag_scale") for name in model.parameters])
    model.follow(circular_orbit(0.0, state0))      # a density table, unused: drag scales 0
    first = integrate(model, 0.0, state0, np.where(drag, 0.0, params), t_out,
                      step_s=2 * integrator_step_s, with_partials=False)
    model.follow(first.positions)
    traj = integrate(model, 0.0, state0, params, t_out, step_s=integrator_step_s,
                     with_partials=False)
    log.info("truth orbit %s + %.1f h: %d force evaluations, %.1f s", t0, span_s / 3600.0,
             traj.n_evaluations, _time.perf_counter() - clock)
    times = from_seconds(t_out, t0)
    pos, vel = traj.states[:, :3], traj.states[:, 3:]
    pos_ef, vel_ef = gcrf_to_itrf(times, pos, vel, eop=eop)
    h = intermediate_to_gcrf_matrix(t0).T @ np.cross(state0[:3], state0[3:])
    attrs = {
        "title": "leopod truth orbit (closed-loop simulator)", "time_system": "GPS",
        "arc_start": str(t0), "arc_end": str(np.datetime64(t_end, "ns")), "seed": int(seed),
        "altitude_m": float(altitude_m), "ltan_h": float(ltan_h),
        "inclination_cip_equator_deg": float(np.degrees(np.arccos(h[2] / np.linalg.norm(h)))),
        "raan_from_cio_deg": float(np.degrees(np.arctan2(h[0], -h[1])) % 360.0),
        "u0_deg": float(u0_deg), "initial_state_gcrf_m_m_s": state0,
        **_force_attrs(forces, dyn, integrator_step_s),
    }
    if common_seed is not None:
        attrs.update({"truth_common_seed": int(common_seed),
                      "truth_correlation": float(correlation)})
    gcrf, itrf = "GCRF (IERS 2010)", "ITRF (IERS 2010, EOP)"
    variables = {
        "pos_gcrf_m": _vector(pos, "m", gcrf, "true centre-of-mass position"),
        "vel_gcrf_m_s": _vector(vel, "m s-1", gcrf, "true inertial velocity"),
        "pos_itrf_m": _vector(pos_ef, "m", itrf, "true centre-of-mass position"),
        "vel_itrf_m_s": _vector(vel_ef, "m s-1", itrf, "true Earth-fixed velocity"),
        "drag_scale": (("drag_interval_start",), forces.drag_scale,
                       {"units": "1", "long_name": "true drag scale factor per interval "
                                                   "(from its start to the next start)"}),
        "stochastic_acc_rtn_m_s2": (("stochastic_interval_start", "rtn"),
                                    forces.stochastic_acc_rtn_m_s2,
                                    {"units": "m s-2", "long_name": "true unmodelled "
                                     "acceleration in R, T, N per interval"}),
        "manoeuvre_start": ("manoeuvre", np.array([m.start for m in manoeuvres],
                                                  dtype="datetime64[ns]"),
                            {"long_name": "start of the burn (GPS)"}),
        "manoeuvre_end": ("manoeuvre", np.array([m.end for m in manoeuvres],
                                                dtype="datetime64[ns]"),
                          {"long_name": "end of the burn (GPS)"}),
        "manoeuvre_acc_rtn_m_s2": (("manoeuvre", "rtn"),
                                   np.array([m.acc_rtn_m_s2 for m in manoeuvres],
                                            dtype=float).reshape(-1, 3),
                                   {"units": "m s-2", "long_name": "constant thrust "
                                    "acceleration of the burn in R, T, N"}),
    }
    coords = {"time": times, "xyz": _XYZ, "rtn": _RTN,
              "drag_interval_start": from_seconds(forces.drag_edges_s[:-1], t0),
              "stochastic_interval_start": from_seconds(forces.stochastic_edges_s[:-1], t0)}
    return xr.Dataset(variables, coords=coords, attrs=attrs)


def _vector(values: np.ndarray, units: str, frame: str, long_name: str) -> tuple:
    """A (time, xyz) variable with its attributes."""
    return ("time", "xyz"), values, {"units": units, "long_name": long_name,
                                     "reference_frame": frame}


def write_truth_files(ds: xr.Dataset, sp3_path, nc_path, sat_id: str) -> None:
    """Write a truth orbit as SP3-d (ITRF position and velocity, every epoch) and netCDF.

    SP3-d stores positions in km with 6 decimals (1 mm) and velocities in dm/s with 6
    decimals (1e-7 m/s): the SP3 orbit equals the netCDF one to ≤ 0.5 mm per coordinate
    (≤ 0.87 mm in 3D) and ≤ 5e-8 m/s; the netCDF file is lossless.

    Parameters
    ----------
    ds : xarray.Dataset
        From :func:`simulate_truth_orbit`.
    sp3_path, nc_path : path
        Output files.
    sat_id : str
        Three-character SP3 satellite id (e.g. ``"L01"``).
    """
    sp3 = xr.Dataset({"pos_m": (("time", "sv", "xyz"), ds["pos_itrf_m"].values[:, None, :]),
                      "vel_m_s": (("time", "sv", "xyz"), ds["vel_itrf_m_s"].values[:, None, :])},
                     coords={"time": ds["time"].values, "sv": [sat_id], "xyz": _XYZ},
                     attrs={"time_system": "GPS"})
    write_sp3(sp3, sp3_path, agency="SIM", orbit_type="FIT", coordinate_system="ITRF",
              comments=(f"leopod truth orbit of {sat_id}, centre of mass, seed {ds.attrs['seed']}",
                        (f"gravity {ds.attrs['gravity_field']} to degree "
                         f"{ds.attrs['gravity_max_degree']}, NRLMSISE-00 drag, SRP, tides"),
                        "random drag scale per interval and stochastic RTN accelerations"))
    write_netcdf(ds, nc_path, step="simulate", time_system="GPS",
                 reference_frame="GCRF and ITRF (per variable)",
                 title=f"leopod truth orbit {sat_id}")

"""SLR residuals of a LEO orbit: station reference points, normal-point model, screening.

Why one module of 627 lines: station reference points, range model, screening and the residual
Dataset are one pass over the normal points sharing SlrResidualSettings and the rejection codes;
the statistics are in leopod.validation.slr_statistics.

For every CRD normal point the one-way range ``c · tof / 2`` (observed; ILRS normal points
are calibrated for the station system delay) is compared with the computed range of
:func:`leopod.validation.slr_model.slr_range`:

* station: SINEX position + velocity at the epoch (SLRF2014/2020,
  :func:`leopod.io.sinex.station_position`), plus the ILRS eccentricity from the marker to
  the system reference point (UNE rotated to the ITRF with the geodetic latitude and
  longitude of the station, or XYZ as given), plus the displacements of
  :mod:`leopod.validation.station_displacement` (solid Earth tide, pole tide, and ocean
  loading when BLQ coefficients are given) at the transmit epoch (their change over the
  < 50 ms of a pass of light is < 1 µm);
* satellite: the POD orbit (centre of mass, ITRF) plus the retro-reflector offset rotated by
  the nominal attitude (:class:`leopod.validation.slr_model.OrbitReflector`);
* two-way light time with Earth rotation, Mendes–Pavlis troposphere with FCULa mapping at the
  normal point's meteorological data, Shapiro delay (:func:`slr_range`).

Epochs: CRD epochs are UTC (converted with :func:`leopod.time.scales.utc_to_gps`), the
ground transmit time for epoch event 2; for event 1 (spacecraft bounce time) the transmit
epoch is ``t_b − τ_up`` solved by iteration, for event 0 (ground receive time) it is
``t_r − tof``. Points whose CRD flags say the tropospheric refraction is already applied get
no modelled troposphere; points with the centre-of-mass correction applied are modelled at
the centre of mass (no reflector offset).

Residual = observed − computed. Each model term is stored separately as its contribution to
the computed one-way range: the troposphere and Shapiro delays, and the projections
``−û·d`` of the station displacements d and of the eccentricity, ``+û·o`` of the reflector
offset o (û the unit line of sight from the station to the reflector). The projections are
first-order: they leave out the coupling through the light time (relative |ρ̇|/c < 2.5e-5,
< 0.1 mm for a 3-m eccentricity) and d²/(2ρ) (< 0.01 mm); the computed range itself is
exact.

Screening (:class:`SlrResidualSettings`), in this order: model failures (no orbit at the
epoch, station not in the SINEX file, no eccentricity, unsupported epoch event or range
type, missing meteorological data), elevation below the cut-off, |residual| above a hard
limit (BDS SCB-AR paper: 0.5 m), and |residual − median| > k · robust sigma per satellite and UTC
day (robust sigma = 1.4826 · median absolute deviation, not below a floor). ``flag`` holds
the reason code of :data:`REJECTION_REASONS` (0 = used).

Statistics of the residuals (per station, per elevation bin, RTN projection) are in
:mod:`leopod.validation.slr_statistics`.
"""

from __future__ import annotations

import logging
from dataclasses import asdict, dataclass

import erfa
import numpy as np
import xarray as xr

from leopod.astro.ephemeris import Ephemeris
from leopod.constants import C_LIGHT_M_S, OMEGA_EARTH_RAD_S, WGS84_A_M, WGS84_INV_F
from leopod.frames.leo_attitude import LeoAttitude
from leopod.frames.rtn import rtn_matrix
from leopod.io.sinex import station_eccentricities, station_positions
from leopod.settings import Settings
from leopod.time.eop import EarthOrientation
from leopod.time.scales import utc_to_gps
from leopod.validation.slr_model import OrbitReflector, SlrRange, slr_range, two_way_light_time
from leopod.validation.station_displacement import station_displacements

__all__ = [
    "REJECTION_REASONS",
    "SlrResidualSettings",
    "line_of_sight_orbit_difference",
    "slr_residuals",
    "station_reference_points",
]

logger = logging.getLogger(__name__)

#: Reason codes of the ``flag`` variable (0 = used).
REJECTION_REASONS = {
    0: "used",
    1: "no_orbit",
    2: "no_station",
    3: "no_eccentricity",
    4: "epoch_event",
    5: "range_type",
    6: "no_meteo",
    7: "elevation",
    8: "hard_limit",
    9: "outlier",
}
_CODE = {name: code for code, name in REJECTION_REASONS.items()}
#: CRD epoch events (record 11 field 4) this module handles: 0 ground receive, 1 spacecraft
#: bounce, 2 ground transmit time (CRD 1.01 and 2.01, record 11 field "epoch event").
_RECEIVE, _BOUNCE, _TRANSMIT = 0, 1, 2
#: CRD H4 range type of two-way ranges.
_TWO_WAY = 2
#: Scale of the median absolute deviation to the standard deviation of a normal distribution.
_MAD_TO_SIGMA = 1.4826
#: Transmit epochs kept before the last orbit epoch [s] (> two-way light time of a LEO).
_END_MARGIN_S = 0.1
_NS_PER_DAY = 86_400_000_000_000
_RTN = ["R", "T", "N"]
_XYZ = ["x", "y", "z"]


@dataclass(frozen=True)
class SlrResidualSettings(Settings):
    """Model switches and screening thresholds of :func:`slr_residuals`.

    Attributes
    ----------
    elevation_cut_off_deg : float
        Lowest elevation of a used normal point [deg] (10° is usual for LEO SLR validation).
    hard_limit_m : float
        Reject |residual| above this [m] (BDS SCB-AR paper: outliers exceeding 0.5 m are excluded).
    outlier_k : float
        Reject |residual − median| > k · robust sigma per satellite and UTC day.
    outlier_min_sigma_m : float
        Floor of the robust sigma [m] (keeps noise-free or very consistent days from being
        trimmed at the millimetre level).
    outlier_min_points : int
        No outlier test on groups with fewer used points.
    troposphere, relativity, solid_tide, pole_tide : bool
        Model switches (Mendes–Pavlis/FCULa, Shapiro, IERS 2010 sec. 7.1.1, 7.1.4).
    default_wavelength_nm : float
        Laser wavelength where the CRD configuration gives none [nm].
    interpolation_order : int
        Lagrange order of the orbit interpolation.
    """

    SCHEMA_DEF = "slr_validation"

    elevation_cut_off_deg: float
    hard_limit_m: float
    outlier_k: float
    outlier_min_sigma_m: float
    outlier_min_points: int
    troposphere: bool
    relativity: bool
    solid_tide: bool
    pole_tide: bool
    default_wavelength_nm: float
    interpolation_order: int


# ------------------------------------------------------------------------------ stations
def _ecc_to_itrf(ecc_m: np.ndarray, system: str, pos_m: np.ndarray) -> np.ndarray:
    """Eccentricity (3,) in UNE (geodetic up, north, east) or XYZ as an ITRF vector (3,)."""
    if system == "XYZ":
        return ecc_m
    lon, lat, _ = erfa.gc2gde(WGS84_A_M, 1.0 / WGS84_INV_F, pos_m)
    up = np.array([np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)])
    north = np.array([-np.sin(lat) * np.cos(lon), -np.sin(lat) * np.sin(lon), np.cos(lat)])
    east = np.array([-np.sin(lon), np.cos(lon), 0.0])
    return ecc_m[0] * up + ecc_m[1] * north + ecc_m[2] * east


_STATION_VARIABLES = ("site", "pos_m", "vel_m_y", "ref_epoch", "valid_from", "valid_to")
_ECCENTRICITY_VARIABLES = ("site", "ecc_m", "ref_system", "valid_from", "valid_to")


def _require(ds: xr.Dataset | None, names: tuple, what: str) -> None:
    missing = [] if ds is None else [name for name in names if name not in ds.variables]
    if missing:
        raise ValueError(f"{what} lacks the variables {missing}")


def _station_points(sites: np.ndarray, epochs_utc: np.ndarray, stations: xr.Dataset,
                    eccentricities: xr.Dataset | None, flag: np.ndarray):
    """Marker positions and eccentricities (n, 3) of the normal points; flags failures."""
    _require(stations, _STATION_VARIABLES, "the station Dataset (read_sinex_stations)")
    _require(eccentricities, _ECCENTRICITY_VARIABLES,
             "the eccentricity Dataset (read_sinex_eccentricities)")
    marker = station_positions(stations, sites, epochs_utc)
    ecc = np.zeros_like(marker)
    no_station = np.isnan(marker[:, 0])
    flag[no_station] = _CODE["no_station"]
    if eccentricities is None:
        return marker, ecc
    values, systems = station_eccentricities(eccentricities, sites, epochs_utc)
    flag[~no_station & (systems == "")] = _CODE["no_eccentricity"]
    for i in np.flatnonzero(~no_station & (systems != "")):
        ecc[i] = _ecc_to_itrf(values[i], systems[i], marker[i])
    return marker, ecc


def _blq_coefficients(pads: np.ndarray, names: np.ndarray, ocean_loading: xr.Dataset | None):
    """Per-point BLQ amplitudes and phases (n, 3, 11), NaN for stations not in the file.

    A station is looked up by its CDP pad id, then by its CRD station name.
    """
    if ocean_loading is None:
        return None, None
    n = pads.size
    amp = np.full((n, 3, 11), np.nan)
    phase = np.full((n, 3, 11), np.nan)
    known = set(ocean_loading["site"].values.tolist())
    missing = set()
    for i, (pad, name) in enumerate(zip(pads, names)):
        key = next((k for k in (str(pad).upper(), str(name).upper()) if k in known), None)
        if key is None:
            missing.add(str(pad))
            continue
        amp[i] = ocean_loading["amplitude_m"].sel(site=key).values
        phase[i] = ocean_loading["phase_deg"].sel(site=key).values
    if missing:
        logger.warning("no ocean loading coefficients for stations %s: not applied",
                       sorted(missing))
    return amp, phase


def station_reference_points(normal_points: xr.Dataset, stations: xr.Dataset,
                             eccentricities: xr.Dataset | None = None, *,
                             settings: SlrResidualSettings,
                             ocean_loading: xr.Dataset | None = None,
                             eop: EarthOrientation | None = None,
                             ephemeris: Ephemeris | None = None) -> xr.Dataset:
    """Ranging reference points of the stations at the epochs of normal points.

    ``marker (SINEX position + velocity at the epoch) + eccentricity + solid Earth tide +
    pole tide + ocean loading``, the displacements evaluated at the CRD epoch (a transmit,
    bounce or receive epoch: they differ by < 50 ms, in which the displacements change by
    < 1 µm).

    Parameters
    ----------
    normal_points : xarray.Dataset
        Dimension ``point`` with ``time`` (UTC) and ``station`` (CDP pad id); ``station_name``
        is used to find BLQ sites.
    stations, eccentricities, ocean_loading, eop, ephemeris
        As in :func:`slr_residuals`.
    settings : SlrResidualSettings
        Its ``solid_tide`` and ``pole_tide`` switches are used.

    Returns
    -------
    xarray.Dataset
        Dimension ``point``: ``pos_marker_itrf_m``, ``eccentricity_itrf_m``,
        ``solid_tide_itrf_m``, ``pole_tide_itrf_m``, ``ocean_loading_itrf_m``,
        ``pos_station_itrf_m`` (point, xyz) [m] and ``flag`` (0, or 2 = station not in the
        SINEX file at the epoch, 3 = no eccentricity; :data:`REJECTION_REASONS`). Rows with
        a non-zero flag are NaN.

    Raises
    ------
    ValueError
        If ``stations`` or ``eccentricities`` lack variables of their reader's schema.
    """
    n = normal_points.sizes["point"]
    flag = np.zeros(n, dtype=np.int8)
    epochs_utc = normal_points["time"].values.astype("datetime64[ns]")
    marker, ecc = _station_points(normal_points["station"].values.astype(str), epochs_utc,
                                  stations, eccentricities, flag)
    ok = np.flatnonzero(flag == 0)
    names = normal_points["station_name"] if "station_name" in normal_points.variables \
        else normal_points["station"]
    blq_amp, blq_phase = _blq_coefficients(normal_points["station"].values[ok],
                                           names.values[ok], ocean_loading)
    disp = station_displacements(utc_to_gps(epochs_utc[ok]) if ok.size else epochs_utc[ok],
                                 marker[ok] + ecc[ok], eop=eop, ephemeris=ephemeris,
                                 solid_tide=settings.solid_tide,
                                 pole_tide=settings.pole_tide, blq_amplitude_m=blq_amp,
                                 blq_phase_deg=blq_phase)
    parts = {"pos_marker_itrf_m": (marker[ok], "SINEX marker position at the epoch"),
             "eccentricity_itrf_m": (ecc[ok], "eccentricity marker to reference point"),
             "solid_tide_itrf_m": (disp.solid_tide_m, "solid Earth tide displacement"),
             "pole_tide_itrf_m": (disp.pole_tide_m, "pole tide displacement"),
             "ocean_loading_itrf_m": (disp.ocean_loading_m, "ocean loading displacement"),
             "pos_station_itrf_m": (marker[ok] + ecc[ok] + disp.total_m,
                                    "reference point incl. displacements")}
    data = {}
    for name, (values, title) in parts.items():
        full = np.full((n, 3), np.nan)
        full[ok] = values
        data[name] = (("point", "xyz"), full, {"units": "m", "long_name": title,
                                                "reference_frame": "ITRF"})
    data["flag"] = ("point", flag, {"units": "1", "long_name": "0 ok, 2 no station, "
                                    "3 no eccentricity"})
    return xr.Dataset(data, coords={"time": ("point", epochs_utc), "xyz": _XYZ})


# ------------------------------------------------------------------------------ modelling
def _transmit_seconds(t_event_s: np.ndarray, event: np.ndarray, tof_s: np.ndarray,
                      sta: np.ndarray, reflector: OrbitReflector) -> np.ndarray:
    """Transmit epochs [s on the reflector's axis] from the epochs of the CRD epoch event."""
    t = np.where(event == _RECEIVE, t_event_s - tof_s, t_event_s)
    bounce = event == _BOUNCE
    if np.any(bounce):
        t_b = t_event_s[bounce]
        guess = t_b - 0.5 * tof_s[bounce]
        for _ in range(2):  # each step shrinks the bounce-epoch error by ~|ρ̇|/c ≈ 3e-5
            tau_up = two_way_light_time(guess, sta[bounce], reflector).tau_up_s
            guess = guess - (guess + tau_up - t_b)
        t[bounce] = guess
    return t


def _model(idx: np.ndarray, t_s: np.ndarray, sta: np.ndarray, nps: xr.Dataset,
           reflector: OrbitReflector, settings: SlrResidualSettings) -> SlrRange:
    """:func:`slr_range` of the points ``idx``."""
    wavelength = nps["wavelength_nm"].values[idx].astype(float)
    wavelength = np.where(np.isfinite(wavelength), wavelength, settings.default_wavelength_nm)
    meteo = {}
    if settings.troposphere:
        meteo = {k: nps[k].values[idx] for k in ("pressure_hpa", "temperature_k",
                                                 "humidity_pct")}
    return slr_range(t_s[idx], sta[idx], reflector, wavelength_um=wavelength * 1e-3,
                     relativity=settings.relativity, **meteo)


def _line_of_sight_rtn(reflector: OrbitReflector, t_bounce_s: np.ndarray,
                       unit_los: np.ndarray) -> np.ndarray:
    """Unit lines of sight (n, 3) in the RTN axes of the centre-of-mass orbit at bounce.

    RTN from the position and the inertial velocity ``v_ef + ω × r`` in Earth-fixed axes
    (the radial, along-track and cross-track axes of the inertial orbit).
    """
    pos, vel = reflector.centre_of_mass(t_bounce_s)
    vel_inertial = vel + np.cross([0.0, 0.0, OMEGA_EARTH_RAD_S], pos)
    return np.einsum("nij,nj->ni", rtn_matrix(pos, vel_inertial), unit_los)


#: Optional CRD variables and the value assumed where a Dataset lacks them.
_DEFAULTS = {"epoch_event": _TRANSMIT, "range_type": _TWO_WAY, "refraction_applied": 0,
             "com_applied": 0, "wavelength_nm": np.nan, "pressure_hpa": np.nan,
             "temperature_k": np.nan, "humidity_pct": np.nan, "satellite": "", "pass_id": -1}


def _with_defaults(nps: xr.Dataset) -> xr.Dataset:
    """``nps`` with every optional CRD variable present (module constant ``_DEFAULTS``)."""
    missing = [name for name in ("tof_s", "station") if name not in nps.variables]
    if missing:
        raise ValueError(f"normal points lack the variables {missing} (schema of "
                         "leopod.io.crd.read_crd)")
    n = nps.sizes["point"]
    add = {name: ("point", np.full(n, value)) for name, value in _DEFAULTS.items()
           if name not in nps.variables}
    if "station_name" not in nps.variables:
        add["station_name"] = ("point", nps["station"].values.astype(str))
    return nps.assign(add)


def slr_residuals(orbit: xr.Dataset, normal_points: xr.Dataset, stations: xr.Dataset,
                  eccentricities: xr.Dataset | None = None, *, retro_offset_body_m,
                  settings: SlrResidualSettings,
                  ocean_loading: xr.Dataset | None = None, eop: EarthOrientation | None = None,
                  ephemeris: Ephemeris | None = None,
                  attitude: LeoAttitude | None = None) -> xr.Dataset:
    """SLR residuals of a LEO orbit, one per normal point, screened.

    Parameters
    ----------
    orbit : xarray.Dataset
        POD orbit: coordinate ``time`` (datetime64[ns], GPS time), ``pos_itrf_m`` and
        ``vel_itrf_m_s`` (time, xyz), centre of mass in the ITRF [m, m/s]
        (:func:`leopod.estimation.outputs.orbit_dataset`).
    normal_points : xarray.Dataset
        Normal points of this satellite (:func:`leopod.io.crd.read_crd`, dimension
        ``point``, UTC epochs).
    stations : xarray.Dataset
        Station coordinates and velocities (:func:`leopod.io.sinex.read_sinex_stations`).
    eccentricities : xarray.Dataset, optional
        ILRS eccentricities (:func:`leopod.io.sinex.read_sinex_eccentricities`); None: the
        SINEX positions are taken as the reference points.
    retro_offset_body_m : array_like, shape (3,)
        Retro-reflector offset from the centre of mass in the body frame [m].
    settings : SlrResidualSettings
        Model switches and screening (config ``validation.slr``).
    ocean_loading : xarray.Dataset, optional
        BLQ coefficients (:func:`leopod.io.blq.read_blq`); sites are matched by pad id,
        then by station name.
    eop : EarthOrientation, optional
        EOP for the station displacements (default: installed IERS data).
    ephemeris : Ephemeris, optional
        Sun and Moon for the solid Earth tide (default DE421).
    attitude : LeoAttitude, optional
        Attitude law of the satellite that orients the reflector offset; None: nominal.

    Returns
    -------
    xarray.Dataset
        Dimension ``point`` (order of ``normal_points``), coordinates ``time`` (CRD epoch,
        UTC), ``xyz`` and ``rtn``; variables ``time_transmit_gps``, ``station``,
        ``station_name``, ``satellite``, ``pass_id``, ``elevation_deg``,
        ``observed_range_m``, ``computed_range_m``, ``residual_m`` (observed − computed,
        one way), the computed-range terms ``geometric_range_m``, ``tropo_delay_m``,
        ``relativity_delay_m``, ``solid_tide_range_m``, ``pole_tide_range_m``,
        ``ocean_loading_range_m``, ``eccentricity_range_m``, ``reflector_offset_range_m``,
        ``pos_station_itrf_m`` (point, xyz) (reference point incl. displacements),
        ``los_rtn`` (point, rtn) (unit line of sight station → satellite in the orbit's RTN
        axes), ``flag`` (:data:`REJECTION_REASONS`) and ``reason``. Values are NaN where the
        model could not be evaluated (flags 1–6).

    Raises
    ------
    ValueError
        If ``normal_points`` lacks ``tof_s`` or ``station`` (other CRD variables default to
        epoch event 2, two-way ranges, no corrections applied, no meteorological data).
    """
    nps = _with_defaults(normal_points)
    n = nps.sizes["point"]
    epochs_utc = nps["time"].values.astype("datetime64[ns]")
    event = nps["epoch_event"].values.astype(int)
    tof = nps["tof_s"].values.astype(float)

    points = station_reference_points(nps, stations, eccentricities, settings=settings,
                                      ocean_loading=ocean_loading, eop=eop,
                                      ephemeris=ephemeris)
    flag = points["flag"].values.copy()
    flag[(flag == 0) & ~np.isin(event, (_RECEIVE, _BOUNCE, _TRANSMIT))] = _CODE["epoch_event"]
    flag[(flag == 0) & (nps["range_type"].values != _TWO_WAY)] = _CODE["range_type"]

    reflector = OrbitReflector(orbit, retro_offset_body_m, order=settings.interpolation_order,
                               attitude=attitude)
    t_event_s = reflector.seconds(utc_to_gps(epochs_utc)) if n else np.zeros(0)
    t_last_s = reflector.t_nodes_s[-1] - _END_MARGIN_S
    flag[(flag == 0) & ((t_event_s - tof < 0.0) | (t_event_s + tof > t_last_s))] = \
        _CODE["no_orbit"]

    refraction_applied = nps["refraction_applied"].values == 1
    if settings.troposphere:
        no_met = ~np.isfinite(nps["pressure_hpa"].values + nps["temperature_k"].values
                              + nps["humidity_pct"].values) & ~refraction_applied
        flag[(flag == 0) & no_met] = _CODE["no_meteo"]
    ok = np.flatnonzero(flag == 0)
    sta = points["pos_station_itrf_m"].values

    out = _empty_columns(n)
    com = nps["com_applied"].values == 1
    reflectors = {False: reflector,
                  True: OrbitReflector(orbit, np.zeros(3), order=settings.interpolation_order)}
    for at_com, refl in reflectors.items():
        idx = ok[com[ok] == at_com]
        if idx.size:
            _fill_model(out, idx, refl, t_event_s, event, tof, sta, nps, settings,
                        refraction_applied)
    for name, part in (("solid_tide_range_m", "solid_tide_itrf_m"),
                       ("pole_tide_range_m", "pole_tide_itrf_m"),
                       ("ocean_loading_range_m", "ocean_loading_itrf_m"),
                       ("eccentricity_range_m", "eccentricity_itrf_m")):
        out[name][ok] = -np.einsum("ni,ni->n", out["unit_los"][ok], points[part].values[ok])
    flag[(flag == 0) & ~np.isfinite(out["residual_m"])] = _CODE["no_orbit"]
    _screen(out["residual_m"], out["elevation_deg"], epochs_utc,
            nps["satellite"].values.astype(str), flag, settings)
    ds = _dataset(nps, out, _gps_times(reflector, out["time_transmit_s"]), sta, flag,
                  settings)
    _log_summary(ds)
    return ds


def _empty_columns(n: int) -> dict:
    names = ("time_transmit_s", "elevation_deg", "observed_range_m", "computed_range_m",
             "residual_m", "geometric_range_m", "tropo_delay_m", "relativity_delay_m",
             "solid_tide_range_m", "pole_tide_range_m", "ocean_loading_range_m",
             "eccentricity_range_m", "reflector_offset_range_m")
    out = {name: np.full(n, np.nan) for name in names}
    out["unit_los"] = np.full((n, 3), np.nan)
    out["los_rtn"] = np.full((n, 3), np.nan)
    return out


def _fill_model(out: dict, idx: np.ndarray, reflector: OrbitReflector, t_event_s, event, tof,
                sta, nps, settings: SlrResidualSettings, refraction_applied) -> None:
    """Model the points ``idx`` with one reflector and write their columns into ``out``."""
    t_s = np.full(t_event_s.shape, np.nan)
    t_s[idx] = _transmit_seconds(t_event_s[idx], event[idx], tof[idx], sta[idx], reflector)
    model = _model(idx, t_s, sta, nps, reflector, settings)
    lt = model.light_time
    tropo = np.where(refraction_applied[idx], 0.0, model.tropo_m)
    unit = lt.los_up_m / np.linalg.norm(lt.los_up_m, axis=1, keepdims=True)
    t_bounce = t_s[idx] + lt.tau_up_s
    com, _ = reflector.centre_of_mass(t_bounce)
    out["time_transmit_s"][idx] = t_s[idx]
    out["elevation_deg"][idx] = np.degrees(model.elevation_rad)
    out["observed_range_m"][idx] = 0.5 * C_LIGHT_M_S * tof[idx]
    out["geometric_range_m"][idx] = model.geometric_range_m
    out["tropo_delay_m"][idx] = tropo
    out["relativity_delay_m"][idx] = model.relativity_m
    out["computed_range_m"][idx] = model.geometric_range_m + tropo + model.relativity_m
    out["residual_m"][idx] = out["observed_range_m"][idx] - out["computed_range_m"][idx]
    out["reflector_offset_range_m"][idx] = np.einsum("ni,ni->n", unit,
                                                     lt.pos_reflector_m - com)
    out["unit_los"][idx] = unit
    out["los_rtn"][idx] = _line_of_sight_rtn(reflector, t_bounce, unit)


def line_of_sight_orbit_difference(residuals: xr.Dataset, orbit: xr.Dataset,
                                   reference: xr.Dataset, *, order: int = 10) -> xr.DataArray:
    """Range residuals that the difference of two orbits explains: ``−e · (orbit − reference)``.

    If ``reference`` is the true orbit (simulation) and ``residuals`` those of ``orbit``,
    the residuals minus this are the measurement noise and model errors; for two solutions
    it is the change of the residuals between them. Evaluated at the transmit epochs (the
    difference changes by < 1 µm during the light time), with the lines of sight of
    ``residuals``.

    Parameters
    ----------
    residuals : xarray.Dataset
        From :func:`slr_residuals` (``time_transmit_gps``, ``los_rtn``).
    orbit, reference : xarray.Dataset
        Orbits with ``time`` (GPS), ``pos_itrf_m`` and ``vel_itrf_m_s`` (time, xyz).
    order : int
        Lagrange interpolation order.

    Returns
    -------
    xarray.DataArray
        Dimension ``point`` [m]; NaN where either orbit or the line of sight is missing.
    """
    t = residuals["time_transmit_gps"].values.astype("datetime64[ns]")
    ok = ~np.isnat(t)
    a, b = (OrbitReflector(o, np.zeros(3), order=order) for o in (orbit, reference))
    out = np.full(t.size, np.nan)
    if ok.any():
        pos_a, vel_a = a.centre_of_mass(a.seconds(t[ok]))
        pos_b, _ = b.centre_of_mass(b.seconds(t[ok]))
        rtn = rtn_matrix(pos_a, vel_a + np.cross([0.0, 0.0, OMEGA_EARTH_RAD_S], pos_a))
        diff_rtn = np.einsum("nij,nj->ni", rtn, pos_a - pos_b)
        los = residuals["los_rtn"].transpose("point", "rtn").values[ok]
        out[ok] = -np.einsum("ni,ni->n", los, diff_rtn)
    return xr.DataArray(out, dims="point", attrs={
        "units": "m", "long_name": "orbit minus reference projected on the line of sight, "
        "with the sign of a range residual"})


# ------------------------------------------------------------------------------ screening
def _screen(residual: np.ndarray, elevation_deg: np.ndarray, epochs_utc: np.ndarray,
            satellite: np.ndarray, flag: np.ndarray, settings: SlrResidualSettings) -> None:
    """Elevation cut-off, hard limit and robust outlier test; updates ``flag`` in place."""
    flag[(flag == 0) & (elevation_deg < settings.elevation_cut_off_deg)] = _CODE["elevation"]
    flag[(flag == 0) & (np.abs(residual) > settings.hard_limit_m)] = _CODE["hard_limit"]
    day = epochs_utc.astype(np.int64) // _NS_PER_DAY
    used = flag == 0
    for sat in np.unique(satellite[used]):
        for d in np.unique(day[used & (satellite == sat)]):
            group = np.flatnonzero(used & (satellite == sat) & (day == d))
            if group.size < settings.outlier_min_points:
                continue
            values = residual[group]
            median = np.median(values)
            sigma = max(_MAD_TO_SIGMA * np.median(np.abs(values - median)),
                        settings.outlier_min_sigma_m)
            flag[group[np.abs(values - median) > settings.outlier_k * sigma]] = \
                _CODE["outlier"]


# ------------------------------------------------------------------------------ output
def _gps_times(reflector: OrbitReflector, t_s: np.ndarray) -> np.ndarray:
    """GPS epochs (datetime64[ns]) of seconds on the reflector's axis; NaT where NaN."""
    ok = np.isfinite(t_s)
    out = np.full(t_s.shape, np.datetime64("NaT"), dtype="datetime64[ns]")
    out[ok] = reflector.t0 + np.round(t_s[ok] * 1e9).astype("timedelta64[ns]")
    return out


def _dataset(nps: xr.Dataset, out: dict, t_gps: np.ndarray, sta: np.ndarray, flag: np.ndarray,
             settings: SlrResidualSettings) -> xr.Dataset:
    def var(values, units, title, dims=("point",)):
        attrs = {"long_name": title} if units is None else {"units": units, "long_name": title}
        return dims, values, attrs

    range_terms = {
        "geometric_range_m": "vacuum one-way range incl. displacements and offsets",
        "tropo_delay_m": "Mendes-Pavlis/FCULa tropospheric delay (one way)",
        "relativity_delay_m": "Shapiro delay (one way)",
        "solid_tide_range_m": "range change by the solid Earth tide displacement",
        "pole_tide_range_m": "range change by the pole tide displacement",
        "ocean_loading_range_m": "range change by the ocean loading displacement",
        "eccentricity_range_m": "range change by the station eccentricity",
        "reflector_offset_range_m": "range change by the retro-reflector offset",
    }
    data = {
        "time_transmit_gps": var(t_gps, None, "transmit epoch (GPS time)"),
        "station": var(nps["station"].values.astype(str), "1", "CDP pad id"),
        "station_name": var(nps["station_name"].values.astype(str), "1", "station name"),
        "satellite": var(nps["satellite"].values.astype(str), "1", "CRD target name"),
        "pass_id": var(nps["pass_id"].values, "1", "CRD session index"),
        "elevation_deg": var(out["elevation_deg"], "degree", "elevation of the satellite"),
        "observed_range_m": var(out["observed_range_m"], "m",
                                "observed one-way range c*tof/2"),
        "computed_range_m": var(out["computed_range_m"], "m", "computed one-way range"),
        "residual_m": var(out["residual_m"], "m", "observed minus computed one-way range"),
        **{name: var(out[name], "m", title) for name, title in range_terms.items()},
        "pos_station_itrf_m": var(sta, "m", "station reference point incl. displacements",
                                  ("point", "xyz")),
        "los_rtn": var(out["los_rtn"], "1", "unit line of sight station to satellite in the "
                       "radial, along-track, cross-track axes of the orbit", ("point", "rtn")),
        "flag": var(flag, "1", "0 used, else rejection reason code (attribute reasons)"),
        "reason": var(np.array([REJECTION_REASONS[int(f)] for f in flag], dtype=str), "1",
                      "rejection reason"),
    }
    time = nps["time"].values.astype("datetime64[ns]")
    ds = xr.Dataset(data, coords={"time": ("point", time, {"long_name": "CRD epoch (UTC)"}),
                                  "xyz": _XYZ, "rtn": _RTN})
    ds.attrs.update({
        "title": "SLR residuals",
        "time_system": "UTC (time); GPS (time_transmit_gps)",
        "reference_frame": "ITRF",
        "reasons": "; ".join(f"{k} = {v}" for k, v in REJECTION_REASONS.items()),
        **{f"setting_{k}": (int(v) if isinstance(v, bool) else v)
           for k, v in asdict(settings).items()},
    })
    return ds


def _log_summary(ds: xr.Dataset) -> None:
    codes, counts = np.unique(ds["flag"].values, return_counts=True)
    rejected = ", ".join(f"{REJECTION_REASONS[int(c)]}: {k}" for c, k in zip(codes, counts)
                         if c != 0)
    used = ds["residual_m"].values[ds["flag"].values == 0]
    if used.size:
        logger.info("SLR: %d of %d normal points used, mean %.2f cm, STD %.2f cm, RMS %.2f "
                    "cm; rejected: %s", used.size, ds.sizes["point"], 100 * used.mean(),
                    100 * _std(used), 100 * np.sqrt(np.mean(used**2)), rejected or "none")
    else:
        logger.info("SLR: none of %d normal points used; rejected: %s", ds.sizes["point"],
                    rejected or "none")


def _std(values: np.ndarray) -> float:
    """Sample standard deviation (n − 1); NaN for fewer than two values (no warning)."""
    v = np.asarray(values, dtype=float)
    if v.size < 2:
        return float("nan")
    return float(np.sqrt(np.sum((v - v.mean()) ** 2) / (v.size - 1)))

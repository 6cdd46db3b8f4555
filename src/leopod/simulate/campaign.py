"""A simulated campaign in the standard file formats, with its truth (closed-loop simulator).

One continuous world per campaign: its epoch is 00:00 GPS time of the first day; the GNSS
constellations (:mod:`leopod.simulate.world`, inertial frame = GCRF), their clocks, the
receiver clocks, the code and phase biases (:mod:`leopod.simulate.biases`) and each LEO's truth
orbit (:mod:`leopod.simulate.truth_orbit`) span the whole campaign, so the files of
consecutive days join without jumps. Days are written independently: each starts a new
tracking session (new ambiguities at 00:00).

Files (the rules of ``workflow/rules/simulate.smk``):

* per satellite (:func:`simulate_truth`, :func:`code_bias_map_truth`): the truth orbit of the
  campaign (netCDF, GCRF and ITRF, 10 s) and the code-bias map(s) on a 5° grid;
* per campaign (:func:`simulate_world_truth`): the true biases (GNSS satellites and every
  LEO receiver) and the SLR stations (SINEX);
* per day (:func:`simulate_gnss_products`): GNSS orbits (SP3-d, 15 min, 00:00-24:00, ITRF),
  clocks (RINEX clock, 30 s), integer-recovery clocks with the CNES/CLS ``WL`` records in
  their header, the wide-lane biases alone, and Bias-SINEX OSBs;
* per satellite and day (:func:`simulate_leo_day`): observations (RINEX 3.04 with every
  simulated system, RINEX 2.11 with GPS), the day's truth (SP3 and netCDF with the orbit
  and, per observation, ambiguities, passes, angles, ranges, wind-up, ionosphere, clocks) and
  the SLR normal points of the UTC day (CRD 2).

Settings: :class:`leopod.simulate.settings.SimulationSettings`. Randomness: each stream comes
from :meth:`SimulationSettings.rng` with a label naming its use (``"truth/<sat>"``,
``"gnss-orbit/<sv>"``, ``"gnss-clock/<sv>"``, ``"gnss-walk/<sv>"``, ``"rx-clock/<sat>"``,
``"biases/gnss"``, ``"biases/rx/<sat>"``, ``"obs/<sat>/<date>"``, ``"slr/<sat>/<date>"``), so a
file depends only on the master seed and its own label: the same seed gives the same files
whatever the order in which jobs run.
"""

from __future__ import annotations

import datetime as _dt
import logging
import time as _time
from collections.abc import Mapping, Sequence
from dataclasses import replace

import numpy as np
import xarray as xr

from leopod.constants import C_LIGHT_M_S, GM_EARTH_M3_S2
from leopod.dynamics.model_files import resolve_model_paths
from leopod.frames.earth_rotation import gcrf_from_itrf_matrices
from leopod.frames.leo_attitude import LeoAttitude
from leopod.io.antex import read_antex
from leopod.io.bias_sinex_write import write_bias_sinex
from leopod.io.clock_write import write_rinex_clock
from leopod.io.dcb_write import write_code_dcb
from leopod.io.manoeuvre import Manoeuvre
from leopod.io.manoeuvre_write import write_manoeuvres
from leopod.io.netcdf import write_netcdf
from leopod.io.rinex_obs_write import write_rinex_obs
from leopod.io.sp3_write import write_sp3
from leopod.io.wlbias_write import wl_bias_records, write_wl_bias
from leopod.simulate.biases import (
    SimulatedBiases,
    integer_clock_s,
    simulate_biases,
    truth_dataset,
)
from leopod.simulate.code_bias_map import CodeBiasMap
from leopod.simulate.formation import FormationSettings, follower_initial_state
from leopod.simulate.manoeuvres import daily_manoeuvres
from leopod.simulate.observations import GnssWorld, simulate_observations
from leopod.simulate.product_faults import faulty_products
from leopod.simulate.product_world import osb_biases, product_world
from leopod.simulate.settings import DEFAULT_PCO_BODY_M, SimulationSettings
from leopod.simulate.slr import (
    simulate_normal_points,
    write_normal_points,
    write_station_eccentricities,
    write_station_sinex,
)
from leopod.simulate.truth_orbit import (
    initial_state_sun_synchronous,
    intermediate_to_gcrf_matrix,
    simulate_truth_orbit,
    write_truth_files,
)
from leopod.simulate.world import (
    CircularOrbit,
    KeplerOrbit,
    RandomWalkClock,
    beidou3_constellation,
    gps_constellation,
)
from leopod.time.calendar import parse_date_id, seconds_since

__all__ = ["biases_for", "code_bias_map_truth", "gnss_world", "receiver_clock",
           "p1c1_dcb", "simulate_gnss_products", "simulate_leo_day", "simulate_truth", "simulate_world_truth",
           "write_code_bias_maps", "write_manoeuvre_file", "write_truth_orbit"]

log = logging.getLogger(__name__)

_DAY = np.timedelta64(86_400, "s")
_NS_PER_S = 1_000_000_000
#: Extra span of the clocks' pre-drawn random walks beyond the last day [s].
_CLOCK_SPAN_MARGIN_S = 7200.0
#: Truth orbit around each day handed to the SLR simulation [s] (> two-way light time).
_SLR_TRUTH_MARGIN_S = 120.0
#: Receiver-bias variables of :func:`leopod.simulate.biases.truth_dataset` (per LEO).
_RX_BIAS_VARS = ("code_bias_rx_m", "phase_bias_rx_cyc", "wl_bias_rx_cyc", "if_phase_bias_rx_m",
                 "if_code_bias_rx_m")
_CONSTELLATIONS = {"G": gps_constellation, "C": beidou3_constellation}


# --------------------------------------------------------------------------------- world


def _epoch(day: str) -> np.datetime64:
    """00:00 GPS time of a day given as YYYY-DDD or YYYY-MM-DD."""
    return np.datetime64(parse_date_id(day), "ns")


def _span_s(world_start: str, world_end: str) -> float:
    """Length of the clocks' pre-drawn random walks [s]."""
    days = (_epoch(world_end) - _epoch(world_start)) / _DAY + 1.0
    return float(days) * 86_400.0 + _CLOCK_SPAN_MARGIN_S


def gnss_world(settings: SimulationSettings, world_start: str, world_end: str) -> GnssWorld:
    """The GNSS constellations of the simulated systems and their product clocks.

    Parameters
    ----------
    settings : SimulationSettings
    world_start, world_end : str
        First and last day of the campaign (the clocks span them).

    Returns
    -------
    GnssWorld
        With ``settings.gnss_products``: the real products
        (:func:`leopod.simulate.product_world.product_world`; with simulated clocks when the
        set has no clock file). Else the slots of
        :func:`gps_constellation` / :func:`beidou3_constellation` as
        :class:`KeplerOrbit` with random eccentricities below ``gnss_eccentricity_max`` and
        random perigees (label ``gnss-orbit/<sv>``); clocks with a
        uniform offset and drift and a random walk with nodes on the clock-product grid.
    """
    if settings.gnss_products is not None:
        return product_world(
            settings.gnss_products, _epoch(world_start), systems=sorted(settings.systems),
            simulated_clocks=lambda svs: _simulated_clocks(settings, svs, world_start,
                                                           world_end))
    unknown = sorted(set(settings.systems) - set(_CONSTELLATIONS))
    if unknown:
        raise ValueError(f"no simulated constellation for systems {unknown} (known: "
                         f"{', '.join(_CONSTELLATIONS)}; Galileo flies only against a real "
                         "product set, simulate.gnss_products)")
    orbits = {}
    for system in sorted(settings.systems):
        for sv, nominal in _CONSTELLATIONS[system]().items():
            orbits[sv] = _eccentric(nominal, settings.gnss_eccentricity_max,
                                    settings.rng(f"gnss-orbit/{sv}"))
    return GnssWorld(epoch=_epoch(world_start), orbits=orbits,
                     clocks=_simulated_clocks(settings, orbits, world_start, world_end))


def _simulated_clocks(settings: SimulationSettings, svs, world_start: str,
                      world_end: str) -> dict[str, RandomWalkClock]:
    """Satellite clocks of ``svs``: uniform offset and drift and a random walk with nodes on
    the clock-product grid (labels ``gnss-clock/<sv>``, ``gnss-walk/<sv>``)."""
    c = settings.clocks
    span = _span_s(world_start, world_end)
    clocks = {}
    for sv in sorted(svs):
        rng = settings.rng(f"gnss-clock/{sv}")
        clocks[sv] = RandomWalkClock(
            bias_s=float(rng.uniform(-c.gnss_bias_max_s, c.gnss_bias_max_s)),
            drift_s_s=float(rng.uniform(-c.gnss_drift_max_s_s, c.gnss_drift_max_s_s)),
            walk_s_sqrt_s=c.gnss_walk_s_sqrt_s, seed=settings.int_seed(f"gnss-walk/{sv}"),
            step_s=settings.products.clock_interval_s, span_s=span)
    return clocks


def _eccentric(nominal: CircularOrbit, e_max: float, rng: np.random.Generator) -> KeplerOrbit:
    """The nominal slot with a random eccentricity in [0, e_max) and perigee, and the same
    argument of latitude at t = 0 (to first order in e)."""
    e = float(rng.uniform(0.0, e_max))
    argp = float(rng.uniform(0.0, 360.0))
    return KeplerOrbit(nominal.a_m, e, nominal.inc_deg, nominal.raan_deg, argp,
                       (nominal.u0_deg - argp) % 360.0, j2=nominal.j2)


def receiver_clock(settings: SimulationSettings, sat: str, world_start: str,
                   world_end: str) -> RandomWalkClock:
    """Receiver clock of a LEO [s] as a function of world time (with the steps of
    ``simulate.clocks.rx_jumps``)."""
    c = settings.clocks
    jumps = tuple((float(seconds_since(np.datetime64(j["epoch"], "ns"), _epoch(world_start))),
                   float(j["size_s"])) for j in c.rx_jumps)
    return RandomWalkClock(bias_s=c.rx_bias_s, drift_s_s=c.rx_drift_s_s,
                           walk_s_sqrt_s=c.rx_walk_s_sqrt_s,
                           seed=settings.int_seed(f"rx-clock/{sat}"),
                           step_s=settings.interval_s, span_s=_span_s(world_start, world_end),
                           jumps=jumps)


def _code_bias_maps(settings: SimulationSettings) -> list[CodeBiasMap]:
    return [CodeBiasMap.from_config(m) for m in settings.code_bias_maps]


def code_bias_map_truth(settings: SimulationSettings, step_deg: float = 5.0) -> xr.Dataset:
    """The code-bias maps on a cell-centred grid (:meth:`CodeBiasMap.grid`), one variable
    ``code_bias_<key>_m`` (el, az) [m] per map (:attr:`CodeBiasMap.key`: the signal, and the
    yaw branch of a map that has one), its model and mean in the attributes."""
    out = xr.Dataset(attrs={"title": "simulated antenna-frame code-bias maps (truth)",
                            "signals": " ".join(m.signal for m in _code_bias_maps(settings))})
    for m in _code_bias_maps(settings):
        grid = m.grid(step_deg)
        var = grid["code_bias_m"]
        var.attrs.update({k: v for k, v in grid.attrs.items() if k != "frame"})
        out[f"code_bias_{m.key}_m"] = var
        out.attrs["frame"] = grid.attrs["frame"]
    return out


# --------------------------------------------------------------------------------- truth


def simulate_truth(settings: SimulationSettings, sat: str, world_start: str, world_end: str,
                   *, eop=None, formation: FormationSettings | None = None,
                   manoeuvres: Sequence[Manoeuvre] = ()) -> xr.Dataset:
    """The truth orbit of one LEO over the campaign (00:00 of the first day to 24:00 of the
    last, plus ``orbit.margin_s`` on both sides), :func:`simulate_truth_orbit` with the
    settings' dynamics and models and the seed of label ``truth/<sat>``.

    A formation follower (``formation`` given) starts from the leader's initial state, which
    ``settings.orbit`` then defines, displaced by the ROE
    (:func:`leopod.simulate.formation.follower_initial_state`), and flies its daily burns
    (:func:`leopod.simulate.manoeuvres.daily_manoeuvres`); the dataset attributes
    ``formation_leader`` and ``formation_roe_m`` record them. Its stochastic accelerations and
    drag-scale noise sample the leader's random field (seed of ``truth/<leader>``) with the
    correlation ``formation.truth_correlation``
    (:mod:`leopod.simulate.truth_forces`, Formations). Any other satellite flies the burns
    ``manoeuvres`` (:mod:`leopod.simulate.manoeuvres`; none by default), e.g. a burn its
    operator did not announce."""
    o = settings.orbit
    margin = np.timedelta64(round(o.margin_s * _NS_PER_S), "ns")
    t_start = _epoch(world_start) - margin
    t_end = _epoch(world_end) + _DAY + margin
    models = resolve_model_paths({"m": dict(settings.models)})["m"]
    clock = _time.perf_counter()
    state0, burns, common = None, tuple(manoeuvres), {}
    if formation is not None:
        leader = initial_state_sun_synchronous(t_start, o.altitude_km * 1e3, o.ltan_h,
                                               inclination_deg=o.inclination_deg,
                                               u0_deg=o.u0_deg)
        a_m = 1.0 / (2.0 / np.linalg.norm(leader[:3])
                     - leader[3:] @ leader[3:] / GM_EARTH_M3_S2)
        state0 = follower_initial_state(leader, formation.roe(a_m),
                                        intermediate_to_gcrf_matrix(t_start))
        n_days = int((_epoch(world_end) - _epoch(world_start)) // _DAY) + 1
        burns = daily_manoeuvres(formation.manoeuvres, _epoch(world_start), n_days)
        common = {"common_seed": settings.int_seed(f"truth/{formation.leader}"),
                  "correlation": formation.truth_correlation}
    truth = simulate_truth_orbit(
        t_start, t_end, seed=settings.int_seed(f"truth/{sat}"), step_s=o.step_s,
        altitude_m=o.altitude_km * 1e3, ltan_h=o.ltan_h, inclination_deg=o.inclination_deg,
        u0_deg=o.u0_deg, dynamics=settings.dynamics, eop=eop,
        integrator_step_s=o.integrator_step_s,
        models={"gravity_field": models["field"], "space_weather": models["space_weather"],
                "ocean_tides": models["ocean"]}, state0=state0, manoeuvres=burns, **common)
    truth.attrs["satellite"] = sat
    if formation is not None:
        truth.attrs["formation_leader"] = formation.leader
        truth.attrs["formation_roe_m"] = formation.roe(1.0)
    log.info("truth orbit of %s: %s to %s, %d epochs, %d burns, %.1f s", sat, t_start, t_end,
             truth.sizes["time"], len(burns), _time.perf_counter() - clock)
    return truth


def write_manoeuvre_file(truth: xr.Dataset, path) -> None:
    """Write the burns of a truth orbit (:func:`simulate_truth`) as the satellite's manoeuvre
    file (:mod:`leopod.io.manoeuvre`; the header only when it has none)."""
    burns = [Manoeuvre(s, e, tuple(float(x) for x in a)) for s, e, a in
             zip(truth["manoeuvre_start"].values, truth["manoeuvre_end"].values,
                 truth["manoeuvre_acc_rtn_m_s2"].values)]
    write_manoeuvres(path, burns, satellite=str(truth.attrs.get("satellite", "")))


def _campaign_biases(settings: SimulationSettings, svs: Sequence[str], sat: str | None,
                     world_start: str) -> SimulatedBiases:
    """GNSS satellite biases (label ``biases/gnss``, or the OSBs of the real product set),
    receiver biases of ``sat`` (label ``biases/rx/<sat>``)."""
    signals = settings.signal_codes()
    epoch = _epoch(world_start)
    sat_part = simulate_biases(svs, signals, settings.rng("biases/gnss"), epoch=epoch,
                               settings=settings.biases)
    if settings.gnss_products is not None:
        sat_part = osb_biases(settings.gnss_products, sat_part, epoch)
    if sat is None:
        return sat_part
    rx_part = simulate_biases(svs, signals, settings.rng(f"biases/rx/{sat}"), epoch=epoch,
                              settings=settings.biases)
    return replace(sat_part, code_rx_m=rx_part.code_rx_m, phase_rx_cyc=rx_part.phase_rx_cyc)


def simulate_world_truth(settings: SimulationSettings, sats: Sequence[str], world_start: str,
                         world_end: str, *, biases_path, stations_path,
                         eccentricities_path=None) -> xr.Dataset:
    """Write the campaign's true biases (netCDF), the SLR station coordinates and their
    eccentricities (SINEX; eccentricities skipped if ``eccentricities_path`` is None).

    Returns
    -------
    xarray.Dataset
        :func:`leopod.simulate.biases.truth_dataset` of the GNSS satellite biases, with the
        receiver variables of every LEO along a ``leo`` dimension (read back with
        :func:`biases_for`).
    """
    svs = gnss_world(settings, world_start, world_end).svs
    ds = truth_dataset(_campaign_biases(settings, svs, None, world_start)).drop_vars(
        list(_RX_BIAS_VARS))
    rx = [truth_dataset(_campaign_biases(settings, svs, sat, world_start))[list(_RX_BIAS_VARS)]
          for sat in sats]
    ds = xr.merge([ds, xr.concat(rx, dim=xr.DataArray(list(sats), dims="leo", name="leo"))],
                  combine_attrs="override")
    ds.attrs["title"] = "simulated code and phase biases (truth)"
    write_netcdf(ds, biases_path, step="simulate_world", time_system="GPS",
                 title="simulated code and phase biases (truth)")
    write_station_sinex(settings.slr.station_list, stations_path, _epoch(world_start))
    if eccentricities_path is not None:
        write_station_eccentricities(settings.slr.station_list, eccentricities_path)
    log.info("biases of %d GNSS satellites and %d receivers; %d SLR stations", len(svs),
             len(sats), len(settings.slr.station_list))
    return ds


def biases_for(truth: xr.Dataset, sat: str | None = None) -> SimulatedBiases:
    """:class:`SimulatedBiases` from the file of :func:`simulate_world_truth` (receiver part of
    LEO ``sat``; with ``sat=None`` the receiver biases are NaN)."""
    def bare(da):
        return xr.DataArray(da.values, dims=da.dims,
                            coords={d: da[d].values for d in da.dims})

    systems = [str(s) for s in truth["system"].values]
    if sat is None:
        code_rx = xr.full_like(bare(truth["code_bias_rx_m"].isel(leo=0)), np.nan)
        phase_rx = xr.full_like(bare(truth["phase_bias_rx_cyc"].isel(leo=0)), np.nan)
    else:
        code_rx = bare(truth["code_bias_rx_m"].sel(leo=sat, drop=True))
        phase_rx = bare(truth["phase_bias_rx_cyc"].sel(leo=sat, drop=True))
    return SimulatedBiases(
        code_sat_m=bare(truth["code_bias_sat_m"]), phase_sat_cyc=bare(truth["phase_bias_sat_cyc"]),
        phase_drift_sat_cyc_s=bare(truth["phase_drift_sat_cyc_s"]), code_rx_m=code_rx,
        phase_rx_cyc=phase_rx, epoch=np.datetime64(truth.attrs["epoch"], "ns"),
        phase_pairs={s: tuple(truth.attrs[f"phase_pair_{s}"].split()) for s in systems},
        clock_reference={s: tuple(truth.attrs[f"clock_reference_codes_{s}"].split())
                         for s in systems})


def _day_biases(biases: SimulatedBiases, day0: np.datetime64) -> SimulatedBiases:
    """The same biases with their reference epoch (and drifting phase biases) at ``day0``."""
    phase = biases.sat_phase_cyc_at([day0]).isel(time=0, drop=True)
    return replace(biases, epoch=day0, phase_sat_cyc=phase)


# ------------------------------------------------------------------------- GNSS products


def _grid(day0: np.datetime64, step_s: float, end_inclusive: bool) -> np.ndarray:
    n = round(86_400.0 / step_s) + (1 if end_inclusive else 0)
    return day0 + np.arange(n) * np.timedelta64(round(step_s * _NS_PER_S), "ns")


def simulate_gnss_products(date: str, settings: SimulationSettings, world_start: str,
                           world_end: str, biases_truth: xr.Dataset, *, orbit, clock,
                           integer_clock, wl_bias, osb, dcb_p1c1=None, eop=None) -> None:
    """Write the GNSS products of one day.

    Parameters
    ----------
    date : str
        Day ``YYYY-DDD``.
    settings : SimulationSettings
    world_start, world_end : str
        First and last day of the campaign.
    biases_truth : xarray.Dataset
        From :func:`simulate_world_truth`.
    orbit, clock, integer_clock, wl_bias, osb : path
        SP3-d (``orbit_interval_s``, 00:00-24:00 inclusive, ITRF centre of mass, clocks in
        the P records), RINEX clock 3.00 (``clock_interval_s``, 00:00-23:59:30), the
        integer-recovery clocks with the ``WL`` records as header comments (CNES/CLS style),
        the ``WL`` records alone, Bias-SINEX (satellite code and phase OSBs, one day window).
        Clocks refer to the ionosphere-free combination of the clock-reference codes and
        exclude the periodic relativistic term (IGS convention).
    dcb_p1c1 : path, optional
        CODE-style P1−C1 DCB file of the true satellite biases (:func:`p1c1_dcb`), for
        receivers that track C1C (the clocks refer to C1W/C2W, not to C1C).
    eop : EarthOrientation, optional
    """
    day0 = _epoch(date)
    world = gnss_world(settings, world_start, world_end)
    svs = world.svs
    p = settings.products
    t_orbit = _grid(day0, p.orbit_interval_s, True)
    t_s = np.repeat(seconds_since(t_orbit, world.epoch)[:, None], len(svs), axis=1)
    pos_gcrf, _ = world.state_gcrf(svs, t_s)
    rot, _ = gcrf_from_itrf_matrices(t_orbit, eop)
    pos_itrf = np.einsum("nji,nsj->nsi", rot, pos_gcrf)
    sp3 = xr.Dataset({"pos_m": (("time", "sv", "xyz"), pos_itrf),
                      "clk_s": (("time", "sv"), world.clock_s(svs, t_s))},
                     coords={"time": t_orbit, "sv": svs, "xyz": ["x", "y", "z"]},
                     attrs={"time_system": "GPS"})
    write_sp3(sp3, orbit, agency=p.agency, orbit_type="FIT", coordinate_system="ITRF",
              comments=(f"leopod simulated GNSS orbits (centre of mass), seed {settings.seed}",))
    t_clock = _grid(day0, p.clock_interval_s, False)
    t_s = np.repeat(seconds_since(t_clock, world.epoch)[:, None], len(svs), axis=1)
    clk = xr.DataArray(world.clock_s(svs, t_s), dims=("time", "sv"),
                       coords={"time": t_clock, "sv": svs})
    systems = "/".join(sorted(settings.systems))
    write_rinex_clock(xr.Dataset({"clk_s": clk}, attrs={"time_system": "GPS"}), clock,
                      analysis_center=p.agency, created=_file_time(day0),
                      comments=(f"leopod simulated {systems} satellite clocks",
                                "ionosphere-free clock-reference codes, no relativity"))
    biases = _day_biases(biases_for(biases_truth), day0)
    faulty = faulty_products(biases, p.ar_fault, settings.rng(f"products/fault/{date}"),
                             agency=p.agency)
    products = faulty.products
    if p.ar_fault != "none":
        log.warning("AR products of %s made with the fault %r", date, p.ar_fault)
    records = wl_bias_records(products.wl)
    write_rinex_clock(xr.Dataset({"clk_s": integer_clock_s(clk, faulty.clock_biases)},
                                 attrs={"time_system": "GPS"}), integer_clock,
                      analysis_center=p.agency, created=_file_time(day0),
                      comments=("leopod simulated integer-recovery clocks (CNES/CLS style)",
                                "WL: wide-lane satellite biases, HMW/lam_WL = N + w_r - WL",
                                *records))
    write_wl_bias(products.wl, wl_bias)
    write_bias_sinex(products.osb, osb)
    if dcb_p1c1 is not None:
        dcb = p1c1_dcb(biases)
        write_code_dcb(dcb, dcb_p1c1, allow_empty=True,
                       title=f"LEOPOD SIMULATED GNSS P1-C1 DCB SOLUTION, DAY {date}")
        log.info("P1-C1 DCB of %d satellites, RMS %.3f ns", int(np.isfinite(dcb.dcb_s).sum()),
                 float(np.sqrt(np.nanmean(dcb.dcb_s.values**2)) * 1e9)
                 if np.isfinite(dcb.dcb_s).any() else 0.0)
    log.info("GNSS products %s: %d satellites (%s), %d orbit and %d clock epochs, %d OSB "
             "records", date, len(svs), systems, t_orbit.size, t_clock.size,
             products.osb.sizes["bias"])


def p1c1_dcb(biases: SimulatedBiases) -> xr.Dataset:
    """Satellite P1−C1 DCBs of the simulated biases (schema of :func:`leopod.io.dcb.read_code_dcb`).

    ``DCB(P1−C1) = d^s(C1W) − d^s(C1C)`` [s] (CODE sign, :mod:`leopod.io.dcb`), for the GPS
    satellites that have both codes; empty (no satellite) when C1C or C1W is not simulated.
    """
    code = biases.code_sat_m
    signals = list(map(str, code["code_signal"].values))
    if "C1C" in signals and "C1W" in signals:
        values = (code.sel(code_signal="C1W") - code.sel(code_signal="C1C")).values
    else:
        values = np.full(code.sizes["sv"], np.nan)
    svs = [str(s) for s in code["sv"].values]
    keep = np.array([s[0] == "G" for s in svs]) & np.isfinite(values)
    return xr.Dataset(
        {"dcb_s": ("sv", values[keep] / C_LIGHT_M_S, {"units": "s"}),
         "dcb_sigma_s": ("sv", np.zeros(int(keep.sum())), {"units": "s"})},
        coords={"sv": np.array(svs)[keep]}, attrs={"dcb_type": "P1-C1", "time_system": "GPS"})


# ---------------------------------------------------------------------------- LEO day


def _file_time(day0: np.datetime64) -> _dt.datetime:
    """Creation time written into a simulated day's file headers: the end of the day, so
    that the same settings give bit-identical files (not the wall clock)."""
    return (day0 + _DAY).astype("datetime64[s]").astype(_dt.datetime)


def _rinex_header(settings: SimulationSettings, sat: str, date: str) -> dict:
    return {"marker_name": settings.marker, "receiver_type": "LEOPOD SIMULATOR",
            "antenna_type": "SIMULATED", "observer": "leopod", "agency": "leopod",
            "created": _file_time(_epoch(date)),
            "comments": [f"leopod simulated {sat} {date}, seed {settings.seed}",
                         "truth orbit: dynamics engine, see the _truth.nc file"]}


def _rinex_dataset(obs: xr.Dataset, codes: dict, svs: list, interval_s: float) -> xr.Dataset:
    names = [c for cs in codes.values() for c in cs]
    keep = list(dict.fromkeys(names)) + [f"{c}_lli" for c in dict.fromkeys(names)
                                         if f"{c}_lli" in obs]
    ds = obs[keep].sel(sv=svs)
    ds.attrs = {"interval_s": interval_s, "time_system": "GPS",
                **{f"obs_types_{s}": " ".join(c) for s, c in codes.items()}}
    return ds


def _slr_day(truth: xr.Dataset, day0: np.datetime64, settings: SimulationSettings,
             rng: np.random.Generator, attitude: LeoAttitude | None = None) -> xr.Dataset:
    """Normal points of the UTC day of ``day0`` from the truth around it."""
    margin = np.timedelta64(round(_SLR_TRUTH_MARGIN_S * _NS_PER_S), "ns")
    window = truth[["pos_itrf_m", "vel_itrf_m_s"]].sel(time=slice(day0 - margin,
                                                                   day0 + _DAY + margin))
    nps = simulate_normal_points(window, settings.slr.retro_offset_body_m,
                                 stations=settings.slr.station_list,
                                 settings=settings.slr.settings, rng=rng, attitude=attitude)
    t = nps["time"].values
    return nps.isel(point=np.flatnonzero((t >= day0) & (t < day0 + _DAY)))


def _truth_day(truth: xr.Dataset, obs: xr.Dataset, day0: np.datetime64) -> xr.Dataset:
    """Orbit of the day [00:00, 24:00) and the per-observation truth."""
    orbit = truth[["pos_gcrf_m", "vel_gcrf_m_s", "pos_itrf_m", "vel_itrf_m_s"]].sel(
        time=slice(day0, day0 + _DAY - np.timedelta64(1, "ns")))
    names = [v for v in obs.data_vars if v.startswith(("amb_", "range_", "code_bias_map_"))]
    names += ["pass_true", "el_deg", "az_deg", "windup_cyc", "stec_tecu", "shapiro_m",
              "clk_sv_true_s", "clk_rx_true_s"]
    per_obs = obs[names].rename(time="obs_time")
    ds = xr.merge([orbit, per_obs], combine_attrs="override")
    ds.attrs = dict(truth.attrs)
    return ds


def simulate_leo_day(date: str, sat: str, settings: SimulationSettings, world_start: str,
                     world_end: str, truth: xr.Dataset, biases_truth: xr.Dataset,
                     pco_body_m: Mapping[str, Sequence[float]] | None = None, *,
                     rinex3, rinex2=None, truth_sp3, truth_nc, crd=None,
                     eop=None, leo_attitude: LeoAttitude | None = None) -> xr.Dataset:
    """Simulate and write one day of a LEO's onboard observations, its truth and SLR data.

    Parameters
    ----------
    date : str
        Day ``YYYY-DDD``.
    sat : str
        Satellite id (labels of the random streams and of the receiver biases).
    settings : SimulationSettings
    world_start, world_end : str
        First and last day of the campaign.
    truth : xarray.Dataset
        Truth orbit of the satellite (:func:`simulate_truth`) covering the day.
    biases_truth : xarray.Dataset
        From :func:`simulate_world_truth`.
    pco_body_m : mapping, optional
        Antenna PCO per band name in the body frame [m] (default
        :data:`DEFAULT_PCO_BODY_M`); must name every simulated band.
    rinex3, rinex2, truth_sp3, truth_nc, crd : path
        Outputs: RINEX 3.04 (all systems), RINEX 2.11 (GPS; skipped if None), truth SP3-d
        (10 s, ITRF centre of mass) and netCDF (module docstring), CRD 2 normal points of the
        UTC day (skipped if None).
    eop : EarthOrientation, optional
    leo_attitude : LeoAttitude, optional
        Attitude law of the satellite (antenna offsets, wind-up, antenna-frame code-bias maps,
        SLR retro-reflector); None: nominal.

    Returns
    -------
    xarray.Dataset
        The observations with their truth (:func:`leopod.simulate.observations.
        simulate_observations`).
    """
    clock = _time.perf_counter()
    day0 = _epoch(date)
    interval = np.timedelta64(round(settings.interval_s * _NS_PER_S), "ns")
    times = day0 + np.arange(round(86_400.0 / settings.interval_s)) * interval
    world = gnss_world(settings, world_start, world_end)
    antex = read_antex(settings.gnss_antex) if settings.gnss_antex else None
    obs = simulate_observations(
        times, truth, world, receiver_clock(settings, sat, world_start, world_end),
        biases_for(biases_truth, sat), settings.signal_codes(),
        DEFAULT_PCO_BODY_M if pco_body_m is None else pco_body_m, _code_bias_maps(settings),
        settings.observations, settings.rng(f"obs/{sat}/{date}"), antex=antex, eop=eop,
        leo_attitude=leo_attitude)
    codes = settings.signal_codes()
    header = _rinex_header(settings, sat, date)
    write_rinex_obs(_rinex_dataset(obs, codes, list(obs.sv.values), settings.interval_s),
                    rinex3, version=3.04, header=header)
    gps = [s for s in obs.sv.values if s[0] == "G"]
    if rinex2 is not None and gps:
        write_rinex_obs(_rinex_dataset(obs, {"G": codes["G"]}, gps, settings.interval_s),
                        rinex2, version=2.11, header=header)
    write_truth_files(_truth_day(truth, obs, day0), truth_sp3, truth_nc, settings.leo_sp3_id)
    n_np = 0
    if crd is not None:
        nps = _slr_day(truth, day0, settings, settings.rng(f"slr/{sat}/{date}"), leo_attitude)
        write_normal_points(nps, crd, day0)
        n_np = nps.sizes["point"]
    tracked = np.isfinite(obs["el_deg"].values)
    log.info("simulated %s %s: %d epochs, %d observations of %d satellites, %d passes, "
             "%d slips, %d SLR normal points, %.1f s", sat, date, times.size,
             int(tracked.sum()), int(tracked.any(axis=0).sum()), obs.attrs["n_passes"],
             obs.attrs["n_slips"], n_np, _time.perf_counter() - clock)
    return obs


def write_truth_orbit(truth: xr.Dataset, path) -> None:
    """Write the campaign truth orbit of :func:`simulate_truth` as netCDF."""
    write_netcdf(truth, path, step="simulate_truth", time_system="GPS",
                 reference_frame="GCRF and ITRF (per variable)",
                 title=f"leopod truth orbit {truth.attrs.get('satellite', '')}".strip())


def write_code_bias_maps(settings: SimulationSettings, path) -> None:
    """Write :func:`code_bias_map_truth` as netCDF."""
    write_netcdf(code_bias_map_truth(settings), path, step="simulate_truth",
                 reference_frame="antenna (body) frame", title="simulated code-bias maps")


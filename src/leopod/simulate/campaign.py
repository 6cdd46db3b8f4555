"""Write one simulated day in the standard file formats, with its truth.

Files: onboard observations (RINEX 2.11), GNSS orbits (SP3-d, 15 min, 00:00–24:00) and
clocks (RINEX clock 3.00, 30 s), the LEO truth orbit (SP3-d, 10 s, centre of mass) and a
truth netCDF (ambiguities per pass, true ranges and elevations). All days of a campaign are
cut from one continuous world that starts at the campaign's first day, so arcs of
consecutive days join without jumps.
"""

from __future__ import annotations

import datetime as _dt
import logging
import zlib
from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from leopod.constants import R_EARTH_EQUATOR_M
from leopod.io.clock import write_rinex_clock
from leopod.io.rinex_obs import write_rinex_obs
from leopod.io.sp3 import write_sp3
from leopod.netcdf import write_netcdf
from leopod.simulate.observations import ObservationModel, simulate_observations
from leopod.simulate.world import CircularOrbit, RandomWalkClock, earth_fixed, gps_constellation
from leopod.time import parse_date_id

__all__ = ["SimulationSettings", "simulate_gnss_products", "simulate_leo_day"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class SimulationSettings:
    """World and receiver of a simulated campaign (defaults: an HY-2B-like satellite).

    Attributes
    ----------
    altitude_km, inclination_deg, raan_deg, u0_deg : float
        Circular LEO orbit at the world epoch (HY-2B: ≈970 km, 99.34°, seed 000 sec. II-A).
    interval_s : float
        Observation sampling [s].
    seed : int
        Master seed; each day and satellite derive their own from it.
    marker : str
        Four-character marker name of the RINEX file.
    model : ObservationModel
    """

    altitude_km: float = 970.0
    inclination_deg: float = 99.34
    raan_deg: float = 30.0
    u0_deg: float = 0.0
    interval_s: float = 30.0
    seed: int = 2018
    marker: str = "SIML"
    model: ObservationModel = field(default_factory=ObservationModel)

    @classmethod
    def from_config(cls, cfg: dict) -> "SimulationSettings":
        """Build from the ``simulate`` block of a campaign config (unknown keys are errors)."""
        cfg = dict(cfg or {})
        model_cfg = cfg.pop("observations", {}) or {}
        try:
            return cls(**cfg, model=ObservationModel(**model_cfg))
        except TypeError as err:
            raise ValueError(f"config 'simulate': {err}") from None


def _day_seed(master: int, sat: str, date: str) -> int:
    return (master * 1_000_003 + zlib.crc32(f"{sat}/{date}".encode())) % (2**32)


def _world(settings: SimulationSettings, span_s: float):
    """The GNSS constellation, its product clocks, the P1-C1 DCBs and the receiver clock."""
    gnss = gps_constellation()
    clocks = {k: RandomWalkClock(bias_s=1e-4 * np.sin(j), drift_s_s=1e-12 * np.cos(3 * j),
                                 walk_s_sqrt_s=2e-13, seed=settings.seed + j, span_s=span_s)
              for j, k in enumerate(sorted(gnss))}
    rx_clock = RandomWalkClock(bias_s=3e-4, drift_s_s=5e-10, walk_s_sqrt_s=3e-11,
                               seed=settings.seed + 1000, span_s=span_s)
    rng_dcb = np.random.default_rng(settings.seed + 2000)
    dcb = {k: float(rng_dcb.normal(0, 1e-9)) for k in sorted(gnss)}
    return gnss, clocks, dcb, rx_clock


def _day(date: str, world_start: str):
    """Offset of the day from the world epoch [s] and its 00:00 as datetime64."""
    day = parse_date_id(date)
    offset = (day - parse_date_id(world_start)).days * 86400.0
    if offset < 0:
        raise ValueError(f"day {date} is before the simulated world's start {world_start}")
    return offset, np.datetime64(_dt.datetime(day.year, day.month, day.day), "ns")


def _times(t0: np.datetime64, n: int, step_s: float) -> np.ndarray:
    return t0 + (np.arange(n) * round(step_s * 1e9)).astype("timedelta64[ns]")


def simulate_gnss_products(date: str, world_start: str, settings: SimulationSettings,
                           out_orbit, out_clock) -> None:
    """Write the simulated GNSS orbits (SP3-d, 15 min, 00:00-24:00) and clocks (30 s) of a day."""
    offset, t0 = _day(date, world_start)
    gnss, clocks, _, _ = _world(settings, offset + 2 * 86400.0)
    ids = sorted(gnss)
    t_sp3 = offset + np.arange(0.0, 86400.0 + 1, 900.0)
    pos = np.stack([earth_fixed(t_sp3, gnss[k].inertial(t_sp3)[0])[0] for k in ids], axis=1)
    clk_sp3 = np.stack([clocks[k](t_sp3) for k in ids], axis=1)
    orbit = xr.Dataset({"pos_m": (("time", "sv", "xyz"), pos), "clk_s": (("time", "sv"), clk_sp3)},
                       coords={"time": _times(t0, t_sp3.size, 900.0), "sv": ids, "xyz": ["x", "y", "z"]})
    write_sp3(orbit, out_orbit, agency="SIM", orbit_type="FIT", coordinate_system="SIMEF",
              comments=(f"leopod simulated GNSS orbits, world start {world_start}",))
    t_clk = offset + np.arange(0.0, 86400.0, 30.0)
    clock = xr.Dataset({"clk_s": (("time", "sv"), np.stack([clocks[k](t_clk) for k in ids], axis=1))},
                       coords={"time": _times(t0, t_clk.size, 30.0), "sv": ids})
    write_rinex_clock(clock, out_clock, analysis_center="SIM",
                      comments=("leopod simulated satellite clocks (P1/P2 ionosphere-free)",))


def simulate_leo_day(date: str, world_start: str, sat: str, settings: SimulationSettings,
                     out_obs, out_truth_sp3, out_truth_nc) -> None:
    """Simulate one day of a LEO's onboard observations and write them with the truth.

    Parameters
    ----------
    date : str
        Day ``YYYY-DDD``.
    world_start : str
        First day of the campaign (the world's epoch, 00:00 GPST).
    sat : str
        Satellite id (used for seeds and names).
    settings : SimulationSettings
    out_obs, out_truth_sp3, out_truth_nc : path
        RINEX 2.11 observations, SP3 truth orbit (10 s), truth netCDF.
    """
    offset, t0 = _day(date, world_start)
    gnss, clocks, dcb, rx_clock = _world(settings, offset + 2 * 86400.0)
    leo = CircularOrbit(R_EARTH_EQUATOR_M + settings.altitude_km * 1e3, settings.inclination_deg,
                        settings.raan_deg, settings.u0_deg)
    t_obs = offset + np.arange(0.0, 86400.0, settings.interval_s)
    obs = simulate_observations(t_obs, leo, gnss, clocks, rx_clock, dcb, settings.model,
                                seed=_day_seed(settings.seed, sat, date))
    obs = obs.assign_coords(time=_times(t0, t_obs.size, settings.interval_s))
    rinex = obs[["C1", "P1", "P2", "L1", "L2", "L1_lli", "L2_lli"]]
    rinex.attrs = {"marker_name": settings.marker, "receiver_type": "LEOPOD SIMULATOR",
                   "antenna_type": "SIMULATED", "interval_s": settings.interval_s,
                   "time_system": "GPS", "obs_types_G": "L1 L2 P1 P2 C1"}
    write_rinex_obs(rinex, out_obs, version=2.11,
                    header={"comments": [f"leopod simulated {sat} {date} seed {settings.seed}",
                                         "phase wind-up, GNSS antenna offsets not simulated"]})
    t_leo = offset + np.arange(0.0, 86400.0, 10.0)
    p_ef, v_ef = earth_fixed(t_leo, *leo.inertial(t_leo))
    truth = xr.Dataset({"pos_m": (("time", "sv", "xyz"), p_ef[:, None, :]),
                        "vel_m_s": (("time", "sv", "xyz"), v_ef[:, None, :])},
                       coords={"time": _times(t0, t_leo.size, 10.0), "sv": ["L01"],
                               "xyz": ["x", "y", "z"]})
    write_sp3(truth, out_truth_sp3, agency="SIM", orbit_type="FIT", coordinate_system="SIMEF",
              comments=(f"leopod simulated truth orbit of {sat} (centre of mass)",))
    truth_nc = truth.isel(sv=0, drop=True)
    truth_nc["pos_m"].attrs = {"units": "m", "long_name": "true LEO centre-of-mass position (Earth-fixed)"}
    truth_nc["vel_m_s"].attrs = {"units": "m s-1", "long_name": "true LEO velocity (Earth-fixed)"}
    extra = obs[["true_range_if_m", "amb_L1_cyc", "amb_L2_cyc", "pass_true", "el_deg",
                 "rx_clock_true_s"]].rename({"time": "obs_time"})
    write_netcdf(xr.merge([truth_nc, extra]), out_truth_nc, step="simulate", time_system="GPS",
                 reference_frame="SIMEF (simulated Earth-fixed)", title=f"simulation truth {sat} {date}")
    log.info("simulated %s %s: %d epochs, %d tracked observations, %d passes", sat, date,
             t_obs.size, int(np.isfinite(obs.L1.values).sum()), int(obs.pass_true.max()) + 1)

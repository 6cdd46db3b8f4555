"""A simulated day with frequency-dependent LEO antenna offsets (closed-loop truth).

The simulator (leopod.simulate.observations) puts each band's signal at its own phase centre:
LEO PCOs L1 (0, 0, −0.35) m and L2 (0, 0, −0.37) m in the body frame (2 cm apart along the
boresight, the default campaign's values), the HY-2B-like C1W code-bias map of the default
simulate section, the simulator's biases, noise and passes. To keep the scenario cheap the LEO
flies an analytic circular orbit (leopod.simulate.world.CircularOrbit, 970 km, sun-synchronous
inclination) instead of an integrated one: the antenna terms depend on the geometry only.

What the estimator side sees is built independently of the simulator's geometry: Earth-fixed
LEO and GNSS positions from the orbits through the IERS rotation
(leopod.frames.earth_rotation.gcrf_to_itrf), as the ingest step provides them, and the Sun of
leopod.astro.sun.
"""

from __future__ import annotations

from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import xarray as xr

from leopod.astro.sun import sun_position_ef
from leopod.constants import C_LIGHT_M_S, R_EARTH_EQUATOR_M
from leopod.frames.attitude import antenna_angles, nominal_body_axes
from leopod.frames.earth_rotation import gcrf_from_itrf_matrices, gcrf_to_itrf
from leopod.gnss.antenna_terms import antenna_terms
from leopod.signals import frequency_hz
from leopod.simulate.biases import simulate_biases, truth_dataset
from leopod.simulate.campaign import gnss_world, receiver_clock
from leopod.simulate.code_bias_map import CodeBiasMap
from leopod.simulate.observations import simulate_observations
from leopod.simulate.settings import SimulationSettings
from leopod.simulate.world import CircularOrbit
from leopod.time.calendar import seconds_since
from leopod.workflow.config import with_defaults

DAY, LAST_DAY, SAT = "2019-001", "2019-002", "leo-antenna"
#: LEO antenna offsets per band in the body frame [m]: L1 and L2 2 cm apart (issue 19).
PCO = {"L1": (0.0, 0.0, -0.35), "L2": (0.0, 0.0, -0.37)}
F1, F2 = frequency_hz("G", "L1C"), frequency_hz("G", "L2W")
LAM1, LAM2 = C_LIGHT_M_S / F1, C_LIGHT_M_S / F2


def _circular_truth(epoch: np.datetime64, hours: float) -> tuple[xr.Dataset, CircularOrbit]:
    """GCRF states of a circular LEO orbit on a 30-s grid covering ``hours`` (+10 min)."""
    orbit = CircularOrbit(R_EARTH_EQUATOR_M + 970e3, 99.35, 30.0, 0.0)
    t_s = np.arange(-600.0, hours * 3600.0 + 600.0, 30.0)
    pos, vel = orbit.inertial(t_s)
    times = epoch + (t_s * 1e9).astype("int64").astype("timedelta64[ns]")
    return xr.Dataset({"pos_gcrf_m": (("time", "xyz"), pos),
                       "vel_gcrf_m_s": (("time", "xyz"), vel)}, coords={"time": times}), orbit


def scenario(hours: float = 48.0, interval_s: float = 10.0) -> SimpleNamespace:
    """Simulated observations (phases in metres), their truth and the estimator's terms.

    Returns
    -------
    SimpleNamespace
        ``obs`` (codes and phases [m] on (time, sv), the simulator's truth variables),
        ``terms`` (:func:`leopod.gnss.antenna_terms.antenna_terms` of the estimator's side),
        ``biases`` (truth dataset: ``wl_bias_sat_cyc``, ``wl_bias_rx_cyc``), ``map`` (the
        simulated C1W code-bias map, a callable of (az, el) [deg]), ``el_deg``/``az_deg``
        (antenna-frame angles of the estimator's side, (time, sv)), ``settings``.
    """
    sim = SimulationSettings.from_config(with_defaults("simulate", {"interval_s": interval_s}))
    world = gnss_world(sim, DAY, LAST_DAY)
    epoch = world.epoch
    step = np.timedelta64(round(interval_s * 1e9), "ns")
    times = epoch + np.arange(round(hours * 3600.0 / interval_s)) * step
    truth, leo_orbit = _circular_truth(epoch, hours)
    codes = sim.signal_codes()
    sat = simulate_biases(world.svs, codes, sim.rng("biases/gnss"), epoch=epoch,
                          settings=sim.biases)
    rx = simulate_biases(world.svs, codes, sim.rng(f"biases/rx/{SAT}"), epoch=epoch,
                         settings=sim.biases)
    biases = replace(sat, code_rx_m=rx.code_rx_m, phase_rx_cyc=rx.phase_rx_cyc)
    maps = [CodeBiasMap.from_config(m) for m in sim.code_bias_maps]
    clock = receiver_clock(sim, SAT, DAY, LAST_DAY)
    obs = simulate_observations(times, truth, world, clock, biases, codes, PCO, maps,
                                sim.observations, sim.rng(f"obs/{SAT}"))
    obs["L1C"] = obs["L1C"] * LAM1
    obs["L2W"] = obs["L2W"] * LAM2
    # estimator side: Earth-fixed states at the epochs, as the ingest step gives them
    t_s = seconds_since(times, epoch)
    leo_gcrf, leo_vel_gcrf = leo_orbit.inertial(t_s)
    leo_pos, leo_vel = gcrf_to_itrf(times, leo_gcrf, leo_vel_gcrf)
    svs = [str(s) for s in obs.sv.values]
    rot, _ = gcrf_from_itrf_matrices(times)
    sv_gcrf = np.stack([world.orbits[sv].inertial(t_s)[0] for sv in svs], axis=1)
    sv_pos = np.einsum("nji,nsj->nsi", rot, sv_gcrf)
    terms = antenna_terms(times, svs, leo_pos, leo_vel, sv_pos, sun_position_ef(times),
                          {"G": ["1", "2"]}, PCO)
    el, az = antenna_angles(nominal_body_axes(leo_pos, leo_vel),
                            sv_pos - leo_pos[:, None, :])
    return SimpleNamespace(obs=obs, terms=terms, biases=truth_dataset(biases), map=maps[0],
                           el_deg=el, az_deg=az, settings=sim)

"""A small simulated GPS + BDS-3 arc for the combined-POD tests (ISB, VCE, SD pairs).

One HY-2B-like day of the simulator (leopod.simulate; degree-30 truth field as in
``_simulated_arc``) with GPS L1/L2 (C1W/C2W, L1C/L2W) and BDS-3 B1C/B2a (C1P/C5P, L1P/L5P)
tracked together (Zhang et al. 2024: GPS + BDS-3 B1C/B2a onboard Lutan-1; Jiang et al. 2023:
B1C/B2a onboard HY-2D), ingested and quality-checked in memory per system as the ingest and
quality rules do, and float PODs of a few hours of it: GPS alone, BDS-3 alone and combined.

The noise levels of the codes and phases are chosen so that the ionosphere-free noise of
BDS-3 is :data:`CODE_RATIO` times that of GPS for the code and :data:`PHASE_RATIO` for the
phase (same elevation dependence in both systems), the truth of the variance-component test.
The GNSS clocks are the ordinary (code-referenced) clocks of the simulated products, so that
the code carries no satellite phase bias and the true ISB is the difference of the receiver's
ionosphere-free code biases of the two systems (``if_code_bias_rx_m`` of the bias truth).
"""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import xarray as xr
from _simulated_arc import simulated_gnss_world

from leopod.ambiguity.products import ar_product
from leopod.ambiguity.resolve import ArSettings, resolve_systems
from leopod.estimation.arc import ArcData, run_arc
from leopod.estimation.fixed_arc import FixedSolutions, FloatSolution
from leopod.frames.attitude import antenna_angles, nominal_body_axes
from leopod.gnss.products import GnssProducts
from leopod.gnss.quality import QualitySettings, assess_quality, merge_systems
from leopod.ingest import apriori_from_spp, canonical_observations, gnss_at_epochs
from leopod.io.clock import read_rinex_clock
from leopod.io.rinex_obs import read_rinex_obs
from leopod.io.sp3 import read_sp3
from leopod.signals import frequency_hz, signal_settings
from leopod.simulate.campaign import simulate_leo_day
from leopod.simulate.settings import SimulationSettings
from leopod.workflow.config import load_campaign, with_defaults
from leopod.workflow.settings import pod_settings

REPO = Path(__file__).resolve().parents[2]
DAY, SAT = "2019-001", "hy2b-sim"
T0 = np.datetime64("2019-01-01T00:00", "ns")
#: Signals per system: phase pair, POD code pair (GPS as the default campaign, BDS-3 B1C/B2a
#: pilots as simulated, Jiang et al. 2023).
SIGNALS = {"G": {"phase": ["L1C", "L2W"], "code": ["C1W", "C2W"], "pod_code": ["C1W", "C2W"]},
           "C": {"phase": ["L1P", "L5P"], "code": ["C1P", "C5P"], "pod_code": ["C1P", "C5P"]}}
#: GPS noise at 30° per signal [m] (each code of a pair alike, each phase alike).
GPS_CODE_M, GPS_PHASE_M = 0.06, 0.0015
#: Ratios of the ionosphere-free noise of BDS-3 to that of GPS (truth of the VCE test).
CODE_RATIO, PHASE_RATIO = 2.0, 0.5
#: LEO antenna offsets of the BDS-3 bands (body frame) [m], beside the campaign's L1/L2.
BDS_PCO = {"B1C": [0.0, 0.0, -0.35], "B2a": [0.0, 0.0, -0.38]}


def if_factor(system: str, pair) -> float:
    """Noise amplification of the ionosphere-free combination of a pair of equal noise."""
    f1, f2 = (frequency_hz(system, s) for s in pair)
    return float(np.hypot(f1**2, f2**2) / (f1**2 - f2**2))


def noise_levels() -> dict:
    """``simulate.observations.noise_m`` of the test world (module docstring)."""
    g_code, g_phase = if_factor("G", ("C1W", "C2W")), if_factor("G", ("L1C", "L2W"))
    c_code, c_phase = if_factor("C", ("C1P", "C5P")), if_factor("C", ("L1P", "L5P"))
    bds_code = CODE_RATIO * GPS_CODE_M * g_code / c_code
    bds_phase = PHASE_RATIO * GPS_PHASE_M * g_phase / c_phase
    return {"C1C": 0.3, "C1W": GPS_CODE_M, "C2W": GPS_CODE_M, "L1C": GPS_PHASE_M,
            "L2W": GPS_PHASE_M, "C1P": bds_code, "C5P": bds_code, "L1P": bds_phase,
            "L5P": bds_phase}


def simulated_world(folder: Path) -> SimpleNamespace:
    """Simulated files of :data:`DAY` in ``folder``, ingested and quality-checked."""
    cfg = load_campaign(REPO / "config" / "config.yaml")
    pco = {**cfg["satellites"][SAT]["antenna_pco_body_m"], **BDS_PCO}
    sim = SimulationSettings.from_config(with_defaults("simulate", {
        "truth": {"gravity_degree": 30},
        "code_bias_maps": [],
        "systems": {"G": ["C1C", "C1W", "C2W", "L1C", "L2W"],
                    "C": ["C1P", "C5P", "L1P", "L5P"]},
        "observations": {"noise_m": noise_levels()}}))
    truth, biases = simulated_gnss_world(folder, sim)
    simulate_leo_day(DAY, SAT, sim, DAY, DAY, truth, biases, pco, rinex3=folder / "o.rnx",
                     truth_sp3=folder / "t.sp3", truth_nc=folder / "t.nc")
    signals = signal_settings(SIGNALS)
    obs = canonical_observations(read_rinex_obs(folder / "o.rnx"), signals)
    orbit, clock = read_sp3(folder / "g.sp3"), read_rinex_clock(folder / "g.clk")
    products = GnssProducts.from_datasets(orbit, clock, T0, max_extrapolation_s=900.0)
    gnss = gnss_at_epochs(products, obs.time.values).reindex(sv=obs.sv.values)
    leo = apriori_from_spp(obs, products, signals, pco)
    el, az = antenna_angles(nominal_body_axes(leo.pos_m.values, leo.vel_m_s.values),
                            gnss.pos_m.values - leo.pos_m.values[:, None, :])
    qs = QualitySettings.from_config(cfg["quality"])
    parts = [assess_quality(obs, el, az, x, sig.phase, sig.code, sig.pod_code, qs)
             for x, sig in signals.items()]
    quality = merge_systems(parts)   # as scripts/quality.py
    with xr.open_dataset(folder / "t.nc") as f:
        truth_day = f.load()
    with xr.open_dataset(folder / "b.nc") as f:
        bias_truth = f.load()
    data = ArcData(obs=[obs], quality=[quality], leo=[leo], orbit=orbit, clock=clock)
    return SimpleNamespace(cfg=cfg, pco=pco, data=data, obs=obs, truth=truth_day,
                           biases=bias_truth, folder=folder)


def float_arc(world: SimpleNamespace, systems, hours=(1.0, 5.0), **pod):
    """Float POD of ``hours`` of the world with the systems ``systems`` (a letter or a list)
    and the default campaign's POD settings updated by ``pod``."""
    section = with_defaults("pod", {**world.cfg["pod"], "system": systems, **pod})
    settings = pod_settings(SIGNALS, section, world.cfg["code_bias"])
    settings.pop("code_correction")
    limits = tuple(T0 + np.timedelta64(round(3600 * h), "s") for h in hours)
    return run_arc(DAY, world.data, settings["signals"], settings["arc"], settings["pod"],
                   settings["forces"], world.pco, limits=limits)


def orbit_error_3d_m(arc, truth: xr.Dataset) -> float:
    """3D RMS of the float orbit minus the truth orbit (ITRF) at the orbit epochs [m]."""
    t = truth.interp(time=arc.orbit.time.values) if "time" in truth.dims else truth
    ref = t["pos_itrf_m"].values if "pos_itrf_m" in t else t["pos_m"].values
    d = arc.orbit.pos_itrf_m.values - ref
    ok = np.isfinite(d).all(axis=1)
    return float(np.sqrt(np.mean(np.sum(d[ok] ** 2, axis=1))))


def resolve_combined(world: SimpleNamespace, arc, ambiguity: dict | None = None):
    """Single-difference AR of a combined float arc, each system with its own OSB-based AR
    product (the simulated Bias-SINEX ``g.bia`` with the ordinary clocks of the POD; Jiang et
    al. 2023) and signals; returns the :class:`~leopod.ambiguity.resolve.Resolution` and the
    ArSettings."""
    amb = arc.ambiguities
    sv = amb.sv.values.astype(str)
    epoch = arc.residuals.time.values[arc.residuals.sizes["time"] // 2]
    signals = signal_settings(SIGNALS)
    wl, ifb = {}, {}
    for x in arc.observations.system_order:
        sig = signals[x]
        mine = sv[np.char.startswith(sv, x)]
        product = ar_product(epoch, mine, sig.phase, sig.pod_code,
                             osb_path=world.folder / "g.bia")
        wl[x], ifb[x] = product.wl_sat_cyc, product.per_ambiguity(mine)
    ar = ArSettings.from_config(with_defaults("ambiguity", {**world.cfg["ambiguity"],
                                                            **(ambiguity or {})}))
    order = {x: signals[x] for x in arc.observations.system_order}
    return resolve_systems(amb, arc.residuals, world.obs, order, wl, ar,
                           sat_if_bias_m=ifb), ar


def fixed_arc(world: SimpleNamespace, arc, constraints, systems, hours=(1.0, 5.0), **pod):
    """The fixed solution of ``arc`` (float solution of :func:`float_arc` with the same
    ``systems``, ``hours`` and ``pod``) with ``constraints``."""
    section = with_defaults("pod", {**world.cfg["pod"], "system": systems, **pod})
    settings = pod_settings(SIGNALS, section, world.cfg["code_bias"])
    limits = tuple(T0 + np.timedelta64(round(3600 * h), "s") for h in hours)
    start = FloatSolution(parameters=arc.parameters, ambiguities=arc.ambiguities,
                          residuals=arc.residuals, orbit=arc.orbit)
    return FixedSolutions(DAY, world.data, settings["signals"], settings["arc"],
                          settings["pod"], settings["forces"], world.pco, start,
                          limits=limits).solve(constraints)

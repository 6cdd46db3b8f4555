"""A small simulated BDS-3 B1C/B2a POD arc with OSB-based ambiguity resolution.

One day of the HY-2D-like campaign (config/hy2d-sim.yaml: BDS-3 only, B1C/B2a, Table 1 antenna
offsets of Jiang et al. 2023) with a degree-30 truth field and no code-bias maps (the
observations do not depend on the degree; the maps are another test's subject), ingested and
quality-checked in memory as the ingest and quality rules do; then the float POD of a few
hours, the single-difference WL/NL fixing with the Bias-SINEX code + phase OSBs
(leopod.gnss.signal_bias, mode ``absolute``) and the fixed POD, as the float_pod, ambiguity
and fixed_pod rules do. The satellite clocks of the products refer to the ionosphere-free
combination of ``clock_reference`` (B1C/B2a ``C1P C5P`` or B1I/B3I ``C2I C6I``); ``code_osb``
False drops the code OSBs from the product (phase OSBs kept) to show what ignoring them does.
The LEO attitude is the campaign's (yaw steering, leopod.frames.leo_attitude) in the simulator
and in every step, unless ``solve`` is given another law for the estimation.
"""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import xarray as xr
from _simulated_arc import simulated_gnss_world

from leopod.ambiguity.products import ar_product
from leopod.ambiguity.resolve import ArSettings, resolve_arc
from leopod.estimation.arc import ArcData, run_arc
from leopod.estimation.fixed_arc import FixedSolutions, FloatSolution, constraints_of
from leopod.frames.attitude import antenna_angles
from leopod.frames.leo_attitude import LeoAttitude, leo_body_axes_ef
from leopod.gnss.products import GnssProducts
from leopod.gnss.quality import QualitySettings, assess_quality
from leopod.gnss.signal_bias import SignalBiases, SignalBiasProduct, correct_signal_biases
from leopod.ingest import apriori_from_spp, canonical_observations, gnss_at_epochs
from leopod.io.bias_sinex import read_bias_sinex
from leopod.io.bias_sinex_write import write_bias_sinex
from leopod.io.clock import read_rinex_clock
from leopod.io.rinex_obs import read_rinex_obs
from leopod.io.sp3 import read_sp3
from leopod.signals import signal_settings
from leopod.simulate.ambiguity_truth import true_single_differences, wrong_fixes
from leopod.simulate.campaign import simulate_leo_day
from leopod.simulate.settings import SimulationSettings
from leopod.workflow.config import load_campaign, with_defaults
from leopod.workflow.settings import pod_settings

REPO = Path(__file__).resolve().parents[2]
CONFIG = REPO / "config" / "hy2d-sim.yaml"
SAT = "hy2d-sim"


def simulate_day(folder: Path, clock_reference: tuple[str, str]) -> SimpleNamespace:
    """Simulate the campaign's first day into ``folder`` with BDS clocks referring to the
    ionosphere-free combination of ``clock_reference``; the same seed gives the same
    geometry, noise and ambiguities whatever the reference (only the satellite code biases,
    hence the OSBs, differ)."""
    cfg = load_campaign(CONFIG)
    day = cfg["start_date"]
    section = {k: v for k, v in cfg["simulate"].items() if k != "code_bias_maps"}
    section["code_bias_maps"] = []
    section["truth"] = {"gravity_degree": 30}
    section["biases"] = {"clock_reference": {"C": list(clock_reference)}}
    sim = SimulationSettings.from_config(with_defaults("simulate", section))
    pco = cfg["satellites"][SAT]["antenna_pco_body_m"]
    attitude = LeoAttitude.of(cfg["satellites"][SAT])
    truth, biases = simulated_gnss_world(folder, sim, day, SAT)
    simulate_leo_day(day, SAT, sim, day, day, truth, biases, pco, rinex3=folder / "o.rnx",
                     truth_sp3=folder / "t.sp3", truth_nc=folder / "t.nc",
                     leo_attitude=attitude)
    codeless = read_bias_sinex(folder / "g.bia")
    codeless = codeless.isel(bias=np.char.startswith(codeless.obs1.values.astype(str), "L"))
    write_bias_sinex(codeless, folder / "g_phase_only.bia")
    return SimpleNamespace(folder=folder, cfg=cfg, pco=pco, attitude=attitude)


def solve(world: SimpleNamespace, hours: tuple[float, float] = (1.0, 5.0), *,
          code_osb: bool = True, attitude: LeoAttitude | None = None) -> dict:
    """Float POD, OSB-based AR and fixed POD of ``hours`` of the simulated day, with the LEO
    attitude law ``attitude`` in ingest, quality and POD (None: the simulated one).

    Returns
    -------
    dict
        ``float_3d_m``, ``fixed_3d_m`` (3D RMS of the orbit minus the truth [m]), ``wrong``
        (:func:`leopod.simulate.ambiguity_truth.wrong_fixes`), ``table`` (AR table),
        ``guard`` (the product guard's verdict), ``code_rms_m`` (float IF code residuals).
    """
    folder, cfg = world.folder, world.cfg
    day = cfg["start_date"]
    date = f"{np.datetime64(day, 'D').astype(object):%Y-%j}"
    t0 = np.datetime64(day, "ns")
    signals = signal_settings(cfg["signals"])
    sig = signals["C"]
    obs = canonical_observations(read_rinex_obs(folder / "o.rnx"), signals)
    orbit, clock = read_sp3(folder / "g.sp3"), read_rinex_clock(folder / "g.clk")
    products = GnssProducts.from_datasets(orbit, clock, t0, max_extrapolation_s=900.0)
    gnss = gnss_at_epochs(products, obs.time.values).reindex(sv=obs.sv.values)
    attitude = world.attitude if attitude is None else attitude
    leo = apriori_from_spp(obs, products, signals, world.pco, attitude=attitude)
    el, az = antenna_angles(leo_body_axes_ef(attitude, obs.time.values, leo.pos_m.values,
                                             leo.vel_m_s.values),
                            gnss.pos_m.values - leo.pos_m.values[:, None, :])
    quality = assess_quality(obs, el, az, "C", sig.phase, sig.code, sig.pod_code,
                             QualitySettings.from_config(cfg["quality"]))
    osb_path = folder / ("g.bia" if code_osb else "g_phase_only.bia")
    biases = SignalBiases({date: SignalBiasProduct.read(date, osb_path)}, "absolute", date)
    data = ArcData(obs=[obs], quality=[quality], leo=[leo], orbit=orbit, clock=clock,
                   signal_biases=biases)
    settings = pod_settings(cfg["signals"], cfg["pod"], cfg["code_bias"])
    settings.pop("code_correction")
    args = (date, data, settings["signals"], settings["arc"], settings["pod"],
            settings["forces"], world.pco)
    limits = tuple(t0 + np.timedelta64(round(3600 * h), "s") for h in hours)
    solution = run_arc(*args, limits=limits, attitude=attitude)
    residuals = solution.residuals
    corrected = correct_signal_biases(obs, biases, sig.observations)[0]
    product = ar_product(residuals.time.values[residuals.sizes["time"] // 2],
                         solution.ambiguities.sv.values, sig.phase, sig.pod_code,
                         osb_path=osb_path, osb_applied=biases.osb_applied)
    ar = ArSettings.from_config(with_defaults("ambiguity", cfg["ambiguity"]))
    table = resolve_arc(solution.ambiguities, residuals, corrected, "C", sig.phase,
                        sig.pod_code, product.wl_sat_cyc, ar,
                        sat_if_bias_m=product.per_ambiguity(solution.ambiguities.sv.values)
                        ).table
    with xr.open_dataset(folder / "t.nc") as f:
        truth = f.load()
    start = FloatSolution(parameters=solution.parameters, ambiguities=solution.ambiguities,
                          residuals=residuals, orbit=solution.orbit)
    fixed = FixedSolutions(*args, start, limits=limits, attitude=attitude).solve(
        constraints_of(table, ar.constraint_sigma_m))
    code = residuals.code_residual_m.values
    return {"float_3d_m": orbit_rms_3d_m(solution.orbit, truth),
            "fixed_3d_m": orbit_rms_3d_m(fixed.orbit, truth),
            "wrong": wrong_fixes(table, *true_single_differences(table, residuals, [truth],
                                                           sig.phase)),
            "table": table, "guard": str(table.attrs.get("product_guard", "")),
            "code_rms_m": float(np.sqrt(np.nanmean(code**2)))}


def orbit_rms_3d_m(orbit: xr.Dataset, truth: xr.Dataset) -> float:
    """3D RMS [m] of the GCRF positions of ``orbit`` minus the truth at its epochs."""
    ref = truth.pos_gcrf_m.sel(time=orbit.time.values)
    diff = orbit.pos_gcrf_m.values - ref.values
    return float(np.sqrt(np.nanmean(np.sum(diff**2, axis=1))))

"""A small simulated POD arc for the estimation tests (float solution and AR table).

One HY-2B-like day of the simulator (leopod.simulate, the default campaign's world with a
degree-30 truth field: the observations do not depend on the degree, the cost halves),
ingested and quality-checked in memory as the ingest and quality rules do, and the float
POD and single-difference ambiguity resolution of a few hours of it with the settings of
the default campaign (config/config.yaml).
"""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import xarray as xr

from leopod.ambiguity.products import ar_product
from leopod.ambiguity.resolve import ArSettings, resolve_arc
from leopod.estimation.arc import ArcData, run_arc, setup_arc
from leopod.frames.attitude import antenna_angles, nominal_body_axes
from leopod.gnss.leo_antenna import antenna_frame_of, leo_antenna
from leopod.gnss.products import GnssProducts
from leopod.gnss.quality import QualitySettings, assess_quality
from leopod.ingest import apriori_from_spp, canonical_observations, gnss_at_epochs
from leopod.io.clock import read_rinex_clock
from leopod.io.rinex_obs import read_rinex_obs
from leopod.io.sp3 import read_sp3
from leopod.signals import signal_settings
from leopod.simulate.campaign import (
    simulate_gnss_products,
    simulate_leo_day,
    simulate_truth,
    simulate_world_truth,
)
from leopod.simulate.settings import SimulationSettings
from leopod.workflow.config import load_campaign, with_defaults
from leopod.workflow.settings import pod_settings

REPO = Path(__file__).resolve().parents[2]
#: The real AIUB LEO antenna pattern of GOCE (Jäggi et al. 2009).
GOCE = REPO.parent / "shared" / "data" / "antex" / "GOCE_MAIN_0001.ATX"
DAY, SAT = "2019-001", "hy2b-sim"
T0 = np.datetime64("2019-01-01T00:00", "ns")


def simulated_gnss_world(folder: Path, sim: SimulationSettings, day: str = DAY,
                         sat: str = SAT):
    """Truth orbit of ``sat`` and the world's biases of a one-day campaign ``day``, with the
    day's GNSS products written to ``folder`` (``g.sp3``, ``g.clk``, ``g_int.clk``, ``g.wsb``,
    ``g.bia``)."""
    truth = simulate_truth(sim, sat, day, day)
    biases = simulate_world_truth(sim, [sat], day, day, biases_path=folder / "b.nc",
                                  stations_path=folder / "s.snx")
    simulate_gnss_products(day, sim, day, day, biases, orbit=folder / "g.sp3",
                           clock=folder / "g.clk", integer_clock=folder / "g_int.clk",
                           wl_bias=folder / "g.wsb", osb=folder / "g.bia")
    return truth, biases


def arc_data(cfg: dict, obs: xr.Dataset, orbit: xr.Dataset, clock: xr.Dataset,
             antenna=None) -> ArcData:
    """The inputs of a GPS float POD of one day: the canonical observations ``obs``
    ingested and quality-checked in memory as the ingest and quality rules do
    (scripts/ingest.py, scripts/quality.py) with the campaign ``cfg``, against the GNSS
    ``orbit`` and ``clock`` products (datasets of read_sp3 and read_rinex_clock), with the
    LEO ``antenna`` (a PCO table or a :class:`leopod.gnss.leo_antenna.LeoAntenna`; default:
    the campaign satellite's PCO table)."""
    signals = signal_settings(cfg["signals"])
    if antenna is None:
        antenna = cfg["satellites"][SAT]["antenna_pco_body_m"]
    products = GnssProducts.from_datasets(orbit, clock, T0, max_extrapolation_s=900.0)
    gnss = gnss_at_epochs(products, obs.time.values).reindex(sv=obs.sv.values)
    leo = apriori_from_spp(obs, products, signals, antenna)
    el, az = antenna_angles(nominal_body_axes(leo.pos_m.values, leo.vel_m_s.values),
                            gnss.pos_m.values - leo.pos_m.values[:, None, :],
                            antenna_frame_of(antenna))
    sig = signals["G"]
    quality = assess_quality(obs, el, az, "G", sig.phase, sig.code, sig.pod_code,
                             QualitySettings.from_config(cfg["quality"]))
    return ArcData(obs=[obs], quality=[quality], leo=[leo], orbit=orbit, clock=clock)


def goce_world(folder: Path) -> SimpleNamespace:
    """The default campaign (``cfg``, its satellite without a PCO table), the GOCE antenna
    (``antenna``, a :class:`leopod.gnss.leo_antenna.LeoAntenna`), the same phase centres
    without PCV (``pco_only``, a body-frame table), the simulation settings (degree-30
    truth field, ``sim``) and the world of :func:`simulated_gnss_world` (``truth``,
    ``biases``) with its products in ``folder``."""
    cfg = load_campaign(REPO / "config" / "config.yaml")
    cfg["satellites"][SAT].pop("antenna_pco_body_m")
    antenna = leo_antenna(None, {"antex": str(GOCE), "type": "GOCE"})
    sim = SimulationSettings.from_config(with_defaults("simulate",
                                                       {"truth": {"gravity_degree": 30}}))
    truth, biases = simulated_gnss_world(folder, sim)
    return SimpleNamespace(cfg=cfg, antenna=antenna, sim=sim, truth=truth, biases=biases,
                           pco_only={band: antenna[band].tolist() for band in antenna})


def ingested_arc_data(folder: Path, cfg: dict, rinex: str, antenna) -> SimpleNamespace:
    """Ingest and quality of the simulated RINEX file ``rinex`` in ``folder`` (products of
    :func:`simulated_gnss_world`) with the LEO antenna ``antenna`` (:func:`arc_data`):
    ``data`` (ArcData), ``obs`` and ``signals`` (the GPS signal settings)."""
    obs = canonical_observations(read_rinex_obs(folder / rinex), signal_settings(cfg["signals"]))
    data = arc_data(cfg, obs, read_sp3(folder / "g.sp3"), read_rinex_clock(folder / "g_int.clk"),
                    antenna)
    return SimpleNamespace(data=data, obs=obs, signals=signal_settings(cfg["signals"])["G"])


def float_pod_arc(folder: Path, cfg: dict, rinex: str, antenna, hours: tuple[float, float]):
    """Float POD of ``hours`` of the :func:`ingested_arc_data` of ``rinex`` with ``antenna``,
    as scripts/float_pod.py does; the ArcOutputs."""
    data = ingested_arc_data(folder, cfg, rinex, antenna).data
    settings = pod_settings(cfg["signals"], cfg["pod"], cfg["code_bias"])
    settings.pop("code_correction")
    limits = tuple(T0 + np.timedelta64(round(3600 * h), "s") for h in hours)
    return run_arc(DAY, data, settings["signals"], settings["arc"], settings["pod"],
                   settings["forces"], antenna, limits=limits)


def simulated_arc(folder: Path, hours: tuple[float, float] = (1.0, 5.0), *,
                  ar_fault: str = "none", ambiguity: dict | None = None) -> SimpleNamespace:
    """Files of :data:`DAY` in ``folder``, and the float POD and AR of ``hours`` of it.

    ``ar_fault`` is the simulator's AR product fault (``simulate.products.ar_fault``);
    ``ambiguity`` overrides keys of the campaign's ``ambiguity`` section.

    Returns
    -------
    SimpleNamespace
        ``args`` (positional arguments of run_arc: date, data, signals, arc, pod, forces,
        pco), ``code_correction``, ``limits``, ``float`` (ArcOutputs), ``table`` (AR table),
        ``ar`` (ArSettings) and ``truth`` (truth orbit, GCRF/ITRF).
    """
    cfg = load_campaign(REPO / "config" / "config.yaml")
    pco = cfg["satellites"][SAT]["antenna_pco_body_m"]
    sim = SimulationSettings.from_config(with_defaults(
        "simulate", {"truth": {"gravity_degree": 30}, "products": {"ar_fault": ar_fault}}))
    truth, biases = simulated_gnss_world(folder, sim)
    simulate_leo_day(DAY, SAT, sim, DAY, DAY, truth, biases, pco, rinex3=folder / "o.rnx",
                     truth_sp3=folder / "t.sp3", truth_nc=folder / "t.nc")
    # ingest and quality (scripts/ingest.py, scripts/quality.py)
    ingested = ingested_arc_data(folder, cfg, "o.rnx", pco)
    obs, sig = ingested.obs, ingested.signals
    # float POD of the arc and its AR (scripts/float_pod.py, scripts/ambiguity.py)
    data = ingested.data
    settings = pod_settings(cfg["signals"], cfg["pod"], cfg["code_bias"])
    code_correction = settings.pop("code_correction")
    args = (DAY, data, settings["signals"], settings["arc"], settings["pod"],
            settings["forces"], pco)
    limits = tuple(T0 + np.timedelta64(round(3600 * h), "s") for h in hours)
    arc = run_arc(*args, limits=limits)
    residuals = arc.residuals
    product = ar_product(residuals.time.values[residuals.sizes["time"] // 2],
                         arc.ambiguities.sv.values, sig.phase, sig.pod_code,
                         wl_bias_path=folder / "g.wsb")
    ar = ArSettings.from_config(with_defaults("ambiguity",
                                              {**cfg["ambiguity"], **(ambiguity or {})}))
    resolution = resolve_arc(arc.ambiguities, residuals, obs, "G", sig.phase, sig.pod_code,
                             product.wl_sat_cyc, ar)
    with xr.open_dataset(folder / "t.nc") as f:
        truth_day = f.load()
    return SimpleNamespace(args=args, code_correction=code_correction, limits=limits,
                           float=arc, table=resolution.table, ar=ar, truth=truth_day,
                           constraints=resolution.constraints, obs=obs, product=product,
                           signals=sig)


def at_float_orbit(ref: SimpleNamespace) -> SimpleNamespace:
    """``ref`` of :func:`simulated_arc` with ``problem`` (the arc set up with its float orbit as
    a-priori, as scripts/kinematic_pod.py does) and ``pod`` (the POD settings) added."""
    date, data, signals, arc_settings, pod, forces, pco = ref.args
    ref.problem = setup_arc(date, data, signals, arc_settings, forces, pco,
                            code_correction=ref.code_correction, limits=ref.limits,
                            apriori_orbit=ref.float.orbit.pos_itrf_m)
    ref.pod = pod
    return ref

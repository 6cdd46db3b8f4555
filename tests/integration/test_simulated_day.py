"""Closed loop on one simulated HY-2B-like day: files -> ingest -> quality, against the truth.

Authorities: the simulation truth (orbit, receiver clock, passes, antenna angles) written
beside the files; the code-noise levels put into the simulation are the typical 2-min
STDs of epoch-differenced code minus carrier of Peng et al. (2021) (C1 0.46 m, P1 0.09 m,
P2 0.02 m, sec. II-B), which the quality step must find again; the HY-2B P1 code-bias map of
Peng et al. (2021) (a crescent rising to ~3 m between azimuths 120° and 240° at low
elevation), which legitimately moves the HMW combination there.
"""

from dataclasses import replace

import numpy as np
import pytest
import xarray as xr

from leopod.frames.attitude import antenna_angles, nominal_body_axes
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
from leopod.workflow.config import section_defaults, with_defaults

SIGNALS = signal_settings({"G": {"phase": ["L1C", "L2W"], "code": ["C1C", "C1W", "C2W"],
                                 "pod_code": ["C1W", "C2W"]}})
PCO = {"L1": [0.0, 0.0, -0.35], "L2": [0.0, 0.0, -0.37]}
DAY, SAT = "2019-002", "hy2b-sim"
START, END = DAY, DAY
#: Degree-30 truth field: the observations do not depend on it, the cost halves.
SETTINGS = SimulationSettings.from_config(with_defaults("simulate",
                                                       {"truth": {"gravity_degree": 30}}))


def _leo_day(folder, settings, truth, biases):
    simulate_leo_day(DAY, SAT, settings, START, END, truth, biases, PCO,
                     rinex3=folder / "o.rnx", truth_sp3=folder / "t.sp3",
                     truth_nc=folder / "t.nc")
    obs = canonical_observations(read_rinex_obs(folder / "o.rnx"), SIGNALS)
    products = GnssProducts.from_datasets(read_sp3(folder / "g.sp3"),
                                          read_rinex_clock(folder / "g.clk"),
                                          obs.time.values[0].astype("datetime64[D]"))
    return obs, products


@pytest.fixture(scope="module")
def world(tmp_path_factory):
    """Truth orbit of a one-day campaign, its biases and the day's GNSS products."""
    d = tmp_path_factory.mktemp("sim")
    truth = simulate_truth(SETTINGS, SAT, START, END)
    biases = simulate_world_truth(SETTINGS, [SAT], START, END, biases_path=d / "b.nc",
                                  stations_path=d / "s.snx")
    simulate_gnss_products(DAY, SETTINGS, START, END, biases, orbit=d / "g.sp3",
                           clock=d / "g.clk", integer_clock=d / "g_int.clk",
                           wl_bias=d / "g.wsb", osb=d / "g.bia")
    return {"dir": d, "truth": truth, "biases": biases}


@pytest.fixture(scope="module")
def day(world):
    d = world["dir"]
    obs, products = _leo_day(d, SETTINGS, world["truth"], world["biases"])
    gnss = gnss_at_epochs(products, obs.time.values)
    leo = apriori_from_spp(obs, products, SIGNALS, PCO)
    with xr.open_dataset(d / "t.nc") as f:
        truth = f.load()
    return {"obs": obs, "gnss": gnss, "leo": leo, "truth": truth}


def _radial_and_3d_errors(leo, truth):
    pos = truth.pos_itrf_m.sel(time=leo.time).values
    err = leo.pos_m.values - pos
    radial = np.sum(err * pos, axis=1) / np.linalg.norm(pos, axis=1)
    return radial, np.linalg.norm(err, axis=1)


def test_apriori_orbit_against_truth(day, world):
    # Without the P1 code-bias map (removed with its true value) the code-only orbit is at
    # the noise budget: ionosphere-free P-code noise sqrt((2.55 * 0.064)^2 + (1.55 *
    # 0.014)^2) = 0.17 m at 30 deg (x3.5 at the horizon) times PDOP ~1.6, reduced by the
    # smoothing: a few decimetres, metres at worst.
    obs, truth = day["obs"], day["truth"]
    products = GnssProducts.from_datasets(read_sp3(world["dir"] / "g.sp3"),
                                          read_rinex_clock(world["dir"] / "g.clk"),
                                          obs.time.values[0].astype("datetime64[D]"))
    true_map = truth.code_bias_map_C1W_m.sel(obs_time=obs.time.values, sv=obs.sv.values)
    clean = obs.assign(C1W=obs.C1W - true_map.fillna(0.0).values)
    leo = apriori_from_spp(clean, products, SIGNALS, PCO)
    radial, err = _radial_and_3d_errors(leo, truth)
    ok = np.isfinite(err)
    assert ok.mean() > 0.99
    # measured 2026-11-25: 3D RMS 0.244 m, max 1.06 m, clock STD 0.227 m; bounds +20-25 %
    assert np.sqrt(np.mean(err[ok] ** 2)) < 0.30
    assert np.max(err[ok]) < 1.3
    clk_true = truth.clk_rx_true_s.sel(obs_time=leo.time).values * 299_792_458.0
    assert np.nanstd(leo.clk_rx_m.values - clk_true) < 0.28
    # With the map (2.55 x 0.5-3 m in the ionosphere-free code, larger at low elevation) the
    # code-only orbit moves radially by metres: the effect Peng et al. (2021) corrects with the map.
    radial_map, _ = _radial_and_3d_errors(day["leo"], truth)
    # (measured 2026-11-25: mean radial 3.81 m with the map, −0.002 m without; bound −20 %)
    assert abs(np.nanmean(radial_map)) > 3.0 + abs(np.nanmean(radial[ok]))


def _quality(obs, gnss, leo):
    rot = nominal_body_axes(leo.pos_m.values, leo.vel_m_s.values)
    el, az = antenna_angles(rot, gnss.pos_m.sel(sv=obs.sv).values - leo.pos_m.values[:, None, :])
    q = assess_quality(obs, el, az, "G", ["L1C", "L2W"], ["C1C", "C1W", "C2W"], ["C1W", "C2W"],
                       QualitySettings.from_config(section_defaults("quality")))
    return q, el


def test_quality_recovers_code_noise_at_10_s(world, tmp_path):
    # Peng et al. (2021) measures noise on 1-s data, where the ionospheric change between epochs
    # that also enters epoch-differenced code minus carrier (2 dI) is negligible; at 30 s it adds
    # ~15 % to the 2-cm P2 level, at 10 s a few per cent. So this check uses 10-s data.
    for name in ("g.sp3", "g.clk"):
        (tmp_path / name).write_bytes((world["dir"] / name).read_bytes())
    obs, products = _leo_day(tmp_path, replace(SETTINGS, interval_s=10.0), world["truth"],
                             world["biases"])
    q, _ = _quality(obs, gnss_at_epochs(products, obs.time.values),
                    apriori_from_spp(obs, products, SIGNALS, PCO))
    # typical (histogram-peak) STDs put in: Peng et al. (2021) C1 0.46, P1 0.09, P2 0.02 m,
    # within 25 %
    assert float(q.G_noise_C1C_peak_m) == pytest.approx(0.46, rel=0.25)
    assert float(q.G_noise_C1W_peak_m) == pytest.approx(0.09, rel=0.25)
    assert float(q.G_noise_C2W_peak_m) == pytest.approx(0.02, rel=0.25)


def test_quality_recovers_passes_and_angles(day):
    obs, gnss, leo = day["obs"], day["gnss"], day["leo"]
    q, el = _quality(obs, gnss, leo)
    truth = day["truth"].sel(obs_time=obs.time.values, sv=obs.sv.values)
    tp = truth.pass_true.values
    n_true = len(np.unique(tp[tp >= 0]))
    # within each detected pass the true pass never changes (no missed slip or gap)
    pid = q.pass_id.values
    for p in np.unique(pid[pid >= 0]):
        assert len(np.unique(tp[pid == p])) == 1
    # false boundaries: the HY-2B map moves HMW by up to ~2 wide-lane cycles within a pass
    # in its crescent (azimuth 120-240°, elevation < 15°), which the MW detector may take
    # for slips; elsewhere almost none are added
    prev = np.vstack([np.full((1, tp.shape[1]), -1), tp[:-1]])
    new_true = (tp >= 0) & (tp != prev)
    new_found = np.zeros_like(new_true)
    prev_pid = np.vstack([np.full((1, pid.shape[1]), -1), pid[:-1]])
    new_found[(pid >= 0) & (pid != prev_pid)] = True
    false = new_found & ~new_true & (tp >= 0)
    az_t, el_t = truth.az_deg.values, truth.el_deg.values
    crescent = (az_t > 110.0) & (az_t < 250.0) & (el_t < 15.0)
    assert (false & ~crescent).sum() <= 0.05 * n_true
    assert int(q.G_n_passes) <= 1.35 * n_true
    # angles from the a-priori orbit match the true elevations
    m = np.isfinite(el_t) & np.isfinite(el)
    assert np.max(np.abs(el[m] - el_t[m])) < 0.05

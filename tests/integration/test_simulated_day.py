"""Closed loop on one simulated HY-2B-like day: files -> ingest -> quality, against the truth.

Authorities: the simulation truth (orbit, receiver clock, passes) written beside the files;
the code-noise levels put into the simulation are seed 000's typical 2-min STDs of
epoch-differenced code minus carrier (C1 0.46 m, P1 0.09 m, P2 0.02 m, sec. II-B), which the
quality step must find again; georinex as an independent reader of the simulated RINEX.
"""

import numpy as np
import pytest
import xarray as xr

from leopod.frames.attitude import antenna_angles, nominal_body_axes
from leopod.gnss.quality import QualitySettings, assess_quality
from leopod.ingest import apriori_from_spp, canonical_observations, gnss_at_epochs
from leopod.io.clock import read_rinex_clock
from leopod.io.rinex_obs import read_rinex_obs
from leopod.io.sp3 import read_sp3
from leopod.orbit.products import GnssProducts
from leopod.simulate.campaign import SimulationSettings, simulate_gnss_products, simulate_leo_day

SIGNALS = {"G": {"phase": ["L1C", "L2W"], "code": ["C1C", "C1W", "C2W"], "pod_code": ["C1W", "C2W"]}}
PCO = {"L1": [0.0, 0.0, -0.35], "L2": [0.0, 0.0, -0.37]}


@pytest.fixture(scope="module")
def day(tmp_path_factory):
    d = tmp_path_factory.mktemp("sim")
    settings = SimulationSettings()
    simulate_gnss_products("2019-002", "2019-001", settings, d / "g.sp3", d / "g.clk")
    simulate_leo_day("2019-002", "2019-001", "hy2b-sim", settings, d / "o.rnx", d / "t.sp3", d / "t.nc")
    raw = read_rinex_obs(d / "o.rnx")
    obs = canonical_observations(raw, SIGNALS)
    products = GnssProducts.from_datasets(read_sp3(d / "g.sp3"), read_rinex_clock(d / "g.clk"),
                                          obs.time.values[0].astype("datetime64[D]"))
    gnss = gnss_at_epochs(products, obs.time.values)
    leo = apriori_from_spp(obs, products, SIGNALS, PCO)
    with xr.open_dataset(d / "t.nc") as f:
        truth = f.load()
    return dict(dir=d, raw=raw, obs=obs, gnss=gnss, leo=leo, truth=truth)


def test_independent_reader_agrees(day):
    georinex = pytest.importorskip("georinex")
    g = georinex.load(day["dir"] / "o.rnx")
    ours = day["raw"]
    np.testing.assert_allclose(g["P1"].sel(sv=ours.sv).values, ours["P1"].values, atol=1e-6)
    np.testing.assert_allclose(g["L2"].sel(sv=ours.sv).values, ours["L2"].values, atol=1e-6)


def test_truth_orbit_sp3_matches_netcdf(day):
    sp3 = read_sp3(day["dir"] / "t.sp3")
    diff = sp3.pos_m.isel(sv=0).values - day["truth"].pos_m.values
    assert np.max(np.abs(diff)) < 1e-3                    # SP3 resolution 1 mm


def test_apriori_orbit_against_truth(day):
    truth = day["truth"].pos_m.sel(time=day["leo"].time).values
    err = np.linalg.norm(day["leo"].pos_m.values - truth, axis=1)
    ok = np.isfinite(err)
    assert ok.mean() > 0.99
    # error budget of code-only positioning: ionosphere-free P-code noise
    # sqrt((2.55 * 0.064)^2 + (1.55 * 0.014)^2) = 0.17 m at 30 deg (x4 at the horizon) times
    # PDOP ~1.6, reduced by the 11-sample smoothing: a few decimetres, metres at worst
    assert np.sqrt(np.mean(err[ok] ** 2)) < 0.5
    assert np.max(err[ok]) < 5.0
    clk_true = day["truth"].rx_clock_true_s.values * 299_792_458.0
    dclk = day["leo"].clk_rx_m.values - clk_true
    assert np.nanstd(dclk) < 0.5


def _quality(obs, gnss, leo):
    rot = nominal_body_axes(leo.pos_m.values, leo.vel_m_s.values)
    el, az = antenna_angles(rot, gnss.pos_m.sel(sv=obs.sv).values - leo.pos_m.values[:, None, :])
    q = assess_quality(obs, el, az, "G", ["L1C", "L2W"], ["C1C", "C1W", "C2W"], ["C1W", "C2W"],
                       QualitySettings())
    return q, el


def test_quality_recovers_code_noise_at_10_s(tmp_path):
    # Seed 000 measures noise on 1-s data, where the ionospheric change between epochs that
    # also enters epoch-differenced code minus carrier (2 dI) is negligible; at 30 s it adds
    # ~15 % to the 2-cm P2 level, at 10 s a few per cent. So this check uses 10-s data.
    settings = SimulationSettings(interval_s=10.0)
    simulate_gnss_products("2019-002", "2019-001", settings, tmp_path / "g.sp3", tmp_path / "g.clk")
    simulate_leo_day("2019-002", "2019-001", "hy2b-sim", settings, tmp_path / "o.rnx",
                     tmp_path / "t.sp3", tmp_path / "t.nc")
    obs = canonical_observations(read_rinex_obs(tmp_path / "o.rnx"), SIGNALS)
    products = GnssProducts.from_datasets(read_sp3(tmp_path / "g.sp3"),
                                          read_rinex_clock(tmp_path / "g.clk"),
                                          obs.time.values[0].astype("datetime64[D]"))
    q, _ = _quality(obs, gnss_at_epochs(products, obs.time.values),
                    apriori_from_spp(obs, products, SIGNALS, PCO))
    # typical (histogram-peak) STDs put in: seed 000 C1 0.46, P1 0.09, P2 0.02 m, within 25 %
    assert float(q.G_noise_C1C_peak_m) == pytest.approx(0.46, rel=0.25)
    assert float(q.G_noise_C1W_peak_m) == pytest.approx(0.09, rel=0.25)
    assert float(q.G_noise_C2W_peak_m) == pytest.approx(0.02, rel=0.25)


def test_quality_recovers_passes_and_angles(day):
    obs, gnss, leo = day["obs"], day["gnss"], day["leo"]
    q, el = _quality(obs, gnss, leo)
    # every true pass boundary is found, and few false ones are added
    true_pass = day["truth"].pass_true.values
    tp = true_pass[np.isin(day["truth"].obs_time.values, obs.time.values)]
    n_true = len(np.unique(tp[tp >= 0]))
    assert int(q.G_n_passes) >= n_true
    assert int(q.G_n_passes) <= 1.05 * n_true
    # within each detected pass the true pass never changes (no missed slip)
    pid = q.pass_id.values
    for p in np.unique(pid[pid >= 0]):
        assert len(np.unique(tp[pid == p])) == 1
    # angles from the a-priori orbit match the true elevations
    el_true = day["truth"].el_deg.values
    m = np.isfinite(el_true) & np.isfinite(el)
    assert np.max(np.abs(el[m] - el_true[m])) < 0.05

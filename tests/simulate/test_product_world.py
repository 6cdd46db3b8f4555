"""The simulator's GNSS world from the real WHU 2008-279 product set (issue 7).

Authorities: the real files of ../shared/data/products_2008-279_whu (CODE SP3, WHU phase clocks,
WHU Bias-SINEX OSB, CODE P1-C1 DCB) and their documented conventions: Bias-SINEX 1.00
("corrected = observed − OSB"), CODE's DCB sign (P1−C1 = OSB(C1W) − OSB(C1C), the comment of
CODE's code.bia); the HMW combination (Peng et al. 2021, eq. 3) whose satellite term the AR library
reads from the same file (:func:`leopod.ambiguity.wide_lane.sat_wl_bias_osb`).
"""

import numpy as np
import pytest
from _simulated_day import SECTION, simulation
from snakemake.exceptions import WorkflowError

from leopod.ambiguity.wide_lane import hmw_cycles, sat_wl_bias_osb
from leopod.constants import C_LIGHT_M_S
from leopod.frames.earth_rotation import gcrf_to_itrf
from leopod.io.bias_sinex import read_bias_sinex
from leopod.io.clock import read_rinex_clock
from leopod.io.dcb import read_code_dcb
from leopod.io.sp3 import read_sp3
from leopod.signals import frequency_hz
from leopod.simulate.biases import truth_dataset
from leopod.simulate.campaign import _campaign_biases, gnss_world, receiver_clock, simulate_truth
from leopod.simulate.observations import simulate_observations
from leopod.simulate.product_world import ProductSet
from leopod.simulate.settings import DEFAULT_PCO_BODY_M

pytestmark = pytest.mark.shared

DAY = "2008-279"
EPOCH = np.datetime64("2008-10-05T00:00", "ns")
F1, F2 = frequency_hz("G", "L1C"), frequency_hz("G", "L2W")


@pytest.fixture(scope="module")
def files(shared_data):
    d = shared_data / "products_2008-279_whu"
    return ProductSet(orbit=tuple(str(d / f"COD{w}.EPH.Z") for w in (14996, 15000, 15001)),
                      clock=(str(d / "whp15000.clk.Z"),),
                      osb=str(d / "WHU0IGSFIN_20082790000_01D_01D_ABS.BIA.Z"),
                      dcb_p1c1=str(d / "P1C10810_RINEX.DCB.Z"))


def _section(files):
    return {"orbit": list(files.orbit), "clock": files.clock[0], "osb": files.osb,
            "dcb_p1c1": files.dcb_p1c1}


@pytest.fixture(scope="module")
def settings(files):
    return simulation({**SECTION, "gnss_products": _section(files), "code_bias_maps": []})


def test_config_block_builds_the_product_set(files):
    assert simulation({"gnss_products": _section(files)}).gnss_products == files
    assert simulation({}).gnss_products is None
    without_dcb = {k: v for k, v in _section(files).items() if k != "dcb_p1c1"}
    assert simulation({"gnss_products": without_dcb}).gnss_products.dcb_p1c1 is None
    with pytest.raises(WorkflowError, match="'x' was unexpected"):
        simulation({"gnss_products": {**_section(files), "x": 1}})
    with pytest.raises(WorkflowError, match="'osb' is a required property"):
        simulation({"gnss_products": {"orbit": files.orbit[0], "clock": files.clock[0]}})


def test_world_reproduces_the_sp3_orbits_and_clocks(settings, files):
    """At the SP3 nodes the world's GCRF states, rotated back to the ITRF, are the SP3
    positions (interpolation is exact at the nodes); clocks at the samples are the file's."""
    world = gnss_world(settings, DAY, DAY)
    sp3 = read_sp3(files.orbit[1])
    clk = read_rinex_clock(files.clock[0])
    assert len(world.svs) >= 28 and set(world.svs) <= set(map(str, sp3.sv.values))
    nodes = sp3.time.values[::8]
    t_s = ((nodes - EPOCH) / np.timedelta64(1, "s"))[:, None].repeat(len(world.svs), 1)
    pos, vel = world.state_gcrf(world.svs, t_s)
    for j, sv in enumerate(world.svs):
        itrf, _ = gcrf_to_itrf(nodes, pos[:, j], vel[:, j])
        ref = sp3.pos_m.sel(sv=sv, time=nodes).values
        ok = np.isfinite(ref).all(axis=1)
        np.testing.assert_allclose(itrf[ok], ref[ok], atol=1e-6)
    samples = clk.time.values[::120]
    t_c = ((samples - EPOCH) / np.timedelta64(1, "s"))[:, None].repeat(len(world.svs), 1)
    ref = clk.clk_s.sel(sv=world.svs, time=samples).values
    ok = np.isfinite(ref)
    assert ok.mean() > 0.9
    np.testing.assert_array_equal(world.clock_s(world.svs, t_c)[ok], ref[ok])


def test_world_velocity_is_the_rate_of_its_gcrf_position(settings):
    """The GCRF velocity (ITRF Lagrange rate rotated with R v + dR/dt r) is the central
    difference of the GCRF positions (analytic; ±0.5 s steps, truncation < 1 mm/s): a
    missing Earth-rotation term would be off by ~1.9 km/s at GPS radius."""
    world = gnss_world(settings, DAY, DAY)
    t = np.array([3600.0, 43_210.0, 80_000.0])[:, None].repeat(len(world.svs), 1)
    _, vel = world.state_gcrf(world.svs, t)
    ahead, _ = world.state_gcrf(world.svs, t + 0.5)
    behind, _ = world.state_gcrf(world.svs, t - 0.5)
    np.testing.assert_allclose(vel, ahead - behind, atol=1e-3)


def test_satellite_biases_are_the_files_osbs(settings, files):
    world = gnss_world(settings, DAY, DAY)
    biases = _campaign_biases(settings, world.svs, None, DAY)
    osb = read_bias_sinex(files.osb)
    dcb = read_code_dcb(files.dcb_p1c1)
    for sv in ("G01", "G10", "G29"):
        def value(sig, sv=sv):
            return float(osb.value_m.values[(osb.prn.values == sv) & (osb.obs1.values == sig)][0])
        code = biases.code_sat_m.sel(sv=sv)
        assert float(code.sel(code_signal="C1W")) == pytest.approx(value("C1W"), abs=1e-9)
        # CODE: P1-C1 = OSB(C1W) - OSB(C1C)
        assert float(code.sel(code_signal="C1C")) == pytest.approx(
            value("C1W") - float(dcb.dcb_s.sel(sv=sv)) * C_LIGHT_M_S, abs=1e-9)
        lam1 = C_LIGHT_M_S / F1
        assert float(biases.phase_sat_cyc.sel(sv=sv, phase_signal="L1C")) * lam1 == \
            pytest.approx(value("L1C"), abs=1e-9)
    # the simulator's wide-lane satellite bias is the one the AR library reads from the file
    w_sim = truth_dataset(biases)["wl_bias_sat_cyc"].sel(sv=world.svs).values
    w_file = sat_wl_bias_osb(osb, world.svs, EPOCH).values
    np.testing.assert_allclose(w_sim, w_file, atol=1e-9)


def test_simulated_hmw_minus_file_bias_is_integer(settings, files):
    """Closed loop over two hours: observations simulated against the real products; the
    pass-mean HMW minus the satellite WL bias read from the real OSB file (AR library) minus
    the true receiver WL bias is the true integer wide-lane ambiguity (noise ≪ 0.1 cycle)."""
    truth = simulate_truth(settings, "sim", DAY, DAY)
    world = gnss_world(settings, DAY, DAY)
    biases = _campaign_biases(settings, world.svs, "sim", DAY)
    times = EPOCH + np.arange(240) * np.timedelta64(30, "s")
    obs = simulate_observations(
        times, truth, world, receiver_clock(settings, "sim", DAY, DAY), biases,
        settings.signal_codes(), DEFAULT_PCO_BODY_M, (), settings.observations,
        settings.rng("obs/sim"))
    hmw = hmw_cycles(obs.L1C.values * C_LIGHT_M_S / F1, obs.L2W.values * C_LIGHT_M_S / F2,
                     obs.C1W.values, obs.C2W.values, F1, F2)
    w_file = sat_wl_bias_osb(read_bias_sinex(files.osb), list(obs.sv.values), EPOCH).values
    w_rx = float(truth_dataset(biases)["wl_bias_rx_cyc"].sel(system="G"))
    n_wl = obs.amb_L1C_cyc.values - obs.amb_L2W_cyc.values
    passes = obs.pass_true.values
    checked = 0
    for p in np.unique(passes[passes >= 0]):
        sel = (passes == p) & np.isfinite(hmw)
        if sel.sum() < 20:
            continue
        col = np.nonzero(sel)[1][0]
        mean = np.mean(hmw[sel]) - w_file[col] - w_rx
        n_true = n_wl[sel][0]
        assert abs(mean - n_true) < 0.1, (p, mean, n_true)
        checked += 1
    assert checked >= 10

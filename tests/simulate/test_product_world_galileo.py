"""The simulator's GPS + Galileo world from the real CODE 2023-189 product set, which has no
clock file (simulated clocks, real SP3 orbits and Bias-SINEX OSBs).

Authorities: the real files of ../shared/data/products_2023-189_cod_osb (CODE final SP3-d and
Bias-SINEX OSBs of 2023-07-08) and their documented conventions: Bias-SINEX 1.00 ("corrected
= observed − OSB"; SATELLITE_CLOCK_REFERENCE_OBSERVABLES G C1W C2W, E C1C C5Q in the file's
header), the HMW combination (Peng et al. 2021, eq. 3) whose satellite term the AR library reads
from the same file (:func:`leopod.ambiguity.wide_lane.sat_wl_bias_osb`); frequencies of the
Galileo OS SIS ICD (E1 154 f0, E5a 115 f0).
"""

import numpy as np
import pytest
from _simulated_day import SECTION, simulation

from leopod.ambiguity.wide_lane import hmw_cycles, sat_wl_bias_osb
from leopod.constants import C_LIGHT_M_S
from leopod.frames.earth_rotation import gcrf_to_itrf
from leopod.io.bias_sinex import read_bias_sinex
from leopod.io.sp3 import read_sp3
from leopod.signals import frequency_hz
from leopod.simulate.biases import truth_dataset
from leopod.simulate.campaign import _campaign_biases, gnss_world, receiver_clock, simulate_truth
from leopod.simulate.observations import simulate_observations
from leopod.simulate.product_world import ProductSet, product_world

pytestmark = pytest.mark.shared

DAY = "2023-189"
EPOCH = np.datetime64("2023-07-08T00:00", "ns")
SIGNALS = {"G": ["C1C", "C1W", "C2W", "L1C", "L2W"], "E": ["C1C", "C5Q", "L1C", "L5Q"]}
#: HMW pair per system: phases and codes (the clock-reference codes of the file's header)
PAIRS = {"G": (("L1C", "L2W"), ("C1W", "C2W")), "E": (("L1C", "L5Q"), ("C1C", "C5Q"))}
#: One LEO antenna offset for every band: the HMW then holds no geometric difference of the
#: bands (the POD removes that term before the HMW, leopod.gnss.antenna_terms)
PCO = dict.fromkeys(("L1", "L2", "E1", "E5a"), [0.0, 0.0, -0.35])
#: Code noise reduced to 1 cm: the closed-loop test resolves bias errors of 0.05 WL cycles
#: in passes of 10 minutes (at the default noise a pass mean scatters by ~0.1 cycle)
NOISE_M = dict.fromkeys(("C1C", "E:C1C", "C1W", "C2W", "C5Q"), 0.01)


@pytest.fixture(scope="module")
def files(shared_data):
    d = shared_data / "products_2023-189_cod_osb"
    return ProductSet(orbit=(str(d / "COD0OPSFIN_20231890000_01D_05M_ORB.SP3"),), clock=(),
                      osb=str(d / "COD0OPSFIN_20231890000_01D_01D_OSB.BIA"), dcb_p1c1=None)


@pytest.fixture(scope="module")
def settings(files):
    return simulation({**SECTION, "systems": SIGNALS, "code_bias_maps": [], "gnss_antex": None,
                       "observations": {"noise_m": NOISE_M},
                       "gnss_products": {"orbit": files.orbit[0], "clock": None,
                                         "osb": files.osb}})


def _file_osb_ns(path, sv: str, signal: str) -> float:
    """OSB [ns] of one satellite and signal read from the file's text (independent of the
    reader): columns PRN and OBS1 of a BIAS/SOLUTION line, value after the unit."""
    with open(path, encoding="latin-1") as f:
        for line in f:
            parts = line.split()
            if parts[:1] == ["OSB"] and parts[2] == sv and parts[3] == signal:
                return float(parts[parts.index("ns") + 1])
    raise KeyError((sv, signal))


def test_clock_reference_osbs_have_zero_ionosphere_free_part(files):
    """The premise of simulated clocks (leopod.simulate.product_world): CODE's clocks refer to
    the ionosphere-free combination of C1W/C2W (GPS) and C1C/C5Q (Galileo), so the file's OSBs
    of these codes combine to zero (to the file's 0.1 ps rounding), while the codes themselves
    carry ns-level biases."""
    osb = read_bias_sinex(files.osb)
    checked = {"G": 0, "E": 0}
    for system, (_, (c1, c2)) in PAIRS.items():
        f1, f2 = frequency_hz(system, c1), frequency_hz(system, c2)
        # satellite records (station records carry the system letter alone)
        for sv in sorted({str(p) for p in osb.prn.values
                          if str(p).startswith(system) and len(str(p)) == 3}):
            d1, d2 = (_file_osb_ns(files.osb, sv, c) for c in (c1, c2))
            assert abs((f1**2 * d1 - f2**2 * d2) / (f1**2 - f2**2)) < 1e-3, sv
            assert abs(d1 - d2) > 1e-3 or abs(d1) < 1e-3, sv
            checked[system] += 1
    assert checked == {"G": 32, "E": 24}


def test_no_clock_file_means_simulated_clocks(files, settings):
    """``clock: null`` gives a set without clock files; the world then needs simulated clocks
    (a clear error without), keeps the satellites of both systems present in the SP3 and the
    OSB file, and reproduces the SP3 positions at the nodes (exact Lagrange interpolation)."""
    assert settings.gnss_products == files
    with pytest.raises(ValueError, match="no clock file"):
        product_world(files, EPOCH, systems=("G", "E"))
    world = gnss_world(settings, DAY, DAY)
    assert sum(s[0] == "G" for s in world.svs) == 32
    assert sum(s[0] == "E" for s in world.svs) == 24
    t = np.array([0.0, 43_200.0, 86_370.0])[:, None].repeat(len(world.svs), 1)
    clk = world.clock_s(world.svs, t)
    assert np.isfinite(clk).all() and np.ptp(clk[0]) > 0
    sp3 = read_sp3(files.orbit[0])
    nodes = sp3.time.values[12:280:24]
    t_s = ((nodes - EPOCH) / np.timedelta64(1, "s"))[:, None].repeat(len(world.svs), 1)
    pos, vel = world.state_gcrf(world.svs, t_s)
    for j, sv in enumerate(world.svs):
        itrf, _ = gcrf_to_itrf(nodes, pos[:, j], vel[:, j])
        np.testing.assert_allclose(itrf, sp3.pos_m.sel(sv=sv, time=nodes).values, atol=1e-6)


def test_galileo_biases_are_the_files_osbs(files, settings):
    """Code biases [m] = code OSB; phase biases [cycles] × λ = phase OSB (Bias-SINEX sign),
    read from the file text; the simulator's WL satellite bias is the AR library's."""
    world = gnss_world(settings, DAY, DAY)
    biases = _campaign_biases(settings, world.svs, None, DAY)
    ns = 1e-9 * C_LIGHT_M_S
    for sv in ("E02", "E19", "E36", "G01"):
        (l1, l2), (c1, c2) = PAIRS[sv[0]]
        for sig in (c1, c2):
            assert float(biases.code_sat_m.sel(sv=sv, code_signal=sig)) == pytest.approx(
                _file_osb_ns(files.osb, sv, sig) * ns, abs=1e-9)
        for sig in (l1, l2):
            lam = C_LIGHT_M_S / frequency_hz(sv[0], sig)
            assert float(biases.phase_sat_cyc.sel(sv=sv, phase_signal=sig)) * lam == \
                pytest.approx(_file_osb_ns(files.osb, sv, sig) * ns, abs=1e-9)
    osb = read_bias_sinex(files.osb)
    w_sim = truth_dataset(biases)["wl_bias_sat_cyc"]
    for system, (phase, code) in PAIRS.items():
        svs = [s for s in world.svs if s[0] == system]
        np.testing.assert_allclose(
            w_sim.sel(sv=svs).values,
            sat_wl_bias_osb(osb, svs, EPOCH, phase=phase, code=code).values, atol=1e-9)


def test_galileo_hmw_minus_file_bias_is_integer(files, settings):
    """Closed loop over two hours against the real CODE orbits and OSBs: per pass, the mean
    HMW minus the satellite WL bias read from the real file (AR library) minus the true
    receiver WL bias is the true integer wide lane, for Galileo E1/E5a and GPS L1/L2 (the
    Galileo L1C ambiguities are those of Galileo, not overwritten by GPS L1C's: a bug of the
    simulator's pass bookkeeping, leopod.simulate.tracking.passes, this test found)."""
    truth = simulate_truth(settings, "sim", DAY, DAY)
    world = gnss_world(settings, DAY, DAY)
    biases = _campaign_biases(settings, world.svs, "sim", DAY)
    times = EPOCH + np.arange(240) * np.timedelta64(30, "s")
    obs = simulate_observations(
        times, truth, world, receiver_clock(settings, "sim", DAY, DAY), biases,
        settings.signal_codes(), PCO, (), settings.observations, settings.rng("obs/sim"))
    osb = read_bias_sinex(files.osb)
    checked = {"G": 0, "E": 0}
    for system, ((l1, l2), (c1, c2)) in PAIRS.items():
        cols = [j for j, s in enumerate(obs.sv.values) if str(s)[0] == system]
        sub = obs.isel(sv=cols)
        f1, f2 = frequency_hz(system, l1), frequency_hz(system, l2)
        hmw = hmw_cycles(sub[l1].values * C_LIGHT_M_S / f1, sub[l2].values * C_LIGHT_M_S / f2,
                         sub[c1].values, sub[c2].values, f1, f2)
        w_file = sat_wl_bias_osb(osb, list(sub.sv.values), EPOCH, phase=(l1, l2),
                                 code=(c1, c2)).values
        w_rx = float(truth_dataset(biases)["wl_bias_rx_cyc"].sel(system=system))
        n_wl = sub[f"amb_{l1}_cyc"].values - sub[f"amb_{l2}_cyc"].values
        passes = sub.pass_true.values
        for p in np.unique(passes[passes >= 0]):
            sel = (passes == p) & np.isfinite(hmw)
            if sel.sum() < 20:
                continue
            col = np.nonzero(sel)[1][0]
            mean = np.mean(hmw[sel]) - w_file[col] - w_rx
            assert abs(mean - n_wl[sel][0]) < 0.05, (system, p, mean, n_wl[sel][0])
            checked[system] += 1
    assert checked["G"] >= 8 and checked["E"] >= 6, checked

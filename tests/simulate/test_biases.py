"""Tests of leopod.simulate.biases: simulated code/phase biases and the AR products.

Authorities:
- analytic truth: noise-free P1, P2, L1, L2 built here from the observation equations of the
  module docstring (random geometry, clocks, ionosphere and integer ambiguities) and combined
  with the independent combination code of leopod.gnss.combinations;
- the real product files in ../shared (CODE DCB and OSB files, WHU OSB file) for the
  clock-reference convention and the bias magnitudes;
- file round trips through the Bias-SINEX and WL readers.
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from leopod.constants import C_LIGHT_M_S
from leopod.gnss.combinations import (
    ionosphere_free,
    melbourne_wuebbena,
    narrow_lane_wavelength_m,
    wide_lane_wavelength_m,
)
from leopod.io.bias_sinex import osb, read_bias_sinex
from leopod.io.bias_sinex_write import write_bias_sinex
from leopod.io.dcb import read_code_dcb
from leopod.io.netcdf import write_netcdf
from leopod.io.wlbias import read_wl_bias
from leopod.io.wlbias_write import write_wl_bias
from leopod.signals import frequency_hz
from leopod.simulate.biases import (
    CLOCK_REFERENCE_CODES,
    BiasSettings,
    ar_products,
    integer_clock_s,
    simulate_biases,
)
from leopod.workflow.config import with_defaults

EPOCH = np.datetime64("2020-06-01T00:00", "ns")
GPS = [f"G{i:02d}" for i in range(1, 33)]
BDS = [f"C{i:02d}" for i in range(19, 47)]
TOL_CYC = 1e-9      # integer property of the HMW combination [WL cycles]
TOL_M = 1e-9        # ionosphere-free combinations [m]
#: Bias magnitudes of the simulator (the schema's defaults).
DEFAULTS = BiasSettings.from_config(with_defaults("simulate_biases", {}))


def _biases(seed=1, drift=0.0, svs=GPS + BDS):
    return simulate_biases(svs, None, np.random.default_rng(seed), epoch=EPOCH,
                           settings=BiasSettings.from_config(with_defaults(
                               "simulate_biases", {"nl_drift_sigma_cyc_per_day": drift})))


def _observations(biases, system, times, rng):
    """Noise-free P1, P2, L1, L2 [m] (time, sv) of one system, with their ingredients."""
    truth = ar_products(biases).truth
    c1, c2 = CLOCK_REFERENCE_CODES[system]
    l1, l2 = biases.phase_pairs[system]
    f1, f2 = frequency_hz(system, c1), frequency_hz(system, c2)
    svs = [s for s in truth["sv"].values if s[0] == system]
    n_t, n_s = len(times), len(svs)
    # ranges and clocks reduced to ±1 km: the identities tested are linear, and float64
    # rounding of 2e7 m ranges (2e-8 WL cycles in the HMW) would hide the 1e-9 cycle check
    rho = rng.uniform(-1e3, 1e3, (n_t, n_s))
    clk_rx_s = rng.uniform(-3e-6, 3e-6, (n_t, 1))
    clk_sat_s = rng.uniform(-3e-6, 3e-6, (n_t, n_s))
    iono_m = rng.uniform(0.5, 30.0, (n_t, n_s))            # slant ionosphere on f1
    n1 = rng.integers(-10**6, 10**6, (1, n_s)).astype(float)
    n2 = n1 - rng.integers(-50, 50, (1, n_s))
    sat = truth.sel(sv=svs)
    rx = truth.sel(system=system)
    phase_sat = biases.sat_phase_cyc_at(times).sel(sv=svs)
    geo = rho + C_LIGHT_M_S * (clk_rx_s - clk_sat_s)
    obs = {}
    for code, phase, f, n in ((c1, l1, f1, n1), (c2, l2, f2, n2)):
        gamma = (f1 / f) ** 2
        lam = C_LIGHT_M_S / f
        obs["P" + code[1]] = (geo + gamma * iono_m + float(rx.code_bias_rx_m.sel(code_signal=code))
                              + sat.code_bias_sat_m.sel(code_signal=code).values[None, :])
        obs["L" + code[1]] = (geo - gamma * iono_m
                              + lam * (n + float(rx.phase_bias_rx_cyc.sel(phase_signal=phase))
                                       + phase_sat.sel(phase_signal=phase).values))
    clk = xr.DataArray(clk_sat_s, dims=("time", "sv"), coords={"time": times, "sv": svs})
    return {"obs": obs, "f1": f1, "f2": f2, "rho": rho, "clk_rx_s": clk_rx_s, "clk": clk,
            "n1": n1, "n2": n2, "sat": sat, "rx": rx, "svs": svs, "bands": (c1[1], c2[1])}


TIMES = EPOCH + np.array([0, 3_600, 43_200, 86_399], dtype="timedelta64[s]")


@pytest.mark.parametrize("system", ["G", "C"])
def test_hmw_minus_wide_lane_biases_is_integer(system):
    # analytic truth: HMW/λ_WL − w^s − w_r = N1 − N2 (geometry, clocks, ionosphere cancel)
    b = _biases(drift=0.05)
    s = _observations(b, system, TIMES, np.random.default_rng(7))
    o, f1, f2 = s["obs"], s["f1"], s["f2"]
    p1, p2 = s["bands"]
    hmw_cyc = (melbourne_wuebbena(o["L" + p1], o["L" + p2], o["P" + p1], o["P" + p2], f1, f2)
               / wide_lane_wavelength_m(f1, f2))
    n_wl = hmw_cyc - s["sat"].wl_bias_sat_cyc.values - float(s["rx"].wl_bias_rx_cyc)
    np.testing.assert_allclose(n_wl, np.broadcast_to(s["n1"] - s["n2"], n_wl.shape),
                               rtol=0, atol=TOL_CYC)
    # the biases are not trivially integer: the fractional parts really matter
    frac = s["sat"].wl_bias_sat_cyc.values - np.round(s["sat"].wl_bias_sat_cyc.values)
    assert np.max(np.abs(frac)) > 0.1


@pytest.mark.parametrize("system", ["G", "C"])
def test_integer_clock_gives_integer_if_phase_ambiguity(system):
    # analytic truth: L_IF − ρ − c dt_r + c dt^s_int − (receiver IF phase bias)
    #   = λ_NL N1 + c f2/(f1² − f2²) (N1 − N2), with drift of the NL phase biases on
    b = _biases(drift=0.2)
    s = _observations(b, system, TIMES, np.random.default_rng(8))
    o, f1, f2 = s["obs"], s["f1"], s["f2"]
    p1, p2 = s["bands"]
    clk_int = integer_clock_s(s["clk"], b)
    assert clk_int.dims == ("time", "sv") and clk_int.attrs["units"] == "s"
    l_if = ionosphere_free(o["L" + p1], o["L" + p2], f1, f2)
    amb = (l_if - s["rho"] - C_LIGHT_M_S * s["clk_rx_s"] + C_LIGHT_M_S * clk_int.values
           - float(s["rx"].if_phase_bias_rx_m))
    expected = (narrow_lane_wavelength_m(f1, f2) * s["n1"]
                + C_LIGHT_M_S * f2 / (f1**2 - f2**2) * (s["n1"] - s["n2"]))
    np.testing.assert_allclose(amb, np.broadcast_to(expected, amb.shape), rtol=0, atol=TOL_M)
    # with the ordinary clock the same combination is off by the satellite IF phase bias,
    # which drifts: it differs between the epochs
    amb_plain = amb - C_LIGHT_M_S * (clk_int.values - s["clk"].values)
    assert np.max(np.abs(amb_plain - expected)) > 1e-3
    assert np.ptp(C_LIGHT_M_S * (clk_int.values - s["clk"].values), axis=0).max() > 1e-3


@pytest.mark.parametrize("system", ["G", "C"])
def test_if_code_with_product_clock_has_no_satellite_bias(system):
    # analytic truth + design constraint: IF of the clock-reference code OSBs is zero, so
    # P_IF − ρ − c (dt_r − dt^s) = IF receiver code bias for every satellite
    b = _biases()
    s = _observations(b, system, TIMES, np.random.default_rng(9))
    o, f1, f2 = s["obs"], s["f1"], s["f2"]
    p1, p2 = s["bands"]
    res = (ionosphere_free(o["P" + p1], o["P" + p2], f1, f2) - s["rho"]
           - C_LIGHT_M_S * (s["clk_rx_s"] - s["clk"].values))
    np.testing.assert_allclose(res, float(s["rx"].if_code_bias_rx_m), rtol=0, atol=TOL_M)
    c1, c2 = CLOCK_REFERENCE_CODES[system]
    d = s["sat"].code_bias_sat_m
    np.testing.assert_allclose(ionosphere_free(d.sel(code_signal=c1), d.sel(code_signal=c2),
                                               f1, f2), 0.0, atol=1e-12)


def test_osb_file_corrects_observations(tmp_path):
    # round trip through the Bias-SINEX writer and reader; with the OSBs subtracted
    # ("observation corrected = observation − OSB") the IF phase with the ordinary clock has
    # the integer ambiguity and the HMW has only the receiver wide-lane bias
    b = _biases()
    prods = ar_products(b)
    path = tmp_path / "SIM0LEOFIN_20201530000_01D_01D_OSB.BIA"
    write_bias_sinex(prods.osb, path)
    ds = read_bias_sinex(path)
    assert ds.attrs["satellite_clock_reference_observables_G"] == "C1W C2W"
    assert ds.attrs["satellite_clock_reference_observables_C"] == "C1P C5P"
    s = _observations(b, "G", TIMES[1:2], np.random.default_rng(10))
    t = TIMES[1]
    corr = {key: np.array([[osb(ds, sv, code, t) for sv in s["svs"]]])
            for key, code in (("P1", "C1W"), ("P2", "C2W"), ("L1", "L1C"), ("L2", "L2W"))}
    o = {k: s["obs"][k] - corr[k] for k in corr}
    f1, f2 = s["f1"], s["f2"]
    l_if = ionosphere_free(o["L1"], o["L2"], f1, f2)
    amb = (l_if - s["rho"] - C_LIGHT_M_S * (s["clk_rx_s"] - s["clk"].values)
           - float(s["rx"].if_phase_bias_rx_m))
    expected = (narrow_lane_wavelength_m(f1, f2) * s["n1"]
                + C_LIGHT_M_S * f2 / (f1**2 - f2**2) * (s["n1"] - s["n2"]))
    atol_file_m = 1e-6   # 6 decimals of ns in the file: 5e-7 ns = 0.15 mm/1000
    np.testing.assert_allclose(amb, expected, rtol=0, atol=atol_file_m)
    hmw = (melbourne_wuebbena(o["L1"], o["L2"], o["P1"], o["P2"], f1, f2)
           / wide_lane_wavelength_m(f1, f2))
    np.testing.assert_allclose(hmw - float(s["rx"].wl_bias_rx_cyc), s["n1"] - s["n2"],
                               rtol=0, atol=1e-5)


def test_osb_records_and_phase_drift_windows(tmp_path):
    b = _biases(drift=0.3)
    prods = ar_products(b, window_s=3600.0)
    osb_ds = prods.osb
    # 32 GPS × (3 codes + 2 phases) + 28 BDS × (2 + 2) records per window, 24 windows
    assert osb_ds.sizes["bias"] == 24 * (32 * 5 + 28 * 4)
    path = tmp_path / "sim.bia"
    write_bias_sinex(osb_ds, path)
    ds = read_bias_sinex(path)
    # phase OSB = λ β^s(window centre) [m]; code OSB = d^s
    t_mid = EPOCH + np.timedelta64(5 * 3600 + 1800, "s")
    beta = b.sat_phase_cyc_at([t_mid]).sel(sv="G07", phase_signal="L2W").item()
    lam2 = C_LIGHT_M_S / frequency_hz("G", "L2W")
    assert osb(ds, "G07", "L2W", t_mid) == pytest.approx(lam2 * beta, abs=1e-6)
    assert osb(ds, "C20", "C5P", t_mid) == pytest.approx(
        b.code_sat_m.sel(sv="C20", code_signal="C5P").item(), abs=1e-6)
    # the wide-lane bias does not drift: β1 and β2 drift by the same number of cycles
    beta_t = b.sat_phase_cyc_at(TIMES)
    wl_t = beta_t.sel(phase_signal="L1C") - beta_t.sel(phase_signal="L2W")
    assert float(np.ptp(wl_t.sel(sv=GPS).values, axis=0).max()) < 1e-12


def test_wl_product_has_cnes_sign(tmp_path):
    # CNES convention (module docstring): file value μ^s = −w^s
    b = _biases()
    prods = ar_products(b)
    path = tmp_path / "sim_wl.txt"
    write_wl_bias(prods.wl, path)
    ds = read_wl_bias(path)
    np.testing.assert_allclose(ds["wl_bias_cyc"].sel(sv=GPS + BDS).values[0],
                               -prods.truth["wl_bias_sat_cyc"].sel(sv=GPS + BDS).values,
                               rtol=1e-11, atol=1e-12)
    assert ds.time.values[0] == EPOCH


def test_wl_file_used_as_grg_converter_does(tmp_path):
    # Independent authority for the CNES sign: the public GRG converter (YuanxinPan/clkcomb,
    # utils/grg2snx.cpp, convert2raw_bias with nl = 0, dcb = 0) takes wl = −(file value) and
    # builds phase OSBs OSB_L1 = −wl f2/(f1 (f1 − f2)), OSB_L2 = −wl f1/(f2 (f1 − f2)) [s],
    # subtracted from L1, L2. The corrected HMW must then hold only N1 − N2 + w_r.
    b = _biases()
    path = tmp_path / "wl.txt"
    write_wl_bias(ar_products(b).wl, path)
    s = _observations(b, "G", TIMES, np.random.default_rng(11))
    f1, f2 = s["f1"], s["f2"]
    wl = -read_wl_bias(path)["wl_bias_cyc"].sel(sv=s["svs"]).values
    osb_l1_m = -wl * f2 / (f1 * (f1 - f2)) * C_LIGHT_M_S
    osb_l2_m = -wl * f1 / (f2 * (f1 - f2)) * C_LIGHT_M_S
    o = s["obs"]
    hmw = (melbourne_wuebbena(o["L1"] - osb_l1_m, o["L2"] - osb_l2_m, o["P1"], o["P2"], f1, f2)
           / wide_lane_wavelength_m(f1, f2))
    n_wl = hmw - float(s["rx"].wl_bias_rx_cyc)
    np.testing.assert_allclose(n_wl, np.broadcast_to(s["n1"] - s["n2"], n_wl.shape), rtol=0,
                               atol=TOL_CYC)  # E19.12: 12 digits of a few cycles


def test_magnitudes_and_constellation_datum():
    # zero mean over the constellation (datum of the CODE/WHU DCBs; checked on the real files
    # in test_real_files_clock_reference_and_magnitudes)
    dcb_pair, dcb_c1, phases = [], [], []
    for seed in range(40):
        b = _biases(seed=seed)
        d = b.code_sat_m.sel(sv=GPS) / C_LIGHT_M_S * 1e9   # ns
        pair = d.sel(code_signal="C1W") - d.sel(code_signal="C2W")
        p1c1 = d.sel(code_signal="C1W") - d.sel(code_signal="C1C")
        assert abs(float(pair.mean())) < 1e-9 and abs(float(p1c1.mean())) < 1e-9
        dcb_pair.append(pair.values)
        dcb_c1.append(p1c1.values)
        phases.append(b.phase_sat_cyc.sel(sv=GPS, phase_signal=["L1C", "L2W"]).values)
    n = 32 / 31   # sample std of demeaned draws underestimates sigma by sqrt(31/32)
    assert np.std(dcb_pair) * np.sqrt(n) == pytest.approx(4.0, rel=0.05)
    assert np.std(dcb_c1) * np.sqrt(n) == pytest.approx(1.0, rel=0.05)
    phases = np.concatenate(phases)
    assert phases.min() >= -0.5 and phases.max() < 0.5


@pytest.mark.shared
def test_real_files_clock_reference_and_magnitudes(shared_data):
    # The design constraint (IF of the C1W/C2W satellite OSBs = 0) and the magnitudes of
    # the simulator's default BiasSettings are those of real products.
    f1, f2 = frequency_hz("G", "1"), frequency_hz("G", "2")
    for name in ("products_2008-279_whu/WHU0IGSFIN_20082790000_01D_01D_ABS.BIA.Z",
                 "products_2023-189_cod_osb/COD0OPSFIN_20231890000_01D_01D_OSB.BIA"):
        ds = read_bias_sinex(shared_data / name)
        sat = ds.where((ds.station == "") & ds.prn.str.startswith("G"), drop=True)
        c1w = sat.where(sat.obs1 == "C1W", drop=True).set_index(bias="prn")["value_s"]
        c2w = sat.where(sat.obs1 == "C2W", drop=True).set_index(bias="prn")["value_s"]
        c1w, c2w = xr.align(c1w, c2w, join="inner")
        # IF within the files' rounding (3 decimals of ns in the WHU file)
        assert np.max(np.abs(ionosphere_free(c1w, c2w, f1, f2))) < 2e-12
        std_ns = float((c1w - c2w).std()) * 1e9
        assert 2.5 < std_ns < 5.0   # BiasSettings: 4 ns (WHU 2008: 3.0, COD 2023: 4.8)
    dcb = read_code_dcb(shared_data / "products_2008-279_whu/P1C10810_RINEX.DCB.Z")
    gps = dcb["dcb_s"].sel(sv=[s for s in dcb.sv.values if s.startswith("G")])
    assert float(gps.std()) * 1e9 == pytest.approx(DEFAULTS.dcb_other_sigma_ns, rel=0.1)
    assert abs(float(gps.mean())) < 1e-12


def test_truth_dataset_is_netcdf_ready(tmp_path):
    truth = ar_products(_biases(drift=0.1)).truth
    for name, var in truth.data_vars.items():
        assert var.attrs["units"] and var.attrs["long_name"], name
    path = write_netcdf(truth, tmp_path / "biases.nc", step="simulate")
    with xr.open_dataset(path) as back:
        xr.testing.assert_allclose(back.load()[list(truth.data_vars)], truth, rtol=0, atol=0)
    # deterministic: the same generator seed gives the same biases
    xr.testing.assert_identical(truth, ar_products(_biases(drift=0.1)).truth)


def test_signal_errors():
    rng = np.random.default_rng(0)
    with pytest.raises(ValueError, match="clock-reference codes C1W/C2W"):
        simulate_biases(GPS, {"G": ("C1C", "C2W", "L1C", "L2W")}, rng, epoch=EPOCH,
                        settings=DEFAULTS)
    with pytest.raises(ValueError, match="exactly one phase signal on band 1"):
        simulate_biases(GPS, {"G": ("C1W", "C2W", "L1C", "L1W", "L2W")}, rng, epoch=EPOCH,
                        settings=DEFAULTS)
    with pytest.raises(ValueError, match="system R"):
        simulate_biases(["R01"], None, rng, epoch=EPOCH, settings=DEFAULTS)
    with pytest.raises(ValueError, match="does not divide one day"):
        ar_products(_biases(), window_s=7000.0)


def _b1i_clock_biases(signals):
    settings = BiasSettings.from_config(with_defaults(
        "simulate_biases", {"clock_reference": {"C": ["C2I", "C6I"]}}))
    return simulate_biases(BDS, {"C": signals}, np.random.default_rng(3), epoch=EPOCH,
                           settings=settings)


def test_bds_clocks_of_b1i_b3i_give_b1c_b2a_osbs_a_nonzero_if_part(tmp_path):
    # design constraint (module docstring; Bias-SINEX: the IF code OSB of the clock-reference
    # observables is zero): with clocks of B1I/B3I the IF of C2I/C6I vanishes and that of the
    # B1C/B2a codes does not; the OSB file declares the B1I/B3I reference
    b = _b1i_clock_biases(["C1P", "C5P", "C2I", "C6I", "L1P", "L5P"])
    d = b.code_sat_m

    def if_of(c1, c2):
        return ionosphere_free(d.sel(code_signal=c1), d.sel(code_signal=c2),
                               frequency_hz("C", c1), frequency_hz("C", c2))

    np.testing.assert_allclose(if_of("C2I", "C6I"), 0.0, atol=1e-12)
    # B1C/B2a IF part: 0.68 DCB(B1I-B3I) plus the B1C-B1I and B2a-B3I DCBs (4 and 1 ns
    # sigma), i.e. about 1 m; at least 0.2 m on average
    assert float(np.mean(np.abs(if_of("C1P", "C5P")))) > 0.2
    # B1C refers to B1I and B2a to B3I (nearest in frequency): DCBs of the 'other' sigma (1 ns)
    for code, ref in (("C1P", "C2I"), ("C5P", "C6I")):
        dcb_ns = (d.sel(code_signal=ref) - d.sel(code_signal=code)).values / C_LIGHT_M_S * 1e9
        assert 0.5 < np.std(dcb_ns) < 2.0
    path = tmp_path / "b1i.bia"
    write_bias_sinex(ar_products(b).osb, path)
    assert read_bias_sinex(path).attrs["satellite_clock_reference_observables_C"] == "C2I C6I"


def test_clock_reference_need_not_be_simulated():
    # a B1C/B2a receiver with B1I/B3I clocks: the reference codes are drawn but not output;
    # the B1C/B2a biases keep the law of the previous test: a non-zero IF part, zero mean
    # over the satellites
    b = _b1i_clock_biases(["C1P", "C5P", "L1P", "L5P"])
    assert sorted(b.code_sat_m.code_signal.values) == ["C1P", "C5P"]
    assert b.clock_reference["C"] == ("C2I", "C6I")
    d = b.code_sat_m
    if_part = ionosphere_free(d.sel(code_signal="C1P"), d.sel(code_signal="C5P"),
                              frequency_hz("C", "C1P"), frequency_hz("C", "C5P"))
    assert float(np.mean(np.abs(if_part))) > 0.2
    assert abs(float(np.mean(if_part))) < 1e-9   # demeaned DCBs: the IGS datum
    # default settings keep the B1C/B2a clock reference and a zero IF part
    d0 = _biases(svs=BDS).code_sat_m
    np.testing.assert_allclose(ionosphere_free(
        d0.sel(code_signal="C1P"), d0.sel(code_signal="C5P"), frequency_hz("C", "C1P"),
        frequency_hz("C", "C5P")), 0.0, atol=1e-12)

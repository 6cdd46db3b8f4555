"""Tests of leopod.ambiguity.wide_lane.

Authorities:
- analytic truth: observations built from the observation equations of
  leopod.simulate.biases (integers + biases) give HMW/λ_WL = N_WL + w_r + w^s exactly;
- brute force: per-pass and per-pair statistics recomputed with explicit loops and sets of
  common epochs;
- the simulator's true w^s (leopod.simulate.biases.truth_dataset, independent formula from the
  drawn β and d) against w^s recovered from the written CNES WL and Bias-SINEX OSB files;
- closed loop: synthetic HMW (integers + biases + white noise) -> exact SD integers and
  sigmas consistent with the noise;
- the real WHU OSB file (runs, finite values per GPS satellite).
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from _ambiguity_scenario import BIASES, EPOCH, GPS, W_RX_CYC, scenario

from leopod.ambiguity.pairs import sd_pairs
from leopod.ambiguity.wide_lane import (
    hmw_cycles,
    pass_hmw,
    sat_osb_m,
    sat_wl_bias_cnes,
    sat_wl_bias_osb,
    sd_wide_lane,
)
from leopod.constants import C_LIGHT_M_S
from leopod.io.bias_sinex import read_bias_sinex
from leopod.io.bias_sinex_write import write_bias_sinex
from leopod.io.wlbias import read_wl_bias
from leopod.io.wlbias_write import write_wl_bias
from leopod.signals import frequency_hz
from leopod.simulate.biases import ar_products, simulate_biases

BDS = [f"C{i:02d}" for i in range(19, 47)]


def test_hmw_cycles_is_integer_plus_wide_lane_biases():
    # analytic truth: P_i = ρ + γ_i I + d_i, L_i = ρ − γ_i I + λ_i (N_i + β_i)
    rng = np.random.default_rng(1)
    f1, f2 = frequency_hz("G", "1"), frequency_hz("G", "2")
    rho = rng.uniform(-1e3, 1e3, 50)
    iono = rng.uniform(0.5, 20.0, 50)
    n1 = rng.integers(-1000, 1000, 50)
    n2 = n1 - rng.integers(-20, 20, 50)
    d1, d2, b1, b2 = 0.7, -0.4, 0.21, -0.33
    lam1, lam2 = C_LIGHT_M_S / f1, C_LIGHT_M_S / f2
    g2 = (f1 / f2) ** 2
    p1, p2 = rho + iono + d1, rho + g2 * iono + d2
    l1, l2 = rho - iono + lam1 * (n1 + b1), rho - g2 * iono + lam2 * (n2 + b2)
    lam_wl = C_LIGHT_M_S / (f1 - f2)
    w = b1 - b2 - (f1 * d1 + f2 * d2) / ((f1 + f2) * lam_wl)
    np.testing.assert_allclose(hmw_cycles(l1, l2, p1, p2, f1, f2), n1 - n2 + w, rtol=0,
                               atol=1e-9)


def test_pass_hmw_matches_brute_force():
    s = scenario(seed=4, hours=3.0)
    ds = pass_hmw(s.hmw, s.pass_id)
    h, pid = s.hmw.values, s.pass_id.values
    assert ds.sizes["pass"] == s.amb.sizes["ambiguity"]
    for k, p in enumerate(ds["pass_id"].values):
        t, col = np.nonzero((pid == p) & np.isfinite(h))
        values = h[t, col]
        assert ds["sv"].values[k] == s.svs[col[0]]
        assert ds["start"].values[k] == s.times[t.min()]
        assert ds["end"].values[k] == s.times[t.max()]
        assert ds["n_epochs"].values[k] == values.size
        assert ds["hmw_mean_cyc"].values[k] == pytest.approx(values.mean(), abs=1e-12)
        assert ds["hmw_std_cyc"].values[k] == pytest.approx(values.std(ddof=1), abs=1e-12)
        assert ds["hmw_sigma_cyc"].values[k] == pytest.approx(
            values.std(ddof=1) / np.sqrt(values.size), abs=1e-12)
    for name in ("hmw_mean_cyc", "hmw_std_cyc", "hmw_sigma_cyc"):
        assert ds[name].attrs["units"] == "1"


def test_sd_wide_lane_matches_brute_force_over_common_epochs():
    s = scenario(seed=5, hours=3.0)
    pairs = sd_pairs(s.amb.sv.values, s.amb.start.values, s.amb.end.values, min_common_s=0.0)
    # add a pair without common epochs (same time span is impossible for one satellite)
    i = np.append(pairs.i, 0)
    j = np.append(pairs.j, int(np.nonzero(s.amb.sv.values == s.amb.sv.values[0])[0][-1]))
    sd = sd_wide_lane(s.hmw, s.pass_id, i, j)
    h, pid = s.hmw.values, s.pass_id.values
    for k in range(i.size):
        ci, cj = s.col_of[s.amb.sv.values[i[k]]], s.col_of[s.amb.sv.values[j[k]]]
        ti = set(np.nonzero((pid[:, ci] == i[k]) & np.isfinite(h[:, ci]))[0])
        tj = set(np.nonzero((pid[:, cj] == j[k]) & np.isfinite(h[:, cj]))[0])
        common = np.array(sorted(ti & tj), dtype=int)
        assert sd.n_common[k] == common.size
        if common.size < 2:
            assert np.isnan(sd.std_cyc[k])
            continue
        diff = h[common, ci] - h[common, cj]
        assert sd.value_cyc[k] == pytest.approx(diff.mean(), abs=1e-12)
        assert sd.std_cyc[k] == pytest.approx(diff.std(ddof=1), abs=1e-12)
        assert sd.sigma_cyc[k] == pytest.approx(diff.std(ddof=1) / np.sqrt(common.size),
                                                abs=1e-12)
    assert sd.n_common[-1] == 0 and np.isnan(sd.value_cyc[-1])


def test_sd_wide_lane_closed_loop_integers_and_sigmas():
    # synthetic HMW = N_WL + w_r + w^s + N(0, 0.3²): after removing the true w^s the SD over
    # the common epochs must round to the true ΔN_WL, with σ consistent with the noise
    s = scenario(seed=6, hours=8.0)
    pairs = sd_pairs(s.amb.sv.values, s.amb.start.values, s.amb.end.values)
    sd = sd_wide_lane(s.hmw, s.pass_id, pairs.i, pairs.j, s.truth["wl_bias_sat_cyc"])
    truth = s.n_wl[pairs.i] - s.n_wl[pairs.j]
    assert pairs.i.size > 150
    np.testing.assert_array_equal(np.floor(sd.value_cyc + 0.5), truth)
    # per-epoch SD noise: sqrt(2) * 0.3 cycles (independent white noise on both passes)
    np.testing.assert_allclose(np.median(sd.std_cyc), np.sqrt(2) * s.sigma_hmw_cyc, rtol=0.05)
    z = (sd.value_cyc - truth) / sd.sigma_cyc
    assert 0.8 < np.std(z) < 1.2 and abs(np.mean(z)) < 0.25
    # the receiver bias cancels: without satellite biases the SD is off by w^s_i − w^s_j only
    raw = sd_wide_lane(s.hmw, s.pass_id, pairs.i, pairs.j)
    w = s.truth["wl_bias_sat_cyc"].sel(sv=s.amb.sv.values).values
    np.testing.assert_allclose(raw.value_cyc - sd.value_cyc, w[pairs.i] - w[pairs.j],
                               rtol=0, atol=1e-12)
    assert W_RX_CYC != 0.0


def test_sd_wide_lane_errors():
    s = scenario(seed=7, hours=2.0)
    with pytest.raises(ValueError, match="not in pass_id"):
        sd_wide_lane(s.hmw, s.pass_id, [0], [10_000])
    bad = s.pass_id.copy()
    bad.values[bad.values[:, 1] >= 0, 1] = int(s.pass_id.values[:, 0].max())
    with pytest.raises(ValueError, match="more than one satellite"):
        sd_wide_lane(s.hmw, bad, [0], [1])
    with pytest.raises(ValueError, match="equal length"):
        sd_wide_lane(s.hmw, s.pass_id, [0, 1], [1])


def test_pass_without_hmw_data_gives_an_unfixable_pair():
    """A pass whose codes were all dropped (phase only: no HMW) leaves its pairs without a
    common epoch (NaN, never fixed) and the other pairs as they were (analytic: the SD
    mean uses only epochs of both passes)."""
    s = scenario(seed=7, hours=2.0)
    pid = s.pass_id.values
    first, second = (int(pid[pid[:, c] >= 0, c][0]) for c in (0, 1))
    other = int(pid[pid[:, 2] >= 0, 2][0])
    full = sd_wide_lane(s.hmw, s.pass_id, [first, first], [second, other])
    hmw = s.hmw.copy()
    hmw.values[pid == second] = np.nan
    part = sd_wide_lane(hmw, s.pass_id, [first, first], [second, other])
    assert part.n_common[0] == 0 and np.isnan(part.value_cyc[0]) and np.isnan(part.sigma_cyc[0])
    assert part.value_cyc[1] == full.value_cyc[1] and part.n_common[1] == full.n_common[1]


def _biases(seed=2, svs=GPS + BDS):
    return simulate_biases(svs, None, np.random.default_rng(seed), epoch=EPOCH, settings=BIASES)


def test_wl_bias_from_cnes_file_equals_simulator_truth(tmp_path):
    # the file holds μ^s = −w^s (CNES sign); the reader-to-w^s step must undo it exactly
    prods = ar_products(_biases())
    path = tmp_path / "wl.txt"
    write_wl_bias(prods.wl, path)
    w = sat_wl_bias_cnes(read_wl_bias(path), EPOCH + np.timedelta64(5, "h"))
    truth = prods.truth["wl_bias_sat_cyc"].sel(sv=w["sv"].values).values
    np.testing.assert_allclose(w.values, truth, rtol=0, atol=1e-10)   # E19.12 in the file
    assert np.max(np.abs(truth)) > 0.3


def test_wl_bias_from_osb_file_equals_simulator_truth(tmp_path):
    # w^s from the HMW combination of the written and re-read OSBs = simulator truth
    # (β1 − β2 − (f1 d1 + f2 d2)/((f1 + f2) λ_WL) from the drawn biases)
    prods = ar_products(_biases(), window_s=6 * 3600.0)
    path = tmp_path / "osb.bia"
    write_bias_sinex(prods.osb, path)
    ds = read_bias_sinex(path)
    t = EPOCH + np.timedelta64(7, "h")
    atol_cyc = 1e-5   # 6 decimals of ns in the file: 1.5e-7 m on a 0.19 m wavelength
    for system, phase, code, svs in (("G", ("L1C", "L2W"), ("C1W", "C2W"), GPS),
                                     ("C", ("L1P", "L5P"), ("C1P", "C5P"), BDS)):
        w = sat_wl_bias_osb(ds, svs, t, phase=phase, code=code)
        truth = prods.truth["wl_bias_sat_cyc"].sel(sv=svs).values
        np.testing.assert_allclose(w.values, truth, rtol=0, atol=atol_cyc, err_msg=system)
    with pytest.raises(ValueError, match="not on the bands"):
        sat_wl_bias_osb(ds, GPS, t, phase=("L1C", "L2W"), code=("C2W", "C1W"))


def test_osb_table_and_cnes_epoch_selection():
    wl = xr.Dataset({"wl_bias_cyc": (("time", "sv"), [[0.1, 0.2], [0.3, np.nan]])},
                    coords={"time": [EPOCH, EPOCH + np.timedelta64(1, "D")],
                            "sv": ["G01", "G02"]})
    np.testing.assert_allclose(sat_wl_bias_cnes(wl, EPOCH + np.timedelta64(23, "h")),
                               [-0.1, -0.2])
    day2 = sat_wl_bias_cnes(wl, EPOCH + np.timedelta64(1, "D"))
    assert day2.values[0] == -0.3 and np.isnan(day2.values[1])
    with pytest.raises(KeyError, match="no WL record"):
        sat_wl_bias_cnes(wl, EPOCH - np.timedelta64(1, "s"))
    prods = ar_products(_biases(svs=GPS[:3]))
    table = sat_osb_m(prods.osb.assign(value_m=prods.osb.value_s * C_LIGHT_M_S),
                      ["G01", "G40"], ["C1W", "L5Q"], EPOCH)
    assert table.dims == ("sv", "signal")
    assert table.sel(sv="G01", signal="C1W").item() == pytest.approx(
        prods.truth["code_bias_sat_m"].sel(sv="G01", code_signal="C1W").item(), abs=1e-12)
    assert np.isnan(table.sel(sv="G40").values).all()
    assert np.isnan(table.sel(signal="L5Q").values).all()


@pytest.mark.shared
def test_real_whu_osb_gives_finite_wide_lane_biases(shared_data):
    ds = read_bias_sinex(shared_data / "products_2008-279_whu"
                         / "WHU0IGSFIN_20082790000_01D_01D_ABS.BIA.Z")
    svs = sorted({str(p) for p in ds.prn.values if str(p).startswith("G")})
    assert len(svs) == 32
    w = sat_wl_bias_osb(ds, svs, "2008-10-05T12:00:00")
    assert np.all(np.isfinite(w.values))
    assert np.all(np.abs(w.values) < 100.0)   # WL cycles: biases of a few ns at most

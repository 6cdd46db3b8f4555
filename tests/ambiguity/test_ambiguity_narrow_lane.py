"""Tests of leopod.ambiguity.narrow_lane.

Authorities:
- analytic truth: float IF ambiguities generated from B = λ_NL N1 + λ_NL f2/(f1 − f2) N_WL
  + b_r + b^s (Peng et al. 2021, eq. (5)); noise-free they must give the true ΔN1 exactly, and the
  fixed IF value must reproduce the noise-free ΔB;
- brute force: covariance of the single differences as D C D^T with an explicit ±1 matrix;
- the simulator's truth ``if_phase_bias_sat_m`` (c (dt^s − dt^s_int), from the drawn β)
  against the IF of the phase OSBs read back from the written Bias-SINEX file;
- closed loop with noise drawn from the known covariance: normalised errors have unit STD.
"""

from __future__ import annotations

import numpy as np
import pytest
from _ambiguity_scenario import BIASES, EPOCH, F1, F2, GPS, LAMBDA_NL_M, scenario

from leopod.ambiguity.narrow_lane import (
    fixed_sd_if_m,
    sat_if_phase_bias_osb,
    sd_covariance_m2,
    sd_narrow_lane,
)
from leopod.ambiguity.pairs import sd_pairs
from leopod.io.bias_sinex import read_bias_sinex
from leopod.io.bias_sinex_write import write_bias_sinex
from leopod.simulate.biases import ar_products, simulate_biases


def _pairs(s):
    return sd_pairs(s.amb.sv.values, s.amb.start.values, s.amb.end.values)


def test_noise_free_float_gives_true_narrow_lane_and_fixed_if_value():
    s = scenario(seed=11)
    p = _pairs(s)
    sat_bias = s.truth["if_phase_bias_sat_m"].sel(sv=s.amb.sv.values).values
    n_wl_sd = s.n_wl[p.i] - s.n_wl[p.j]
    nl = sd_narrow_lane(s.b_true, s.amb.covariance_m2.values, p.i, p.j, n_wl_sd, F1, F2,
                        sat_bias_m=sat_bias)
    truth = s.n1[p.i] - s.n1[p.j]
    np.testing.assert_allclose(nl.value_cyc, truth, rtol=0, atol=1e-6)
    # without the satellite IF bias the values are off the integers
    off = sd_narrow_lane(s.b_true, s.amb.covariance_m2.values, p.i, p.j, n_wl_sd, F1, F2)
    assert np.max(np.abs(off.value_cyc - truth)) > 0.1
    # fixed SD IF value (bias added back) = noise-free B_i − B_j
    fixed = fixed_sd_if_m(n_wl_sd, truth, F1, F2, sat_bias_sd_m=sat_bias[p.i] - sat_bias[p.j])
    np.testing.assert_allclose(fixed, s.b_true[p.i] - s.b_true[p.j], rtol=0, atol=1e-8)


def test_sigma_and_covariance_of_single_differences():
    s = scenario(seed=12)
    p = _pairs(s)
    cov = s.amb.covariance_m2.values
    d = np.zeros((p.i.size, cov.shape[0]))        # brute force: explicit D
    d[np.arange(p.i.size), p.i] = 1.0
    d[np.arange(p.i.size), p.j] = -1.0
    expected = d @ cov @ d.T
    np.testing.assert_allclose(sd_covariance_m2(cov, p.i, p.j), expected, rtol=1e-12,
                               atol=1e-20)
    nl = sd_narrow_lane(s.amb.value_m.values, cov, p.i, p.j, np.zeros(p.i.size), F1, F2)
    np.testing.assert_allclose(nl.sigma_cyc, np.sqrt(np.diag(expected)) / LAMBDA_NL_M,
                               rtol=1e-12)


def test_closed_loop_normalised_errors():
    # noise drawn from the stated covariance: (ΔN1_float − ΔN1)/σ has unit STD
    errors = []
    for seed in range(21, 27):
        s = scenario(seed=seed)
        p = _pairs(s)
        sat_bias = s.truth["if_phase_bias_sat_m"].sel(sv=s.amb.sv.values).values
        nl = sd_narrow_lane(s.amb.value_m.values, s.amb.covariance_m2.values, p.i, p.j,
                            s.n_wl[p.i] - s.n_wl[p.j], F1, F2, sat_bias_m=sat_bias)
        errors.append((nl.value_cyc - (s.n1[p.i] - s.n1[p.j])) / nl.sigma_cyc)
    z = np.concatenate(errors)
    assert z.size > 1000
    assert 0.85 < np.std(z) < 1.15 and abs(np.mean(z)) < 0.3


def test_if_phase_bias_from_osb_equals_simulator_truth(tmp_path):
    biases = simulate_biases(GPS, None, np.random.default_rng(4), epoch=EPOCH, settings=BIASES)
    prods = ar_products(biases)
    path = tmp_path / "osb.bia"
    write_bias_sinex(prods.osb, path)
    b = sat_if_phase_bias_osb(read_bias_sinex(path), GPS, EPOCH + np.timedelta64(3, "h"))
    assert b.attrs["units"] == "m"
    np.testing.assert_allclose(b.values, prods.truth["if_phase_bias_sat_m"].sel(sv=GPS).values,
                               rtol=0, atol=1e-6)   # 6 decimals of ns in the file
    assert np.max(np.abs(b.values)) > 0.05


def test_pair_index_errors():
    with pytest.raises(ValueError, match="must lie in"):
        sd_narrow_lane([0.0, 1.0], np.eye(2), [0], [2], [0], F1, F2)
    with pytest.raises(ValueError, match="equal length"):
        sd_covariance_m2(np.eye(2), [0, 1], [1])

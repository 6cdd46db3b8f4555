"""The product guard's statistics (leopod.ambiguity.consistency).

Authorities: analytic values of the mean cosine and of its null standard deviation
(``σ0² = Σ_p |Z_p|² / (2 N²)``, derived in the module docstring), the definition of the size
of a test (under the null hypothesis — independent uniform satellite errors — a level-α test
rejects with probability at most α; Phipson & Smyth 2010 for the Monte-Carlo p-value), and the
wrapped normal ``E cos 2πx = exp(−2π²σ²)`` (Mardia & Jupp 2000, ch. 3) for a consistent product.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.special import ndtr

from leopod.ambiguity.consistency import (
    float_consistent,
    product_verdict,
    rotation_test,
    satellite_pair_sums,
)

SATS = [f"G{k:02d}" for k in range(1, 13)]


def _sds(rng, n_sat: int, n_sd: int):
    """Random SDs between ``n_sat`` satellites (both passes of different satellites)."""
    a = rng.integers(0, n_sat, n_sd)
    b = (a + rng.integers(1, n_sat, n_sd)) % n_sat
    return np.array(SATS)[a], np.array(SATS)[b], a, b


def test_all_integer_values_give_the_analytic_statistic():
    # 3 SDs G01-G02 (one written G02-G01), 1 SD G02-G03: C = 1, Z = (3, 1), N = 4,
    # sigma0 = sqrt((9 + 1)/2)/4, u = 1/sigma0; no rotation reaches C = 1: p = 1/(M + 1)
    test = rotation_test(["G01", "G02", "G01", "G02"], ["G02", "G01", "G02", "G03"],
                         [3.0, -7.0, 0.0, 12.0], "WL", draws=999)
    assert test.mean_cos == pytest.approx(1.0)
    assert test.mean_resultant_length == pytest.approx(1.0)
    assert test.mean_direction_cyc == pytest.approx(0.0, abs=1e-12)
    assert test.statistic == pytest.approx(4.0 / np.sqrt(5.0))
    assert test.p_value == pytest.approx(1 / 1000)
    assert (test.n_sd, test.n) == (4, 2)


def test_cluster_at_half_a_cycle_fails():
    # the direction 0 is part of the hypothesis: a cluster at 0.5 has C = -1 and p = 1
    test = rotation_test(SATS[:6], SATS[1:7], np.full(6, 2.5), draws=199)
    assert test.mean_cos == pytest.approx(-1.0)
    assert test.mean_resultant_length == pytest.approx(1.0)
    assert test.p_value == 1.0
    assert not test.passed(0.05, 1)


def test_orientation_of_an_sd_does_not_matter():
    rng = np.random.default_rng(2)
    si, sj, _, _ = _sds(rng, 7, 40)
    x = rng.normal(0.0, 0.1, 40) + rng.integers(-5, 5, 40)
    one = rotation_test(si, sj, x, draws=499)
    other = rotation_test(sj, si, -x, draws=499)
    assert one.mean_cos == pytest.approx(other.mean_cos)
    assert one.p_value == other.p_value
    sums = satellite_pair_sums(si, sj, x)
    assert np.all(sums.node_a < sums.node_b) and sums.count.sum() == 40


def test_null_standard_deviation_matches_simulation():
    # independent uniform satellite errors shared by all SDs of a satellite pair:
    # var(C) over the errors equals sigma0^2 of the module docstring (5 % at 20 000 draws)
    rng = np.random.default_rng(5)
    si, sj, a, b = _sds(rng, 8, 120)
    noise = rng.normal(0.0, 0.05, 120)
    sigma0 = rotation_test(si, sj, noise, draws=1).statistic
    sigma0 = np.mean(np.cos(2 * np.pi * noise)) / sigma0   # C / u
    e = rng.uniform(0.0, 1.0, (20_000, 8))
    c = np.mean(np.cos(2 * np.pi * (noise + e[:, a] - e[:, b])), axis=1)
    assert abs(np.mean(c)) < 4 * sigma0 / np.sqrt(20_000)
    assert np.std(c) == pytest.approx(sigma0, rel=0.05)


def test_size_of_the_guard_with_many_sds_per_satellite_pair():
    # 6 satellites, 90 SDs (~6 per satellite pair, sharing the pair's error): the
    # randomization test keeps its level; a test that counted the SDs as independent
    # (u = sqrt(2N) C, Mardia & Jupp 2000 V-test) would not
    rng = np.random.default_rng(11)
    alpha, runs = 0.05, 400
    guard = naive = 0
    for _ in range(runs):
        si, sj, a, b = _sds(rng, 6, 90)
        e = rng.uniform(0.0, 1.0, 6)
        x = e[a] - e[b] + rng.normal(0.0, 0.05, 90) + rng.integers(-3, 3, 90)
        test = rotation_test(si, sj, x, draws=199, seed=int(rng.integers(1 << 30)))
        guard += test.p_value <= alpha
        naive += ndtr(-np.sqrt(2 * 90) * test.mean_cos) <= alpha
    bound = alpha + 3 * np.sqrt(alpha * (1 - alpha) / runs)
    assert guard / runs <= bound
    assert naive / runs > 2 * bound


def test_consistent_product_passes_with_nine_satellite_pairs():
    # wrapped-normal SD noise of 0.15 cycles (C = exp(-2 pi^2 0.15^2) = 0.64) over 10
    # satellites: significant at 0.1 %
    rng = np.random.default_rng(4)
    si, sj, _, _ = _sds(rng, 10, 150)
    x = rng.normal(0.0, 0.15, 150) + rng.integers(-20, 20, 150)
    test = rotation_test(si, sj, x, "NL")
    assert test.mean_cos == pytest.approx(np.exp(-2 * np.pi**2 * 0.15**2), abs=0.08)
    assert test.n == 9 and test.passed(1e-3, 5)


def test_verdict_refuses_wl_then_nl_and_names_the_lane():
    rng = np.random.default_rng(8)
    si, sj, a, b = _sds(rng, 10, 150)
    good = rng.normal(0.0, 0.03, 150)
    e = rng.uniform(0.0, 1.0, 10)
    bad = good + e[a] - e[b]
    usable = np.ones(150, bool)
    kw = {"alpha": 1e-3, "min_pairs": 5, "draws": 9999}
    v = product_verdict(si, sj, bad, usable, good, usable, **kw)
    assert not v.accepted and "WL" in v.reason and v.nl is None
    v = product_verdict(si, sj, good, usable, bad, usable, **kw)
    assert not v.accepted and "NL" in v.reason and v.wl.passed(1e-3, 5)
    v = product_verdict(si, sj, good, usable, good, usable, **kw)
    assert v.accepted and v.reason == ""
    attrs = v.attrs(1e-3, 5)
    assert attrs["product_guard"] == "accepted" and attrs["nl_guard_n"] == 9
    # SDs that are not usable do not enter: too few satellite pairs left -> refused
    few = np.isin(si, SATS[:3]) & np.isin(sj, SATS[:3])
    v = product_verdict(si, sj, good, few, good, few, **kw)
    assert not v.accepted and "only 2 satellite pairs" in v.reason


def test_float_screen():
    ok, reason = float_consistent([0.05, -0.05, 0.1, np.nan], [0.01, 0.02, 0.0, 0.01], 4.0)
    np.testing.assert_array_equal(ok, [False, True, False, True])
    assert reason[0] == "fixing moves the float value by 5.0 sigma > 4" and reason[1] == ""


def test_bad_input_is_refused_clearly():
    with pytest.raises(ValueError, match="alpha"):
        product_verdict(["G01"], ["G02"], [0.0], [True], [0.0], [True], alpha=0.7,
                        min_pairs=1)
    with pytest.raises(ValueError, match="one length"):
        satellite_pair_sums(["G01", "G02"], ["G02"], [0.0, 1.0])
    with pytest.raises(ValueError, match="draws"):
        rotation_test(["G01"], ["G02"], [0.0], draws=0)
    with pytest.raises(ValueError, match="max_shift_sigma"):
        float_consistent([0.1], [0.1], 0.0)

"""Tests of leopod.ambiguity.decision.

Authorities:
- Peng et al. (2021) Table II thresholds (0.24 / 0.12 cycles) for the rounding rule, at the
  boundary;
- Dong & Bock (1989) eq. A-12 (BDS SCB-AR paper, eq. (9)): its defining sum re-evaluated by direct
  numerical integration of the normal density (scipy.stats.norm, scipy.integrate.quad) over
  the intervals |e| ∈ (i − d, i + d), and the analytic limits (d = 0: P0 = 1; d = 1/2: the
  series telescopes to erf(1/(2√2 σ)); σ → 0: 1; σ → ∞: 1 − 2d);
- integer bootstrapping (Teunissen 1998): diagonal covariance = plain rounding with success
  rate Π(2Φ(1/(2σ)) − 1); 2×2 conditional variance σ2² − σ12²/σ1²; brute-force integer least
  squares over an integer grid for the best candidate and the bound on the ratio;
  closed loop (integers + noise drawn from the covariance).
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from scipy import integrate, stats
from scipy.special import erf

from leopod.ambiguity.decision import (
    DONG_BOCK_ALPHA,
    NL_MAX_DEV_CYC,
    WL_MAX_DEV_CYC,
    dong_bock_decision,
    dong_bock_probability,
    integer_bootstrap,
    rounding_decision,
)


def test_peng2021_thresholds():
    assert WL_MAX_DEV_CYC == 0.24 and NL_MAX_DEV_CYC == 0.12   # Peng et al. (2021), Table II
    assert DONG_BOCK_ALPHA == 1e-3                              # the BDS SCB-AR paper: α = 0.1 %


def test_rounding_decision_values_and_reasons():
    value = np.array([0.24, 3.2401, -1.31, 2.5, -7.02, np.nan, 4.0])
    sigma = np.array([0.05, 0.05, 0.05, 0.05, 0.30, 0.05, np.inf])
    d = rounding_decision(value, sigma, max_dev_cyc=0.24, max_sigma_cyc=0.2)
    np.testing.assert_array_equal(d.integer, [0, 3, -1, 3, -7, 0, 4])
    np.testing.assert_allclose(d.fraction_cyc[:5], [0.24, 0.2401, -0.31, -0.5, -0.02],
                               atol=1e-12)
    assert np.isnan(d.fraction_cyc[5])
    np.testing.assert_array_equal(d.fixed, [True, False, False, False, False, False, False])
    assert list(d.reason) == ["", "fractional part 0.24 > 0.24", "fractional part 0.31 > 0.24",
                              "fractional part 0.50 > 0.24", "sigma 0.300 > 0.200",
                              "value or sigma not finite", "value or sigma not finite"]
    both = rounding_decision([0.5], [1.0], max_dev_cyc=0.12, max_sigma_cyc=0.1)
    assert both.reason[0] == "fractional part 0.50 > 0.12; sigma 1.000 > 0.100"
    # no sigma bound by default
    assert rounding_decision([10.1], [50.0], max_dev_cyc=0.12).fixed[0]


def _q_numeric(d: float, sigma: float) -> float:
    """Σ_i P(|e| ∈ (i − d, i + d)), e ~ N(0, σ²), by quadrature of the density."""
    total = 0.0
    for i in range(1, int(12 * sigma) + 3):
        part, _ = integrate.quad(lambda x: stats.norm.pdf(x, scale=sigma), i - d, i + d,
                                 epsabs=1e-14)
        total += 2.0 * part
    return total


@pytest.mark.parametrize("value,sigma", [(0.1, 0.1), (3.2, 0.15), (-0.4, 0.3), (7.77, 0.5),
                                         (0.05, 1.5), (-2.45, 0.25), (0.3, 4.0)])
def test_dong_bock_matches_numerical_integration(value, sigma):
    d = abs(value - np.floor(value + 0.5))
    p0 = dong_bock_probability([value], [sigma])[0]
    assert 1.0 - p0 == pytest.approx(_q_numeric(d, sigma), rel=1e-7, abs=1e-13)


def test_dong_bock_limits():
    sigma = np.array([0.01, 0.1, 0.3, 1.0, 3.0])
    # d = 0: every term vanishes, P0 = 1 whatever σ
    np.testing.assert_allclose(dong_bock_probability(np.full(5, 4.0), sigma), 1.0, atol=0)
    # d = 1/2: the sum telescopes to erfc(1/(2√2 σ))
    np.testing.assert_allclose(dong_bock_probability(np.full(5, 2.5), sigma),
                               erf(0.5 / (np.sqrt(2.0) * sigma)), rtol=0, atol=1e-14)
    # σ → 0 with d < 1/2: certain
    assert dong_bock_probability([0.45], [1e-3])[0] == 1.0
    # σ → ∞: P0 → 1 − 2d (the terms become a Riemann sum of the density over half a period)
    np.testing.assert_allclose(dong_bock_probability([0.3, 0.1], [1000.0, 1000.0]),
                               [0.4, 0.8], atol=1e-3)
    assert np.isnan(dong_bock_probability([0.1, np.nan, 0.1], [0.0, 0.1, np.nan])).all()


def test_dong_bock_decision():
    value = np.array([5.03, 5.2, 5.2, np.nan])
    sigma = np.array([0.05, 0.2, 0.3, 0.1])
    d = dong_bock_decision(value, sigma, alpha=1e-3)
    np.testing.assert_array_equal(d.fixed, [True, True, False, False])
    np.testing.assert_array_equal(d.integer, [5, 5, 5, 0])
    # 1 − P0 ≈ erfc(0.8/(√2 σ)) − erfc(1.2/(√2 σ)): 6e-5 for σ = 0.2, 8e-3 for σ = 0.3
    q = 1.0 - dong_bock_probability([5.2], [0.3])[0]
    assert q == pytest.approx(0.0078, rel=0.05)
    assert d.reason[2] == f"1 - P0 = {q:.3g} > alpha 0.001"
    assert d.reason[3].startswith("value or sigma not finite")


def test_bootstrap_diagonal_is_rounding():
    value = np.array([1.2, -3.45, 7.49, 0.51])
    sigma = np.array([0.1, 0.2, 0.15, 0.05])
    r = integer_bootstrap(value, np.diag(sigma**2))
    np.testing.assert_array_equal(r.integer, [1, -3, 7, 1])
    np.testing.assert_array_equal(r.order, [3, 0, 2, 1])       # smallest variance first
    np.testing.assert_allclose(r.conditional_sigma_cyc, sigma[r.order], rtol=1e-14)
    expected = np.prod(2.0 * stats.norm.cdf(0.5 / sigma) - 1.0)
    assert r.success_rate == pytest.approx(expected, rel=1e-12)


def test_bootstrap_conditional_variance_2x2():
    s1, s2, rho = 0.1, 0.3, 0.8
    s12 = rho * s1 * s2
    r = integer_bootstrap([0.02, 0.9], [[s1**2, s12], [s12, s2**2]])
    np.testing.assert_allclose(r.conditional_sigma_cyc,
                               [s1, np.sqrt(s2**2 - s12**2 / s1**2)], rtol=1e-12)
    # 2nd component conditioned on the 1st rounded to 0: 0.9 − s12/s1² (0.02 − 0) = 0.852
    np.testing.assert_array_equal(r.integer, [0, 1])


def _ils_brute_force(a, cov, span=3):
    """All integer vectors within ±span of round(a), sorted by (a − z)^T Q^-1 (a − z)."""
    qinv = np.linalg.inv(cov)
    base = np.floor(a + 0.5)
    cands = np.array([base + np.array(o) for o in
                      itertools.product(range(-span, span + 1), repeat=a.size)])
    r = a - cands
    q = np.einsum("ki,ij,kj->k", r, qinv, r)
    order = np.argsort(q)
    return cands[order], q[order]


def test_bootstrap_against_brute_force_integer_least_squares():
    rng = np.random.default_rng(9)
    checked = 0
    for _ in range(30):
        m = rng.normal(size=(3, 3)) * 0.15
        cov = m @ m.T + np.diag([0.01, 0.02, 0.015])
        a = rng.integers(-20, 20, 3) + rng.multivariate_normal(np.zeros(3), cov)
        r = integer_bootstrap(a, cov)
        cands, q = _ils_brute_force(a, cov)
        assert r.q_best >= q[0] - 1e-9       # never better than the ILS optimum
        assert r.q_second >= q[1] - 1e-9
        if np.array_equal(r.integer, cands[0]):
            checked += 1
            assert r.q_best == pytest.approx(q[0], rel=1e-9, abs=1e-12)
            assert r.ratio >= q[1] / q[0] - 1e-9   # upper bound of the LAMBDA ratio
        z = np.asarray(r.integer, dtype=float)
        np.testing.assert_allclose((a - z) @ np.linalg.solve(cov, a - z), r.q_best,
                                   rtol=1e-9)
    assert checked >= 25


def test_bootstrap_closed_loop_correlated():
    # a_k = z_k + g_k e + ε_k: a shared error e (σ 0.05) scaled by g_k (3..8) spoils plain
    # rounding; conditioning on the first rounded components recovers e and the integers
    rng = np.random.default_rng(10)
    n = 40
    g = np.concatenate([[1.0], rng.uniform(3.0, 8.0, n - 1) * rng.choice([-1, 1], n - 1)])
    cov = 0.05**2 * np.outer(g, g) + np.diag(np.full(n, 0.01**2))
    truth = rng.integers(-50, 50, n)
    shared = 0.09   # a 1.8-sigma draw of e, fixed so that plain rounding surely fails
    a = truth + g * shared + rng.normal(0.0, 0.01, n)
    assert np.sum(np.floor(a + 0.5) != truth) > 10
    r = integer_bootstrap(a, cov)
    np.testing.assert_array_equal(r.integer, truth)
    assert r.success_rate > 0.99 and r.ratio > 3.0
    with pytest.raises(ValueError, match="positive definite"):
        integer_bootstrap([0.1, 0.2], [[1.0, 2.0], [2.0, 1.0]])
    with pytest.raises(ValueError, match="finite"):
        integer_bootstrap([np.nan, 0.2], np.eye(2))

"""Tests of leopod.ambiguity.ils (LAMBDA: Teunissen 1995; de Jonge & Tiberius 1996).

Authorities (analytic and brute-force truth):
- Q = Lᵀ D L reproduces Q; the decorrelation Z is unimodular (integer, |det Z| = 1), keeps
  det Q_z = det Q and leaves |L_ij| <= 1/2 (de Jonge & Tiberius 1996, sec. 3);
- the best and second-best integer vectors equal an exhaustive search over a box that
  contains the ellipsoid q(z) <= χ² of two known integer vectors (|a_i − z_i| <= sqrt(χ² Q_ii));
- diagonal Q: ILS is rounding;
- partial fixing keeps the well-determined ambiguities and fixes them to their true integers.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from leopod.ambiguity.alternatives import ils_nl_decision
from leopod.ambiguity.ils import decorrelate, ils, ltdl, partial_ils


def _random_q(rng, n):
    a = rng.normal(size=(n, n))
    return a @ a.T * rng.uniform(0.01, 1.0) + 1e-3 * np.eye(n)


@pytest.mark.parametrize("n", [2, 3, 4])
def test_decorrelation_is_unimodular_and_keeps_the_determinant(n):
    rng = np.random.default_rng(n)
    for _ in range(50):
        q = _random_q(rng, n)
        lower, d = ltdl(q)
        np.testing.assert_allclose(lower.T @ np.diag(d) @ lower, q, atol=1e-12)
        z, lz, dz = decorrelate(q)
        assert np.array_equal(z, np.rint(z)) and abs(round(np.linalg.det(z))) == 1
        qz = z.T @ q @ z
        np.testing.assert_allclose(lz.T @ np.diag(dz) @ lz, qz, rtol=1e-9, atol=1e-12)
        assert np.linalg.det(qz) == pytest.approx(np.linalg.det(q), rel=1e-8)
        assert np.all(np.abs(np.tril(lz, -1)) <= 0.5 + 1e-12)


@pytest.mark.parametrize("n", [2, 3, 4])
def test_ils_equals_exhaustive_search(n):
    rng = np.random.default_rng(10 + n)
    checked = 0
    while checked < 40:
        q = _random_q(rng, n)
        a = rng.normal(size=n) * 3
        qi = np.linalg.inv(q)

        def qf(z, a=a, qi=qi):
            return (a - z) @ qi @ (a - z)

        c = np.rint(a)
        chi2 = max(qf(c), qf(c + np.eye(n)[0]))
        half = np.sqrt(chi2 * np.diag(q))
        axes = [range(int(np.floor(a[i] - half[i])), int(np.ceil(a[i] + half[i])) + 1)
                for i in range(n)]
        if np.prod([len(x) for x in axes]) > 20000:
            continue
        found = sorted((qf(np.array(z)), z) for z in itertools.product(*axes))
        res = ils(a, q)
        assert tuple(res.integer) == found[0][1]
        assert res.q_best == pytest.approx(found[0][0], rel=1e-9)
        assert res.q_second == pytest.approx(found[1][0], rel=1e-9)
        checked += 1


def test_diagonal_covariance_is_rounding():
    a = np.array([0.3, -1.7, 2.45, 5.1])
    res = ils(a, np.diag([0.01, 0.04, 0.02, 0.03]))
    assert np.array_equal(res.integer, np.rint(a).astype(int))


def test_partial_fixing_keeps_the_good_subset():
    rng = np.random.default_rng(5)
    truth = rng.integers(-20, 20, 8)
    sig = np.array([0.03] * 6 + [0.6, 0.8])             # two ambiguities hopelessly weak
    q = np.diag(sig**2)
    noise = np.concatenate([rng.normal(size=6) * sig[:6], [0.5, 0.45]])   # near half cycles
    a = truth + noise
    fixed, res = partial_ils(a, q, min_ratio=3.0, min_success_rate=0.999)
    assert fixed.tolist() == [True] * 6 + [False, False]
    assert np.array_equal(res.integer, truth[:6])


def test_ils_nl_decision_on_single_differences():
    # 4 passes, SDs 0-1, 1-2, 2-3, 0-2 (the last dependent); undifferenced covariance diagonal
    rng = np.random.default_rng(7)
    i, j = np.array([0, 1, 2, 0]), np.array([1, 2, 3, 2])
    d = np.zeros((4, 4))
    d[np.arange(4), i], d[np.arange(4), j] = 1.0, -1.0
    cov = d @ np.diag([0.001] * 4) @ d.T
    truth = np.array([3, -2, 5, 1])
    x = truth + rng.normal(size=4) * 0.01
    dec = ils_nl_decision(x, cov, i, j, np.ones(4, bool), min_ratio=3.0,
                          min_success_rate=0.999)
    assert dec.fixed.sum() == 3                      # a maximal independent set
    assert np.array_equal(dec.integer[dec.fixed], truth[dec.fixed])

"""Tests of leopod.ambiguity.independent.

Authorities:
- brute force linear algebra: numpy.linalg.matrix_rank of the ±1 incidence rows of the
  selected and of all single differences;
- brute force optimality: enumeration of every subset of the maximal size of a small graph,
  keeping the linearly independent ones, for the smallest total key;
- hand-counted graphs for the fixing rate of Jiang et al. (2023) (independent fixed / all
  independent).
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from leopod.ambiguity.independent import (
    CONSTRAINT_SIGMA_M,
    constraint_matrix,
    constraint_rows,
    fixing_rate,
    graph_rank,
    independent_edges,
)


def _incidence(i, j, n):
    a = np.zeros((len(i), n))
    a[np.arange(len(i)), i] = 1.0
    a[np.arange(len(i)), j] = -1.0
    return a


def _random_graph(rng, n_nodes, n_edges):
    i = rng.integers(0, n_nodes, n_edges)
    j = (i + rng.integers(1, n_nodes, n_edges)) % n_nodes
    return np.minimum(i, j), np.maximum(i, j)


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_kruskal_selection_is_maximal_and_independent(seed):
    rng = np.random.default_rng(seed)
    n = 40
    i, j = _random_graph(rng, n, 90)
    keep = independent_edges(i, j, rng.uniform(size=i.size))
    a_all = _incidence(i, j, n)
    rank_all = np.linalg.matrix_rank(a_all)
    assert np.linalg.matrix_rank(a_all[keep]) == keep.sum()     # independent
    assert keep.sum() == rank_all                               # maximal
    assert graph_rank(i, j) == rank_all


def test_kruskal_has_smallest_total_key_brute_force():
    rng = np.random.default_rng(7)
    n = 6
    i, j = _random_graph(rng, n, 10)
    key = rng.uniform(size=i.size)
    keep = independent_edges(i, j, key)
    a = _incidence(i, j, n)
    r = np.linalg.matrix_rank(a)
    best = min(key[list(c)].sum() for c in itertools.combinations(range(i.size), r)
               if np.linalg.matrix_rank(a[list(c)]) == r)
    assert key[keep].sum() == pytest.approx(best, abs=1e-12)


def test_order_and_ties():
    # triangle 0-1-2: the worst edge (largest key) closes the cycle and is dropped
    i, j = np.array([0, 1, 0]), np.array([1, 2, 2])
    np.testing.assert_array_equal(independent_edges(i, j, [0.1, 0.3, 0.2]), [True, False, True])
    np.testing.assert_array_equal(independent_edges(i, j), [True, True, False])  # input order
    with pytest.raises(ValueError, match="itself"):
        independent_edges([1], [1])
    assert independent_edges([], []).size == 0


def test_fixing_rate_jiang2023_definition():
    # two components: triangle {0, 1, 2} (rank 2) and path 3-4-5 (rank 2): 4 independent SDs
    i = np.array([0, 1, 0, 3, 4])
    j = np.array([1, 2, 2, 4, 5])
    # fixed: two triangle edges (rank 2) and nothing of the path -> 2/4
    assert fixing_rate(i, j, [True, True, False, False, False]) == 0.5
    # all three triangle edges are still only 2 independent fixes
    assert fixing_rate(i, j, [True, True, True, False, False]) == 0.5
    assert fixing_rate(i, j, [False, True, True, True, True]) == 1.0
    assert np.isnan(fixing_rate([], [], []))


def test_constraint_rows_reproduce_integer_values():
    # values of consistent fixed SDs B_i − B_j: the selected rows hold them exactly, the
    # design matrix has full row rank and A @ B = value
    rng = np.random.default_rng(3)
    n = 25
    b = rng.normal(size=n)
    i, j = _random_graph(rng, n, 60)
    value = b[i] - b[j]
    key = rng.uniform(size=i.size)
    rows = constraint_rows(i, j, value, key)
    keep = independent_edges(i, j, key)
    np.testing.assert_array_equal(rows.index_i, i[keep])
    np.testing.assert_array_equal(rows.index_j, j[keep])
    np.testing.assert_allclose(rows.sigma_m, CONSTRAINT_SIGMA_M)
    a = constraint_matrix(rows, n)
    assert a.shape == (keep.sum(), n)
    assert np.linalg.matrix_rank(a) == keep.sum()
    np.testing.assert_allclose(a @ b, rows.value_m, rtol=0, atol=1e-12)
    assert constraint_rows(i, j, value, key, sigma_m=2e-3).sigma_m.max() == 2e-3

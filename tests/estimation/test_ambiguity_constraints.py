"""Fixed single-difference constraints in the POD normal equations (analytic truth)."""

import numpy as np

from leopod.estimation.float_pod import constrain_differences
from leopod.estimation.normals import NormalEquations


def test_constraints_equal_explicit_pseudo_observations():
    # [2 arc parameters, ambiguities of passes 0, 3, 5]; constraints B3 - B0 = 1.5 +- 0.01,
    # B5 - B3 = -0.2 +- 0.02 and one on a pass without phase (7: skipped)
    rng = np.random.default_rng(4)
    a = rng.standard_normal((10, 5))
    ne = NormalEquations(matrix=a.T @ a, rhs=rng.standard_normal(5), ltpl=0.0, n_rows=10)
    ref_matrix, ref_rhs = ne.matrix.copy(), ne.rhs.copy()
    active = np.array([0, 3, 5])
    ambiguity = np.zeros(8)
    ambiguity[[0, 3, 5]] = [0.3, 1.0, 0.9]
    pass_i, pass_j = np.array([3, 5, 7]), np.array([0, 3, 0])
    value, sigma = np.array([1.5, -0.2, 9.0]), np.array([0.01, 0.02, 0.01])
    constrain_differences(ne, 2, active, ambiguity, (pass_i, pass_j, value, sigma))
    # explicit rows D dx = v - D x0 with weights 1/sigma^2 (columns 2, 3, 4 = passes 0, 3, 5)
    d = np.zeros((2, 5))
    d[0, 3], d[0, 2] = 1, -1
    d[1, 4], d[1, 3] = 1, -1
    w = np.diag(1 / sigma[:2] ** 2)
    misclosure = value[:2] - np.array([1.0 - 0.3, 0.9 - 1.0])
    assert np.allclose(ne.matrix, ref_matrix + d.T @ w @ d)
    assert np.allclose(ne.rhs, ref_rhs + d.T @ w @ misclosure)

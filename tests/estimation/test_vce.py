"""Redundancy numbers of observation groups with pre-eliminated clocks (VCE).

Authority: linear algebra. The redundancy of a group, ``r_g = n_g − tr(N⁻¹ A_gᵀP_gA_g)``
(Förstner 1979; Koch 1999), computed by brute force with one explicit clock column per epoch
and the full normal matrix, must equal :func:`leopod.estimation.vce.group_redundancy`, which
works on the clock-reduced normal equations (eq. (2) of its module); and the redundancies of
all groups plus that of the pseudo-observations must sum to ``n − u`` (the trace of the
residual projector).
"""

import numpy as np
from test_normals import _full_design, _problem

from leopod.estimation.normals import accumulate, solve
from leopod.estimation.vce import group_redundancy


def test_group_redundancy_equals_dense_computation():
    rows = _problem(seed=3, m=25, k=6, n_amb=6)
    k = rows.partials.shape[2]
    rng = np.random.default_rng(7)
    # a-priori constraints on two arc parameters (like pulses): pseudo-observations
    constraint = np.zeros(k + rows.n_amb)
    constraint[[1, 4]] = [0.5, 2.0]
    _, q = solve(accumulate(rows), constraint, np.zeros(k + rows.n_amb))
    h = _full_design(rows)
    n_full = (h * rows.weight[:, None]).T @ h
    n_full[np.diag_indices(k + rows.n_amb)] += constraint
    q_full = np.linalg.inv(n_full)
    # four groups: code / phase of two "systems" (random split of the satellites' rows)
    system = rng.integers(0, 2, rows.epoch.size)
    total = 0.0
    for g in range(4):
        mask = (system == g // 2) & ((rows.amb >= 0) == bool(g % 2))
        hg = h[mask]
        dense = mask.sum() - np.trace(q_full @ ((hg * rows.weight[mask, None]).T @ hg))
        fast = group_redundancy(rows, q, mask)
        assert abs(fast - dense) < 1e-9 * max(1.0, abs(dense)), (g, fast, dense)
        total += fast
    # with the redundancy of the pseudo-observations: n + n_c − u
    r_constraints = 2 - float(np.sum(np.diag(q_full)[[1, 4]] * constraint[[1, 4]]))
    u = h.shape[1]
    assert abs(total + r_constraints - (rows.epoch.size + 2 - u)) < 1e-8

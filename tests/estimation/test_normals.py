"""Clock pre-elimination: identical to the least-squares solution with explicit clocks.

Authority: linear algebra (Schur complement). The brute-force reference solves the full
weighted least-squares problem with one clock unknown per epoch by numpy.linalg.lstsq.
"""

import numpy as np

from leopod.estimation.normals import Rows, accumulate, epoch_clocks, solve


def _problem(seed=1, m=40, k=5, n_amb=7):
    rng = np.random.default_rng(seed)
    epoch, amb = [], []
    for e in range(m):
        for j in rng.choice(n_amb, size=4, replace=False):
            epoch += [e, e]
            amb += [-1, j]          # a code and a phase row per satellite
    epoch, amb = np.array(epoch), np.array(amb)
    r = epoch.size
    a_o = rng.normal(size=(r, k))
    w = np.where(amb >= 0, 1e4, 1.0) * rng.uniform(0.5, 2.0, r)
    x_o, x_a, clk = rng.normal(size=k), rng.normal(size=n_amb) * 10, rng.normal(size=m) * 100
    l = a_o @ x_o + np.where(amb >= 0, x_a[amb], 0.0) + clk[epoch] + rng.normal(size=r) / np.sqrt(w)
    return Rows(a_o, amb, epoch, l, w, m, n_amb)


def _brute(rows):
    r = rows.epoch.size
    h = np.zeros((r, rows.a_o.shape[1] + rows.n_amb + rows.n_epochs))
    k = rows.a_o.shape[1]
    h[:, :k] = rows.a_o
    ph = rows.amb >= 0
    h[np.flatnonzero(ph), k + rows.amb[ph]] = 1.0
    h[np.arange(r), k + rows.n_amb + rows.epoch] = 1.0
    sw = np.sqrt(rows.weight)
    x, *_ = np.linalg.lstsq(h * sw[:, None], rows.misclosure * sw, rcond=None)
    cov = np.linalg.inv((h * rows.weight[:, None]).T @ h)
    return x, cov


def test_reduced_solution_equals_explicit_clock_solution():
    rows = _problem()
    dx, cov = solve(accumulate(rows))
    ref, ref_cov = _brute(rows)
    p = dx.size
    assert np.allclose(dx, ref[:p], rtol=0, atol=1e-8)
    assert np.allclose(cov, ref_cov[:p, :p], rtol=1e-8, atol=1e-14)
    clocks, res = epoch_clocks(rows, dx)
    assert np.allclose(clocks, ref[p:], atol=1e-7)
    # residuals are orthogonal to the clock columns (weighted sum per epoch zero)
    per_epoch = np.bincount(rows.epoch, weights=rows.weight * res)
    assert np.allclose(per_epoch, 0.0, atol=1e-6)


def test_ltpl_is_weighted_square_sum_of_residuals_at_solution():
    rows = _problem(seed=3)
    ne = accumulate(rows)
    dx, _ = solve(ne)
    _, res = epoch_clocks(rows, dx)
    # vᵀWv = lᵀWl − bᵀx (normal-equation identity)
    assert np.isclose(np.sum(rows.weight * res**2), ne.ltpl - ne.rhs @ dx, rtol=1e-8)

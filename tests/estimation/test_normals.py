"""Clock pre-elimination and the epoch-factored accumulation of the normal equations.

Authorities: linear algebra (Schur complement): the brute-force reference solves the full
weighted least-squares problem with one clock unknown per epoch by numpy.linalg.lstsq; and
the direct formula of the reduced system with the dense rows ``A_o = u_r · P_e`` formed
explicitly (``N = HᵀWH − GᵀS⁻¹G``, ``b = HᵀWl − GᵀS⁻¹EᵀWl``, :mod:`leopod.estimation.normals`)
for the grouped, blocked accumulation.
"""

import numpy as np
import pytest
import scipy.sparse as sp

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
    direction = rng.normal(size=(r, 3))
    partials = rng.normal(size=(m, 3, k))
    a_o = _dense(direction, partials, epoch)
    w = np.where(amb >= 0, 1e4, 1.0) * rng.uniform(0.5, 2.0, r)
    x_o, x_a, clk = rng.normal(size=k), rng.normal(size=n_amb) * 10, rng.normal(size=m) * 100
    l = a_o @ x_o + np.where(amb >= 0, x_a[amb], 0.0) + clk[epoch] + rng.normal(size=r) / np.sqrt(w)
    return Rows(direction, partials, amb, epoch, l, w, n_amb)


def _dense(direction, partials, epoch):
    """The rows ``A_o`` (r, k): ``direction[r] @ partials[epoch[r]]``."""
    return np.einsum("ni,nik->nk", direction, partials[epoch])


def _full_design(rows: Rows) -> np.ndarray:
    """Dense design matrix with one column per arc parameter, ambiguity and epoch clock."""
    r = rows.epoch.size
    a_o = _dense(rows.direction, rows.partials, rows.epoch)
    k = a_o.shape[1]
    h = np.zeros((r, k + rows.n_amb + rows.n_epochs))
    h[:, :k] = a_o
    ph = rows.amb >= 0
    h[np.flatnonzero(ph), k + rows.amb[ph]] = 1.0
    h[np.arange(r), k + rows.n_amb + rows.epoch] = 1.0
    return h


def _brute(rows):
    h = _full_design(rows)
    sw = np.sqrt(rows.weight)
    x, *_ = np.linalg.lstsq(h * sw[:, None], rows.misclosure * sw, rcond=None)
    cov = np.linalg.inv((h * rows.weight[:, None]).T @ h)
    return x, cov


def _direct(rows):
    """Reduced normal equations and ``lᵀWl`` from the dense rows ``A_o``, the incidences
    ``A_a`` (rows on ambiguities) and ``E`` (rows on epochs), block by block of ``H``."""
    r, m, k = rows.epoch.size, rows.n_epochs, rows.partials.shape[2]
    a_o = _dense(rows.direction, rows.partials, rows.epoch)
    ph = rows.amb >= 0
    a_a = sp.csr_matrix((np.ones(ph.sum()), (np.flatnonzero(ph), rows.amb[ph])),
                        shape=(r, rows.n_amb))
    e = sp.csr_matrix((np.ones(r), (np.arange(r), rows.epoch)), shape=(r, m))
    w, l = rows.weight, rows.misclosure
    s = e.T @ w
    s_inv = sp.diags(np.where(s > 0, 1.0 / np.where(s > 0, s, 1.0), 0.0))
    g_o, g_a, g_l = e.T @ (w[:, None] * a_o), e.T @ sp.diags(w) @ a_a, e.T @ (w * l)
    n = np.empty((k + rows.n_amb,) * 2)
    n[:k, :k] = a_o.T @ (w[:, None] * a_o) - g_o.T @ (s_inv @ g_o)
    n[:k, k:] = (a_a.T @ (w[:, None] * a_o)).T - (g_a.T @ (s_inv @ g_o)).T
    n[k:, :k] = n[:k, k:].T
    n[k:, k:] = (a_a.T @ sp.diags(w) @ a_a - g_a.T @ s_inv @ g_a).toarray()
    b = np.concatenate([a_o.T @ (w * l) - g_o.T @ (s_inv @ g_l),
                        a_a.T @ (w * l) - g_a.T @ (s_inv @ g_l)])
    return n, b, w @ (l * l) - g_l @ (s_inv @ g_l)


def _pod_shaped(seed, m, per_epoch, k_dyn, pulse_every, n_amb):
    """Rows shaped like a POD arc: partials of ``k_dyn`` dense columns and of pulses every
    ``pulse_every`` epochs (zero before their epoch), epochs without or with one row, one
    code and one phase row per satellite and epoch, weights of code and phase."""
    rng = np.random.default_rng(seed)
    n_pulses = (m - 1) // pulse_every
    k = k_dyn + 3 * n_pulses
    p = rng.normal(size=(m, 3, k)) * 1e3
    for i in range(n_pulses):
        p[:(i + 1) * pulse_every, :, k_dyn + 3 * i:k_dyn + 3 * i + 3] = 0.0
    n_sat = rng.integers(0, per_epoch + 1, m)
    n_sat[:3] = [0, 1, 2]
    epoch = np.repeat(np.arange(m), 2 * n_sat)
    amb = np.where(np.arange(epoch.size) % 2 == 1, rng.integers(0, n_amb, epoch.size), -1)
    los = rng.normal(size=(epoch.size, 3))
    los /= np.linalg.norm(los, axis=1)[:, None]
    w = np.where(amb >= 0, 1e4, 4.0) * rng.uniform(0.2, 1.0, epoch.size)
    l = rng.normal(size=epoch.size) * np.where(amb >= 0, 0.01, 1.0) + 3.0
    return Rows(-los, p, amb, epoch, l, w, n_amb)


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


@pytest.mark.parametrize("shape", [
    # epochs, satellites per epoch (at most), dynamic columns, pulse spacing, ambiguities
    (150, 5, 7, 20, 30),            # several blocks of epochs, blocks without new columns
    (2880, 10, 47, 30, 760),        # GRACE-A 2007-080 at 30 s: k = 332, 95 pulses
])
def test_grouped_accumulation_equals_direct_formula(shape):
    rows = _pod_shaped(5, *shape)
    ne = accumulate(rows)
    n, b, ltpl = _direct(rows)
    scale = np.sqrt(np.outer(np.diag(n), np.diag(n)))
    np.testing.assert_allclose(ne.matrix / scale, n / scale, rtol=0, atol=1e-12)
    scale_b = np.sqrt(np.diag(n) * (rows.weight @ rows.misclosure**2))
    np.testing.assert_allclose(ne.rhs / scale_b, b / scale_b, rtol=0, atol=1e-12)
    assert ne.ltpl == pytest.approx(ltpl, rel=1e-10)


def test_epoch_clocks_equal_direct_formula():
    rows = _pod_shaped(6, 150, 5, 7, 20, 30)
    k = rows.partials.shape[2]
    dx = np.random.default_rng(7).normal(size=k + rows.n_amb) * 1e-3
    reduced = rows.misclosure - _dense(rows.direction, rows.partials, rows.epoch) @ dx[:k]
    ph = rows.amb >= 0
    reduced[ph] -= dx[k + rows.amb[ph]]
    s = np.bincount(rows.epoch, weights=rows.weight, minlength=rows.n_epochs)
    num = np.bincount(rows.epoch, weights=rows.weight * reduced, minlength=rows.n_epochs)
    clocks, res = epoch_clocks(rows, dx)
    assert np.isnan(clocks[0]) and np.isfinite(clocks[s > 0]).all()
    np.testing.assert_allclose(clocks[s > 0], num[s > 0] / s[s > 0], rtol=1e-13, atol=1e-12)
    np.testing.assert_allclose(res, reduced - clocks[rows.epoch], rtol=0, atol=1e-11)


def test_extra_sparse_columns_equal_explicit_least_squares():
    """Further sparse columns (e.g. PCV node weights, leopod.antenna.pcv_direct) after the
    ambiguities: the solution, covariance and residuals of the full least-squares problem with
    those columns and one clock per epoch (numpy.linalg.lstsq)."""
    rows = _problem(seed=11)
    rng = np.random.default_rng(12)
    r, x = rows.epoch.size, 6
    extra = sp.random(r, x, density=0.4, random_state=13, format="csr")
    truth = rng.normal(size=x)
    rows.misclosure = rows.misclosure + extra @ truth
    ne = accumulate(rows, extra)
    dx, cov = solve(ne)
    h = _full_design(rows)
    k_a = h.shape[1] - rows.n_epochs
    h = np.concatenate([h[:, :k_a], extra.toarray(), h[:, k_a:]], axis=1)
    sw = np.sqrt(rows.weight)
    ref, *_ = np.linalg.lstsq(h * sw[:, None], rows.misclosure * sw, rcond=None)
    p = dx.size
    assert np.allclose(dx, ref[:p], rtol=0, atol=1e-8)
    ref_cov = np.linalg.inv((h * rows.weight[:, None]).T @ h)
    assert np.allclose(cov, ref_cov[:p, :p], rtol=1e-8, atol=1e-14)
    clocks, res = epoch_clocks(rows, dx, extra)
    assert np.allclose(clocks, ref[p:], atol=1e-7)
    # vᵀWv = lᵀWl − bᵀx, to the rounding of lᵀWl (large misclosures: clocks of 100 m)
    assert np.isclose(np.sum(rows.weight * res**2), ne.ltpl - ne.rhs @ dx, rtol=0,
                      atol=1e-12 * ne.ltpl)

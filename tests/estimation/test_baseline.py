"""Joint solution of two arcs with DD constraints (leopod.estimation.baseline).

Authority: analytic least squares — the solve of stacked normal equations plus constraint
pseudo-observations equals the least-squares solution of the stacked weighted observation
equations with the constraints as further rows (Koch 1999, Parameter Estimation, sec. 3.2).
"""

import numpy as np

from leopod.ambiguity.double_difference import DdConstraints
from leopod.estimation.baseline import dd_rows, joint_solve
from leopod.estimation.float_pod import ArcNormals
from leopod.estimation.normals import NormalEquations


def _arc(rng, k, passes, n_obs=60):
    """Synthetic arc: observations l = H x + e with k parameters and ambiguities of passes."""
    n = k + passes.size
    h = rng.normal(size=(n_obs, n))
    x_true = rng.normal(size=n)
    w = np.full(n_obs, 4.0)
    l = h @ x_true + rng.normal(scale=0.5, size=n_obs)
    ne = NormalEquations(matrix=h.T @ (w[:, None] * h), rhs=h.T @ (w * l),
                         ltpl=float(np.sum(w * l * l)), n_rows=n_obs)
    amb0 = rng.normal(size=passes.size)
    arc = ArcNormals(normals=ne, k=k, active=passes, ambiguity_m=amb0, _solution=None,
                     _state=None)
    return arc, h, w, l


def test_joint_solve_equals_stacked_least_squares():
    rng = np.random.default_rng(21)
    pass_a, pass_b = np.array([0, 2, 3, 5]), np.array([1, 4, 6])
    a, ha, wa, la = _arc(rng, 5, pass_a)
    b, hb, wb, lb = _arc(rng, 4, pass_b)
    # constraints refer to rows of the float ambiguity datasets (here: rows = pass order)
    c = DdConstraints(amb_a_i=np.array([0, 1]), amb_b_i=np.array([0, 1]),
                      amb_a_j=np.array([2, 3]), amb_b_j=np.array([2, 2]),
                      value_m=np.array([0.3, -1.2]), sigma_m=np.array([1e-3, 1e-3]))
    design, misclosure, weight = dd_rows(a, b, pass_a, pass_b, c)
    joint = joint_solve(a, b, design, misclosure, weight)
    # stacked observation equations [H_A 0; 0 H_B; D] with the constraint rows in x0 terms
    n_a, n_b = ha.shape[1], hb.shape[1]
    big = np.zeros((ha.shape[0] + hb.shape[0] + design.shape[0], n_a + n_b))
    big[:ha.shape[0], :n_a] = ha
    big[ha.shape[0]:ha.shape[0] + hb.shape[0], n_a:] = hb
    big[ha.shape[0] + hb.shape[0]:] = design
    obs = np.concatenate([la, lb, misclosure])
    w = np.concatenate([wa, wb, weight])
    x_ls = np.linalg.lstsq(big * np.sqrt(w)[:, None], obs * np.sqrt(w), rcond=None)[0]
    np.testing.assert_allclose(np.concatenate([joint.dx_a, joint.dx_b]), x_ls, atol=1e-8)
    # constraints satisfied to (well within) their sigma
    x0 = np.concatenate([np.zeros(a.k), a.ambiguity_m, np.zeros(b.k), b.ambiguity_m])
    amb = x0 + np.concatenate([joint.dx_a, joint.dx_b])
    np.testing.assert_array_less(np.abs(design @ amb - c.value_m), c.sigma_m)
    # the DDs couple the two arcs: cross covariances between A and B are not zero, and the
    # covariance equals the inverse of the stacked normal matrix
    cross = joint.covariance[:n_a, n_a:]
    assert np.max(np.abs(cross)) > 1e-6
    np.testing.assert_allclose(joint.covariance,
                               np.linalg.inv(big.T @ (w[:, None] * big)), rtol=1e-6, atol=1e-12)


def test_without_constraints_the_arcs_are_independent():
    rng = np.random.default_rng(3)
    a, *_ = _arc(rng, 3, np.array([0, 1]))
    b, *_ = _arc(rng, 3, np.array([0, 1]))
    joint = joint_solve(a, b, np.zeros((0, 10)), np.zeros(0), np.zeros(0))
    np.testing.assert_allclose(joint.dx_a, np.linalg.solve(a.normals.matrix, a.normals.rhs),
                               rtol=1e-8)
    assert np.all(joint.covariance[:5, 5:] == 0.0)


def _phase_arc(rng, k, n_pass, rows_per_pass, sigma_m):
    """Synthetic phase-only arc: each pass sees its satellite along a slowly varying
    direction, so its float ambiguity is strongly correlated with the position parameters
    (as for short GNSS passes); returns the arc linearised at zero and the true values."""
    n = k + n_pass
    rows = []
    for p in range(n_pass):
        u = rng.normal(size=k)
        u /= np.linalg.norm(u)
        for _ in range(rows_per_pass):
            r = np.zeros(n)
            r[:k] = u + 0.1 * rng.normal(size=k)
            r[k + p] = 1.0
            rows.append(r)
    h = np.array(rows)
    x = rng.normal(size=n)
    w = np.full(h.shape[0], 1.0 / sigma_m**2)
    l = h @ x + rng.normal(scale=sigma_m, size=h.shape[0])
    ne = NormalEquations(matrix=h.T @ (w[:, None] * h), rhs=h.T @ (w * l), ltpl=0.0,
                         n_rows=h.shape[0])
    return ArcNormals(normals=ne, k=k, active=np.arange(n_pass), ambiguity_m=np.zeros(n_pass),
                      _solution=None, _state=None), x


def test_wrong_integer_is_a_baseline_jump():
    """A DD fixed one GPS narrow-lane wavelength (0.107 m) off moves the baseline (here the
    difference of the two arcs' position parameters) by many of its formal sigmas, while the
    right integer leaves it within them: closed loop with known truth."""
    rng = np.random.default_rng(7)
    k, n_pass = 3, 6
    (a, xa), (b, xb) = (_phase_arc(rng, k, n_pass, 10, 0.003) for _ in range(2))
    passes = np.arange(n_pass)
    i, j = np.array([0, 1, 2, 3, 4]), np.array([5, 5, 5, 5, 5])
    true_dd = (xb[k + i] - xa[k + i]) - (xb[k + j] - xa[k + j])

    def baseline(values):
        c = DdConstraints(i, i, j, j, values, np.full(i.size, 1e-3))
        joint = joint_solve(a, b, *dd_rows(a, b, passes, passes, c))
        sel = np.zeros((k, joint.covariance.shape[0]))
        sel[np.arange(k), joint.n_a + np.arange(k)] = 1.0
        sel[np.arange(k), np.arange(k)] = -1.0
        sigma = np.sqrt(np.diag(sel @ joint.covariance @ sel.T))
        return joint.dx_b[:k] - joint.dx_a[:k], sigma

    true_base = xb[:k] - xa[:k]
    right, sigma = baseline(true_dd)
    assert np.all(np.abs(right - true_base) < 4 * sigma)
    wrong, _ = baseline(true_dd + np.array([0.107, 0, 0, 0, 0]))
    assert np.max(np.abs(wrong - true_base) / sigma) > 10

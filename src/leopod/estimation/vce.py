"""Redundancy numbers of observation groups for variance component estimation (VCE).

The combined GPS + BDS-3 solutions of Zhang et al. (2024, Table 1: "observation weighting:
variance component estimation", their ref. [18], Bähr et al. 2007) weight each system by
variance components estimated from its residuals. leopod uses the iterated estimator of
Förstner (1979) (Koch 1999, "iterated estimates of variance components"): with groups ``g``
of observations whose weights are ``P_g = P_g⁰ / σ²_g``, the least-squares residuals ``v``,
the normal matrix ``N = AᵀPA`` (plus pseudo-observations) and ``N_g = A_gᵀP_gA_g`` the
contribution of group g, ::

    σ̂²_g = v_gᵀ P_g v_g / r_g,        r_g = n_g − tr(N⁻¹ N_g),                  (1)

``r_g`` the redundancy of the group (the sum of its partial redundancies; Σ_g r_g plus the
redundancy of the pseudo-observations is n − u). The weights are divided by ``σ̂²_g`` and the
system solved again until every ``σ̂²_g`` is 1 within a tolerance. A standard deviation
``σ̂²_g √(2/r_g)`` is reported for each factor (the variance of an estimated variance with
``r_g`` degrees of freedom for normally distributed residuals).

The receiver clocks are pre-eliminated from the normal equations
(:mod:`leopod.estimation.normals`), so ``tr(N⁻¹ N_g)`` is split into the clock part and the
rest. The full model's hat matrix is the sum of the (P-orthogonal) projector onto the clock
space, whose diagonal is ``w_r / S_e`` (``S_e`` the weight sum of the row's epoch), and the
projector ``Ã N⁻¹ ÃᵀP`` of the clock-projected rows ``ã_r = a_r − ā_e`` (every column minus
its weighted epoch mean), so that exactly ::

    r_g = n_g − Σ_{r∈g} w_r / S_e(r) − tr(N⁻¹ Σ_{r∈g} w_r ã_r ã_rᵀ)                 (2)

with ``N⁻¹`` the inverse of the reduced normal matrix. No approximation is made;
``tests/estimation/test_vce.py`` checks (2) against the dense computation with explicit
clock columns. The cost of one group is that of one accumulation of the normal equations.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from leopod.estimation.normals import Rows, _per_epoch, _quadratic_sum

__all__ = ["group_normals", "group_redundancy"]


def group_normals(rows: Rows, mask: np.ndarray) -> tuple[np.ndarray, float]:
    """Clock-projected normal-matrix contribution of the rows ``mask`` (module docstring).

    Parameters
    ----------
    rows : Rows
        All rows of the solution (the clock projection uses the weights of every row).
    mask : ndarray of bool, shape (r,)
        Rows of the group.

    Returns
    -------
    n_g : ndarray, shape (k + n_amb, k + n_amb)
        ``Σ_{r∈g} w_r ã_r ã_rᵀ`` in the parameters ``[x_o, x_a]`` of
        :func:`leopod.estimation.normals.accumulate`.
    clock_trace : float
        ``Σ_{r∈g} w_r / S_e(r)``: the group's share of the clock parameters.
    """
    e, a = rows._incidence()
    w = rows.weight
    ep = rows.epoch
    m, d, k = rows.partials.shape
    r = ep.size
    s = np.bincount(ep, weights=w, minlength=m)
    s_inv = np.where(s > 0, 1.0 / np.where(s > 0, s, 1.0), 0.0)
    u = rows.direction - (_per_epoch(ep, rows.direction * w[:, None], m) * s_inv[:, None])[ep]
    wg = np.where(mask, w, 0.0)
    c = _per_epoch(ep, ((wg[:, None] * u)[:, :, None] * u[:, None, :]).reshape(-1, d * d), m)
    p = rows.partials.reshape(m * d, k)
    # ambiguity columns minus their weighted epoch means (sparse: the ambiguities of the epoch)
    mean = sp.diags(s_inv) @ (e.T @ sp.diags(w) @ a)                     # (m, n_a)
    a_t = (a - e @ mean).tocsr()                                         # (r, n_a)
    n = np.empty((k + rows.n_amb, k + rows.n_amb))
    n[:k, :k] = _quadratic_sum(rows.partials, c.reshape(m, d, d))
    spread = sp.csr_matrix(((wg[:, None] * u).ravel(),
                            ((ep[:, None] * d + np.arange(d)).ravel(), np.repeat(np.arange(r), d))),
                           shape=(m * d, r))                             # (m d, r)
    n_oa = np.asarray(((spread @ a_t).T @ p).T)                           # (k, n_a)
    n[:k, k:] = n_oa
    n[k:, :k] = n_oa.T
    n[k:, k:] = (a_t.T @ sp.diags(wg) @ a_t).toarray()
    return n, float(np.sum(wg * s_inv[ep]))


def group_redundancy(rows: Rows, q: np.ndarray, mask: np.ndarray) -> float:
    """Redundancy ``r_g`` of the rows ``mask``, eq. (2) of the module docstring.

    Parameters
    ----------
    rows : Rows
    q : ndarray, shape (k + n_amb, k + n_amb)
        Inverse of the reduced normal matrix of the solution (pseudo-observations included),
        in units of the weights (:func:`leopod.estimation.normals.solve`).
    mask : ndarray of bool, shape (r,)

    Returns
    -------
    float
        ``n_g − Σ w_r/S_e − tr(q N_g)`` [1].
    """
    n_g, clock = group_normals(rows, mask)
    return float(np.count_nonzero(mask) - clock - np.sum(q * n_g))

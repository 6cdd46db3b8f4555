"""Normal equations with epoch-wise pre-eliminated receiver clocks.

Observation equations (one row per code or phase observation, weight ``w``)::

    l = A_o x_o + A_a x_a + c_e + v

with dense partials ``A_o`` of the arc parameters (orbit, dynamics, pulses, ...), the
incidence ``A_a`` of the float ambiguities (phase rows only) and one receiver clock ``c_e``
per epoch, common to all rows of the epoch. The clocks are eliminated epoch by epoch
(Bernese/GHOST practice; Jäggi et al. 2006 J. Geod. 80:47-60): with the incidence ``E`` of
rows on epochs, ``S = EᵀWE`` (diagonal, the weight sum of each epoch) and ``G = EᵀW[A_o A_a]``,
the reduced system is::

    N = HᵀWH − Gᵀ S⁻¹ G,     b = HᵀWl − Gᵀ S⁻¹ EᵀWl,     H = [A_o A_a].

This equals the normal equations of the rows projected onto the complement of the clocks
(every column minus its weighted epoch mean), so clocks never become unknowns; they are
recovered afterwards as ``c_e = (EᵀW(l − H x))_e / S_e``. The ambiguity blocks are built from
sparse matrices: a row touches one ambiguity, an epoch couples only the ambiguities observed
in it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.sparse as sp

__all__ = ["NormalEquations", "Rows", "accumulate", "epoch_clocks", "solve"]


@dataclass
class Rows:
    """Linearised observation rows.

    Attributes
    ----------
    a_o : ndarray, shape (r, k)
        Partials of the arc parameters.
    amb : ndarray of int, shape (r,)
        Ambiguity column of the row (−1 for code rows).
    epoch : ndarray of int, shape (r,)
        Epoch of the row (0 ... m−1).
    misclosure : ndarray, shape (r,)
        Observed minus computed [m].
    weight : ndarray, shape (r,)
        ``1/σ²`` [1/m²].
    n_epochs, n_amb : int
        Sizes of the clock and ambiguity axes.
    """

    a_o: np.ndarray
    amb: np.ndarray
    epoch: np.ndarray
    misclosure: np.ndarray
    weight: np.ndarray
    n_epochs: int
    n_amb: int

    def subset(self, keep: np.ndarray) -> Rows:
        """The rows where ``keep`` is True."""
        return Rows(self.a_o[keep], self.amb[keep], self.epoch[keep], self.misclosure[keep],
                    self.weight[keep], self.n_epochs, self.n_amb)

    def _incidence(self):
        r = self.epoch.size
        rows = np.arange(r)
        e = sp.csr_matrix((np.ones(r), (rows, self.epoch)), shape=(r, self.n_epochs))
        ph = self.amb >= 0
        a = sp.csr_matrix((np.ones(ph.sum()), (rows[ph], self.amb[ph])),
                          shape=(r, self.n_amb))
        return e, a


@dataclass
class NormalEquations:
    """Reduced normal equations ``N x = b`` of ``[x_o, x_a]`` (clocks eliminated).

    Attributes
    ----------
    matrix : ndarray, shape (k + n_amb, k + n_amb)
    rhs : ndarray, shape (k + n_amb,)
    ltpl : float
        ``lᵀWl`` after clock elimination (for the a-posteriori variance).
    n_rows : int
    """

    matrix: np.ndarray
    rhs: np.ndarray
    ltpl: float
    n_rows: int


def accumulate(rows: Rows) -> NormalEquations:
    """Normal equations of ``rows`` with the epoch clocks pre-eliminated (module docstring)."""
    e, a = rows._incidence()
    w = rows.weight
    l = rows.misclosure
    s = np.asarray(e.T @ w).ravel()
    s_inv = np.where(s > 0, 1.0 / np.where(s > 0, s, 1.0), 0.0)
    wa_o = rows.a_o * w[:, None]
    g_o = e.T @ wa_o                                                     # (m, k) dense
    wa = sp.diags(w) @ a                                                 # (r, n_a) sparse
    g_a = (e.T @ wa).tocsr()                                             # (m, n_a) sparse
    g_l = np.asarray(e.T @ (w * l)).ravel()                              # (m,)
    k = rows.a_o.shape[1]
    n = np.empty((k + rows.n_amb, k + rows.n_amb))
    n[:k, :k] = rows.a_o.T @ wa_o - g_o.T @ (g_o * s_inv[:, None])
    n_oa = np.asarray((wa.T @ rows.a_o).T) - np.asarray((g_a.T @ (g_o * s_inv[:, None])).T)
    n[:k, k:] = n_oa
    n[k:, :k] = n_oa.T
    n[k:, k:] = (a.T @ wa - g_a.T @ sp.diags(s_inv) @ g_a).toarray()
    b = np.empty(k + rows.n_amb)
    b[:k] = wa_o.T @ l - g_o.T @ (s_inv * g_l)
    b[k:] = np.asarray(wa.T @ l).ravel() - np.asarray(g_a.T @ (s_inv * g_l)).ravel()
    ltpl = float(np.sum(w * l * l) - np.sum(s_inv * g_l**2))
    return NormalEquations(matrix=n, rhs=b, ltpl=ltpl, n_rows=l.size)


def solve(ne: NormalEquations, constraint_weight: np.ndarray | None = None,
          constraint_rhs: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Solve the normal equations with optional diagonal pseudo-observations.

    Parameters
    ----------
    ne : NormalEquations
    constraint_weight : ndarray, shape (p,), optional
        Added to the diagonal (``1/σ²`` of a-priori constraints; 0: none).
    constraint_rhs : ndarray, shape (p,), optional
        Added to the right-hand side (``(x_apriori − x_current)/σ²``).

    Returns
    -------
    dx : ndarray, shape (p,)
        Correction.
    covariance : ndarray, shape (p, p)
        ``N⁻¹`` (in units of the weights; multiply by σ0² for a-posteriori values).
    """
    n = ne.matrix.copy()
    b = ne.rhs.copy()
    if constraint_weight is not None:
        n[np.diag_indices_from(n)] += constraint_weight
        b += constraint_rhs
    d = np.sqrt(np.diag(n))
    if np.any(~np.isfinite(d)) or np.any(d == 0):
        raise ValueError("normal matrix has a parameter without observations")
    scaled = n / np.outer(d, d)
    factor = scipy.linalg.cho_factor(scaled, lower=True, check_finite=False)
    dx = scipy.linalg.cho_solve(factor, b / d, check_finite=False) / d
    inv = scipy.linalg.cho_solve(factor, np.eye(n.shape[0]), check_finite=False)
    return dx, inv / np.outer(d, d)


def epoch_clocks(rows: Rows, dx: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Receiver clocks and residuals after the solution ``dx`` of ``[x_o, x_a]``.

    Returns
    -------
    clocks : ndarray, shape (m,)
        Weighted mean per epoch of ``l − H dx`` [m] (NaN for epochs without rows).
    residuals : ndarray, shape (r,)
        ``l − H dx − c_e`` [m].
    """
    k = rows.a_o.shape[1]
    reduced = rows.misclosure - rows.a_o @ dx[:k]
    ph = rows.amb >= 0
    reduced[ph] -= dx[k + rows.amb[ph]]
    w = rows.weight
    s = np.bincount(rows.epoch, weights=w, minlength=rows.n_epochs)
    num = np.bincount(rows.epoch, weights=w * reduced, minlength=rows.n_epochs)
    clocks = np.full(rows.n_epochs, np.nan)
    has = s > 0
    clocks[has] = num[has] / s[has]
    return clocks, reduced - clocks[rows.epoch]

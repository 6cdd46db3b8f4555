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

Rows factor through the epoch. A GNSS observation depends on the arc parameters only through
the receiver position at its epoch, so its row of ``A_o`` is ``u_r · P_e``: a direction
``u_r`` (d,) of the row (for a range, minus the line of sight) times the partials ``P_e``
(d, k) of the epoch (position partials, shared by all rows of the epoch). ``A_o`` is never
formed (it would be rows × k doubles). The projection onto the complement of the clocks acts
on the directions only, ``ũ_r = u_r − ū_e`` with ``ū_e`` the weighted mean direction of the
epoch, and since ``Σ_{r∈e} w_r ũ_r = 0``::

    N_oo = Σ_e P_eᵀ C_e P_e,  C_e = Σ_{r∈e} w_r ũ_r ũ_rᵀ   (d × d per epoch)
    N_oa[:, j] = Σ_{r: amb j} w_r P_eᵀ ũ_r,     b_o = Σ_e P_eᵀ Σ_{r∈e} w_r l_r ũ_r.

``N_oo`` is summed over blocks of epochs and only over the leading columns that are non-zero
in the block (pulses act only after their epoch, piecewise parameters only after the start of
their interval), which more than halves the work of the dominant product for a POD arc with
pulses.

Further sparse columns ``X`` (r, x) - parameters that do not factor through the epoch, e.g.
the bilinear weights of antenna PCV nodes (:mod:`leopod.antenna.pcv_direct`) - join the
ambiguities: with ``S = [A_a X]`` every ambiguity formula above holds for ``S``, and the
unknowns become ``[x_o, x_a, x_x]``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.sparse as sp

__all__ = ["NormalEquations", "Rows", "accumulate", "epoch_clocks", "leading_blocks", "solve"]

#: Blocks of consecutive epochs of the ``N_oo`` sum: one matrix product each (few calls keep
#: the overhead of threaded BLAS low; 16 blocks do 41 % of the full product on GRACE-A
#: 2007-080, 64 blocks 40 %).
_N_BLOCKS = 16


@dataclass
class Rows:
    """Linearised observation rows, their arc-parameter partials factored by epoch.

    Row ``r`` of ``A_o`` is ``direction[r] @ partials[epoch[r]]`` (module docstring).

    Attributes
    ----------
    direction : ndarray, shape (r, d)
        Direction of each row in the space of the epoch's partials (for a GNSS range, minus
        the unit line of sight, GCRF).
    partials : ndarray, shape (m, d, k)
        Partials of the epoch's position-like quantity (d components) w.r.t. the k arc
        parameters [m per parameter unit].
    amb : ndarray of int, shape (r,)
        Ambiguity column of the row (−1 for code rows).
    epoch : ndarray of int, shape (r,)
        Epoch of the row (0 ... m−1).
    misclosure : ndarray, shape (r,)
        Observed minus computed [m].
    weight : ndarray, shape (r,)
        ``1/σ²`` [1/m²].
    n_amb : int
        Size of the ambiguity axis.
    """

    direction: np.ndarray
    partials: np.ndarray
    amb: np.ndarray
    epoch: np.ndarray
    misclosure: np.ndarray
    weight: np.ndarray
    n_amb: int

    @property
    def n_epochs(self) -> int:
        """Size of the clock (epoch) axis."""
        return self.partials.shape[0]

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


def _per_epoch(epoch: np.ndarray, values: np.ndarray, m: int) -> np.ndarray:
    """Sums of ``values`` (r, c) over the rows of each epoch: (m, c)."""
    return np.stack([np.bincount(epoch, weights=v, minlength=m) for v in values.T], axis=1)


def _quadratic_sum(p: np.ndarray, c: np.ndarray) -> np.ndarray:
    """``Σ_e P_eᵀ C_e P_e`` of ``p`` (m, d, k) and ``c`` (m, d, d): (k, k).

    Summed over ``_N_BLOCKS`` blocks of consecutive epochs, each over the leading columns up
    to the last one that is non-zero in the block (the columns after it contribute exact
    zeros).
    """
    k = p.shape[2]
    cp = np.einsum("mij,mjk->mik", c, p)
    out = np.zeros((k, k))
    for block, n in leading_blocks(p):
        out[:n, :n] += p[block, :, :n].reshape(-1, n).T @ cp[block, :, :n].reshape(-1, n)
    return out


def leading_blocks(p: np.ndarray, n_blocks: int = _N_BLOCKS):
    """Blocks of consecutive epochs of partials ``p`` (m, d, k) and, for each, the number of
    leading columns up to the last one that is non-zero in the block (blocks of zeros only
    are left out): products over a block may stop there, the columns after it being exact
    zeros (pulses after the block, piecewise parameters of later intervals).

    Yields
    ------
    block : slice
        Epochs of the block (``n_blocks`` blocks of equal size, the last one shorter).
    n : int
        Leading columns to keep, 1 ... k.
    """
    m = p.shape[0]
    nonzero = np.any(p != 0.0, axis=1)                                   # (m, k)
    size = max(-(-m // n_blocks), 1)
    for start in range(0, m, size):
        block = slice(start, start + size)
        columns = np.flatnonzero(nonzero[block].any(axis=0))
        if columns.size:
            yield block, int(columns[-1]) + 1


def accumulate(rows: Rows, extra: sp.spmatrix | None = None) -> NormalEquations:
    """Normal equations of ``rows`` with the epoch clocks pre-eliminated (module docstring).

    Parameters
    ----------
    rows : Rows
    extra : scipy.sparse matrix, shape (r, x), optional
        Further columns of the rows (module docstring), unknowns after the ambiguities.

    Returns
    -------
    NormalEquations
        Over ``[x_o (k), x_a (n_amb), x_x (x)]``.
    """
    e, a = rows._incidence()
    if extra is not None:
        a = sp.hstack([a, sp.csr_matrix(extra)]).tocsr()
    n_s = a.shape[1]
    w = rows.weight
    l = rows.misclosure
    ep = rows.epoch
    m, d, k = rows.partials.shape
    s = np.bincount(ep, weights=w, minlength=m)
    s_inv = np.where(s > 0, 1.0 / np.where(s > 0, s, 1.0), 0.0)
    # directions projected onto the complement of the clocks: minus their weighted epoch mean
    u = rows.direction - (_per_epoch(ep, rows.direction * w[:, None], m) * s_inv[:, None])[ep]
    wu = u * w[:, None]
    c = _per_epoch(ep, (wu[:, :, None] * u[:, None, :]).reshape(-1, d * d), m)
    p = rows.partials.reshape(m * d, k)
    r = l.size
    wu_rows = sp.csr_matrix((wu.ravel(), (np.repeat(np.arange(r), d),
                                          (ep[:, None] * d + np.arange(d)).ravel())),
                            shape=(r, m * d))                            # (r, m d) sparse
    q_a = (wu_rows.T @ a).tocsr()                                        # (m d, n_s) sparse
    wa = sp.diags(w) @ a                                                 # (r, n_s) sparse
    g_a = (e.T @ wa).tocsr()                                             # (m, n_s) sparse
    g_l = np.bincount(ep, weights=w * l, minlength=m)                    # (m,)
    n = np.empty((k + n_s, k + n_s))
    n[:k, :k] = _quadratic_sum(rows.partials, c.reshape(m, d, d))
    n_oa = np.asarray((q_a.T @ p).T)
    n[:k, k:] = n_oa
    n[k:, :k] = n_oa.T
    n[k:, k:] = (a.T @ wa - g_a.T @ sp.diags(s_inv) @ g_a).toarray()
    b = np.empty(k + n_s)
    b[:k] = p.T @ _per_epoch(ep, wu * l[:, None], m).ravel()
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


def epoch_clocks(rows: Rows, dx: np.ndarray, extra: sp.spmatrix | None = None
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Receiver clocks and residuals after the solution ``dx`` of ``[x_o, x_a]`` (and
    ``x_x`` of the ``extra`` columns (r, x) of :func:`accumulate`).

    Returns
    -------
    clocks : ndarray, shape (m,)
        Weighted mean per epoch of ``l − H dx`` [m] (NaN for epochs without rows).
    residuals : ndarray, shape (r,)
        ``l − H dx − c_e`` [m].
    """
    m, d, k = rows.partials.shape
    shift = (rows.partials.reshape(m * d, k) @ dx[:k]).reshape(m, d)
    reduced = rows.misclosure - np.sum(rows.direction * shift[rows.epoch], axis=1)
    ph = rows.amb >= 0
    reduced[ph] -= dx[k + rows.amb[ph]]
    if extra is not None:
        reduced -= sp.csr_matrix(extra) @ dx[k + rows.n_amb:]
    w = rows.weight
    s = np.bincount(rows.epoch, weights=w, minlength=rows.n_epochs)
    num = np.bincount(rows.epoch, weights=w * reduced, minlength=rows.n_epochs)
    clocks = np.full(rows.n_epochs, np.nan)
    has = s > 0
    clocks[has] = num[has] / s[has]
    return clocks, reduced - clocks[rows.epoch]

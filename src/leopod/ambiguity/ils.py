"""Integer least squares (ILS) of a correlated ambiguity set: LAMBDA decorrelation and search.

Problem (Teunissen 1995): given float ambiguities ``a`` [cycles] with covariance ``Q``
[cycles²], find ``ž = argmin_{z ∈ Zⁿ} (a − z)ᵀ Q⁻¹ (a − z)``.

1. **Factorisation** ``Q = Lᵀ D L`` with ``L`` unit lower triangular, ``D`` diagonal,
   computed from the last row upwards (de Jonge & Tiberius 1996, sec. 3.3): ``D_i`` is the
   variance of ``a_i`` conditioned on ``a_{i+1} … a_n``.
2. **Decorrelation** by a unimodular integer matrix ``Z`` (``|det Z| = 1``, integer inverse:
   the integer lattice is mapped onto itself), ``Q_z = Zᵀ Q Z``, ``z = Zᵀ a``: integer Gauss
   transformations make ``|L_ij| <= 1/2`` and a swap of neighbours ``k, k+1`` is done when it
   moves variance to the back, ``D_k + L²_{k+1,k} D_{k+1} < D_{k+1}`` (Teunissen 1995, sec.
   3; de Jonge & Tiberius 1996, sec. 3.5), with the lazy reduction and local restart of
   MLAMBDA (Chang et al. 2005) and the whole of ``L`` reduced at the end. ``det Q_z = det Q``.
3. **Search** of the ellipsoid ``Σ_i (ẑ_{i|I} − z_i)²/D_i < χ²`` from the last component to
   the first, enumerating each level's integers in order of distance from the conditional
   float value (de Jonge & Tiberius 1996, sec. 4), with the bound shrunk to the second-best
   value found (so that the best and the second-best integer vectors are both exact; the
   initial bound is that of the bootstrapped vector and its best one-component variant).
4. **Ratio test** ``q₂/q₁ >= c`` (a fixed critical value, the common practice reviewed by
   Verhagen & Teunissen 2013) and the bootstrapped **success rate** of the decorrelated
   set, ``Π_i (2Φ(1/(2 sqrt(D_i))) − 1)``, a lower bound of the ILS success rate (Teunissen
   1998, 1999).
5. **Partial fixing** (:func:`partial_ils`): when the test fails, the worst-determined
   ambiguities (largest variance) are left float and the rest solved again — a subset in the
   original ambiguities, so that each fixed one is still a single difference (the fixed POD
   takes constraints on single differences only).

Written for leopod from the equations of the cited papers.
"""

from __future__ import annotations

import logging
from typing import NamedTuple

import numpy as np
from scipy.special import ndtr

__all__ = ["IlsResult", "decorrelate", "ils", "ltdl", "partial_ils", "search"]

log = logging.getLogger(__name__)

_MAX_NODES = 2_000_000   # search nodes before giving up (a degenerate or huge problem)


def ltdl(q) -> tuple[np.ndarray, np.ndarray]:
    """``Q = Lᵀ diag(D) L`` with unit lower-triangular ``L`` (module docstring, step 1).

    Parameters
    ----------
    q : array_like, shape (n, n)
        Symmetric positive-definite covariance [cycles²].

    Returns
    -------
    L : ndarray, shape (n, n)
    D : ndarray, shape (n,)
        Conditional variances [cycles²].

    Raises
    ------
    ValueError
        If ``Q`` is not positive definite.
    """
    a = np.array(q, dtype=float)
    n = a.shape[0]
    lower = np.zeros((n, n))
    d = np.zeros(n)
    for i in range(n - 1, -1, -1):
        if not a[i, i] > 0.0:
            raise ValueError("the covariance matrix is not positive definite")
        d[i] = a[i, i]
        row = a[i, : i + 1] / np.sqrt(d[i])
        a[:i, :i] -= np.outer(row[:i], row[:i])
        lower[i, : i + 1] = a[i, : i + 1] / d[i]
    return lower, d


def _gauss(lower, z, i, j):
    """Integer Gauss transformation making ``|L_ij| <= 1/2`` (i > j)."""
    mu = np.rint(lower[i, j])
    if mu != 0.0:
        lower[i:, j] -= mu * lower[i:, i]
        z[:, j] -= mu * z[:, i]


def _swap(lower, d, z, k):
    """Swap components ``k`` and ``k+1`` and update ``L``, ``D`` and ``Z``."""
    # Derived by matching d_k u uᵀ + d_{k+1} v vᵀ (rows k, k+1 after the column swap) with
    # the new rows: δ = d_k + η² d_{k+1}, λ = d_{k+1} η/δ, d'_k = d_k d_{k+1}/δ, d'_{k+1} = δ;
    # columns j < k: L'_k = L_{k+1} − η L_k, L'_{k+1} = (d_k/δ) L_k + λ L_{k+1}.
    eta = lower[k + 1, k]
    delta = d[k] + eta * eta * d[k + 1]
    lam = d[k + 1] * eta / delta
    block = np.array([[-eta, 1.0], [d[k] / delta, lam]])
    d[k], d[k + 1] = d[k] * d[k + 1] / delta, delta
    lower[[k, k + 1], :k] = block @ lower[[k, k + 1], :k]
    lower[k + 1, k] = lam
    lower[k + 2:, [k, k + 1]] = lower[k + 2:, [k + 1, k]]
    z[:, [k, k + 1]] = z[:, [k + 1, k]]


def decorrelate(q) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """LAMBDA decorrelation ``Q_z = Zᵀ Q Z`` (module docstring, step 2).

    Parameters
    ----------
    q : array_like, shape (n, n)
        Covariance [cycles²].

    Returns
    -------
    Z : ndarray of float (integer values), shape (n, n)
        Unimodular transformation; ``z = Zᵀ a``.
    L, D : ndarray
        Factors of ``Q_z = Lᵀ diag(D) L``.
    """
    lower, d = ltdl(q)
    n = d.size
    z = np.eye(n)
    k = n - 2
    while k >= 0:
        # only the entry of the swap test is reduced here, and after a swap only the pair
        # above it can have changed: MLAMBDA, Chang et al. 2005 (the original LAMBDA reduces
        # the whole column and restarts from the last pair: O(n) times slower for large n)
        _gauss(lower, z, k + 1, k)
        if d[k] + lower[k + 1, k] ** 2 * d[k + 1] < d[k + 1] * (1.0 - 1e-12):
            _swap(lower, d, z, k)
            k = min(k + 1, n - 2)
        else:
            k -= 1
    for j in range(n - 1):        # all of L reduced (the swaps leave earlier columns intact)
        for i in range(j + 1, n):
            _gauss(lower, z, i, j)
    return z, lower, d


def search(a_z, lower, d, n_best: int = 2) -> tuple[np.ndarray, np.ndarray]:
    """The ``n_best`` integer vectors of smallest ``q(z) = Σ (ẑ_{i|I} − z_i)²/D_i``.

    Parameters
    ----------
    a_z : ndarray, shape (n,)
        Float ambiguities in the decorrelated space [cycles].
    lower, d : ndarray
        ``Q_z = Lᵀ diag(D) L`` (:func:`decorrelate`).
    n_best : int
        Number of candidates (>= 1).

    Returns
    -------
    candidates : ndarray, shape (n_best, n)
        Integer vectors, best first.
    q : ndarray, shape (n_best,)
        Their squared norms [1].

    Raises
    ------
    RuntimeError
        If the search visits more than 2e6 nodes.
    """
    n = a_z.size
    best_z = np.zeros((n_best, n))
    best_q = np.full(n_best, np.inf)
    z = np.zeros(n)
    cond = np.zeros(n)       # conditional float values ẑ_{i|I}
    dist = np.zeros(n + 1)   # partial sums from the back: dist[i] = Σ_{j>i} …
    step = np.zeros(n)
    nodes = 0
    i = n - 1
    cond[i] = a_z[i]
    z[i] = np.rint(cond[i])
    step[i] = 1.0 if cond[i] - z[i] >= 0 else -1.0
    while True:
        nodes += 1
        if nodes > _MAX_NODES:
            raise RuntimeError("integer least-squares search exceeded 2e6 nodes")
        new = dist[i + 1] + (cond[i] - z[i]) ** 2 / d[i]
        if new < best_q[-1]:
            if i > 0:
                dist[i] = new
                i -= 1
                # ẑ_{i|I} = a_i − Σ_{j>i} L_ji (ẑ_{j|J} − z_j)
                cond[i] = a_z[i] - lower[i + 1:, i] @ (cond[i + 1:] - z[i + 1:])
                z[i] = np.rint(cond[i])
                step[i] = 1.0 if cond[i] - z[i] >= 0 else -1.0
                continue
            k = int(np.searchsorted(best_q, new))
            best_q[k + 1:] = best_q[k:-1].copy()
            best_z[k + 1:] = best_z[k:-1].copy()
            best_q[k], best_z[k] = new, z
            z[0] += step[0]
            step[0] = -step[0] - np.sign(step[0])
            continue
        if i == n - 1:
            break
        i += 1
        z[i] += step[i]
        step[i] = -step[i] - np.sign(step[i])
    return best_z, best_q


class IlsResult(NamedTuple):
    """Integer least-squares solution of a (sub)set.

    Attributes
    ----------
    integer : ndarray of int64, shape (n,)
        Best integer vector in the original ambiguities.
    q_best, q_second : float
        ``(a − ž)ᵀ Q⁻¹ (a − ž)`` of the best and second-best vector [1].
    ratio : float
        ``q_second / q_best`` (inf when ``q_best`` is 0).
    success_rate : float
        Bootstrapped success rate of the decorrelated set (a lower bound of the ILS one).
    """

    integer: np.ndarray
    q_best: float
    q_second: float
    ratio: float
    success_rate: float


def ils(value_cyc, covariance_cyc2) -> IlsResult:
    """Integer least squares by LAMBDA (module docstring, steps 1–4).

    Parameters
    ----------
    value_cyc : array_like, shape (n,)
        Float ambiguities [cycles], finite.
    covariance_cyc2 : array_like, shape (n, n)
        Their covariance [cycles²], symmetric positive definite.

    Returns
    -------
    IlsResult

    Raises
    ------
    ValueError
        If shapes do not match, values are not finite or ``Q`` is not positive definite.
    """
    return _search(*_prepare(value_cyc, covariance_cyc2))


def _prepare(value_cyc, covariance_cyc2):
    """Checked inputs, decorrelation and bootstrapped success rate of :func:`ils`."""
    a = np.asarray(value_cyc, dtype=float)
    q = np.asarray(covariance_cyc2, dtype=float)
    if a.ndim != 1 or a.size == 0 or q.shape != (a.size, a.size):
        raise ValueError(f"need value (n,), n >= 1, and covariance (n, n), got {a.shape} and "
                         f"{q.shape}")
    if not (np.all(np.isfinite(a)) and np.all(np.isfinite(q))):
        raise ValueError("values and covariance must be finite")
    shift = np.rint(a)                      # search near zero: better conditioned sums
    zmat, lower, d = decorrelate(0.5 * (q + q.T))
    success = float(np.prod(2.0 * ndtr(0.5 / np.sqrt(d)) - 1.0))
    return a - shift, shift, zmat, lower, d, success


def _search(a, shift, zmat, lower, d, success) -> IlsResult:
    """Search step of :func:`ils` on the output of :func:`_prepare`."""
    cand, qq = search(zmat.T @ a, lower, d, n_best=2)
    integer = np.rint(np.linalg.solve(zmat.T, cand[0])).astype(np.int64) + shift.astype(np.int64)
    ratio = np.inf if qq[0] == 0.0 else float(qq[1] / qq[0])
    return IlsResult(integer, float(qq[0]), float(qq[1]), ratio, success)


def partial_ils(value_cyc, covariance_cyc2, *, min_ratio: float,
                min_success_rate: float, drop_fraction: float = 0.1
                ) -> tuple[np.ndarray, IlsResult | None]:
    """ILS of the largest well-determined subset that passes ratio and success-rate tests.

    The full set is tried first; while the test fails, the ``drop_fraction`` (at least one)
    of the remaining ambiguities with the largest variance is left float (partial ambiguity
    resolution: the best-determined subset that passes, Teunissen et al. 1999; Parkins 2011).
    A subset whose bootstrapped success rate is too low is not searched, and a search that
    exceeds its node limit counts as a failed test.

    Parameters
    ----------
    value_cyc : array_like, shape (n,)
        Float ambiguities [cycles].
    covariance_cyc2 : array_like, shape (n, n)
        Covariance [cycles²].
    min_ratio : float
        Critical value of ``q₂/q₁`` (>= 1).
    min_success_rate : float
        Smallest accepted bootstrapped success rate.
    drop_fraction : float
        Share of the subset left float per round.

    Returns
    -------
    fixed : ndarray of bool, shape (n,)
        Which ambiguities are fixed.
    result : IlsResult or None
        Solution of the fixed subset, ``integer`` of length ``fixed.sum()``; None if no subset
        passes.
    """
    a = np.asarray(value_cyc, dtype=float)
    q = np.asarray(covariance_cyc2, dtype=float)
    keep = np.argsort(np.diag(q), kind="stable")       # best determined first
    while keep.size:
        sub = np.sort(keep)
        prepared = _prepare(a[sub], q[np.ix_(sub, sub)])
        res = None
        if prepared[-1] >= min_success_rate:    # no search for a subset that fails anyway
            try:
                res = _search(*prepared)
            except RuntimeError as err:          # a huge search: treated as a failed test
                log.debug("partial ILS, %d ambiguities: %s", sub.size, err)
        if res is not None and res.ratio >= min_ratio:
            fixed = np.zeros(a.size, dtype=bool)
            fixed[sub] = True
            log.debug("partial ILS: %d of %d fixed, ratio %.2f, success rate %.6f", sub.size,
                      a.size, res.ratio, res.success_rate)
            return fixed, res
        keep = keep[: keep.size - max(1, int(drop_fraction * keep.size))]
    return np.zeros(a.size, dtype=bool), None

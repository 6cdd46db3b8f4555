"""Fixing decisions for float ambiguities in cycles (vectorised over ambiguities).

* :func:`rounding_decision` — the rule of Peng et al. (2021) (Table II: "Wide-lane fixing decision
  0.24 cycles", "Narrow-lane fixing decision 0.12 cycles"): fix to the nearest integer when
  ``|x − round(x)| <= max_dev_cyc`` and ``sigma <= max_sigma_cyc``. The text of Peng et al. (2021)
  calls the 0.24 cycles "the STD threshold value of the WL ambiguities for making the fixing
  decision", its Table II a "fixing decision": both bounds are therefore parameters (the
  caller chooses which sigma, formal or empirical STD, to pass).
* :func:`dong_bock_probability` / :func:`dong_bock_decision` — Dong, D., Bock, Y. (1989)
  "Global Positioning System network analysis with phase ambiguity resolution applied to
  crustal deformation studies in California", J. Geophys. Res. 94(B4), 3949-3966, App. A
  (eq. A-12), as used by the BDS SCB-AR paper, eq. (9), with ``α = 0.1 %``.
* :func:`integer_bootstrap` — sequential conditional rounding of a correlated set
  (Teunissen, P.J.G. (1998) "Success probability of integer GPS ambiguity rounding and
  bootstrapping", J. Geodesy 72, 606-612), without decorrelation, with its success rate
  and a ratio test.
"""

from __future__ import annotations

import logging
from typing import NamedTuple

import numpy as np
from scipy.special import erfc, ndtr

__all__ = [
    "DONG_BOCK_ALPHA", "NL_MAX_DEV_CYC", "WL_MAX_DEV_CYC", "BootstrapResult", "FixDecision",
    "dong_bock_decision", "dong_bock_probability", "integer_bootstrap", "rounding_decision",
]

logger = logging.getLogger(__name__)

#: Largest deviation from the nearest integer of a fixable WL ambiguity [cycles] (Peng et al. 2021,
#: Table II).
WL_MAX_DEV_CYC = 0.24
#: Largest deviation from the nearest integer of a fixable NL ambiguity [cycles] (Peng et al. 2021,
#: Table II).
NL_MAX_DEV_CYC = 0.12
#: Largest accepted probability of a wrong rounding, ``1 − P0`` (BDS SCB-AR paper: α = 0.1 %).
DONG_BOCK_ALPHA = 1e-3

_DB_TERM_TOL = 1e-17     # an element's Dong & Bock series stops when its term is below this
_DB_MAX_SIGMA_CYC = 1e4  # larger sigmas (~9 sigma terms) are not summed: P0 is NaN


class FixDecision(NamedTuple):
    """Outcome of a fixing decision for m ambiguities.

    Attributes
    ----------
    integer : ndarray of int64, shape (m,)
        Nearest integer (0 where the input is not finite).
    fraction_cyc : ndarray, shape (m,)
        ``x − integer`` in ``[−0.5, 0.5)`` [cycles] (NaN where not finite).
    fixed : ndarray of bool, shape (m,)
        Whether the ambiguity is fixed to ``integer``.
    reason : ndarray of str (object), shape (m,)
        Why an ambiguity is not fixed (``"fractional part 0.31 > 0.24"``); "" where fixed.
    """

    integer: np.ndarray
    fraction_cyc: np.ndarray
    fixed: np.ndarray
    reason: np.ndarray


def _nearest(value_cyc) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Nearest integer (half up), fraction in [−0.5, 0.5), finiteness."""
    x = np.atleast_1d(np.asarray(value_cyc, dtype=float))
    finite = np.isfinite(x)
    n = np.floor(np.where(finite, x, 0.0) + 0.5)
    return n.astype(np.int64), np.where(finite, x - n, np.nan), finite


def _join(messages: list[np.ndarray], size: int) -> np.ndarray:
    """Element-wise "; "-join of the non-empty messages."""
    out = np.empty(size, dtype=object)
    for k in range(size):
        out[k] = "; ".join(m[k] for m in messages if m[k])
    return out


def _messages(mask: np.ndarray, make) -> np.ndarray:
    """``make(k)`` where ``mask`` is set, "" elsewhere."""
    out = np.full(mask.size, "", dtype=object)
    for k in np.nonzero(mask)[0]:
        out[k] = make(k)
    return out


def rounding_decision(value_cyc, sigma_cyc, *, max_dev_cyc: float,
                      max_sigma_cyc: float = np.inf) -> FixDecision:
    """Fixing rule of Peng et al. (2021): fractional part and sigma below their bounds.

    Parameters
    ----------
    value_cyc : array_like, shape (m,)
        Float ambiguities [cycles].
    sigma_cyc : array_like, shape (m,)
        Their sigma (formal or empirical STD) [cycles].
    max_dev_cyc : float
        Largest ``|x − round(x)|`` [cycles] (:data:`WL_MAX_DEV_CYC`,
        :data:`NL_MAX_DEV_CYC`).
    max_sigma_cyc : float
        Largest sigma [cycles] (default: no bound).

    Returns
    -------
    FixDecision
        Fixed iff value and sigma are finite, ``|fraction| <= max_dev_cyc`` and
        ``sigma <= max_sigma_cyc``; every rejection says which bound failed.
    """
    integer, frac, finite = _nearest(value_cyc)
    sigma = np.broadcast_to(np.asarray(sigma_cyc, dtype=float), integer.shape)
    bad_input = ~finite | ~np.isfinite(sigma)
    dev = np.abs(np.where(bad_input, 0.0, frac))
    sig = np.where(bad_input, 0.0, sigma)
    too_far = ~bad_input & (dev > max_dev_cyc)
    too_loose = ~bad_input & (sig > max_sigma_cyc)
    reason = _join([
        _messages(bad_input, lambda k: "value or sigma not finite"),
        _messages(too_far, lambda k: f"fractional part {dev[k]:.2f} > {max_dev_cyc:.2f}"),
        _messages(too_loose, lambda k: f"sigma {sig[k]:.3f} > {max_sigma_cyc:.3f}"),
    ], integer.size)
    fixed = ~(bad_input | too_far | too_loose)
    logger.debug("rounding decision: %d of %d fixed", int(fixed.sum()), fixed.size)
    return FixDecision(integer=integer, fraction_cyc=frac, fixed=fixed, reason=reason)


def dong_bock_probability(value_cyc, sigma_cyc) -> np.ndarray:
    """Dong & Bock (1989) probability ``P0`` of the nearest integer (BDS SCB-AR paper, eq. (9)).

    ``P0 = 1 − Σ_{i=1}^{∞} [erfc((i − d)/(√2 σ)) − erfc((i + d)/(√2 σ))]``,
    ``d = |x − round(x)|``. Each term is the probability that an ``N(0, σ²)`` variable has
    ``|e|`` in ``(i − d, i + d)``; the terms decrease with ``i`` and the series is summed
    until they fall below 1e-17. The text of the BDS SCB-AR paper calls σ "its variance": it is
    the standard deviation (erfc argument ``(i ∓ d)/(√2 σ)``, as in Dong & Bock 1989, eq. A-12).

    Properties: ``P0 = 1`` for ``d = 0`` whatever σ (combine with a sigma bound);
    ``P0 = erf(1/(2√2 σ))`` for ``d = 1/2`` (the series telescopes); ``P0 → 1`` as
    ``σ → 0`` for ``d < 1/2``; ``P0 → 1 − 2d`` as ``σ → ∞``.

    Parameters
    ----------
    value_cyc : array_like, shape (m,)
        Float ambiguities [cycles].
    sigma_cyc : array_like, shape (m,)
        Their standard deviations [cycles], > 0.

    Returns
    -------
    ndarray, shape (m,)
        ``P0``; NaN where value or sigma is not finite, sigma <= 0 or sigma > 1e4 cycles.
    """
    _, frac, finite = _nearest(value_cyc)
    sigma = np.broadcast_to(np.asarray(sigma_cyc, dtype=float), frac.shape)
    ok = finite & np.isfinite(sigma) & (sigma > 0.0) & (sigma <= _DB_MAX_SIGMA_CYC)
    d = np.abs(np.where(ok, frac, 0.0))
    scale = 1.0 / (np.sqrt(2.0) * np.where(ok, sigma, 1.0))
    q = np.zeros(frac.shape)
    active = np.nonzero(ok)[0]
    i = 1
    while active.size:
        term = erfc((i - d[active]) * scale[active]) - erfc((i + d[active]) * scale[active])
        q[active] += term
        active = active[term > _DB_TERM_TOL]
        i += 1
    return np.where(ok, 1.0 - q, np.nan)


def dong_bock_decision(value_cyc, sigma_cyc, *, alpha: float = DONG_BOCK_ALPHA) -> FixDecision:
    """Fix to the nearest integer when ``1 − P0 <= alpha`` (BDS SCB-AR paper, eq. (9)).

    Parameters
    ----------
    value_cyc, sigma_cyc : array_like, shape (m,)
        Float ambiguities and their standard deviations [cycles].
    alpha : float
        Largest accepted ``1 − P0`` (BDS SCB-AR paper: 0.1 %).

    Returns
    -------
    FixDecision
        Rejections read ``"1 - P0 = 0.0123 > alpha 0.001"``.
    """
    integer, frac, _ = _nearest(value_cyc)
    q = 1.0 - dong_bock_probability(value_cyc, sigma_cyc)
    bad_input = ~np.isfinite(q)
    too_likely = ~bad_input & (q > alpha)
    reason = _join([
        _messages(bad_input, lambda k: "value or sigma not finite or not positive"),
        _messages(too_likely, lambda k: f"1 - P0 = {q[k]:.3g} > alpha {alpha:.3g}"),
    ], integer.size)
    fixed = ~(bad_input | too_likely)
    logger.debug("Dong & Bock decision: %d of %d fixed", int(fixed.sum()), fixed.size)
    return FixDecision(integer=integer, fraction_cyc=frac, fixed=fixed, reason=reason)


class BootstrapResult(NamedTuple):
    """Integer bootstrapping of a correlated ambiguity vector.

    Attributes
    ----------
    integer : ndarray of int64, shape (n,)
        The integer candidate with the smallest ``q`` (the bootstrapped vector, unless one
        of the alternatives of :func:`integer_bootstrap` is closer).
    order : ndarray of int64, shape (n,)
        Order in which the components were rounded (smallest conditional variance first).
    conditional_sigma_cyc : ndarray, shape (n,)
        Conditional standard deviations ``σ_{i|I}`` [cycles], in ``order``.
    success_rate : float
        Bootstrapping success rate ``Π_i (2 Φ(1/(2 σ_{i|I})) − 1)`` (Teunissen 1998).
    q_best, q_second : float
        ``(a − z)^T Q^-1 (a − z)`` of the best and second-best candidate found.
    ratio : float
        ``q_second / q_best`` (inf if ``q_best`` is 0).
    """

    integer: np.ndarray
    order: np.ndarray
    conditional_sigma_cyc: np.ndarray
    success_rate: float
    q_best: float
    q_second: float
    ratio: float


def _pivoted_ldl(cov: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``Q[order][:, order] = L D L^T`` choosing the smallest conditional variance first.

    Returns ``order`` (n,), unit lower-triangular ``L`` (n, n) in that order, ``D`` (n,).
    """
    n = cov.shape[0]
    schur = cov.copy()
    remaining = np.ones(n, dtype=bool)
    order = np.empty(n, dtype=np.int64)
    columns = np.zeros((n, n))
    d = np.empty(n)
    for k in range(n):
        p = int(np.argmin(np.where(remaining, np.diag(schur), np.inf)))
        if not schur[p, p] > 0.0:
            raise ValueError("the covariance matrix is not positive definite")
        order[k], d[k] = p, schur[p, p]
        col = np.where(remaining, schur[:, p] / d[k], 0.0)
        columns[:, k] = col
        remaining[p] = False
        schur -= np.outer(col, schur[p, :])
    return order, columns[order], d


def integer_bootstrap(value_cyc, covariance_cyc2) -> BootstrapResult:
    """Integer bootstrapping with success rate and ratio test (Teunissen 1998).

    With ``Q = L D L^T`` (permuted so that the smallest conditional variance comes first)
    the conditional float values are ``c_i = a_i − Σ_{j<i} L_ij e_j`` with residuals
    ``e_j = c_j − z_j``, ``z_i = round(c_i)``, and ``q(z) = Σ e_i²/D_i``. No decorrelating
    (LAMBDA) transformation is applied.

    Ratio test: the second-best candidate is searched among the n alternatives that round
    one component ``k`` to its second-nearest integer and bootstrap the later components
    again. This is not an exhaustive integer least-squares search: the true second-best
    ``q`` can be smaller, so the ratio is an upper bound of the LAMBDA ratio when the
    bootstrapped vector is the integer least-squares solution.

    Parameters
    ----------
    value_cyc : array_like, shape (n,)
        Float ambiguities [cycles].
    covariance_cyc2 : array_like, shape (n, n)
        Their covariance [cycles²], symmetric positive definite.

    Returns
    -------
    BootstrapResult

    Raises
    ------
    ValueError
        If shapes do not match, values are not finite or the covariance is not positive
        definite.
    """
    a = np.asarray(value_cyc, dtype=float)
    cov = np.asarray(covariance_cyc2, dtype=float)
    n = a.size
    if a.ndim != 1 or n == 0 or cov.shape != (n, n):
        raise ValueError(f"need value (n,), n >= 1, and covariance (n, n), got {a.shape} and "
                         f"{cov.shape}")
    if not (np.all(np.isfinite(a)) and np.all(np.isfinite(cov))):
        raise ValueError("values and covariance must be finite")
    order, lower, d = _pivoted_ldl(0.5 * (cov + cov.T))
    a = a[order]
    # row 0: the bootstrapped vector; row 1 + k: component k rounded the other way
    e = np.zeros((n + 1, n))
    z = np.zeros((n + 1, n))
    for i in range(n):
        c = a[i] - e[:, :i] @ lower[i, :i]
        z[:, i] = np.floor(c + 0.5)
        z[i + 1, i] += 1.0 if c[i + 1] >= z[i + 1, i] else -1.0   # second-nearest integer
        e[:, i] = c - z[:, i]
    q = np.sum(e * e / d, axis=1)
    best, second = np.argsort(q, kind="stable")[:2]
    q1, q2 = float(q[best]), float(q[second])
    integer = np.empty(n, dtype=np.int64)
    integer[order] = z[best].astype(np.int64)
    sigma = np.sqrt(d)
    success = float(np.prod(2.0 * ndtr(0.5 / sigma) - 1.0))
    ratio = np.inf if q1 == 0.0 else q2 / q1
    return BootstrapResult(integer=integer, order=order, conditional_sigma_cyc=sigma,
                           success_rate=success, q_best=q1, q_second=q2, ratio=ratio)

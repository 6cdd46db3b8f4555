"""Sigma of the mean of time-correlated HMW series (honest wide-lane statistics, issue 19).

The float single-difference WL is the mean of ``n`` HMW epochs. Code multipath makes those
epochs correlated over minutes, so ``STD/sqrt(n)`` is optimistic and the Dong & Bock test
(BDS SCB-AR paper, eq. 9) then acts almost like plain rounding. Here the variance of the
mean of a stationary series with correlation ``r(Δt)`` is (Bayley & Hammersley 1946)::

    var(x̄) = σ² c,     c = (1/n²) Σ_i Σ_j r(t_i − t_j) = 1/n_eff,

``n_eff`` the effective number of independent epochs (``n/(1 + 2 Σ_k (1 − k/n) ρ_k)`` on a
gap-free grid). The sample variance of a correlated series is biased low, ``E[s²] = σ² n(1 −
c)/(n − 1)``; the unbiased estimator of the variance of the mean is therefore (Zięba 2010)::

    var̂(x̄) = s² (n − 1) c / (n (1 − c)) = s² (n − 1) / (n (n_eff − 1)).

Choice (why not the ACF of each series, why not the per-pass STD of Peng et al. 2021):

* a single SD series is 8–40 minutes long; its own sample autocorrelation cannot see a
  correlation of several minutes (mean removal biases it towards zero, and truncation rules
  then stop early): Thiébaux & Zwiers (1984) found such single-series estimates of ``n_eff``
  unreliable for short series; a prototype simulation for this change (noise model of
  ``benchmarks/wl_statistics.py``, not kept) gave single-series estimates (ACF summed to its
  first non-positive lag, or AR(1) from lag 1) a Dong & Bock false-fix rate of about 6 α,
  no better than ``STD/sqrt(n)``;
* the correlation *shape* is pooled over all SD series of the arc instead: the empirical
  semivariogram ``γ(k) = ½ mean[(x_{t+kΔ} − x_t)²]`` (no mean to remove, so no bias from
  short series) at lags ``k = 1 … MAX_LAG`` is fitted by white noise plus a first-order
  Gauss–Markov process, ``γ(k) = σ_w² + σ_m² (1 − exp(−kΔ/τ))``, i.e.
  ``r(Δt) = (σ_w² δ(Δt) + σ_m² exp(−|Δt|/τ)) / (σ_w² + σ_m²)``; the truncation is explicit
  in the model (no lag sum to truncate);
* the *level* stays each series' own ``s²`` (noise grows at low elevation), bias-corrected
  with Zięba's formula above;
* the empirical per-pass STD of Peng et al. (2021) is a fixing bound for the rounding rule
  (0.24 cycles), not a sigma of the mean: used as σ in the Dong & Bock test it would reject
  nearly everything.

``s²`` of a correlated series has fewer degrees of freedom than ``n − 1``. Their number
from Satterthwaite (1946), ``ν = tr(A R)² / tr(A R A R)`` with ``A = I − 11ᵀ/n``, is returned
so that a decision can account for the uncertainty of the sigma itself
(:func:`student_t_factor`).
"""

from __future__ import annotations

import logging
from typing import NamedTuple

import numpy as np
from scipy.special import ndtri, stdtrit

__all__ = ["MAX_LAG", "MIN_PAIRS_PER_LAG", "CorrelationModel", "MeanSigma", "fit_correlation",
           "mean_sigma", "semivariogram", "student_t_factor"]

log = logging.getLogger(__name__)

#: Largest lag of the fitted semivariogram [epochs]: 40 × 30 s = 20 min, about the longest
#: common time of most single differences (longer lags have few pairs).
MAX_LAG = 40
#: Fewest epoch pairs a lag needs to enter the fit.
MIN_PAIRS_PER_LAG = 50


class CorrelationModel(NamedTuple):
    """White noise plus a first-order Gauss–Markov process (module docstring).

    Attributes
    ----------
    white_var : float
        ``σ_w²`` [cycles²].
    markov_var : float
        ``σ_m²`` [cycles²].
    tau_s : float
        Correlation time ``τ`` [s].
    """

    white_var: float
    markov_var: float
    tau_s: float

    def correlation(self, lag_s) -> np.ndarray:
        """Correlation ``r(Δt)`` [1] at lags [s] (1 at zero lag)."""
        lag = np.abs(np.asarray(lag_s, dtype=float))
        total = self.white_var + self.markov_var
        return np.where(lag == 0.0, 1.0, self.markov_var * np.exp(-lag / self.tau_s) / total)


def semivariogram(times_s: list[np.ndarray], values: list[np.ndarray], step_s: float,
                  max_lag: int = MAX_LAG) -> tuple[np.ndarray, np.ndarray]:
    """Pooled empirical semivariogram of several series on a common sampling grid.

    Parameters
    ----------
    times_s : list of ndarray
        Epochs of each series [s], ascending (gaps allowed).
    values : list of ndarray
        The series [cycles].
    step_s : float
        Sampling interval [s]; a lag is the epoch difference rounded to a multiple of it.
    max_lag : int
        Largest lag [epochs].

    Returns
    -------
    gamma : ndarray, shape (max_lag,)
        ``½ mean[(x(t + kΔ) − x(t))²]`` for ``k = 1 … max_lag`` [cycles²] (NaN without pairs).
    count : ndarray of int, shape (max_lag,)
        Number of epoch pairs at each lag.
    """
    ssq = np.zeros(max_lag + 1)
    count = np.zeros(max_lag + 1, dtype=np.int64)
    for t, x in zip(times_s, values, strict=True):
        k = np.rint((np.asarray(t, float) - t[0]) / step_s).astype(np.int64)
        for shift in range(1, min(max_lag, x.size - 1) + 1):
            lag = k[shift:] - k[:-shift]
            d = x[shift:] - x[:-shift]
            ok = lag <= max_lag
            ssq += np.bincount(lag[ok], weights=d[ok] ** 2, minlength=max_lag + 1)
            count += np.bincount(lag[ok], minlength=max_lag + 1)
    gamma = np.divide(ssq, 2.0 * count, out=np.full(ssq.shape, np.nan), where=count > 0)
    return gamma[1:], count[1:]


def fit_correlation(gamma: np.ndarray, count: np.ndarray, step_s: float) -> CorrelationModel:
    """Fit white noise plus Gauss–Markov to a semivariogram (module docstring).

    Weighted least squares of the relative misfit, weight ``sqrt(count)`` (the relative
    sampling error of ``γ̂(k)`` falls like ``1/sqrt(count)``); parameters fitted as logarithms
    (positive) within bounds (comment in the code).

    Parameters
    ----------
    gamma, count : ndarray, shape (K,)
        Output of :func:`semivariogram` (lags 1 … K).
    step_s : float
        Sampling interval [s].

    Returns
    -------
    CorrelationModel

    Raises
    ------
    ValueError
        If fewer than 3 lags have ``MIN_PAIRS_PER_LAG`` pairs.
    """
    lag = np.arange(1, gamma.size + 1)
    use = (count >= MIN_PAIRS_PER_LAG) & np.isfinite(gamma) & (gamma > 0)
    if use.sum() < 3:
        raise ValueError(f"only {int(use.sum())} lags with >= {MIN_PAIRS_PER_LAG} epoch pairs: "
                         "too little data for the HMW correlation model")
    k, g, w = lag[use], gamma[use], np.sqrt(count[use])

    def misfit(p):
        white, markov, tau = np.exp(p)
        return (white + markov * (1.0 - np.exp(-k * step_s / tau)) - g) / g * w

    # Bounds keep the fit inside what the lags can tell: variances up to twice the largest
    # semivariance, τ up to the span of the fitted lags (a smooth, slowly varying error, e.g.
    # an uncorrected code-bias pattern, has a semivariogram growing like k² that the
    # exponential model can only follow with τ and σ_m² running to infinity).
    top = 2.0 * float(g.max())
    lo = np.log([1e-12 * top, 1e-12 * top, 0.1 * step_s])
    hi = np.log([top, top, float(k[-1]) * step_s])
    start = np.clip(np.log([0.5 * g[0], max(g[-1] - 0.5 * g[0], 1e-3 * g[-1]), 5.0 * step_s]),
                    lo + 1e-9, hi - 1e-9)
    from scipy.optimize import least_squares  # here: only the ambiguity step fits (0.1 s import)

    white, markov, tau = np.exp(least_squares(misfit, start, bounds=(lo, hi)).x)
    return CorrelationModel(float(white), float(markov), float(tau))


class MeanSigma(NamedTuple):
    """Sigma of the mean of one series (:func:`mean_sigma`)."""

    sigma: float    # [cycles]
    n_eff: float    # effective number of independent epochs
    dof: float      # Satterthwaite degrees of freedom of s²


def mean_sigma(times_s: np.ndarray, values: np.ndarray, model: CorrelationModel) -> MeanSigma:
    """Unbiased sigma of the mean of one correlated series (Zięba 2010; module docstring).

    Parameters
    ----------
    times_s : ndarray, shape (n,)
        Epochs [s].
    values : ndarray, shape (n,)
        The series [cycles].
    model : CorrelationModel
        Correlation shape (:func:`fit_correlation`).

    Returns
    -------
    MeanSigma
        ``sigma`` [cycles] (inf when ``n_eff <= 1``: the series cannot tell its own level),
        ``n_eff``, ``dof``; NaN for fewer than 2 epochs.
    """
    n = values.size
    if n < 2:
        return MeanSigma(np.nan, float(n), np.nan)
    t = np.asarray(times_s, dtype=float)
    r = model.correlation(t[:, None] - t[None, :])
    c = r.sum() / n**2
    n_eff = 1.0 / c
    s2 = float(np.var(values, ddof=1))
    sigma = np.sqrt(s2 * (n - 1) * c / (n * (1.0 - c))) if c < 1.0 - 1e-12 else np.inf
    ar = r - r.mean(axis=0, keepdims=True)          # A R with A = I − 11ᵀ/n
    dof = np.trace(ar) ** 2 / np.sum(ar * ar.T)
    return MeanSigma(float(sigma), float(n_eff), float(dof))


def student_t_factor(dof, alpha: float) -> np.ndarray:
    """Factor by which a sigma with ``dof`` degrees of freedom is widened for a test at ``alpha``.

    ``t_ν⁻¹(1 − α/2) / Φ⁻¹(1 − α/2)``: a Gaussian test with the widened sigma has the
    two-sided tail ``α`` of the Student-t distribution that the error over an estimated
    sigma follows (Student 1908; ν from Satterthwaite 1946). 1 for infinite or NaN ``dof``.

    Parameters
    ----------
    dof : array_like
        Degrees of freedom (> 0).
    alpha : float
        Tail probability of the test.

    Returns
    -------
    ndarray
        Factor >= 1.
    """
    nu = np.asarray(dof, dtype=float)
    good = np.isfinite(nu) & (nu > 0)
    q = 1.0 - alpha / 2.0
    return np.where(good, stdtrit(np.where(good, nu, 1.0), q) / ndtri(q), 1.0)

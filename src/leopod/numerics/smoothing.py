"""Savitzky–Golay smoothing and differentiation of regularly sampled series.

Every sample is replaced by the value (or a derivative) of the polynomial of degree ``p``
fitted by least squares to the ``w`` samples of a window around it (Savitzky & Golay 1964).
On a regular grid the fit is linear in the samples with the same weights everywhere: with the
window offsets ``j = −h … h`` (``w = 2h + 1``) and the Vandermonde matrix ``V[j, k] = jᵏ``, the
polynomial coefficients of a window are ``c = V⁺ y`` and the ``d``-th derivative at offset
``x`` is ``Σ_k c_k k!/(k−d)! x^(k−d) / Δtᵈ``. Inside the series the window is centred
(``x = 0``); the first and last ``h`` samples take the polynomial of the first or last full
window evaluated at their own offsets, so no padding is invented at the ends.

It is written here rather than taken from :func:`scipy.signal.savgol_filter` (which the test
compares it with) because importing ``scipy.signal`` costs ~0.9 s, more than the whole work
of the ingest step that uses it once per day.
"""

from __future__ import annotations

from math import factorial

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

__all__ = ["savitzky_golay"]


def _derivative_weights(offsets: np.ndarray, order: int, deriv: int) -> np.ndarray:
    """(len(offsets), order + 1): ``∂ᵈ/∂xᵈ xᵏ`` at each offset, so that ``W @ c`` is the
    ``deriv``-th derivative of the polynomial with coefficients ``c`` (per unit of offset)."""
    k = np.arange(order + 1)
    coef = np.array([factorial(i) // factorial(i - deriv) if i >= deriv else 0 for i in k],
                    dtype=float)
    power = np.clip(k - deriv, 0, None)
    return coef * np.asarray(offsets, dtype=float)[:, None] ** power


def savitzky_golay(y: np.ndarray, window: int, order: int, *, deriv: int = 0,
                   delta: float = 1.0) -> np.ndarray:
    """Smoothed series or its derivative (module docstring), along the first axis.

    Parameters
    ----------
    y : ndarray, shape (n, ...)
        Regularly sampled values (no NaN).
    window : int
        Odd number of samples of the local fit, ``order < window <= n``.
    order : int
        Degree of the local polynomial.
    deriv : int, optional
        Order of the derivative (0: the smoothed values).
    delta : float, optional
        Sampling interval (unit of the derivative's denominator, e.g. s).

    Returns
    -------
    ndarray, shape (n, ...)
        In the units of ``y`` per ``delta**deriv``.

    Raises
    ------
    ValueError
        For an even window, ``order >= window`` or a window longer than the series.
    """
    y = np.asarray(y, dtype=float)
    n = y.shape[0]
    if window % 2 == 0 or order >= window or window > n:
        raise ValueError(f"Savitzky-Golay: need an odd window ({window}) > order ({order}) "
                         f"and <= the series length ({n})")
    h = window // 2
    offsets = np.arange(-h, h + 1)
    fit = np.linalg.pinv(_derivative_weights(offsets, order, 0))        # (order+1, window)
    scale = 1.0 / delta**deriv
    centre = _derivative_weights(np.zeros(1), order, deriv) @ fit       # (1, window)
    windows = sliding_window_view(y, window, axis=0)                     # (n-w+1, ..., w)
    out = np.empty_like(y)
    out[h:n - h] = (windows @ centre[0]) * scale
    # the ends: the first / last full window's polynomial at the samples' own offsets
    ends = _derivative_weights(offsets[:h], order, deriv) @ fit          # (h, window)
    out[:h] = np.tensordot(ends, y[:window], axes=(1, 0)) * scale
    ends = _derivative_weights(offsets[h + 1:], order, deriv) @ fit
    out[n - h:] = np.tensordot(ends, y[n - window:], axes=(1, 0)) * scale
    return out

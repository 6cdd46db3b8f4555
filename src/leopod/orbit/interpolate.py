"""Lagrange interpolation of tabulated orbits (e.g. 15-min SP3 GNSS orbits).

Each query time uses the ``order + 1`` table nodes nearest to it (a window centred on the
query, shifted inward at the table ends). For 15-min GNSS orbits a 10th-order polynomial
(11 nodes) interpolates Earth-fixed positions to the millimetre level (Schenewerk 2003,
GPS Solutions 7:2; Montenbruck & Gill, Satellite Orbits, 2000, sec. 4.1).
"""

from __future__ import annotations

import numpy as np

__all__ = ["lagrange_weights", "interpolate_table"]


def lagrange_weights(t_nodes: np.ndarray, t: np.ndarray, order: int):
    """Node indices and Lagrange weights (and their time derivatives) for query times.

    Parameters
    ----------
    t_nodes : ndarray, shape (n,)
        Strictly increasing node times [s].
    t : ndarray, shape (m,)
        Query times [s].
    order : int
        Polynomial degree; uses ``order + 1`` nodes (must be <= n - 1).

    Returns
    -------
    idx : ndarray of int, shape (m, order+1)
        Node indices used for each query.
    w : ndarray, shape (m, order+1)
        Interpolation weights: ``f(t) = sum(w * f[idx])``.
    dw : ndarray, shape (m, order+1)
        Weights of the derivative: ``f'(t) = sum(dw * f[idx])`` [1/s].
    """
    t_nodes = np.asarray(t_nodes, dtype=float)
    t = np.atleast_1d(np.asarray(t, dtype=float))
    k = order + 1
    if len(t_nodes) < k:
        raise ValueError(f"need at least {k} nodes for order {order}, got {len(t_nodes)}")
    # first node of each window: centre the window on the query time
    right = np.searchsorted(t_nodes, t, side="right")
    start = np.clip(right - k // 2 - (k % 2), 0, len(t_nodes) - k)
    idx = start[:, None] + np.arange(k)[None, :]
    x = t_nodes[idx]                                    # (m, k)
    dx = t[:, None] - x                                 # (m, k)
    diff = x[:, :, None] - x[:, None, :]                # (m, k, k) x_j - x_l
    eye = np.eye(k, dtype=bool)
    diff[:, eye] = 1.0
    denom = diff.prod(axis=2)                           # prod_{l != j} (x_j - x_l)
    factors = np.broadcast_to(dx[:, None, :], (len(t), k, k)).copy()
    factors[:, eye] = 1.0                               # factors[j, l] = t - x_l, l != j
    numer = factors.prod(axis=2)
    w = numer / denom
    # derivative: sum over m != j of prod_{l != j, m} (t - x_l)
    dnum = np.zeros_like(numer)
    for m_ in range(k):
        f = factors.copy()
        f[:, :, m_] = 1.0
        mask = np.ones(k, dtype=bool)
        mask[m_] = False
        dnum[:, mask] += f[:, mask, :].prod(axis=2)
    dw = dnum / denom
    return idx, w, dw


def interpolate_table(t_nodes, values, t, order: int = 10, *, max_gap_s: float | None = None,
                      max_extrapolation_s: float = 0.0):
    """Interpolate tabulated values (and their rates) at query times.

    Parameters
    ----------
    t_nodes : ndarray, shape (n,)
        Node times [s], strictly increasing.
    values : ndarray, shape (n, ...)
        Tabulated values; NaN nodes make the result NaN where they enter a window.
    t : ndarray, shape (m,)
        Query times [s]. Queries more than ``max_extrapolation_s`` outside
        ``[t_nodes[0], t_nodes[-1]]`` give NaN.
    order : int
        Polynomial degree (default 10).
    max_gap_s : float, optional
        If given, queries whose window spans a node spacing larger than this give NaN.
    max_extrapolation_s : float
        How far beyond the first/last node the edge polynomial may be used [s] (default 0).
        Extrapolation degrades quickly; callers must flag such values.

    Returns
    -------
    value : ndarray, shape (m, ...)
    rate : ndarray, shape (m, ...)
        Time derivative [unit/s].
    """
    t_nodes = np.asarray(t_nodes, dtype=float)
    values = np.asarray(values, dtype=float)
    t = np.atleast_1d(np.asarray(t, dtype=float))
    idx, w, dw = lagrange_weights(t_nodes, t, order)
    v = values[idx]                                     # (m, k, ...)
    extra = (slice(None), slice(None)) + (None,) * (values.ndim - 1)
    val = (w[extra] * v).sum(axis=1)
    rate = (dw[extra] * v).sum(axis=1)
    bad = (t < t_nodes[0] - max_extrapolation_s) | (t > t_nodes[-1] + max_extrapolation_s)
    if max_gap_s is not None:
        spans = np.diff(t_nodes[idx], axis=1).max(axis=1)
        bad |= spans > max_gap_s
    val[bad] = np.nan
    rate[bad] = np.nan
    return val, rate

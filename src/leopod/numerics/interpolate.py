"""Lagrange interpolation of tabulated orbits (e.g. 15-min SP3 GNSS orbits).

Each query time uses the ``order + 1`` table nodes nearest to it (a window centred on the
query, shifted inward at the table ends). For 15-min GNSS orbits a 10th-order polynomial
(11 nodes) interpolates Earth-fixed positions to the millimetre level (Schenewerk 2003,
GPS Solutions 7:2; Montenbruck & Gill, Satellite Orbits, 2000, sec. 4.1).
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["interpolate_table", "lagrange_equidistant", "lagrange_equidistant_many",
           "lagrange_weights"]


def _window_denominators(t_nodes: np.ndarray, starts: np.ndarray, k: int) -> np.ndarray:
    """``prod_{l != j} (x_j - x_l)`` for the windows starting at ``starts``, shape (len, k)."""
    x = t_nodes[starts[:, None] + np.arange(k)[None, :]]
    diff = x[:, :, None] - x[:, None, :]
    diff[:, np.eye(k, dtype=bool)] = 1.0
    return diff.prod(axis=2)


def _products_without(dx: np.ndarray) -> np.ndarray:
    """``prod_{l != j} dx_l`` for every j, by prefix and suffix products, shape like ``dx``."""
    ones = np.ones(dx.shape[:-1] + (1,))
    prefix = np.cumprod(np.concatenate([ones, dx[..., :-1]], axis=-1), axis=-1)
    suffix = np.cumprod(np.concatenate([ones, dx[..., :0:-1]], axis=-1), axis=-1)[..., ::-1]
    return prefix * suffix


def lagrange_weights(t_nodes: np.ndarray, t: np.ndarray, order: int):
    """Node indices and Lagrange weights (and their time derivatives) for query times.

    Costs O(m·k) per call: numerators by prefix/suffix products, denominators once per
    distinct window, derivatives from ``w_j Σ_{l≠j} 1/(t − x_l)`` (with the limit taken
    exactly when a query coincides with a node).

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
    uniq, inverse = np.unique(start, return_inverse=True)
    denom = _window_denominators(t_nodes, uniq, k)[inverse]          # (m, k)
    dx = t[:, None] - t_nodes[idx]                                     # (m, k)
    at_node = np.abs(dx) < 1e-9
    w = _products_without(dx) / denom
    with np.errstate(divide="ignore", invalid="ignore"):
        recip = np.where(at_node, 0.0, 1.0 / dx)
    dw = w * (recip.sum(axis=1, keepdims=True) - recip)
    rows = np.nonzero(at_node.any(axis=1))[0]
    if rows.size:
        # query on node z: w = e_z; dw_j = prod_{l != j, z} dx_l / denom_j, dw_z = Σ_{l≠z} 1/dx_l
        z = at_node[rows].argmax(axis=1)
        dxz = dx[rows].copy()
        dxz[np.arange(rows.size), z] = 1.0
        dwr = _products_without(dxz) / denom[rows]
        dwr[np.arange(rows.size), z] = recip[rows].sum(axis=1)
        dw[rows] = dwr
        wr = np.zeros((rows.size, k))
        wr[np.arange(rows.size), z] = 1.0
        w[rows] = wr
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


# --------------------------------------------------------------- equidistant nodes, compiled
# The force model evaluates Earth orientation, tide arguments and Sun/Moon positions inside its
# compiled right-hand side from tables on equidistant epochs; these kernels are the numba form
# of the same Lagrange interpolation for that case (no window search, no allocation).


@numba.njit(cache=True)
def lagrange_equidistant(t, t_first, step, n_points, nodes, out):  # pragma: no cover - numba
    """Lagrange interpolation at t on equidistant nodes ``t_first + k step``.

    ``nodes`` (n, k) holds the tabulated values; ``out`` (k,) receives the interpolated row,
    from the ``n_points`` nodes centred on t (window shifted inward at the ends).
    """
    x = (t - t_first) / step
    first = int(np.floor(x)) - (n_points // 2 - 1)
    first = min(max(first, 0), nodes.shape[0] - n_points)
    for c in range(out.shape[0]):
        out[c] = 0.0
    for j in range(n_points):
        w = 1.0
        for m in range(n_points):
            if m != j:
                w *= (x - (first + m)) / (j - m)
        for c in range(out.shape[0]):
            out[c] += w * nodes[first + j, c]


@numba.njit(cache=True)
def lagrange_equidistant_many(t, t_first, step, n_points, nodes):  # pragma: no cover - numba
    out = np.empty((t.shape[0], nodes.shape[1]))
    for i in range(t.shape[0]):
        lagrange_equidistant(t[i], t_first, step, n_points, nodes, out[i])
    return out

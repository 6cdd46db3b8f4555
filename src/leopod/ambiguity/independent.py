"""Linearly independent single-difference ambiguities, pseudo-observations, fixing rates.

A single difference ``B_i − B_j`` is an edge between the undifferenced ambiguities ``i`` and
``j`` (graph nodes); its row of the design matrix is the edge's incidence vector (+1 at i,
−1 at j). A set of such rows is linearly independent iff the edges contain no cycle (the
incidence matrix of a graph has rank = number of nodes − number of connected components,
and a cycle's rows sum to zero with ±1 signs). A maximal independent set is a spanning
forest, and Kruskal's algorithm with a union-find over the edges sorted by a quality key
("best-determined first", e.g. the NL sigma) gives the one of smallest total key.

The fixed set enters the fixed POD as pseudo-observations ``B_i − B_j = ΔB_IF`` with a small
sigma (Peng et al. 2021, sec. III-B: the recovered single-differenced IF integer ambiguities "are
mapped back onto the undifferenced ambiguities and are strongly constrained"; Jiang et al. 2023:
"the relationship ΔN = N_i − N_j is taken as the pseudo-observation to tightly constrain
the ionospheric-free ambiguity parameters").

Fixing rate (Jiang et al. 2023, "Internal consistency validation"): "the ratio of the number of
independent fixed ambiguities to the total number of independent ambiguities", i.e.
``rank(fixed edges) / rank(all candidate edges)``.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["CONSTRAINT_SIGMA_M", "ConstraintRows", "constraint_matrix", "constraint_rows",
           "fixing_rate", "graph_rank", "independent_edges"]

#: Default sigma of the ambiguity pseudo-observations [m] (1 mm: "tight", Peng et al. 2021 and
#: Jiang et al. 2023 give no number).
CONSTRAINT_SIGMA_M = 1e-3


def _edges(i, j) -> tuple[np.ndarray, np.ndarray]:
    i = np.asarray(i, dtype=np.int64)
    j = np.asarray(j, dtype=np.int64)
    if i.shape != j.shape or i.ndim != 1:
        raise ValueError(f"i and j must be 1-d of equal length, got {i.shape} and {j.shape}")
    if np.any(i < 0) or np.any(j < 0):
        raise ValueError("node indices must be >= 0")
    if np.any(i == j):
        raise ValueError("an edge joins a node to itself (i == j)")
    return i, j


def independent_edges(i, j, key=None) -> np.ndarray:
    """Maximal linearly independent subset of single differences, best key first (Kruskal).

    Parameters
    ----------
    i, j : array_like of int, shape (m,)
        Undifferenced ambiguity indices of each single difference ``B_i − B_j``.
    key : array_like of float, shape (m,), optional
        Quality key, smaller is better (e.g. the NL sigma); ties and None keep the input
        order.

    Returns
    -------
    ndarray of bool, shape (m,)
        True for the selected edges: no cycle, and every other edge closes a cycle with
        them (a spanning forest of minimal total key).

    Raises
    ------
    ValueError
        If shapes differ, an index is negative or an edge is a loop.
    """
    i, j = _edges(i, j)
    order = (np.arange(i.size) if key is None
             else np.argsort(np.broadcast_to(np.asarray(key, dtype=float), i.shape),
                             kind="stable"))
    parent = list(range(int(max(i.max(initial=-1), j.max(initial=-1))) + 1))

    def root(node: int) -> int:
        while parent[node] != node:
            parent[node] = parent[parent[node]]   # path halving
            node = parent[node]
        return node

    keep = np.zeros(i.size, dtype=bool)
    for e in order:
        ri, rj = root(int(i[e])), root(int(j[e]))
        if ri != rj:
            parent[ri] = rj
            keep[e] = True
    return keep


def graph_rank(i, j) -> int:
    """Rank of the incidence rows of the edges: nodes − connected components."""
    return int(independent_edges(i, j).sum())


def fixing_rate(i, j, fixed) -> float:
    """Fixing rate of Jiang et al. (2023): independent fixed / all independent single differences.

    Parameters
    ----------
    i, j : array_like of int, shape (m,)
        All candidate single differences (e.g. the pairs of :func:`leopod.ambiguity.pairs.sd_pairs`).
    fixed : array_like of bool, shape (m,)
        Which of them are fixed (for the NL rate: WL and NL fixed).

    Returns
    -------
    float
        ``graph_rank(fixed) / graph_rank(all)``; NaN without edges.
    """
    i, j = _edges(i, j)
    fixed = np.asarray(fixed, dtype=bool)
    total = graph_rank(i, j)
    return graph_rank(i[fixed], j[fixed]) / total if total else np.nan


class ConstraintRows(NamedTuple):
    """Pseudo-observations ``B[index_i] − B[index_j] = value_m ± sigma_m``.

    Attributes
    ----------
    index_i, index_j : ndarray of int64, shape (k,)
        Undifferenced ambiguity indices.
    value_m : ndarray, shape (k,)
        Fixed single-difference IF ambiguity [m]
        (:func:`leopod.ambiguity.narrow_lane.fixed_sd_if_m`).
    sigma_m : ndarray, shape (k,)
        Sigma of the pseudo-observation [m].
    """

    index_i: np.ndarray
    index_j: np.ndarray
    value_m: np.ndarray
    sigma_m: np.ndarray


def constraint_rows(i, j, value_m, key=None, *, sigma_m=CONSTRAINT_SIGMA_M) -> ConstraintRows:
    """Pseudo-observations for a maximal independent subset of fixed single differences.

    Parameters
    ----------
    i, j : array_like of int, shape (m,)
        Fixed single differences ``B_i − B_j``.
    value_m : array_like, shape (m,)
        Their fixed IF values [m].
    key : array_like, shape (m,), optional
        Quality key, smaller first (:func:`independent_edges`).
    sigma_m : float or array_like, shape (m,)
        Constraint sigma [m] (default :data:`CONSTRAINT_SIGMA_M`).

    Returns
    -------
    ConstraintRows
        The selected rows, in input order.
    """
    i, j = _edges(i, j)
    keep = independent_edges(i, j, key)
    value = np.broadcast_to(np.asarray(value_m, dtype=float), i.shape)
    sigma = np.broadcast_to(np.asarray(sigma_m, dtype=float), i.shape)
    return ConstraintRows(index_i=i[keep], index_j=j[keep], value_m=value[keep].copy(),
                          sigma_m=sigma[keep].copy())


def constraint_matrix(rows: ConstraintRows, n_ambiguities: int) -> np.ndarray:
    """Design matrix (k, n) of the pseudo-observations: +1 at ``index_i``, −1 at ``index_j``."""
    a = np.zeros((rows.index_i.size, n_ambiguities))
    k = np.arange(rows.index_i.size)
    a[k, rows.index_i] = 1.0
    a[k, rows.index_j] = -1.0
    return a

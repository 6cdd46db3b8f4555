"""Least-squares estimation of an antenna-frame code-bias map from multipath combinations.

The multipath combination of a code (Peng et al. 2021, eq. (1); :func:`leopod.gnss.combinations.
multipath`) observed in direction ``(a, e)`` of the antenna frame during pass ``p`` is modelled
as::

    MP = o_p + Σ_k w_k(a, e) x_k + ε

with one offset ``o_p`` per continuous phase pass (ambiguities, phase and code biases), the map
values ``x_k`` at the grid nodes and their bilinear weights ``w_k`` (:class:`~leopod.codebias.
grid.AntennaGrid`). The pass offsets are eliminated from the normal equations (Schur
complement, built from sparse matrices), so only the node values are solved for. Because the
weights of a direction sum to one, a constant added to all nodes can be taken out of all pass
offsets: the datum is fixed by a zero mean of the node values weighted by their observation
counts (``Σ n_k x_k = 0``: the mean correction of the observations is zero, and sparsely
observed nodes do not move the level of the map), imposed as ``N + c w wᵀ``. The system is solved by eigen-decomposition, so that nodes the data cannot
separate from their neighbours and the pass offsets (a defect beyond the datum, e.g. a node
seen by one pass only) are found and left out instead of failing the step.

Options: smoothness (pseudo-observations ``x_i − x_j = 0 ± σ_s`` between adjacent nodes);
observation weights from the robust (MAD) scatter of the residuals per elevation band, with
Huber down-weighting of residuals beyond ``robust_k`` scatters, iterated. Nodes no observation
touches are not estimated unless smoothing ties them to their neighbours; nodes not linked to
the rest of the map by common passes or smoothing (an island of passes) are dropped with their
observations (logged). Nodes with fewer than ``min_count``
observations are estimated but flagged empty in the products.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from leopod.codebias.grid import AntennaGrid
from leopod.settings import Settings

__all__ = ["MapFit", "MapSettings", "band_index", "estimate_map"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class MapSettings(Settings):
    """Tunables of the map estimation (config ``code_bias``; units in the names).

    Attributes
    ----------
    az_step_deg, el_step_deg : float
        Grid spacing [deg] (Peng et al. 2021: 5° × 5°).
    min_count : int
        Nodes touched by fewer observations are flagged empty (Peng et al. 2021, Fig. 9: 200).
    smoothing_sigma_m : float or None
        Sigma of the difference of adjacent nodes [m]; None: no smoothing.
    robust_k : float
        Huber threshold in robust standard deviations of the elevation band.
    iterations : int
        Re-weighting iterations after the first solution.
    band_width_deg : float
        Width of the elevation bands of the weights and the statistics [deg].
    """

    SCHEMA_DEF = "code_bias"

    az_step_deg: float
    el_step_deg: float
    min_count: int
    smoothing_sigma_m: float | None
    robust_k: float
    iterations: int
    band_width_deg: float

    @property
    def grid(self) -> AntennaGrid:
        """The node grid."""
        return AntennaGrid(self.az_step_deg, self.el_step_deg)


@dataclass
class MapFit:
    """Result of :func:`estimate_map`.

    Attributes
    ----------
    value_m, sigma_m : ndarray, shape (n_nodes,)
        Node values and formal sigmas [m] (NaN for nodes not estimated).
    count : ndarray of int, shape (n_nodes,)
        Observations with a non-zero weight on the node.
    sigma0 : float
        A-posteriori standard deviation of unit weight.
    n_downweighted : int
        Observations beyond ``robust_k`` robust scatters in the last iteration.
    """

    value_m: np.ndarray
    sigma_m: np.ndarray
    count: np.ndarray
    sigma0: float
    n_downweighted: int

    def empty(self, min_count: int) -> np.ndarray:
        """Nodes without a usable value: fewer than ``min_count`` observations or not
        estimated (n_nodes,)."""
        return (self.count < min_count) | ~np.isfinite(self.value_m)


def band_index(el_deg: np.ndarray, band_width_deg: float) -> np.ndarray:
    """Elevation band of each direction (0 = [0, width)); 90° falls in the last band."""
    n_bands = int(np.ceil(90.0 / band_width_deg))
    return np.clip((np.asarray(el_deg) // band_width_deg).astype(int), 0, n_bands - 1)


def _pass_incidence(pass_key: np.ndarray) -> sp.csr_matrix:
    _, p = np.unique(pass_key, return_inverse=True)
    n = p.size
    return sp.csr_matrix((np.ones(n), (np.arange(n), p)), shape=(n, int(p.max()) + 1))


def _reduced_normals(a: sp.csr_matrix, g: sp.csr_matrix, w: np.ndarray, y: np.ndarray):
    """Normal equations of the node values with the pass offsets eliminated."""
    aw = sp.csr_matrix(a.multiply(w[:, None]))
    wp = np.asarray(g.T @ w).ravel()
    s = sp.csr_matrix(g.T @ aw)
    inv_wp = np.divide(1.0, wp, out=np.zeros_like(wp), where=wp > 0)
    n = (a.T @ aw).toarray() - (s.T @ sp.diags(inv_wp) @ s).toarray()
    wy = w * y
    b = a.T @ wy - s.T @ (inv_wp * (g.T @ wy))
    return n, np.asarray(b).ravel()


def _pass_mean(values: np.ndarray, g: sp.csr_matrix, w: np.ndarray) -> np.ndarray:
    """Weighted mean per pass, returned per observation."""
    wp = np.asarray(g.T @ w).ravel()
    mean = np.divide(g.T @ (w * values), wp, out=np.zeros_like(wp), where=wp > 0)
    return g @ mean


def _main_component(a: sp.csr_matrix, g: sp.csr_matrix, smooth: sp.csr_matrix | None,
                    active: np.ndarray) -> np.ndarray:
    """Nodes of the largest group linked by common passes (and smoothing)."""
    s = sp.csr_matrix(g.T @ (a != 0).astype(float))
    link = s.T @ s
    if smooth is not None:
        link = link + smooth.T @ smooth
    _, label = connected_components(link, directed=False)
    counts = np.bincount(label[active], minlength=label.max() + 1)
    return active & (label == np.argmax(counts))


def _robust_weights(r: np.ndarray, band: np.ndarray, k: float) -> tuple[np.ndarray, int]:
    """Weights 1/σ_band² with Huber down-weighting beyond ``k σ_band``."""
    w = np.zeros_like(r)
    n_down = 0
    for b in np.unique(band):
        sel = band == b
        scale = 1.4826 * np.median(np.abs(r[sel] - np.median(r[sel])))
        scale = max(scale, 1e-4)
        z = np.abs(r[sel]) / scale
        w[sel] = np.minimum(1.0, k / np.maximum(z, 1e-12)) / scale**2
        n_down += int(np.sum(z > k))
    return w, n_down


def _solve_datum(n: np.ndarray, b: np.ndarray, w: np.ndarray, rel_tol: float = 1e-10):
    """Solution of ``N x = b`` with the datum ``wᵀ x = 0`` and the diagonal of its covariance.

    ``N`` is singular along the constant vector (``1ᵀ b = 0``); with ``M = N + c w wᵀ``
    (``Σ w = 1``) the solution of ``M x = b`` is the one with ``wᵀ x = 0``, and the covariance
    of that solution is ``M⁻¹ − 1 1ᵀ / c``. Any other direction with an eigenvalue of ``M``
    below ``rel_tol`` of the largest is a defect of the data: the nodes it involves are
    reported as undetermined and the pseudo-inverse is used.

    Returns
    -------
    x : ndarray (m,)
    cov_diag : ndarray (m,)
        Diagonal of the covariance [m² per unit weight].
    undetermined : ndarray of bool (m,)
    """
    c = np.trace(n)
    lam, v = sla.eigh(n + c * np.outer(w, w))
    good = lam > rel_tol * lam.max()
    vg = v[:, good]
    x = vg @ ((vg.T @ b) / lam[good])
    cov_diag = np.sum(vg**2 / lam[good], axis=1) - 1.0 / c
    undetermined = np.sum(v[:, ~good] ** 2, axis=1) > 1e-2  # share of a defect direction
    return x, cov_diag, undetermined


def _solve_datum_regular(n: np.ndarray, b: np.ndarray, w: np.ndarray, *, covariance: bool):
    """:func:`_solve_datum` for an ``N`` whose only defect is the datum, by Cholesky.

    ``M = N + c w wᵀ`` is then positive definite: ``x`` from its Cholesky factor ``L`` and
    ``diag(M⁻¹)`` as the column sums of ``(L⁻¹)²`` (about a tenth of the eigendecomposition's
    cost). Returns ``x`` and, if ``covariance``, the diagonal of its covariance (else None).
    """
    c = np.trace(n)
    chol = sla.cholesky(n + c * np.outer(w, w), lower=True)
    x = sla.cho_solve((chol, True), b)
    if not covariance:
        return x, None
    inv_l = sla.solve_triangular(chol, np.eye(chol.shape[0]), lower=True)
    return x, np.sum(inv_l**2, axis=0) - 1.0 / c


def estimate_map(az_deg, el_deg, mp_m, pass_key, settings: MapSettings) -> MapFit:
    """Code-bias map from multipath observations (module docstring).

    Parameters
    ----------
    az_deg, el_deg : array_like, shape (n,)
        Antenna-frame direction of each observation [deg].
    mp_m : array_like, shape (n,)
        Multipath combination [m] (any per-pass constant may remain; NaN = not observed).
    pass_key : array_like of int, shape (n,)
        Pass of each observation (one offset per distinct key).
    settings : MapSettings

    Returns
    -------
    MapFit

    Raises
    ------
    ValueError
        If there are no usable observations.
    """
    grid = settings.grid
    az, el, y = (np.asarray(v, dtype=float) for v in (az_deg, el_deg, mp_m))
    key = np.asarray(pass_key)
    used = np.isfinite(y) & np.isfinite(az) & np.isfinite(el)
    if not used.any():
        raise ValueError("no finite multipath observation to estimate a code-bias map from")
    a = grid.design(az[used], el[used])
    a.eliminate_zeros()
    g = _pass_incidence(key[used])
    smooth = None
    if settings.smoothing_sigma_m:
        pairs = grid.neighbour_pairs()
        k = pairs.shape[0]
        smooth = sp.csr_matrix((np.r_[np.ones(k), -np.ones(k)],
                                (np.r_[np.arange(k), np.arange(k)], pairs.T.ravel())),
                               shape=(k, grid.n_nodes))
    candidates = np.diff(a.tocsc().indptr) > 0
    if smooth is not None:
        candidates[:] = True  # smoothing ties nodes without data to their neighbours
    active = _main_component(a, g, smooth, candidates)
    if candidates.sum() > active.sum():
        keep = np.asarray(a[:, ~active].sum(axis=1)).ravel() == 0
        log.warning("%d nodes (%d observations) are not linked to the rest of the map: "
                    "not estimated", int(candidates.sum() - active.sum()), int((~keep).sum()))
        idx = np.flatnonzero(used)
        used[idx[~keep]] = False
        a, g = a[keep], _pass_incidence(key[used])
    y_u, band = y[used], band_index(el[used], settings.band_width_deg)
    cols = np.flatnonzero(active)
    a_act = sp.csr_matrix(a[:, cols])
    m = cols.size
    reg = None
    if smooth is not None:
        sm = smooth[:, cols]
        sm = sm[np.asarray(abs(sm).sum(axis=1)).ravel() == 2]
        reg = (sm.T @ sm).toarray() / settings.smoothing_sigma_m**2
    count_act = np.diff(a_act.tocsc().indptr)
    datum = count_act / count_act.sum()
    w = np.ones(y_u.size)
    n_down = 0
    undetermined = np.zeros(m, dtype=bool)
    for it in range(settings.iterations + 1):
        n, b = _reduced_normals(a_act, g, w, y_u)
        if reg is not None:
            n += reg
        regular = it > 0 and not undetermined.any()  # same observations, same defects
        try:
            if regular:
                x, cov_diag = _solve_datum_regular(n, b, datum,
                                                   covariance=it == settings.iterations)
        except np.linalg.LinAlgError:  # a defect spread too thin to mark any node
            regular = False
        if not regular:
            x, cov_diag, undetermined = _solve_datum(n, b, datum)
        fitted = a_act @ x
        resid = y_u - fitted - _pass_mean(y_u - fitted, g, w)
        if it < settings.iterations:
            w, n_down = _robust_weights(resid, band, settings.robust_k)
    dof = max(y_u.size - g.shape[1] - (m - 1), 1)
    sigma0 = float(np.sqrt(np.sum(w * resid**2) / dof))
    if undetermined.any():
        log.warning("%d nodes are not determined by the data (e.g. observations of one pass "
                    "only): not estimated", int(undetermined.sum()))
    value = np.full(grid.n_nodes, np.nan)
    sigma = np.full(grid.n_nodes, np.nan)
    value[cols] = np.where(undetermined, np.nan, x)
    sigma[cols] = np.where(undetermined, np.nan, sigma0 * np.sqrt(np.maximum(cov_diag, 0.0)))
    count = np.zeros(grid.n_nodes, dtype=np.int64)
    count[cols] = count_act
    log.info("code-bias map: %d observations, %d passes, %d nodes, sigma0 %.3f, "
             "%d down-weighted", y_u.size, g.shape[1], m, sigma0, n_down)
    return MapFit(value_m=value, sigma_m=sigma, count=count, sigma0=sigma0,
                  n_downweighted=n_down)

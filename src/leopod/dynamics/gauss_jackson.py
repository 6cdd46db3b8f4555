"""Gauss–Jackson integration of one smooth segment of the augmented orbit equations.

The second-order system ``ÿ = F(t, y)`` of :mod:`leopod.dynamics.integrator` (state with its
variational equations) is integrated on equidistant nodes between two breakpoints.

Method. A fixed-step Gauss–Jackson (summed Störmer–Cowell for r, summed Adams for v)
predictor–corrector of order q = 10 (11 back values, one force evaluation per step in PEC mode;
Berry & Healy 2004, J. Astronaut. Sci. 52(3):331–357; Montenbruck & Gill 2000, sec. 4.2).
Its coefficients are derived here from the generating functions of the backward-difference
operator ∇ (corrector ``σ*(∇) = ∇²/ln²(1−∇)`` and ``γ*(∇) = −∇/ln(1−∇)``, predictor
divided by ``1−∇``), so any order is available. The running first and second sums are
accumulated with compensated (Kahan) summation: without it their round-off reaches 0.01 mm
over 30 h at 5-s steps, with it 0.0003 mm. The method starts (and restarts) by a
collocation on the first q + 1 nodes solved by fixed-point iteration, which is also what the
dense output uses: between nodes, ``f`` is replaced by its interpolating polynomial over
q + 1 nodes and integrated once and twice from the nearest node.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache
from math import comb
from typing import TYPE_CHECKING

import numba
import numpy as np

if TYPE_CHECKING:
    from leopod.dynamics.integrator import _Rhs

_STARTUP_MAX_ITERATIONS = 60
_STARTUP_RTOL_STATE = 1e-15      # relative change of the start nodes ending the iteration,
_STARTUP_RTOL_PARTIALS = 1e-11   # for the state and the partials (needed: ~1e-6)
_STARTUP_FLOOR = 100.0           # a change within this factor that stops decreasing ends it
_DENSE_BLOCK = 256               # output epochs interpolated per block (bounds memory)


# --------------------------------------------------------------------------------------------
# Coefficients


def _series_inverse(a: list[Fraction], n: int) -> list[Fraction]:
    """First n coefficients of 1/a(x) for a power series with a[0] != 0."""
    inv = [Fraction(0)] * n
    inv[0] = 1 / a[0]
    for k in range(1, n):
        inv[k] = -sum((a[i] * inv[k - i] for i in range(1, min(k, len(a) - 1) + 1)),
                      Fraction(0)) / a[0]
    return inv


def _series_product(a: list[Fraction], b: list[Fraction], n: int) -> list[Fraction]:
    """First n coefficients of a(x) b(x)."""
    return [sum((a[i] * b[k - i] for i in range(k + 1)), Fraction(0)) for k in range(n)]


def _ordinates(diff_coef: list[Fraction], order: int) -> np.ndarray:
    """Weights of ``f_{n-q}, ..., f_n`` (oldest first) equal to ``Σ_j c_j ∇^j f_n``, j ≤ q."""
    w = [Fraction(0)] * (order + 1)
    for j in range(order + 1):
        for k in range(j + 1):
            w[k] += diff_coef[j] * (-1) ** k * comb(j, k)
    return np.array([float(x) for x in w[::-1]])


@lru_cache(maxsize=8)
def _gauss_jackson_weights(order: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Ordinate weights of the summed Adams (v) and Störmer–Cowell (r) formulas of order q.

    With ``S1_n = S1_{n-1} + f_n`` and ``S2_n = S2_{n-1} + S1_{n-1}`` (integration constants
    fixed at the start) the correctors are ``v_n = h (S1_n + Σ a*_j ∇^j f_n)`` and
    ``r_n = h² (S2_n + Σ b*_j ∇^j f_n)`` with ``a*(x) = (γ*(x) − 1)/x``,
    ``b*(x) = (σ*(x) − 1 + x)/x²``, ``γ*(x) = −x/ln(1−x)``, ``σ*(x) = x²/ln²(1−x)``; the
    predictors ``v_{n+1} = h (S1_n + Σ a_j ∇^j f_n)``, ``r_{n+1} = h² (S2_n + S1_n + Σ b_j ∇^j
    f_n)`` follow from ``f_{n+1} = f_n/(1−∇)``: ``a = (1 + a*)/(1−x)``, ``b = b*/(1−x)``
    (Berry & Healy 2004; Montenbruck & Gill 2000, sec. 4.2).

    Returns
    -------
    pred_v, pred_r, corr_v, corr_r : ndarray, shape (q + 1,)
        Weights of the q + 1 last accelerations, oldest first (predictor: up to f_n,
        corrector: up to f_{n+1}).
    """
    n = order + 3
    # −ln(1−x)/x = Σ x^k/(k+1)
    m = [Fraction(1, k + 1) for k in range(n + 2)]
    gamma_star = _series_inverse(m, n + 2)
    sigma_star = _series_inverse(_series_product(m, m, n + 2), n + 2)
    a_star = gamma_star[1:n + 1]          # γ*_0 = 1
    b_star = sigma_star[2:n + 2]          # σ*_0 = 1, σ*_1 = −1
    geometric = [Fraction(1)] * n
    a_pred = _series_product([1 + a_star[0]] + a_star[1:], geometric, n)
    b_pred = _series_product(b_star, geometric, n)
    return (_ordinates(a_pred, order), _ordinates(b_pred, order),
            _ordinates(a_star, order), _ordinates(b_star, order))


@lru_cache(maxsize=8)
def _gauss_legendre(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre nodes and weights on [0, 1]."""
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (x + 1.0), 0.5 * w


def _integration_weights(offset: np.ndarray, s: np.ndarray, n_nodes: int
                         ) -> tuple[np.ndarray, np.ndarray]:
    """Weights integrating the interpolating polynomial of f once and twice from a node.

    The polynomial interpolates f at the nodes ``x_i = offset + i`` (i < n_nodes, unit
    spacing, base node at 0); the weights give ``∫_0^s p(u) du = Σ w1_i f_i`` and
    ``∫_0^s (s − u) p(u) du = Σ w2_i f_i`` (Gauss–Legendre quadrature, exact for this degree).

    Parameters
    ----------
    offset : ndarray of int, shape (m,)
    s : ndarray, shape (m,)
        Abscissa of the query in steps from the base node.
    n_nodes : int

    Returns
    -------
    w1, w2 : ndarray, shape (m, n_nodes)
    """
    xg, wg = _gauss_legendre(n_nodes // 2 + 2)
    u = s[:, None] * xg[None, :]                                   # (m, G)
    idx = np.arange(n_nodes)
    diff = u[:, :, None] - (offset[:, None, None] + idx[None, None, :])   # (m, G, K)
    denom = np.array([np.prod([float(i - k) for k in idx if k != i]) for i in idx])
    basis = np.empty_like(diff)
    for i in idx:
        basis[:, :, i] = np.prod(np.delete(diff, i, axis=2), axis=2) / denom[i]
    w1 = s[:, None] * np.einsum("g,mgi->mi", wg, basis)
    w2 = (s**2)[:, None] * np.einsum("g,mgi->mi", wg * (1.0 - xg), basis)
    return w1, w2


# --------------------------------------------------------------------------------------------
# Segments


@numba.njit(cache=True)
def _gj_sum(f_hist, s1, s2, w_v, w_r, h, add_s1_to_r, y_out):  # pragma: no cover - numba
    """``y_r = h² (S2 [+ S1] + Σ w_r f)``, ``y_v = h (S1 + Σ w_v f)`` over the history."""
    n_hist, _, n_col = f_hist.shape
    for i in range(3):
        for j in range(n_col):
            acc_v = 0.0
            acc_r = 0.0
            for k in range(n_hist):
                acc_v += w_v[k] * f_hist[k, i, j]
                acc_r += w_r[k] * f_hist[k, i, j]
            base = s2[i, j] + s1[i, j] if add_s1_to_r else s2[i, j]
            y_out[i, j] = h * h * (base + acc_r)
            y_out[3 + i, j] = h * (s1[i, j] + acc_v)


@numba.njit(cache=True)
def _kahan_add(total, compensation, x):  # pragma: no cover - numba
    """``total += x`` with compensated (Kahan) summation, in place."""
    for i in range(total.shape[0]):
        for j in range(total.shape[1]):
            y = x[i, j] - compensation[i, j]
            t = total[i, j] + y
            compensation[i, j] = (t - total[i, j]) - y
            total[i, j] = t


@dataclass
class _NodeSegment:
    """Gauss–Jackson solution on equidistant nodes ``t_start + k h`` (k = 0..N)."""

    t_start: float
    t_end: float
    h: float
    y: np.ndarray        # (N + 1, 6, C)
    f: np.ndarray        # (N + 1, 3, C)
    order: int

    def evaluate(self, t_s: np.ndarray) -> np.ndarray:
        """Augmented matrix at times inside the segment, shape (m, 6, C)."""
        n_last = self.y.shape[0] - 1
        x = (t_s - self.t_start) / self.h
        base = np.clip(np.rint(x).astype(int), 0, n_last)
        s = x - base
        first = np.clip(base - self.order // 2, 0, n_last - self.order)
        out = self.y[base].copy()
        off = np.flatnonzero(s != 0.0)
        stencil = np.arange(self.order + 1)
        for blk in np.array_split(off, max(1, -(-off.size // _DENSE_BLOCK))):
            if blk.size == 0:
                continue
            w1, w2 = _integration_weights(first[blk] - base[blk], s[blk], self.order + 1)
            f = self.f[first[blk][:, None] + stencil[None, :]]      # (b, K, 3, C)
            out[blk, :3] += (s[blk] * self.h)[:, None, None] * self.y[base[blk], 3:]
            out[blk, :3] += self.h**2 * np.einsum("bk,bkrc->brc", w2, f)
            out[blk, 3:] += self.h * np.einsum("bk,bkrc->brc", w1, f)
        return out

    @property
    def y_end(self) -> np.ndarray:
        return self.y[-1]



def _relative_change(new: np.ndarray, old: np.ndarray) -> np.ndarray:
    """Per column ``max|new − old| / max(|new|, |old|)`` of blocks (nodes, 3, C), shape (C,)."""
    scale = np.maximum(np.abs(new).max(axis=(0, 1)), np.abs(old).max(axis=(0, 1)))
    return np.abs(new - old).max(axis=(0, 1)) / (scale + np.finfo(float).tiny)


def _inside(t_s: np.ndarray, t_start: float, t_end: float) -> np.ndarray:
    """Epochs at which to evaluate the forces of a segment: clipped to it, and its ends moved
    one ulp inside, so that a force jumping at a breakpoint is evaluated on this segment's side
    (whatever the force's convention at the breakpoint itself)."""
    lo, hi = sorted((np.nextafter(t_start, t_end), np.nextafter(t_end, t_start)))
    return np.clip(t_s, lo, hi)



def _startup(rhs: _Rhs, t_nodes: np.ndarray, h: float, y: np.ndarray, f: np.ndarray,
             order: int) -> None:
    """Fill nodes 1..q of ``y`` and 0..q of ``f`` by collocation (fixed-point iteration).

    ``v_j = v_0 + h Σ w1_ji f_i``, ``r_j = r_0 + j h v_0 + h² Σ w2_ji f_i`` with the weights of
    the polynomial through the q + 1 nodes, iterated from ``f_i = f_0`` until the node
    values stop changing (an implicit Runge–Kutta collocation method of order q + 1). A
    change that stops decreasing within ``_STARTUP_FLOOR`` times the tolerance is the noise of
    the force model (e.g. numerically differentiated partials) and ends the iteration too.
    """
    j = np.arange(1, order + 1)
    w1, w2 = _integration_weights(np.zeros(order, dtype=int), j.astype(float), order + 1)
    rhs(t_nodes[0], y[0], f[0])
    f[1:order + 1] = f[0]
    y[1:order + 1] = y[0]
    tol = np.full(y.shape[2], _STARTUP_RTOL_PARTIALS)
    tol[0] = _STARTUP_RTOL_STATE
    previous_ratio = np.inf
    for _ in range(_STARTUP_MAX_ITERATIONS):
        y_old = y[1:order + 1].copy()
        y[1:order + 1, :3] = (y[0, :3] + (j * h)[:, None, None] * y[0, 3:]
                              + h**2 * np.einsum("ji,irc->jrc", w2, f[:order + 1]))
        y[1:order + 1, 3:] = y[0, 3:] + h * np.einsum("ji,irc->jrc", w1, f[:order + 1])
        for k in j:
            rhs(t_nodes[k], y[k], f[k])
        change = np.maximum(_relative_change(y[1:order + 1, :3], y_old[:, :3]),
                            _relative_change(y[1:order + 1, 3:], y_old[:, 3:]))
        ratio = float(np.max(change / tol))
        if ratio <= 1.0 or (ratio <= _STARTUP_FLOOR and ratio > 0.5 * previous_ratio):
            return                              # converged, or at the noise floor of the forces
        previous_ratio = ratio
    raise RuntimeError(f"integrator start at t = {t_nodes[0]} s did not converge; "
                       f"reduce step_s (now {abs(h)} s)")


def _gauss_jackson_segment(rhs: _Rhs, t_start: float, t_end: float, y0: np.ndarray,
                           step_s: float, order: int, pece: bool) -> _NodeSegment:
    """Integrate one smooth segment with the Gauss–Jackson method."""
    n_steps = max(order, int(np.ceil(abs(t_end - t_start) / step_s - 1e-9)))
    h = (t_end - t_start) / n_steps
    t_nodes = _inside(t_start + h * np.arange(n_steps + 1), t_start, t_end)
    y = np.empty((n_steps + 1, 6, y0.shape[1]))
    f = np.empty((n_steps + 1, 3, y0.shape[1]))
    y[0] = y0
    _startup(rhs, t_nodes, h, y, f, order)
    pred_v, pred_r, corr_v, corr_r = _gauss_jackson_weights(order)
    # integration constants from the corrector at node q
    zero = np.zeros((3, y0.shape[1]))
    sums = np.empty((6, y0.shape[1]))
    _gj_sum(f[:order + 1], zero, zero, corr_v, corr_r, h, False, sums)
    s1 = (y[order, 3:] - sums[3:]) / h
    s2 = (y[order, :3] - sums[:3]) / h**2
    c1 = np.zeros_like(s1)                 # compensations of the running sums
    c2 = np.zeros_like(s2)
    for n in range(order, n_steps):
        _gj_sum(f[n - order:n + 1], s1, s2, pred_v, pred_r, h, True, y[n + 1])
        rhs(t_nodes[n + 1], y[n + 1], f[n + 1])
        _kahan_add(s2, c2, s1)
        _kahan_add(s1, c1, f[n + 1])
        _gj_sum(f[n + 1 - order:n + 2], s1, s2, corr_v, corr_r, h, False, y[n + 1])
        if pece:
            f_predicted = f[n + 1].copy()
            rhs(t_nodes[n + 1], y[n + 1], f[n + 1])
            _kahan_add(s1, c1, f[n + 1] - f_predicted)
    return _NodeSegment(t_start, t_end, h, y, f, order)


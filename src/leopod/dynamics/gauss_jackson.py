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

from dataclasses import dataclass, field
from fractions import Fraction
from functools import lru_cache
from math import comb
from typing import TYPE_CHECKING

import numba
import numpy as np

from leopod.dynamics.compiled import augmented_rhs
from leopod.frames.rtn import _rtn_basis

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
    """Gauss–Jackson solution on equidistant nodes ``t_start + k h`` (k = 0..N).

    Velocity pulses at the nodes ``jump_node`` (without restart): ``y`` holds the right
    limit there and ``y_left`` the left one.
    """

    t_start: float
    t_end: float
    h: float
    y: np.ndarray        # (N + 1, 6, C)
    f: np.ndarray        # (N + 1, 3, C)
    order: int
    jump_node: np.ndarray = field(default_factory=lambda: np.empty(0, dtype=int))
    y_left: np.ndarray | None = None     # (J, 6, C)

    def evaluate(self, t_s: np.ndarray) -> np.ndarray:
        """Augmented matrix at times inside the segment, shape (m, 6, C)."""
        n_last = self.y.shape[0] - 1
        x = (t_s - self.t_start) / self.h
        base = np.clip(np.rint(x).astype(int), 0, n_last)
        s = x - base
        first = np.clip(base - self.order // 2, 0, n_last - self.order)
        out = self.y[base].copy()
        if self.jump_node.size:                  # left of a pulse: its left limit
            j = np.searchsorted(self.jump_node, base)
            left = ((j < self.jump_node.size) & (s * self.h < 0.0)
                    & (self.jump_node[np.minimum(j, self.jump_node.size - 1)] == base))
            out[left] = self.y_left[j[left]]
        off = np.flatnonzero(s != 0.0)
        stencil = np.arange(self.order + 1)
        for blk in np.array_split(off, max(1, -(-off.size // _DENSE_BLOCK))):
            if blk.size == 0:
                continue
            w1, w2 = _integration_weights(first[blk] - base[blk], s[blk], self.order + 1)
            f = self.f[first[blk][:, None] + stencil[None, :]]      # (b, K, 3, C)
            out[blk, :3] += (s[blk] * self.h)[:, None, None] * out[blk, 3:]
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



@lru_cache(maxsize=8)
def _startup_weights(order: int) -> tuple[np.ndarray, np.ndarray]:
    """Collocation weights (q, q + 1) of the start-up nodes 1..q (:func:`_startup`)."""
    j = np.arange(1, order + 1)
    return _integration_weights(np.zeros(order, dtype=int), j.astype(float), order + 1)


def _startup_tolerance(n_columns: int) -> np.ndarray:
    tol = np.full(n_columns, _STARTUP_RTOL_PARTIALS)
    tol[0] = _STARTUP_RTOL_STATE
    return tol


def segment_grid(t_start: float, t_end: float, step_s: float, order: int) -> tuple[int, float]:
    """Steps N and signed step h of a segment: the largest h ≤ step_s dividing it, N ≥ q."""
    n_steps = max(order, int(np.ceil(abs(t_end - t_start) / step_s - 1e-9)))
    return n_steps, (t_end - t_start) / n_steps


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
    w1, w2 = _startup_weights(order)
    rhs(t_nodes[0], y[0], f[0])
    f[1:order + 1] = f[0]
    y[1:order + 1] = y[0]
    tol = _startup_tolerance(y.shape[2])
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


@numba.njit(cache=True)
def _max_relative_change(y, y_old, c, first_row):  # pragma: no cover - numba
    """``max|new − old| / max(|new|, |old|)`` over nodes and 3 rows of column c."""
    diff, big_new, big_old = 0.0, 0.0, 0.0
    for k in range(y.shape[0]):
        for r in range(first_row, first_row + 3):
            diff = max(diff, abs(y[k, r, c] - y_old[k, r, c]))
            big_new = max(big_new, abs(y[k, r, c]))
            big_old = max(big_old, abs(y_old[k, r, c]))
    return diff / (max(big_new, big_old) + 2.2250738585072014e-308)


@numba.njit(cache=True)
def _startup_compiled(t_nodes, h, y, f, order, w1, w2, tol, params, data,
                      work):  # pragma: no cover - numba
    """:func:`_startup` with :func:`leopod.dynamics.compiled.augmented_rhs`; returns the
    number of force evaluations, negative if the iteration did not converge."""
    n_col = y.shape[2]
    augmented_rhs(t_nodes[0], y[0], f[0], params, data, work)
    for k in range(1, order + 1):
        f[k] = f[0]
        y[k] = y[0]
    n_eval = 1
    previous_ratio = np.inf
    for _ in range(_STARTUP_MAX_ITERATIONS):
        y_old = y[1:order + 1].copy()
        for jj in range(1, order + 1):
            for r in range(3):
                for c in range(n_col):
                    s1 = 0.0
                    s2 = 0.0
                    for i in range(order + 1):
                        s1 += w1[jj - 1, i] * f[i, r, c]
                        s2 += w2[jj - 1, i] * f[i, r, c]
                    y[jj, r, c] = y[0, r, c] + (jj * h) * y[0, 3 + r, c] + h * h * s2
                    y[jj, 3 + r, c] = y[0, 3 + r, c] + h * s1
        for k in range(1, order + 1):
            augmented_rhs(t_nodes[k], y[k], f[k], params, data, work)
        n_eval += order
        ratio = 0.0
        for c in range(n_col):
            change = max(_max_relative_change(y[1:order + 1], y_old, c, 0),
                         _max_relative_change(y[1:order + 1], y_old, c, 3))
            ratio = max(ratio, change / tol[c])
        if ratio <= 1.0 or (ratio <= _STARTUP_FLOOR and ratio > 0.5 * previous_ratio):
            return n_eval
        previous_ratio = ratio
    return -n_eval


@numba.njit(cache=True)
def _jump(y, f, t_nodes, node, order, dv_rtn, sign, da_dr, da_dv, saved):  # pragma: no cover
    """Velocity pulse ``sign · M Δv`` at ``node``, into y (6, C), without a restart.

    The back values f of the q nodes before are replaced by those of the orbit after the pulse
    extended backwards to first order, ``f_k + A (t_k − t_p) Δv`` (+ ``B Δv`` at the node;
    A, B the partials of the last evaluation), so that the difference formulas see a smooth
    right-hand side; ``saved`` (q, 3) receives the original back values of the state column.
    """
    basis = np.empty((3, 3))
    _rtn_basis(y[:3, 0].copy(), y[3:, 0].copy(), basis)
    dv = np.zeros(3)
    for i in range(3):
        for j in range(3):
            dv[i] += sign * basis[i, j] * dv_rtn[j]
    for i in range(3):
        y[3 + i, 0] += dv[i]
    for k in range(order + 1):
        row = node - k
        dt = t_nodes[row] - t_nodes[node]
        for i in range(3):
            if k > 0:
                saved[k - 1, i] = f[row, i, 0]
            for j in range(3):
                f[row, i, 0] += da_dr[i, j] * dv[j] * dt + (da_dv[i, j] * dv[j] if k == 0
                                                              else 0.0)


@numba.njit(cache=True)
def _force_jump(y, f, node, order, f_new, saved):  # pragma: no cover - numba
    """Right-hand side jumping at ``node`` (a breakpoint of piecewise-constant force
    parameters) from ``f[node]`` (its old side) to ``f_new`` (the new side), without a restart.

    The back values of the q nodes before are those of the new side extended backwards:
    ``f_k + M_k M_nodeᵀ (f_new − f[node])``, the jump held constant in the orbit's radial,
    along- and cross-track frame M (the piecewise-constant empirical accelerations and drag
    scales are so; over q steps the frame turns by a few degrees), so that the difference
    formulas see a smooth right-hand side; ``saved`` (q, 3, C) receives the original back
    values.
    """
    n_col = f.shape[2]
    basis = np.empty((3, 3))
    _rtn_basis(y[node, :3, 0].copy(), y[node, 3:, 0].copy(), basis)
    jump_rtn = basis.T @ (f_new - f[node])                       # (3, C)
    for k in range(1, order + 1):
        row = node - k
        _rtn_basis(y[row, :3, 0].copy(), y[row, 3:, 0].copy(), basis)
        jump = basis @ jump_rtn
        for i in range(3):
            for c in range(n_col):
                saved[k - 1, i, c] = f[row, i, c]
                f[row, i, c] += jump[i, c]
    f[node] = f_new


@numba.njit(cache=True)
def _sums_from_node(y_node, f_hist, corr_v, corr_r, h, s1, s2, c1, c2):  # pragma: no cover
    """Integration constants S1, S2 from the state and back values at a node (correctors)."""
    zero = np.zeros((3, y_node.shape[1]))
    sums = np.empty((6, y_node.shape[1]))
    _gj_sum(f_hist, zero, zero, corr_v, corr_r, h, False, sums)
    s1[:, :] = (y_node[3:] - sums[3:]) / h
    s2[:, :] = (y_node[:3] - sums[:3]) / (h * h)
    c1[:, :] = 0.0
    c2[:, :] = 0.0


@numba.njit(cache=True)
def _gauss_jackson_compiled(t_nodes, h, y, f, order, w1, w2, tol, weights, pece, jump_node,
                            jump_dv, direction, y_left, break_node, params, data,
                            work):  # pragma: no cover - numba
    """Start-up and Gauss–Jackson steps of one segment with the compiled force model.

    Velocity pulses ``jump_dv[j]`` (RTN [m/s]) at the nodes ``jump_node[j]`` (increasing
    along the integration, more than q nodes apart and after the start-up) enter the state
    without a restart (:func:`_jump`; the integration constants are taken anew from the state
    after the pulse); ``y`` keeps the right limit at those nodes and ``y_left[j]`` the left
    one. At the nodes ``break_node`` (breakpoints of the force parameters, under the same
    conditions and apart from the pulses) the node is corrected with the right-hand side of
    the side it is reached from, then the right-hand side jumps to the other side
    (:func:`_force_jump`; one more evaluation instead of a restart's start-up). Returns the
    number of force evaluations (negative: the start-up did not converge).
    """
    pred_v, pred_r, corr_v, corr_r = weights
    n_steps = t_nodes.size - 1
    n_eval = _startup_compiled(t_nodes, h, y, f, order, w1, w2, tol, params, data, work)
    if n_eval < 0:
        return n_eval
    n_col = y.shape[2]
    s1, s2 = np.empty((3, n_col)), np.empty((3, n_col))
    c1, c2 = np.empty((3, n_col)), np.empty((3, n_col))
    _sums_from_node(y[order], f[:order + 1], corr_v, corr_r, h, s1, s2, c1, c2)
    saved = np.empty((order, 3))
    restore = -1                           # node whose back values to restore, -1: none
    next_jump = 0
    saved_f = np.empty((order, 3, n_col))
    f_new = np.empty((3, n_col))
    restore_f = -1                         # the same for a force breakpoint (all columns)
    next_break = 0
    for n in range(order, n_steps):
        if restore >= 0 and n == restore + order:   # out of the window: the true values
            for k in range(1, order + 1):
                f[restore - k, :, 0] = saved[k - 1]
            restore = -1
        if restore_f >= 0 and n == restore_f + order:
            for k in range(1, order + 1):
                f[restore_f - k] = saved_f[k - 1]
            restore_f = -1
        at_break = next_break < break_node.size and break_node[next_break] == n + 1
        # a breakpoint node is reached on its old side: the forces one ulp before it
        t_eval = np.nextafter(t_nodes[n + 1], t_nodes[n]) if at_break else t_nodes[n + 1]
        _gj_sum(f[n - order:n + 1], s1, s2, pred_v, pred_r, h, True, y[n + 1])
        augmented_rhs(t_eval, y[n + 1], f[n + 1], params, data, work)
        n_eval += 1
        _kahan_add(s2, c2, s1)
        _kahan_add(s1, c1, f[n + 1])
        _gj_sum(f[n + 1 - order:n + 2], s1, s2, corr_v, corr_r, h, False, y[n + 1])
        if pece:
            f_predicted = f[n + 1].copy()
            augmented_rhs(t_eval, y[n + 1], f[n + 1], params, data, work)
            n_eval += 1
            _kahan_add(s1, c1, f[n + 1] - f_predicted)
        if at_break:
            t_new = np.nextafter(t_nodes[n + 1], t_nodes[n + 1] + (t_nodes[n + 1] - t_nodes[n]))
            augmented_rhs(t_new, y[n + 1], f_new, params, data, work)
            n_eval += 1
            _force_jump(y, f, n + 1, order, f_new, saved_f)
            _sums_from_node(y[n + 1], f[n + 1 - order:n + 2], corr_v, corr_r, h, s1, s2, c1,
                            c2)
            restore_f = n + 1
            next_break += 1
        if next_jump < jump_node.size and jump_node[next_jump] == n + 1:
            reached = y[n + 1].copy()
            _jump(y[n + 1], f, t_nodes, n + 1, order, jump_dv[next_jump], float(direction),
                  work[1], work[2], saved)
            _sums_from_node(y[n + 1], f[n + 1 - order:n + 2], corr_v, corr_r, h, s1, s2, c1,
                            c2)
            restore = n + 1
            if direction > 0:
                y_left[next_jump] = reached
            else:                          # backwards: reached from the right
                y_left[next_jump] = y[n + 1]
                y[n + 1] = reached
            next_jump += 1
    if restore >= 0:
        for k in range(1, order + 1):
            f[restore - k, :, 0] = saved[k - 1]
    if restore_f >= 0:
        for k in range(1, order + 1):
            f[restore_f - k] = saved_f[k - 1]
    return n_eval


def _gauss_jackson_segment(rhs: _Rhs, t_start: float, t_end: float, y0: np.ndarray,
                           step_s: float, order: int, pece: bool) -> _NodeSegment:
    """Integrate one smooth segment with the Gauss–Jackson method."""
    n_steps, h = segment_grid(t_start, t_end, step_s, order)
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



def gauss_jackson_compiled(compiled, params: np.ndarray, t_start: float, t_end: float,
                           y0: np.ndarray, step_s: float, order: int, pece: bool,
                           jump_node: np.ndarray, jump_dv: np.ndarray,
                           direction: int, break_node: np.ndarray | None = None
                           ) -> tuple[_NodeSegment, int]:
    """One segment with the compiled force model, pulses and force breakpoints at nodes
    crossed without restart.

    Parameters
    ----------
    compiled : leopod.dynamics.compiled.CompiledForceModel
    params : ndarray, shape (P,)
    t_start, t_end : float
        Segment [TT s] (t_end < t_start backwards).
    y0 : ndarray, shape (6, C)
        Augmented matrix at t_start.
    step_s, order, pece
        As :func:`leopod.dynamics.integrator.integrate`.
    jump_node : ndarray of int, shape (J,)
        Node indices in (q, N), more than q apart, of velocity pulses (:func:`segment_grid`).
    jump_dv : ndarray, shape (J, 3)
        The pulses in R, T, N [m/s] (applied with the sign of ``direction``).
    direction : int
        +1 forwards, −1 backwards.
    break_node : ndarray of int, shape (B,), optional
        Node indices in (q, N), more than q apart and from the pulses, of breakpoints of the
        force parameters (the forces jump there).

    Returns
    -------
    segment : _NodeSegment
    n_evaluations : int
    """
    n_steps, h = segment_grid(t_start, t_end, step_s, order)
    t_nodes = _inside(t_start + h * np.arange(n_steps + 1), t_start, t_end)
    n_col = y0.shape[1]
    y = np.empty((n_steps + 1, 6, n_col))
    f = np.empty((n_steps + 1, 3, n_col))
    y[0] = y0
    y_left = np.empty((jump_node.size, 6, n_col))
    w1, w2 = _startup_weights(order)
    p = np.ascontiguousarray(params, dtype=float)
    work = (np.empty(3), np.empty((3, 3)), np.empty((3, 3)), np.empty((3, p.size)))
    n_eval = _gauss_jackson_compiled(
        t_nodes, h, y, f, order, w1, w2, _startup_tolerance(n_col), _gauss_jackson_weights(order),
        pece, np.asarray(jump_node, dtype=np.int64),
        np.ascontiguousarray(jump_dv, dtype=float).reshape(-1, 3), direction, y_left,
        np.asarray([] if break_node is None else break_node, dtype=np.int64), p,
        compiled.data, work)
    if n_eval < 0:
        raise RuntimeError(f"integrator start at t = {t_start} s did not converge; "
                           f"reduce step_s (now {abs(h)} s)")
    segment = _NodeSegment(t_start, t_end, h, y, f, order, np.asarray(jump_node, dtype=int),
                           y_left)
    return segment, n_eval

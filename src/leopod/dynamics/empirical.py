"""Empirical accelerations (piecewise constant + once-per-revolution) and the RTN frame.

RTN (radial, along-track, cross-track) frame of a state (r, v): ``R = r/|r|``,
``N = (r × v)/|r × v|``, ``T = N × R`` (T is along the velocity for a circular orbit); the
matrix of :func:`rtn_matrix` is the transpose of :func:`leopod.frames.rtn.rtn_basis`. :func:`rtn_matrix` returns the rows R, T, N:
``x_rtn = M @ x_gcrf``.

Empirical acceleration of Peng et al. (2021) Table II ("piece-wise periodical terms in the along-
and cross-track directions estimated every 180 min"), Jiang et al. (2023) Table 2 (every 120 min)
and Jäggi et al. (2006, J. Geod. 80:47–60, "Pseudo-stochastic orbit modeling techniques for
low-Earth orbiters"), per interval k and direction X ∈ {R, T, N}::

    a_X = C_X,k + A_X,k cos u + B_X,k sin u

with u the argument of latitude computed from the current state (angle in the orbital plane
from the ascending node to r: ``u = atan2(|h| z, h_x y − h_y x)``, h = r × v), so that the
once-per-revolution terms follow the actual orbit rather than a nominal mean motion. The
acceleration is ``a = Mᵀ [a_R, a_T, a_N]``.

Partial derivatives: ``∂a/∂(C, A, B)`` are exact (``Mᵀ e_X``, ``Mᵀ e_X cos u``,
``Mᵀ e_X sin u`` for the interval containing t, zero for the others). ``∂a/∂r`` and
``∂a/∂v`` through the RTN frame and u are neglected (returned as zeros): they are of order
|a|/|r| ≈ 1e-14 s⁻² and |a|/|v| ≈ 1e-11 s⁻¹ for |a| ≈ 1e-7 m/s², eight orders of magnitude
below the gravity gradient.

Parameter layout: the flat vector is ``coefficients[k, d, j]`` raveled in C order, k the
interval, d the direction (``EmpiricalModel.directions``), j the term (``terms``); see
:meth:`EmpiricalModel.index` and :meth:`EmpiricalModel.active`. :class:`Empirical` is the force
of the orbit integrator.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np

from leopod.dynamics.forces import Force

__all__ = ["Empirical", "EmpiricalModel", "argument_of_latitude", "empirical_acceleration"]

_DIRECTIONS = ("R", "T", "N")
_TERMS = ("const", "cos", "sin")


def argument_of_latitude(pos_m, vel_m_s):
    """Argument of latitude u [rad] in (−π, π] of the state(s) (module docstring formula).

    Parameters
    ----------
    pos_m, vel_m_s : array_like, shape (..., 3)
        Inertial position [m] and velocity [m/s].

    Returns
    -------
    float or ndarray, shape (...)
    """
    r = np.asarray(pos_m, dtype=float)
    h = np.cross(r, np.asarray(vel_m_s, dtype=float))
    return np.arctan2(np.linalg.norm(h, axis=-1) * r[..., 2],
                      h[..., 0] * r[..., 1] - h[..., 1] * r[..., 0])


@dataclass(frozen=True)
class EmpiricalModel:
    """Layout of piecewise empirical accelerations.

    Parameters
    ----------
    boundaries_s : array_like, shape (n_intervals + 1,)
        Increasing interval boundaries [s], in the time argument used for ``t`` (e.g. TT
        seconds since the reference epoch of the arc, as ``Force.evaluate``); they are the
        breakpoints of the integration. Interval k is ``[b_k, b_k+1)``; epochs before the first or
        after the last boundary use the first or last interval (the integrator may step a
        little beyond the arc).
    directions : tuple of str
        Subset of ("R", "T", "N"), default ("T", "N") as in Peng et al. (2021) Table II.
    terms : tuple of str
        Subset of ("const", "cos", "sin"), default all three.
    """

    boundaries_s: np.ndarray
    directions: tuple[str, ...] = ("T", "N")
    terms: tuple[str, ...] = _TERMS

    def __post_init__(self):
        b = np.asarray(self.boundaries_s, dtype=float)
        if b.ndim != 1 or b.size < 2 or np.any(np.diff(b) <= 0.0):
            raise ValueError("boundaries_s must be at least two increasing epochs")
        if not self.directions or any(d not in _DIRECTIONS for d in self.directions):
            raise ValueError(f"directions must be a non-empty subset of {_DIRECTIONS}")
        if not self.terms or any(t not in _TERMS for t in self.terms):
            raise ValueError(f"terms must be a non-empty subset of {_TERMS}")
        object.__setattr__(self, "boundaries_s", b)
        object.__setattr__(self, "directions", tuple(self.directions))
        object.__setattr__(self, "terms", tuple(self.terms))
        object.__setattr__(self, "_dir_idx",
                           np.array([_DIRECTIONS.index(d) for d in self.directions]))
        object.__setattr__(self, "_term_idx", np.array([_TERMS.index(j) for j in self.terms]))

    @classmethod
    def regular(cls, start_s: float, end_s: float, interval_s: float, **kwargs):
        """Intervals of ``interval_s`` [s] from ``start_s`` (the last one ends at ``end_s``)."""
        n = max(int(np.ceil((end_s - start_s) / interval_s - 1e-9)), 1)
        bounds = np.minimum(start_s + interval_s * np.arange(n + 1), end_s)
        return cls(bounds, **kwargs)

    @property
    def n_intervals(self) -> int:
        return self.boundaries_s.size - 1

    @property
    def n_per_interval(self) -> int:
        return len(self.directions) * len(self.terms)

    @property
    def n_params(self) -> int:
        return self.n_intervals * self.n_per_interval

    def interval(self, t_s: float) -> int:
        """Index of the interval containing ``t_s`` (clipped to the first/last interval)."""
        k = int(np.searchsorted(self.boundaries_s, t_s, side="right")) - 1
        return min(max(k, 0), self.n_intervals - 1)

    def index(self, interval: int, direction: str, term: str) -> int:
        """Position of one coefficient in the flat parameter vector."""
        d = self.directions.index(direction)
        j = self.terms.index(term)
        return (interval * len(self.directions) + d) * len(self.terms) + j

    def active(self, t_s: float) -> slice:
        """Slice of the flat parameter vector acting at ``t_s`` (one interval's coefficients)."""
        k = self.interval(t_s)
        return slice(k * self.n_per_interval, (k + 1) * self.n_per_interval)

    def names(self, prefix: str = "emp") -> list[str]:
        """Names ``f"{prefix}_{term}_{X}_{k}"`` of the flat parameter vector, in its order
        (e.g. ``"emp_cos_T_3"``, the naming of :mod:`leopod.dynamics.forces`)."""
        return [f"{prefix}_{j}_{d}_{k}" for k in range(self.n_intervals)
                for d in self.directions for j in self.terms]


@numba.njit(cache=True)
def _local_partials(pos, vel, dir_idx, term_idx):
    """∂a/∂p of one interval's coefficients, shape (3, n_dir * n_terms)."""
    h = np.array([pos[1] * vel[2] - pos[2] * vel[1], pos[2] * vel[0] - pos[0] * vel[2],
                  pos[0] * vel[1] - pos[1] * vel[0]])
    nh = np.sqrt(h[0] ** 2 + h[1] ** 2 + h[2] ** 2)
    nr = np.sqrt(pos[0] ** 2 + pos[1] ** 2 + pos[2] ** 2)
    axes = np.empty((3, 3))  # rows R, T, N
    for i in range(3):
        axes[0, i] = pos[i] / nr
        axes[2, i] = h[i] / nh
    axes[1, 0] = axes[2, 1] * axes[0, 2] - axes[2, 2] * axes[0, 1]
    axes[1, 1] = axes[2, 2] * axes[0, 0] - axes[2, 0] * axes[0, 2]
    axes[1, 2] = axes[2, 0] * axes[0, 1] - axes[2, 1] * axes[0, 0]
    u = np.arctan2(nh * pos[2], h[0] * pos[1] - h[1] * pos[0])
    factor = np.array([1.0, np.cos(u), np.sin(u)])
    n_t = term_idx.size
    out = np.empty((3, dir_idx.size * n_t))
    for d in range(dir_idx.size):
        for j in range(n_t):
            for i in range(3):
                out[i, d * n_t + j] = axes[dir_idx[d], i] * factor[term_idx[j]]
    return out


def empirical_acceleration(t_s: float, pos_m, vel_m_s, coefficients, model: EmpiricalModel):
    """Piecewise empirical acceleration in the RTN directions and its partials.

    Parameters
    ----------
    t_s : float
        Epoch [s], in the time argument of ``model.boundaries_s``.
    pos_m, vel_m_s : ndarray, shape (3,)
        GCRF position [m] and velocity [m/s].
    coefficients : ndarray, shape (model.n_params,)
        Flat coefficient vector [m/s²] (layout in the module docstring).
    model : EmpiricalModel

    Returns
    -------
    acc : ndarray, shape (3,)
        GCRF acceleration [m/s²].
    da_dr, da_dv : ndarray, shape (3, 3)
        Zeros (frame partials neglected, module docstring).
    da_dp : ndarray, shape (3, model.n_params)
        ∂a/∂coefficients [1]; non-zero only in the columns ``model.active(t_s)``.
    """
    coef = np.asarray(coefficients, dtype=float)
    if coef.shape != (model.n_params,):
        raise ValueError(f"expected {model.n_params} coefficients, got shape {coef.shape}")
    active = model.active(t_s)
    local = _local_partials(np.asarray(pos_m, dtype=float), np.asarray(vel_m_s, dtype=float),
                            model._dir_idx, model._term_idx)
    da_dp = np.zeros((3, model.n_params))
    da_dp[:, active] = local
    return local @ coef[active], np.zeros((3, 3)), np.zeros((3, 3)), da_dp


class Empirical(Force):
    """Constant and once-per-revolution accelerations per interval
    (:func:`leopod.dynamics.empirical.empirical_acceleration`); parameters
    ``emp_{term}_{direction}_{k}`` [m/s²].

    Parameters
    ----------
    model : EmpiricalModel
    apriori, estimate, sigma
        A priori value of every coefficient (0), whether they are estimated, and an a priori
        constraint [m/s²] (None: free).
    """

    def __init__(self, model: EmpiricalModel, *, apriori: float = 0.0, estimate: bool = True,
                 sigma: float | None = None):
        self.model = model
        self.parameters = model.names("emp")
        self.apriori = np.full(model.n_params, float(apriori))
        self.estimate = bool(estimate)
        self.sigma = np.full(model.n_params, np.inf if sigma is None else float(sigma))

    @property
    def breakpoints_s(self) -> np.ndarray:
        return self.model.boundaries_s[1:-1]

    def kernel_data(self) -> tuple:
        """``(boundaries_s, direction indices, term indices)`` (compiled force model)."""
        return self.model.boundaries_s, self.model._dir_idx, self.model._term_idx

    def evaluate(self, t_s, pos_m, vel_m_s, params):
        return empirical_acceleration(t_s, pos_m, vel_m_s, params, self.model)

"""Force-model interface of the orbit integrator, and simple forces to build and test with.

Every force model (gravity field, tides, third bodies, drag, solar radiation pressure,
relativity, empirical accelerations) implements :class:`Force`: given the time ``t_s`` [TT
seconds since the reference epoch of the arc, fixed when the force is constructed], the GCRF
position ``pos_m`` (3,) and velocity ``vel_m_s`` (3,) of the satellite and the values of the
force's own dynamic parameters ``params`` (k,), it returns

* the acceleration ``acc`` (3,) [m/s²],
* its partials ``da_dr`` (3, 3) [1/s²] and ``da_dv`` (3, 3) [1/s] (the matrices A and B of the
  variational equations, Montenbruck & Gill 2000, sec. 7.2), and
* ``da_dp`` (3, k) with respect to the parameters (M&G 2000, sec. 7.2), in the order
  of ``parameters`` (names such as ``"drag_scale_0"``, ``"emp_cos_T_3"``).

A force whose acceleration jumps at known epochs (piecewise-constant parameters) lists them in
``breakpoints_s``: the integrator restarts there, since a multistep or high-order Runge–Kutta
step across a discontinuity of the right-hand side loses its order.

:class:`ForceModel` sums forces and concatenates their parameters into one global vector;
:func:`apriori_parameters`, :func:`estimated_parameters` and :func:`constraint_sigmas` collect
the forces' per-parameter a priori values, estimation flags and constraints. Forces with a
scale factor per interval (:func:`interval_edges`; drag, solar radiation pressure) derive
from ``_Scaled``.
:class:`PseudoStochasticPulses` is not a force: instantaneous velocity changes whose partials
follow from the state transition matrix (:func:`leopod.dynamics.integrator.pulse_partials`).

RTN frame of a state (r, v): ``e_R = r/|r|``, ``e_N = (r × v)/|r × v|``, ``e_T = e_N × e_R``
(radial, along-track, cross-track; Montenbruck & Gill 2000, sec. 3.7.4).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Sequence
from dataclasses import dataclass, field
from itertools import pairwise

import numpy as np

from leopod.constants import GM_EARTH_M3_S2
from leopod.dynamics.environment import ArcEnvironment
from leopod.frames.rtn import RTN_AXES, rtn_basis, rtn_vector_partials
from leopod.numerics.interpolate import interpolate_table

__all__ = ["ConstantAcceleration", "Force", "ForceModel", "PointMassGravity",
           "PseudoStochasticPulses", "apriori_parameters", "constraint_sigmas",
           "circular_orbit", "estimated_parameters", "extended_orbit", "interval_edges",
           "tabulated_orbit"]


class Force(ABC):
    """One force model: acceleration with partials, in GCRF (see the module docstring).

    Subclasses set the instance attribute ``parameters`` (list of str): the names of the
    dynamic parameters owned by the force (may be empty).
    """

    parameters: list[str]

    @property
    def breakpoints_s(self) -> np.ndarray:
        """Epochs [TT s since the reference epoch] where the acceleration is discontinuous."""
        return np.empty(0)

    @abstractmethod
    def evaluate(self, t_s: float, pos_m: np.ndarray, vel_m_s: np.ndarray,
                 params: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Acceleration and partials at one state.

        Parameters
        ----------
        t_s : float
            Time [TT s since the reference epoch].
        pos_m, vel_m_s : ndarray, shape (3,)
            GCRF position [m] and velocity [m/s].
        params : ndarray, shape (k,)
            Values of the force's parameters, in the order of ``parameters``.

        Returns
        -------
        acc : ndarray, shape (3,)
            Acceleration [m/s²].
        da_dr : ndarray, shape (3, 3)
            ``∂a/∂r`` [1/s²].
        da_dv : ndarray, shape (3, 3)
            ``∂a/∂v`` [1/s].
        da_dp : ndarray, shape (3, k)
            ``∂a/∂p`` [m/s² per unit of each parameter].
        """


class ForceModel:
    """Sum of forces, with their parameters concatenated in the order of ``forces``.

    Parameters
    ----------
    forces : sequence of Force

    Attributes
    ----------
    forces : list of Force
    parameters : list of str
        Global parameter names (unique); ``params`` vectors follow this order.
    breakpoints_s : ndarray, shape (b,)
        Sorted union of the forces' breakpoints [TT s].
    """

    def __init__(self, forces: Sequence[Force]):
        self.forces = list(forces)
        self.parameters = [name for f in self.forces for name in f.parameters]
        duplicates = sorted({p for p in self.parameters if self.parameters.count(p) > 1})
        if duplicates:
            raise ValueError(f"parameter names must be unique across forces: {duplicates}")
        bounds = np.cumsum([0] + [len(f.parameters) for f in self.forces])
        self._slices = [slice(int(a), int(b)) for a, b in pairwise(bounds)]
        parts = [np.asarray(f.breakpoints_s, dtype=float) for f in self.forces]
        self.breakpoints_s = np.unique(np.concatenate(parts)) if parts else np.empty(0)

    @property
    def n_params(self) -> int:
        """Number P of global parameters."""
        return len(self.parameters)

    def follow(self, positions) -> None:
        """Give the forces that are tabulated along a reference orbit (drag: its density,
        :meth:`leopod.dynamics.drag.Drag.follow`) that orbit: ``positions(t_s (n,)) -> (n, 3)``
        GCRF positions [m] over the arc."""
        for force in self.forces:
            if hasattr(force, "follow"):
                force.follow(positions)

    def evaluate(self, t_s: float, pos_m: np.ndarray, vel_m_s: np.ndarray,
                 params: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Total acceleration and partials; ``da_dp`` has shape (3, P), global order.

        Arguments and results as :meth:`Force.evaluate`, with ``params`` of shape (P,).
        """
        acc = np.zeros(3)
        da_dr = np.zeros((3, 3))
        da_dv = np.zeros((3, 3))
        da_dp = np.zeros((3, self.n_params))
        for force, sl in zip(self.forces, self._slices):
            a, ar, av, ap = force.evaluate(t_s, pos_m, vel_m_s, params[sl])
            acc += a
            da_dr += ar
            da_dv += av
            da_dp[:, sl] = ap
        return acc, da_dr, da_dv, da_dp


class PointMassGravity(Force):
    """Central-body attraction ``a = −GM r/|r|³`` (Montenbruck & Gill 2000, sec. 2.1).

    Partials (M&G 2000, sec. 7.2): ``∂a/∂r = −GM/r³ (I − 3 r rᵀ/r²)``, ``∂a/∂v = 0``. No parameters.

    Parameters
    ----------
    gm_m3_s2 : float, optional
        Gravitational constant of the body [m³/s²] (default: Earth, IERS 2010).
    """

    def __init__(self, gm_m3_s2: float = GM_EARTH_M3_S2):
        self.gm_m3_s2 = float(gm_m3_s2)
        self.parameters = []

    def evaluate(self, t_s, pos_m, vel_m_s, params):
        r2 = pos_m @ pos_m
        k = self.gm_m3_s2 / (r2 * np.sqrt(r2))
        acc = -k * pos_m
        da_dr = -k * (np.eye(3) - 3.0 * np.outer(pos_m, pos_m) / r2)
        return acc, da_dr, np.zeros((3, 3)), np.zeros((3, 0))


class ConstantAcceleration(Force):
    """Piecewise-constant empirical accelerations in RTN over given time intervals.

    Interval i is ``[edges_s[i], edges_s[i+1])``; in it ``a = M(r, v) @ (p_R,i, p_T,i, p_N,i)``
    with M from :func:`rtn_basis`; outside all intervals ``a = 0``. Parameters, 3 per
    interval: ``f"{prefix}_R_{i}"``, ``_T_``, ``_N_`` [m/s²]. ``∂a/∂p`` are the RTN unit vectors
    in the interval (0 outside); the partials of the rotating RTN frame w.r.t. r and v are
    included exactly (:func:`rtn_vector_partials`; they are ~1e-8 of the gravity gradient for
    accelerations of 1e-7 m/s², so they could be neglected). Montenbruck & Gill 2000,
    sec. 3.7.4 and 7.2.

    Parameters
    ----------
    edges_s : array_like, shape (n + 1,)
        Increasing interval boundaries [TT s since the reference epoch]; they are breakpoints.
    prefix : str, optional
        Prefix of the parameter names (default ``"emp_const"``).
    """

    def __init__(self, edges_s, prefix: str = "emp_const"):
        self.edges_s = np.asarray(edges_s, dtype=float)
        if self.edges_s.ndim != 1 or self.edges_s.size < 2 or np.any(np.diff(self.edges_s) <= 0):
            raise ValueError("edges_s must be at least two strictly increasing epochs")
        n = self.edges_s.size - 1
        self.parameters = [f"{prefix}_{axis}_{i}" for i in range(n) for axis in RTN_AXES]

    @property
    def breakpoints_s(self) -> np.ndarray:
        return self.edges_s

    def interval(self, t_s: float) -> int:
        """Index of the interval containing ``t_s``, or -1 outside all intervals."""
        i = int(np.searchsorted(self.edges_s, t_s, side="right")) - 1
        return i if 0 <= i < self.edges_s.size - 1 else -1

    def evaluate(self, t_s, pos_m, vel_m_s, params):
        da_dp = np.zeros((3, len(self.parameters)))
        i = self.interval(t_s)
        if i < 0:
            zero = np.zeros((3, 3))
            return np.zeros(3), zero, zero.copy(), da_dp
        basis = rtn_basis(pos_m, vel_m_s)
        coef = params[3 * i:3 * i + 3]
        da_dp[:, 3 * i:3 * i + 3] = basis
        da_dr, da_dv = rtn_vector_partials(pos_m, vel_m_s, coef)
        return basis @ coef, da_dr, da_dv, da_dp


@dataclass(frozen=True, eq=False)
class PseudoStochasticPulses:
    """Pseudo-stochastic pulses: instantaneous velocity changes in R, T, N at given epochs.

    Not a force: a pulse ``Δv_i`` at ``t_i`` changes the velocity by ``M(t_i) Δv_i`` (M from
    :func:`rtn_basis`); its partials come from the state transition matrix without
    re-integration (Jäggi et al. 2006, J. Geod. 80:47-60, doi:10.1007/s00190-006-0029-9;
    Wang et al. 2024, sec. 2.1, eq. 1-3): see :func:`leopod.dynamics.integrator.pulse_partials`, and
    :func:`leopod.dynamics.integrator.apply_pulses` to integrate with actual pulses.

    Attributes
    ----------
    epochs_s : ndarray, shape (n,)
        Pulse epochs [TT s since the reference epoch], strictly increasing.
    prefix : str
        Prefix of the parameter names ``f"{prefix}_R_{i}"``, ``_T_``, ``_N_`` [m/s].
    """

    epochs_s: np.ndarray
    prefix: str = "pulse"
    parameters: list[str] = field(init=False)

    def __post_init__(self):
        epochs = np.atleast_1d(np.asarray(self.epochs_s, dtype=float))
        if epochs.ndim != 1 or np.any(np.diff(epochs) <= 0):
            raise ValueError("pulse epochs must be strictly increasing")
        object.__setattr__(self, "epochs_s", epochs)
        names = [f"{self.prefix}_{axis}_{i}" for i in range(epochs.size) for axis in RTN_AXES]
        object.__setattr__(self, "parameters", names)


# ------------------------------------------------------- reference orbits (ForceModel.follow)


#: Epochs of the Lagrange interpolation of :func:`tabulated_orbit` (degree 8).
_TABLE_NODES = 9
#: A step of a tabulated orbit longer than this many median steps is a gap bridged by
#: circular orbits (:func:`tabulated_orbit`); shorter holes (5 min of 30-s data) stay inside
#: the degree-8 interpolation.
_TABLE_GAP_STEPS = 10.0


def circular_orbit(t0_s: float, state0: np.ndarray):
    """Circular two-body motion through a state: a reference orbit for minutes around it.

    Keeps the radius and the orbital plane of ``state0`` (GCRF position [m], velocity [m/s] at
    ``t0_s``); a LEO departs from it by ~a e radially (km) and by the J2 drift, which a
    density looked up along the orbit tolerates (:class:`leopod.dynamics.drag.DensityAlongOrbit`).

    Returns
    -------
    callable
        ``positions(t_s (m,)) -> (m, 3)`` GCRF [m].
    """
    state = np.asarray(state0, dtype=float)
    radius = np.linalg.norm(state[:3])
    e1 = state[:3] / radius
    e2 = state[3:] - (state[3:] @ e1) * e1
    e2 /= np.linalg.norm(e2)
    n = np.sqrt(GM_EARTH_M3_S2 / radius**3)

    def positions(t_s):
        angle = n * (np.atleast_1d(np.asarray(t_s, dtype=float)) - t0_s)
        return radius * (np.cos(angle)[:, None] * e1 + np.sin(angle)[:, None] * e2)
    return positions


def extended_orbit(inside, lo: float, hi: float, state_lo: np.ndarray, state_hi: np.ndarray):
    """A reference orbit known on [lo, hi], continued by :func:`circular_orbit` beyond.

    Parameters
    ----------
    inside : callable
        ``positions(t_s (m,)) -> (m, 3)`` GCRF [m] for epochs in [lo, hi] [s].
    lo, hi : float
        Span of ``inside`` [s].
    state_lo, state_hi : ndarray, shape (6,)
        GCRF states at lo and hi.

    Returns
    -------
    callable
        ``positions(t_s (m,)) -> (m, 3)`` for any epochs.
    """
    before, after = circular_orbit(lo, state_lo), circular_orbit(hi, state_hi)

    def positions(t_s):
        t = np.atleast_1d(np.asarray(t_s, dtype=float))
        out = np.empty((t.size, 3))
        early, late = t < lo, t > hi
        middle = ~(early | late)
        for sel, fn in ((middle, inside), (early, before), (late, after)):
            if sel.any():
                out[sel] = fn(t[sel])
        return out
    return positions


def tabulated_orbit(t_s: np.ndarray, pos_m: np.ndarray):
    """A reference orbit for :meth:`ForceModel.follow` from tabulated positions.

    The table is cut at gaps longer than :data:`_TABLE_GAP_STEPS` median steps (a data gap
    of the a-priori orbit); each piece of at least 9 epochs is interpolated on its own, and a
    gap is bridged by the :func:`circular_orbit` of the states at its two edges, blended
    linearly across it. A degree-8 polynomial through nodes on both sides of an hours-long
    gap swings by more than 1000 km (a 2-h gap of the simulated HY-2B day gave heights of
    −400 km); the bridge stays within the km of :func:`circular_orbit`, enough for
    a density looked up along the orbit (Drag.follow).

    Parameters
    ----------
    t_s : ndarray, shape (n,)
        Increasing epochs [TT s since the reference epoch]; a piece without a gap of at least
        9 of them.
    pos_m : ndarray, shape (n, 3)
        GCRF positions [m] (e.g. the a-priori orbit).

    Returns
    -------
    callable
        ``positions(t_s (m,)) -> (m, 3)``: Lagrange interpolation (degree 8) inside the
        pieces, the bridges between them, :func:`extended_orbit` beyond the first and last.

    Raises
    ------
    ValueError
        If no piece has 9 epochs.
    """
    t = np.asarray(t_s, dtype=float)
    pos = np.asarray(pos_m, dtype=float)
    step = np.diff(t)
    cuts = np.flatnonzero(step > _TABLE_GAP_STEPS * np.median(step)) + 1 if t.size > 1 else []
    pieces = [p for p in np.split(np.arange(t.size), cuts) if p.size >= _TABLE_NODES]
    if not pieces:
        raise ValueError(f"reference orbit: no stretch of {_TABLE_NODES} positions without a "
                         f"gap (of more than {_TABLE_GAP_STEPS} steps) among {t.size}")
    spans, states, tables = [], [], []
    for p in pieces:
        tp, xp = t[p], pos[p]
        ends, rates = interpolate_table(tp, xp, tp[[0, -1]], order=_TABLE_NODES - 1)
        spans.append((tp[0], tp[-1]))
        states.append((np.concatenate([ends[0], rates[0]]), np.concatenate([ends[1], rates[1]])))
        tables.append((tp, xp))

    def inside(q):
        out = np.empty((q.size, 3))
        for k, ((lo, hi), (tp, xp)) in enumerate(zip(spans, tables, strict=True)):
            sel = (q >= lo) & (q <= hi)
            if sel.any():
                out[sel] = interpolate_table(tp, xp, q[sel], order=_TABLE_NODES - 1)[0]
            if k + 1 < len(spans):        # the bridge of the gap after piece k
                nxt = spans[k + 1][0]
                sel = (q > hi) & (q < nxt)
                if sel.any():
                    w = ((q[sel] - hi) / (nxt - hi))[:, None]
                    out[sel] = ((1.0 - w) * circular_orbit(hi, states[k][1])(q[sel])
                                + w * circular_orbit(nxt, states[k + 1][0])(q[sel]))
        return out
    return extended_orbit(inside, spans[0][0], spans[-1][1], states[0][0], states[-1][1])


# ------------------------------------------------------- parameters per interval


def interval_edges(t_start_s: float, t_end_s: float, interval_s: float | None) -> np.ndarray:
    """Boundaries of intervals of ``interval_s`` from ``t_start_s`` (the last ends at
    ``t_end_s``); one interval for ``None``."""
    if interval_s is None:
        return np.array([t_start_s, t_end_s], dtype=float)
    if interval_s <= 0:
        raise ValueError(f"interval_s must be positive, not {interval_s}")
    n = max(int(np.ceil((t_end_s - t_start_s) / interval_s - 1e-9)), 1)
    return np.minimum(t_start_s + interval_s * np.arange(n + 1), t_end_s)


class _Scaled(Force):
    """Force ``s_k a0(t, r, v)`` with a scale factor per interval (shared by drag, SRP and
    Earth radiation), on a cannonball or on ``plates``.

    Parameters ``f"{prefix}_{k}"``; the interval k holding t is clipped to the first and
    last (the integrator may step just outside the arc); interior edges are breakpoints.
    """

    def __init__(self, env: ArcEnvironment, edges_s: np.ndarray, prefix: str, *,
                 apriori: float = 1.0, estimate: bool = True, sigma: float | None = None,
                 plates=None):
        self.env = env
        #: The macro model flown with an attitude (:class:`leopod.dynamics.plates.Plates`),
        #: or None for a cannonball.
        self.plates = plates
        self.edges_s = np.asarray(edges_s, dtype=float)
        n = self.edges_s.size - 1
        self.parameters = [f"{prefix}_{k}" for k in range(n)]
        self.apriori = np.full(n, float(apriori))
        self.estimate = bool(estimate)
        self.sigma = np.full(n, np.inf if sigma is None else float(sigma))

    @property
    def breakpoints_s(self) -> np.ndarray:
        return self.edges_s[1:-1]

    def follow(self, positions) -> None:
        """Tabulate the attitude of the plates (if any) along a reference orbit
        ``positions(t_s (n,)) -> (n, 3)`` (GCRF [m])."""
        if self.plates is not None:
            self.plates.follow(positions)

    @property
    def ready(self) -> bool:
        """False while plates wait for their reference orbit (no compiled form yet)."""
        return self.plates is None or self.plates.ready

    def interval(self, t_s: float) -> int:
        k = int(np.searchsorted(self.edges_s, t_s, side="right")) - 1
        return min(max(k, 0), self.edges_s.size - 2)

    @abstractmethod
    def _unscaled(self, t_s, pos, vel, scale):
        """(s a0, ∂(s a0)/∂r, ∂(s a0)/∂v, a0 (3, 1)) at one state."""

    def evaluate(self, t_s, pos_m, vel_m_s, params):
        self.env.check(t_s)
        k = self.interval(t_s)
        acc, da_dr, da_dv, a0 = self._unscaled(float(t_s), np.asarray(pos_m, dtype=float),
                                               np.asarray(vel_m_s, dtype=float), params[k])
        da_dp = np.zeros((3, len(self.parameters)))
        da_dp[:, k] = a0[:, 0]
        return acc, da_dr, da_dv, da_dp


# ------------------------------------------------------- parameter attributes


def _per_parameter(force_model: ForceModel, attribute: str, default) -> np.ndarray:
    parts = []
    for force in force_model.forces:
        k = len(force.parameters)
        value = getattr(force, attribute, default)
        parts.append(np.broadcast_to(np.asarray(value), (k,)))
    return np.concatenate(parts) if parts else np.empty(0)


def apriori_parameters(force_model: ForceModel) -> np.ndarray:
    """A priori values (P,) of the force model's parameters (0 for forces without any)."""
    return _per_parameter(force_model, "apriori", 0.0).astype(float)


def estimated_parameters(force_model: ForceModel) -> np.ndarray:
    """Boolean mask (P,): which parameters are estimated (default True)."""
    return _per_parameter(force_model, "estimate", True).astype(bool)


def constraint_sigmas(force_model: ForceModel) -> np.ndarray:
    """A priori standard deviations (P,) of the parameters (inf: unconstrained)."""
    return _per_parameter(force_model, "sigma", np.inf).astype(float)

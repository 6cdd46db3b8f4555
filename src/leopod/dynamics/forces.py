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

:class:`ForceModel` sums forces and concatenates their parameters into one global vector.
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
from leopod.frames.rtn import RTN_AXES, rtn_basis, rtn_vector_partials

__all__ = ["ConstantAcceleration", "Force", "ForceModel", "PointMassGravity",
           "PseudoStochasticPulses"]


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

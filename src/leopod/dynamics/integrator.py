"""Orbit integration with the variational equations: state, transition and sensitivity matrices.

The equation of motion ``r̈ = a(t, r, v, p)`` (GCRF, TT seconds since the reference epoch of the
force model) is integrated together with the variational equations (Montenbruck & Gill 2000,
sec. 7.2) for the state transition matrix ``Φ(t, t0) = ∂y(t)/∂y(t0)`` (6×6) and the sensitivity
matrix ``S(t) = ∂y(t)/∂p`` (6×P), ``y = (r, v)``::

    Φ̈_r = A Φ_r + B Φ̇_r ,          Φ(t0) = I
    S̈_r = A S_r + B Ṡ_r + ∂a/∂p ,  S(t0) = 0        (A = ∂a/∂r, B = ∂a/∂v)

All of them form one second-order system for the 3×C matrix ``[r | Φ_r | S_r]``
(C = 1 + 6 + P columns), whose "acceleration" is ``[a | A Φ_r + B Φ_v | A S_r + B S_v + ∂a/∂p]``.

Method. A fixed-step Gauss–Jackson (summed Störmer–Cowell for r, summed Adams for v)
predictor–corrector of order q = 10 (11 back values, one force evaluation per step in PEC mode;
Berry & Healy 2004, J. Astronaut. Sci. 52(3):331–357; Montenbruck & Gill 2000, sec. 4.2):
its coefficients, start-up and dense output are in :mod:`leopod.dynamics.gauss_jackson`.

Why this method (benchmarks/integrator.py and tests; LEO a = 6878 km, e = 0.001, 30 h):

* Two-body / J2: Gauss–Jackson q = 10 at 30 s steps is within 0.0002 mm of Kepler with
  3 700 force evaluations; scipy's adaptive DOP853 (rtol 1e-13) needs 17 000–18 000
  evaluations and is 0.015–0.03 mm off.
* EGM2008 to degree 120: the field has power at periods down to ~50 s, which the step must
  resolve. Against a 2-s run, Gauss–Jackson is 0.002 mm off at 5 s, 0.04 mm at 7.5 s,
  0.5 mm at 10 s and 100 mm at 15 s. DOP853's error estimate does not see this content: at
  rtol 1e-13 it takes 22 000 evaluations and is 58 mm off after 30 h (capping its step at
  10 s fixes that at ~140 000 evaluations). Hence the default fixed step of 5 s
  (``DEFAULT_STEP_S``): about 22 000 force evaluations per 30-h arc, the budget of the force
  model (0.2 s of integrator overhead with 40 parameters; ~1 s per arc with the degree-120
  field and its gradient). Lower-degree fields allow longer steps.
* PEC and PECE give the same accuracy at 5 s; PEC needs half the evaluations and is stable
  for LEO steps up to ~60 s at q = 10 (PECE up to ~180 s), so PEC is the default.
* Force-model partials must be smooth: a finite-difference gradient with 1e-9 relative noise
  spoils Φ at the 1e-7..1e-6 level (see the tests).

DOP853 (scipy, adaptive, dense output) stays available as ``method="dop853"`` for
comparison; its error control then acts on the state only (the variational equations follow
the same steps).

Compiled path. When the force model has a compiled form
(:class:`leopod.dynamics.compiled.CompiledForceModel`: the forces of
:func:`leopod.dynamics.force_config.build_force_model`, drag following a reference orbit), the
Gauss–Jackson start-up and steps run in numba with one call of the compiled right-hand side per
evaluation (the same formulas, results equal to round-off); otherwise the forces are called
from Python. Counts per integration are logged (DEBUG).

Discontinuities. The right-hand side may jump at the forces' ``breakpoints_s`` (piecewise
constant parameters) and, with :func:`apply_pulses`, the velocity jumps at pulse epochs. Each
arc is therefore integrated in segments between consecutive breakpoints, restarting at each;
a segment's step is the largest ≤ ``step_s`` that divides it (at least q steps). On the
compiled path a pulse that falls on a node (past the start-up, more than q nodes from the
previous one) needs no restart (:func:`leopod.dynamics.gauss_jackson.gauss_jackson_compiled`):
the state jumps and the back values are those of the orbit after the pulse, which agrees with
a restart to 1e-7 m over 3 h (tests/dynamics/test_compiled.py) for ~45 fewer evaluations per
pulse. Without partials (the simulator's truth orbits, with 10-min stochastic accelerations)
a breakpoint on a node needs none either: the node is corrected with the forces of the side it
is reached from and the back values take the jump of the forces there (one more evaluation
instead of a start-up; as accurate as restarts against 1-s steps, same test file).

Arcs run in both directions from t0 (outputs may precede t0). The trajectory is
right-continuous in time: at a pulse epoch it holds the state after the pulse.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from itertools import pairwise

import numba
import numpy as np

from leopod.dynamics.compiled import CompiledForceModel, fill_acceleration
from leopod.dynamics.forces import ForceModel, PseudoStochasticPulses, extended_orbit
from leopod.dynamics.gauss_jackson import (
    _gauss_jackson_segment,
    _inside,
    gauss_jackson_compiled,
    segment_grid,
)
from leopod.frames.rtn import rtn_basis

__all__ = ["DEFAULT_ORDER", "DEFAULT_STEP_S", "Trajectory", "apply_pulses", "integrate",
           "pulse_partials", "sampled_trajectory"]

log = logging.getLogger(__name__)

#: Default Gauss–Jackson step [s]: resolves a degree-120 gravity field in LEO (module doc).
DEFAULT_STEP_S = 5.0
#: Default Gauss–Jackson order q (highest backward difference; q + 1 back values).
DEFAULT_ORDER = 10

_DOP853_RTOL = 1e-13             # default tolerances of method="dop853"
_DOP853_ATOL = 1e-9              # [m, m/s]
_N_STATE_COLUMNS = 7             # columns of y and Φ in the augmented matrix


# --------------------------------------------------------------------------------------------
# Right-hand side


class _Rhs:
    """Augmented acceleration ``F(t, Y)`` (3, C) of the 6×C matrix ``Y = [y | Φ | S]``."""

    def __init__(self, force_model: ForceModel, params: np.ndarray, with_partials: bool):
        self.force_model = force_model
        self.params = params
        self.n_columns = 1 + (6 + force_model.n_params) * with_partials
        self.n_evaluations = 0

    def __call__(self, t_s: float, y: np.ndarray, out: np.ndarray) -> None:
        acc, da_dr, da_dv, da_dp = self.force_model.evaluate(t_s, y[:3, 0].copy(),
                                                             y[3:, 0].copy(), self.params)
        self.n_evaluations += 1
        fill_acceleration(np.asarray(acc, dtype=float), np.asarray(da_dr, dtype=float),
                           np.asarray(da_dv, dtype=float), np.asarray(da_dp, dtype=float),
                           y, out)


# --------------------------------------------------------------------------------------------
# Segments


@dataclass
class _DenseSegment:
    """DOP853 solution of one segment (scipy dense output)."""

    t_start: float
    t_end: float
    sol: object
    y_end: np.ndarray

    def evaluate(self, t_s: np.ndarray) -> np.ndarray:
        return self.sol(t_s).T.reshape(t_s.size, 6, -1)


@dataclass
class _PointSegment:
    """State after a pulse at the last epoch of a forward arc."""

    t_start: float
    t_end: float
    y_end: np.ndarray

    def evaluate(self, t_s: np.ndarray) -> np.ndarray:
        return np.broadcast_to(self.y_end, (t_s.size,) + self.y_end.shape).copy()


def _dop853_segment(rhs: _Rhs, t_start: float, t_end: float, y0: np.ndarray, rtol: float,
                    atol: float) -> _DenseSegment:
    """Integrate one smooth segment with scipy's DOP853, error control on the state only.

    scipy's error norm is the RMS over all 6 C components and its rtol is one number. The
    partials get an infinite tolerance, and the state's tolerance ``atol + rtol |r0|`` for
    positions (``|v0|`` for velocities; constant enough for near-circular orbits) divided by
    sqrt(C) is passed as atol with scipy's smallest rtol, so that the steps are those of a
    state-only integration.
    """
    from scipy.integrate import solve_ivp  # comparison only: spares every job its import

    n_col = y0.shape[1]
    shape = (6, n_col)
    work = np.empty((3, n_col))

    def fun(t, yflat):
        y = yflat.reshape(shape)
        rhs(float(_inside(np.array([t]), t_start, t_end)[0]), y, work)
        return np.concatenate([y[3:], work]).ravel()

    atol_vec = np.full(shape, 1e300)
    atol_vec[:3, 0] = atol + rtol * np.linalg.norm(y0[:3, 0])
    atol_vec[3:, 0] = atol + rtol * np.linalg.norm(y0[3:, 0])
    atol_vec[:, 0] /= np.sqrt(n_col)
    sol = solve_ivp(fun, (t_start, t_end), y0.ravel(), method="DOP853", dense_output=True,
                    rtol=100 * np.finfo(float).eps, atol=atol_vec.ravel())
    if not sol.success:
        raise RuntimeError(f"DOP853 failed between {t_start} and {t_end} s: {sol.message}")
    return _DenseSegment(t_start, t_end, sol.sol, sol.y[:, -1].reshape(shape))


# --------------------------------------------------------------------------------------------
# Arcs and trajectory


@dataclass
class _Arc:
    """Consecutive segments from t0 in one direction (+1 forward, −1 backward)."""

    direction: int
    segments: list = field(default_factory=list)

    def evaluate(self, t_s: np.ndarray) -> np.ndarray:
        if self.direction > 0:
            starts = np.array([s.t_start for s in self.segments])
            k = np.searchsorted(starts, t_s, side="right") - 1
        else:
            ends = np.array([s.t_end for s in self.segments])
            k = np.searchsorted(-ends, -t_s, side="left")
        k = np.clip(k, 0, len(self.segments) - 1)
        out = None
        for i in np.unique(k):
            sel = k == i
            part = self.segments[i].evaluate(t_s[sel])
            if out is None:
                out = np.empty((t_s.size,) + part.shape[1:])
            out[sel] = part
        return out


@dataclass(eq=False)
class Trajectory:
    """Integrated orbit with its partials at output epochs, and a dense interpolant.

    Attributes
    ----------
    t_s : ndarray, shape (m,)
        Output epochs [TT s since the reference epoch].
    states : ndarray, shape (m, 6)
        GCRF position [m] and velocity [m/s].
    stm : ndarray, shape (m, 6, 6) or None
        State transition matrix ``Φ(t, t0) = ∂y(t)/∂y(t0)`` (None without partials).
    sensitivity : ndarray, shape (m, 6, P) or None
        ``S(t) = ∂y(t)/∂p`` in the order of ``parameters`` (None without partials).
    t0_s : float
        Epoch of the initial state [TT s].
    parameters : list of str
        Names of the dynamic parameters (columns of ``sensitivity``).
    n_evaluations : int
        Force-model evaluations spent by the integration.
    """

    t_s: np.ndarray
    states: np.ndarray
    stm: np.ndarray | None
    sensitivity: np.ndarray | None
    t0_s: float
    parameters: list[str]
    n_evaluations: int
    _y0: np.ndarray = field(repr=False)
    _arcs: list[_Arc] = field(repr=False)

    @property
    def span_s(self) -> tuple[float, float]:
        """Time interval covered by the dense interpolant [TT s]."""
        ends = [s.t_end for arc in self._arcs for s in arc.segments]
        return min([self.t0_s] + ends), max([self.t0_s] + ends)

    def positions(self, t_s) -> np.ndarray:
        """GCRF positions (m, 3) [m] at epochs ``t_s``, continued beyond :attr:`span_s` by
        :func:`leopod.dynamics.forces.extended_orbit`: the orbit as a reference for
        :meth:`leopod.dynamics.forces.ForceModel.follow`."""
        lo, hi = self.span_s
        ends = self.at([lo, hi]).states
        return extended_orbit(lambda t: self.at(t).states[:, :3], lo, hi, ends[0],
                              ends[1])(t_s)

    def at(self, t_s) -> Trajectory:
        """The trajectory interpolated at other epochs inside :attr:`span_s`.

        Parameters
        ----------
        t_s : array_like, shape (m,)
            Epochs [TT s since the reference epoch].

        Returns
        -------
        Trajectory
            Same arcs, outputs at ``t_s`` (interpolation error well below the integration
            error: same order as the integrator, from the nearest node).
        """
        t = np.atleast_1d(np.asarray(t_s, dtype=float))
        lo, hi = self.span_s
        if t.size and (t.min() < lo or t.max() > hi):
            raise ValueError(f"epochs outside the integrated span [{lo}, {hi}] s")
        y = np.empty((t.size,) + self._y0.shape)
        y[t == self.t0_s] = self._y0
        for arc in self._arcs:
            sel = (t - self.t0_s) * arc.direction > 0
            if sel.any():
                y[sel] = arc.evaluate(t[sel])
        return _trajectory_from(t, y, self.t0_s, self.parameters, self.n_evaluations,
                                self._y0, self._arcs)


    @property
    def augmented(self) -> np.ndarray:
        """``[y | Φ | S]`` at the output epochs, shape (m, 6, 1 + 6 + P) (partials needed):
        what :func:`sampled_trajectory` takes back."""
        if self.stm is None:
            raise ValueError("a trajectory without partials has no augmented matrices")
        return np.concatenate([self.states[:, :, None], self.stm, self.sensitivity], axis=2)

    @property
    def initial(self) -> np.ndarray:
        """``[y | Φ | S]`` at t0, shape (6, C)."""
        return self._y0


@dataclass
class _SampledSegment:
    """Augmented matrices known at listed epochs only (:func:`sampled_trajectory`)."""

    t_start: float
    t_end: float
    t_s: np.ndarray
    y: np.ndarray

    def evaluate(self, t_s: np.ndarray) -> np.ndarray:
        i = np.clip(np.searchsorted(self.t_s, t_s), 0, self.t_s.size - 1)
        missing = self.t_s[i] != t_s
        if missing.any():
            raise ValueError(f"a sampled trajectory is known at its epochs only, not at "
                             f"{t_s[missing][:3]} s ({int(missing.sum())} epochs)")
        return self.y[i].copy()


def sampled_trajectory(t_s, augmented, t0_s: float, parameters, initial) -> Trajectory:
    """A trajectory known at given epochs only, e.g. an integration stored in a file.

    Its :meth:`Trajectory.at` returns the stored values at any of the epochs ``t_s`` (same
    bits) and refuses other epochs with a ``ValueError``: it serves computations that ask
    for exactly the epochs it was sampled at (the fixed POD at those of the float POD,
    :mod:`leopod.estimation.linearisation`).

    Parameters
    ----------
    t_s : array_like, shape (m,)
        Epochs [TT s since the reference epoch], increasing.
    augmented : array_like, shape (m, 6, C)
        ``[y | Φ | S]`` at ``t_s`` (:attr:`Trajectory.augmented`).
    t0_s : float
        Epoch of the initial state [TT s].
    parameters : list of str
        Names of the ``C − 7`` sensitivity columns.
    initial : array_like, shape (6, C)
        ``[y | Φ | S]`` at t0 (:attr:`Trajectory.initial`).
    """
    t = np.asarray(t_s, dtype=float)
    y = np.asarray(augmented, dtype=float)
    if t.ndim != 1 or np.any(np.diff(t) <= 0):
        raise ValueError("sampled trajectory: epochs must increase")
    if y.shape[:2] != (t.size, 6) or y.shape[2] != _N_STATE_COLUMNS + len(parameters):
        raise ValueError(f"sampled trajectory: augmented matrices of shape {y.shape} do not "
                         f"fit {t.size} epochs and {len(parameters)} parameters")
    arcs = []
    for direction in (1, -1):
        sel = (t - t0_s) * direction > 0
        if sel.any():
            ends = (float(t0_s), float(t[sel][-1] if direction > 0 else t[sel][0]))
            arcs.append(_Arc(direction, [_SampledSegment(*ends, t[sel], y[sel])]))
    return _trajectory_from(np.empty(0), np.empty((0,) + y.shape[1:]), t0_s, parameters, 0,
                            np.asarray(initial, dtype=float), arcs).at(t)


def _trajectory_from(t, y, t0_s, parameters, n_evaluations, y0, arcs) -> Trajectory:
    """Split augmented matrices (m, 6, C) into states, STM and sensitivity."""
    partials = y.shape[2] > 1
    return Trajectory(t_s=t, states=y[:, :, 0].copy(),
                      stm=y[:, :, 1:_N_STATE_COLUMNS].copy() if partials else None,
                      sensitivity=y[:, :, _N_STATE_COLUMNS:].copy() if partials else None,
                      t0_s=float(t0_s), parameters=list(parameters),
                      n_evaluations=n_evaluations, _y0=y0, _arcs=arcs)


def _velocity_jump(y: np.ndarray, dv_rtn_m_s: np.ndarray, direction: int) -> np.ndarray:
    """Augmented matrix after a pulse crossed in ``direction`` (partials left unchanged)."""
    out = y.copy()
    out[3:, 0] += direction * rtn_basis(y[:3, 0], y[3:, 0]) @ dv_rtn_m_s
    return out


_PULSE_ON_NODE = 1e-7          # a pulse or breakpoint this close to a node [steps] is on it


def _compiled_pieces(compiled: CompiledForceModel, params, a: float, b: float, y0, jumps,
                     breaks, step_s: float, order: int, pece: bool, direction: int):
    """Segments from a to b with the compiled force model; the pulses and force breakpoints
    strictly inside that fall on nodes past the start-up, more than q nodes apart, are crossed
    without restart (:func:`leopod.dynamics.gauss_jackson.gauss_jackson_compiled`); the
    others split it."""
    compiled.env.check(a)
    compiled.env.check(b)

    def inside(times):
        return {t for t in times if (t - a) * direction > 0 and (b - t) * direction > 0}

    pulses, forces = inside(jumps), inside(breaks)
    events = sorted(pulses | forces, key=lambda t: t * direction)
    n_steps, h = segment_grid(a, b, step_s, order)
    node = np.array([(t - a) / h for t in events])
    index = np.rint(node).astype(int)
    bad = ((np.abs(node - index) > _PULSE_ON_NODE) | (index <= order) | (index >= n_steps)
           | (np.diff(index, prepend=0) <= order)
           | np.array([t in pulses and t in forces for t in events], dtype=bool))
    if not bad.any():
        is_pulse = np.array([t in pulses for t in events], dtype=bool)
        dv = np.array([jumps[t] for t in events if t in pulses]).reshape(-1, 3)
        segment, n_eval = gauss_jackson_compiled(compiled, params, a, b, y0, step_s, order,
                                                 pece, index[is_pulse], dv, direction,
                                                 break_node=index[~is_pulse])
        return [segment], n_eval
    t_split = events[int(np.argmax(bad))]
    left, n_left = _compiled_pieces(compiled, params, a, t_split, y0, jumps, breaks, step_s,
                                    order, pece, direction)
    y = left[-1].y_end
    if t_split in pulses:
        y = _velocity_jump(y, jumps[t_split], direction)
    right, n_right = _compiled_pieces(compiled, params, t_split, b, y, jumps, breaks, step_s,
                                      order, pece, direction)
    return left + right, n_left + n_right


def _integrate(force_model: ForceModel, t0_s: float, state0, params, t_out_s,
               jumps: dict[float, np.ndarray], *, step_s: float = DEFAULT_STEP_S,
               order: int = DEFAULT_ORDER, pece: bool = False, method: str = "gauss-jackson",
               rtol: float = _DOP853_RTOL, atol: float = _DOP853_ATOL,
               with_partials: bool = True) -> Trajectory:
    """Arcs from t0 to the extreme output epochs, in segments between breakpoints/jumps."""
    state0 = np.asarray(state0, dtype=float)
    params = np.asarray(params, dtype=float)
    t_out = np.atleast_1d(np.asarray(t_out_s, dtype=float))
    if state0.shape != (6,):
        raise ValueError(f"state0 must have shape (6,), not {state0.shape}")
    if params.shape != (force_model.n_params,):
        raise ValueError(f"params must have shape ({force_model.n_params},) for the force "
                         f"model parameters, not {params.shape}")
    if not np.all(np.isfinite(t_out)):
        raise ValueError("output epochs must be finite")
    if method not in ("gauss-jackson", "dop853"):
        raise ValueError(f"unknown method {method!r} (gauss-jackson or dop853)")
    if method == "gauss-jackson" and (step_s <= 0 or not 2 <= order <= 16):
        raise ValueError(f"need step_s > 0 and 2 <= order <= 16 (got {step_s}, {order})")
    rhs = _Rhs(force_model, params, with_partials)
    compiled = CompiledForceModel.of(force_model) if method == "gauss-jackson" else None
    y0 = np.zeros((6, rhs.n_columns))
    y0[:, 0] = state0
    if with_partials:
        y0[:, 1:_N_STATE_COLUMNS] = np.eye(6)
    # the compiled path crosses pulses on nodes without splitting the arc, and breakpoints
    # too when there are no partials (the parameter partials, zero before their interval, are
    # 3e-6 relative less accurate without the restart: tests/dynamics/test_compiled.py)
    crossed = compiled is not None and not with_partials
    breaks = np.union1d([] if crossed else force_model.breakpoints_s,
                        [] if compiled else list(jumps))
    force_breaks = [float(t) for t in force_model.breakpoints_s] if crossed else []
    n_compiled = 0
    arcs = []
    for direction, t_end in ((1, t_out.max(initial=t0_s)), (-1, t_out.min(initial=t0_s))):
        if t_end == t0_s:
            continue
        inner = breaks[(breaks - t0_s) * direction > 0]
        inner = inner[(t_end - inner) * direction > 0][::direction]
        edges = np.concatenate([[t0_s], inner, [t_end]])
        arc = _Arc(direction)
        y = y0
        for a, b in pairwise(edges):
            if a in jumps:
                y = _velocity_jump(y, jumps[a], direction)
            if compiled is not None:
                pieces, n_eval = _compiled_pieces(compiled, params, a, b, y, jumps,
                                                  force_breaks, step_s, order, pece, direction)
                arc.segments.extend(pieces)
                n_compiled += n_eval
                y = pieces[-1].y_end
                continue
            if method == "gauss-jackson":
                seg = _gauss_jackson_segment(rhs, a, b, y, step_s, order, pece)
            else:
                seg = _dop853_segment(rhs, a, b, y, rtol, atol)
            arc.segments.append(seg)
            y = seg.y_end
        if direction > 0 and t_end in jumps:          # right-continuous at a final pulse
            y = _velocity_jump(y, jumps[t_end], direction)
            arc.segments.append(_PointSegment(t_end, t_end, y))
        arcs.append(arc)
    n_evaluations = rhs.n_evaluations + n_compiled
    log.debug("integrated %d arc(s), %d segment(s), %d force evaluations (%s)", len(arcs),
              sum(len(a.segments) for a in arcs), n_evaluations,
              "compiled" if compiled else "Python")
    shell = _trajectory_from(np.empty(0), np.empty((0,) + y0.shape), t0_s,
                             force_model.parameters, n_evaluations, y0, arcs)
    return shell.at(t_out)


def integrate(force_model: ForceModel, t0_s: float, state0, params, t_out_s, *,
              step_s: float = DEFAULT_STEP_S, order: int = DEFAULT_ORDER, pece: bool = False,
              method: str = "gauss-jackson", rtol: float = _DOP853_RTOL,
              atol: float = _DOP853_ATOL, with_partials: bool = True) -> Trajectory:
    """Integrate the orbit and its variational equations from t0 to the output epochs.

    Parameters
    ----------
    force_model : ForceModel
        Forces (GCRF; time in TT seconds since their reference epoch).
    t0_s : float
        Epoch of the initial state [TT s].
    state0 : array_like, shape (6,)
        Initial GCRF position [m] and velocity [m/s].
    params : array_like, shape (P,)
        Dynamic parameters in the order of ``force_model.parameters``.
    t_out_s : array_like, shape (m,)
        Output epochs [TT s], any order, before and/or after t0 (arcs of 30 h and more).
    step_s : float, optional
        Gauss–Jackson step [s] (default 5 s, for LEO with a degree-120 field; see module doc).
    order : int, optional
        Gauss–Jackson order q (default 10).
    pece : bool, optional
        Re-evaluate the force at the corrected state (PECE, 2 evaluations per step) instead
        of PEC (default).
    method : {"gauss-jackson", "dop853"}, optional
        Integrator; "dop853" is scipy's adaptive Runge–Kutta (for comparison).
    rtol, atol : float, optional
        DOP853 only: relative and absolute [m, m/s] tolerances on the state.
    with_partials : bool, optional
        Integrate the variational equations (default). The force model computes its
        partials either way.

    Returns
    -------
    Trajectory
        States, Φ(t, t0) and S(t) at ``t_out_s``, with a dense interpolant (:meth:`Trajectory.at`).
    """
    return _integrate(force_model, t0_s, state0, params, t_out_s, {}, step_s=step_s,
                      order=order, pece=pece, method=method, rtol=rtol, atol=atol,
                      with_partials=with_partials)


def _pulse_epochs(pulse_epochs_s) -> np.ndarray:
    if isinstance(pulse_epochs_s, PseudoStochasticPulses):
        return pulse_epochs_s.epochs_s
    return np.atleast_1d(np.asarray(pulse_epochs_s, dtype=float))


def apply_pulses(force_model: ForceModel, t0_s: float, state0, params, t_out_s,
                 pulse_epochs_s, dv_rtn_m_s, **options) -> Trajectory:
    """Integrate with actual velocity pulses (simulation): restart with ``v += M Δv``.

    At a pulse epoch ``t_i`` after t0 the velocity jumps by ``M(t_i) Δv_i`` (M: RTN axes,
    :func:`leopod.frames.rtn.rtn_basis`, of the state reaching ``t_i``); for ``t_i``
    before t0 the backward integration applies ``−M Δv_i``, so that in both cases
    ``v(t_i+) − v(t_i−) = M Δv_i``. Φ and S are carried through a pulse unchanged (the
    dependence of the RTN axes on the state is neglected: relative effect ~|Δv|/|v|).

    Parameters
    ----------
    force_model, t0_s, state0, params, t_out_s
        As :func:`integrate`.
    pulse_epochs_s : array_like, shape (n,), or PseudoStochasticPulses
        Pulse epochs [TT s]; none may equal t0.
    dv_rtn_m_s : array_like, shape (n, 3)
        Velocity changes in R, T, N [m/s].
    **options
        Keyword options of :func:`integrate`.

    Returns
    -------
    Trajectory
    """
    epochs = _pulse_epochs(pulse_epochs_s)
    dv = np.asarray(dv_rtn_m_s, dtype=float)
    if dv.shape != (epochs.size, 3):
        raise ValueError(f"dv_rtn_m_s must have shape ({epochs.size}, 3), not {dv.shape}")
    if np.any(epochs == t0_s):
        raise ValueError("a pulse at t0 is indistinguishable from the initial velocity")
    return _integrate(force_model, t0_s, state0, params, t_out_s,
                      dict(zip(epochs.tolist(), dv, strict=True)), **options)


@numba.njit(cache=True)
def _pulse_columns(t_s, stm, epochs_s, t0_s, back, out):  # pragma: no cover - numba
    """``out[j, :, 3i:3i+3] = ±Φ(t_j, t0)[:r] back_i`` where pulse i acts at ``t_j`` (else
    kept 0), ``r = out.shape[1]`` leading rows of the state.

    A pulse after t0 acts at ``t ≥ t_i`` (+), one before t0 at ``t < t_i`` (−).
    """
    for j in range(t_s.size):
        for i in range(epochs_s.size):
            if epochs_s[i] > t0_s:
                if t_s[j] < epochs_s[i]:
                    continue
                sign = 1.0
            else:
                if t_s[j] >= epochs_s[i]:
                    continue
                sign = -1.0
            for a in range(out.shape[1]):
                for c in range(3):
                    acc = 0.0
                    for b in range(6):
                        acc += stm[j, a, b] * back[i, b, c]
                    out[j, a, 3 * i + c] = sign * acc


def pulse_partials(trajectory: Trajectory, pulse_epochs_s, t_out_s=None, *,
                   position_only: bool = False) -> np.ndarray:
    """Partials of the state w.r.t. velocity pulses in R, T, N, from the STM alone.

    A pulse ``Δv_i`` at ``t_i`` (Jäggi et al. 2006, J. Geod. 80:47–60; Wang et al. 2024, sec. 2.1,
    eq. 1–3) changes the state after it by ``Φ(t, t_i) [0; M(t_i)] Δv_i`` with
    ``Φ(t, t_i) = Φ(t, t0) Φ(t_i, t0)⁻¹`` (Montenbruck & Gill 2000, sec. 7.2): no
    re-integration. For ``t_i > t0`` this applies to ``t ≥ t_i`` (zero before); for a pulse
    before t0 (backward arc) the state at t0 is held fixed, so it is
    ``−Φ(t, t_i) [0; M(t_i)]`` for ``t < t_i`` (zero after), consistent with
    :func:`apply_pulses`. ``M(t_i)`` are the RTN axes of the trajectory at ``t_i``. Only the
    non-zero blocks are computed (compiled loop over epochs and pulses).

    Parameters
    ----------
    trajectory : Trajectory
        Integrated with partials; its span must contain the pulse epochs.
    pulse_epochs_s : array_like, shape (n,), or PseudoStochasticPulses
        Pulse epochs [TT s]; none may equal t0.
    t_out_s : array_like, shape (m,), optional
        Epochs [TT s] (default: ``trajectory.t_s``).
    position_only : bool, optional
        Return the position rows only (``∂r(t)/∂Δv``, shape (m, 3, 3 n)).

    Returns
    -------
    ndarray, shape (m, 6, 3 n)
        ``∂y(t)/∂Δv`` [s; 1], columns ordered pulse by pulse as R, T, N
        (:attr:`PseudoStochasticPulses.parameters`).
    """
    if trajectory.stm is None:
        raise ValueError("pulse partials need a trajectory integrated with partials")
    epochs = _pulse_epochs(pulse_epochs_s)
    if np.any(epochs == trajectory.t0_s):
        raise ValueError("a pulse at t0 is indistinguishable from the initial velocity")
    out_traj = trajectory if t_out_s is None else trajectory.at(t_out_s)
    at_pulse = trajectory.at(epochs)
    rhs = np.zeros((epochs.size, 6, 3))
    for i, state in enumerate(at_pulse.states):
        rhs[i, 3:] = rtn_basis(state[:3], state[3:])
    # Φ(t_i, t0)⁻¹ [0; M]  (n, 6, 3)
    back = np.linalg.solve(at_pulse.stm, rhs)
    partials = np.zeros((out_traj.t_s.size, 3 if position_only else 6, 3 * epochs.size))
    _pulse_columns(out_traj.t_s, np.ascontiguousarray(out_traj.stm), epochs,
                   float(trajectory.t0_s), back, partials)
    return partials

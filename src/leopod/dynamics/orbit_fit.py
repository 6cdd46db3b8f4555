"""Dynamic orbit fit: batch least squares of an integrated orbit to tabulated positions.

The unknowns are the GCRF state at the first epoch and the estimated parameters of the force
model (:mod:`leopod.dynamics.force_config`: drag scale factors, empirical accelerations, ...);
the observations are positions (e.g. a reference orbit in the ITRF, rotated to the GCRF with
the IERS 2010 transformation and EOP). Gauss–Newton iteration (Montenbruck & Gill 2000,
sec. 8.1-8.2): with the residuals ``Δz = z − r(x)`` and the design matrix
``H = ∂r/∂x = [Φ_rr Φ_rv | S_r]`` from the variational equations
(:func:`leopod.dynamics.integrator.integrate`), the correction minimises
``|W^½ (Δz − H Δx)|² + |C (x_apriori − x − Δx)|²`` (C = diag(1/σ_apriori) for constrained
parameters), solved by a QR decomposition of the column-scaled stacked system; the
covariance is ``(HᵀWH + CᵀC)⁻¹`` (W = I/σ_obs²). Iterations stop when every correction is
below ``tolerance`` times its formal standard deviation; the residuals, covariance and RMS
reported are those of the final parameters (one integration after the last correction).

Residuals are given in the RTN frame of the fitted orbit (radial, along-track, cross-track;
:func:`leopod.frames.rtn.rtn_matrix`).

A fit that only starts a finer estimation (the float POD from code-only positions) can use
a cheaper force model, :func:`starting_forces`.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from leopod.dynamics.environment import ArcEnvironment
from leopod.dynamics.force_config import ForceModelSettings, build_force_model
from leopod.dynamics.forces import (
    ForceModel,
    apriori_parameters,
    constraint_sigmas,
    estimated_parameters,
    tabulated_orbit,
)
from leopod.dynamics.integrator import DEFAULT_STEP_S, Trajectory, integrate
from leopod.frames.earth_rotation import itrf_to_gcrf
from leopod.frames.rtn import rtn_matrix
from leopod.io.manoeuvre import Manoeuvre
from leopod.time.calendar import seconds_since
from leopod.time.eop import EarthOrientation

__all__ = ["STATE_NAMES", "FitResult", "fit_orbit", "initial_state", "starting_forces",
           "starting_step_s"]

log = logging.getLogger(__name__)

#: Names of the six initial-state parameters (GCRF position [m], velocity [m/s]).
STATE_NAMES = ("x0_m", "y0_m", "z0_m", "vx0_m_s", "vy0_m_s", "vz0_m_s")
_VELOCITY_FIT_POINTS = 9      # epochs of the polynomial giving an initial velocity
_VELOCITY_FIT_DEGREE = 6
_DEFAULT_STEP_DEGREE = 120    # the field degree that DEFAULT_STEP_S resolves
_MAX_STARTING_STEP_S = 20.0   # Gauss-Jackson PEC step of a starting fit at most [s]


@dataclass(eq=False)
class FitResult:
    """Result of :func:`fit_orbit`.

    Attributes
    ----------
    times : ndarray of datetime64[ns], shape (n,)
        Epochs of the observations used (GPS time).
    t_ref : datetime64
        Reference epoch of the force model (times are TT = GPS seconds since it).
    t_s : ndarray, shape (n,)
        Observation epochs [s since ``t_ref``]; ``t_s[0]`` is the epoch of the initial state.
    parameter_names : list of str
        Estimated parameters: :data:`STATE_NAMES`, then the estimated force parameters.
    estimates, sigmas : ndarray, shape (k,)
        Estimated values and formal standard deviations (from ``sigma_obs_m``).
    covariance : ndarray, shape (k, k)
        Formal covariance.
    sigma0 : float
        A posteriori standard deviation of unit weight (multiply ``sigmas`` by it for
        residual-scaled sigmas).
    state0_gcrf : ndarray, shape (6,)
        Fitted GCRF position [m] and velocity [m/s] at ``t_ref`` (propagated back when the
        first valid observation is later; ``estimates`` refer to the first valid epoch).
    force_parameters : ndarray, shape (P,)
        All force-model parameters (estimated and fixed), order of ``force_model.parameters``.
    force_model : ForceModel
    trajectory : Trajectory
        Fitted orbit at ``t_s`` (GCRF) with its partials.
    residuals_rtn_m : ndarray, shape (n, 3)
        Observed minus fitted positions in R, T, N [m].
    iterations : int
        Gauss–Newton corrections applied.
    converged : bool
    integrations : int
        Orbit integrations (with the variational equations).
    force_evaluations : int
        Force-model evaluations of these integrations.
    """

    times: np.ndarray
    t_ref: np.datetime64
    t_s: np.ndarray
    parameter_names: list[str]
    estimates: np.ndarray
    sigmas: np.ndarray
    covariance: np.ndarray
    sigma0: float
    state0_gcrf: np.ndarray
    force_parameters: np.ndarray
    force_model: ForceModel = field(repr=False)
    trajectory: Trajectory = field(repr=False)
    residuals_rtn_m: np.ndarray = field(repr=False)
    iterations: int = 0
    converged: bool = False
    integrations: int = 0
    force_evaluations: int = 0

    @property
    def rms_rtn_m(self) -> np.ndarray:
        """RMS of the residuals in R, T, N [m], shape (3,)."""
        return np.sqrt(np.mean(self.residuals_rtn_m**2, axis=0))

    @property
    def rms_3d_m(self) -> float:
        """3D RMS of the residuals, ``sqrt(mean(|Δr|²))`` [m]."""
        return float(np.sqrt(np.mean(np.sum(self.residuals_rtn_m**2, axis=1))))

    def estimate(self, name: str) -> tuple[float, float]:
        """Estimated value and formal sigma of one parameter."""
        i = self.parameter_names.index(name)
        return float(self.estimates[i]), float(self.sigmas[i])


def initial_state(t_s: np.ndarray, pos_m: np.ndarray) -> np.ndarray:
    """State at ``t_s[0]`` from positions: velocity of a polynomial fitted to the first epochs.

    Parameters
    ----------
    t_s : ndarray, shape (n,)
        Epochs [s], increasing, n >= 3.
    pos_m : ndarray, shape (n, 3)
        Inertial positions [m].

    Returns
    -------
    ndarray, shape (6,)
        Position [m] (the first one) and velocity [m/s] (polynomial of degree ≤ 6 over up to
        9 epochs; accurate to mm/s at 10-30 s sampling, enough to start the iteration).
    """
    k = min(_VELOCITY_FIT_POINTS, t_s.size)
    if k < 3:
        raise ValueError("need at least 3 epochs for an initial velocity")
    dt = t_s[:k] - t_s[0]
    scale = max(dt[-1], 1.0)
    coef = np.polynomial.polynomial.polyfit(dt / scale, pos_m[:k] - pos_m[0],
                                            min(_VELOCITY_FIT_DEGREE, k - 1))
    return np.concatenate([pos_m[0], coef[1] / scale])


def _solve(design: np.ndarray, misclosure: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Least-squares solution and covariance of ``design dx ≈ misclosure`` (weighted rows).

    Columns are scaled to unit norm before a QR decomposition (conditioning).
    """
    norms = np.linalg.norm(design, axis=0)
    if np.any(norms == 0.0):
        raise ValueError("a parameter has no influence on the observations (zero column)")
    q, r = np.linalg.qr(design / norms)
    dx = np.linalg.solve(r, q.T @ misclosure) / norms
    r_inv = np.linalg.solve(r, np.eye(r.shape[0]))
    cov = (r_inv @ r_inv.T) / np.outer(norms, norms)
    return dx, cov


def _observations(times, pos_m, vel_m_s, frame: str, eop):
    """Valid epochs, GCRF positions and (optional) velocities."""
    times = np.asarray(times, dtype="datetime64[ns]")
    pos = np.asarray(pos_m, dtype=float)
    if pos.shape != (times.size, 3):
        raise ValueError(f"pos_m must have shape ({times.size}, 3), not {pos.shape}")
    valid = np.isfinite(pos).all(axis=1)
    if np.any(np.diff(times[valid]) <= np.timedelta64(0, "ns")):
        raise ValueError("observation epochs must be strictly increasing")
    vel = None if vel_m_s is None else np.asarray(vel_m_s, dtype=float)[valid]
    times, pos = times[valid], pos[valid]
    if frame == "itrf":
        pos, vel = itrf_to_gcrf(times, pos, vel, eop=eop)
    elif frame != "gcrf":
        raise ValueError(f"frame must be 'itrf' or 'gcrf', not {frame!r}")
    return times, pos, vel


def fit_orbit(times, pos_m, force_settings: ForceModelSettings, *, frame: str = "itrf",
              vel_m_s=None, state0_gcrf=None, t_ref=None, sigma_obs_m: float = 0.01,
              max_iterations: int = 10, tolerance: float = 0.01,
              eop: EarthOrientation | None = None, step_s: float = DEFAULT_STEP_S,
              environment: ArcEnvironment | None = None,
              manoeuvres: Sequence[Manoeuvre] = (), attitude=None) -> FitResult:
    """Fit a dynamic orbit to positions by batch least squares (module docstring).

    Parameters
    ----------
    times : array_like of datetime64, shape (n,)
        Observation epochs (GPS time), strictly increasing; the first valid one is the
        epoch of the estimated initial state.
    pos_m : array_like, shape (n, 3)
        Observed positions [m] in ``frame`` (rows with NaN are skipped).
    force_settings : ForceModelSettings
        Force model settings for :func:`leopod.dynamics.force_config.build_force_model`
        (arc = ``t_ref`` or the first valid epoch, whichever is earlier, to the last).
    frame : {"itrf", "gcrf"}
        Frame of ``pos_m`` (and ``vel_m_s``).
    vel_m_s : array_like, shape (n, 3), optional
        Observed velocities [m/s] (only the first is used, for the a priori state).
    state0_gcrf : array_like, shape (6,), optional
        A priori initial state (default: from ``vel_m_s`` or :func:`initial_state`).
    t_ref : datetime64, optional
        Reference epoch of the force model (default: the first epoch).
    sigma_obs_m : float
        Standard deviation of each position coordinate [m] (default 0.01).
    max_iterations : int
        Maximum number of Gauss–Newton corrections.
    tolerance : float
        Convergence: every correction below ``tolerance`` times its formal sigma.
    eop : EarthOrientation, optional
        EOP for ITRF -> GCRF and the force model (default: installed IERS data).
    step_s : float
        Integration step [s].
    environment : ArcEnvironment, optional
        Grids of Earth rotation, Sun and Moon to share (covering the fitted arc and t_ref).
    manoeuvres : sequence of Manoeuvre, optional
        Burns of the satellite, modelled with ``force_settings.manoeuvre``
        (:func:`leopod.dynamics.force_config.build_force_model`).
    attitude : leopod.frames.leo_attitude.LeoAttitude, optional
        Attitude law of the plate forces (``force_settings.macro_model``; None: nominal).

    Returns
    -------
    FitResult
    """
    times, pos, vel = _observations(times, pos_m, vel_m_s, frame, eop)
    if times.size < 3:
        raise ValueError("need at least 3 valid observation epochs")
    t_ref = times[0] if t_ref is None else np.datetime64(t_ref, "ns")
    t_s = seconds_since(times, t_ref)
    # from t_ref on: the state is propagated back to it if the first epochs are missing
    force_model = build_force_model(force_settings, t_ref, min(0.0, t_s[0]), t_s[-1], eop=eop,
                                    environment=environment, manoeuvres=manoeuvres,
                                    attitude=attitude)
    if state0_gcrf is not None:
        state = np.asarray(state0_gcrf, dtype=float).copy()
    elif vel is not None and np.isfinite(vel[0]).all():
        state = np.concatenate([pos[0], vel[0]])
    else:
        state = initial_state(t_s, pos)
    params = apriori_parameters(force_model)
    apriori = params.copy()
    est = estimated_parameters(force_model)
    sigma_c = constraint_sigmas(force_model)[est]
    constrained = np.flatnonzero(np.isfinite(sigma_c))
    names = list(STATE_NAMES) + [p for p, e in zip(force_model.parameters, est) if e]
    k = len(names)
    converged = False
    iterations = 0
    integrations = evaluations = 0
    # forces tabulated along a reference orbit (drag) follow the observed positions, then
    # each iteration's orbit
    force_model.follow(tabulated_orbit(t_s, pos))
    while True:
        traj = integrate(force_model, t_s[0], state, params, t_s, step_s=step_s)
        force_model.follow(traj.positions)
        integrations += 1
        evaluations += traj.n_evaluations
        res = pos - traj.states[:, :3]
        design = np.concatenate([traj.stm[:, :3, :], traj.sensitivity[:, :3, est]], axis=2)
        rows = [design.reshape(-1, k) / sigma_obs_m]
        rhs = [res.ravel() / sigma_obs_m]
        if constrained.size:
            c = np.zeros((constrained.size, k))
            c[np.arange(constrained.size), 6 + constrained] = 1.0 / sigma_c[constrained]
            rows.append(c)
            rhs.append((apriori[est] - params[est])[constrained] / sigma_c[constrained])
        dx, cov = _solve(np.vstack(rows), np.concatenate(rhs))
        sigmas = np.sqrt(np.diag(cov))
        ratio = float(np.max(np.abs(dx) / sigmas))
        log.info("orbit fit iteration %d: 3D RMS %.4f m, max |correction|/sigma %.3g",
                 iterations, np.sqrt(np.mean(np.sum(res**2, axis=1))), ratio)
        if iterations and ratio < tolerance:
            converged = True
            break
        if iterations == max_iterations:
            log.warning("orbit fit: no convergence after %d iterations (max |dx|/sigma %.3g)",
                        iterations, ratio)
            break
        state += dx[:6]
        params[est] += dx[6:]
        iterations += 1
    dof = max(res.size + constrained.size - k, 1)
    sigma0 = float(np.sqrt(np.sum((res / sigma_obs_m) ** 2) / dof))
    state_ref = state
    if t_s[0] != 0.0:  # first valid epoch after t_ref: the state at t_ref, as documented
        back = integrate(force_model, t_s[0], state, params, np.array([0.0]), step_s=step_s)
        integrations += 1
        evaluations += back.n_evaluations
        state_ref = back.states[0]
    rtn = rtn_matrix(traj.states[:, :3], traj.states[:, 3:])
    return FitResult(times=times, t_ref=np.datetime64(t_ref, "ns"), t_s=t_s,
                     parameter_names=names, estimates=np.concatenate([state, params[est]]),
                     sigmas=sigmas, covariance=cov, sigma0=sigma0, state0_gcrf=state_ref,
                     force_parameters=params, force_model=force_model, trajectory=traj,
                     residuals_rtn_m=np.einsum("nij,nj->ni", rtn, res),
                     iterations=iterations, converged=converged, integrations=integrations,
                     force_evaluations=evaluations)


def starting_forces(settings: ForceModelSettings, max_degree: int) -> ForceModelSettings:
    """A cheaper force model for a fit that only starts a finer estimation.

    The gravity field (and its gradient) to at most ``max_degree``; one drag and one SRP
    scale factor for the whole arc (estimated or not as in ``settings``); no empirical
    accelerations (a-priori zero in an estimation that starts from nothing); the other
    forces as in ``settings``. Per integration, the gravity cost falls with the square of
    the degree and the variational equations carry at most 1 + 6 + 2 columns instead of
    1 + 6 + P.

    Parameters
    ----------
    settings : ForceModelSettings
        The force model of the estimation.
    max_degree : int
        Degree and order of the gravity field of the fit (lowered to that of ``settings``;
        not above the degree of the field file).

    Returns
    -------
    ForceModelSettings
    """
    gravity = settings.gravity
    if gravity is not None:
        degree = max_degree if gravity.max_degree is None else min(max_degree,
                                                                   gravity.max_degree)
        gradient = (None if gravity.gradient_degree is None
                    else min(gravity.gradient_degree, degree))
        gravity = replace(gravity, max_degree=degree, gradient_degree=gradient)
    return replace(settings, gravity=gravity,
                   drag=None if settings.drag is None else replace(settings.drag,
                                                                   interval_s=None),
                   srp=None if settings.srp is None else replace(settings.srp, interval_s=None),
                   empirical=None)


def starting_step_s(max_degree: int) -> float:
    """Integration step [s] of a fit with the gravity field to ``max_degree`` only.

    The shortest periods of a field along a LEO orbit scale as the orbital period over the
    degree, so the step that resolves degree 120 (:data:`DEFAULT_STEP_S`, integrator module
    docstring) grows in proportion, up to 20 s. Measured with :func:`starting_forces` of the
    default campaign to degree 30 over 30 h against a 2.5-s integration: 20 s is 0.02 mm
    off at 971 km and 0.6 mm at 450 km altitude (30 s: 0.7 mm and 45 mm), far below the
    metre-level positions such a fit starts from.
    """
    return min(DEFAULT_STEP_S * _DEFAULT_STEP_DEGREE / max_degree, _MAX_STARTING_STEP_S)

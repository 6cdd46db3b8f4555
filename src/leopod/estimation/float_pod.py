"""Float reduced-dynamic POD: iterated batch least squares on undifferenced IF code and phase.

Why one module of about 600 lines: the four dataclasses (settings, observations, start,
result) are the interface of the one solver below them (_Problem, float_pod) and are imported
with it by leopod.estimation.arc, .inputs, .outputs and leopod.ambiguity.resolve.

Unknowns (Peng et al. 2021; Wang et al. 2024; Jiang et al. 2023; Jäggi et al. 2006, J. Geod.
80:47-60): the GCRF initial state, the estimated force-model parameters (drag and SRP scale
factors, piecewise empirical accelerations, :mod:`leopod.dynamics.force_config`),
pseudo-stochastic velocity pulses in R, T, N at regular epochs with a-priori zero and a given
sigma, optionally the LEO antenna PCO Z-component, one float ionosphere-free ambiguity per
pass (a new pass at every detected slip,
:mod:`leopod.gnss.passes`), and one receiver clock per epoch, pre-eliminated from the normal
equations epoch by epoch (:mod:`leopod.estimation.normals`).

An iteration integrates the orbit with its variational equations and the current pulses
(:func:`leopod.dynamics.integrator.apply_pulses`), evaluates the observation model
(:mod:`leopod.estimation.obsmodel`) at the true reception times (nominal epoch minus the
receiver clock of the previous iteration), and solves for corrections. Outliers are screened
separately for code and phase once the orbit correction is below ``screen_below_m``:
observations whose normalised residual exceeds ``outlier_k`` times the robust (MAD) scale
of their type are rejected, repeatedly, and the system is solved again. Iterations stop
when the largest position correction over the arc is below ``tolerance_m``; the orbit of
the solution is then the last integrated one plus the corrections since through its partials
(:class:`leopod.estimation.orbit_correction.CorrectedOrbit`: a second-order error of
~|Δr|²/r, 1e-13 m for a correction below 1 mm), not a new integration. For the same
reason an iteration after a correction below :data:`_INTEGRATE_ABOVE_M` (|Δr|²/r below
4e-10 m) integrates nothing: it linearises at the last integration plus the corrections
since. That saves one of the usual three integrations of a day (the first correction is
metres to ~150 m, the second millimetres, the third the effect of the screening).

The ambiguity-fixed solution (:class:`FixedPod`) is one linearisation at the converged float
solution, solved once per set of ambiguity constraints.

Weights: ``σ(e) = σ0`` above ``weight_elevation_deg`` and ``σ0 / (2 sin e)`` below
(continuous at 30°), e the antenna-frame elevation (floored at 1°).

Several systems in one arc (``PodObservations.systems``, e.g. GPS L1/L2 and BDS-3 B1C/B2a,
Zhang et al. 2024, sec. 2; Jiang et al. 2023): each system has its own ionosphere-free pair
(and narrow-lane wavelength of the wind-up), the receiver clock of an epoch is common to all,
and the code of every system but the first carries an inter-system bias (ISB) ``isb_<X>``
[m], one per arc or per piece of ``isb_interval_s``: the difference of the receiver's
ionosphere-free code biases of system X and of the first system, which the clock absorbs
(the datum: ISB of the first system = 0). The receiver phase biases of each system go into
its ambiguities, which single differences within a system remove
(:mod:`leopod.ambiguity.pairs`). With ``vce`` the weights of each system and observation type
are scaled by variance components (:func:`leopod.estimation.vce.variance_components`,
Förstner 1979 as used by Bähr et al. 2007, cited for the combined solution of Zhang et al.
2024, Table 1), iterated at each linearisation once the screening has started.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np

from leopod.astro.sun import sun_position_ef
from leopod.constants import C_LIGHT_M_S, ERA_RATE_RAD_S
from leopod.dynamics.forces import (
    ForceModel,
    PseudoStochasticPulses,
    apriori_parameters,
    constraint_sigmas,
    estimated_parameters,
)
from leopod.dynamics.integrator import (
    Trajectory,
    apply_pulses,
    integrate,
    pulse_partials,
)
from leopod.dynamics.orbit_fit import STATE_NAMES
from leopod.estimation.normals import NormalEquations, Rows, accumulate, epoch_clocks, solve
from leopod.estimation.obsmodel import ModelResult, Pairs, compute_model
from leopod.estimation.orbit_correction import CorrectedOrbit, epoch_covariance
from leopod.estimation.vce import group_redundancy
from leopod.frames.earth_rotation import gcrf_from_itrf_matrices
from leopod.frames.leo_attitude import LeoAttitude
from leopod.gnss.products import GnssProducts
from leopod.settings import Settings
from leopod.time.calendar import seconds_since
from leopod.time.eop import EarthOrientation

__all__ = ["ArcNormals", "FixedPod", "PodObservations", "PodResult", "PodSettings", "PodStart",
           "constrain_differences", "elevation_sigma", "float_pod", "pulse_epochs",
           "robust_scale"]

log = logging.getLogger(__name__)

_MAD_TO_SIGMA = 1.4826
#: Weight [1/m²] of the zero-misclosure pseudo-observation of each ISB increment (σ = 10 km):
#: 1e-9 of the weight of one code observation of σ 0.3 m, so the solution of an observed piece
#: is unchanged (at convergence the increment is 0 either way).
_ISB_DAMPING_WEIGHT = 1.0e-8
_MIN_ELEVATION_FOR_WEIGHT_DEG = 1.0
#: Largest shift of the reception times [ns] over which the ITRF -> GCRF matrices are carried
#: by the Earth rotation angle alone (_ReceptionRotation).
_ROTATION_CARRY_NS = 1000
#: A correction of the orbit larger than this [m] is followed by a new integration; after a
#: smaller one the next iteration linearises at the corrected orbit (module docstring): its
#: second-order error |Δr|²/r is below 4e-10 m, its partials change by ~|Δr|/r < 1e-8.
_INTEGRATE_ABOVE_M = 0.05

#: Margin [s] by which an integration spans the reception epochs and the nominal epochs at
#: both ends, so that the orbit can be evaluated at the reception epochs of later clock
#: estimates without a new integration (the fixed POD at the float POD's final clocks,
#: leopod.estimation.linearisation): 1 ms, a clock change of 300 km.
_SPAN_MARGIN_S = 1e-3


@dataclass(frozen=True)
class PodSettings(Settings):
    """Tunables of the float POD (all configurable from the campaign file).

    Attributes
    ----------
    code_sigma_m, phase_sigma_m : float
        A-priori sigma of the undifferenced ionosphere-free code and phase at high
        elevation [m].
    weight_elevation_deg : float
        Elevation below which the sigma grows as ``1/(2 sin e)`` [deg].
    min_elevation_deg : float
        Antenna-frame elevation cut-off [deg].
    pulse_interval_s : float or None
        Spacing of the pseudo-stochastic pulses [s] (None: no pulses).
    pulse_sigma_m_s : tuple of 3 float
        A-priori sigma of the pulses in R, T, N [m/s].
    integrator_step_s : float
        Gauss–Jackson step of the orbit and its partials [s]
        (:data:`leopod.dynamics.integrator.DEFAULT_STEP_S` resolves a degree-120 field from
        ~400 km up; the field's short periods fade with height, so a higher orbit allows a
        longer step: schema description).
    estimate_pco_z : bool
        Estimate a correction to the LEO antenna PCO Z-component (all frequencies alike).
    outlier_k : float
        Rejection threshold in robust standard deviations.
    screen_below_m : float
        Screening starts once the largest position correction is below this [m].
    max_iterations : int
    tolerance_m : float
        Convergence: largest position correction over the arc [m].
    min_phase_obs : int
        Passes with fewer phase observations are dropped.
    gross_code_m : float
        Before the first solution, code observations deviating from the median misclosure
        of their epoch by more than this are rejected (gross errors in the data) [m].
    isb_interval_s : float or None
        Length of the pieces of the inter-system biases [s] (None: one per system and arc).
    vce : bool
        Estimate a variance factor per system and observation type (module docstring).
    vce_max_iterations : int
        Largest number of variance-component iterations at one linearisation.
    vce_tolerance : float
        The iterations stop when every estimated factor is within ``1 ± vce_tolerance``.
    """

    SCHEMA_DEF = "pod"

    code_sigma_m: float
    phase_sigma_m: float
    weight_elevation_deg: float
    min_elevation_deg: float
    pulse_interval_s: float | None
    pulse_sigma_m_s: tuple[float, float, float]
    integrator_step_s: float
    estimate_pco_z: bool
    outlier_k: float
    screen_below_m: float
    max_iterations: int
    tolerance_m: float
    min_phase_obs: int
    gross_code_m: float
    isb_interval_s: float | None
    vce: bool
    vce_max_iterations: int
    vce_tolerance: float


@dataclass
class PodObservations:
    """Ionosphere-free observations of an arc, flattened to (epoch, satellite) pairs.

    Attributes
    ----------
    times : ndarray of datetime64[ns], shape (m,)
        Nominal epochs (receiver time tags, GPS time).
    sv : ndarray of str, shape (s,)
        Satellite ids of the observation columns.
    epoch, sat : ndarray of int, shape (n,)
        Epoch and satellite index of each pair.
    code_m, phase_m : ndarray, shape (n,)
        IF code and phase [m] (NaN where not used).
    pass_index : ndarray of int, shape (n,)
        Ambiguity (pass) index of the phase, −1 where the phase is not used.
    clk_rx_m : ndarray, shape (m,)
        A-priori receiver clock [m] (e.g. from code-only positioning).
    nl_wavelength_m : float or ndarray, shape (s,)
        ``c/(f1+f2)`` of the phase pair (wind-up scale) [m]: one value, or one per satellite
        (several systems).
    systems : tuple of str
        GNSS letters of the arc, the reference of the inter-system biases first (empty: the
        systems of ``sv`` in order of appearance).
    """

    times: np.ndarray
    sv: np.ndarray
    epoch: np.ndarray
    sat: np.ndarray
    code_m: np.ndarray
    phase_m: np.ndarray
    pass_index: np.ndarray
    clk_rx_m: np.ndarray
    nl_wavelength_m: float | np.ndarray
    systems: tuple[str, ...] = ()

    @property
    def system_order(self) -> tuple[str, ...]:
        """The systems of the arc, reference first (``systems`` or those of ``sv``)."""
        if self.systems:
            return tuple(self.systems)
        return tuple(dict.fromkeys(str(s)[0] for s in self.sv))

    @property
    def sat_system(self) -> np.ndarray:
        """Index into :attr:`system_order` of each satellite of ``sv`` (s,)."""
        order = {x: i for i, x in enumerate(self.system_order)}
        return np.array([order[str(s)[0]] for s in self.sv], dtype=int)


@dataclass
class PodStart:
    """Estimates of an earlier solution of the same arc to continue from (warm start).

    The ambiguity-fixed solution (:class:`FixedPod`) is linearised at the converged float
    one: its corrections are the (cm-level) effect of the constraints.

    Attributes
    ----------
    parameter_names : list of str
        Must equal the arc parameters of the new run (same force model and pulses).
    estimates : ndarray, shape (k,)
        Values of the arc parameters (:attr:`PodResult.estimates`).
    ambiguity_pass : ndarray of int, shape (a,)
    ambiguity_m : ndarray, shape (a,)
        Float ambiguities [m] of these passes.
    clk_rx_m : ndarray, shape (m,)
        Receiver clock per epoch of the observations [m] (NaN: unknown).
    code_rejected, phase_rejected : ndarray of bool, shape (n,)
        Outliers of the earlier solution (per observation pair); screening continues.
    variance_factors : ndarray, shape (2 × systems,), optional
        Variance factors of the earlier solution (``PodResult.variance_factors``); None: 1.
    """

    parameter_names: list[str]
    estimates: np.ndarray
    ambiguity_pass: np.ndarray
    ambiguity_m: np.ndarray
    clk_rx_m: np.ndarray
    code_rejected: np.ndarray
    phase_rejected: np.ndarray
    variance_factors: np.ndarray | None = None


@dataclass(eq=False)
class PodResult:
    """Outcome of :func:`float_pod` (see the attributes; arrays as in PodObservations).

    Attributes
    ----------
    t_ref : datetime64
        Time origin of the force model (``t_s`` = GPS seconds since it).
    parameter_names : list of str
        Arc parameters: initial state, estimated force parameters, pulses, [pco_z_m].
    estimates, sigmas : ndarray, shape (k,)
        Values (pulses and pco correction included) and formal sigmas (scaled by σ0).
    covariance : ndarray, shape (k + a, k + a)
        Formal covariance (scaled by σ0²) of the arc parameters and ambiguities.
    ambiguity_m, ambiguity_sigma_m : ndarray, shape (a,)
        Float IF ambiguities [m] (including receiver/satellite phase biases).
    ambiguity_pass : ndarray of int, shape (a,)
        Pass index (``PodObservations.pass_index`` value) of each ambiguity.
    orbit : CorrectedOrbit
        Final orbit (GCRF): the last integrated orbit and the last correction.
    pulses : PseudoStochasticPulses or None
    force_model : ForceModel
    force_parameters : ndarray
        All force-model parameters (estimated and fixed).
    clk_rx_m : ndarray, shape (m,)
        Estimated receiver clock [m] (NaN at epochs without observations).
    model : ModelResult
        Observation model of the last iteration (per pair).
    code_residual_m, phase_residual_m : ndarray, shape (n,)
        Post-fit residuals per pair (NaN where not used).
    code_used, phase_used : ndarray of bool, shape (n,)
        Observations in the final solution (False: rejected or not available).
    code_rejected, phase_rejected : ndarray of bool, shape (n,)
        Rejected by the screening.
    sigma0 : float
        A-posteriori standard deviation of unit weight.
    iterations : int
        Linearisations solved.
    converged : bool
    integrations : int
        Orbit integrations (with the variational equations) of the run.
    force_evaluations : int
        Force-model evaluations of these integrations.
    systems : tuple of str
        Systems of the arc, reference first.
    variance_factors : ndarray, shape (2 × systems,)
        Variance factor of each group ``2 × system + (0 code, 1 phase)`` that scales the
        a-priori variances (1 without VCE): weight = 1 / (factor σ²).
    variance_sigmas : ndarray, shape (2 × systems,)
        Approximate standard deviations of the factors, ``factor · √(2 / r_g)`` (NaN
        without VCE).
    redundancy : ndarray, shape (2 × systems,)
        Redundancy number of each group in the final solution (NaN without VCE).
    group_rms_m : ndarray, shape (2 × systems,)
        Residual RMS of each group of the final solution [m] (NaN without observations).
    group_count : ndarray of int, shape (2 × systems,)
        Observations of each group in the final solution.
    apriori_sigma_m : ndarray, shape (2 × systems,)
        A-priori standard deviation of each group above ``weight_elevation_deg``
        (``code_sigma_m``, ``phase_sigma_m``) [m], which its variance factor scales.
    isb_piece : ndarray of int, shape (m,)
        Index of the inter-system-bias piece of each epoch (0 with one ISB per arc).
    """

    t_ref: np.datetime64
    parameter_names: list[str]
    estimates: np.ndarray
    sigmas: np.ndarray
    covariance: np.ndarray
    ambiguity_m: np.ndarray
    ambiguity_sigma_m: np.ndarray
    ambiguity_pass: np.ndarray
    orbit: CorrectedOrbit = field(repr=False)
    pulses: PseudoStochasticPulses | None
    force_model: ForceModel = field(repr=False)
    force_parameters: np.ndarray
    clk_rx_m: np.ndarray
    model: ModelResult = field(repr=False)
    code_residual_m: np.ndarray
    phase_residual_m: np.ndarray
    code_used: np.ndarray
    phase_used: np.ndarray
    code_rejected: np.ndarray
    phase_rejected: np.ndarray
    sigma0: float
    iterations: int
    converged: bool
    integrations: int
    force_evaluations: int
    systems: tuple[str, ...] = ("G",)
    variance_factors: np.ndarray = field(default_factory=lambda: np.ones(2))
    variance_sigmas: np.ndarray = field(default_factory=lambda: np.full(2, np.nan))
    redundancy: np.ndarray = field(default_factory=lambda: np.full(2, np.nan))
    group_rms_m: np.ndarray = field(default_factory=lambda: np.full(2, np.nan))
    group_count: np.ndarray = field(default_factory=lambda: np.zeros(2, int))
    apriori_sigma_m: np.ndarray = field(default_factory=lambda: np.full(2, np.nan))
    isb_piece: np.ndarray | None = None

    def orbit_at(self, t_s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """GCRF state and formal position covariance at epochs [s since ``t_ref``].

        Returns
        -------
        states : ndarray, shape (m, 6)
            Position [m] and velocity [m/s] of :attr:`orbit`.
        cov_pos : ndarray, shape (m, 3, 3)
            Formal GCRF position covariance [m²] from the arc-parameter covariance.
        partials : ndarray, shape (m, 3, k)
            Position partials of the arc parameters.
        """
        states, g = self.orbit.at(t_s)
        k = len(self.parameter_names)
        g = g[:, :3]
        if g.shape[2] < k:                       # PCO-Z column: no orbit partial
            g = np.concatenate([g, np.zeros(g.shape[:2] + (k - g.shape[2],))], axis=2)
        return states, epoch_covariance(g, self.covariance[:k, :k]), g


def pulse_epochs(t_start_s: float, t_end_s: float, interval_s: float | None) -> np.ndarray:
    """Regular pulse epochs strictly inside (t_start, t_end) [s]."""
    if not interval_s:
        return np.empty(0)
    n = int(np.floor((t_end_s - t_start_s) / interval_s - 1e-9))
    return t_start_s + interval_s * np.arange(1, n + 1)


def _position_partials(traj: Trajectory, pulses, est: np.ndarray, k: int) -> np.ndarray:
    """∂r/∂(state, estimated force parameters, pulses) at the epochs of ``traj`` (m, 3, k).

    The pulse partials come from the dense interpolant that ``traj`` carries (the whole arc),
    at its own epochs. Columns after the orbit parameters (PCO-Z) are zero.
    """
    g = np.zeros((traj.t_s.size, 3, k))
    g[:, :, :6] = traj.stm[:, :3, :]
    n_e = int(np.count_nonzero(est))
    g[:, :, 6:6 + n_e] = traj.sensitivity[:, :3, est]
    if pulses is not None and pulses.epochs_s.size:
        g[:, :, 6 + n_e:6 + n_e + 3 * pulses.epochs_s.size] = pulse_partials(
            traj, pulses, position_only=True)
    return g


class _ReceptionRotation:
    """ITRF -> GCRF matrices at the reception times of the iterations of one arc.

    The reception times move between iterations by the change of the receiver clock (a few
    ns once the code-only clock is replaced). Matrices computed at earlier times ``t`` are
    carried to ``t + δ`` by the Earth rotation, ``R(t + δ) = R(t) R3(−ω δ)`` (ω the rate of
    the Earth rotation angle); they are recomputed with
    :func:`leopod.frames.earth_rotation.gcrf_from_itrf_matrices` once any ``|δ|`` exceeds
    ``_ROTATION_CARRY_NS`` (1 µs). Neglected over 1 µs: the tilt of the rotation axis from
    ITRF Z (polar motion, < 2.5e-6 rad, times ω δ < 7.3e-11 rad: < 2e-16 rad), the rates of
    precession-nutation and polar motion (< 1e-11 rad/s: < 1e-17 rad) and of UT1 − TAI
    (1e-8 relative), all far below the ~3e-14 rad resolution of the Earth rotation angle of
    ``erfa.era00`` in the direct computation.
    """

    def __init__(self, eop: EarthOrientation | None):
        self.eop = eop
        self.times: np.ndarray | None = None
        self.rot: np.ndarray | None = None

    def __call__(self, times: np.ndarray) -> np.ndarray:
        """Matrices (m, 3, 3) at ``times`` (datetime64[ns], shape (m,), same epochs)."""
        if self.times is not None:
            shift_ns = (times - self.times).astype(np.int64)
            if np.abs(shift_ns).max(initial=0) <= _ROTATION_CARRY_NS:
                angle = ERA_RATE_RAD_S * 1e-9 * shift_ns
                c, s = np.cos(angle)[:, None], np.sin(angle)[:, None]
                rot = self.rot.copy()
                rot[:, :, 0] = c * self.rot[:, :, 0] + s * self.rot[:, :, 1]
                rot[:, :, 1] = c * self.rot[:, :, 1] - s * self.rot[:, :, 0]
                return rot
        self.rot, _ = gcrf_from_itrf_matrices(times, eop=self.eop)
        self.times = times
        return self.rot


def elevation_sigma(el_deg: np.ndarray, sigma0: float, knee_deg: float) -> np.ndarray:
    """A-priori sigma of observations at elevations ``el_deg`` [m]: ``sigma0`` above
    ``knee_deg``, ``sigma0 / (2 sin el)`` below (the float POD's and kinematic POD's weights)."""
    el = np.radians(np.maximum(el_deg, _MIN_ELEVATION_FOR_WEIGHT_DEG))
    return np.where(np.degrees(el) >= knee_deg, sigma0, sigma0 / (2.0 * np.sin(el)))


def robust_scale(z: np.ndarray) -> float:
    """Robust standard deviation of ``z``: the median absolute deviation scaled to a normal
    sigma (0 for no values)."""
    return float(_MAD_TO_SIGMA * np.median(np.abs(z - np.median(z)))) if z.size else 0.0


class _Problem:
    """Book-keeping of one float POD run (observations, parameters, current estimates)."""

    def __init__(self, obs: PodObservations, products: GnssProducts, force_model: ForceModel,
                 t_ref, settings: PodSettings, eop, leo_pco_body_m, sat_pco_body_m, sat_pcv_m,
                 leo_attitude: LeoAttitude | None = None, leo_antenna=None,
                 cover_s: tuple[float, float] | None = None):
        self.obs, self.products, self.fm, self.settings = obs, products, force_model, settings
        self.eop = eop
        self.rotation = _ReceptionRotation(eop)
        self.leo_pco = (np.zeros(3) if leo_pco_body_m is None
                        else np.asarray(leo_pco_body_m, dtype=float).copy())
        self.sat_pco, self.sat_pcv = sat_pco_body_m, sat_pcv_m
        self.leo_attitude = leo_attitude
        self.leo_antenna = leo_antenna
        self.t_ref = np.datetime64(t_ref, "ns")
        self.t_nom_s = seconds_since(obs.times, self.t_ref)
        # what an integration spans besides its evaluation epochs: the nominal epochs and
        # cover_s (output epochs beyond the observations)
        cover = (self.t_nom_s[0], self.t_nom_s[-1]) if cover_s is None else cover_s
        self.span_s = (min(self.t_nom_s[0], cover[0]), max(self.t_nom_s[-1], cover[1]))
        self.t_nom_prod_s = seconds_since(obs.times, products.ref)
        self.sun = sun_position_ef(obs.times)
        self.pairs = Pairs(epoch=obs.epoch, isv=products.sv_index(obs.sv)[obs.sat],
                           sat=obs.sat)
        self.est = estimated_parameters(force_model)
        self.params = apriori_parameters(force_model)
        self.apriori = self.params.copy()
        sig = constraint_sigmas(force_model)[self.est]
        self.t0 = float(self.t_nom_s[0])
        epochs = pulse_epochs(self.t0, float(self.t_nom_s[-1]), settings.pulse_interval_s)
        self.pulses = PseudoStochasticPulses(epochs) if epochs.size else None
        n_p = 0 if self.pulses is None else epochs.size
        self.dv = np.zeros((n_p, 3))
        self.names = list(STATE_NAMES) + [p for p, e in zip(force_model.parameters, self.est)
                                          if e]
        if self.pulses is not None:
            self.names += self.pulses.parameters
        self.k_orbit = len(self.names)
        if settings.estimate_pco_z:
            self.names.append("pco_z_m")
        # systems, inter-system biases (code of every system but the first), VCE groups
        self.systems = obs.system_order
        self.pair_system = obs.sat_system[obs.sat]                       # (n,)
        interval = settings.isb_interval_s
        piece = (np.zeros(obs.times.size, int) if not interval
                 else np.floor((self.t_nom_s - self.t0) / interval + 1e-9).astype(int))
        self.isb_piece = piece                                           # (m,)
        self.n_pieces = int(piece.max(initial=0)) + 1
        self.k_isb = len(self.names)
        for x in self.systems[1:]:
            self.names += ([f"isb_{x}_m"] if self.n_pieces == 1 else
                           [f"isb_{x}_{p:03d}_m" for p in range(self.n_pieces)])
        self.isb = np.zeros((len(self.systems) - 1, self.n_pieces))
        self.variance_factor = np.ones(2 * len(self.systems))
        self.vce_sigma = np.full(2 * len(self.systems), np.nan)
        self.vce_redundancy = np.full(2 * len(self.systems), np.nan)
        self.k = len(self.names)
        self.vce_iterations = 0
        w = np.zeros(self.k)
        w[6:6 + sig.size] = np.where(np.isfinite(sig), 1.0 / np.where(np.isfinite(sig), sig,
                                                                         1.0)**2, 0.0)
        if n_p:
            w[6 + sig.size:self.k_orbit] = np.tile(1.0 / np.asarray(settings.pulse_sigma_m_s)**2,
                                                   n_p)
        # ISB: a negligible damping of the increments (no a-priori value: the misclosure is
        # always 0) that keeps a piece without code observations of its system solvable
        w[self.k_isb:self.k] = _ISB_DAMPING_WEIGHT
        self.constraint_weight = w
        self.pco_dz = 0.0
        self.clk_rx_m = np.asarray(obs.clk_rx_m, dtype=float).copy()
        self.ambiguity = np.zeros(int(obs.pass_index.max(initial=-1)) + 1)
        self.code_ok = np.isfinite(obs.code_m)
        self.phase_ok = (obs.pass_index >= 0) & np.isfinite(obs.phase_m)
        self.code_rej = np.zeros(obs.epoch.size, bool)
        self.phase_rej = np.zeros(obs.epoch.size, bool)
        self.integrations = 0
        self.force_evaluations = 0

    # -- orbit ------------------------------------------------------------------------------
    def integrate(self, state0: np.ndarray, t_eval: np.ndarray) -> Trajectory:
        """Orbit at ``t_eval`` [s] whose dense output also spans ``span_s`` (the nominal and
        output epochs), both by at least ``_SPAN_MARGIN_S``, to ends on the integrator's step
        grid from t0 (so that the last segment keeps whole steps and the pulses in it fall on
        nodes: no restarts); forces tabulated along a reference orbit (drag) follow it from
        then on."""
        step = self.settings.integrator_step_s
        lo = min(t_eval.min(), self.span_s[0]) - _SPAN_MARGIN_S
        hi = max(t_eval.max(), self.span_s[1]) + _SPAN_MARGIN_S
        t_out = np.append(t_eval, [self.t0 - step * np.ceil((self.t0 - lo) / step),
                                   self.t0 + step * np.ceil((hi - self.t0) / step)])
        if self.pulses is None:
            traj = integrate(self.fm, self.t0, state0, self.params, t_out, step_s=step)
        else:
            traj = apply_pulses(self.fm, self.t0, state0, self.params, t_out, self.pulses,
                                self.dv, step_s=step)
        self.integrations += 1
        self.force_evaluations += traj.n_evaluations
        self.fm.follow(traj.positions)
        return traj.at(t_eval)

    def current_vector(self, state0: np.ndarray) -> np.ndarray:
        parts = [state0, self.params[self.est], self.dv.ravel()]
        if self.settings.estimate_pco_z:
            parts.append([self.pco_dz])
        parts.append(self.isb.ravel())
        return np.concatenate(parts)

    def load(self, start: PodStart) -> np.ndarray:
        """Take the estimates, clocks and outliers of ``start`` (nothing of earlier solves);
        returns the initial state."""
        if list(start.parameter_names) != self.names:
            raise ValueError("warm start: the arc parameters differ from those of the earlier "
                             "solution (force model, pulses or PCO settings changed)")
        est = np.asarray(start.estimates, dtype=float)
        n_e = int(self.est.sum())
        self.params[self.est] = est[6:6 + n_e]
        self.dv = est[6 + n_e:self.k_orbit].reshape(self.dv.shape).copy()
        if self.settings.estimate_pco_z:
            self.pco_dz = float(est[self.k_orbit])
        self.isb = est[self.k_isb:self.k].reshape(self.isb.shape).copy()
        if start.variance_factors is not None:
            self.variance_factor = np.asarray(start.variance_factors, dtype=float).copy()
        self.ambiguity = np.zeros_like(self.ambiguity)
        self.ambiguity[np.asarray(start.ambiguity_pass, dtype=int)] = start.ambiguity_m
        self.clk_rx_m = np.where(np.isfinite(start.clk_rx_m), start.clk_rx_m,
                                 self.obs.clk_rx_m)
        self.code_rej = np.asarray(start.code_rejected, dtype=bool).copy()
        self.phase_rej = np.asarray(start.phase_rejected, dtype=bool).copy()
        return est[:6].copy()

    def apply(self, state0: np.ndarray, dx: np.ndarray) -> np.ndarray:
        n_e = int(self.est.sum())
        self.params[self.est] += dx[6:6 + n_e]
        self.dv += dx[6 + n_e:self.k_orbit].reshape(self.dv.shape)
        if self.settings.estimate_pco_z:
            self.pco_dz += dx[self.k_orbit]
        self.isb += dx[self.k_isb:self.k].reshape(self.isb.shape)
        return state0 + dx[:6]

    def constraint_rhs(self, state0: np.ndarray) -> np.ndarray:
        apriori = np.concatenate([state0, self.apriori[self.est], np.zeros(self.dv.size),
                                  [0.0] * self.settings.estimate_pco_z,
                                  self.isb.ravel()])           # no a-priori value of the ISB
        return self.constraint_weight * (apriori - self.current_vector(state0))

    # -- observations -----------------------------------------------------------------------
    def linearise(self, state0: np.ndarray, orbit: CorrectedOrbit | None = None):
        """Integrate, model and build the observation rows at the current estimates.

        With ``orbit`` (the orbit at these estimates and its partials, e.g. the float POD's,
        :mod:`leopod.estimation.linearisation`) nothing is integrated: the states and
        partials are those of ``orbit`` and the trajectory returned is its own.
        """
        dt_rx_s = np.nan_to_num(self.clk_rx_m) / C_LIGHT_M_S
        t_eval = self.t_nom_s - dt_rx_s
        if orbit is None:
            traj = self.integrate(state0, t_eval)
            states = traj.states
            g = _position_partials(traj, self.pulses, self.est, self.k)
        else:
            traj = orbit.trajectory
            states, partials = orbit.at(t_eval)
            g = np.zeros((t_eval.size, 3, self.k))
            g[:, :, :self.k_orbit] = partials[:, :3]
        times_true = self.obs.times - (dt_rx_s * 1e9).round().astype("timedelta64[ns]")
        rot = self.rotation(times_true)
        pco = self.leo_pco + np.array([0.0, 0.0, self.pco_dz])
        model = compute_model(self.pairs, self.t_nom_prod_s - dt_rx_s, states[:, :3],
                              states[:, 3:], rot, self.products, self.sun,
                              leo_pco_body_m=pco, sat_pco_body_m=self.sat_pco,
                              sat_pcv_m=self.sat_pcv,
                              nl_wavelength_m=self.obs.nl_wavelength_m,
                              leo_attitude=self.leo_attitude, leo_antenna=self.leo_antenna)
        return traj, model, g

    def rows(self, model: ModelResult, g: np.ndarray):
        """Code and phase rows of the usable observations, and their pair indices."""
        s = self.settings
        usable = model.valid & (model.el_deg >= s.min_elevation_deg)
        code = self.code_ok & usable & ~self.code_rej
        phase = self.phase_ok & usable & ~self.phase_rej
        # passes with too few phase observations are dropped
        counts = np.bincount(self.obs.pass_index[phase], minlength=self.ambiguity.size)
        phase &= counts[np.maximum(self.obs.pass_index, 0)] >= s.min_phase_obs
        active = np.flatnonzero(np.bincount(self.obs.pass_index[phase],
                                            minlength=self.ambiguity.size))
        column = np.full(self.ambiguity.size, -1)
        column[active] = np.arange(active.size)
        ic, ip = np.flatnonzero(code), np.flatnonzero(phase)
        pair = np.concatenate([ic, ip])
        is_phase = np.concatenate([np.zeros(ic.size, bool), np.ones(ip.size, bool)])
        ep = self.obs.epoch[pair]
        if s.estimate_pco_z:            # the antenna moves along body +Z with the PCO
            g = g.copy()
            g[self.obs.epoch, :, self.k_orbit] = model.z_body_gcrf
        computed = np.where(is_phase, model.phase_m[pair], model.code_m[pair])
        observed = np.where(is_phase, self.obs.phase_m[pair], self.obs.code_m[pair])
        amb = np.where(is_phase, column[self.obs.pass_index[pair]], -1)
        amb_value = np.where(is_phase, self.ambiguity[self.obs.pass_index[pair]], 0.0)
        sigma = np.where(is_phase,
                         elevation_sigma(model.el_deg[pair], s.phase_sigma_m, s.weight_elevation_deg),
                         elevation_sigma(model.el_deg[pair], s.code_sigma_m, s.weight_elevation_deg))
        group = self.group(pair, is_phase)
        variance = sigma**2 * self.variance_factor[group]
        direction = -model.los_gcrf[pair]
        misclosure = observed - computed - amb_value
        n_x = len(self.systems) - 1
        if n_x:
            # the ISB as further components of the row directions: 1 for the code of system
            # x > 0, whose "partials" are the ISB column of the epoch's piece (the ISB
            # columns follow the pulses and are non-zero in every block of epochs, so the
            # blocked sum of normals.accumulate works on all columns for combined arcs)
            system = self.pair_system[pair]
            isb_row = (~is_phase) & (system > 0)
            misclosure = misclosure - np.where(
                isb_row, self.isb[np.maximum(system - 1, 0), self.isb_piece[ep]], 0.0)
            extra = np.zeros((pair.size, n_x))
            extra[isb_row, system[isb_row] - 1] = 1.0
            direction = np.concatenate([direction, extra], axis=1)
            m = g.shape[0]
            g_isb = np.zeros((m, n_x, self.k))
            for x in range(n_x):
                g_isb[np.arange(m), x, self.k_isb + x * self.n_pieces + self.isb_piece] = 1.0
            g = np.concatenate([g, g_isb], axis=1)
        rows = Rows(direction=direction, partials=g, amb=amb, epoch=ep,
                    misclosure=misclosure, weight=1.0 / variance, n_amb=active.size)
        return rows, pair, is_phase, active

    def group(self, pair: np.ndarray, is_phase: np.ndarray) -> np.ndarray:
        """Variance group ``2 × system + (0 code, 1 phase)`` of rows (pair indices)."""
        return 2 * self.pair_system[pair] + is_phase.astype(int)

    def reject_gross_code(self, model: ModelResult) -> int:
        """Reject code observations far from the median misclosure of their epoch."""
        ok = self.code_ok & model.valid
        l = np.where(ok, self.obs.code_m - model.code_m, np.nan)
        med = np.full(self.obs.times.size, np.nan)
        order = np.argsort(self.obs.epoch[ok], kind="stable")
        ep_ok, l_ok = self.obs.epoch[ok][order], l[ok][order]
        starts = np.flatnonzero(np.r_[True, np.diff(ep_ok) > 0])
        for a, b in zip(starts, np.r_[starts[1:], ep_ok.size]):
            med[ep_ok[a]] = np.median(l_ok[a:b])
        bad = ok & (np.abs(l - med[self.obs.epoch]) > self.settings.gross_code_m)
        self.code_rej |= bad
        return int(bad.sum())

    def screen(self, rows: Rows, residuals: np.ndarray, pair: np.ndarray,
               is_phase: np.ndarray) -> int:
        """Reject code and phase outliers (module docstring); returns the number rejected."""
        z = residuals * np.sqrt(rows.weight)
        n_new = 0
        for phase_type, rejected in ((False, self.code_rej), (True, self.phase_rej)):
            sel = is_phase == phase_type
            scale = robust_scale(z[sel])
            bad = sel & (np.abs(z) > self.settings.outlier_k * scale)
            rejected[pair[bad]] = True
            n_new += int(bad.sum())
        return n_new


def constrain_differences(ne, k: int, active: np.ndarray, ambiguity: np.ndarray,
                           constraints) -> None:
    """Add ``B_i − B_j = v ± σ`` pseudo-observations to the normal equations (in place).

    ``ne`` holds ``[arc parameters (k), ambiguities of the passes ``active``]``; the
    misclosure uses the current ambiguity values ``ambiguity`` (indexed by pass).
    """
    pass_i, pass_j, value, sigma = (np.asarray(c) for c in constraints)
    col = np.full(max(int(active.max()), int(pass_i.max()), int(pass_j.max())) + 1, -1)
    col[active] = k + np.arange(active.size)
    ci, cj = col[pass_i], col[pass_j]
    ok = (ci >= 0) & (cj >= 0)
    ci, cj, w = ci[ok], cj[ok], 1.0 / sigma[ok] ** 2
    misclosure = value[ok] - (ambiguity[pass_i[ok]] - ambiguity[pass_j[ok]])
    np.add.at(ne.matrix, (ci, ci), w)
    np.add.at(ne.matrix, (cj, cj), w)
    np.add.at(ne.matrix, (ci, cj), -w)
    np.add.at(ne.matrix, (cj, ci), -w)
    np.add.at(ne.rhs, ci, w * misclosure)
    np.add.at(ne.rhs, cj, -w * misclosure)


@dataclass
class _Solution:
    """One solve of the linearised system (after its screening)."""

    rows: Rows
    pair: np.ndarray
    is_phase: np.ndarray
    active: np.ndarray
    dx: np.ndarray
    cov: np.ndarray
    clocks: np.ndarray
    residuals: np.ndarray
    shift_m: float


def _solve_linearised(prob: _Problem, state: np.ndarray, model: ModelResult, g: np.ndarray,
                      screening: bool, ambiguity_constraints=None) -> _Solution:
    """Solve at one linearisation, again after each screening round that rejects some."""
    while True:
        rows, pair, is_phase, active = prob.rows(model, g)
        ne = accumulate(rows)
        if ambiguity_constraints is not None:
            constrain_differences(ne, prob.k, active, prob.ambiguity, ambiguity_constraints)
        dx, cov = solve(ne, np.concatenate([prob.constraint_weight, np.zeros(active.size)]),
                        np.concatenate([prob.constraint_rhs(state), np.zeros(active.size)]))
        clocks, res = epoch_clocks(rows, dx)
        if not screening or prob.screen(rows, res, pair, is_phase) == 0:
            if not (screening and prob.settings.vce) or _vce_step(prob, rows, res, pair,
                                                                  is_phase, cov):
                break
    shift = float(np.max(np.linalg.norm(np.einsum("mik,k->mi", g[:, :, :prob.k],
                                                  dx[:prob.k]), axis=1)))
    return _Solution(rows=rows, pair=pair, is_phase=is_phase, active=active, dx=dx, cov=cov,
                     clocks=clocks, residuals=res, shift_m=shift)


def _vce_step(prob: _Problem, rows: Rows, residuals: np.ndarray, pair: np.ndarray,
              is_phase: np.ndarray, q: np.ndarray) -> bool:
    """One variance-component update of the groups (:mod:`leopod.estimation.vce`).

    ``σ̂²_g = v_gᵀ P_g v_g / r_g`` with the redundancy ``r_g = n_g − tr(N⁻¹ N_g)`` of the
    group (clocks included, :func:`leopod.estimation.vce.group_redundancy`); the factors of
    the groups are multiplied by ``σ̂²_g``. Returns True when every ``σ̂²_g`` is within
    ``1 ± vce_tolerance`` (converged) or the iterations are used up; False: solve again.
    """
    group = prob.group(pair, is_phase)
    n_groups = prob.variance_factor.size
    estimate = np.ones(n_groups)
    redundancy = np.full(n_groups, np.nan)
    for g in range(n_groups):
        sel = group == g
        if not sel.any():
            continue
        redundancy[g] = group_redundancy(rows, q, sel)
        if redundancy[g] > 1.0:
            estimate[g] = float(np.sum(rows.weight[sel] * residuals[sel] ** 2) / redundancy[g])
    prob.variance_factor = prob.variance_factor * estimate
    prob.vce_redundancy = redundancy
    # sigma of an estimated variance with r degrees of freedom (Koch 1999): σ² √(2/r)
    prob.vce_sigma = prob.variance_factor * np.sqrt(2.0 / np.where(redundancy > 0,
                                                                   redundancy, np.nan))
    prob.vce_iterations += 1
    log.info("variance components (iteration %d): %s", prob.vce_iterations, ", ".join(
        f"{prob.systems[g // 2]} {'phase' if g % 2 else 'code'} {prob.variance_factor[g]:.4g} "
        f"(r {redundancy[g]:.1f})" for g in range(n_groups) if np.isfinite(redundancy[g])))
    done = bool(np.all(np.abs(estimate - 1.0) <= prob.settings.vce_tolerance))
    if prob.vce_iterations >= prob.settings.vce_max_iterations:
        if not done:
            log.warning("variance components not converged after %d iterations",
                        prob.vce_iterations)
        prob.vce_iterations = 0
        return True
    if done:
        prob.vce_iterations = 0
    return done


def _update(prob: _Problem, state: np.ndarray, sol: _Solution) -> np.ndarray:
    """Apply a solution's corrections to the estimates; returns the new initial state."""
    prob.ambiguity[sol.active] += sol.dx[prob.k:]
    prob.clk_rx_m = np.where(np.isfinite(sol.clocks), sol.clocks, prob.clk_rx_m)
    return prob.apply(state, sol.dx)


def _result(label: str, prob: _Problem, state: np.ndarray, orbit: CorrectedOrbit,
            model: ModelResult, sol: _Solution, iterations: int, converged: bool) -> PodResult:
    """PodResult of the estimates ``state`` (and ``prob``'s) after the solution ``sol``."""
    rows, res, pair, is_phase, active = sol.rows, sol.residuals, sol.pair, sol.is_phase, sol.active
    dof = max(rows.epoch.size - prob.k - active.size - np.unique(rows.epoch).size, 1)
    v_pv = float(np.sum(rows.weight * res**2))
    sigma0 = float(np.sqrt(v_pv / dof))
    cov = sol.cov * sigma0**2
    n = prob.obs.epoch.size
    code_res = np.full(n, np.nan)
    phase_res = np.full(n, np.nan)
    code_res[pair[~is_phase]] = res[~is_phase]
    phase_res[pair[is_phase]] = res[is_phase]
    code_used = np.zeros(n, bool)
    phase_used = np.zeros(n, bool)
    code_used[pair[~is_phase]] = True
    phase_used[pair[is_phase]] = True
    sig = np.sqrt(np.diag(cov))
    group = prob.group(pair, is_phase)
    n_groups = prob.variance_factor.size
    count = np.bincount(group, minlength=n_groups)
    rms = np.sqrt(np.bincount(group, weights=res**2, minlength=n_groups)
                  / np.where(count > 0, count, 1))
    rms = np.where(count > 0, rms, np.nan)
    for g in range(n_groups):
        if count[g]:
            log.info("%s: %s %s residual RMS %.4f m (%d observations), variance factor %.4g",
                     label, prob.systems[g // 2], "phase" if g % 2 else "code", rms[g],
                     count[g], prob.variance_factor[g])
    for name, value, sigma in zip(prob.names[prob.k_isb:], prob.isb.ravel(),
                                  sig[prob.k_isb:prob.k], strict=True):
        log.info("%s: %s %.4f ± %.4f m", label, name, value, sigma)
    log.info("%s: sigma0 %.3f, code RMS %.3f m, phase RMS %.4f m, %d passes; %d integrations, "
             "%d force evaluations", label, sigma0, np.sqrt(np.mean(res[~is_phase]**2)),
             np.sqrt(np.mean(res[is_phase]**2)), active.size, prob.integrations,
             prob.force_evaluations)
    return PodResult(
        t_ref=prob.t_ref, parameter_names=prob.names,
        estimates=prob.current_vector(state), sigmas=sig[:prob.k],
        covariance=cov, ambiguity_m=prob.ambiguity[active],
        ambiguity_sigma_m=sig[prob.k:], ambiguity_pass=active, orbit=orbit,
        pulses=prob.pulses, force_model=prob.fm, force_parameters=prob.params.copy(),
        clk_rx_m=sol.clocks, model=model, code_residual_m=code_res, phase_residual_m=phase_res,
        code_used=code_used, phase_used=phase_used, code_rejected=prob.code_rej.copy(),
        phase_rejected=prob.phase_rej.copy(), sigma0=sigma0, iterations=iterations,
        converged=converged, integrations=prob.integrations,
        force_evaluations=prob.force_evaluations, systems=prob.systems,
        variance_factors=prob.variance_factor.copy(),
        variance_sigmas=(prob.vce_sigma.copy() if prob.settings.vce
                         else np.full(n_groups, np.nan)),
        redundancy=(prob.vce_redundancy.copy() if prob.settings.vce
                    else np.full(n_groups, np.nan)),
        group_rms_m=rms, group_count=count,
        apriori_sigma_m=np.tile([prob.settings.code_sigma_m, prob.settings.phase_sigma_m],
                                len(prob.systems)),
        isb_piece=prob.isb_piece.copy())


def _announce(label: str, prob: _Problem) -> None:
    """Log the size of the problem; fail without code observations."""
    log.info("%s: %d epochs, %d code and %d phase observations, %d passes, %d arc parameters "
             "(%d pulses)", label, prob.obs.times.size, int(prob.code_ok.sum()),
             int(prob.phase_ok.sum()), prob.ambiguity.size, prob.k,
             0 if prob.pulses is None else prob.pulses.epochs_s.size)
    if not prob.code_ok.any():
        raise ValueError("float POD: no usable code observation in the arc (all missing, "
                         "rejected, or dropped by a code-bias map without values: see "
                         "code_bias.min_count and code_bias.empty_cells)")


def _log_without_products(prob: _Problem, model: ModelResult) -> None:
    """Log the observations left out for want of GNSS orbit or clock (records missing or
    flagged bad in the products, or outside them), per satellite."""
    missing = (prob.code_ok | prob.phase_ok) & ~model.valid
    if missing.any():
        svs, counts = np.unique(np.asarray(prob.obs.sv)[prob.obs.sat[missing]],
                                return_counts=True)
        log.warning("%d observations without GNSS orbit or clock (missing or bad in the "
                    "products) not used: %s", int(missing.sum()),
                    ", ".join(f"{sv} {n}" for sv, n in zip(svs, counts, strict=True)))


def float_pod(obs: PodObservations, products: GnssProducts, force_model: ForceModel, t_ref,
              state0_gcrf: np.ndarray, settings: PodSettings, *,
              eop: EarthOrientation | None = None, leo_pco_body_m=None,
              sat_pco_body_m: np.ndarray | None = None, sat_pcv_m=None,
              leo_attitude: LeoAttitude | None = None, leo_antenna=None,
              cover_s: tuple[float, float] | None = None) -> PodResult:
    """Float reduced-dynamic orbit from ionosphere-free code and phase (module docstring).

    Parameters
    ----------
    obs : PodObservations
    products : GnssProducts
        GNSS orbits and clocks (reference signals of the clocks = the code pair of ``obs``).
    force_model : ForceModel
        Arc force model, time origin ``t_ref``.
    t_ref : datetime64
        Time origin of the force model (GPS time label).
    state0_gcrf : array_like, shape (6,)
        A-priori GCRF state at ``t_ref`` (e.g. a dynamic fit to a code-only orbit,
        :func:`leopod.dynamics.orbit_fit.fit_orbit`).
    settings : PodSettings
    eop : EarthOrientation, optional
    leo_pco_body_m : array_like, shape (3,), optional
        Ionosphere-free LEO antenna PCO in the body frame [m].
    sat_pco_body_m : ndarray, shape (s, 3), optional
        Ionosphere-free GNSS antenna PCO per ``obs.sv`` (body frame) [m].
    sat_pcv_m : callable, optional
        ``f(sat_index, nadir_deg) -> m``: ionosphere-free GNSS antenna PCV.
    leo_attitude : LeoAttitude, optional
        Attitude law of the LEO (PCO, wind-up, PCO-Z partial); None: nominal.
    leo_antenna : leopod.estimation.obsmodel.ReceiverAntenna, optional
        Antenna frame and ionosphere-free PCV of an ANTEX LEO antenna; None: none.
    cover_s : (float, float), optional
        First and last epoch [s since ``t_ref``] the integrated orbit also covers (output
        epochs beyond the observations); None: the observations.

    Returns
    -------
    PodResult
        Its orbit is the last integration plus the corrections since (module docstring), or,
        without convergence, an integration at the final estimates.
    """
    prob = _Problem(obs, products, force_model, t_ref, settings, eop, leo_pco_body_m,
                    sat_pco_body_m, sat_pcv_m, leo_attitude, leo_antenna, cover_s)
    state = np.asarray(state0_gcrf, dtype=float).copy()
    _announce("float POD", prob)
    screening = False
    converged = False
    base = None        # correction of the last integration at the current estimates
    for iteration in range(1, settings.max_iterations + 1):
        if base is None:
            traj, model, g = prob.linearise(state)
            base = np.zeros(prob.k_orbit)
        else:
            traj, model, g = prob.linearise(state, CorrectedOrbit(traj, prob.pulses, prob.est,
                                                                  base))
        if iteration == 1:
            log.info("rejected %d code observations with gross errors (> %.0f m)",
                     prob.reject_gross_code(model), settings.gross_code_m)
            _log_without_products(prob, model)
        sol = _solve_linearised(prob, state, model, g, screening)
        res, is_phase = sol.residuals, sol.is_phase
        log.info("iteration %d: max position correction %.4f m, code RMS %.3f m, phase RMS "
                 "%.4f m, rejected %d code / %d phase", iteration, sol.shift_m,
                 np.sqrt(np.mean(res[~is_phase]**2)), np.sqrt(np.mean(res[is_phase]**2)),
                 int(prob.code_rej.sum()), int(prob.phase_rej.sum()))
        state = _update(prob, state, sol)
        correction = base + sol.dx[:prob.k_orbit]
        base = correction if sol.shift_m < _INTEGRATE_ABOVE_M else None
        if sol.shift_m < settings.screen_below_m and not screening:
            screening = True
            continue
        if screening and sol.shift_m < settings.tolerance_m:
            converged = True
            break
    if converged:
        orbit = CorrectedOrbit(traj, prob.pulses, prob.est, correction)
    else:
        log.warning("float POD: not converged after %d iterations", settings.max_iterations)
        t_eval = prob.t_nom_s - np.nan_to_num(prob.clk_rx_m) / C_LIGHT_M_S
        orbit = CorrectedOrbit(prob.integrate(state, t_eval), prob.pulses, prob.est,
                               np.zeros(prob.k_orbit))
    return _result("float POD", prob, state, orbit, model, sol, iteration, converged)


class FixedPod:
    """Ambiguity-fixed solutions of an arc in one linearisation at its float solution.

    The constraints of fixed single-difference ambiguities (Peng et al. 2021, sec. III-B)
    move the converged float solution by their effect only, at the cm level. So the
    observation equations are built once, at the float estimates (orbit integrated with its
    variational equations at the float parameters, observation model at the float receiver
    clocks), and each set of constraints is one solve of that system, with the outlier
    screening of :func:`float_pod` continued from the float outliers; the orbit is the
    integrated one plus the correction through its partials (:class:`CorrectedOrbit`). The
    linearisation error is of the order of ``|Δr|²/r``: (1 cm)²/7000 km ≈ 1.4e-11 m for
    the cm-level float-to-fixed correction, so iterating further (a new integration at
    the fixed estimates, as the fixed POD did before) changes nothing that matters
    (tests/estimation/test_fixed_pod.py: 6e-7 m, the reproducibility of an integration).
    The receiver clocks that set the reception epochs are the float ones: a clock change of
    1 cm moves them by 33 ps, the orbit by 0.3 µm.

    Parameters
    ----------
    obs, products, force_model, t_ref, settings, eop, leo_pco_body_m, sat_pco_body_m, sat_pcv_m,
    leo_attitude, leo_antenna, cover_s
        As for :func:`float_pod` (the same as for the float solution).
    start : PodStart
        The float solution of the arc.
    float_orbit : tuple (Trajectory, ndarray), optional
        The float solution's orbit as its last integration, sampled at least at the epochs
        of this solution (reception epochs of the float clocks, output and pulse epochs), and
        its last correction (:class:`leopod.estimation.linearisation.FloatLinearisation`):
        the linearisation without an integration. None: integrate at the float estimates.
    """

    def __init__(self, obs: PodObservations, products: GnssProducts, force_model: ForceModel,
                 t_ref, settings: PodSettings, start: PodStart, *,
                 eop: EarthOrientation | None = None, leo_pco_body_m=None,
                 sat_pco_body_m: np.ndarray | None = None, sat_pcv_m=None,
                 leo_attitude: LeoAttitude | None = None, leo_antenna=None,
                 float_orbit: tuple | None = None,
                 cover_s: tuple[float, float] | None = None):
        self._prob = _Problem(obs, products, force_model, t_ref, settings, eop, leo_pco_body_m,
                              sat_pco_body_m, sat_pcv_m, leo_attitude, leo_antenna, cover_s)
        self._start = start
        p = self._prob
        _announce("fixed POD (linearised at the float solution)", p)
        orbit = None
        self._base = np.zeros(p.k_orbit)     # correction of the trajectory at the estimates
        if float_orbit is not None:
            orbit = CorrectedOrbit(float_orbit[0], p.pulses, p.est, float_orbit[1])
            self._base = orbit.correction
            log.info("fixed POD: orbit and partials of the float POD's last integration, "
                     "no integration")
        self._traj, self._model, self._g = p.linearise(p.load(start), orbit)
        # smallest orbit radius [m], scale of the linearisation error |Δr|²/r
        self._radius_m = float(np.min(np.linalg.norm(self._traj.states[:, :3], axis=1)))

    def solve(self, ambiguity_constraints=None) -> PodResult:
        """The solution with the constraints ``(pass_i, pass_j, value_m, sigma_m)``.

        Pseudo-observations ``B_i − B_j = value ± sigma`` of the ambiguities of passes
        ``pass_i``/``pass_j`` (values of ``obs.pass_index``); constraints on passes without
        used phase are skipped; None: no constraint (the float solution again).

        Returns
        -------
        PodResult
            One iteration; ``converged`` if the linearisation error ``|Δr|²/r`` (the next
            Gauss–Newton correction) of the largest position correction |Δr| is below
            ``tolerance_m``: for corrections up to ~80 m.
        """
        prob = self._prob
        state = prob.load(self._start)       # every solve starts from the float estimates
        sol = _solve_linearised(prob, state, self._model, self._g, True, ambiguity_constraints)
        second_order_m = sol.shift_m**2 / self._radius_m
        converged = second_order_m < prob.settings.tolerance_m
        log.info("fixed solution: max position correction %.4f m (linearisation error ~%.1e "
                 "m), rejected %d code / %d phase", sol.shift_m, second_order_m,
                 int(prob.code_rej.sum()), int(prob.phase_rej.sum()))
        if not converged:
            log.warning("fixed solution: its correction of %.1f m from the float solution "
                        "leaves a linearisation error of ~%.1e m, above tolerance_m",
                        sol.shift_m, second_order_m)
        state = _update(prob, state, sol)
        orbit = CorrectedOrbit(self._traj, prob.pulses, prob.est,
                               self._base + sol.dx[:prob.k_orbit])
        return _result("fixed POD", prob, state, orbit, self._model, sol, 1, converged)

    def normals(self, ambiguity_constraints=None, columns=None) -> ArcNormals:
        """The arc's reduced normal equations at the float solution, for a joint solution
        with another arc (:mod:`leopod.estimation.baseline`) or with parameters common to
        several arcs (:mod:`leopod.antenna.pcv_direct`).

        The rows are screened as in :meth:`solve` (continuing the float outliers); the
        a-priori constraints of the arc parameters are included.

        Parameters
        ----------
        ambiguity_constraints : tuple, optional
            As for :meth:`solve`: screening with them, and their pseudo-observations added
            (None: the float system).
        columns : callable, optional
            ``columns(model, pair, is_phase) -> scipy.sparse (r, x)``: further columns of
            the rows (:func:`leopod.estimation.normals.accumulate`) from the observation
            model (:class:`~leopod.estimation.obsmodel.ModelResult`), the observation index
            ``pair`` (r,) and the phase flag ``is_phase`` (r,) of each row; their unknowns
            follow the ambiguities, without a-priori constraint.
        """
        prob = self._prob
        if ambiguity_constraints is not None and np.asarray(ambiguity_constraints[0]).size == 0:
            ambiguity_constraints = None
        state = prob.load(self._start)
        sol = _solve_linearised(prob, state, self._model, self._g, True, ambiguity_constraints)
        extra = None if columns is None else columns(self._model, sol.pair, sol.is_phase)
        ne = accumulate(sol.rows, extra)
        n = ne.rhs.size - prob.k
        ne.matrix[np.diag_indices_from(ne.matrix)] += np.concatenate(
            [prob.constraint_weight, np.zeros(n)])
        ne.rhs += np.concatenate([prob.constraint_rhs(state), np.zeros(n)])
        if ambiguity_constraints is not None:
            constrain_differences(ne, prob.k, sol.active, prob.ambiguity, ambiguity_constraints)
        return ArcNormals(normals=ne, k=prob.k, active=sol.active,
                          ambiguity_m=prob.ambiguity[sol.active].copy(), _solution=sol,
                          _state=state, names=tuple(prob.names),
                          values=prob.current_vector(state), t_ref=prob.t_ref,
                          pulse_epochs_s=(np.empty(0) if prob.pulses is None
                                          else prob.pulses.epochs_s.copy()))

    def solution(self, normals: ArcNormals, dx: np.ndarray, covariance: np.ndarray,
                 label: str = "baseline solution") -> PodResult:
        """The arc's solution for a correction ``dx`` (k + a,) of the parameters of
        :meth:`normals` (obtained elsewhere, e.g. jointly with another arc) and its
        covariance ``covariance`` (k + a, k + a) in units of the weights (scaled by the
        arc's own σ0² in the result). Once per :meth:`normals` (the correction is applied to
        the estimates that it loaded)."""
        prob = self._prob
        sol = normals._solution
        clocks, res = epoch_clocks(sol.rows, dx)
        shift = float(np.max(np.linalg.norm(np.einsum("mik,k->mi", self._g[:, :, :prob.k],
                                                      dx[:prob.k]), axis=1)))
        sol = _Solution(rows=sol.rows, pair=sol.pair, is_phase=sol.is_phase, active=sol.active,
                        dx=dx, cov=covariance, clocks=clocks, residuals=res, shift_m=shift)
        state = _update(prob, normals._state.copy(), sol)
        orbit = CorrectedOrbit(self._traj, prob.pulses, prob.est, self._base + dx[:prob.k_orbit])
        converged = shift**2 / self._radius_m < prob.settings.tolerance_m
        return _result(label, prob, state, orbit, self._model, sol, 1, converged)


@dataclass(eq=False)
class ArcNormals:
    """Reduced normal equations of an arc linearised at its float solution
    (:meth:`FixedPod.normals`).

    Attributes
    ----------
    normals : NormalEquations
        Over ``[arc parameters (k), ambiguities of the passes active (a)]`` (and the further
        columns of :meth:`FixedPod.normals`, after them), a-priori constraints of the arc
        parameters included.
    k : int
        Number of arc parameters.
    active : ndarray of int, shape (a,)
        Pass ids (``obs.pass_index`` values) of the ambiguity columns.
    ambiguity_m : ndarray, shape (a,)
        Ambiguity values [m] at the linearisation (misclosures of constraints refer to them).
    names : tuple of str, length k
        Names of the arc parameters (``x0_m`` …, force-model parameters, ``pulse_R_0`` …).
    values : ndarray, shape (k,)
        Their values at the linearisation (SI units; pulses [m/s]).
    t_ref : datetime64
        Reference epoch of the arc (force-model and pulse times count from it).
    pulse_epochs_s : ndarray, shape (n_pulses,)
        Epochs of the pulses [s since ``t_ref``] (empty without pulses).
    """

    normals: NormalEquations
    k: int
    active: np.ndarray
    ambiguity_m: np.ndarray
    _solution: _Solution
    _state: np.ndarray
    names: tuple = ()
    values: np.ndarray | None = None
    t_ref: np.datetime64 | None = None
    pulse_epochs_s: np.ndarray | None = None

    @property
    def rows(self) -> Rows:
        """The screened observation rows of the normal equations."""
        return self._solution.rows

"""Kinematic POD: epoch-wise LEO positions and clocks with pass ambiguities shared by epochs.

The kinematic orbit of gravity-field users (Švehla & Rothacher 2005; Jäggi et al. 2007): no
force model, one position ``r_e`` (GCRF, at the true reception time) and one receiver clock
``c_e`` per epoch, from the undifferenced ionosphere-free code and phase of the reduced-
dynamic POD, with one float ambiguity per pass common to all its epochs. The observation
model, antenna offsets, attitude, weights, elevation mask and outlier threshold are those of
the float POD (:mod:`leopod.estimation.obsmodel`, :class:`PodSettings`); the linearisation
starts at a reference orbit (the reduced-dynamic float orbit of the arc) and is iterated at
the kinematic positions until the largest correction is below ``tolerance_m``.

Normal equations. Per epoch, the rows ``l_r = a_rᵀ y_e + B_{p(r)} + v_r`` with
``a_r = [−los_r, 1]`` and ``y_e = [δr_e, c_e]`` give the 4 × 4 block ``N_e = Σ w a aᵀ``, its
right-hand side ``b_e`` and the coupling ``N_eB`` to the ambiguities of the passes observed at
the epoch. The epoch parameters are eliminated epoch by epoch (block-diagonal)::

    N_BB' = N_BB − Σ_e N_Be N_e⁻¹ N_eB,    b_B' = b_B − Σ_e N_Be N_e⁻¹ b_e,

the ambiguities solved (optionally with fixed single differences ``B_i − B_j`` of the
ambiguity step as tight pseudo-observations: the *kinematic fixed* orbit), and the epoch
parameters back-substituted, ``y_e = N_e⁻¹ (b_e − N_eB B)``, with their covariance
``N_e⁻¹ + N_e⁻¹ N_eB Q_BB N_Be N_e⁻¹`` (scaled by σ0²).

Epochs with fewer than ``min_satellites`` satellites with code, or whose PDOP of the code
geometry exceeds ``max_pdop``, are not solved (their observations are left out and they are
reported); epochs whose formal 3D sigma exceeds ``max_sigma_m`` (in practice those whose
passes all begin there, positioned by the code alone) are solved but reported as not solved.
The variance factors of code and phase are estimated (Förstner 1979, with the exact
redundancy numbers of the rows) and scale the weights, so that the covariances describe the
data rather than the a-priori sigmas. Outliers are screened as in the float POD, from the first linearisation on (at the
reference orbit the observations are already cm from their model), but on residuals
standardised with their redundancy numbers: beyond ``outlier_k`` robust standard deviations of their type (code,
phase) they are rejected, the largest of each epoch per round, repeatedly.
Several GNSS (the rows of :func:`solve_kinematic`, e.g. a combined baseline): one code
inter-system bias per further system, constant over the arc, is estimated like an ambiguity
(a column common to all epochs); the phase biases go into the ambiguities. The kinematic POD
step keeps to one GNSS per POD line.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from leopod.astro.sun import sun_position_ef
from leopod.constants import C_LIGHT_M_S
from leopod.estimation.float_pod import (
    PodObservations,
    PodSettings,
    constrain_differences,
    elevation_sigma,
    robust_scale,
)
from leopod.estimation.normals import NormalEquations, solve
from leopod.estimation.obsmodel import Pairs, compute_model
from leopod.frames.earth_rotation import gcrf_from_itrf_matrices
from leopod.frames.leo_attitude import LeoAttitude
from leopod.frames.rtn import rtn_matrix
from leopod.gnss.products import GnssProducts
from leopod.numerics.interpolate import interpolate_table
from leopod.settings import Settings
from leopod.time.calendar import seconds_since

__all__ = ["KinematicModel", "KinematicResult", "KinematicSettings", "kinematic_dataset",
           "kinematic_pod", "kinematic_sp3_dataset", "orbit_state", "pdop_of_epochs",
           "solve_kinematic"]

log = logging.getLogger(__name__)

_N_EPOCH = 4                     # dx, dy, dz, clock
_MAX_SCREEN_ROUNDS = 50
#: The variance factors of code and phase are re-estimated until every new estimate is
#: within 1 ± this.
_FACTOR_TOLERANCE = 0.05
#: Rows with a smaller redundancy number are not tested for outliers.
_MIN_REDUNDANCY = 0.05


@dataclass(frozen=True)
class KinematicSettings(Settings):
    """Settings of the kinematic POD (config ``kinematic``).

    Attributes
    ----------
    enabled : bool
        Run the kinematic_pod step.
    ambiguities : str
        ``float`` or ``fixed`` (fixed single differences of the ambiguity step as
        constraints).
    max_pdop : float
        Epochs with a larger PDOP of the code geometry are not solved.
    min_satellites : int
        Epochs with fewer satellites with code are not solved.
    max_sigma_m : float
        Epochs whose formal 3D position sigma exceeds this are reported not solved [m].
    max_iterations : int
        Largest number of linearisations.
    tolerance_m : float
        Convergence: largest position correction of an iteration [m].
    baseline_systems : tuple of str
        GNSS of the kinematic baselines of formation pairs
        (:mod:`leopod.estimation.kinematic_baseline`); empty: none.
    """

    SCHEMA_DEF = "kinematic"

    enabled: bool
    ambiguities: str
    max_pdop: float
    min_satellites: int
    max_sigma_m: float
    max_iterations: int
    tolerance_m: float
    baseline_systems: tuple[str, ...]


@dataclass(eq=False)
class KinematicResult:
    """Outcome of :func:`kinematic_pod` (epoch axis of the observations, m epochs).

    Attributes
    ----------
    times : ndarray of datetime64[ns], shape (m,)
        Nominal epochs (receiver time tags, GPS time).
    pos_gcrf_m : ndarray, shape (m, 3)
        Kinematic centre-of-mass positions at the nominal epochs (GCRF) [m] (NaN: not solved).
    cov_gcrf_m2 : ndarray, shape (m, 3, 3)
        Their formal covariance, σ0-scaled [m²].
    clock_m : ndarray, shape (m,)
        Receiver clock [m] (NaN: not solved).
    clock_sigma_m : ndarray, shape (m,)
        Formal sigma of the clock [m].
    reference_gcrf_m, reference_vel_gcrf_m_s : ndarray, shape (m, 3)
        Reference orbit at the nominal epochs (GCRF) [m, m/s].
    solved : ndarray of bool, shape (m,)
    n_satellites : ndarray of int, shape (m,)
        Satellites with usable code at the epoch.
    pdop : ndarray, shape (m,)
        PDOP of the code geometry (NaN with fewer than 4 satellites).
    ambiguity_pass : ndarray of int, shape (a,)
    ambiguity_m : ndarray, shape (a,)
        Estimated IF ambiguities [m] of the passes.
    code_residual_m, phase_residual_m : ndarray, shape (n,)
        Post-fit residuals per observation pair (NaN where not used).
    sigma0 : float
    iterations : int
    converged : bool
    n_constraints : int
        Single-difference constraints in the solution.
    isb_m : ndarray, shape (k − 1,)
        Inter-system code biases of the systems after the first [m] (NaN: no code of that
        system); empty for one system.
    """

    times: np.ndarray
    pos_gcrf_m: np.ndarray
    cov_gcrf_m2: np.ndarray
    clock_m: np.ndarray
    clock_sigma_m: np.ndarray
    reference_gcrf_m: np.ndarray
    reference_vel_gcrf_m_s: np.ndarray
    solved: np.ndarray
    n_satellites: np.ndarray
    pdop: np.ndarray
    ambiguity_pass: np.ndarray
    ambiguity_m: np.ndarray
    code_residual_m: np.ndarray
    phase_residual_m: np.ndarray
    sigma0: float
    iterations: int
    converged: bool
    n_constraints: int
    isb_m: np.ndarray = field(default_factory=lambda: np.zeros(0))


def pdop_of_epochs(epoch: np.ndarray, los: np.ndarray, m: int) -> tuple[np.ndarray, np.ndarray]:
    """Satellite count and PDOP per epoch of unit lines of sight.

    Parameters
    ----------
    epoch : ndarray of int, shape (r,)
        Epoch of each line of sight (one per satellite and epoch).
    los : ndarray, shape (r, 3)
        Unit vectors receiver → satellite.
    m : int
        Number of epochs.

    Returns
    -------
    count : ndarray of int, shape (m,)
    pdop : ndarray, shape (m,)
        ``√trace(Q[:3, :3])`` of ``Q = (GᵀG)⁻¹``, ``G = [−los, 1]`` (NaN below 4 satellites
        or for a singular geometry).
    """
    count = np.bincount(epoch, minlength=m)
    g = np.concatenate([-los, np.ones((los.shape[0], 1))], axis=1)
    n = np.zeros((m, _N_EPOCH, _N_EPOCH))
    np.add.at(n, epoch, g[:, :, None] * g[:, None, :])
    pdop = np.full(m, np.nan)
    ok = count >= _N_EPOCH
    ok[ok] = np.linalg.cond(n[ok]) < 1e12
    if ok.any():
        q = np.linalg.inv(n[ok])
        pdop[ok] = np.sqrt(np.trace(q[:, :3, :3], axis1=1, axis2=2))
    return count, pdop


@dataclass
class _EpochRows:
    """The rows of the solved epochs padded to ``(m, K)`` (pads: weight 0, pass −1)."""

    design: np.ndarray        # (m, K, 4)
    weight: np.ndarray        # (m, K)
    misclosure: np.ndarray    # (m, K)
    column: np.ndarray        # (m, K) ambiguity column of phase rows, −1 otherwise
    slot: tuple               # (epoch, k) of each row in the padded arrays
    n_amb: int


def _pad(epoch: np.ndarray, design, weight, misclosure, column, m: int, n_amb: int) -> _EpochRows:
    order = np.argsort(epoch, kind="stable")
    counts = np.bincount(epoch, minlength=m)
    first = np.concatenate([[0], np.cumsum(counts)[:-1]])
    k = np.empty(epoch.size, int)
    k[order] = np.arange(epoch.size) - first[epoch[order]]
    width = max(int(counts.max(initial=0)), 1)
    slot = (epoch, k)
    d = np.zeros((m, width, _N_EPOCH))
    w, l = np.zeros((m, width)), np.zeros((m, width))
    c = np.full((m, width), -1)
    d[slot], w[slot], l[slot], c[slot] = design, weight, misclosure, column
    return _EpochRows(design=d, weight=w, misclosure=l, column=c, slot=slot, n_amb=n_amb)


def _solve_epochs(r: _EpochRows, solved: np.ndarray, active: np.ndarray, constraints):
    """Eliminate the epoch parameters, solve the ambiguities, back-substitute (module doc).

    Returns the epoch parameters (m, 4) and their covariance (m, 4, 4), the ambiguities
    (n_amb,), all in units of the weights, the number of constraints used, and the
    redundancy number ``1 − w aᵀ Q a`` of each padded row (m, K) (``a`` the row's
    partials of ``[y_e, B]``, ``Q`` their covariance; Förstner 1979).
    """
    wd = r.design * r.weight[:, :, None]                                  # (m, K, 4)
    n_e = np.einsum("mki,mkj->mij", wd, r.design)
    b_e = np.einsum("mki,mk->mi", wd, r.misclosure)
    q_e = np.zeros_like(n_e)
    q_e[solved] = np.linalg.inv(n_e[solved])
    phase = r.column >= 0
    p = np.where(phase[:, :, None], wd, 0.0)                              # N_eB by row
    col = np.where(phase, r.column, 0)
    n_a = r.n_amb
    n_bb = np.zeros((n_a, n_a))
    np.add.at(n_bb, (col[phase], col[phase]), r.weight[phase])
    qp = np.einsum("mij,mkj->mki", q_e, p)                                # N_e⁻¹ N_eB
    reduce = np.einsum("mki,mli->mkl", p, qp)                             # (m, K, K)
    both = phase[:, :, None] & phase[:, None, :]
    np.add.at(n_bb, (np.broadcast_to(col[:, :, None], both.shape)[both],
                     np.broadcast_to(col[:, None, :], both.shape)[both]), -reduce[both])
    b_b = np.bincount(col[phase], weights=(r.weight * r.misclosure)[phase], minlength=n_a)
    b_b -= np.bincount(col[phase], weights=np.einsum("mki,mi->mk", qp, b_e)[phase],
                       minlength=n_a)
    ne = NormalEquations(matrix=n_bb, rhs=b_b, ltpl=0.0, n_rows=int(phase.sum()))
    n_constraints = 0
    if constraints is not None and len(constraints[0]) and n_a:
        # full ambiguity values are estimated: the misclosure of a constraint is its value
        constrain_differences(ne, 0, active, np.zeros(int(max(active.max(),
                                                            np.max(constraints[0]),
                                                            np.max(constraints[1]))) + 1),
                               constraints)
        n_constraints = int(np.count_nonzero(np.isin(constraints[0], active)
                                             & np.isin(constraints[1], active)))
    amb, q_bb = solve(ne) if n_a else (np.zeros(0), np.zeros((0, 0)))
    a_rows = np.where(phase, amb[col] if n_a else 0.0, 0.0)               # (m, K)
    y = np.einsum("mij,mj->mi", q_e, b_e - np.einsum("mki,mk->mi", p, a_rows))
    q_sub = np.where(both, q_bb[col[:, :, None], col[:, None, :]] if n_a else 0.0, 0.0)
    cov = q_e + np.einsum("mki,mkl,mlj->mij", qp, q_sub, qp)
    # variance of each row's adjusted value: aᵀ Q_yy a + 2 aᵀ Q_yB + Q_BB of its pass
    q_yb = -np.einsum("mki,mkl->mli", qp, q_sub)                          # (m, K, 4)
    a = r.design
    fitted = (np.einsum("mki,mij,mkj->mk", a, cov, a)
              + np.where(phase, 2.0 * np.einsum("mki,mki->mk", a, q_yb)
                         + np.diagonal(q_sub, axis1=1, axis2=2), 0.0))
    return y, cov, amb, n_constraints, 1.0 - r.weight * fitted


def orbit_state(orbit: xr.Dataset, times: np.ndarray, t_ref, dt_s=0.0) -> np.ndarray:
    """GCRF state (m, 6) [m, m/s] of an orbit dataset (``pos_gcrf_m``, ``vel_gcrf_m_s`` on
    ``time``) at ``times`` minus ``dt_s`` [s], interpolated (at most 60 s beyond its ends)."""
    t_ref = np.datetime64(t_ref, "ns")
    state, _ = interpolate_table(seconds_since(orbit.time.values, t_ref),
                                 np.concatenate([orbit.pos_gcrf_m.values,
                                                 orbit.vel_gcrf_m_s.values], axis=1),
                                 seconds_since(times, t_ref) - dt_s, max_extrapolation_s=60.0)
    return state


class KinematicModel:
    """Observation model of one receiver's rows at a reference orbit plus epoch offsets.

    Parameters
    ----------
    obs : PodObservations
    products : GnssProducts
    reference : xarray.Dataset
        Reference orbit (``pos_gcrf_m``, ``vel_gcrf_m_s`` on ``time``).
    t_ref : datetime64
        Time origin.
    eop : EarthOrientation or None
    antennas : dict
        ``leo_pco_body_m``, ``sat_pco_body_m``, ``sat_pcv_m``, ``leo_attitude``,
        ``leo_antenna`` of :func:`leopod.estimation.obsmodel.compute_model`.
    """

    def __init__(self, obs: PodObservations, products: GnssProducts, reference: xr.Dataset,
                 t_ref, eop, antennas: dict):
        self.obs, self.products, self.eop = obs, products, eop
        self.antennas = antennas
        self.t_ref = np.datetime64(t_ref, "ns")
        self.t_nom_prod_s = seconds_since(obs.times, products.ref)
        self.reference = reference
        self.sun = sun_position_ef(obs.times)
        self.pairs = Pairs(epoch=obs.epoch, isv=products.sv_index(obs.sv)[obs.sat],
                           sat=obs.sat)

    def reference_at(self, dt_s: np.ndarray) -> np.ndarray:
        """Reference state (m, 6) at the nominal epochs minus ``dt_s``."""
        return orbit_state(self.reference, self.obs.times, self.t_ref, dt_s)

    def model(self, offset: np.ndarray, clock_m: np.ndarray):
        """Model at the reference orbit plus ``offset`` (m, 3) at the reception times."""
        dt_s = np.nan_to_num(clock_m) / C_LIGHT_M_S
        state = self.reference_at(dt_s)
        times_true = self.obs.times - (dt_s * 1e9).round().astype("timedelta64[ns]")
        rot, _ = gcrf_from_itrf_matrices(times_true, eop=self.eop)
        pos = np.nan_to_num(state[:, :3]) + offset
        model = compute_model(self.pairs, self.t_nom_prod_s - dt_s, pos,
                              np.nan_to_num(state[:, 3:]), rot, self.products, self.sun,
                              nl_wavelength_m=self.obs.nl_wavelength_m, **self.antennas)
        model.valid &= np.isfinite(state).all(axis=1)[self.obs.epoch]
        return model, pos


def kinematic_pod(obs: PodObservations, products: GnssProducts, reference: xr.Dataset, t_ref,
                  pod: PodSettings, settings: KinematicSettings, *, eop=None,
                  leo_pco_body_m=None, sat_pco_body_m: np.ndarray | None = None,
                  sat_pcv_m=None, leo_attitude: LeoAttitude | None = None,
                  leo_antenna=None, constraints=None) -> KinematicResult:
    """Kinematic positions and clocks of an arc (module docstring).

    Parameters
    ----------
    obs : PodObservations
        One system only.
    products : GnssProducts
    reference : xarray.Dataset
        Reference orbit (``pos_gcrf_m``, ``vel_gcrf_m_s`` on ``time``, the schema of
        :func:`leopod.estimation.outputs.orbit_dataset`) covering the epochs, e.g. the
        reduced-dynamic float orbit.
    t_ref : datetime64
        Time origin (any epoch; the first of ``obs`` in the POD).
    pod : PodSettings
        Weights, elevation mask, ``outlier_k``, ``min_phase_obs``.
    settings : KinematicSettings
    eop, leo_pco_body_m, sat_pco_body_m, sat_pcv_m, leo_attitude, leo_antenna
        As for :func:`leopod.estimation.float_pod.float_pod`.
    constraints : tuple, optional
        ``(pass_i, pass_j, value_m, sigma_m)``: fixed single differences ``B_i − B_j``
        (:func:`leopod.estimation.fixed_arc.constraints_of`).

    Returns
    -------
    KinematicResult
    """
    if len(obs.system_order) != 1:
        raise ValueError(f"kinematic POD: one GNSS per arc, got {obs.system_order} (a combined "
                         "arc would need inter-system biases); use a single-system POD line")
    lin = KinematicModel(obs, products, reference, t_ref, eop,
                         {"leo_pco_body_m": leo_pco_body_m, "sat_pco_body_m": sat_pco_body_m,
                          "sat_pcv_m": sat_pcv_m, "leo_attitude": leo_attitude,
                          "leo_antenna": leo_antenna})
    return solve_kinematic(obs, lin.model, lin.reference_at,
                           np.nan_to_num(np.asarray(obs.clk_rx_m, dtype=float)), pod, settings,
                           constraints=constraints)


def solve_kinematic(obs: PodObservations, model_at, reference_at, clock0_m: np.ndarray,
                    pod: PodSettings, settings: KinematicSettings, *, constraints=None,
                    clock_offset_m: np.ndarray | None = None,
                    variance_factors=(1.0, 1.0), label: str = "kinematic POD"
                    ) -> KinematicResult:
    """Iterated epoch-wise solution of rows ``obs`` with the model ``model_at`` (module
    docstring): linearisation, PDOP and satellite-count checks, outlier screening, variance
    factors, convergence, positions at the nominal epochs.

    Parameters
    ----------
    obs : PodObservations
        Rows: ``epoch``, ``code_m``, ``phase_m``, ``pass_index`` (the ambiguity of a phase row;
        e.g. a receiver's passes, or the receiver single differences of a baseline).
    model_at : callable
        ``model_at(offset (m, 3), clock (m,)) -> (ModelResult, pos (m, 3))``: the model of every
        row (without the estimated clock and ambiguity) at the reference orbit plus ``offset``
        and the GCRF positions at the reception times, for the clocks ``clock`` [m].
    reference_at : callable
        ``reference_at(dt_s (m,)) -> state (m, 6)``: the reference orbit at the nominal epochs
        minus ``dt_s``.
    clock0_m : ndarray, shape (m,)
        Clocks of the first linearisation [m].
    pod, settings, constraints
        As for :func:`kinematic_pod`.
    clock_offset_m : ndarray, shape (m,), optional
        Added to the estimated clock for the reception times of the positions (a baseline's
        differential clock: the reference receiver's clock); 0 by default.
    variance_factors : (float, float)
        A-priori variance factors of code and phase relative to the elevation-dependent
        sigmas of ``pod`` (re-estimated).
    label : str
        Name in the log.

    Returns
    -------
    KinematicResult
    """
    m, n = obs.times.size, obs.epoch.size
    clock = np.asarray(clock0_m, dtype=float).copy()
    offset = np.zeros((m, 3))
    code_rej, phase_rej = np.zeros(n, bool), np.zeros(n, bool)
    factor = np.asarray(variance_factors, dtype=float).copy()   # code, phase
    converged = False
    for iteration in range(1, settings.max_iterations + 1):
        model, pos = model_at(offset, clock)
        usable = model.valid & (model.el_deg >= pod.min_elevation_deg)
        code_ok = np.isfinite(obs.code_m) & usable
        for _ in range(_MAX_SCREEN_ROUNDS):
            # the geometry of the codes in use (the screening may take an epoch below 4)
            code = code_ok & ~code_rej
            n_sat, pdop = pdop_of_epochs(obs.epoch[code], model.los_gcrf[code], m)
            solved = (n_sat >= settings.min_satellites) & (pdop <= settings.max_pdop)
            sol = _solve_linearised(obs, model, pod, solved, code, usable & ~phase_rej,
                                    constraints, factor)
            if _screen(sol, pod.outlier_k, code_rej, phase_rej):
                continue
            estimate = _variance_factors(sol)
            factor = factor * estimate
            if np.all(np.abs(estimate - 1.0) < _FACTOR_TOLERANCE):
                break
        shift = np.linalg.norm(sol["dpos"], axis=1)
        offset[solved] += sol["dpos"][solved]
        clock = np.where(solved, sol["clock"], clock)
        largest = float(shift[solved].max(initial=0.0))
        log.info("%s iteration %d: %d of %d epochs solved, largest position correction "
                 "%.4f m, sigma0 %.3f, rejected %d code / %d phase", label, iteration,
                 int(solved.sum()), m, largest, sol["sigma0"], int(code_rej.sum()),
                 int(phase_rej.sum()))
        if largest < settings.tolerance_m:
            converged = True
            break
    if not converged:
        log.warning("%s: not converged after %d iterations", label, settings.max_iterations)
    # epochs that the code alone positions (all their passes new): metres off, and their
    # formal sigmas say so
    sigma_3d = np.sqrt(np.abs(np.trace(sol["cov"][:, :3, :3], axis1=1, axis2=2)))
    imprecise = solved & ~(sigma_3d <= settings.max_sigma_m)
    solved = solved & ~imprecise
    dt_s = (clock if clock_offset_m is None else clock + clock_offset_m) / C_LIGHT_M_S
    ref_true = reference_at(dt_s)
    ref_nominal = reference_at(np.zeros(m))
    # the position at the nominal epoch: the one at the reception time moved by v·dt_rx
    pos_nominal = np.where(solved[:, None], pos + sol["dpos"] + ref_true[:, 3:] * dt_s[:, None],
                           np.nan)
    cov = np.where(solved[:, None, None], sol["cov"][:, :3, :3], np.nan)
    code_res, phase_res = np.full(n, np.nan), np.full(n, np.nan)
    code_res[sol["code_pairs"]] = sol["residual"][:sol["code_pairs"].size]
    phase_res[sol["phase_pairs"]] = sol["residual"][sol["code_pairs"].size:]
    log.info("%s: %d of %d epochs solved (%d with fewer than %d satellites, %d with "
             "PDOP above %.1f, %d with a formal 3D sigma above %.3f m), sigma0 %.3f, %d passes, "
             "%d constraints", label, int(solved.sum()), m,
             int((n_sat < settings.min_satellites).sum()), settings.min_satellites,
             int(((n_sat >= settings.min_satellites) & ~(pdop <= settings.max_pdop)).sum()),
             settings.max_pdop, int(imprecise.sum()), settings.max_sigma_m, sol["sigma0"],
             sol["active"].size, sol["n_constraints"])
    return KinematicResult(
        times=obs.times, pos_gcrf_m=pos_nominal, cov_gcrf_m2=cov,
        clock_m=np.where(solved, clock, np.nan),
        clock_sigma_m=np.where(solved, np.sqrt(np.abs(sol["cov"][:, 3, 3])), np.nan),
        reference_gcrf_m=ref_nominal[:, :3], reference_vel_gcrf_m_s=ref_nominal[:, 3:],
        solved=solved, n_satellites=n_sat, pdop=pdop, ambiguity_pass=sol["active"],
        ambiguity_m=sol["ambiguity"], code_residual_m=code_res, phase_residual_m=phase_res,
        sigma0=sol["sigma0"], iterations=iteration, converged=converged,
        n_constraints=sol["n_constraints"], isb_m=sol["isb"])


def _solve_linearised(obs: PodObservations, model, pod: PodSettings, solved: np.ndarray,
                      code: np.ndarray, phase: np.ndarray, constraints,
                      factor: np.ndarray) -> dict:
    """One solve at a linearisation: rows of the solved epochs, elimination, residuals.

    ``factor`` (2,): variance factors of code and phase scaling the a-priori variances.
    """
    in_solved = solved[obs.epoch]
    code = code & in_solved
    phase = phase & in_solved & (obs.pass_index >= 0) & np.isfinite(obs.phase_m)
    n_pass = int(obs.pass_index.max(initial=-1)) + 1
    counts = np.bincount(obs.pass_index[phase], minlength=n_pass)
    phase &= counts[np.maximum(obs.pass_index, 0)] >= pod.min_phase_obs
    active = np.flatnonzero(np.bincount(obs.pass_index[phase], minlength=n_pass))
    column = np.full(n_pass, -1)
    column[active] = np.arange(active.size)
    ic, ip = np.flatnonzero(code), np.flatnonzero(phase)
    pair = np.concatenate([ic, ip])
    is_phase = np.concatenate([np.zeros(ic.size, bool), np.ones(ip.size, bool)])
    el = model.el_deg[pair]
    sigma = np.where(is_phase, elevation_sigma(el, pod.phase_sigma_m, pod.weight_elevation_deg),
                     elevation_sigma(el, pod.code_sigma_m, pod.weight_elevation_deg))
    sigma = sigma * np.sqrt(factor[is_phase.astype(int)])
    observed = np.where(is_phase, obs.phase_m[pair], obs.code_m[pair])
    computed = np.where(is_phase, model.phase_m[pair], model.code_m[pair])
    design = np.concatenate([-model.los_gcrf[pair], np.ones((pair.size, 1))], axis=1)
    # one inter-system code bias per further system with code rows, a column after the
    # ambiguities (coefficient 1, like an ambiguity; the phase biases go into the ambiguities)
    row_system = obs.sat_system[obs.sat[pair]]
    coded = np.unique(row_system[~is_phase])
    isb_column = np.full(len(obs.system_order), -1)
    isb_column[coded[coded > 0]] = active.size + np.arange(int((coded > 0).sum()))
    amb_col = np.where(is_phase, column[obs.pass_index[pair]], isb_column[row_system])
    n_col = active.size + int((coded > 0).sum())
    m = solved.size
    rows = _pad(obs.epoch[pair], design, 1.0 / sigma**2, observed - computed, amb_col, m,
                n_col)
    y, cov, amb, n_constraints, redundancy = _solve_epochs(rows, solved, active, constraints)
    ep = obs.epoch[pair]
    residual = observed - computed - np.sum(design * y[ep], axis=1)
    with_col = amb_col >= 0
    residual[with_col] -= amb[amb_col[with_col]]
    w = 1.0 / sigma**2
    dof = max(pair.size - _N_EPOCH * int(solved.sum()) - n_col + n_constraints, 1)
    sigma0 = float(np.sqrt(np.sum(w * residual**2) / dof))
    isb = np.full(len(obs.system_order) - 1, np.nan)
    isb[isb_column[1:] >= 0] = amb[isb_column[1:][isb_column[1:] >= 0]]
    return {"dpos": y[:, :3], "clock": y[:, 3], "cov": cov * sigma0**2,
            "ambiguity": amb[:active.size], "isb": isb,
            "active": active, "residual": residual, "weight": w, "is_phase": is_phase,
            "code_pairs": ic, "phase_pairs": ip, "sigma0": sigma0,
            "n_constraints": n_constraints, "redundancy": redundancy[rows.slot], "epoch": ep}


def _variance_factors(sol: dict) -> np.ndarray:
    """Estimates ``vᵀPv / r`` of the variance factors of code and phase (2,) relative to the
    weights of ``sol``, ``r`` the sum of the redundancy numbers of the type's rows
    (Förstner 1979)."""
    wv2 = sol["weight"] * sol["residual"] ** 2
    out = np.ones(2)
    for i, sel in enumerate((~sol["is_phase"], sol["is_phase"])):
        r = float(sol["redundancy"][sel].sum())
        if r > 1.0:
            out[i] = float(wv2[sel].sum() / r)
    return out


def _screen(sol: dict, outlier_k: float, code_rej: np.ndarray, phase_rej: np.ndarray) -> int:
    """Reject code and phase outliers beyond ``outlier_k`` robust sigmas (in place).

    The residuals are standardised with their redundancy numbers ``r`` (Baarda's
    ``v / (σ √r)``): an epoch with few satellites leaves its rows little redundancy and small
    residuals, which would shrink the robust scale of the others; rows with
    ``r < _MIN_REDUNDANCY`` cannot be tested and are kept.
    """
    r = sol["redundancy"]
    testable = r >= _MIN_REDUNDANCY
    z = np.where(testable, sol["residual"] * np.sqrt(sol["weight"] / np.where(testable, r, 1.0)),
                 0.0)
    n_new = 0
    for is_phase, pairs, rejected in ((False, sol["code_pairs"], code_rej),
                                      (True, sol["phase_pairs"], phase_rej)):
        sel = sol["is_phase"] == is_phase
        zz = z[sel]
        bad = np.abs(zz) > outlier_k * robust_scale(z[sel & testable])
        # one per epoch and round, the largest (data snooping): a blunder spreads into the
        # residuals of its epoch's other rows through the epoch's position and clock
        ep = sol["epoch"][sel]
        worst = np.full(int(ep.max(initial=-1)) + 1, -1.0)
        np.maximum.at(worst, ep[bad], np.abs(zz[bad]))
        bad &= np.abs(zz) == worst[ep]
        rejected[pairs[bad]] = True
        n_new += int(bad.sum())
    return n_new


def kinematic_dataset(result: KinematicResult, *, eop=None) -> xr.Dataset:
    """The kinematic orbit as a Dataset: ITRF positions, 3 × 3 covariances, clocks, PDOP,
    satellite count, solved flag, and kinematic minus reference in RTN.

    Variables: ``pos_itrf_m`` (time, xyz) [m], ``cov_itrf_m2`` (time, xyz, xyz_) [m²],
    ``sigma_itrf_m`` (time, xyz) [m], ``clock_m`` / ``clock_sigma_m`` (time) [m], ``pdop``,
    ``n_satellites``, ``solved`` (time), ``diff_rtn_m`` (time, rtn) [m]: kinematic minus
    reference orbit in radial, along-track, cross-track.
    """
    rot, _ = gcrf_from_itrf_matrices(result.times, eop=eop)                # ITRF -> GCRF
    pos = np.einsum("mji,mj->mi", rot, result.pos_gcrf_m)
    cov = np.einsum("mji,mjk,mkl->mil", rot, result.cov_gcrf_m2, rot)
    rtn = rtn_matrix(result.reference_gcrf_m, result.reference_vel_gcrf_m_s)
    diff = np.einsum("mij,mj->mi", rtn, result.pos_gcrf_m - result.reference_gcrf_m)
    xyz = ["x", "y", "z"]
    return xr.Dataset(
        {
            "pos_itrf_m": (("time", "xyz"), pos, {"units": "m", "reference_frame": "ITRF",
                                                  "long_name": "kinematic centre-of-mass "
                                                  "position (NaN: epoch not solved)"}),
            "cov_itrf_m2": (("time", "xyz", "xyz_"), cov,
                            {"units": "m2", "long_name": "formal position covariance "
                             "(sigma0-scaled)", "reference_frame": "ITRF"}),
            "sigma_itrf_m": (("time", "xyz"), np.sqrt(np.diagonal(cov, axis1=1, axis2=2)),
                             {"units": "m", "long_name": "formal position sigma"}),
            "clock_m": (("time",), result.clock_m, {"units": "m",
                                                    "long_name": "receiver clock (c dt)"}),
            "clock_sigma_m": (("time",), result.clock_sigma_m,
                              {"units": "m", "long_name": "formal sigma of the clock"}),
            "pdop": (("time",), result.pdop, {"units": "1",
                                              "long_name": "PDOP of the code geometry"}),
            "n_satellites": (("time",), result.n_satellites,
                             {"units": "1", "long_name": "satellites with usable code"}),
            "solved": (("time",), result.solved.astype("i1"),
                       {"units": "1", "long_name": "1: epoch solved, 0: too few satellites "
                        "or PDOP too large"}),
            "diff_rtn_m": (("time", "rtn"), diff,
                           {"units": "m", "long_name": "kinematic minus reference orbit in "
                            "radial, along-track, cross-track"}),
        },
        coords={"time": result.times, "xyz": xyz, "xyz_": xyz, "rtn": ["R", "T", "N"]},
        attrs={"sigma0": result.sigma0, "iterations": result.iterations,
               "converged": int(result.converged), "sd_constraints": result.n_constraints,
               "epochs_solved": int(result.solved.sum()), "epochs": int(result.times.size)},
    )


def kinematic_sp3_dataset(ds: xr.Dataset, sat_id: str) -> xr.Dataset:
    """The kinematic orbit of :func:`kinematic_dataset` in the
    :func:`leopod.io.sp3_write.write_sp3` schema: ITRF positions, receiver clocks [s] and
    their formal sigmas (SP3-d record accuracy exponents); unsolved epochs are absent."""
    return xr.Dataset(
        {"pos_m": (("time", "sv", "xyz"), ds.pos_itrf_m.values[:, None, :]),
         "pos_sigma_m": (("time", "sv", "xyz"), ds.sigma_itrf_m.values[:, None, :]),
         "clk_s": (("time", "sv"), ds.clock_m.values[:, None] / C_LIGHT_M_S),
         "clk_sigma_s": (("time", "sv"), ds.clock_sigma_m.values[:, None] / C_LIGHT_M_S)},
        coords={"time": ds.time.values, "sv": [sat_id], "xyz": ["x", "y", "z"]},
        attrs={"time_system": "GPS"})

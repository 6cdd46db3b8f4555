"""The ambiguity-fixed POD of an arc: the float solution re-solved with the fixed ambiguities.

The single differences that the ambiguity step fixed and chose as independent
(``constrained`` in its table, :func:`leopod.ambiguity.resolve.resolve_arc`) become tight
constraints of the POD linearised once at the float solution
(:class:`leopod.estimation.float_pod.FixedPod`: one orbit integration and one observation
model per arc, at the float estimates, clocks and outliers; no dynamic fit; with the float
POD's last linearisation, :mod:`leopod.estimation.linearisation`, no integration either:
the orbit and its partials are the float POD's own). Fixes that
raise the phase residuals of their passes (:func:`leopod.ambiguity.screening.degraded_passes`)
have their constraints dropped and the same linearised system is solved again, at most
``max_rejection_rounds`` times.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import xarray as xr

from leopod.ambiguity.resolve import ArSettings
from leopod.ambiguity.screening import degraded_passes, drop_constraints
from leopod.codebias.apply import CodeCorrection
from leopod.dynamics.force_config import ForceModelSettings
from leopod.estimation.arc import ArcData, ArcOutputs, ArcSettings, arc_outputs, setup_arc
from leopod.estimation.float_pod import FixedPod, PodSettings
from leopod.estimation.linearisation import FloatLinearisation, reception_epochs_s
from leopod.estimation.outputs import pod_start
from leopod.frames.leo_attitude import LeoAttitude
from leopod.io.netcdf import load_netcdf
from leopod.signals import SystemSignals
from leopod.time.calendar import seconds_since

__all__ = ["FixedArc", "FixedSolutions", "FloatSolution", "constraints_of", "run_fixed_arc"]

log = logging.getLogger(__name__)


@dataclass(eq=False)
class FloatSolution:
    """The float solution of the arc (outputs of the float POD), read from its files.

    Attributes
    ----------
    parameters, ambiguities, residuals : xarray.Dataset
        Continued from (:func:`leopod.estimation.outputs.pod_start`).
    orbit : xarray.Dataset
        Its orbit: the reference (``apriori_diff_rtn_m``) of the fixed one.
    """

    parameters: xr.Dataset
    ambiguities: xr.Dataset
    residuals: xr.Dataset
    orbit: xr.Dataset

    @classmethod
    def read(cls, *, parameters, ambiguities, residuals, orbit) -> FloatSolution:
        """Read the float POD's netCDF files."""
        return cls(*(load_netcdf(p, f"float POD {kind}") for p, kind in (
            (parameters, "parameters"), (ambiguities, "ambiguities"), (residuals, "residuals"),
            (orbit, "orbit"))))


class FixedSolutions:
    """The arc linearised once at its float solution (one orbit integration, one observation
    model); each :meth:`solve` is one solve of that system with a set of constraints.

    Parameters
    ----------
    date, data, signals, arc, pod, forces, pco_body_m, code_correction, yaw_flips, eop, limits,
    attitude
        As for :func:`leopod.estimation.arc.run_arc` (those of the float solution).
    float_solution : FloatSolution
    linearisation : FloatLinearisation, optional
        The float POD's last linearisation at this arc's epochs: no orbit integration
        (None: one integration at the float estimates).
    """

    def __init__(self, date: str, data: ArcData, signals: SystemSignals, arc: ArcSettings,
                 pod: PodSettings, forces: ForceModelSettings, pco_body_m: Mapping | None,
                 float_solution: FloatSolution, *,
                 code_correction: CodeCorrection | None = None, yaw_flips=None, eop=None,
                 limits=None, attitude: LeoAttitude | None = None,
                 linearisation: FloatLinearisation | None = None):
        self.problem = setup_arc(date, data, signals, arc, forces, pco_body_m,
                                 code_correction=code_correction, yaw_flips=yaw_flips, eop=eop,
                                 limits=limits, apriori_orbit=float_solution.orbit.pos_itrf_m,
                                 attitude=attitude)
        start = pod_start(float_solution.parameters, float_solution.ambiguities,
                          float_solution.residuals, self.problem.observations)
        p = self.problem
        float_orbit = None
        if linearisation is not None:
            po = p.observations
            linearisation.check(p.t_ref, reception_epochs_s(
                seconds_since(po.times, p.t_ref), start.clk_rx_m, po.clk_rx_m),
                seconds_since(p.output_times, p.t_ref))
            float_orbit = (linearisation.trajectory, linearisation.correction)
        self._pod = FixedPod(p.observations, p.products, p.force_model, p.t_ref, pod, start,
                             eop=eop, float_orbit=float_orbit, cover_s=p.output_span_s,
                             **p.antennas)

    @property
    def pod(self) -> FixedPod:
        """The linearised system (its :meth:`~FixedPod.normals` for joint solutions)."""
        return self._pod

    def solve(self, constraints: tuple | None = None) -> ArcOutputs:
        """The solution with ``(pass_i, pass_j, value_m, sigma_m)`` (:func:`constraints_of`;
        None or none: the float solution again), and its datasets."""
        if constraints is not None and constraints[0].size == 0:
            constraints = None
        return arc_outputs(self.problem, self._pod.solve(constraints))


@dataclass(eq=False)
class FixedArc:
    """Result of :func:`run_fixed_arc`: the solution, the constraints it kept and the
    linearised system (for normal equations with further parameters,
    :meth:`FixedPod.normals`)."""

    arc: ArcOutputs
    constraints: tuple
    dropped_rounds: int
    pod: FixedPod | None = None


def constraints_of(table: xr.Dataset, sigma_m: float) -> tuple:
    """``(pass_i, pass_j, value_m, sigma_m)`` of the constrained single differences.

    Parameters
    ----------
    table : xarray.Dataset
        Table of the ambiguity step (``constrained``, ``fixed_if_m``, ``pass_i``, ``pass_j``).
    sigma_m : float
        Sigma given to every constraint [m].
    """
    sel = table.constrained.values == 1
    value = table.fixed_if_m.values[sel]
    return (table.pass_i.values[sel].astype(int), table.pass_j.values[sel].astype(int), value,
            np.full(value.shape, sigma_m))


def run_fixed_arc(date: str, data: ArcData, signals: SystemSignals, arc: ArcSettings,
                  pod: PodSettings, forces: ForceModelSettings, pco_body_m: Mapping | None,
                  table: xr.Dataset, float_solution: FloatSolution, settings: ArSettings, *,
                  code_correction: CodeCorrection | None = None, yaw_flips=None,
                  eop=None, attitude: LeoAttitude | None = None, limits=None,
                  linearisation: FloatLinearisation | None = None) -> FixedArc:
    """Ambiguity-fixed POD of the arc of ``date`` (module docstring).

    Parameters
    ----------
    date, data, signals, arc, pod, forces, pco_body_m, code_correction, yaw_flips, eop,
    attitude, limits
        As for :func:`leopod.estimation.arc.run_arc` (those of the float solution).
    linearisation : FloatLinearisation, optional
        As for :class:`FixedSolutions`.
    table : xarray.Dataset
        Single differences of the ambiguity step.
    float_solution : FloatSolution
    settings : ArSettings
        ``constraint_sigma_m``, ``max_residual_ratio`` and ``max_rejection_rounds``.

    Returns
    -------
    FixedArc
    """
    constraints = constraints_of(table, settings.constraint_sigma_m)
    log.info("%d fixed single differences constrain the solution (AR product: %s)",
             constraints[0].size, table.attrs.get("ar_product"))
    if table.attrs.get("product_guard") == "refused":
        log.warning("the AR product was refused (%s)", table.attrs.get("product_guard_reason"))
    if constraints[0].size == 0:
        log.warning("no fixed ambiguity: the fixed solution equals the float one")
    fixed = FixedSolutions(date, data, signals, arc, pod, forces, pco_body_m, float_solution,
                           code_correction=code_correction, yaw_flips=yaw_flips, eop=eop,
                           limits=limits, attitude=attitude, linearisation=linearisation)
    solution = fixed.solve(constraints)
    rounds = 0
    for _ in range(settings.max_rejection_rounds):
        bad = degraded_passes(float_solution.residuals, solution.residuals,
                              ratio=settings.max_residual_ratio)
        if bad.size == 0:
            break
        before = constraints[0].size
        constraints = drop_constraints(constraints, bad)
        log.warning("phase residuals of %d passes grew by more than x%.1f with the fixes: "
                    "%d of %d constraints dropped, solving again", bad.size,
                    settings.max_residual_ratio, before - constraints[0].size, before)
        solution = fixed.solve(constraints)
        rounds += 1
    log.info("%d constraints in the fixed solution", constraints[0].size)
    return FixedArc(arc=solution, constraints=constraints, dropped_rounds=rounds,
                    pod=fixed.pod)

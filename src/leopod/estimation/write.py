"""Products of a POD arc (rules ``float_pod`` and ``fixed_pod``): netCDF, SP3 and the log."""

from __future__ import annotations

import logging
import textwrap

import numpy as np

from leopod import __version__
from leopod.estimation.arc import ArcOutputs
from leopod.estimation.linearisation import linearisation_dataset
from leopod.estimation.outputs import sp3_dataset
from leopod.io.netcdf import write_netcdf
from leopod.io.sp3_write import write_sp3
from leopod.validation.quality_gate import GateSettings, Verdict, check, pod_figures, stamp

__all__ = ["ARC_PRODUCTS", "gate_arc", "log_arc", "write_arc", "write_linearisation"]

#: The files :func:`write_arc` writes (its path arguments).
ARC_PRODUCTS = ("orbit", "sp3", "sp3_arc", "residuals", "parameters", "ambiguities")

log = logging.getLogger(__name__)


def log_arc(arc: ArcOutputs, label: str) -> None:
    """Log the convergence, residual RMS, rejections and arc parameters of a solution."""
    res = arc.result
    log.info("%s: %d iterations (converged: %s), sigma0 %.3f", label, res.iterations,
             res.converged, res.sigma0)
    fit = ("" if arc.fit is None else f" after an initial fit of {arc.fit.integrations} "
           f"integrations, {arc.fit.force_evaluations} force evaluations (reduced model)")
    log.info("%d integrations, %d force evaluations%s", res.integrations,
             res.force_evaluations, fit)
    log.info("post-fit RMS: phase %.2f mm (%d obs), code %.3f m (%d obs)",
             1e3 * np.sqrt(np.nanmean(res.phase_residual_m**2)), int(res.phase_used.sum()),
             np.sqrt(np.nanmean(res.code_residual_m**2)), int(res.code_used.sum()))
    log.info("rejected: %d code, %d phase; passes (ambiguities): %d",
             int(res.code_rejected.sum()), int(res.phase_rejected.sum()), res.ambiguity_m.size)
    for name, value, sigma in zip(res.parameter_names, res.estimates, res.sigmas, strict=True):
        if not name.startswith("pulse_"):
            log.info("parameter %-16s %+.6e +- %.2e", name, value, sigma)


def gate_arc(arc: ArcOutputs, gate: GateSettings, label: str, day,
             sampling_s: float) -> Verdict:
    """The quality gate of a solution (:mod:`leopod.validation.quality_gate`): its figures
    and verdict logged (a warning unless ok) and kept in ``arc.parameters``' attributes.

    ``day`` (datetime64 or ISO date) is 00:00 of the day the orbit is for and
    ``sampling_s`` the observation sampling [s] (the coverage of the day refers to them).
    """
    start = np.datetime64(day, "ns")
    figures = pod_figures(arc.orbit, arc.residuals, arc.parameters,
                          (start, start + np.timedelta64(86_400, "s")), sampling_s)
    verdict = check(figures, gate, converged=arc.result.converged)
    log.info("%s: quality figures %s", label,
             ", ".join(f"{k} {v:.4g}" for k, v in figures.items()))
    (log.info if verdict.status == "ok" else log.warning)("%s: quality gate %s", label,
                                                          verdict)
    stamp(arc.parameters, figures, verdict)
    return verdict


def write_arc(arc: ArcOutputs, *, orbit, sp3, sp3_arc, residuals, parameters, ambiguities,
              step: str, kind: str, title: str, sp3_id: str, inputs, day,
              coordinate_system: str) -> None:
    """Write orbit (netCDF + SP3), residuals, parameters and ambiguities of a solution.

    Parameters
    ----------
    arc : ArcOutputs
    orbit, sp3, sp3_arc, residuals, parameters, ambiguities : str or Path
        Output paths (``sp3``: the day, 00:00 to before 24:00; ``sp3_arc``: the whole arc).
    step : str
        Processing step written into the metadata (rule name).
    kind : str
        ``"float"`` or ``"ambiguity-fixed"``, for titles.
    title : str
        Satellite and day.
    sp3_id : str
        Satellite id in the SP3 file.
    inputs : list of str
        Input files (provenance).
    day : datetime64 or str
        The day of the arc (its daily SP3).
    coordinate_system : str
        Reference frame of the GNSS orbits the arc used (:attr:`ArcData.coordinate_system`),
        the SP3 header's coordinate system and the netCDF orbit's ``reference_frame``.
    """
    common = {"step": step, "inputs": inputs, "time_system": "GPS"}
    write_netcdf(arc.orbit, orbit, reference_frame=f"{coordinate_system} and GCRF",
                 title=f"{kind} reduced-dynamic orbit {title}", **common)
    write_netcdf(arc.residuals, residuals, reference_frame="antenna",
                 title=f"{kind} POD residuals {title}", **common)
    write_netcdf(arc.parameters, parameters, title=f"{kind} POD parameters {title}",
                 **common)
    write_netcdf(arc.ambiguities, ambiguities, title=f"{kind} ambiguities {title}",
                 **common)
    t = arc.orbit.time.values
    for path, span, selected in ((sp3, "the day", day), (sp3_arc, "the whole arc", None)):
        text = (f"leopod {__version__}, {kind} reduced-dynamic orbit of {title}; this file: "
                f"{span} (arc {str(t[0])[:19]} to {str(t[-1])[:19]} GPS); record accuracies: "
                "formal sigmas")
        write_sp3(sp3_dataset(arc.orbit, sp3_id, day=selected), path, orbit_type="FIT",
                  coordinate_system=coordinate_system, comments=tuple(textwrap.wrap(text, 77)))


def write_linearisation(arc: ArcOutputs, path, *, title: str, inputs) -> None:
    """Write the float POD's last linearisation for the fixed POD
    (:mod:`leopod.estimation.linearisation`), uncompressed (doubles that do not compress,
    read once)."""
    write_netcdf(linearisation_dataset(arc.result, arc.observations, arc.orbit.time.values),
                 path, step="float_pod", inputs=inputs, time_system="GPS",
                 reference_frame="GCRF", title=f"float POD linearisation {title}",
                 compress=False)

"""Inputs and products of a POD arc (rules ``float_pod`` and ``fixed_pod``)."""

from __future__ import annotations

import logging
import textwrap

import numpy as np
import xarray as xr

from leopod.estimation.arc import ArcOutputs
from leopod.estimation.outputs import sp3_dataset
from leopod.io.antex import read_antex
from leopod.io.clock import read_rinex_clock
from leopod.io.netcdf import merge_days, write_netcdf
from leopod.io.sp3 import read_sp3
from leopod.io.sp3_write import write_sp3
from leopod.plots.pod import (
    plot_apriori_difference,
    plot_residual_skymap,
    plot_residuals_elevation,
    plot_residuals_time,
)

__all__ = ["ArcInputs", "log_arc", "write_arc"]

log = logging.getLogger(__name__)


class ArcInputs:
    """Inputs of :func:`leopod.estimation.arc.run_arc` read from a rule's input files.

    Attributes: ``obs``, ``quality``, ``leo`` (lists of daily datasets), ``orbit``, ``clock``
    (merged GNSS products), ``antex`` (or None), ``code_maps`` (or None), ``files`` (the
    input files, for provenance).
    """

    def __init__(self, inp):
        self.obs = [xr.load_dataset(p) for p in inp.obs]
        self.quality = [xr.load_dataset(p) for p in inp.quality]
        self.leo = [xr.load_dataset(p) for p in inp.leo]
        self.orbit = merge_days([read_sp3(p) for p in inp.orbit])
        self.clock = merge_days([read_rinex_clock(p) for p in inp.clock])
        self.antex = read_antex(inp.antex) if inp.get("antex") else None
        self.code_maps = xr.load_dataset(inp.code_bias) if inp.get("code_bias") else None
        self.files = [*inp.obs, *inp.quality, *inp.leo, *inp.orbit, *inp.clock]


def log_arc(arc: ArcOutputs, label: str) -> None:
    """Log the convergence, residual RMS, rejections and arc parameters of a solution."""
    res = arc.result
    log.info("%s: %d iterations (converged: %s), sigma0 %.3f", label, res.iterations,
             res.converged, res.sigma0)
    log.info("post-fit RMS: phase %.2f mm (%d obs), code %.3f m (%d obs)",
             1e3 * np.sqrt(np.nanmean(res.phase_residual_m**2)), int(res.phase_used.sum()),
             np.sqrt(np.nanmean(res.code_residual_m**2)), int(res.code_used.sum()))
    log.info("rejected: %d code, %d phase; passes (ambiguities): %d",
             int(res.code_rejected.sum()), int(res.phase_rejected.sum()), res.ambiguity_m.size)
    for name, value, sigma in zip(res.parameter_names, res.estimates, res.sigmas, strict=True):
        if not name.startswith("pulse_"):
            log.info("parameter %-16s %+.6e +- %.2e", name, value, sigma)


def write_arc(arc: ArcOutputs, out, *, step: str, kind: str, title: str, sp3_id: str,
              inputs) -> None:
    """Write orbit (netCDF + SP3), residuals, parameters, ambiguities and figures.

    Parameters
    ----------
    arc : ArcOutputs
    out : mapping
        Output paths: ``orbit``, ``sp3``, ``residuals``, ``parameters``, ``ambiguities``,
        ``res_time``, ``res_elevation``, ``res_skymap``, ``apriori``.
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
    """
    common = {"step": step, "inputs": inputs, "time_system": "GPS"}
    write_netcdf(arc.orbit, out.orbit, reference_frame="ITRF and GCRF",
                 title=f"{kind} reduced-dynamic orbit {title}", **common)
    write_netcdf(arc.residuals, out.residuals, reference_frame="antenna",
                 title=f"{kind} POD residuals {title}", **common)
    write_netcdf(arc.parameters, out.parameters, title=f"{kind} POD parameters {title}",
                 **common)
    write_netcdf(arc.ambiguities, out.ambiguities, title=f"{kind} ambiguities {title}",
                 **common)
    write_sp3(sp3_dataset(arc.orbit, sp3_id), out.sp3, orbit_type="FIT",
              comments=tuple(textwrap.wrap(f"leopod {kind} reduced-dynamic orbit {title}",
                                           77)))
    plot_residuals_time(arc.residuals, out.res_time, title=f"{kind} {title}")
    plot_residuals_elevation(arc.residuals, out.res_elevation, title=f"{kind} {title}")
    plot_residual_skymap(arc.residuals, out.res_skymap, title=f"{kind} {title}")
    plot_apriori_difference(arc.orbit, out.apriori, title=f"{kind} {title}")

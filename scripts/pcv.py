"""Rule pcv: receiver PCV of one satellite line and period by the residual method
(leopod.antenna.pcv) or the direct method (leopod.antenna.pcv_direct); leopod.io.antex_write,
leopod.plots.pcv."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

import logging
from collections.abc import Mapping

import xarray as xr

from leopod.antenna.pcv import (
    PcvSettings,
    apriori_pattern,
    estimated_pattern,
    pco_shift_neu,
    stack_residuals,
)
from leopod.antenna.pcv_direct import solve_normals
from leopod.io.antex_write import write_antex
from leopod.io.netcdf import load_netcdf, write_netcdf
from leopod.plots.pcv import plot_pcv_map
from leopod.workflow.boundary import leo_antenna_of, plain
from leopod.workflow.log import configure_logging

log = logging.getLogger("leopod.pcv")


def estimate(paths, settings: PcvSettings, *, sat: str, period: str, solution: str
             ) -> xr.Dataset:
    """The map of the period: phase residuals ``paths`` stacked (residual method) or the
    days' normal equations ``paths`` solved (direct method)."""
    if settings.method == "direct":
        return solve_normals((load_netcdf(p, "PCV normal equations") for p in paths),
                             settings, period=period, satellite=sat, solution=solution)
    residuals = []
    for path in paths:
        with xr.open_dataset(path) as f:
            residuals.append(f[["phase_residual_m", "el_deg", "az_deg",
                                "phase_rejected"]].load())
    return stack_residuals(residuals, settings, period=period, satellite=sat,
                           solution=solution)


def main(paths, outputs: Mapping, *, antenna, settings: PcvSettings, sat: str,
         period: str, solution: str, title: str) -> None:
    """Map of the POD days of the period (``paths``: residuals or normal equations,
    :func:`estimate`) into ``outputs``: ``nc``, ``antex`` (the POD's antenna ``antenna`` with
    the map, and the PCO-Z of the direct method, added) and ``map`` (figure)."""
    pcv = estimate(paths, settings, sat=sat, period=period, solution=solution)
    apriori, _ = apriori_pattern(antenna)
    pcv.attrs["apriori_antenna"] = getattr(antenna, "source", "antenna_pco_body_m table")
    write_netcdf(pcv, outputs["nc"], step="pcv", inputs=paths,
                 reference_frame="antenna", title=f"PCV map {title}")
    pattern = estimated_pattern(apriori, pcv, serial=sat[:20],
                                pco_shift_neu_m=pco_shift_neu(antenna, pcv))
    comments = [f"leopod rule pcv: {sat} {period}, {solution}, {settings.method} method",
                f"{len(paths)} days, {pcv.attrs['n_residuals']} phase observations",
                f"grid {settings.az_step_deg:g} x {settings.zenith_step_deg:g} deg, datum "
                f"{settings.datum}",
                "PCV = a-priori PCV + ionosphere-free map,",
                "filled in for every frequency; PCO as a priori"
                + (" + PCO-Z" if settings.estimate_pco_z else ""),
                f"a priori: {pcv.attrs['apriori_antenna']}"]
    write_antex(outputs["antex"], [pattern], comments=[c[:60] for c in comments])
    log.info("wrote %s (type %r) for satellites.%s.antenna", outputs["antex"],
             pattern.antenna_type, sat)
    plot_pcv_map(pcv, outputs["map"], title=title)


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    files = plain(sm.input)
    main(files["neq" if "neq" in files else "residuals"], plain(sm.output),
         antenna=leo_antenna_of(sm.params.pco_body_m, sm.params.leo_antenna, files),
         settings=PcvSettings.from_config(sm.params.settings), sat=sm.wildcards.sat,
         period=sm.wildcards.period, solution=sm.params.solution, title=sm.params.title)


if __name__ == "__main__":
    if "snakemake" not in globals():  # by hand: a job of the default campaign
        from leopod.workflow.boundary import mock_snakemake

        snakemake = mock_snakemake("pcv", sat="hy2b-sim", period="2019-01")
    run(snakemake)  # noqa: F821 (injected by Snakemake)

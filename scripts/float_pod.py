"""Snakemake script of rule float_pod: see leopod.estimation.arc."""

import numpy as np
import xarray as xr

from leopod.estimation.arc import merge_days, run_arc
from leopod.estimation.outputs import sp3_dataset
from leopod.io.antex import read_antex
from leopod.io.clock import read_rinex_clock
from leopod.io.sp3 import read_sp3, write_sp3
from leopod.netcdf import write_netcdf
from leopod.plots.pod import (
    plot_apriori_difference,
    plot_residual_skymap,
    plot_residuals_elevation,
    plot_residuals_time,
)
from leopod.workflow import configure_logging


def main(inp, out, params, date, log):
    obs = [xr.load_dataset(p) for p in inp.obs]
    quality = [xr.load_dataset(p) for p in inp.quality]
    leo = [xr.load_dataset(p) for p in inp.leo]
    orbit = merge_days([read_sp3(p) for p in inp.orbit])
    clock = merge_days([read_rinex_clock(p) for p in inp.clock])
    antex = read_antex(inp.antex) if inp.get("antex") else None
    code_maps = xr.load_dataset(inp.code_bias) if inp.get("code_bias") else None
    arc = run_arc(date, obs, quality, leo, orbit, clock, antex, params.signals, params.pod,
                  params.pco_body_m, code_maps=code_maps, code_bias_cfg=params.code_bias,
                  yaw_flips=params.yaw_flips)
    res = arc.result
    n_code, n_phase = int(res.code_used.sum()), int(res.phase_used.sum())
    log.info("float POD %s: %d iterations (converged: %s), sigma0 %.3f", date, res.iterations,
             res.converged, res.sigma0)
    log.info("post-fit RMS: phase %.2f mm (%d obs), code %.3f m (%d obs)",
             1e3 * np.sqrt(np.nanmean(res.phase_residual_m**2)), n_phase,
             np.sqrt(np.nanmean(res.code_residual_m**2)), n_code)
    log.info("rejected: %d code, %d phase; passes (float ambiguities): %d",
             int(res.code_rejected.sum()), int(res.phase_rejected.sum()),
             res.ambiguity_m.size)
    for name, value, sigma in zip(res.parameter_names, res.estimates, res.sigmas):
        if not name.startswith("pulse_"):
            log.info("parameter %-16s %+.6e +- %.2e", name, value, sigma)
    inputs = [*inp.obs, *inp.quality, *inp.leo, *inp.orbit, *inp.clock]
    common = {"step": "float_pod", "inputs": inputs, "time_system": "GPS"}
    write_netcdf(arc.orbit, out.orbit, reference_frame="ITRF and GCRF",
                 title=f"float reduced-dynamic orbit {params.title}", **common)
    write_netcdf(arc.residuals, out.residuals, reference_frame="antenna",
                 title=f"float POD residuals {params.title}", **common)
    write_netcdf(arc.parameters, out.parameters, title=f"float POD parameters {params.title}",
                 **common)
    write_netcdf(arc.ambiguities, out.ambiguities,
                 title=f"float ambiguities {params.title}", **common)
    write_sp3(sp3_dataset(arc.orbit, params.sp3_id), out.sp3, orbit_type="FIT",
              comments=(f"leopod float reduced-dynamic orbit {params.title}",))
    plot_residuals_time(arc.residuals, out.res_time, title=params.title)
    plot_residuals_elevation(arc.residuals, out.res_elevation, title=params.title)
    plot_residual_skymap(arc.residuals, out.res_skymap, title=params.title)
    plot_apriori_difference(arc.orbit, out.apriori, title=params.title)


if __name__ == "__main__":
    log = configure_logging(snakemake)  # noqa: F821 (injected by Snakemake)
    sm = snakemake  # noqa: F821
    main(sm.input, sm.output, sm.params, sm.wildcards.date, log)

"""Snakemake script of rule reference_orbit: a POD arc against a reference orbit over its day."""

import xarray as xr

from leopod.io.netcdf import write_netcdf
from leopod.validation.reference import compare_day, read_reference_orbit
from leopod.workflow.log import configure_logging


def main(inp, out, params, date, log):
    reference = read_reference_orbit(inp.reference, sv=params.reference_id)
    diff = compare_day(xr.load_dataset(inp.orbit), reference, date,
                       time_system=params.time_system)
    rms = diff.rms_m.sel(period="total")
    log.info("%s minus reference over %s (%d epochs): RMS R %.2f T %.2f N %.2f 3D %.2f cm",
             params.solution, date, int(diff.n_epochs.sel(period="total")),
             *(100 * float(rms.sel(component=c)) for c in ("R", "T", "N", "3D")))
    write_netcdf(diff, out.nc, step="reference_orbit", inputs=[inp.orbit, *inp.reference],
                 time_system="GPS", title=f"{params.solution} orbit minus reference "
                 f"{params.title}")


if __name__ == "__main__":
    log = configure_logging(snakemake)  # noqa: F821 (injected by Snakemake)
    sm = snakemake  # noqa: F821
    main(sm.input, sm.output, sm.params, sm.wildcards.date, log)

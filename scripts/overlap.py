"""Snakemake script of rule overlap: see leopod.validation.overlap."""

import xarray as xr

from leopod.io.netcdf import write_netcdf
from leopod.validation.overlap import overlap
from leopod.workflow.log import configure_logging


def main(inp, out, params, log):
    ov = overlap(xr.load_dataset(inp.a), xr.load_dataset(inp.b), trim_s=params.trim_s)
    rms = ov.rms_m
    log.info("overlap %s to %s (%d epochs): RMS R %.2f T %.2f N %.2f 3D %.2f cm",
             ov.attrs["span_start"], ov.attrs["span_end"], int(ov.n_epochs),
             *(100 * float(rms.sel(component=c)) for c in ("R", "T", "N", "3D")))
    write_netcdf(ov, out.nc, step="overlap", inputs=[inp.a, inp.b], time_system="GPS",
                 title=f"orbit overlap {params.title}")


if __name__ == "__main__":
    log = configure_logging(snakemake)  # noqa: F821 (injected by Snakemake)
    main(snakemake.input, snakemake.output, snakemake.params, log)  # noqa: F821

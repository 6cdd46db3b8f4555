"""Snakemake script of rule slr: laser ranging residuals of one POD arc (leopod.validation.slr)."""

import xarray as xr

from leopod.io.blq import read_blq
from leopod.io.crd import read_crd
from leopod.io.netcdf import write_netcdf
from leopod.io.sinex import read_sinex_eccentricities, read_sinex_stations
from leopod.validation.slr import SlrResidualSettings, slr_residuals
from leopod.workflow.log import configure_logging


def main(inp, out, params, log):
    cfg = {k: v for k, v in params.settings.items()
           if k not in ("elevation_bin_deg", "ocean_loading_blq")}
    res = slr_residuals(
        xr.load_dataset(inp.orbit), read_crd(inp.normal_points),
        read_sinex_stations(inp.stations),
        read_sinex_eccentricities(inp.eccentricities) if inp.get("eccentricities") else None,
        retro_offset_body_m=params.retro_offset_body_m, settings=SlrResidualSettings(**cfg),
        ocean_loading=read_blq(inp.ocean_loading) if inp.get("ocean_loading") else None)
    write_netcdf(res, out.nc, step="slr", inputs=[v for k, v in inp.items() if k != "code"],
                 time_system="UTC", reference_frame="ITRF",
                 title=f"SLR residuals of the {params.solution} orbit {params.title}")


if __name__ == "__main__":
    log = configure_logging(snakemake)  # noqa: F821 (injected by Snakemake)
    main(snakemake.input, snakemake.output, snakemake.params, log)  # noqa: F821

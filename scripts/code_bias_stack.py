"""Snakemake script of rule code_bias_stack: see leopod.codebias.products.stack_maps."""

import itertools

import xarray as xr

from leopod.codebias.products import map_difference, stack_maps
from leopod.io import write_text
from leopod.io.netcdf import write_netcdf
from leopod.plots.codebias import plot_code_bias_maps, plot_map_difference
from leopod.workflow.log import configure_logging


def main(inp, out, params, log):
    maps = [xr.load_dataset(p) for p in inp.maps]
    stacked = stack_maps(maps)
    write_netcdf(stacked, out.nc, step="code_bias_stack", inputs=inp.maps, time_system="GPS",
                 reference_frame="antenna", title=f"stacked code-bias maps {params.title}")
    lines = ["period_a,period_b,signal,mode,rms_difference_m"]
    for a, b in itertools.pairwise(maps):
        _, rms = map_difference(a, b)
        for sig in rms.signal.values:
            for mode in rms.mode.values:
                value = float(rms.sel(signal=sig, mode=mode))
                lines.append(f"{a.attrs['period']},{b.attrs['period']},{sig},{mode},{value:.4f}")
                log.info("map difference %s - %s %s mode %d: RMS %.3f m", b.attrs["period"],
                         a.attrs["period"], sig, mode, value)
    write_text(out.differences, "\n".join(lines) + "\n")
    plot_code_bias_maps(stacked, out.maps, title=f"stacked code-bias maps {params.title}")
    plot_map_difference(maps[-2], maps[-1], out.difference,
                        title=f"{params.title} {maps[-1].attrs['period']} minus "
                              f"{maps[-2].attrs['period']}")


if __name__ == "__main__":
    log = configure_logging(snakemake)  # noqa: F821 (injected by Snakemake)
    main(snakemake.input, snakemake.output, snakemake.params, log)  # noqa: F821

"""Snakemake script of rule reference_summary: daily and total reference-orbit statistics
(seed 001 Table 4, seed 002 Fig. 17)."""

import pandas as pd
import xarray as xr

from leopod.io import write_text
from leopod.io.netcdf import write_netcdf
from leopod.plots.validation import plot_daily_statistics, plot_reference_differences
from leopod.validation.orbit_statistics import orbit_statistics, statistics_table
from leopod.workflow.log import configure_logging


def main(inp, out, params, log):
    diffs, stats = {}, {}
    for solution in params.solutions:
        days = [xr.load_dataset(p)[["diff_rtn_m", "diff_3d_m"]] for p in inp[solution]]
        diffs[solution] = xr.concat(days, dim="time")
        stats[solution] = orbit_statistics(diffs[solution].dropna("time"), daily=True)
        rms = stats[solution].rms_m.sel(period="total")
        log.info("%s minus reference, campaign: RMS R %.2f T %.2f N %.2f 3D %.2f cm", solution,
                 *(100 * float(rms.sel(component=c)) for c in ("R", "T", "N", "3D")))
    ds = xr.concat(list(stats.values()), dim=pd.Index(list(stats), name="solution"))
    write_netcdf(ds, out.nc, step="reference_summary",
                 inputs=[f for s in params.solutions for f in inp[s]], time_system="GPS",
                 title=f"orbit minus reference, daily statistics {params.title}")
    tables = [statistics_table(s).assign(solution=k).set_index("solution", append=True)
              for k, s in stats.items()]
    write_text(out.csv, pd.concat(tables).to_csv(float_format="%.5f"))
    plot_reference_differences(diffs, out.differences, title=params.title)
    plot_daily_statistics(stats, out.daily, title=params.title)


if __name__ == "__main__":
    log = configure_logging(snakemake)  # noqa: F821 (injected by Snakemake)
    main(snakemake.input, snakemake.output, snakemake.params, log)  # noqa: F821

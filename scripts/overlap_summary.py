"""Snakemake script of rule overlap_summary: campaign overlap statistics (seed 002 Fig. 13)."""

import pandas as pd
import xarray as xr

from leopod.io import write_text
from leopod.io.netcdf import write_netcdf
from leopod.plots.validation import plot_overlaps
from leopod.validation.orbit_statistics import statistics_table
from leopod.validation.overlap import overlap_summary
from leopod.workflow.log import configure_logging


def main(inp, out, params, log):
    summaries = {}
    for solution in params.solutions:
        files = list(inp[solution])
        summaries[solution] = overlap_summary([xr.load_dataset(p) for p in files])
        camp = summaries[solution]
        log.info("%s overlaps (%d pairs): 3D RMS %.2f +- %.2f cm", solution, len(files),
                 100 * float(camp.campaign_rms_mean_m.sel(component="3D")),
                 100 * float(camp.campaign_rms_std_m.sel(component="3D")))
    ds = xr.concat(list(summaries.values()), dim=pd.Index(list(summaries), name="solution"))
    write_netcdf(ds, out.nc, step="overlap_summary", inputs=[f for s in params.solutions
                                                              for f in inp[s]],
                 time_system="GPS", title=f"orbit overlaps {params.title}")
    tables = [statistics_table(s).assign(solution=k).set_index("solution", append=True)
              for k, s in summaries.items()]
    write_text(out.csv, pd.concat(tables).to_csv(float_format="%.5f"))
    plot_overlaps(summaries, out.figure, title=f"{params.title} overlaps")


if __name__ == "__main__":
    log = configure_logging(snakemake)  # noqa: F821 (injected by Snakemake)
    main(snakemake.input, snakemake.output, snakemake.params, log)  # noqa: F821

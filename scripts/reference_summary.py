"""Rule reference_summary: daily and total reference-orbit statistics
(Wang et al. 2024, Table 4; Jiang et al. 2023, Fig. 17)."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

import logging
from collections.abc import Mapping

import pandas as pd
import xarray as xr

from leopod.io import write_text
from leopod.io.netcdf import load_netcdf, write_netcdf
from leopod.plots.tables import frame_tables, html_page
from leopod.plots.validation import plot_daily_statistics, plot_reference_differences
from leopod.validation.orbit_statistics import orbit_statistics, statistics_table
from leopod.workflow.boundary import plain
from leopod.workflow.log import configure_logging

log = logging.getLogger(__name__)


def main(differences: Mapping, outputs: Mapping, *, title: str) -> None:
    """Statistics of the daily difference files of every solution (``{solution: [paths]}``)
    into ``outputs``: ``nc``, ``csv``, ``html`` (report table), ``differences`` and ``daily``
    (PNG)."""
    diffs, stats = {}, {}
    for solution, files in differences.items():
        days = [load_netcdf(p)[["diff_rtn_m", "diff_3d_m"]] for p in files]
        diffs[solution] = xr.concat(days, dim="time")
        stats[solution] = orbit_statistics(diffs[solution].dropna("time"), daily=True)
        rms = stats[solution].rms_m.sel(period="total")
        log.info("%s minus reference, campaign: RMS R %.2f T %.2f N %.2f 3D %.2f cm", solution,
                 *(100 * float(rms.sel(component=c)) for c in ("R", "T", "N", "3D")))
    ds = xr.concat(list(stats.values()), dim=pd.Index(list(stats), name="solution"))
    write_netcdf(ds, outputs["nc"], step="reference_summary",
                 inputs=[f for files in differences.values() for f in files], time_system="GPS",
                 title=f"orbit minus reference, daily statistics {title}")
    tables = [statistics_table(s).assign(solution=k).set_index("solution", append=True)
              for k, s in stats.items()]
    write_text(outputs["csv"], pd.concat(tables).to_csv(float_format="%.5f"))
    write_text(outputs["html"], html_page(f"{title}: orbit minus reference", frame_tables(
        {k: statistics_table(s) for k, s in stats.items()}, row_header="day",
        missing="no value", aggregate=lambda label: label == "total")))
    plot_reference_differences(diffs, outputs["differences"], title=title)
    plot_daily_statistics(stats, outputs["daily"], title=title)


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    files = plain(sm.input)
    main({s: files[s] for s in sm.params.solutions}, plain(sm.output), title=sm.params.title)


if __name__ == "__main__":
    if "snakemake" not in globals():  # by hand: a job of the default campaign
        from leopod.workflow.boundary import mock_snakemake

        snakemake = mock_snakemake("reference_summary", sat="hy2b-sim")
    run(snakemake)  # noqa: F821 (injected by Snakemake)

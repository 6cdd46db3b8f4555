"""Rule overlap_summary: campaign overlap statistics (Jiang et al. 2023, Fig. 13)."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

import datetime as dt
import logging
from collections.abc import Mapping
from pathlib import Path

import pandas as pd
import xarray as xr

from leopod.io import write_text
from leopod.io.netcdf import load_netcdf, write_netcdf
from leopod.plots.tables import frame_tables, html_page
from leopod.plots.validation import plot_overlaps
from leopod.time.calendar import parse_date_id
from leopod.validation.orbit_statistics import statistics_table
from leopod.validation.overlap import overlap_summary
from leopod.workflow.boundary import plain
from leopod.workflow.log import configure_logging

log = logging.getLogger(__name__)


def _pair_label(path) -> str:
    """Label of the overlap file ``<day>.nc`` (day ``YYYY-DDD`` of arc a): the ISO date of the
    next day, which arc b is centred on - from the name, not from the span compared, which a
    day with little data shortens (two labels from spans would then coincide)."""
    return (parse_date_id(Path(path).stem) + dt.timedelta(days=1)).isoformat()


def main(overlaps: Mapping, outputs: Mapping, *, title: str) -> None:
    """Summary of the overlap files of every solution (``{solution: [paths]}``) into
    ``outputs``: ``nc``, ``csv``, ``html`` (report table) and ``figure``."""
    summaries = {}
    for solution, files in overlaps.items():
        summaries[solution] = overlap_summary([load_netcdf(p) for p in files],
                                              labels=[_pair_label(p) for p in files])
        camp = summaries[solution]
        log.info("%s overlaps (%d pairs): 3D RMS %.2f +- %.2f cm", solution, len(files),
                 100 * float(camp.campaign_rms_mean_m.sel(component="3D")),
                 100 * float(camp.campaign_rms_std_m.sel(component="3D")))
    ds = xr.concat(list(summaries.values()), dim=pd.Index(list(summaries), name="solution"))
    write_netcdf(ds, outputs["nc"], step="overlap_summary",
                 inputs=[f for files in overlaps.values() for f in files],
                 time_system="GPS", title=f"orbit overlaps {title}")
    tables = [statistics_table(s).assign(solution=k).set_index("solution", append=True)
              for k, s in summaries.items()]
    write_text(outputs["csv"], pd.concat(tables).to_csv(float_format="%.5f"))
    write_text(outputs["html"], html_page(f"{title}: orbit overlaps", frame_tables(
        {k: statistics_table(s) for k, s in summaries.items()}, row_header="arc pair (day b)",
        missing="campaign rows: mean and STD over the pairs of the RMS only",
        aggregate=lambda label: label.startswith("campaign"))))
    plot_overlaps(summaries, outputs["figure"], title=f"{title} overlaps")


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    files = plain(sm.input)
    main({s: files[s] for s in sm.params.solutions}, plain(sm.output), title=sm.params.title)


if __name__ == "__main__":
    if "snakemake" not in globals():  # by hand: a job of the default campaign
        from leopod.workflow.boundary import mock_snakemake

        snakemake = mock_snakemake("overlap_summary", sat="hy2b-sim")
    run(snakemake)  # noqa: F821 (injected by Snakemake)

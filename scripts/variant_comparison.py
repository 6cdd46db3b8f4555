"""Rule variant_comparison: the campaign summaries of a satellite's POD lines (its solution and
the solution variants) side by side (leopod.validation.comparison), as CSV and HTML."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

import logging
from collections.abc import Mapping

import xarray as xr

from leopod.io import write_text
from leopod.plots.pages import comparison_html
from leopod.validation.comparison import compare_lines
from leopod.validation.summary import column_meta
from leopod.workflow.boundary import plain
from leopod.workflow.log import configure_logging

log = logging.getLogger(__name__)


def main(summaries: Mapping[str, str], outputs: Mapping, *, title: str) -> None:
    """Compare the campaign summaries ``{line id: summary netCDF}`` into ``outputs``
    (``csv``, ``html``)."""
    tables = {}
    for line, path in summaries.items():
        with xr.open_dataset(path) as ds:
            tables[line] = ds.to_dataframe().set_index(["date", "solution"])
    table = compare_lines(tables)
    log.info("solution variants:\n%s", table.to_string(float_format=lambda v: f"{v:.3g}"))
    write_text(outputs["csv"], table.to_csv(float_format="%.4f"))
    meta = {name: column_meta(name) for name in table.index}
    write_text(outputs["html"], comparison_html(table, meta, title))


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    main(dict(zip(sm.params.lines, sm.input.summaries, strict=True)), plain(sm.output),
         title=sm.params.title)


if __name__ == "__main__":
    if "snakemake" not in globals():  # by hand: a job of the default campaign
        from leopod.workflow.boundary import mock_snakemake

        snakemake = mock_snakemake("variant_comparison", sat="hy2b-sim")
    run(snakemake)  # noqa: F821 (injected by Snakemake)

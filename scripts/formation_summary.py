"""Rule formation_summary: the campaign table of a formation pair (leopod.validation.formation)
as CSV and HTML, and its figure."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

import logging
from collections.abc import Mapping

from leopod.io import write_text
from leopod.io.netcdf import load_netcdf
from leopod.plots.pages import formation_html
from leopod.plots.validation import plot_formation_summary
from leopod.simulate.dd_truth import true_double_differences, wrong_dd_fixes
from leopod.validation.formation import formation_day_row, formation_table
from leopod.workflow.log import configure_logging

log = logging.getLogger(__name__)


def _wrong(files: Mapping, phases: Mapping) -> dict | None:
    """Wrong DD fixes of a simulated pair-day, None without truth files."""
    if "truth_a" not in files:
        return None
    table = load_netcdf(files["dd"])
    res = [load_netcdf(files[f"residuals_{k}"]) for k in ("a", "b")]
    truth = [[load_netcdf(p) for p in files[f"truth_{k}"]] for k in ("a", "b")]
    wl, nl = true_double_differences(table, res[0], res[1], truth[0], truth[1], phases)
    return wrong_dd_fixes(table, wl, nl)


def main(files: Mapping, outputs: Mapping, *, phases: Mapping, title: str) -> None:
    """Formation table of ``files`` (``{date: {product: path}}``) into ``outputs``."""
    rows = {}
    for date, f in files.items():
        rows[date] = formation_day_row(
            load_netcdf(f["baseline"]),
            kinematic=load_netcdf(f["kinematic"]) if "kinematic" in f else None,
            ranges=load_netcdf(f["range"]) if "range" in f else None,
            overlap=load_netcdf(f["overlap"]) if "overlap" in f else None,
            wrong=_wrong(f, phases),
            lines={k: load_netcdf(v) for k, v in f["lines"].items()} if "lines" in f
            else None)
    table, meta = formation_table(rows)
    log.info("formation summary:\n%s", table.T.to_string(float_format=lambda v: f"{v:.3g}"))
    write_text(outputs["csv"], table.to_csv(float_format="%.4f"))
    write_text(outputs["html"], formation_html(table, meta, title))
    plot_formation_summary(table, outputs["figure"], title=title)


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    main(sm.params.files, dict(sm.output.items()), phases=sm.params.phases,
         title=sm.params.title)


if __name__ == "__main__":
    run(snakemake)  # noqa: F821 (injected by Snakemake)

"""Rule campaign_summary: per day and solution residual RMS (all systems and per system),
fixing rates (graph rank and share of SDs, per system), product-guard statistics per system,
wrong fixes against the simulated truth, overlap, reference-orbit and SLR statistics, the
PCO-Z estimates, inter-system biases and variance components of a satellite
(leopod.validation.summary), with the PCO-Z, fixing-rate and ISB figures
(leopod.plots.summary)."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

import html
import logging
from collections.abc import Mapping

import numpy as np
import pandas as pd
import xarray as xr

from leopod.io import write_text
from leopod.io.netcdf import load_netcdf, write_netcdf
from leopod.plots.summary import plot_fixing_rates, plot_isb, plot_pco_z
from leopod.plots.tables import Column, Footnotes, html_page, html_table
from leopod.simulate.ambiguity_truth import wrong_fix_counts
from leopod.validation.quality_gate import STATUS, GateSettings
from leopod.validation.summary import (
    campaign_table,
    column_kind,
    column_label,
    column_meta,
    csv_text,
    day_row,
    excluded_row,
    isb_series,
    missing_reason,
    sections,
    system_of_column,
)
from leopod.workflow.boundary import plain
from leopod.workflow.log import configure_logging

log = logging.getLogger(__name__)


def _load(files: dict, key: str, date: str):
    """The day's file of product ``key``, opened lazily: the table reads a few of its
    variables (e.g. the residuals' RMS, not their directions)."""
    path = files.get(key, {}).get(date)
    return load_netcdf(path, lazy=True) if path else None


#: Row labels of the solutions and of the statistics over the days in the HTML table.
_SOLUTIONS = {"float_pod": "float", "fixed_pod": "ambiguity-fixed"}
_AGGREGATES = {"mean": "mean", "std": "STD", "all_days": "all days"}


def _columns(table) -> list[Column]:
    """The report columns of the campaign table; per-system columns only when the campaign
    has more than one system (with one they repeat the all-system columns)."""
    systems = {s for name in table.columns if (s := system_of_column(name))}
    return [Column(name, column_label(name), *column_meta(name)[:1], kind=column_kind(name),
                   description=column_meta(name)[1], levels=STATUS)
            for name in table.columns if len(systems) > 1 or not system_of_column(name)]


def _html_rows(table, columns: list[Column], n_days: int, excluded: Mapping[str, str]):
    """Rows of :func:`leopod.plots.tables.html_table`: day and solution labels, the values,
    why a missing value is missing, and whether the row is a statistic over the days."""
    keys = [c.key for c in columns]
    for (day, solution), row in table[keys].iterrows():
        def reason(column, day=day):
            if day in excluded:
                return f"day excluded from the campaign: {excluded[day]}"
            return missing_reason(column.key, day, n_days)
        yield ((_AGGREGATES.get(day, day), _SOLUTIONS.get(solution, solution)),
               row.to_numpy(dtype=float), reason, day in _AGGREGATES)


def _gate_list(rows: list[dict]) -> str:
    """HTML list of the days the quality gate did not pass, with the reasons."""
    items = [f"<li>{r['date']} {_SOLUTIONS.get(r['solution'], r['solution'])}: "
             f"{STATUS[int(r['quality_gate'])]} ({html.escape(r['quality_gate_reasons'])})</li>"
             for r in rows if np.isfinite(r["quality_gate"]) and r["quality_gate"] > 0]
    return ("<h4>quality gate</h4>\n"
            + (f"<ul>{''.join(items)}</ul>\n" if items else "<p>every day passed</p>\n"))


def summary_html(table, rows: list[dict], *, title: str, n_days: int,
                 excluded: Mapping[str, str], gate: bool) -> str:
    """The report page of the campaign table: one table per section, footnotes for the
    missing values."""
    notes = Footnotes()
    columns = {c.key: c for c in _columns(table)}
    parts = [f"<h4>{name}</h4>\n" + html_table(
        [columns[k] for k in keys if k in columns],
        _html_rows(table, [columns[k] for k in keys if k in columns], n_days, excluded),
        notes, row_header=("day", "solution"))
        for name, keys in sections(columns).items()]
    intro = ("<p>Daily figures per solution, then over the days: <i>mean</i> and <i>STD</i> "
             "of every figure (counts per day) and <i>all days</i> (counts summed, the quality "
             "gate of the worst day). Hover over a header for its full description.</p>\n")
    return html_page(f"{title}: campaign summary",
                     intro + (_gate_list(rows) if gate else "") + "".join(parts) + notes.html())


def main(files: Mapping, days, input_files, outputs: Mapping, *, title: str,
         phases: Mapping | None = None, gate: GateSettings | None = None,
         excluded: Mapping[str, str] | None = None) -> None:
    """Campaign table from ``files`` (``{solution: {product: {date: path}}}``, products
    ``residuals``, ``ambiguity``, ``overlap``, ``reference``, ``slr``, ``parameters``, and
    ``truth`` (``{date: [simulator truth files of the arc's days]}``, simulated satellites))
    into ``outputs``: ``nc``, ``csv``, ``html``, ``pco_z_png``, ``fixing_png`` and
    ``isb_png``; ``phases`` (phase pair per system) count the wrong fixes against the truth;
    ``input_files`` are recorded as provenance; the days ``excluded`` from the campaign
    (day -> reason, config ``exclude_days``) get rows without figures, gate failed."""
    rows, isb, truths = [], [], {}
    excluded = dict(excluded or {})
    for solution, products in files.items():
        for date in sorted([*days, *excluded]):
            if date in excluded:
                rows.append(excluded_row(date, solution, excluded[date]))
                log.warning("%s %s: %s", date, solution, rows[-1]["quality_gate_reasons"])
                continue
            residuals = _load(products, "residuals", date)
            parameters = _load(products, "parameters", date)
            ambiguity = _load(products, "ambiguity", date)
            # an arc spans up to three days' truth files, and each solution counts its fixes
            paths = products.get("truth", {}).get(date, [])
            truths.update({p: load_netcdf(p, lazy=True) for p in paths if p not in truths})
            truth = [truths[p] for p in paths]
            wrong = (wrong_fix_counts(ambiguity, residuals, truth, phases)
                     if truth and ambiguity is not None else None)
            rows.append(day_row(date, solution, residuals=residuals, ambiguity=ambiguity,
                                overlap=_load(products, "overlap", date),
                                reference=_load(products, "reference", date),
                                slr=_load(products, "slr", date),
                                parameters=parameters, wrong_fixes=wrong, gate=gate))
            row = rows[-1]
            if row["quality_gate"] > 0:
                log.warning("quality gate %s %s: %s (%s)", date, solution,
                            STATUS[int(row["quality_gate"])], row["quality_gate_reasons"])
            if parameters is not None:
                isb.append(isb_series(parameters, residuals).assign(solution=solution,
                                                                    date=date))
    table = campaign_table(rows)
    log.info("campaign summary:\n%s", table.to_string(float_format=lambda v: f"{v:.3g}"))
    ds = xr.Dataset.from_dataframe(table.reset_index().rename_axis("row"))
    meta = {name: column_meta(name) for name in table.columns}
    for name, (unit, text) in meta.items():
        ds[name].attrs.update(units=unit, long_name=text)
    for name in ("date", "solution"):
        ds[name].attrs.update(units="1", long_name=name)
    write_netcdf(ds, outputs["nc"], step="campaign_summary", inputs=list(input_files),
                 time_system="GPS", title=f"campaign summary {title}")
    write_text(outputs["csv"], csv_text(table))
    write_text(outputs["html"], summary_html(table, rows, title=title, n_days=len(days),
                                             excluded=excluded, gate=gate is not None))
    plot_pco_z(table, outputs["pco_z_png"], title=title)
    plot_fixing_rates(table, outputs["fixing_png"], title=title)
    plot_isb(pd.concat(isb, ignore_index=True) if isb else pd.DataFrame(
        columns=["system", "start", "end", "estimate_m", "sigma_m", "solution"]),
        outputs["isb_png"], title=title)


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    p = sm.params
    main({s: p.files[s] for s in p.solutions}, list(p.days), [str(f) for f in sm.input],
         plain(sm.output), title=p.title, phases=dict(p.phases),
         gate=GateSettings.from_config(p.quality_gate), excluded=dict(p.excluded))


if __name__ == "__main__":
    if "snakemake" not in globals():  # by hand: a job of the default campaign
        from leopod.workflow.boundary import mock_snakemake

        snakemake = mock_snakemake("campaign_summary", sat="hy2b-sim")
    run(snakemake)  # noqa: F821 (injected by Snakemake)

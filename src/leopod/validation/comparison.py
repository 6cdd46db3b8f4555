"""Side-by-side comparison of the POD lines of a satellite (solution variants).

The campaign summary of each line (:mod:`leopod.validation.summary`) ends with a ``mean`` and
a ``std`` row per solution; this table puts those rows of every line next to each other, the
form of the GPS / BDS-3 / GPS + BDS-3 comparisons of Jiang et al. (2023, Figs. 8, 13, 16) and
Zhang et al. (2024, Tables 3-5).
"""

from __future__ import annotations

import html
from collections.abc import Mapping
from dataclasses import replace

import numpy as np
import pandas as pd

from leopod.plots.tables import Column, Footnotes, format_value, html_page, unit_column

__all__ = ["compare_lines", "comparison_html"]


def compare_lines(tables: Mapping[str, pd.DataFrame]) -> pd.DataFrame:
    """Campaign means and STDs of every line and solution side by side.

    Parameters
    ----------
    tables : mapping
        ``{line id: campaign summary table}`` (index ``(date, solution)`` with ``mean`` and
        ``std`` rows, :func:`leopod.validation.summary.campaign_table`), in display order.

    Returns
    -------
    pandas.DataFrame
        Index: the summary columns (union over the lines, in first-seen order); columns: a
        MultiIndex ``(line, solution, statistic)`` with statistic ``mean`` or ``std``. A
        column a line lacks (e.g. another system's RMS) is NaN.
    """
    parts = {}
    for line, table in tables.items():
        for solution in table.index.get_level_values("solution").unique():
            for statistic in ("mean", "std"):
                if (statistic, solution) in table.index:
                    parts[(line, solution, statistic)] = table.loc[(statistic, solution)]
    if not parts:
        raise ValueError("no mean/std rows in the campaign summaries to compare")
    order = list(dict.fromkeys(name for row in parts.values() for name in row.index))
    out = pd.DataFrame(parts).reindex(order)
    out.columns = pd.MultiIndex.from_tuples(out.columns, names=["line", "solution", "statistic"])
    return out


def _cell(mean: float, std: float, column: Column, notes: Footnotes) -> str:
    """``mean ± std`` written by the column's kind (a count's "mean" is its sum)."""
    text = format_value(mean, column)
    if text is None:
        return f"<td class='missing'>{notes.dash('no value in that line')}</td>"
    spread = format_value(std, replace(column, kind="number")) if column.kind != "count" else None
    return f"<td>{text}" + (f" &plusmn; {spread}" if spread is not None else "") + "</td>"


def comparison_html(table: pd.DataFrame, meta: Mapping[str, tuple[str, str]], title: str) -> str:
    """HTML page of :func:`compare_lines`: one row per figure, one column per line and
    solution with ``mean ± std`` over the days (:mod:`leopod.plots.tables` conventions)."""
    keys = [(line, sol) for line, sol, stat in table.columns if stat == "mean"]
    head = "".join(f"<th>{html.escape(line)}<br>{html.escape(sol)}</th>" for line, sol in keys)
    notes = Footnotes()
    rows = []
    for name, row in table.iterrows():
        unit, text = meta[name]
        column = unit_column(name, name.replace("_", " "), unit, text)
        cells = "".join(_cell(row[(line, sol, "mean")], row.get((line, sol, "std"), np.nan),
                              column, notes) for line, sol in keys)
        rows.append(f"<tr><td class='label' title='{html.escape(text, quote=True)}'>"
                    f"{html.escape(column.header)}</td>{cells}</tr>")
    body = (f"<table><thead><tr><th>figure</th>{head}</tr></thead><tbody>\n"
            + "\n".join(rows) + "\n</tbody></table>\n" + notes.html())
    return html_page(f"{title}: solution variants side by side (mean and STD over the days)",
                     body)

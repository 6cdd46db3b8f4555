"""HTML report pages of the validation summaries that compare days or solution lines.

:func:`formation_html` shows the table of :func:`leopod.validation.formation.formation_table`,
:func:`comparison_html` that of :func:`leopod.validation.comparison.compare_lines`, both in
the conventions of :mod:`leopod.plots.tables` (units in the labels, rates in per cent, counts
as integers, a footnoted dash where a value is missing).
"""

from __future__ import annotations

import html
from collections.abc import Mapping
from dataclasses import replace

import numpy as np
import pandas as pd

from leopod.plots.tables import (
    Column,
    Footnotes,
    format_value,
    html_page,
    row_table,
    unit_column,
)

__all__ = ["comparison_html", "formation_html"]


def formation_html(table: pd.DataFrame, meta: Mapping[str, tuple[str, str]],
                   title: str) -> str:
    """HTML page of :func:`leopod.validation.formation.formation_table`: one row per figure
    (label with its unit, the description as tooltip), one column per day, then the mean (of
    a count: the sum over the days) and the STD (:mod:`leopod.plots.tables` conventions:
    counts as integers, rates in per cent, a footnoted dash where a day has no value)."""
    notes = Footnotes()
    headers = ["figure", *(str(d) for d in table.index[:-2]), "mean (counts: sum)", "STD"]
    rows = [(unit_column(c, meta[c][1], meta[c][0]), table[c].to_numpy(dtype=float))
            for c in table.columns]
    body = row_table(headers, rows, notes, "no value (no product, truth or data that day)")
    return html_page(f"{title}: formation summary", body + notes.html())


def _cell(mean: float, std: float, column: Column, notes: Footnotes) -> str:
    """``mean ± std`` written by the column's kind (a count's "mean" is its sum)."""
    text = format_value(mean, column)
    if text is None:
        return f"<td class='missing'>{notes.dash('no value in that line')}</td>"
    spread = format_value(std, replace(column, kind="number")) if column.kind != "count" else None
    return f"<td>{text}" + (f" &plusmn; {spread}" if spread is not None else "") + "</td>"


def comparison_html(table: pd.DataFrame, meta: Mapping[str, tuple[str, str]], title: str) -> str:
    """HTML page of :func:`leopod.validation.comparison.compare_lines`: one row per figure,
    one column per line and solution with ``mean ± std`` over the days
    (:mod:`leopod.plots.tables` conventions)."""
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

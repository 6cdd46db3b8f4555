"""Side-by-side comparison of the POD lines of a satellite (solution variants).

The campaign summary of each line (:mod:`leopod.validation.summary`) ends with a ``mean`` and
a ``std`` row per solution; this table puts those rows of every line next to each other, the
form of the GPS / BDS-3 / GPS + BDS-3 comparisons of Jiang et al. (2023, Figs. 8, 13, 16) and
Zhang et al. (2024, Tables 3-5).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

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


def _cell(mean: float, std: float) -> str:
    if not np.isfinite(mean):
        return "&ndash;"
    text = f"{mean:.0f}" if mean == round(mean) and abs(mean) >= 1000 else f"{mean:.3g}"
    return text + (f" &plusmn; {std:.2g}" if np.isfinite(std) else "")


def comparison_html(table: pd.DataFrame, meta: Mapping[str, tuple[str, str]], title: str) -> str:
    """HTML page of :func:`compare_lines`: one row per figure, one column per line and
    solution with ``mean +- std`` over the days."""
    keys = [(line, sol) for line, sol, stat in table.columns if stat == "mean"]
    head = "".join(f"<th>{line}<br>{sol}</th>" for line, sol in keys)
    rows = []
    for name, row in table.iterrows():
        unit, text = meta[name]
        cells = "".join(
            f"<td>{_cell(row[(line, sol, 'mean')], row.get((line, sol, 'std'), np.nan))}</td>"
            for line, sol in keys
        )
        rows.append(f"<tr><td title='{text}'>{name} [{unit}]</td>{cells}</tr>")
    body = "\n".join(rows)
    return (
        f"<html><body><h3>{title}: solution variants side by side (mean &plusmn; STD over "
        f"the days)</h3><table border='1' cellpadding='3'><tr><th>figure</th>{head}</tr>\n"
        f"{body}</table></body></html>\n"
    )

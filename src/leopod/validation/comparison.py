"""Side-by-side comparison of the POD lines of a satellite (solution variants).

The campaign summary of each line (:mod:`leopod.validation.summary`) ends with a ``mean`` and
a ``std`` row per solution; this table puts those rows of every line next to each other, the
form of the GPS / BDS-3 / GPS + BDS-3 comparisons of Jiang et al. (2023, Figs. 8, 13, 16) and
Zhang et al. (2024, Tables 3-5).
"""

from __future__ import annotations

from collections.abc import Mapping

import pandas as pd

__all__ = ["compare_lines"]


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

"""HTML tables of the workflow's report pages (campaign summary, data quality, variants).

A table is a list of :class:`Column` (a readable header with its unit, the full description as
a tooltip, and the kind of number, which decides how a cell is written) and rows of values.
A missing value (NaN) is never shown as ``nan``: the cell holds a dash with a numbered footnote
that says why the value is missing (:class:`Footnotes`; the caller knows the reason: not
estimated, no AR product, one day only, ...). Counts are written as integers with thousands
separators (never ``2.84e+04``), rates in per cent with one decimal, yes/no flags and
named levels as words, other figures with a fixed number of decimals per unit.

The page carries its own small style sheet (the Snakemake report shows it in a frame), so it
reads the same when opened on its own.
"""

from __future__ import annotations

import html
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

__all__ = ["Column", "Footnotes", "format_value", "frame_tables", "html_page", "html_table",
           "row_table", "unit_column"]

#: Kinds of column: how their values are written (:func:`format_value`).
KINDS = ("count", "percent", "flag", "level", "number")
#: Decimals of a ``number`` per unit (1 mm of a metre value; 0.01 of a cm or mm value).
_DECIMALS = {"m": 3, "cm": 2, "mm": 2, "%": 1, "1": 3}
_STYLE = (
    "body{font-family:sans-serif;font-size:13px;margin:8px}"
    "table{border-collapse:collapse;margin:4px 0 14px 0}"
    "th,td{border:1px solid #bbb;padding:2px 6px}"
    "th{background:#eef1f5;font-weight:600;vertical-align:bottom;text-align:center}"
    "td{text-align:right;white-space:nowrap;font-variant-numeric:tabular-nums}"
    "td.label{text-align:left}"
    "tr.aggregate td{background:#f6f6f6;font-style:italic}"
    "td.missing{color:#888;text-align:center}"
    "sup{line-height:0}sup a{text-decoration:none}"
    "ol.notes{font-size:12px;color:#444}"
    "h3{margin:4px 0}h4{margin:12px 0 2px 0}"
)


@dataclass(frozen=True)
class Column:
    """One column of a report table.

    Attributes
    ----------
    key : str
        Name of the value in the data (e.g. ``phase_rms_mm``).
    label : str
        Readable header without the unit (e.g. ``phase RMS``).
    unit : str
        Unit of the values (``"1"``: none), shown in brackets after the label.
    kind : {"count", "percent", "flag", "level", "number"}
        How values are written (:func:`format_value`).
    description : str
        Full description, the header's tooltip.
    levels : tuple of str
        Names of the integer levels 0, 1, ... of a ``level`` column.
    """

    key: str
    label: str
    unit: str = "1"
    kind: str = "number"
    description: str = ""
    levels: tuple[str, ...] = ()

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ValueError(f"column {self.key}: kind must be one of {KINDS}, not {self.kind!r}")

    @property
    def header(self) -> str:
        """The label with the unit in brackets (none for unitless columns)."""
        return self.label if self.unit in ("1", "") else f"{self.label} [{self.unit}]"


def format_value(value, column: Column, *, aggregate: bool = False) -> str | None:
    """Text of one value of ``column``; None for a missing (non-finite) value.

    ``count``: an integer with thousands separators (a mean count rounded); ``percent``: one
    decimal; ``flag``: ``yes`` (1) or ``no`` (0), a number in an ``aggregate`` row (the mean
    of a flag is a share, its STD no flag);
    ``level``: the name of the level (``column.levels``), a number otherwise; ``number``:
    decimals by unit (3 for m and unitless, 2 for cm and mm), a value that rounds to zero
    without a sign.
    """
    try:
        v = float(value)
    except (TypeError, ValueError):
        return html.escape(str(value))
    if not np.isfinite(v):
        return None
    if column.kind == "count":
        return f"{round(v):,}"
    if column.kind == "flag" and not aggregate and v in (0.0, 1.0):
        return "yes" if v else "no"
    if column.kind == "level" and v == round(v) and 0 <= v < len(column.levels):
        return column.levels[int(v)]
    text = f"{v:.{_DECIMALS.get(column.unit, 3)}f}"
    return text.removeprefix("-") if float(text) == 0.0 else text     # no "-0.00"


class Footnotes:
    """Numbered footnotes of a page: each distinct reason once, in order of first use."""

    def __init__(self) -> None:
        self._numbers: dict[str, int] = {}

    def dash(self, reason: str) -> str:
        """A dash marked with the number of ``reason`` (HTML)."""
        n = self._numbers.setdefault(reason, len(self._numbers) + 1)
        return f"&ndash;<sup><a href='#note-{n}'>{n}</a></sup>"

    def html(self) -> str:
        """The footnotes as an ordered list (empty without any)."""
        if not self._numbers:
            return ""
        items = "".join(f"<li id='note-{n}'>{html.escape(text)}</li>"
                        for text, n in self._numbers.items())
        return f"<p>&ndash; no value:</p><ol class='notes'>{items}</ol>\n"


def html_table(columns: Sequence[Column], rows: Iterable[tuple], notes: Footnotes, *,
               row_header: Sequence[str]) -> str:
    """An HTML table: label cells, then one cell per column.

    Parameters
    ----------
    columns : sequence of Column
        The value columns, in order.
    rows : iterable of (labels, values, reason, aggregate)
        ``labels``: the row's label cells (as many as ``row_header``); ``values``: one value
        per column; ``reason``: callable ``reason(column) -> str`` giving why a missing
        value of that column is missing (the footnote); ``aggregate``: True for a row of
        statistics over other rows (drawn apart).
    notes : Footnotes
        Collects the footnotes of the page.
    row_header : sequence of str
        Headers of the label cells.
    """
    head = "".join(f"<th>{html.escape(h)}</th>" for h in row_header) + "".join(
        f"<th title='{html.escape(c.description, quote=True)}'>{html.escape(c.header)}</th>"
        for c in columns)
    body = []
    for labels, values, reason, aggregate in rows:
        cells = [f"<td class='label'>{html.escape(str(x))}</td>" for x in labels]
        for column, value in zip(columns, values, strict=True):
            text = format_value(value, column, aggregate=aggregate)
            cells.append(f"<td>{text}</td>" if text is not None
                         else f"<td class='missing'>{notes.dash(reason(column))}</td>")
        style = " class='aggregate'" if aggregate else ""
        body.append(f"<tr{style}>{''.join(cells)}</tr>")
    return f"<table><thead><tr>{head}</tr></thead><tbody>\n" + "\n".join(body) + \
        "\n</tbody></table>\n"


def row_table(headers: Sequence[str], rows: Sequence[tuple[Column, Sequence]],
              notes: Footnotes, missing: str) -> str:
    """An HTML table with one row per quantity (its own :class:`Column`: label, unit and
    kind) and one value cell per column of ``headers[1:]`` (days, systems, ...); ``headers[0]``
    heads the labels. A missing value is a dash with the footnote ``missing``."""
    head = "".join(f"<th>{html.escape(h)}</th>" for h in headers)
    body = []
    for column, values in rows:
        texts = [format_value(v, column) for v in values]
        cells = "".join(f"<td>{t}</td>" if t is not None
                        else f"<td class='missing'>{notes.dash(missing)}</td>" for t in texts)
        body.append(f"<tr><td class='label' title='{html.escape(column.description, quote=True)}'>"
                    f"{html.escape(column.header)}</td>{cells}</tr>")
    return f"<table><thead><tr>{head}</tr></thead><tbody>\n" + "\n".join(body) + \
        "\n</tbody></table>\n"


def unit_column(key: str, label: str, unit: str, description: str = "") -> Column:
    """A column whose kind follows its unit: ``%`` per cent, ``1`` a count, else a number."""
    kind = {"%": "percent", "1": "count"}.get(unit, "number")
    return Column(key, label, unit, kind, description or label)


def html_page(title: str, body: str) -> str:
    """A complete HTML page (UTF-8, the table style sheet) with ``title`` as heading."""
    t = html.escape(title)
    return (f"<!DOCTYPE html>\n<html><head><meta charset='utf-8'><title>{t}</title>"
            f"<style>{_STYLE}</style></head>\n<body><h3>{t}</h3>\n{body}</body></html>\n")


#: Readable names of the statistics of the validation tables (column name parts).
_STATISTICS = {"mean": "mean", "std": "STD", "rms": "RMS"}
#: Readable names of the count columns of the validation tables.
_COUNTS = {"n_epochs": "epochs", "n_np": "normal points"}


def _frame_column(name: str) -> tuple[Column, float]:
    """Column and factor of a validation table column: ``<stat>[_<component>]_m`` in cm,
    ``n_*`` a count."""
    if name in _COUNTS or name.startswith("n_"):
        return Column(name, _COUNTS.get(name, name[2:]), "1", "count", name), 1.0
    if name.endswith("_m"):
        stat, *component = name[:-2].split("_")
        label = " ".join([_STATISTICS.get(stat, stat), *component])
        return Column(name, label, "cm", "number", f"{label} [cm] (column {name} in m)"), 100.0
    return Column(name, name.replace("_", " "), "1", "number", name), 1.0


def frame_tables(frames: dict[str, pd.DataFrame], *, row_header: str, missing: str,
                 aggregate=lambda label: False) -> str:
    """HTML tables (one per solution, a heading each) of validation statistics in metres
    (:func:`leopod.validation.orbit_statistics.statistics_table`, the SLR station table):
    centimetres with two decimals, counts as integers, a footnoted dash where a cell is
    empty (``missing`` says why), rows for which ``aggregate(label)`` holds drawn apart.

    Parameters
    ----------
    frames : dict of str to pandas.DataFrame
        ``{solution: table}``, the index the row labels, columns ``*_m`` and ``n_*``.
    row_header : str
        Header of the label column.
    missing : str
        Footnote of an empty cell.
    aggregate : callable
        ``aggregate(label) -> bool``: a row of statistics over other rows.
    """
    notes = Footnotes()
    parts = []
    for solution, frame in frames.items():
        specs = [_frame_column(c) for c in frame.columns]
        columns = [c for c, _ in specs]
        rows = [((label,), [float(v) * f if pd.notna(v) else np.nan
                            for v, (_, f) in zip(values, specs, strict=True)],
                 lambda _c: missing, aggregate(str(label)))
                for label, values in zip(frame.index, frame.itertuples(index=False), strict=True)]
        parts.append(f"<h4>{html.escape(solution)}</h4>\n"
                     + html_table(columns, rows, notes, row_header=[row_header]))
    return "".join(parts) + notes.html()

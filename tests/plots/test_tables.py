"""HTML tables of the report (issue 23 item 5).

Authority: analytic construction - the formatting rules of :mod:`leopod.plots.tables`
(integers with thousands separators, one-decimal per cent, yes/no, level names) applied to
known values, and the HTML read back with the standard library's parser.
"""

from html.parser import HTMLParser

import numpy as np
import pytest

from leopod.plots.tables import Column, Footnotes, format_value, html_page, html_table


class _Cells(HTMLParser):
    def __init__(self):
        super().__init__()
        self.cells, self._in = [], False

    def handle_starttag(self, tag, attrs):
        self._in = tag in ("td", "th")
        if self._in:
            self.cells.append("")

    def handle_endtag(self, tag):
        self._in = self._in and tag not in ("td", "th")

    def handle_data(self, data):
        if self._in:
            self.cells[-1] += data


def test_values_read_by_kind():
    assert format_value(28419.0, Column("n", "obs.", kind="count")) == "28,419"
    assert format_value(29446.33, Column("n", "obs.", kind="count")) == "29,446"
    assert format_value(98.7147, Column("r", "rate", "%", kind="percent")) == "98.7"
    assert format_value(6.89401, Column("p", "phase RMS", "mm")) == "6.89"
    assert format_value(0.31042, Column("c", "code RMS", "m")) == "0.310"
    flag = Column("a", "accepted", kind="flag")
    assert format_value(1.0, flag) == "yes" and format_value(0.0, flag) == "no"
    assert format_value(0.0, flag, aggregate=True) == "0.000"        # an STD is no verdict
    gate = Column("g", "gate", kind="level", levels=("ok", "suspect", "failed"))
    assert format_value(2.0, gate) == "failed"
    assert format_value(np.nan, gate) is None
    with pytest.raises(ValueError):
        Column("x", "x", kind="ratio")


def test_table_has_units_dashes_and_footnotes():
    columns = [Column("phase_rms_mm", "phase RMS", "mm", description="post-fit RMS"),
               Column("n_phase", "phase obs.", kind="count")]
    notes = Footnotes()
    rows = [(("2019-001", "float"), [6.894, 28419.0], lambda c: "unused", False),
            (("std", "float"), [np.nan, np.nan], lambda c: f"one day only ({c.key})", True)]
    page = html_page("HY-2B: summary", html_table(columns, rows, notes,
                                                   row_header=("day", "solution"))
                     + notes.html())
    parser = _Cells()
    parser.feed(page)
    assert parser.cells[:4] == ["day", "solution", "phase RMS [mm]", "phase obs."]
    assert parser.cells[4:8] == ["2019-001", "float", "6.89", "28,419"]
    assert parser.cells[8:10] == ["std", "float"]
    assert parser.cells[10].startswith("–") and parser.cells[11].startswith("–")
    assert "nan" not in page.lower().replace("nanum", "")
    assert "one day only (phase_rms_mm)" in page and "one day only (n_phase)" in page
    assert page.count("<li id='note-") == 2

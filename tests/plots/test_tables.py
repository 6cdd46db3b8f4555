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


def test_quality_summary_page_writes_each_indicator_by_its_kind():
    # the daily quality page (scripts/quality.py) of a combined G+C day: shares in per cent,
    # counts as integers with separators, metres in centimetres, a footnoted dash where a
    # system has no value (values chosen by hand, expected text by the rules above)
    import xarray as xr

    from leopod.plots.quality import summary_html

    def part(system, completeness, n_phase, noise_m):
        q = xr.Dataset({
            f"{system}_completeness": ((), completeness,
                                       {"units": "1", "long_name": f"{system}: epochs with "
                                        "data / expected epochs"}),
            f"{system}_n_phase_obs": ((), np.int64(n_phase),
                                      {"units": "1", "long_name": f"{system}: satellite-epochs "
                                       "with dual-frequency phase and code"}),
            f"{system}_noise_C2W_min_m": ((), noise_m, {"units": "m", "long_name":
                                                        f"{system}: C2W noise: minimum STD"}),
        })
        q.attrs["system"] = system
        return q

    page = summary_html([part("G", 0.9987, 24959, 0.0007616),
                         part("C", 0.5, 1200, np.nan)], "LT-1A 2022-200")
    parser = _Cells()
    parser.feed(page)
    cells = parser.cells
    assert cells[:3] == ["indicator", "G", "C"]

    def row(label):
        i = cells.index(label)
        return cells[i + 1:i + 3]

    assert row("epochs with data / expected epochs [%]") == ["99.9", "50.0"]
    assert row("satellite-epochs with dual-frequency phase and code") == ["24,959", "1,200"]
    noise = row("C2W noise: minimum STD [cm]")
    assert noise[0] == "0.08" and noise[1].startswith("\u2013")
    assert "nan" not in page and "no such value for this system" in page


def test_validation_tables_in_centimetres_with_counts_and_campaign_rows():
    # the overlap/reference/SLR report tables (scripts/*_summary.py): metres shown in cm with
    # two decimals (a value that rounds to zero without a sign), counts as integers, empty
    # cells of the campaign rows as footnoted dashes (values chosen by hand)
    import pandas as pd

    from leopod.plots.tables import frame_tables

    frame = pd.DataFrame({"mean_R_m": [-0.00004, np.nan], "rms_3D_m": [0.01234, 0.0047],
                          "n_epochs": [2880, np.nan]},
                         index=pd.Index(["2019-01-02", "campaign mean"], name="pair"))
    page = html_page("t", frame_tables({"float_pod": frame}, row_header="arc pair",
                                       missing="campaign rows: RMS only",
                                       aggregate=lambda label: label.startswith("campaign")))
    parser = _Cells()
    parser.feed(page)
    cells = parser.cells
    assert cells[:4] == ["arc pair", "mean R [cm]", "RMS 3D [cm]", "epochs"]
    assert cells[4:8] == ["2019-01-02", "0.00", "1.23", "2,880"]
    assert cells[8] == "campaign mean" and cells[10] == "0.47"
    assert cells[9].startswith("\u2013") and cells[11].startswith("\u2013")
    assert "campaign rows: RMS only" in page and "class='aggregate'" in page

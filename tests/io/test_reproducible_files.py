"""Header creation times and atomic writes: identical inputs give identical bytes.

Authority: the reproducible-builds specification of ``SOURCE_DATE_EPOCH`` (integer seconds
since 1970-01-01 00:00 UTC; https://reproducible-builds.org/specs/source-date-epoch/) and the
RINEX clock 3.00 header line "PGM / RUN BY / DATE" (date as yyyymmdd hhmmss UTC, columns 41-60).
"""

from __future__ import annotations

import datetime as dt

import matplotlib.pyplot as plt
import numpy as np
import pytest
import xarray as xr

from leopod.io._text import creation_time
from leopod.io.clock_write import write_rinex_clock
from leopod.plots import save_figure


def _clocks() -> xr.Dataset:
    t = np.datetime64("2019-01-01T00:00:00", "ns") + np.arange(3) * np.timedelta64(30, "s")
    return xr.Dataset({"clk_s": (("time", "sv"), np.full((3, 1), 1.25e-4))},
                      coords={"time": t, "sv": ["G01"]}, attrs={"time_system": "GPS"})


def test_source_date_epoch_sets_the_header_date(tmp_path, monkeypatch):
    # 1546300800 s after 1970-01-01 = 2019-01-01 00:00:00 UTC (17897 days x 86400 s)
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1546300800")
    assert creation_time() == dt.datetime(2019, 1, 1)
    write_rinex_clock(_clocks(), tmp_path / "a.clk")
    line = (tmp_path / "a.clk").read_text().splitlines()[1]
    assert line[40:60].strip() == "20190101 000000 UTC"


def test_an_explicit_creation_time_gives_identical_files(tmp_path, monkeypatch):
    monkeypatch.delenv("SOURCE_DATE_EPOCH", raising=False)
    created = dt.datetime(2019, 1, 2)
    for name in ("a.clk", "b.clk"):
        write_rinex_clock(_clocks(), tmp_path / name, created=created)
    assert (tmp_path / "a.clk").read_bytes() == (tmp_path / "b.clk").read_bytes()
    # an aware time is converted to UTC
    aware = dt.datetime(2019, 1, 2, 8, tzinfo=dt.timezone(dt.timedelta(hours=8)))
    assert creation_time(aware) == created


def test_figures_are_reproducible_and_never_partial(tmp_path):
    for name in ("a.png", "b.png"):
        fig, ax = plt.subplots()
        ax.plot([0, 1], [1, 0])
        save_figure(fig, tmp_path / name)
    assert (tmp_path / "a.png").read_bytes() == (tmp_path / "b.png").read_bytes()
    fig, _ = plt.subplots()
    with pytest.raises(ValueError):  # unknown format: nothing is left behind
        save_figure(fig, tmp_path / "c.notaformat")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.png", "b.png"]

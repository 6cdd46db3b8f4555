"""Figures of the SLR validation: PNGs written and deterministic, drawn values equal the
statistics, robust to rejected-only data and one or several solutions."""

from __future__ import annotations

import struct

import matplotlib.pyplot as plt
import numpy as np
import pytest
import xarray as xr
from matplotlib.container import BarContainer

from leopod.plots import slr as slr_plots
from leopod.validation.slr_statistics import elevation_statistics, station_statistics

pytestmark = pytest.mark.filterwarnings("error")

SITES = ["7090", "7839", "7105"]


def _residuals(seed: int = 1, bias_cm: float = 0.0) -> xr.Dataset:
    """Residual Dataset in the layout of leopod.validation.slr.slr_residuals: 3 stations,
    60 points around midnight UTC, 1.5 cm noise, a few rejected points."""
    rng = np.random.default_rng(seed)
    n = 60
    time = np.datetime64("2021-03-01T22:00", "ns") + np.sort(rng.integers(0, 4 * 3600, n)) \
        * np.timedelta64(1, "s")
    res = rng.normal(bias_cm * 0.01, 0.015, n)
    flag = np.zeros(n, dtype=np.int8)
    flag[[3, 17]] = 9                       # outliers
    res[[3, 17]] = [0.4, -0.3]
    flag[25] = 7                            # below the cut-off
    flag[40] = 2                            # no station: no residual
    res[40] = np.nan
    el = rng.uniform(5.0, 88.0, n)
    el[40] = np.nan
    return xr.Dataset(
        {"station": ("point", np.array(SITES)[np.arange(n) % 3]),
         "residual_m": ("point", res), "elevation_deg": ("point", el),
         "flag": ("point", flag)},
        coords={"time": ("point", time)})


def _png_chunk_types(data: bytes) -> list[bytes]:
    """Chunk types of a PNG file (PNG specification, ISO/IEC 15948, section 5.3)."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    types, pos = [], 8
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        types.append(data[pos + 4:pos + 8])
        pos += 12 + length
    return types


def _each(results, statistic):
    """``statistic`` of one residual Dataset or of each of a mapping of them."""
    if isinstance(results, dict):
        return {k: statistic(v) for k, v in results.items()}
    return statistic(results)


def _stations(results, path, **kwargs):
    """The station figure of the statistics the slr_summary step computes."""
    slr_plots.plot_slr_stations(_each(results, station_statistics), path, **kwargs)


def _elevation(results, path, **kwargs):
    """The elevation figure with 5° bins, as the slr_summary step draws it by default."""
    slr_plots.plot_slr_elevation(results, _each(results, lambda r: elevation_statistics(r, 5.0)),
                                 path, **kwargs)


PLOTS = [slr_plots.plot_slr_residuals_time, _stations, _elevation]


@pytest.mark.parametrize("plot", PLOTS)
def test_plots_deterministic(plot, tmp_path):
    first, second = tmp_path / "a.png", tmp_path / "b.png"
    plot(_residuals(), first, title="HY2B 2021-060")
    plot(_residuals(), second, title="HY2B 2021-060")
    data = first.read_bytes()
    assert len(data) > 1000 and data == second.read_bytes()
    # no time stamp (tIME) and no text chunks (Software) that could differ between runs
    assert not {b"tIME", b"tEXt", b"iTXt", b"zTXt"} & set(_png_chunk_types(data))


@pytest.mark.parametrize("plot", PLOTS)
def test_plots_with_nothing_used(plot, tmp_path):
    res = _residuals()
    res["flag"][:] = 9
    plot(res, tmp_path / "none.png")
    assert (tmp_path / "none.png").stat().st_size > 0


@pytest.mark.parametrize("plot", [_stations, _elevation])
def test_comparison_of_solutions(plot, tmp_path):
    plot({"float": _residuals(1, 0.5), "fixed": _residuals(2)}, tmp_path / "two.png")
    assert (tmp_path / "two.png").stat().st_size > 1000
    with pytest.raises(ValueError):
        plot({}, tmp_path / "none.png")


def _capture(monkeypatch) -> list:
    figures = []
    monkeypatch.setattr(slr_plots, "save_figure", lambda fig, path: figures.append(fig))
    return figures


def test_station_bars_are_mean_and_std(monkeypatch):
    # Bars = mean, error bars = sample STD of the used residuals per station, computed here
    # with numpy (definition of Peng et al. 2021, Table IV), last group all stations, in cm.
    figures = _capture(monkeypatch)
    res = _residuals()
    _stations(res, "unused.png")
    ax = figures[0].axes[0]
    heights = [p.get_height() for p in ax.patches]
    used = res["flag"].values == 0
    r, sites = res["residual_m"].values[used] * 100, res["station"].values[used]
    expected = [r[sites == s].mean() for s in sorted(SITES)] + [r.mean()]
    np.testing.assert_allclose(heights, expected, rtol=1e-12)
    bars = next(c for c in ax.containers if isinstance(c, BarContainer))
    err = bars.errorbar.lines[2][0].get_segments()
    np.testing.assert_allclose([seg[1, 1] - seg[0, 1] for seg in err],
                               [2 * r[sites == s].std(ddof=1) for s in sorted(SITES)]
                               + [2 * r.std(ddof=1)], rtol=1e-12)
    plt.close("all")


def test_elevation_std_per_bin(monkeypatch):
    # Lower panel: STD per 5° bin of the used residuals (Peng et al. 2021, Figs. 17-18), in cm.
    figures = _capture(monkeypatch)
    res = _residuals()
    _elevation(res, "unused.png")
    line = figures[0].axes[1].lines[0]           # STD line (then the mean, the zero line)
    centres, std_cm = line.get_xdata(), line.get_ydata()
    used = res["flag"].values == 0
    el, r = res["elevation_deg"].values[used], res["residual_m"].values[used] * 100
    for c, s in zip(centres, std_cm):
        sel = (el >= c - 2.5) & (el < c + 2.5)
        if sel.sum() > 1:
            assert s == pytest.approx(r[sel].std(ddof=1), rel=1e-12)
        else:
            assert np.isnan(s)
    plt.close("all")

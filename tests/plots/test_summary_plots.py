"""Figures of the campaign summary (issue 20 part 5): PCO-Z float vs fixed (Jiang et al. 2023,
Fig. 8), fixing rates and inter-system biases over time; PNGs written, byte-identical on reruns, a note instead of data where
the campaign has none (PCO-Z not estimated, no ambiguity resolution, one system)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from leopod.plots.summary import plot_fixing_rates, plot_isb, plot_pco_z
from leopod.validation.summary import campaign_table, day_row

pytestmark = pytest.mark.filterwarnings("error")

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"   # PNG specification (ISO/IEC 15948), section 5.2
DAYS = ("2021-186", "2021-187", "2021-188")


def _table(pco: bool, ar: bool):
    """Campaign table of three days, float and fixed, optionally with PCO-Z and AR."""
    res = xr.Dataset({"phase_residual_m": (("time", "sv"), [[0.003]]),
                      "code_residual_m": (("time", "sv"), [[0.3]])}, coords={"sv": ["C20"]})
    rows = []
    for solution, offset_m in (("float_pod", 0.017), ("fixed_pod", 0.0095)):
        for k, day in enumerate(DAYS):
            params = xr.Dataset({"estimate": ("parameter", [offset_m + 0.002 * k]),
                                 "sigma": ("parameter", [0.006])},
                                coords={"parameter": ["pco_z_m"] if pco else ["x0_m"]})
            amb = None
            if ar:
                fixed = np.array([1, 1, 1, k % 2], np.int8)
                amb = xr.Dataset({"wl_fixed": ("pair", fixed), "nl_fixed": ("pair", fixed),
                                  "constrained": ("pair", fixed)},
                                 attrs={"wl_fixing_rate": 0.9, "nl_fixing_rate": 0.8 + 0.05 * k})
            rows.append(day_row(day, solution, residuals=res, ambiguity=amb, parameters=params))
    return campaign_table(rows)


def _png(path) -> bytes:
    data = path.read_bytes()
    assert data.startswith(PNG_SIGNATURE)
    assert len(data) > 5_000
    return data


def test_pco_z_figure_float_and_fixed(tmp_path):
    table = _table(pco=True, ar=True)
    plot_pco_z(table, tmp_path / "a.png", title="HY-2D")
    plot_pco_z(table, tmp_path / "b.png", title="HY-2D")
    data = _png(tmp_path / "a.png")
    assert data == (tmp_path / "b.png").read_bytes()
    # NaN everywhere (PCO-Z not estimated): a figure that says so, different from the data one
    plot_pco_z(_table(pco=False, ar=True), tmp_path / "none.png", title="HY-2D")
    assert _png(tmp_path / "none.png") != data


def test_pco_z_figure_with_a_missing_day(tmp_path):
    # one day without a parameter file (NaN value and sigma) is a gap, not an error
    table = _table(pco=True, ar=False)
    table.loc[(DAYS[1], "fixed_pod"), ["pco_z_cm", "pco_z_sigma_cm"]] = np.nan
    plot_pco_z(table, tmp_path / "gap.png")
    _png(tmp_path / "gap.png")


def test_fixing_rate_figure(tmp_path):
    table = _table(pco=False, ar=True)
    plot_fixing_rates(table, tmp_path / "rates.png", title="HY-2D")
    data = _png(tmp_path / "rates.png")
    plot_fixing_rates(_table(pco=False, ar=False), tmp_path / "none.png")
    assert _png(tmp_path / "none.png") != data


def test_isb_figure(tmp_path):
    # piecewise ISBs of two days (6-h pieces), float and fixed, as isb_series gives them
    day0 = np.datetime64("2021-07-05T00:00", "ns")
    rows = [{"solution": s, "system": "C", "start": day0 + np.timedelta64(6 * k, "h"),
             "end": day0 + np.timedelta64(6 * k + 6, "h") - np.timedelta64(30, "s"),
             "estimate_m": 1.1 + 0.01 * k + shift, "sigma_m": 0.02}
            for s, shift in (("float_pod", 0.0), ("fixed_pod", 0.005)) for k in range(8)]
    series = pd.DataFrame(rows)
    plot_isb(series, tmp_path / "a.png", title="HY-2D")
    plot_isb(series, tmp_path / "b.png", title="HY-2D")
    data = _png(tmp_path / "a.png")
    assert data == (tmp_path / "b.png").read_bytes()
    plot_isb(series.iloc[:0], tmp_path / "none.png", title="HY-2D")
    assert _png(tmp_path / "none.png") != data

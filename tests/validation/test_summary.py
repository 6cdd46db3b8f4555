"""Campaign summary table (issue 8).

Authority: analytic construction — residuals, fixing rates and statistics with known values
must appear unchanged (units converted) in the row; means are means of the daily rows.
"""

import numpy as np
import pytest
import xarray as xr

from leopod.validation.summary import COLUMNS, campaign_table, day_row


def _residuals(phase_m, code_m):
    return xr.Dataset({"phase_residual_m": (("time", "sv"), np.asarray(phase_m, float)),
                       "code_residual_m": (("time", "sv"), np.asarray(code_m, float))})


def _stats(value_by_component, dim, label):
    comps = ["R", "T", "N", "3D"]
    return xr.Dataset({"rms_m": ((dim, "component"), [[value_by_component[c] for c in comps]])},
                      coords={dim: [label], "component": comps})


def test_row_carries_each_product():
    res = _residuals([[0.003, -0.004], [np.nan, 0.0]], [[0.3, -0.3], [0.3, np.nan]])
    amb = xr.Dataset({"constrained": ("pair", [1, 0, 1])},
                     attrs={"wl_fixing_rate": 0.98, "nl_fixing_rate": 0.9})
    ov = _stats({"R": 0.001, "T": 0.002, "N": 0.001, "3D": 0.005}, "x", 0).isel(x=0)
    ref = _stats({"R": 0.002, "T": 0.003, "N": 0.004, "3D": 0.01}, "period", "total")
    slr = xr.Dataset({"residual_m": ("point", [0.01, -0.01, 0.5]),
                      "flag": ("point", [0, 0, 8])})
    row = day_row("2019-001", "fixed_pod", residuals=res, ambiguity=amb, overlap=ov,
                  reference=ref, slr=slr)
    assert row["phase_rms_mm"] == pytest.approx(1e3 * np.sqrt((0.003**2 + 0.004**2) / 3))
    assert row["code_rms_m"] == pytest.approx(0.3)
    assert row["n_phase"] == 3 and row["n_constraints"] == 2
    assert row["nl_fixing_rate_pct"] == pytest.approx(90.0)
    assert row["overlap_3d_rms_cm"] == pytest.approx(0.5)
    assert row["reference_n_rms_cm"] == pytest.approx(0.4)
    assert row["slr_n"] == 2 and row["slr_mean_cm"] == pytest.approx(0.0)
    assert row["slr_std_cm"] == pytest.approx(100 * np.std([0.01, -0.01], ddof=1))
    assert set(COLUMNS) <= set(row)


def test_table_means_per_solution():
    rows = [day_row(d, s, residuals=_residuals([[v]], [[1.0]]))
            for s in ("float_pod", "fixed_pod") for d, v in (("2019-001", 0.004),
                                                             ("2019-002", 0.002))]
    table = campaign_table(rows)
    assert table.loc[("mean", "float_pod"), "phase_rms_mm"] == pytest.approx(3.0)
    assert table.loc[("mean", "fixed_pod"), "n_phase"] == 2
    assert np.isnan(table.loc[("2019-001", "float_pod"), "overlap_3d_rms_cm"])


def test_row_reports_the_product_guard():
    # the guard's verdict and statistics (attributes of the ambiguity table) reach the summary
    res = _residuals([[0.003]], [[0.3]])
    refused = xr.Dataset({"constrained": ("pair", [0, 0])},
                         attrs={"product_guard": "refused", "wl_guard_mean_cos": 0.05})
    row = day_row("2019-001", "fixed_pod", residuals=res, ambiguity=refused)
    assert row["ar_product_accepted"] == 0.0 and row["n_constraints"] == 0
    assert row["wl_guard_mean_cos"] == pytest.approx(0.05) and np.isnan(row["nl_guard_mean_cos"])
    untested = xr.Dataset(attrs={"product_guard": "not tested"})
    assert np.isnan(day_row("2019-001", "fixed_pod", residuals=res,
                            ambiguity=untested)["ar_product_accepted"])

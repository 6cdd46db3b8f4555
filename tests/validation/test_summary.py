"""Campaign summary table (issue 8; issue 20 part 5: per-system RMS, both fixing-rate
definitions, PCO-Z float vs fixed).

Authority: analytic construction — residuals, fixing rates and statistics with known values
must appear unchanged (units converted) in the row; means are means of the daily rows.
"""

import numpy as np
import pytest
import xarray as xr

from leopod.ambiguity.independent import fixing_rate
from leopod.validation.summary import COLUMNS, campaign_table, column_meta, day_row


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
    # a combined arc (leopod.ambiguity.resolve.resolve_systems) has one verdict per system:
    # accepted only if every system's product is
    for c_verdict, accepted in (("accepted", 1.0), ("refused", 0.0)):
        joined = xr.Dataset(attrs={"systems": "G C", "G_product_guard": "accepted",
                                   "C_product_guard": c_verdict,
                                   "G_product_guard_reason": ""})
        assert day_row("2019-001", "fixed_pod", residuals=res,
                       ambiguity=joined)["ar_product_accepted"] == accepted


def _graph_ambiguities(i, j, wl_fixed, nl_fixed):
    """Ambiguity table with the graph-rank fixing rates of :mod:`leopod.ambiguity.independent`
    in its attrs, as :func:`leopod.ambiguity.resolve` writes it."""
    i, j = np.asarray(i), np.asarray(j)
    wl, nl = np.asarray(wl_fixed, bool), np.asarray(nl_fixed, bool)
    return xr.Dataset({"wl_fixed": ("pair", wl.astype(np.int8)),
                       "nl_fixed": ("pair", nl.astype(np.int8)),
                       "constrained": ("pair", np.zeros(i.size, np.int8))},
                      attrs={"wl_fixing_rate": fixing_rate(i, j, wl),
                             "nl_fixing_rate": fixing_rate(i, j, nl)})


def test_both_fixing_rate_definitions():
    # Authority: graph theory (rank of an incidence matrix = nodes - components). Passes 0..3;
    # SDs 0-1, 1-2, 0-2 (a triangle: rank 2) and 2-3. WL: the triangle is fixed, 2-3 not:
    # graph-rank rate 2/3 (Jiang et al. 2023: fixed independent / all independent), share of
    # SDs 3/4: the share is the larger. NL (only where the WL is fixed): 0-1 alone: rank 1/3,
    # share 1/4.
    amb = _graph_ambiguities([0, 1, 0, 2], [1, 2, 2, 3], [1, 1, 1, 0], [1, 0, 0, 0])
    row = day_row("2019-001", "fixed_pod", residuals=_residuals([[0.001]], [[0.1]]),
                  ambiguity=amb)
    assert row["wl_fixing_rate_pct"] == pytest.approx(100 * 2 / 3)
    assert row["wl_sd_fixed_pct"] == pytest.approx(75.0)
    assert row["nl_fixing_rate_pct"] == pytest.approx(100 / 3)
    assert row["nl_sd_fixed_pct"] == pytest.approx(25.0)
    assert row["n_sd"] == 4
    assert "n_sd_G" not in row          # no satellite ids in this table: no per-system shares
    # per system (SDs are formed within a system; Jiang et al. 2023 report BDS-3 and GPS
    # apart): the triangle is BDS, the 2-3 SD GPS -> C: WL 3/3, NL 1/3; G: WL 0/1, NL 0/1
    amb["sv_i"] = ("pair", ["C20", "C21", "C20", "G05"])
    row = day_row("2019-001", "fixed_pod", residuals=_residuals([[0.001]], [[0.1]]),
                  ambiguity=amb)
    assert row["n_sd_C"] == 3 and row["n_sd_G"] == 1
    assert row["wl_sd_fixed_C_pct"] == pytest.approx(100.0)
    assert row["nl_sd_fixed_C_pct"] == pytest.approx(100 / 3)
    assert row["wl_sd_fixed_G_pct"] == 0.0 and row["nl_sd_fixed_G_pct"] == 0.0
    table = campaign_table([row])
    after = list(table.columns[list(table.columns).index("nl_sd_fixed_pct") + 1:][:6])
    assert after == ["n_sd_C", "wl_sd_fixed_C_pct", "nl_sd_fixed_C_pct",
                     "n_sd_G", "wl_sd_fixed_G_pct", "nl_sd_fixed_G_pct"]
    assert table.loc[("mean", "fixed_pod"), "n_sd_C"] == 3
    assert np.isnan(table.loc[("std", "fixed_pod"), "n_sd_C"])
    # no candidates: no share (NaN), not 0 %
    empty = _graph_ambiguities([], [], [], [])
    empty.attrs.update(wl_fixing_rate=np.nan, nl_fixing_rate=np.nan)
    row = day_row("2019-001", "fixed_pod", residuals=_residuals([[0.001]], [[0.1]]),
                  ambiguity=empty)
    assert row["n_sd"] == 0 and np.isnan(row["wl_sd_fixed_pct"])


def _sv_residuals(sv, phase_m, code_m):
    return _residuals(phase_m, code_m).assign_coords(sv=list(sv))


def test_residual_rms_per_system():
    # Authority: arithmetic. GPS phase residuals 3, 4 mm (and a NaN): RMS sqrt(12.5) mm;
    # BDS phase 1 mm twice: 1 mm; codes 0.3/0.4 m (GPS), 2 m (BDS). The all-system column
    # mixes them (sqrt((9+16+1+1)/4) mm).
    res = _sv_residuals(["G01", "C20", "G05"],
                        [[0.003, 0.001, 0.004], [np.nan, -0.001, np.nan]],
                        [[0.3, 2.0, -0.4], [np.nan, 2.0, np.nan]])
    row = day_row("2019-001", "float_pod", residuals=res)
    assert row["phase_rms_G_mm"] == pytest.approx(np.sqrt(12.5))
    assert row["phase_rms_C_mm"] == pytest.approx(1.0)
    assert row["code_rms_G_m"] == pytest.approx(np.sqrt(0.125))
    assert row["code_rms_C_m"] == pytest.approx(2.0)
    assert row["n_phase_G"] == 2 and row["n_phase_C"] == 2
    assert row["phase_rms_mm"] == pytest.approx(np.sqrt(27 / 4))
    assert "phase_rms_E_mm" not in row
    # a campaign whose second day has no BDS: per-system columns of every system in the data,
    # NaN where absent; they follow n_phase, sorted by system; counts summed in the mean row
    gps_only = _sv_residuals(["G01"], [[0.002]], [[0.2]])
    table = campaign_table([row, day_row("2019-002", "float_pod", residuals=gps_only)])
    assert list(table.columns[2:9]) == ["n_phase", "phase_rms_C_mm", "code_rms_C_m",
                                        "n_phase_C", "phase_rms_G_mm", "code_rms_G_m",
                                        "n_phase_G"]
    assert np.isnan(table.loc[("2019-002", "float_pod"), "phase_rms_C_mm"])
    assert table.loc[("mean", "float_pod"), "n_phase_G"] == 3
    assert table.loc[("mean", "float_pod"), "n_phase_C"] == 2
    assert column_meta("code_rms_C_m") == ("m", COLUMNS["code_rms_m"][1] + ", system C")
    with pytest.raises(KeyError):
        column_meta("phase_rms_GC_mm")


def test_pco_z_float_and_fixed_with_sigma():
    # Authority: unit conversion of the POD's parameter file (pco_z_m and its sigma [m]);
    # mean and STD over the days as in the legend of Jiang et al. (2023), Fig. 8.
    def params(value_m, sigma_m):
        names = ["x0_m", "pco_z_m"]
        return xr.Dataset({"estimate": ("parameter", [7e6, value_m]),
                           "sigma": ("parameter", [0.01, sigma_m])},
                          coords={"parameter": names})
    res = _residuals([[0.001]], [[0.1]])
    rows = [day_row(d, s, residuals=res, parameters=params(v, sg))
            for s, values in (("float_pod", ((0.0169, 0.0071), (0.0269, 0.0061))),
                              ("fixed_pod", ((0.0095, 0.0058), (0.0105, 0.0050))))
            for d, (v, sg) in zip(("2021-150", "2021-151"), values, strict=True)]
    table = campaign_table(rows)
    assert table.loc[("2021-150", "float_pod"), "pco_z_cm"] == pytest.approx(1.69)
    assert table.loc[("2021-150", "float_pod"), "pco_z_sigma_cm"] == pytest.approx(0.71)
    assert table.loc[("2021-151", "fixed_pod"), "pco_z_cm"] == pytest.approx(1.05)
    assert table.loc[("mean", "float_pod"), "pco_z_cm"] == pytest.approx(2.19)
    assert table.loc[("std", "float_pod"), "pco_z_cm"] == pytest.approx(np.sqrt(0.5))
    assert table.loc[("std", "fixed_pod"), "pco_z_cm"] == pytest.approx(np.sqrt(0.005))
    assert np.isnan(table.loc[("std", "fixed_pod"), "n_phase"])
    # not estimated: no parameter pco_z_m -> NaN, like a campaign without parameter files
    names = ["x0_m"]
    without = xr.Dataset({"estimate": ("parameter", [7e6]), "sigma": ("parameter", [0.01])},
                         coords={"parameter": names})
    row = day_row("2021-150", "float_pod", residuals=res, parameters=without)
    assert np.isnan(row["pco_z_cm"]) and np.isnan(row["pco_z_sigma_cm"])

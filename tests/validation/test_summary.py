"""Campaign summary table (issue 8; issue 20 part 5: per-system RMS, both fixing-rate
definitions, PCO-Z float vs fixed, ISB and variance components, per-system guard statistics,
graph-rank rates and wrong fixes).

Authority: analytic construction — residuals, fixing rates and statistics with known values
must appear unchanged (units converted) in the row; means are means of the daily rows.
"""

import numpy as np
import pytest
import xarray as xr

from leopod.ambiguity.independent import fixing_rate
from leopod.simulate.ambiguity_truth import wrong_fix_counts
from leopod.validation.summary import (
    COLUMNS,
    campaign_table,
    column_meta,
    day_row,
    excluded_row,
    isb_series,
    sections,
)


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
    # issue 23 item 5: a count's mean row is its mean per day; the sum is labelled all_days
    assert table.loc[("mean", "fixed_pod"), "n_phase"] == 1
    assert table.loc[("all_days", "fixed_pod"), "n_phase"] == 2
    assert np.isnan(table.loc[("all_days", "fixed_pod"), "phase_rms_mm"])
    assert np.isnan(table.loc[("2019-001", "float_pod"), "overlap_3d_rms_cm"])


def test_an_excluded_day_is_a_failed_row_without_figures():
    # issue 24, item 5: a day left out of the campaign (exclude_days) keeps its row, the gate
    # failed, and does not enter the means of the figures
    rows = [day_row("2019-001", "float_pod", residuals=_residuals([[0.004]], [[1.0]])),
            excluded_row("2019-002", "float_pod", "ingest: files/x.rnx: line 9: cut short"),
            day_row("2019-003", "float_pod", residuals=_residuals([[0.002]], [[1.0]]))]
    assert rows[1]["quality_gate_reasons"] == ("excluded from the campaign: ingest: "
                                               "files/x.rnx: line 9: cut short")
    table = campaign_table(rows)
    assert table.loc[("2019-002", "float_pod"), "quality_gate"] == 2
    assert np.isnan(table.loc[("2019-002", "float_pod"), "phase_rms_mm"])
    assert table.loc[("mean", "float_pod"), "phase_rms_mm"] == pytest.approx(3.0)
    assert table.loc[("all_days", "float_pod"), "quality_gate"] == 2
    assert list(table.index.get_level_values("date")[:3]) == ["2019-001", "2019-002",
                                                              "2019-003"]


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
    assert table.loc[("all_days", "fixed_pod"), "n_sd_C"] == 3
    assert np.isnan(table.loc[("std", "fixed_pod"), "n_sd_C"])        # one day: no STD
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
    # NaN where absent; they follow n_phase, sorted by system; counts summed in all_days
    gps_only = _sv_residuals(["G01"], [[0.002]], [[0.2]])
    table = campaign_table([row, day_row("2019-002", "float_pod", residuals=gps_only)])
    assert list(table.columns[2:9]) == ["n_phase", "phase_rms_C_mm", "code_rms_C_m",
                                        "n_phase_C", "phase_rms_G_mm", "code_rms_G_m",
                                        "n_phase_G"]
    assert np.isnan(table.loc[("2019-002", "float_pod"), "phase_rms_C_mm"])
    assert table.loc[("all_days", "float_pod"), "n_phase_G"] == 3
    assert table.loc[("all_days", "float_pod"), "n_phase_C"] == 2
    assert table.loc[("mean", "float_pod"), "n_phase_G"] == 1.5
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
    assert table.loc[("std", "fixed_pod"), "n_phase"] == 0.0   # equal counts on both days
    # not estimated: no parameter pco_z_m -> NaN, like a campaign without parameter files
    names = ["x0_m"]
    without = xr.Dataset({"estimate": ("parameter", [7e6]), "sigma": ("parameter", [0.01])},
                         coords={"parameter": names})
    row = day_row("2021-150", "float_pod", residuals=res, parameters=without)
    assert np.isnan(row["pco_z_cm"]) and np.isnan(row["pco_z_sigma_cm"])


def _combined_parameters(isb_names, isb_m, isb_cov, factors, factor_sigmas):
    """Parameter file of a combined G+C POD as leopod.estimation.outputs.parameter_dataset
    writes it (ISB parameters after x0_m, variance groups on ``group``)."""
    names = ["x0_m", *isb_names]
    k = len(names)
    cov = np.zeros((k, k))
    cov[0, 0] = 1e-4
    cov[1:, 1:] = isb_cov
    groups = ["G_code", "G_phase", "C_code", "C_phase"]
    return xr.Dataset(
        {"estimate": ("parameter", [7e6, *isb_m]),
         "sigma": ("parameter", np.sqrt(np.diag(cov))),
         "covariance": (("parameter", "parameter_b"), cov),
         "variance_factor": ("group", factors),
         "variance_factor_sigma": ("group", factor_sigmas),
         "apriori_sigma_m": ("group", [0.3, 0.005, 0.3, 0.005])},
        coords={"parameter": names, "parameter_b": names, "group": groups},
        attrs={"systems": "G C", "sigma0": 1.02})


def test_isb_and_variance_components():
    # Authority: arithmetic. Three ISB pieces 1.0, 1.2, 1.1 m with covariance C: their mean
    # 1.1 m, the sigma of the mean sqrt(1'C1)/3, the STD of the pieces 0.1 m. Variance factors
    # 0.25 (G code), 4 (C code), 0.5 (C phase) scale the a-priori variances 0.3 m / 5 mm
    # (weight = 1/(factor sigma^2), leopod.estimation.float_pod): sigmas 0.15 m, 0.6 m,
    # sqrt(0.5) 5 mm.
    cov = np.array([[0.04, 0.01, 0.0], [0.01, 0.09, 0.02], [0.0, 0.02, 0.01]])
    names = ["isb_C_000_m", "isb_C_001_m", "isb_C_002_m"]
    params = _combined_parameters(names, [1.0, 1.2, 1.1], cov, [0.25, 1.0, 4.0, 0.5],
                                  [0.01, 0.05, 0.2, 0.03])
    res = _sv_residuals(["G01", "C20"], [[0.001, 0.002]] * 4, [[0.1, 0.2]] * 4)
    res["isb_piece"] = ("time", [0, 0, 1, 2])
    res = res.assign_coords(time=np.datetime64("2021-07-12T00:00", "ns")
                            + np.arange(4) * np.timedelta64(30, "s"))
    row = day_row("2021-193", "float_pod", residuals=res, parameters=params)
    assert row["isb_C_m"] == pytest.approx(1.1)
    assert row["isb_C_sigma_m"] == pytest.approx(np.sqrt(cov.sum()) / 3)
    assert row["isb_C_std_m"] == pytest.approx(0.1) and row["n_isb_C"] == 3
    assert "isb_G_m" not in row                           # GPS is the datum
    assert row["vf_G_code"] == 0.25 and row["vf_C_code_sigma"] == 0.2
    assert row["sigma_G_code_m"] == pytest.approx(0.15)
    assert row["sigma_C_code_m"] == pytest.approx(0.6)
    assert row["sigma_C_phase_mm"] == pytest.approx(5 * np.sqrt(0.5))
    assert row["sigma_G_phase_mm"] == pytest.approx(5.0) and row["sigma0"] == 1.02
    # the pieces over time: each over the epochs of its isb_piece
    series = isb_series(params, res)
    assert list(series.estimate_m) == [1.0, 1.2, 1.1]
    np.testing.assert_allclose(series.sigma_m, np.sqrt(np.diag(cov)))
    assert series.start[1] == series.end[1] == res.time.values[2]
    assert series.end[0] == res.time.values[1]
    with pytest.raises(ValueError, match="isb_piece"):
        isb_series(params, res.drop_vars("isb_piece"))
    # one ISB per arc: the parameter and its sigma, no STD; the table's last section
    one = _combined_parameters(["isb_C_m"], [-3.2], [[0.0025]], [1.0] * 4, [np.nan] * 4)
    row = day_row("2021-193", "fixed_pod", residuals=res, parameters=one)
    assert row["isb_C_m"] == -3.2 and row["isb_C_sigma_m"] == pytest.approx(0.05)
    assert np.isnan(row["isb_C_std_m"]) and row["n_isb_C"] == 1
    table = campaign_table([row])
    last = sections(table.columns)["antenna, inter-system biases and variance components"]
    assert last[:4] == ["pco_z_cm", "pco_z_sigma_cm", "sigma0", "isb_C_m"]
    assert "vf_G_phase_sigma" in last and "sigma_C_phase_mm" in last
    assert column_meta("sigma_C_phase_mm")[0] == "mm"
    assert np.isnan(table.loc[("std", "fixed_pod"), "n_isb_C"])


def test_per_system_rates_and_guard():
    # Authority: the attributes of leopod.ambiguity.resolve.resolve_systems (one resolution,
    # guard and graph-rank rate per system, ``<S>_*``) reach their per-system columns; a
    # single-system table (resolve_arc) fills its system's columns with its own figures.
    res = _residuals([[0.003]], [[0.3]])
    joined = xr.Dataset(
        {"sv_i": ("pair", ["G01", "C20"]), "wl_fixed": ("pair", [1, 1]),
         "nl_fixed": ("pair", [1, 0]), "constrained": ("pair", [1, 0])},
        attrs={"systems": "G C", "wl_fixing_rate": 1.0, "nl_fixing_rate": 0.5,
               "G_wl_fixing_rate": 1.0, "G_nl_fixing_rate": 1.0,
               "C_wl_fixing_rate": 1.0, "C_nl_fixing_rate": 0.0,
               "G_product_guard": "accepted", "C_product_guard": "refused",
               "G_wl_guard_mean_cos": 0.97, "G_nl_guard_mean_cos": 0.91,
               "C_wl_guard_mean_cos": 0.12})
    row = day_row("2021-193", "fixed_pod", residuals=res, ambiguity=joined)
    assert row["nl_fixing_rate_G_pct"] == 100.0 and row["nl_fixing_rate_C_pct"] == 0.0
    assert row["ar_product_accepted_G"] == 1.0 and row["ar_product_accepted_C"] == 0.0
    assert row["ar_product_accepted"] == 0.0
    assert row["wl_guard_mean_cos_G"] == 0.97 and row["wl_guard_mean_cos_C"] == 0.12
    assert np.isnan(row["nl_guard_mean_cos_C"])
    table = campaign_table([row])
    cols = list(table.columns)
    k = cols.index("n_sd_C")
    assert cols[k:k + 5] == ["n_sd_C", "wl_fixing_rate_C_pct", "nl_fixing_rate_C_pct",
                             "wl_sd_fixed_C_pct", "nl_sd_fixed_C_pct"]
    k = cols.index("nl_guard_mean_cos")
    assert cols[k + 1:k + 4] == ["ar_product_accepted_C", "wl_guard_mean_cos_C",
                                 "nl_guard_mean_cos_C"]
    single = joined.drop_attrs().assign(sv_i=("pair", ["C20", "C21"]))
    single.attrs.update(wl_fixing_rate=0.5, nl_fixing_rate=0.25, product_guard="accepted",
                        wl_guard_mean_cos=0.8)
    row = day_row("2021-193", "fixed_pod", residuals=res, ambiguity=single)
    assert row["wl_fixing_rate_C_pct"] == 50.0 and row["nl_fixing_rate_C_pct"] == 25.0
    assert row["ar_product_accepted_C"] == 1.0 and row["wl_guard_mean_cos_C"] == 0.8
    assert "wl_fixing_rate_G_pct" not in row


def test_wrong_fixes_per_system_against_truth():
    # Authority: the simulator's integers (amb_<phase>_cyc), constructed here. Passes 0, 1
    # (G01, G02: L1C/L2W) and 2, 3 (C20, C21: L1P/L5P); true SD of GPS: N1 5-2 = 3, NWL
    # (5-1)-(2-4) = 6; of BDS: N1 7-9 = -2, NWL (7-3)-(9-9) = 4. The BDS SD must take the
    # L1P/L5P pair (GPS's L1C/L2W have no value there). The table's integers are right; one
    # altered BDS NL integer is one wrong BDS fix.
    t = np.datetime64("2021-07-12T00:00", "ns") + np.arange(2) * np.timedelta64(30, "s")
    sv = ["G01", "G02", "C20", "C21"]
    res = _sv_residuals(sv, [[0.001] * 4] * 2, [[0.1] * 4] * 2).assign_coords(time=t)
    res["pass_index"] = (("time", "sv"), [[0, 1, 2, 3]] * 2)
    nan = np.nan
    amb = {"L1C": [5, 2, nan, nan], "L2W": [1, 4, nan, nan],
           "L1P": [nan, nan, 7, 9], "L5P": [nan, nan, 3, 9]}
    truth = xr.Dataset({f"amb_{k}_cyc": (("obs_time", "sv"), [v] * 2) for k, v in amb.items()},
                       coords={"obs_time": t, "sv": sv})
    table = xr.Dataset({"pass_i": ("pair", [0, 2]), "pass_j": ("pair", [1, 3]),
                        "sv_i": ("pair", ["G01", "C20"]), "wl_integer": ("pair", [6, 4]),
                        "nl_integer": ("pair", [3, -2]), "wl_fixed": ("pair", [1, 1]),
                        "nl_fixed": ("pair", [1, 1]), "constrained": ("pair", [1, 1])},
                       attrs={"wl_fixing_rate": 1.0, "nl_fixing_rate": 1.0})
    phases = {"G": ["L1C", "L2W"], "C": ["L1P", "L5P"]}

    def row_of(tab):
        return day_row("2021-193", "fixed_pod", residuals=res, ambiguity=tab,
                       wrong_fixes=wrong_fix_counts(tab, res, [truth], phases))

    row = row_of(table)
    assert row["nl_wrong"] == 0 and row["wl_wrong_C"] == 0 and row["constrained_wrong_G"] == 0
    table["nl_integer"] = ("pair", [3, -1])
    row = row_of(table)
    assert row["nl_wrong"] == 1 and row["constrained_wrong"] == 1
    assert row["nl_wrong_C"] == 1 and row["constrained_wrong_C"] == 1 and row["wl_wrong_C"] == 0
    assert row["nl_wrong_G"] == 0
    summary = campaign_table([row])
    assert summary.loc[("all_days", "fixed_pod"), "nl_wrong_C"] == 1      # a count: summed
    # the GPS pair for every system: BDS has no true integers, its fix counts as wrong
    counts = wrong_fix_counts(table, res, [truth], {"G": phases["G"], "C": phases["G"]})
    assert counts["C"]["wl_wrong"] == 1 and counts["G"]["wl_wrong"] == 0
    with pytest.raises(KeyError, match="amb_L2C_cyc"):
        wrong_fix_counts(table, res, [truth], {"G": ["L1C", "L2C"]})


def test_report_labels_kinds_and_reasons():
    # issue 23 item 5: readable headers, the kind that decides how a value reads, and why a
    # value is missing (analytic: the definitions of the columns)
    from leopod.validation.summary import (
        column_kind,
        column_label,
        csv_text,
        missing_reason,
        system_of_column,
    )
    assert column_label("phase_rms_mm") == "phase RMS"
    assert column_label("phase_rms_G_mm") == "phase RMS G" and system_of_column("n_sd_C") == "C"
    assert system_of_column("n_sd") is None
    assert [column_kind(c) for c in ("n_phase", "n_phase_G", "wl_fixing_rate_pct",
                                     "ar_product_accepted_C", "quality_gate", "sigma0")] == [
        "count", "count", "percent", "flag", "level", "number"]
    assert "two days" in missing_reason("phase_rms_mm", "std", 1)
    assert "last day" in missing_reason("overlap_3d_rms_cm", "2019-003", 3)
    assert "float solution" in missing_reason("n_constraints", "2019-001", 3)
    assert "pod.estimate_pco_z" in missing_reason("pco_z_sigma_cm", "mean", 3)
    assert "one ISB piece" in missing_reason("isb_C_std_m", "2019-001", 3)
    assert "worst day" in missing_reason("quality_gate", "mean", 3)
    # the CSV writes counts as integers, never 2.84e+04 or 28419.0000
    rows = [day_row(d, "float_pod", residuals=_residuals(np.full((28419, 1), 0.004),
                                                          np.ones((28419, 1))))
            for d in ("2019-001", "2019-002")]
    text = csv_text(campaign_table(rows))
    assert "2019-001,float_pod,4.0000,1.0000,28419," in text
    assert "all_days,float_pod,,,56838," in text

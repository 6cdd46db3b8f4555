"""Quality gate of a POD day (issue 24, item 4): figures against thresholds -> ok, suspect, failed,
in the POD's parameters file and the campaign summary.

Authority: the definition of the gate (leopod.validation.quality_gate module docstring) and
the schema defaults; analytic datasets whose figures are known. The fault catalogue
(tests/estimation/test_pod_faults.py) checks the gate on simulated faults.
"""

import numpy as np
import pytest
import xarray as xr

from leopod.validation.quality_gate import (
    FIGURES,
    GateSettings,
    check,
    pod_figures,
    stamp,
    stamped_figures,
)
from leopod.validation.summary import campaign_table, day_row
from leopod.workflow.config import section_defaults

GATE = GateSettings.from_config({})
T0 = np.datetime64("2019-01-01T00:00", "ns")


def test_defaults_come_from_the_schema():
    defaults = section_defaults("quality_gate")
    assert GATE.max_phase_rms_mm == defaults["max_phase_rms_mm"] == 20.0
    assert GATE.min_coverage_pct == 80.0 and GATE.failed_factor == 5.0
    assert {field for field, _ in FIGURES.values()} | {"failed_factor"} == set(defaults)


def test_ok_suspect_failed():
    assert check({"phase_rms_mm": 8.0, "coverage_pct": 100.0}, GATE).status == "ok"
    suspect = check({"phase_rms_mm": 30.0, "coverage_pct": 50.0}, GATE)
    assert suspect.status == "suspect" and suspect.level == 1
    assert suspect.reasons == ("phase_rms_mm 30 > 20", "coverage_pct 50 < 80")
    assert check({"phase_rms_mm": 101.0}, GATE).status == "failed"      # > 5 x 20
    assert check({"coverage_pct": 15.9}, GATE).status == "failed"        # < 80 / 5
    assert check({"phase_rms_mm": np.nan, "overlap_3d_cm": np.nan}, GATE).status == "ok"
    not_converged = check({}, GATE, converged=False)
    assert (not_converged.status, not_converged.reasons) == ("failed", ("POD not converged",))
    assert str(suspect) == "suspect (phase_rms_mm 30 > 20; coverage_pct 50 < 80)"


def _solution(n=2880, step_s=30.0, with_phase=2880):
    t = T0 + (np.arange(n) * step_s * 1e9).astype("timedelta64[ns]")
    phase = np.full((n, 2), np.nan)
    phase[:with_phase] = 0.004             # 4 mm everywhere observed
    residuals = xr.Dataset({"phase_residual_m": (("time", "sv"), phase),
                            "code_residual_m": (("time", "sv"), np.full((n, 2), 0.5))},
                           coords={"time": t})
    sigma = np.zeros((n, 3))
    sigma[n // 2] = [0.03, 0.04, 0.0]      # 5 cm at one epoch
    orbit = xr.Dataset({"sigma_rtn_m": (("time", "rtn"), sigma),
                        "apriori_diff_rtn_m": (("time", "rtn"), np.full((n, 3), 2.0))},
                       coords={"time": t})
    parameters = xr.Dataset({"estimate": ("parameter", [0.0]), "sigma": ("parameter", [1.0])},
                            coords={"parameter": ["drag_scale"]},
                            attrs={"sigma0": 1.5, "converged": 1})
    return orbit, residuals, parameters


def test_pod_figures():
    orbit, residuals, parameters = _solution(with_phase=1440)
    figures = pod_figures(orbit, residuals, parameters, (T0, T0 + np.timedelta64(1, "D")), 30.0)
    assert figures == pytest.approx({"phase_rms_mm": 4.0, "code_rms_m": 0.5, "sigma0": 1.5,
                                     "position_sigma_cm": 5.0,
                                     "apriori_diff_m": np.sqrt(12.0), "coverage_pct": 50.0})


def test_summary_marks_the_day_and_keeps_the_worst():
    rows = []
    for date, with_phase, overlap_m in (("2019-001", 2880, 0.02), ("2019-002", 1440, 0.6)):
        orbit, residuals, parameters = _solution(with_phase=with_phase)
        day = np.datetime64(f"{date[:4]}-01-0{date[-1]}", "ns")
        figures = pod_figures(orbit, residuals.assign_coords(time=residuals.time - T0 + day),
                              parameters, (day, day + np.timedelta64(1, "D")), 30.0)
        stamp(parameters, figures, check(figures, GATE))
        assert stamped_figures(parameters) == figures
        overlap = xr.Dataset({"rms_m": ("component", [0.0, 0.0, 0.0, overlap_m])},
                             coords={"component": ["R", "T", "N", "3D"]})
        rows.append(day_row(date, "float_pod", residuals=residuals, parameters=parameters,
                            overlap=overlap, gate=GATE))
    assert parameters.attrs["quality_gate"] == "suspect"          # the POD's own verdict
    assert rows[0]["quality_gate"] == 0 and rows[0]["quality_gate_reasons"] == ""
    # the summary adds the overlap: 60 cm > 5 x 10 cm fails the second day
    assert rows[1]["quality_gate"] == 2
    assert rows[1]["quality_gate_reasons"] == "coverage_pct 50 < 80; overlap_3d_cm 60 > 10"
    table = campaign_table(rows)
    assert table.loc[("all_days", "float_pod"), "quality_gate"] == 2  # the worst day
    assert np.isnan(table.loc[("mean", "float_pod"), "quality_gate"])  # no mean of levels
    assert "quality_gate_reasons" not in table

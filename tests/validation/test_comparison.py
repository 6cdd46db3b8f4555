"""Solution variants side by side (leopod.validation.comparison; issue 20 part 2).

Authority: analytic construction - the comparison only rearranges the ``mean`` and ``std``
rows of each line's campaign summary, so every cell must equal the summary's value, and a
figure one line lacks (another system's RMS) must be empty rather than borrowed.
"""

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from leopod.plots.pages import comparison_html
from leopod.validation.comparison import compare_lines
from leopod.validation.summary import campaign_table, column_meta, day_row


def _table(values_by_system: dict) -> pd.DataFrame:
    rows = []
    for day, scale in (("2021-193", 1.0), ("2021-194", 3.0)):
        for solution in ("float_pod", "fixed_pod"):
            sv = list(values_by_system)
            phase = [[scale * values_by_system[s] for s in sv]]
            res = xr.Dataset({"phase_residual_m": (("time", "sv"), np.asarray(phase)),
                              "code_residual_m": (("time", "sv"), np.ones((1, len(sv))))},
                             coords={"sv": sv})
            rows.append(day_row(day, solution, residuals=res))
    return campaign_table(rows)


def test_each_cell_is_the_lines_mean_and_std():
    lines = {"hy2d-sim": _table({"G01": 0.002, "C19": 0.004}),
             "hy2d-sim_G": _table({"G01": 0.002})}
    table = compare_lines(lines)
    for line, summary in lines.items():
        for solution in ("float_pod", "fixed_pod"):
            for stat in ("mean", "std"):
                assert table[(line, solution, stat)]["phase_rms_G_mm"] == pytest.approx(
                    summary.loc[(stat, solution), "phase_rms_G_mm"])
    # GPS-only line: 2 mm on day 1, 6 mm on day 2 -> mean 4 mm, sample STD 2.83 mm
    assert table[("hy2d-sim_G", "fixed_pod", "mean")]["phase_rms_mm"] == pytest.approx(4.0)
    assert table[("hy2d-sim_G", "fixed_pod", "std")]["phase_rms_mm"] == pytest.approx(
        np.std([2.0, 6.0], ddof=1))
    # the GPS-only line has no BDS residuals: empty, not another line's value
    assert np.isnan(table[("hy2d-sim_G", "float_pod", "mean")]["phase_rms_C_mm"])
    assert np.isfinite(table[("hy2d-sim", "float_pod", "mean")]["phase_rms_C_mm"])


def test_the_page_shows_mean_and_std_per_line_and_solution():
    table = compare_lines({"a": _table({"G01": 0.002}), "a_C": _table({"C19": 0.004})})
    html = comparison_html(table, {n: column_meta(n) for n in table.index}, "test")
    assert "<th>a<br>fixed_pod</th>" in html and "<th>a_C<br>float_pod</th>" in html
    assert "4.00 &plusmn; 2.83" in html      # 2 and 6 mm: mean 4, STD 2.83 (mm: 2 decimals)
    assert "&ndash;" in html                 # a figure a line lacks


def test_no_summary_rows_is_an_error():
    with pytest.raises(ValueError, match="mean/std"):
        compare_lines({})


def test_figures_keep_the_summary_order():
    # the summary's column order (residuals, fixing, validation, PCO-Z), not alphabetical
    table = compare_lines({"a": _table({"G01": 0.002}), "a_C": _table({"C19": 0.004})})
    names = list(table.index)
    assert names.index("phase_rms_mm") < names.index("code_rms_m") < names.index("n_phase")
    assert names.index("phase_rms_G_mm") < names.index("phase_rms_C_mm") or \
        names.index("phase_rms_C_mm") < names.index("code_rms_m")

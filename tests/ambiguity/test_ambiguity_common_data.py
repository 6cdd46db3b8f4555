"""No wide-lane fix from less than min_common_s of common HMW data (leopod.ambiguity.resolve).

Authority: Peng et al. (2021, sec. IV-B) - single differences observed together for less
than 8 min are not fixed; the rule must hold for the data actually in common, not only for
the passes' spans (in config/hy2d-sim-gc.yaml a WL was wrongly fixed from 2 common epochs
whose empirical STD, 0.05 cycles, was small by chance). Generating model:
tests/ambiguity/_ambiguity_scenario.py with a consistent OSB product.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from _ambiguity_scenario import EPOCH, arc_inputs, scenario

from leopod.ambiguity.products import ar_product
from leopod.ambiguity.resolve import ArSettings, resolve_arc
from leopod.io.bias_sinex_write import write_bias_sinex
from leopod.workflow.config import section_defaults

AR = ArSettings.from_config(section_defaults("ambiguity"))
PHASES, CODES = ("L1C", "L2W"), ("C1W", "C2W")


def _resolve(s, obs, residuals, tmp_path):
    write_bias_sinex(s.products.osb, tmp_path / "osb.bia")
    product = ar_product(EPOCH + np.timedelta64(5, "h"), s.amb.sv.values, PHASES, CODES,
                         osb_path=tmp_path / "osb.bia")
    return resolve_arc(s.amb, residuals, obs, "G", PHASES, CODES, product.wl_sat_cyc,
                       dataclasses.replace(AR, product_guard=False),
                       sat_if_bias_m=product.per_ambiguity(s.amb.sv.values)).table


def test_sds_with_two_common_hmw_epochs_are_not_fixed(tmp_path):
    s = scenario(seed=31, hours=10.0, clocks="ordinary")
    residuals, obs = arc_inputs(s)
    full = _resolve(s, obs, residuals, tmp_path)
    # keep only 2 HMW epochs of every pass of one satellite: its passes keep their spans
    sv = str(s.amb.sv.values[0])
    pid = residuals.pass_index.sel(sv=sv).values
    keep = np.zeros(pid.size, bool)
    for p in np.unique(pid[pid >= 0]):
        keep[np.flatnonzero(pid == p)[:2]] = True
    thin = obs.copy(deep=True)
    thin["L1C"].loc[{"sv": sv}] = np.where(keep, thin["L1C"].sel(sv=sv).values, np.nan)
    table = _resolve(s, thin, residuals, tmp_path)

    involved = (full.sv_i.values == sv) | (full.sv_j.values == sv)
    assert involved.any() and (full.wl_fixed.values[involved] == 1).sum() > 0
    assert np.all(table.wl_n_common.values[involved] <= 2)
    assert not (table.wl_fixed.values[involved] == 1).any()
    assert all(str(r).startswith("common HMW data < 480 s")
               for r in table.wl_reason.values[involved])
    # the other single differences are decided as before
    np.testing.assert_array_equal(table.wl_fixed.values[~involved],
                                  full.wl_fixed.values[~involved])


def test_a_satellite_without_any_hmw_data_is_not_fixed_and_no_error(tmp_path):
    # every code of one satellite dropped (code-bias map cells without values): the arc is
    # resolved, that satellite's SDs are not (ambiguity step crashed before: "pass ids have
    # no HMW data")
    s = scenario(seed=31, hours=10.0, clocks="ordinary")
    residuals, obs = arc_inputs(s)
    sv = str(s.amb.sv.values[0])
    obs["C1W"].loc[{"sv": sv}] = np.nan
    table = _resolve(s, obs, residuals, tmp_path)
    involved = (table.sv_i.values == sv) | (table.sv_j.values == sv)
    assert involved.any() and np.all(table.wl_n_common.values[involved] == 0)
    assert not (table.wl_fixed.values[involved] == 1).any()
    assert (table.wl_fixed.values[~involved] == 1).sum() > 0

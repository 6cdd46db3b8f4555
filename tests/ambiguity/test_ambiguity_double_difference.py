"""Closed loop of the inter-satellite double-difference (DD) ambiguity resolution.

Authorities:
- the generating model (tests/ambiguity/_dd_scenario.py: two receivers tracking the same GPS
  satellites with receiver-specific WL and IF biases, the simulator's satellite biases,
  independent slips and noise of known statistics): every fixed DD WL and NL integer must
  equal the true one;
- analytic: in a DD the receiver and satellite biases cancel exactly (Zhang et al. 2024,
  eq. 3), so without noise the DD WL and NL floats are the true integers; the DD rows over
  the undifferenced ambiguities have the graph rank of the DD edges over the receiver single
  differences (module docstring of leopod.ambiguity.double_difference);
- Zhang et al. (2024), Lutan-1: 100 % WL and > 98 % NL of the independent DD ambiguities
  fixed from real data; the scenario's noise (HMW 0.25 cycles per 10-s epoch, float IF
  ambiguities ~3 mm) is of that kind, so the graph-rank rates must reach 98 % too;
- LAMBDA partial fixing (Teunissen 1995; Teunissen et al. 1999): with the float covariance
  inflated it fixes fewer DDs, none wrong.

Measured (seeds 5 and 6, 8 h, 10 GPS satellites): graph-rank rates WL 99.1 % / 99.0 %, NL
the same with rounding and Dong-Bock; partial LAMBDA fixes the whole independent NL set at
the nominal noise (seed 8, 4 h: 58 of 58) and 14 of 58 with the float sigmas inflated 2.5
times (NL sigma 0.066 -> 0.165 cycles); no wrong fix.

A test on real formation data is not possible: ../shared holds no two-receiver (formation)
data set.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import xarray as xr
from _ambiguity_scenario import EPOCH
from _dd_scenario import B_RX_IF_M, SIGNALS, W_RX_CYC, combined, dd_scenario, true_dd

from leopod.ambiguity.double_difference import (
    DdConstraints,
    ReceiverArc,
    dd_constraint_matrix,
    resolve_dd,
    resolve_dd_systems,
)
from leopod.ambiguity.independent import graph_rank
from leopod.ambiguity.resolve import ArSettings
from leopod.io.netcdf import write_netcdf
from leopod.signals import SystemSignals
from leopod.workflow.config import section_defaults

PHASES, CODES = ("L1C", "L2W"), ("C1W", "C2W")
SETTINGS = ArSettings.from_config(section_defaults("ambiguity"))


def _resolve(s, settings=SETTINGS):
    return resolve_dd(*s.arcs, "G", PHASES, CODES, settings)


def _true_if(s):
    return np.concatenate([s.a.b_true, s.b.b_true])


def test_receiver_and_satellite_biases_cancel_exactly():
    s = dd_scenario(seed=11, noise=False)
    assert W_RX_CYC[0] != W_RX_CYC[1] and B_RX_IF_M[0] != B_RX_IF_M[1]
    res = _resolve(s)
    t = res.table
    wl_true, nl_true = true_dd(s, t, "n_wl"), true_dd(s, t, "n1")
    finite = np.isfinite(t.wl_float_cyc.values)
    assert finite.sum() > 100
    np.testing.assert_allclose(t.wl_float_cyc.values[finite], wl_true[finite], atol=1e-9)
    wl = t.wl_fixed.values == 1
    np.testing.assert_allclose(t.nl_float_cyc.values[wl], nl_true[wl], atol=1e-6)
    # the constraints are the DDs of the true float IF parameters (biases included)
    c = res.constraints
    m = dd_constraint_matrix(c, s.a.amb.sizes["ambiguity"], s.b.amb.sizes["ambiguity"])
    np.testing.assert_allclose(m @ _true_if(s), c.value_m, atol=1e-9)


@pytest.mark.parametrize("decision", ["rounding", "dong_bock"])
@pytest.mark.parametrize("seed", [5, 6])
def test_fixed_dd_integers_equal_the_truth(decision, seed):
    s = dd_scenario(seed=seed)
    res = _resolve(s, dataclasses.replace(SETTINGS, decision=decision))
    t = res.table
    wl, nl = t.wl_fixed.values == 1, t.nl_fixed.values == 1
    assert np.array_equal(t.wl_integer.values[wl], true_dd(s, t, "n_wl")[wl])
    assert np.array_equal(t.nl_integer.values[nl], true_dd(s, t, "n1")[nl])
    assert t.attrs["wl_fixing_rate"] >= 0.98 and t.attrs["nl_fixing_rate"] >= 0.98
    assert 0.0 < t.attrs["nl_dd_fixed_share"] <= t.attrs["wl_dd_fixed_share"] <= 1.0
    # every rejection says why
    assert np.all((t.wl_reason.values != "") == ~wl)
    assert np.all((t.nl_reason.values != "") == ~nl)
    # constraints: independent over the undifferenced ambiguities, values of the truth
    c = res.constraints
    n_a, n_b = s.a.amb.sizes["ambiguity"], s.b.amb.sizes["ambiguity"]
    m = dd_constraint_matrix(c, n_a, n_b)
    assert c.value_m.size == graph_rank(t.node_i.values[nl], t.node_j.values[nl])
    assert np.linalg.matrix_rank(m) == c.value_m.size
    np.testing.assert_allclose(m @ _true_if(s), c.value_m, atol=1e-9)


def test_dd_rank_over_ambiguities_is_the_graph_rank():
    s = dd_scenario(seed=7, hours=4.0)
    t = _resolve(s).table
    rows = dd_constraint_matrix(
        _all_rows(t), s.a.amb.sizes["ambiguity"], s.b.amb.sizes["ambiguity"])
    assert np.linalg.matrix_rank(rows) == graph_rank(t.node_i.values, t.node_j.values)
    assert t.attrs["n_independent"] == graph_rank(t.node_i.values, t.node_j.values)


def _all_rows(t):
    n = t.sizes["dd"]
    return DdConstraints(t.amb_a_i.values, t.amb_b_i.values, t.amb_a_j.values,
                         t.amb_b_j.values, np.zeros(n), np.ones(n))


def test_partial_lambda_fixes_fewer_with_inflated_sigma_and_never_wrong():
    ils = dataclasses.replace(SETTINGS, nl_method="ils")
    counts = []
    for factor in (1.0, 2.5):
        s = dd_scenario(seed=8, hours=4.0, sigma_if_m=0.003 * factor,
                        factor_if_m=0.001 * factor)
        t = _resolve(s, ils).table
        nl = t.nl_fixed.values == 1
        assert np.array_equal(t.nl_integer.values[nl], true_dd(s, t, "n1")[nl])
        counts.append(int(nl.sum()))
    assert counts[0] > counts[1] > 0


def _arc(sv, spans, value_m, times):
    """One receiver tracking one pass per satellite over ``spans`` (epoch index ranges)."""
    pid = np.full((times.size, len(sv)), -1)
    for k, (a, b) in enumerate(spans):
        pid[a:b, k] = k
    coords = {"time": times, "sv": sv}
    zero = xr.DataArray(np.where(pid >= 0, 0.0, np.nan), dims=("time", "sv"), coords=coords)
    amb = xr.Dataset({"pass_index": ("ambiguity", np.arange(len(sv))),
                      "value_m": ("ambiguity", np.asarray(value_m, float)),
                      "covariance_m2": (("ambiguity", "ambiguity_b"), 1e-6 * np.eye(len(sv)))})
    obs = xr.Dataset({"L1C": zero, "L2W": zero, "C1W": zero, "C2W": zero})
    pass_index = xr.DataArray(pid, dims=("time", "sv"), coords=coords)
    return ReceiverArc(amb, xr.Dataset({"pass_index": pass_index}), obs)


@pytest.mark.parametrize(("common_epochs", "formed"), [(47, False), (49, True)])
def test_dd_with_too_little_common_time_is_not_formed(common_epochs, formed):
    """Two satellites whose common time is 470 s or 490 s (10-s epochs; min_common_s 480 s,
    Peng et al. 2021)."""
    times = EPOCH + np.arange(200) * np.timedelta64(10, "s")
    sv = ["G01", "G02"]
    a = _arc(sv, [(0, 100), (100 - common_epochs - 1, 200)], [0.0, 0.0], times)
    b = _arc(sv, [(0, 100), (0, 200)], [0.0, 0.0], times)
    t = resolve_dd(a, b, "G", PHASES, CODES, SETTINGS).table
    assert t.sizes["dd"] == int(formed)


def test_missing_float_ambiguity_is_named():
    times = EPOCH + np.arange(100) * np.timedelta64(10, "s")
    a = _arc(["G01", "G02"], [(0, 100), (0, 100)], [0.0, 0.0], times)
    b = _arc(["G01", "G02"], [(0, 100), (0, 100)], [0.0, 0.0], times)
    b = b._replace(amb=b.amb.isel(ambiguity=[0], ambiguity_b=[0]))
    with pytest.raises(ValueError, match=r"receiver LT1B: passes \[1\]"):
        resolve_dd(a, b, "G", PHASES, CODES, SETTINGS, names=("LT1A", "LT1B"))


def test_table_is_netcdf_ready(tmp_path):
    t = _resolve(dd_scenario(seed=9, hours=3.0)).table
    path = write_netcdf(t, tmp_path / "dd.nc", step="test")
    back = xr.open_dataset(path)
    assert back.sizes["dd"] == t.sizes["dd"]
    assert np.array_equal(back.nl_fixed.values, t.nl_fixed.values)
    assert back.attrs["float_covariance"].startswith("the two receivers'")


def test_combined_systems_fix_each_system_on_its_own():
    """GPS L1/L2 and Galileo E1/E5a in one arc per receiver: DDs only within a system, each
    with its own wavelengths; the joined table keeps the truth and the graph-rank rates."""
    s = combined(dd_scenario(seed=5, hours=4.0), dd_scenario(seed=6, hours=4.0, system="E"))
    signals = {x: SystemSignals(phase=p, code=c, pod_code=c, exclude_geo=False)
               for x, (p, c) in SIGNALS.items()}
    res = resolve_dd_systems(*s.arcs, signals, SETTINGS)
    t = res.table
    assert set(t.system.values) == {"G", "E"}
    assert np.all(t.sv_i.str[0].values == t.system.values)
    assert np.all(t.sv_j.str[0].values == t.system.values)
    wl, nl = t.wl_fixed.values == 1, t.nl_fixed.values == 1
    assert np.array_equal(t.wl_integer.values[wl], true_dd(s, t, "n_wl")[wl])
    assert np.array_equal(t.nl_integer.values[nl], true_dd(s, t, "n1")[nl])
    assert t.attrs["nl_fixing_rate"] >= 0.98 and t.attrs["E_nl_fixing_rate"] >= 0.98
    c = res.constraints
    m = dd_constraint_matrix(c, s.a.amb.sizes["ambiguity"], s.b.amb.sizes["ambiguity"])
    np.testing.assert_allclose(m @ _true_if(s), c.value_m, atol=1e-9)
    assert np.linalg.matrix_rank(m) == c.value_m.size

"""The product guard in the whole single-difference chain (leopod.ambiguity.resolve_arc).

Authority: the generating model of tests/ambiguity/_ambiguity_scenario.py (true integers,
true float SDs) with the simulator's products written to and read back from files, both
kinds leopod knows: CNES/CLS WL records with integer-recovery clocks, and Bias-SINEX OSBs
with ordinary clocks. Faults (leopod.simulate.product_faults): a flipped sign of every bias
record (issue 19), and biases/clocks of another realisation ("another analysis centre":
WL right, NL not integer). Done-when of issue 19, part 1: with a faulty product nothing is
fixed and the table says why; with the right product the guard passes and the fixing is
the one without the guard.
"""

from __future__ import annotations

import dataclasses
import logging

import numpy as np
import pytest
from _ambiguity_scenario import EPOCH, arc_inputs, scenario

from leopod.ambiguity.products import ar_product
from leopod.ambiguity.resolve import ArSettings, resolve_arc
from leopod.estimation.fixed_arc import constraints_of
from leopod.io.bias_sinex_write import write_bias_sinex
from leopod.io.wlbias_write import write_wl_bias
from leopod.workflow.config import section_defaults

AR = ArSettings.from_config(section_defaults("ambiguity"))
SIGNALS = {"phases": ("L1C", "L2W"), "codes": ("C1W", "C2W")}
#: product kind -> clocks of the float solution
KINDS = {"wl": "integer", "osb": "ordinary"}


def _run(tmp_path, fault: str, kind: str, guard: bool, **settings):
    s = scenario(seed=31, hours=10.0, fault=fault, clocks=KINDS[kind])
    write_wl_bias(s.products.wl, tmp_path / "wl.txt")
    write_bias_sinex(s.products.osb, tmp_path / "osb.bia")
    files = ({"wl_bias_path": tmp_path / "wl.txt"} if kind == "wl"
             else {"osb_path": tmp_path / "osb.bia"})
    product = ar_product(EPOCH + np.timedelta64(5, "h"), s.amb.sv.values, SIGNALS["phases"],
                         SIGNALS["codes"], **files)
    residuals, obs = arc_inputs(s)
    res = resolve_arc(s.amb, residuals, obs, "G", SIGNALS["phases"], SIGNALS["codes"],
                      product.wl_sat_cyc,
                      dataclasses.replace(AR, product_guard=guard, **settings),
                      sat_if_bias_m=product.per_ambiguity(s.amb.sv.values))
    return s, res


def _wrong(s, res) -> dict:
    """Wrong WL fixes, and constraints whose value is off the true float SD by > 1 mm
    (a wrong integer, or a right one with a wrong bias) — counted against the truth."""
    t = res.table
    i, j = t.amb_i.values, t.amb_j.values
    wl = t.wl_fixed.values == 1
    c = t.constrained.values == 1
    off = np.abs(t.fixed_if_m.values[c] - (s.b_true[i] - s.b_true[j])[c])
    return {"wl_fixed": int(wl.sum()),
            "wl_wrong": int(np.sum(t.wl_integer.values[wl] != (s.n_wl[i] - s.n_wl[j])[wl])),
            "constrained": int(c.sum()), "constrained_wrong": int(np.sum(off > 1e-3))}


@pytest.mark.parametrize("kind", list(KINDS))
def test_right_product_passes_and_fixing_is_unchanged(tmp_path, kind):
    s, with_guard = _run(tmp_path, "none", kind, guard=True)
    _, without = _run(tmp_path, "none", kind, guard=False)
    t = with_guard.table
    assert t.attrs["product_guard"] == "accepted"
    assert t.attrs["wl_guard_p_value"] <= AR.guard_alpha
    assert t.attrs["nl_guard_p_value"] <= AR.guard_alpha
    for name in ("wl_fixed", "nl_fixed", "constrained", "wl_integer", "nl_integer"):
        np.testing.assert_array_equal(t[name].values, without.table[name].values)
    for a, b in zip(with_guard.constraints, without.constraints, strict=True):
        np.testing.assert_array_equal(a, b)
    counts = _wrong(s, with_guard)
    assert counts["constrained"] > 50 and counts["wl_wrong"] == counts["constrained_wrong"] == 0


@pytest.mark.parametrize("kind", list(KINDS))
def test_flipped_sign_is_refused(tmp_path, kind, caplog):
    s, before = _run(tmp_path, "flipped_sign", kind, guard=False)
    # without the guard the flipped product fixes wrong wide lanes and wrong constraints
    counts = _wrong(s, before)
    assert counts["wl_wrong"] > 100 and counts["constrained_wrong"] > 10
    with caplog.at_level(logging.WARNING, logger="leopod.ambiguity.resolve"):
        _, after = _run(tmp_path, "flipped_sign", kind, guard=True)
    t = after.table
    assert _wrong(s, after) == {"wl_fixed": 0, "wl_wrong": 0, "constrained": 0,
                                "constrained_wrong": 0}
    assert t.nl_fixed.values.sum() == 0 and after.constraints[0].size == 0
    assert constraints_of(t, AR.constraint_sigma_m)[0].size == 0   # what fixed_pod reads
    assert t.attrs["product_guard"] == "refused"
    assert t.attrs["wl_guard_p_value"] > AR.guard_alpha
    assert "WL fractional parts do not cluster at 0" in t.attrs["product_guard_reason"]
    assert set(t.wl_reason.values) == {t.attrs["product_guard_reason"]}
    assert "nothing is fixed: product refused: WL" in caplog.text


@pytest.mark.parametrize("kind", list(KINDS))
def test_biases_of_another_centre_are_refused_by_the_narrow_lane(tmp_path, kind):
    s, before = _run(tmp_path, "other_centre", kind, guard=False)
    # the WL is right, but constraints carry the other centre's NL bias
    counts = _wrong(s, before)
    assert counts["wl_wrong"] == 0 and counts["constrained_wrong"] > 10
    _, after = _run(tmp_path, "other_centre", kind, guard=True)
    t = after.table
    assert t.attrs["wl_guard_p_value"] <= AR.guard_alpha
    assert t.attrs["nl_guard_p_value"] > AR.guard_alpha
    assert "NL fractional parts do not cluster at 0" in t.attrs["product_guard_reason"]
    assert t.wl_fixed.values.sum() == t.nl_fixed.values.sum() == 0
    assert after.constraints[0].size == 0


def test_table_states_the_integer_convention(tmp_path):
    _, res = _run(tmp_path, "none", "wl", guard=True)
    attrs = res.table.attrs
    assert "(N_L1C - N_L2W)_i - (N_L1C - N_L2W)_j" in attrs["convention_wl_integer"]
    assert "N_L1C,i - N_L1C,j" in attrs["convention_nl_integer"]
    assert "corrected = observed - OSB" in attrs["convention_osb"]
    assert "wind-up" in attrs["convention_windup"]

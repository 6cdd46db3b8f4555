"""C1-based wide-lane fixing with and without the P1−C1 DCB (issue 19, part 3, done-when).

A receiver that tracks the C/A code C1C instead of the semi-codeless P code C1W sees, per
satellite, ``d^s(C1C) = d^s(C1W) − DCB(P1−C1)`` (CODE sign, leopod.io.dcb). The satellite
clocks and the CNES/CLS wide-lane product refer to C1W/C2W (the clock-reference codes), so the
C1C-based HMW combination carries ``−f1 DCB / ((f1 + f2) λ_WL)`` ≈ −0.196 WL cycles per ns of
DCB, which differs between satellites.

Authorities: the generating model of tests/ambiguity/_ambiguity_scenario.py (true integers,
the simulator's CNES WL product written to and read back from a file), the simulator's
satellite code biases (P1−C1 with the 1-ns spread of CODE's P1C10810_RINEX.DCB, the schema
default of simulate.biases.dcb_other_sigma_ns) and, where ../shared is present, the real
satellite P1−C1 values of that CODE file; the IGS convention ``C1 → C1 + DCB(P1−C1)``
(IGS p1c1bias.hist, "cc2noncc"). Without the correction some WL fixes are wrong; with the
DCB file applied by leopod.gnss.signal_bias, none is and the fixing equals the C1W-based one.
Measured (seed 31, 10 satellites, 423 WL fixes with C1W): real CODE P1-C1 values (spread
1.02 ns): 251 fixed / 7 wrong without the DCB, 423 / 0 with it; simulated values of this draw
(spread 0.44 ns): 393 / 0 without, 423 / 0 with.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from _ambiguity_scenario import EPOCH, arc_inputs, scenario

from leopod.ambiguity.products import ar_product
from leopod.ambiguity.resolve import ArSettings, resolve_arc
from leopod.constants import C_LIGHT_M_S
from leopod.gnss.signal_bias import SignalBiases, SignalBiasProduct, correct_signal_biases
from leopod.io.dcb import read_code_dcb
from leopod.io.dcb_write import write_code_dcb
from leopod.io.wlbias_write import write_wl_bias
from leopod.simulate.campaign import p1c1_dcb
from leopod.workflow.config import section_defaults

#: the default campaign's decision (config/config.yaml: rounding), without the product
#: guard, so that the counts show the wide lane itself
AR = dataclasses.replace(ArSettings.from_config(section_defaults("ambiguity")),
                         decision="rounding", product_guard=False)
PHASES = ("L1C", "L2W")
DAY = str(EPOCH.astype("datetime64[D]").item().strftime("%Y-%j"))
P1C1_REAL = "products_2008-279_whu/P1C10810_RINEX.DCB.Z"


def _wrong(s, res) -> tuple[int, int]:
    """(WL fixed, WL wrong) against the true integers."""
    t = res.table
    i, j = t.amb_i.values, t.amb_j.values
    wl = t.wl_fixed.values == 1
    return int(wl.sum()), int(np.sum(t.wl_integer.values[wl] != (s.n_wl[i] - s.n_wl[j])[wl]))


def _resolve(s, obs, codes, product):
    residuals = arc_inputs(s)[0]
    return resolve_arc(s.amb, residuals, obs, "G", PHASES, codes, product.wl_sat_cyc, AR,
                       sat_if_bias_m=product.per_ambiguity(s.amb.sv.values))


def _c1c_case(tmp_path, dcb_path_truth):
    """Scenario, CNES product, C1W- and C1C-tracking observations (C1C = C1W − DCB)."""
    s = scenario(seed=31, hours=10.0, clocks="integer")
    write_wl_bias(s.products.wl, tmp_path / "wl.txt")
    product = ar_product(EPOCH + np.timedelta64(5, "h"), s.amb.sv.values, PHASES,
                         ("C1W", "C2W"), wl_bias_path=tmp_path / "wl.txt")
    _, obs = arc_inputs(s)
    dcb = read_code_dcb(dcb_path_truth)
    dcb_m = dcb.dcb_s.reindex(sv=s.svs).values * C_LIGHT_M_S
    assert np.isfinite(dcb_m).all()
    obs["C1C"] = obs["C1W"] - dcb_m[None, :]
    return s, product, obs, dcb_m


@pytest.mark.parametrize("source", ["simulated", "code_2008_10"])
def test_c1c_wide_lane_wrong_without_dcb_and_none_with_it(tmp_path, source, request):
    if source == "simulated":
        s0 = scenario(seed=31, hours=10.0, clocks="integer")
        truth_path = tmp_path / "p1c1_sim.dcb"
        write_code_dcb(p1c1_dcb(s0.biases), truth_path)
    else:
        truth_path = request.getfixturevalue("shared_data") / P1C1_REAL
    s, product, obs, dcb_m = _c1c_case(tmp_path, truth_path)
    # realistic size: the spread of the satellite DCBs is of order 1 ns (0.3 m)
    spread_ns = np.std(dcb_m) / C_LIGHT_M_S * 1e9
    assert 0.3 < spread_ns < 3.0

    reference = _resolve(s, obs, ("C1W", "C2W"), product)
    before = _resolve(s, obs, ("C1C", "C2W"), product)
    biases = SignalBiases({DAY: SignalBiasProduct.read(DAY, None, [truth_path])},
                          "clock_reference", DAY)
    corrected, summary = correct_signal_biases(obs, biases, ["C1C", "C1W", "C2W", *PHASES])
    after = _resolve(s, corrected, ("C1C", "C2W"), product)

    n_ref, wrong_ref = _wrong(s, reference)
    n_before, wrong_before = _wrong(s, before)
    n_after, wrong_after = _wrong(s, after)
    print(f"\n[{source}] P1-C1 spread {spread_ns:.2f} ns; WL fixed/wrong: C1W "
          f"{n_ref}/{wrong_ref}, C1C without DCB {n_before}/{wrong_before}, C1C with DCB "
          f"{n_after}/{wrong_after}")
    assert wrong_ref == 0 and n_ref > 100
    # the uncorrected DCB costs fixes, and with the real spread (1.02 ns) it fixes wrong
    # integers (the ten simulated satellites of this draw spread only 0.44 ns)
    assert n_before < n_ref
    if source == "code_2008_10":
        assert wrong_before > 0
    assert wrong_after == 0
    # the corrected C1C equals C1W to the file's 0.001 ns: the same decisions as with C1W
    np.testing.assert_array_equal(after.table.wl_fixed.values, reference.table.wl_fixed.values)
    np.testing.assert_array_equal(after.table.wl_integer.values,
                                  reference.table.wl_integer.values)
    assert summary["C1C"]["rms_m"] > 0.1 and summary["C1W"]["rms_m"] == 0.0


def test_osb_applied_to_observations_is_not_applied_twice(tmp_path):
    """With the OSBs already removed from codes and phases (absolute mode), the AR product
    contributes zero (NaN for satellites the file lacks) instead of w^s and b^s_IF again."""
    from leopod.io.bias_sinex_write import write_bias_sinex

    s = scenario(seed=31, hours=10.0)
    write_bias_sinex(s.products.osb, tmp_path / "osb.bia")
    svs = [*s.svs, "G99"]
    kwargs = {"osb_path": tmp_path / "osb.bia"}
    plain = ar_product(EPOCH, svs, PHASES, ("C1W", "C2W"), **kwargs)
    applied = ar_product(EPOCH, svs, PHASES, ("C1W", "C2W"), osb_applied=True, **kwargs)
    assert np.abs(plain.wl_sat_cyc.sel(sv=s.svs).values).max() > 0.05
    np.testing.assert_array_equal(applied.wl_sat_cyc.sel(sv=s.svs).values, 0.0)
    np.testing.assert_array_equal(applied.if_phase_bias_m.sel(sv=s.svs).values, 0.0)
    assert np.isnan(applied.wl_sat_cyc.sel(sv="G99")) and np.isnan(plain.wl_sat_cyc.sel(sv="G99"))
    assert "applied to the observations" in applied.label

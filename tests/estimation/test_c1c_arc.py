"""C1C-based float POD and AR of a simulated arc, without and with the P1−C1 DCB.

The simulated receiver's C1C carries the satellite bias ``d^s(C1C) = d^s(C1W) − DCB(P1−C1)``
(leopod.simulate.biases), while the simulated clocks refer to C1W/C2W (the real products'
convention). The DCB file the simulator writes (leopod.simulate.campaign.p1c1_dcb, CODE
layout) reaches the POD through ``ArcData.signal_biases`` (leopod.estimation.arc.setup_arc)
and the AR through leopod.gnss.signal_bias.correct_signal_biases, as in the workflow.

Authorities: the simulation truth (integer ambiguities, leopod.simulate.ambiguity_truth) and
the IGS convention ``C1 → C1 + DCB(P1−C1)`` (IGS p1c1bias.hist, "cc2noncc"). With the DCB the
IF code residuals lose the satellite-dependent ``2.546 DCB`` (so their RMS drops) and no WL or
NL fix is wrong; without it the fixing is worse (fewer fixes, wrong fixes or a refused
product).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import xarray as xr
from _simulated_arc import DAY, simulated_arc

from leopod.ambiguity.resolve import resolve_arc
from leopod.estimation.arc import run_arc
from leopod.gnss.signal_bias import SignalBiases, SignalBiasProduct, correct_signal_biases
from leopod.io.dcb_write import write_code_dcb
from leopod.simulate.ambiguity_truth import true_single_differences, wrong_fixes
from leopod.simulate.campaign import biases_for, p1c1_dcb


@pytest.fixture(scope="module")
def arcs(tmp_path_factory):
    folder = tmp_path_factory.mktemp("arc")
    ref = simulated_arc(folder)
    write_code_dcb(p1c1_dcb(biases_for(xr.load_dataset(folder / "b.nc"))), folder / "p1c1.dcb")
    biases = SignalBiases({DAY: SignalBiasProduct.read(DAY, None, [folder / "p1c1.dcb"])},
                          "clock_reference", DAY)
    signals = dataclasses.replace(ref.signals, pod_code=("C1C", "C2W"))
    date, data, _, arc, pod, forces, pco = ref.args
    out = {}
    for name, bias in (("without", None), ("with", biases)):
        solution = run_arc(date, dataclasses.replace(data, signal_biases=bias), signals, arc,
                           pod, forces, pco, limits=ref.limits)
        obs = correct_signal_biases(ref.obs, bias, signals.observations)[0]
        table = resolve_arc(solution.ambiguities, solution.residuals, obs, "G", signals.phase,
                            signals.pod_code, ref.product.wl_sat_cyc, ref.ar).table
        wrong = wrong_fixes(table, *true_single_differences(table, solution.residuals,
                                                            [ref.truth]))
        code = solution.residuals.code_residual_m.values
        out[name] = {"table": table, "wrong": wrong,
                     "code_rms_m": float(np.sqrt(np.nanmean(code**2)))}
    return out


def test_dcb_removes_the_c1c_bias_from_the_pod_codes(arcs):
    before, after = arcs["without"]["code_rms_m"], arcs["with"]["code_rms_m"]
    print(f"\nIF code residual RMS: without DCB {before:.3f} m, with DCB {after:.3f} m")
    assert after < 0.9 * before


def test_c1c_ambiguity_resolution_has_no_wrong_fix_with_the_dcb(arcs):
    w0, w1 = arcs["without"]["wrong"], arcs["with"]["wrong"]
    t0, t1 = arcs["without"]["table"], arcs["with"]["table"]
    print(f"\nwithout DCB: {w0}, guard {t0.attrs['product_guard']}\nwith DCB: {w1}, "
          f"guard {t1.attrs['product_guard']}")
    assert t1.attrs["product_guard"] == "accepted"
    assert w1["wl_fixed"] > 0 and w1["constrained"] > 0
    assert w1["wl_wrong"] == 0 and w1["nl_wrong"] == 0 and w1["constrained_wrong"] == 0
    # without the DCB the fixing is worse: refused, fewer fixes, or wrong ones
    assert (w0["wl_wrong"] > 0 or w0["wl_fixed"] < w1["wl_fixed"]
            or t0.attrs["product_guard"] != "accepted")

"""The simulator's P1−C1 DCB product (leopod.simulate.campaign.p1c1_dcb).

Authorities: the simulator's bias model (leopod.simulate.biases: ``d^s(C1C) = d^s(C1W) −
DCB(P1−C1)``, the DCBs drawn with the spread of CODE's P1C10810_RINEX.DCB, 1.04 ns, as the
schema default ``simulate.biases.dcb_other_sigma_ns = 1``); the CODE sign ``DCB(P1−C1) =
bias(P1) − bias(C1)`` (leopod.io.dcb); the clock datum of the real products (the
ionosphere-free combination of the C1W/C2W OSBs is zero), so that a receiver tracking C1C
differs from the clock reference by the DCB alone.
"""

from __future__ import annotations

import numpy as np

from leopod.constants import C_LIGHT_M_S
from leopod.io.dcb import read_code_dcb
from leopod.io.dcb_write import write_code_dcb
from leopod.signals import frequency_hz
from leopod.simulate.biases import BiasSettings, simulate_biases
from leopod.simulate.campaign import p1c1_dcb
from leopod.workflow.config import section_defaults

GPS = [f"G{i:02d}" for i in range(1, 33)]
SETTINGS = BiasSettings.from_config(section_defaults("simulate_biases"))


def test_p1c1_dcb_is_c1w_minus_c1c_and_round_trips(tmp_path):
    biases = simulate_biases(GPS, None, np.random.default_rng(7), epoch="2019-01-01",
                             settings=SETTINGS)
    dcb = p1c1_dcb(biases)
    code = biases.code_sat_m
    expected_m = (code.sel(code_signal="C1W") - code.sel(code_signal="C1C")).values
    np.testing.assert_allclose(dcb.dcb_s.values * C_LIGHT_M_S, expected_m, rtol=1e-12)
    # a constellation-mean-free draw with the configured spread (32 satellites)
    ns = dcb.dcb_s.values * 1e9
    assert abs(ns.mean()) < 1e-9
    assert 0.6 * SETTINGS.dcb_other_sigma_ns < ns.std() < 1.5 * SETTINGS.dcb_other_sigma_ns
    # the clock reference is C1W/C2W (zero IF), not the C1C a receiver may track
    f1, f2 = frequency_hz("G", "C1W"), frequency_hz("G", "C2W")
    d1, d2 = code.sel(code_signal="C1W").values, code.sel(code_signal="C2W").values
    np.testing.assert_allclose((f1**2 * d1 - f2**2 * d2) / (f1**2 - f2**2), 0.0, atol=1e-12)
    write_code_dcb(dcb, tmp_path / "p1c1.dcb")
    back = read_code_dcb(tmp_path / "p1c1.dcb")
    assert back.attrs["dcb_type"] == "P1-C1"
    np.testing.assert_allclose(back.dcb_s.values, dcb.dcb_s.values, rtol=0, atol=5e-13)


def test_no_c1c_no_dcb():
    biases = simulate_biases(GPS[:4], {"G": ("C1W", "C2W", "L1C", "L2W")},
                             np.random.default_rng(7), epoch="2019-01-01", settings=SETTINGS)
    assert p1c1_dcb(biases).sizes["sv"] == 0

"""Deliberately wrong AR products of the simulator (leopod.simulate.product_faults).

Authority: the definitions of the faults — a flipped sign negates every record; biases of
"another analysis centre" shift both satellite phase biases by the same δ^s cycles, which
leaves ``w^s = β1 − β2 − ...`` unchanged and moves the ionosphere-free phase bias by
``c δ^s (f1 − f2)/(f1² − f2²) = λ_NL δ^s`` (leopod.simulate.biases.if_phase_bias_m) — and the
readers of the files (Bias-SINEX, CNES WL) through which leopod sees them.
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from leopod.ambiguity import sat_if_phase_bias_osb, sat_wl_bias_osb
from leopod.constants import C_LIGHT_M_S
from leopod.io.bias_sinex import read_bias_sinex
from leopod.io.bias_sinex_write import write_bias_sinex
from leopod.signals import frequency_hz
from leopod.simulate.biases import BiasSettings, ar_products, simulate_biases
from leopod.simulate.product_faults import faulty_products
from leopod.workflow.config import section_defaults

EPOCH = np.datetime64("2020-06-01T00:00", "ns")
GPS = [f"G{i:02d}" for i in range(1, 33)]


@pytest.fixture(scope="module")
def biases():
    return simulate_biases(GPS, None, np.random.default_rng(7), epoch=EPOCH,
                           settings=BiasSettings.from_config(section_defaults("simulate_biases")))


def _read(ds, tmp_path):
    write_bias_sinex(ds, tmp_path / "p.bia")
    return read_bias_sinex(tmp_path / "p.bia")


def test_no_fault_is_the_consistent_product(biases):
    right = ar_products(biases)
    faulty = faulty_products(biases, "none", np.random.default_rng(0))
    xr.testing.assert_identical(faulty.products.osb, right.osb)
    xr.testing.assert_identical(faulty.products.wl, right.wl)
    assert faulty.clock_biases is biases


def test_flipped_sign_negates_every_record(biases):
    right = ar_products(biases)
    flipped = faulty_products(biases, "flipped_sign", np.random.default_rng(0))
    np.testing.assert_array_equal(flipped.products.osb.value_s.values, -right.osb.value_s.values)
    np.testing.assert_array_equal(flipped.products.wl.wl_bias_cyc.values,
                                  -right.wl.wl_bias_cyc.values)
    xr.testing.assert_identical(flipped.products.truth, right.truth)
    assert flipped.clock_biases is biases   # the integer clocks stay right


def test_other_centre_keeps_the_wide_lane_and_breaks_the_narrow_lane(biases, tmp_path):
    right = ar_products(biases)
    other = faulty_products(biases, "other_centre", np.random.default_rng(3))
    xr.testing.assert_identical(other.products.truth, right.truth)
    f1, f2 = frequency_hz("G", "L1C"), frequency_hz("G", "L2W")
    lam_nl = C_LIGHT_M_S / (f1 + f2)
    a, b = _read(right.osb, tmp_path), _read(other.products.osb, tmp_path)
    np.testing.assert_allclose(sat_wl_bias_osb(b, GPS, EPOCH).values,
                               sat_wl_bias_osb(a, GPS, EPOCH).values, rtol=0, atol=1e-5)
    shift = (other.clock_biases.phase_sat_cyc - biases.phase_sat_cyc).values
    np.testing.assert_allclose(shift[:, 0], shift[:, 1], rtol=0, atol=1e-12)
    delta_nl = (sat_if_phase_bias_osb(b, GPS, EPOCH).values
                - sat_if_phase_bias_osb(a, GPS, EPOCH).values) / lam_nl
    np.testing.assert_allclose(delta_nl, shift[:, 0], rtol=0, atol=1e-4)
    assert np.abs(delta_nl - np.round(delta_nl)).max() > 0.3   # not integer


def test_unknown_fault_is_refused(biases):
    with pytest.raises(ValueError, match="unknown AR product fault 'sign'"):
        faulty_products(biases, "sign", np.random.default_rng(0))

"""Orbit records their producer marks as unusable are missing records
(leopod.gnss.products.usable_positions).

Authority: SP3-d (Hilla 2016): the P record's manoeuvre flag "M" (column 79), the record
accuracy exponents (base ** n mm, columns 62-69) and the header accuracy (2 ** n mm); the
threshold leopod.gnss.products.MAX_ORBIT_SIGMA_M.
"""

import logging

import numpy as np
import xarray as xr

from leopod.gnss.products import MAX_ORBIT_SIGMA_M, usable_positions


def _orbit(**extra):
    pos = np.ones((4, 3, 3)) * 2.6e7
    return xr.Dataset({"pos_m": (("time", "sv", "xyz"), pos), **extra},
                      coords={"time": np.arange(4).astype("datetime64[m]").astype("datetime64[ns]"),
                              "sv": ["G01", "G02", "G03"], "xyz": ["x", "y", "z"]})


def test_unflagged_orbit_is_unchanged():
    orbit = _orbit()
    np.testing.assert_array_equal(usable_positions(orbit), orbit.pos_m.values)


def test_flags_and_accuracies_make_records_missing(caplog):
    flag = np.zeros((4, 3), np.int8)
    flag[1, 0] = 1                                     # G01 manoeuvres at epoch 1
    sigma = np.full((4, 3, 3), 0.01)
    sigma[2, 1, 2] = 2 * MAX_ORBIT_SIGMA_M             # G02's z record at epoch 2
    orbit = _orbit(manoeuvre_flag=(("time", "sv"), flag),
                   pos_sigma_m=(("time", "sv", "xyz"), sigma),
                   orbit_accuracy_m=(("sv",), [0.02, 0.02, 4.096]))   # G03: 2**12 mm
    with caplog.at_level(logging.WARNING):
        pos = usable_positions(orbit)
    missing = np.isnan(pos).all(axis=2)
    expected = np.zeros((4, 3), bool)
    expected[1, 0] = expected[2, 1] = True
    expected[:, 2] = True
    np.testing.assert_array_equal(missing, expected)
    assert "6 records flagged" in caplog.text and "G01 1, G02 1, G03 4" in caplog.text
    assert not np.isnan(orbit.pos_m.values).any()      # the dataset itself is untouched

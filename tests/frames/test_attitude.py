"""Nominal attitude and antenna-frame angles on an equatorial orbit (analytic truth)."""

import numpy as np
import pytest

from leopod.constants import OMEGA_EARTH_RAD_S
from leopod.frames.attitude import antenna_angles, body_to_ef, nominal_body_axes

A = 7_000e3
V = 7_546.0


def _frame():
    r = np.array([[A, 0.0, 0.0]])
    v_inertial = np.array([[0.0, V, 0.0]])
    v_ef = v_inertial - np.cross([0.0, 0.0, OMEGA_EARTH_RAD_S], r)   # Earth-fixed velocity
    return nominal_body_axes(r, v_ef)


def test_axes_of_equatorial_prograde_orbit():
    rot = _frame()[0]
    np.testing.assert_allclose(rot[2], [-1, 0, 0], atol=1e-12)   # Z to the geocentre
    np.testing.assert_allclose(rot[0], [0, 1, 0], atol=1e-12)    # X along inertial velocity
    np.testing.assert_allclose(rot[1], [0, 0, -1], atol=1e-12)   # Y opposite the orbit normal


@pytest.mark.parametrize("los,el,az", [
    ([1, 0, 0], 90.0, None),       # zenith
    ([0, 1, 0], 0.0, 0.0),         # flight direction
    ([0, 0, -1], 0.0, 90.0),       # +Y
    ([0, -1, 0], 0.0, 180.0),      # backwards
    ([1, 0, 1], 45.0, 270.0),      # 45° up towards the orbit normal (−Y)
])
def test_antenna_angles(los, el, az):
    e, a = antenna_angles(_frame(), np.array([[los]], dtype=float))
    assert e[0, 0] == pytest.approx(el, abs=1e-9)
    if az is not None:
        assert a[0, 0] == pytest.approx(az, abs=1e-9)


def test_body_offset_rotated_to_earth_fixed():
    # a phase centre 0.45 m along -Z (towards zenith) is 0.45 m radially outwards
    np.testing.assert_allclose(body_to_ef(_frame(), np.array([0, 0, -0.45]))[0], [0.45, 0, 0],
                               atol=1e-12)

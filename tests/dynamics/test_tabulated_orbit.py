"""Reference orbit from tabulated positions across a data gap
(leopod.dynamics.forces.tabulated_orbit).

Authority: two-body motion: a circular orbit sampled every 30 s with a 2-h hole; the reference
orbit must stay within the tolerance of leopod.dynamics.forces.circular_orbit (km) of the
sampled orbit inside the hole, and interpolate it elsewhere.
"""

import numpy as np
import pytest

from leopod.constants import GM_EARTH_M3_S2
from leopod.dynamics.forces import tabulated_orbit

RADIUS_M = 7.35e6


def _circle(t_s):
    n = np.sqrt(GM_EARTH_M3_S2 / RADIUS_M**3)
    i = np.radians(66.0)
    return RADIUS_M * np.column_stack([np.cos(n * t_s), np.sin(n * t_s) * np.cos(i),
                                       np.sin(n * t_s) * np.sin(i)])


def test_a_two_hour_gap_is_bridged():
    t = np.arange(0.0, 6 * 3600.0, 30.0)
    kept = (t < 7200.0) | (t >= 14400.0)
    orbit = tabulated_orbit(t[kept], _circle(t[kept]))
    error = np.linalg.norm(orbit(t) - _circle(t), axis=1)
    assert error[kept].max() < 1e-3                    # the table itself
    assert error[~kept].max() < 1e3                    # the bridge: circular motion


def test_needs_a_stretch_of_nine_epochs():
    t = np.array([0.0, 30.0, 3600.0, 3630.0, 7200.0])
    with pytest.raises(ValueError, match="no stretch of 9 positions"):
        tabulated_orbit(t, _circle(t))

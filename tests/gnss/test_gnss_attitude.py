"""Yaw-steering attitude of GNSS satellites (IGS convention, Montenbruck et al. 2015, ASR 56):
+Z to the geocentre, +Y = Z × e_sun along the panel axis, +X towards the Sun-lit side."""

import numpy as np

from leopod.gnss.attitude import gnss_body_axes


def test_axes_point_as_the_convention_says():
    pos = np.array([26_560e3, 0.0, 0.0])
    sun = np.array([1.0e11, 1.0e11, 0.0])            # Sun in the +x/+y quadrant
    x, y, z = gnss_body_axes(pos, sun)
    np.testing.assert_allclose(z, [-1, 0, 0], atol=1e-12)
    assert x @ (sun - pos) > 0                        # +X towards the Sun
    assert abs(y @ (sun - pos)) < 1e-3                # +Y perpendicular to the Sun direction
    np.testing.assert_allclose(np.cross(x, y), z, atol=1e-12)   # right-handed

"""Yaw-steering attitude of GNSS satellites (IGS convention, Montenbruck et al. 2015, ASR 56):
+Z to the geocentre, +Y = Z × e_sun along the panel axis, +X towards the Sun-lit side; the
low-precision Sun (Astronomical Almanac) and the DE421 Sun against pyerfa (SOFA epv00)."""

import erfa
import numpy as np
import pytest

from leopod.astro.ephemeris import Ephemeris
from leopod.astro.sun import sun_position_ef
from leopod.gnss.attitude import gnss_body_axes
from leopod.time.scales import tai_minus_utc_s


def test_axes_point_as_the_convention_says():
    pos = np.array([26_560e3, 0.0, 0.0])
    sun = np.array([1.0e11, 1.0e11, 0.0])            # Sun in the +x/+y quadrant
    x, y, z = gnss_body_axes(pos, sun)
    np.testing.assert_allclose(z, [-1, 0, 0], atol=1e-12)
    assert x @ (sun - pos) > 0                        # +X towards the Sun
    assert abs(y @ (sun - pos)) < 1e-3                # +Y perpendicular to the Sun direction
    np.testing.assert_allclose(np.cross(x, y), z, atol=1e-12)   # right-handed


@pytest.mark.parametrize("sun,ex,ey", [
    # Sun along +y: e_sun ⟂ e_z, so +Y = e_z × e_sun = (−x̂) × ŷ = −ẑ and +X = Y × Z = +ŷ
    ([0.0, 1.5e11, 0.0], [0, 1, 0], [0, 0, -1]),
    # Sun along +z: +Y = (−x̂) × ẑ = +ŷ and +X = ŷ × (−x̂) = +ẑ
    ([0.0, 0.0, 1.5e11], [0, 0, 1], [0, 1, 0]),
])
def test_yaw_steering_axes_hand_geometry(sun, ex, ey):
    """Montenbruck et al. (2015, Adv. Space Res. 56:1015), Kouba (2009, GPS
    Solut. 13:1): e_Z = −r/|r|, e_Y = e_Z × e_sun / |e_Z × e_sun|, e_X = e_Y × e_Z; with the
    satellite on +x̂ the axes follow by hand (cross products worked in the parameter comments),
    exact because the Sun direction seen from the satellite stays in the plane ⟂ to the result."""
    pos = np.array([26_560e3, 0.0, 0.0])
    x, y, z = gnss_body_axes(pos, np.array(sun))
    np.testing.assert_allclose(z, [-1, 0, 0], atol=1e-15)
    np.testing.assert_allclose(y, ey, atol=1e-12)
    np.testing.assert_allclose(x, ex, atol=1e-3)       # e_sun from the satellite: |r|/|s| ~ 2e-4
    assert x @ (np.array(sun) - pos) > 0.99 * np.linalg.norm(np.array(sun) - pos)


def test_yaw_steering_sun_in_x_hemisphere_and_y_perpendicular_everywhere():
    """Montenbruck et al. (2015): the Sun lies in the +X/±Z half-plane of the body frame (+X
    towards the Sun-lit side, +Y ⟂ Sun direction); orthonormal right-handed triad."""
    rng = np.random.default_rng(11)
    pos = rng.normal(size=(200, 3))
    pos *= 26_560e3 / np.linalg.norm(pos, axis=1, keepdims=True)
    sun = rng.normal(size=(200, 3))
    sun *= 1.496e11 / np.linalg.norm(sun, axis=1, keepdims=True)
    axes = gnss_body_axes(pos, sun)
    e_sun = (sun - pos) / np.linalg.norm(sun - pos, axis=1, keepdims=True)
    np.testing.assert_allclose(np.einsum("nij,nkj->nik", axes, axes),
                               np.broadcast_to(np.eye(3), (200, 3, 3)), atol=1e-12)
    np.testing.assert_allclose(np.linalg.det(axes), 1.0, atol=1e-12)
    np.testing.assert_allclose(axes[:, 2], -pos / 26_560e3, atol=1e-12)
    assert np.all(np.einsum("ni,ni->n", axes[:, 0], e_sun) > 0)
    np.testing.assert_allclose(np.einsum("ni,ni->n", axes[:, 1], e_sun), 0.0, atol=1e-12)


# --------------------------------------------------------------------------- Sun position
AU_M = 149_597_870_700.0          # IAU 2012 Resolution B2
_J2000 = np.datetime64("2000-01-01T12:00:00", "ns")


def _erfa_sun(times_gps):
    """Geocentric Sun from pyerfa: ICRS axes (−heliocentric Earth of ``erfa.epv00``) and ITRS
    axes (``erfa.c2t06a``, IAU 2006/2000A, UT1 ≈ UTC, no polar motion), TT = GPST + 51.184 s."""
    t = np.asarray(times_gps, dtype="datetime64[ns]")
    days_tt = ((t - _J2000).astype("int64") * 1e-9 + 51.184) / 86400.0
    pvh, _ = erfa.epv00(2451545.0, days_tt)
    sun_icrs = -pvh["p"] * AU_M
    days_utc = days_tt - (32.184 + tai_minus_utc_s(t)) / 86400.0
    c2t = erfa.c2t06a(2451545.0, days_tt, 2451545.0, days_utc, 0.0, 0.0)
    return sun_icrs, np.einsum("nij,nj->ni", c2t, sun_icrs), days_tt * 86400.0


def _angle_deg(a, b):
    cos = np.sum(a * b, axis=1) / np.linalg.norm(a, axis=1) / np.linalg.norm(b, axis=1)
    return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))


# one epoch every 9 days and 7 hours over 2000-2030 (GPS time): all seasons and times of day
_TIMES = np.arange(np.datetime64("2000-01-01T00:00"), np.datetime64("2030-01-01T00:00"),
                   np.timedelta64(9 * 86400 + 7 * 3600, "s")).astype("datetime64[ns]")


def test_low_precision_sun_against_erfa():
    """Authority: pyerfa ``epv00`` (SOFA; heliocentric Earth within 11.2 km max of JPL DE405,
    1900–2100, i.e. 4e-6° — exact at this tolerance) rotated to the ITRS with ``c2t06a``
    (IERS Conventions 2010 ch. 5). Tolerance: the Astronomical Almanac's low-precision
    formula is good to 0.01° (1950–2050), plus 0.004° for UT1 ≈ UTC (|UT1−UTC| < 0.9 s);
    its distance keeps terms down to 1.4e-4 AU and ignores the Earth's motion about the
    Earth–Moon barycentre (3e-5 AU): bound 1.5e-4 relative. Measured 2026-11-25 over
    2000–2030: 0.0117° and 8.2e-5 at worst. The former series (Montenbruck & Gill's, J2000
    equinox rotated by the GMST of date with UT1 ≈ GPS time) was 0.59° off at worst."""
    _, sun_itrs, _ = _erfa_sun(_TIMES)
    lp = sun_position_ef(_TIMES)
    assert np.max(_angle_deg(lp, sun_itrs)) < 0.015
    rel = np.linalg.norm(lp, axis=1) / np.linalg.norm(sun_itrs, axis=1) - 1.0
    assert np.max(np.abs(rel)) < 1.5e-4


def test_de421_sun_against_erfa():
    """Authority: pyerfa ``epv00`` (SOFA; max 11.2 km from DE405 over 1900–2100 for the
    heliocentric Earth, ICRS-aligned axes); DE421 and DE405 agree on the Earth–Sun vector far
    below that. Tolerance 12 km = epv00's stated maximum error plus 0.8 km. Measured
    2026-11-25: 10.5 km at worst over 2000–2030."""
    sun_icrs, _, tt_s = _erfa_sun(_TIMES)
    de = Ephemeris().sun_m(tt_s)
    assert np.max(np.linalg.norm(de - sun_icrs, axis=1)) < 12e3

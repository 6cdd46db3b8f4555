"""Sun/Moon ephemeris and accelerations; relativistic accelerations (IERS 2010 eq. 10.12).

Authorities: astronomical events and constants (total lunar eclipse of 2007-03-03, greatest
eclipse 23:21 UT, NASA eclipse catalogue: Sun and Moon in opposition; Earth's perihelion /
aphelion distances 0.983 / 1.017 AU), an independent low-precision Sun series
(the Astronomical Almanac's, in leopod.astro.sun), analytic special cases
and finite differences.
"""

import numpy as np
import pytest

from leopod.astro.ephemeris import Ephemeris
from leopod.constants import C_LIGHT_M_S, GM_EARTH_M3_S2
from leopod.dynamics.relativity import EARTH_ANGULAR_MOMENTUM_M2_S, relativistic_acceleration
from leopod.dynamics.third_body import GM_MOON_M3_S2, GM_SUN_M3_S2, third_body_acceleration

AU = 1.495978707e11
J2000 = np.datetime64("2000-01-01T12:00:00", "ns")


def _t(iso_tt: str) -> float:
    return float((np.datetime64(iso_tt, "ns") - J2000).astype("int64")) * 1e-9


def test_lunar_eclipse_2007_sun_and_moon_opposite():
    eph = Ephemeris()
    t = _t("2007-03-03T23:22:05")                 # 23:21 UT + 65 s (TT-UT1 in 2007)
    s, m = eph.sun_m(t)[0], eph.moon_m(t)[0]
    angle = np.degrees(np.arccos(s @ m / np.linalg.norm(s) / np.linalg.norm(m)))
    assert angle > 179.0                           # total eclipse: within ~0.5° of opposition
    assert 3.56e8 < np.linalg.norm(m) < 4.07e8     # perigee / apogee range


def test_sun_distance_and_direction_against_low_precision_series():
    from leopod.astro.sun import sun_position_ef

    eph = Ephemeris()
    assert np.linalg.norm(eph.sun_m(_t("2007-01-04T00:00:00"))[0]) / AU == pytest.approx(0.9833, abs=2e-4)
    assert np.linalg.norm(eph.sun_m(_t("2007-07-07T00:00:00"))[0]) / AU == pytest.approx(1.0167, abs=2e-4)
    # the declination (frame-independent between GCRF and Earth-fixed up to polar motion and
    # precession since J2000, < 0.2°) agrees with the Astronomical Almanac's formula
    times = np.arange(0, 365) * 86400.0 + _t("2007-01-01T12:00:00")
    de = eph.sun_m(times)
    lp = sun_position_ef(J2000 + (times * 1e9).astype("timedelta64[ns]") - np.timedelta64(64184, "ms"))
    dec = lambda x: np.degrees(np.arcsin(x[:, 2] / np.linalg.norm(x, axis=1)))  # noqa: E731
    assert np.max(np.abs(dec(de) - dec(lp))) < 0.2


def test_third_body_gradient_and_indirect_term():
    r = np.array([6.9e6, -1.0e6, 2.0e6])
    s = np.array([1.2e8, 3.5e8, -0.4e8])
    acc, grad = third_body_acceleration(r, s, GM_MOON_M3_S2)
    zero, _ = third_body_acceleration(np.zeros(3), s, GM_MOON_M3_S2)
    assert np.allclose(zero, 0.0, atol=1e-20)      # the indirect term cancels at the geocentre
    h = 1.0
    fd = np.stack([(third_body_acceleration(r + h * e, s, GM_MOON_M3_S2, False)
                    - third_body_acceleration(r - h * e, s, GM_MOON_M3_S2, False)) / (2 * h)
                   for e in np.eye(3)], axis=1)
    np.testing.assert_allclose(grad, fd, rtol=1e-6, atol=1e-22)
    # tidal order of magnitude: 2 GM r / d^3 ~ 1e-6 m/s^2 for the Moon at a LEO
    assert 5e-7 < np.linalg.norm(acc) < 3e-6
    a_sun, _ = third_body_acceleration(r, np.array([AU, 0, 0]), GM_SUN_M3_S2)
    assert 2e-7 < np.linalg.norm(a_sun) < 1.5e-6


def test_schwarzschild_circular_orbit_closed_form():
    r = 6.878e6
    v = np.sqrt(GM_EARTH_M3_S2 / r)
    acc = relativistic_acceleration(np.array([r, 0, 0]), np.array([0, v, 0]), lense_thirring=False)
    # circular orbit: 3 (GM)^2 / (c^2 r^3), radially outwards (analytic)
    np.testing.assert_allclose(acc, [3 * GM_EARTH_M3_S2**2 / (C_LIGHT_M_S**2 * r**3), 0, 0],
                               rtol=1e-12, atol=1e-24)


def test_lense_thirring_equatorial_closed_form():
    r, v = 7.0e6, 7.5e3
    a_s = relativistic_acceleration(np.array([r, 0, 0]), np.array([0, v, 0]), lense_thirring=False)
    a = relativistic_acceleration(np.array([r, 0, 0]), np.array([0, v, 0]))
    # r.J = 0, v x J = (v J, 0, 0): a_LT = 2 GM v J / (c^2 r^3) along +x (analytic)
    expected = 2 * GM_EARTH_M3_S2 * v * EARTH_ANGULAR_MOMENTUM_M2_S / (C_LIGHT_M_S**2 * r**3)
    np.testing.assert_allclose(a - a_s, [expected, 0, 0], rtol=1e-12, atol=1e-25)


def test_de_sitter_is_perpendicular_to_velocity_and_small():
    eph = Ephemeris()
    t = _t("2019-01-01T00:00:00")
    sun = eph.sun_m(t)[0]
    sun_v = (eph.sun_m(t + 1)[0] - eph.sun_m(t - 1)[0]) / 2
    r, v = np.array([7.0e6, 0, 0]), np.array([0, 5.3e3, 5.3e3])
    d = relativistic_acceleration(r, v, sun, sun_v) - relativistic_acceleration(r, v)
    assert abs(d @ v) < 1e-12 * np.linalg.norm(d) * np.linalg.norm(v)
    assert 1e-11 < np.linalg.norm(d) < 1e-9

"""Wind-up, Shapiro delay and relativistic clock correction.

Authorities: geometry (a rigid rotation of transmitter and receiver about the line of sight
leaves the wind-up unchanged; rotating one antenna by α about the line of sight changes it by
α/2π, Wu et al. 1993), the straight-line integral of the Shapiro delay (IERS Conventions 2010
eq. 11.17 is its closed form), and IS-GPS-200 20.3.3.3.3.1 (Δt_r = F e √A sin E with
F = −4.442807633e-10 s m^-1/2). The *sign* of the wind-up as used by the estimator was checked
on real data: GRACE-A 2007-080, 6-h float arc, phase RMS 6.50 mm with this sign, 7.53 mm with
the opposite sign, 6.86 mm without wind-up (session note of issue 5).
"""

import numpy as np
import pytest
from scipy.integrate import quad

from leopod.constants import C_LIGHT_M_S, GM_EARTH_M3_S2
from leopod.gnss.corrections import (
    relativistic_clock_s,
    shapiro_delay_m,
    unwrap_windup,
    windup_cycles,
)


def _rot(axis, angle):
    """Rotation matrix of angle [rad] about a unit axis (Rodrigues)."""
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * kx + (1 - np.cos(angle)) * kx @ kx


def _geometry(seed=0):
    rng = np.random.default_rng(seed)
    # receiver looking up (boresight +z) with a tilted frame, transmitter somewhere above
    r = _rot(rng.normal(size=3), 0.3)
    rx_x, rx_y = r @ np.array([1.0, 0, 0]), r @ np.array([0, 1.0, 0])
    los = np.array([0.3, -0.2, 1.0])
    k = -los / np.linalg.norm(los)                         # transmitter -> receiver
    s = _rot(rng.normal(size=3), 1.0)
    z_sv = k                                               # transmitter boresight to the receiver
    x_sv = s @ np.array([1.0, 0, 0])
    x_sv -= z_sv * (x_sv @ z_sv)
    x_sv /= np.linalg.norm(x_sv)
    y_sv = np.cross(z_sv, x_sv)
    return k, rx_x, rx_y, x_sv, y_sv


def _windup(k, rx_x, rx_y, sv_x, sv_y):
    return float(windup_cycles(k[None], rx_x[None], rx_y[None], sv_x[None], sv_y[None])[0])


@pytest.mark.parametrize("angle", [0.4, 1.3, -2.0])
def test_rigid_rotation_about_line_of_sight_leaves_windup_unchanged(angle):
    k, rx_x, rx_y, sv_x, sv_y = _geometry()
    w0 = _windup(k, rx_x, rx_y, sv_x, sv_y)
    m = _rot(k, angle)
    w1 = _windup(k, m @ rx_x, m @ rx_y, m @ sv_x, m @ sv_y)
    assert w1 == pytest.approx(w0, abs=1e-12)


@pytest.mark.parametrize("angle", [0.4, 1.3, -2.0])
def test_rotating_one_antenna_changes_windup_by_the_angle(angle):
    k, rx_x, rx_y, sv_x, sv_y = _geometry(1)
    w0 = _windup(k, rx_x, rx_y, sv_x, sv_y)
    m = _rot(k, angle)
    w_rx = _windup(k, m @ rx_x, m @ rx_y, sv_x, sv_y)
    w_sv = _windup(k, rx_x, rx_y, m @ sv_x, m @ sv_y)
    change = angle / (2 * np.pi)
    wrap = lambda x: (x + 0.5) % 1.0 - 0.5  # noqa: E731
    # receiver and transmitter rotations act with opposite signs (rigid rotation cancels)
    assert abs(wrap(w_rx - w0 - change)) < 1e-12 or abs(wrap(w_rx - w0 + change)) < 1e-12
    assert wrap(w_rx - w0) == pytest.approx(-wrap(w_sv - w0), abs=1e-12)


def test_unwrap_makes_tracks_continuous():
    true = np.concatenate([np.linspace(0.2, 3.7, 50), np.linspace(-0.1, -2.9, 30)])
    track = np.concatenate([np.zeros(50, int), np.ones(30, int)])
    order = np.concatenate([np.arange(50), np.arange(30)])
    wrapped = (true + 0.5) % 1.0 - 0.5
    perm = np.random.default_rng(2).permutation(80)        # any input order
    out = unwrap_windup(wrapped[perm], track[perm], order[perm])
    expected = true - np.concatenate([np.full(50, np.round(true[0])), np.full(30, np.round(true[50]))])
    assert np.allclose(out, expected[perm], atol=1e-12)


def test_shapiro_equals_straight_line_integral():
    tx = np.array([[15e6, 20e6, 5e6]])
    rx = np.array([[6.9e6, 0.4e6, 0.2e6]])
    rho = np.linalg.norm(tx - rx)
    integral = quad(lambda s: 1.0 / np.linalg.norm(rx[0] + s * (tx[0] - rx[0])), 0.0, 1.0,
                    epsabs=0.0, epsrel=1e-12)[0] * rho
    expected = 2 * GM_EARTH_M3_S2 / C_LIGHT_M_S**2 * integral
    assert shapiro_delay_m(tx, rx)[0] == pytest.approx(expected, rel=1e-8)
    assert 0.01 < shapiro_delay_m(tx, rx)[0] < 0.03       # GPS-LEO: ~2 cm


def test_relativistic_clock_matches_is_gps_200():
    a, e, big_e = 26_560e3, 0.02, np.linspace(0, 2 * np.pi, 13)
    n = np.sqrt(GM_EARTH_M3_S2 / a**3)
    r = a * (1 - e * np.cos(big_e))
    pos = np.stack([a * (np.cos(big_e) - e), a * np.sqrt(1 - e**2) * np.sin(big_e), 0 * big_e], 1)
    edot = n / (1 - e * np.cos(big_e))
    vel = np.stack([-a * np.sin(big_e) * edot, a * np.sqrt(1 - e**2) * np.cos(big_e) * edot,
                    0 * big_e], 1)
    assert np.allclose(np.linalg.norm(pos, axis=1), r)
    f_const = -4.442807633e-10                                 # IS-GPS-200 [s m^-1/2]
    expected = f_const * e * np.sqrt(a) * np.sin(big_e)
    assert np.allclose(relativistic_clock_s(pos, vel), expected, atol=1e-13)

"""Wind-up, Shapiro delay and relativistic clock correction.

Authorities: geometry (a rigid rotation of transmitter and receiver about the line of sight
leaves the wind-up unchanged; rotating one antenna by α about the line of sight changes it by
α/2π, Wu et al. 1993), the straight-line integral of the Shapiro delay (IERS Conventions 2010
eq. 11.17 is its closed form), and IS-GPS-200 20.3.3.3.3.1 (Δt_r = F e √A sin E with
F = −4.442807633e-10 s m^-1/2). The *sign* of the wind-up follows from hand geometry with
Kouba's (2009) formula and from the RHCP polarisation of the signal (IS-GPS-200 3.3.1.5, IEEE
Std 145): test_windup_sign_*; it agrees with real data: GRACE-A 2007-080, 6-h float arc,
phase RMS 6.50 mm with this sign, 7.53 mm with the opposite sign, 6.86 mm without wind-up
(session note of issue 5).
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
    # m turns the receiver by −angle about its boresight −k (test_windup_sign_* below:
    # +angle/2π) and the transmitter by +angle about its boresight k (−angle/2π); a rigid
    # rotation of both cancels
    assert wrap(w_rx - w0 - change) == pytest.approx(0.0, abs=1e-12)
    assert wrap(w_sv - w0 + change) == pytest.approx(0.0, abs=1e-12)


# local east, north, up of a receiver whose antenna boresight is the zenith
_E, _N, _U = np.eye(3)


@pytest.mark.parametrize("alpha", [0.3, 1.2, 2.5, -0.7, -2.9])
def test_windup_sign_receiver_turned_about_its_boresight(alpha):
    """Sign of the wind-up from hand geometry (Wu et al. 1993, manuscripta geodaetica 18:91;
    Kouba 2009, "A guide to using IGS products", sec. 5.3; Navipedia "Carrier phase wind-up").

    Transmitter at the zenith, boresight down: k = −U (transmitter → receiver), x' = N, y' = E
    (x' × y' = −U). Receiver: x = N, y = W (Kouba's ground convention, x × y = U = boresight
    towards the transmitter). Effective dipoles D = x − k(k·x) + k × y = 2N and
    D' = x' − k(k·x') − k × y' = 2N: no wind-up. Turning the receiver by +α about U (right-handed,
    i.e. counter-clockwise as seen from the transmitter) gives D = 2(cos α N + sin α W), the
    angle α between D' and D, and ζ = k·(D' × D) = −4 sin α: Δφ = −α/2π cycles.

    Physical check of the sign: GPS signals are right-hand circularly polarised (IS-GPS-200
    3.3.1.5); per IEEE Std 145 the field rotates right-handed about the propagation direction k.
    A receiver frame turned by +α about −k sees the field α further along its rotation, as it
    would see it α/ω later without the turn: a carrier phase *advance* of α, an apparent
    range shortened by α/2π cycles. The function's value is added to the modelled phase in
    the range sense (RINEX: phase has the sign of the pseudorange), so −α/2π."""
    k, sv_x, sv_y = -_U, _N, _E
    assert _windup(k, _N, -_E, sv_x, sv_y) == pytest.approx(0.0, abs=1e-15)
    c, s = np.cos(alpha), np.sin(alpha)
    rx_x = c * _N + s * np.cross(_U, _N)               # R_U(α) x: U × N = W
    rx_y = c * (-_E) + s * np.cross(_U, -_E)           # R_U(α) y: U × W = −N
    assert _windup(k, rx_x, rx_y, sv_x, sv_y) == pytest.approx(-alpha / (2 * np.pi), abs=1e-12)


@pytest.mark.parametrize("alpha", [0.3, 2.5, -1.1])
def test_windup_sign_transmitter_turned_about_its_boresight(alpha):
    """Same geometry and authorities as the receiver case: the transmitter turned by +α about its
    own boresight k (towards the receiver) turns the transmitted field with the RHCP sense,
    i.e. advances the carrier: −α/2π cycles. (This is the GPS yaw effect of Wu et al. 1993;
    a rigid rotation of both antennas about k leaves the wind-up unchanged, so the receiver
    turned by +α about −k and the transmitter by +α about +k must give the same value.)"""
    c, s = np.cos(alpha), np.sin(alpha)
    k = -_U
    sv_x = c * _N + s * np.cross(k, _N)                # R_k(α) x'
    sv_y = c * _E + s * np.cross(k, _E)                # R_k(α) y'
    assert _windup(k, _N, -_E, sv_x, sv_y) == pytest.approx(-alpha / (2 * np.pi), abs=1e-12)


def test_windup_antenna_spinning_raises_the_received_frequency():
    """A receiver antenna spinning at ω_a right-handed about its boresight (towards the
    transmitter) adds ω_a/2π to the received RHCP carrier frequency (the phase "wrap-up" of
    spinning vehicles; same physics as the two tests above): the range-sense phase decreases
    by ω_a/2π cycles per second, continuously across the ±0.5-cycle wraps once unwrapped."""
    omega_a, dt = 2 * np.pi * 0.37, 0.1                # 0.37 turns per second, 10 Hz
    t = np.arange(100) * dt
    ang = omega_a * t
    rx_x = np.cos(ang)[:, None] * _N + np.sin(ang)[:, None] * np.cross(_U, _N)
    rx_y = np.cos(ang)[:, None] * (-_E) + np.sin(ang)[:, None] * np.cross(_U, -_E)
    n = t.size
    w = windup_cycles(np.tile(-_U, (n, 1)), rx_x, rx_y, np.tile(_N, (n, 1)), np.tile(_E, (n, 1)))
    w = unwrap_windup(w, np.zeros(n, int), np.arange(n))
    np.testing.assert_allclose(np.diff(w) / dt, -omega_a / (2 * np.pi), rtol=1e-9)


def test_unwrap_makes_tracks_continuous():
    true = np.concatenate([np.linspace(0.2, 3.7, 50), np.linspace(-0.1, -2.9, 30)])
    track = np.concatenate([np.zeros(50, int), np.ones(30, int)])
    order = np.concatenate([np.arange(50), np.arange(30)])
    wrapped = (true + 0.5) % 1.0 - 0.5
    perm = np.random.default_rng(2).permutation(80)        # any input order
    out = unwrap_windup(wrapped[perm], track[perm], order[perm])
    expected = true - np.concatenate([np.full(50, np.round(true[0])), np.full(30, np.round(true[50]))])
    assert np.allclose(out, expected[perm], atol=1e-12)


def test_shapiro_radial_path_hand_value():
    """IERS Conventions 2010 eq. 11.17 (γ = 1), Earth term: for a radial path (GPS satellite at
    the zenith of a LEO) the straight-line integral 2GM/c² ∫ dr/r is 2GM/c² ln(r2/r1), and the
    delay is positive (the signal is late). r1 = 6878 km (500 km altitude), r2 = 26 560 km:
    2GM/c² = 8.8700 mm, ln(3.86159) = 1.35106, delay 11.984 mm (worked by hand); at the LEO
    horizon (ρ = √(r2² − r1²) = 25 654 km) ln(59 092/7 784) = 2.0270: 17.98 mm."""
    r1, r2 = 6_878e3, 26_560e3
    rx = np.array([[0.0, 0.0, r1]])
    zenith = shapiro_delay_m(np.array([[0.0, 0.0, r2]]), rx)[0]
    assert zenith == pytest.approx(2 * GM_EARTH_M3_S2 / C_LIGHT_M_S**2 * np.log(r2 / r1), rel=1e-12)
    assert zenith == pytest.approx(0.011984, abs=2e-6)
    horizon = np.array([[np.sqrt(r2**2 - r1**2), 0.0, r1]])
    assert shapiro_delay_m(horizon, rx)[0] == pytest.approx(0.01798, abs=2e-5)


def test_shapiro_equals_straight_line_integral():
    tx = np.array([[15e6, 20e6, 5e6]])
    rx = np.array([[6.9e6, 0.4e6, 0.2e6]])
    rho = np.linalg.norm(tx - rx)
    integral = quad(lambda s: 1.0 / np.linalg.norm(rx[0] + s * (tx[0] - rx[0])), 0.0, 1.0,
                    epsabs=0.0, epsrel=1e-12)[0] * rho
    expected = 2 * GM_EARTH_M3_S2 / C_LIGHT_M_S**2 * integral
    assert shapiro_delay_m(tx, rx)[0] == pytest.approx(expected, rel=1e-8)
    assert 0.01 < shapiro_delay_m(tx, rx)[0] < 0.03       # GPS-LEO: ~2 cm


def test_relativistic_clock_hand_value():
    """IS-GPS-200 20.3.3.3.3.1: Δt_r = F e √A sin E, F = −2√μ/c² = −4.442807633e-10 s m^-1/2,
    added to the satellite clock offset. GPS orbit a = 26 560 km, e = 0.01, at E = 90°:
    r = (−a e, a√(1−e²), 0), v = (−a n, 0, 0) (Ė = n there), r·v = e a² n = e√(μ a),
    Δt_r = −2 e √(μ a)/c² = −4.442807633e-10 × 0.01 × 5153.64 s = −22.897 ns (by hand).
    Negative: around perigee the clock is deeper in the potential and faster, so it runs
    slow and lags a quarter orbit later."""
    a, e = 26_560e3, 0.01
    n = np.sqrt(GM_EARTH_M3_S2 / a**3)
    pos = np.array([[-a * e, a * np.sqrt(1 - e**2), 0.0]])
    vel = np.array([[-a * n, 0.0, 0.0]])
    assert relativistic_clock_s(pos, vel)[0] == pytest.approx(-22.897e-9, abs=0.002e-9)
    assert relativistic_clock_s(pos, -vel)[0] == pytest.approx(+22.897e-9, abs=0.002e-9)


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

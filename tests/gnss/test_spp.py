"""Single point positioning against a closed-loop simulation solved in an inertial frame.

The synthetic code is built independently of leopod's model: light time is solved by
iteration in an inertial frame (no Sagnac approximation), satellite clocks carry the periodic
relativistic effect ``-2 r·v/c²`` (IS-GPS-200 20.3.3.3.3.1), and the receiver clock offset
shifts the true reception time. SPP must recover position and clock to the millimetre.
"""

import numpy as np
import pytest

from leopod.constants import C_LIGHT_M_S, OMEGA_EARTH_WGS84_RAD_S
from leopod.gnss.products import GnssProducts
from leopod.gnss.spp import solve_spp

W = OMEGA_EARTH_WGS84_RAD_S


def _rot_in_to_ef(theta):
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])


def _gps_inertial(t, k):
    """Circular 55° orbits in 6 planes, radius 26 560 km."""
    a, n = 26_560e3, 2 * np.pi / 43_082.0
    raan = np.radians(60.0 * (k % 6))
    u = n * t + np.radians(45.0 * k)
    inc = np.radians(55.0)
    x = a * (np.cos(raan) * np.cos(u) - np.sin(raan) * np.sin(u) * np.cos(inc))
    y = a * (np.sin(raan) * np.cos(u) + np.cos(raan) * np.sin(u) * np.cos(inc))
    z = a * np.sin(u) * np.sin(inc)
    return np.stack([x, y, z], axis=-1)


def _leo_inertial(t):
    a, n = 6_878e3, np.sqrt(3.986004418e14 / 6_878e3**3)
    inc = np.radians(89.0)
    u = n * t
    return a * np.stack([np.cos(u), np.sin(u) * np.cos(inc), np.sin(u) * np.sin(inc)], axis=-1)


def _to_ef(t, r_in):
    return np.einsum("...ij,...j->...i", np.stack([_rot_in_to_ef(W * tt) for tt in np.atleast_1d(t)]), r_in)


def _sat_clock(t, k):
    return 1e-4 * (k - 12) / 12 + 1e-11 * t + 2e-9 * np.sin(t / 3000.0 + k)


@pytest.fixture(scope="module")
def scenario():
    n_sv = 24
    sv = np.array([f"G{k + 1:02d}" for k in range(n_sv)])
    t_orb = np.arange(-3600.0, 7200.0 + 1, 900.0)
    pos_tab = np.stack([_to_ef(t_orb, _gps_inertial(t_orb, k)) for k in range(n_sv)], axis=1)
    t_clk = np.arange(-3600.0, 7200.0 + 1, 30.0)
    clk_tab = np.stack([_sat_clock(t_clk, k) for k in range(n_sv)], axis=1)
    products = GnssProducts(ref=np.datetime64("2020-01-01T00:00:00", "ns"), sv=sv,
                            t_orbit_s=t_orb, pos_m=pos_tab, t_clock_s=t_clk, clk_s=clk_tab)
    t_read = np.arange(0.0, 3600.0, 60.0)
    dt_rx = 2.5e-4 + 1e-9 * t_read                        # receiver clock [s]
    t_true = t_read - dt_rx
    code = np.full((t_read.size, n_sv), np.nan)
    for i, T in enumerate(t_true):
        r_rx = _leo_inertial(T)
        for k in range(n_sv):
            tau = 0.07
            for _ in range(10):
                tau = np.linalg.norm(_gps_inertial(T - tau, k) - r_rx) / C_LIGHT_M_S
            r_s = _gps_inertial(T - tau, k)
            if np.dot(r_s - r_rx, r_rx) < 0:                   # below the LEO horizon
                continue
            eps = 0.01
            v_s = (_gps_inertial(T - tau + eps, k) - _gps_inertial(T - tau - eps, k)) / (2 * eps)
            rel = -2.0 * np.dot(r_s, v_s) / C_LIGHT_M_S**2
            code[i, k] = C_LIGHT_M_S * (tau + dt_rx[i] - (_sat_clock(T - tau, k) + rel))
    truth_ef = np.stack([_to_ef(T, _leo_inertial(T))[0] for T in t_true])
    return products, sv, t_read, code, truth_ef, dt_rx


def test_spp_recovers_position_and_clock(scenario):
    products, sv, t_read, code, truth_ef, dt_rx = scenario
    res = solve_spp(t_read, sv, code, products)
    assert np.isfinite(res.pos_m).all()
    err = np.linalg.norm(res.pos_m - truth_ef, axis=1)
    assert err.max() < 5e-3                                   # 5 mm (clock interpolation)
    assert np.max(np.abs(res.clk_rx_m - C_LIGHT_M_S * dt_rx)) < 5e-3
    assert np.nanmax(res.rms_m) < 5e-3


def test_spp_rejects_a_gross_outlier(scenario):
    products, sv, t_read, code, truth_ef, _ = scenario
    bad = code.copy()
    i = 10
    k = np.nonzero(np.isfinite(bad[i]))[0][0]
    bad[i, k] += 500.0
    res = solve_spp(t_read, sv, bad, products)
    assert np.isnan(res.residual_m[i, k])
    assert np.linalg.norm(res.pos_m[i] - truth_ef[i]) < 5e-3

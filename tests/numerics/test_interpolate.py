"""Lagrange interpolation: exact for polynomials up to its degree (analytic truth)."""

import numpy as np
import pytest

from leopod.numerics.interpolate import interpolate_table


def test_polynomial_reproduced_exactly_with_derivative():
    t_nodes = np.arange(0.0, 7200.0 + 1, 900.0)
    coef = np.array([3.0, -2e-3, 5e-7, -1e-10])
    f = np.polynomial.polynomial.polyval(t_nodes, coef)
    t = np.linspace(0, 7200, 97)
    v, r = interpolate_table(t_nodes, f, t, order=6)
    assert np.allclose(v, np.polynomial.polynomial.polyval(t, coef), rtol=0, atol=1e-9)
    dcoef = np.polynomial.polynomial.polyder(coef)
    assert np.allclose(r, np.polynomial.polynomial.polyval(t, dcoef), rtol=0, atol=1e-12)


def test_gps_like_orbit_to_sub_millimetre():
    # circular orbit of GPS radius and period sampled at 15 min (analytic truth)
    a, period = 26_560e3, 43_082.0
    pos = lambda t: a * np.stack([np.cos(2 * np.pi * t / period), np.sin(2 * np.pi * t / period),
                                  np.zeros_like(t)], axis=-1)
    t_nodes = np.arange(0.0, 86400.0 - 899, 900.0)
    t = np.arange(3600.0, 80000.0, 30.0)
    v, _ = interpolate_table(t_nodes, pos(t_nodes), t, order=10)
    assert np.max(np.linalg.norm(v - pos(t), axis=1)) < 1e-3


def test_no_extrapolation_unless_allowed():
    t_nodes = np.arange(0.0, 100.0, 10.0)
    # nodes span 0..90 s
    v, _ = interpolate_table(t_nodes, t_nodes**2, np.array([-1.0, 85.0, 95.0]), order=4)
    assert np.isnan(v[0]) and v[1] == pytest.approx(85.0**2) and np.isnan(v[2])
    v, _ = interpolate_table(t_nodes, t_nodes**2, np.array([95.0]), order=4, max_extrapolation_s=10)
    assert v[0] == pytest.approx(95.0**2)

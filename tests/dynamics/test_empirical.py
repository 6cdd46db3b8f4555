"""Tests of leopod.dynamics.empirical: RTN frame, argument of latitude, piecewise accelerations."""

from __future__ import annotations

import numpy as np
import pytest

from leopod.constants import GM_EARTH_M3_S2
from leopod.dynamics.empirical import EmpiricalModel, argument_of_latitude, empirical_acceleration
from leopod.frames.rtn import rtn_matrix


def _rot(axis: int, angle_rad: float) -> np.ndarray:
    """Frame rotation R_i about a coordinate axis (IERS 2010 sec. 5.1 convention)."""
    c, s = np.cos(angle_rad), np.sin(angle_rad)
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    rot = np.eye(3)
    rot[i, i] = rot[j, j] = c
    rot[i, j], rot[j, i] = s, -s
    return rot


def _circular_state(raan, inc, u, radius=6.85e6):
    """Analytic Keplerian construction: r = Rz(−Ω) Rx(−i) (cos u, sin u, 0) r, circular v."""
    to_inertial = _rot(2, -raan) @ _rot(0, -inc)
    speed = np.sqrt(GM_EARTH_M3_S2 / radius)
    pos = to_inertial @ (radius * np.array([np.cos(u), np.sin(u), 0.0]))
    vel = to_inertial @ (speed * np.array([-np.sin(u), np.cos(u), 0.0]))
    return pos, vel, to_inertial


STATE = _circular_state(np.radians(35.0), np.radians(89.0), np.radians(123.0))


# ----------------------------------------------------------------------------- RTN frame


def test_rtn_equatorial_orbit():
    # Analytic: r along x, v along y → R = x, T = y, N = z
    np.testing.assert_allclose(rtn_matrix([7e6, 0, 0], [0, 7.5e3, 0]), np.eye(3), atol=1e-15)


def test_rtn_orthonormal_and_vectorised():
    pos, vel, to_inertial = STATE
    m = rtn_matrix(pos, vel)
    np.testing.assert_allclose(m @ m.T, np.eye(3), atol=1e-15)
    assert np.linalg.det(m) == pytest.approx(1.0, abs=1e-15)
    # circular orbit: T is along v, N is the orbit normal (third column of Rz(−Ω) Rx(−i))
    np.testing.assert_allclose(m[1], vel / np.linalg.norm(vel), atol=1e-15)
    np.testing.assert_allclose(m[2], to_inertial[:, 2], atol=1e-15)
    stacked = rtn_matrix(np.stack([pos, -pos]), np.stack([vel, -vel]))
    assert stacked.shape == (2, 3, 3)
    np.testing.assert_allclose(stacked[0], m)


@pytest.mark.parametrize("u_deg", [-170.0, -45.0, 0.0, 10.0, 123.0, 179.0])
@pytest.mark.parametrize("inc_deg", [0.5, 51.6, 89.0, 98.7, 135.0])
def test_argument_of_latitude(u_deg, inc_deg):
    # Analytic: the u of the Keplerian construction is recovered
    pos, vel, _ = _circular_state(np.radians(-60.0), np.radians(inc_deg), np.radians(u_deg))
    assert argument_of_latitude(pos, vel) == pytest.approx(np.radians(u_deg), abs=1e-12)


# ----------------------------------------------------------------------- parameter layout


def test_regular_intervals_and_active_parameters():
    # Peng et al. (2021) Table II: 30-h arc, every 180 min → 10 intervals of 6 (T, N × C, cos, sin)
    model = EmpiricalModel.regular(0.0, 30 * 3600.0, 180 * 60.0)
    assert model.n_intervals == 10 and model.n_params == 60
    assert model.interval(0.0) == 0 and model.interval(10_799.9) == 0
    assert model.interval(10_800.0) == 1 and model.interval(108_000.0) == 9
    assert model.interval(-5.0) == 0 and model.interval(2e5) == 9  # clipped
    assert model.active(12_000.0) == slice(6, 12)
    assert model.index(1, "N", "cos") == 10
    assert model.names()[10] == "emp_cos_N_1"
    # Jiang et al. (2023): 24 h every 120 min → 12; a remainder interval is kept
    assert EmpiricalModel.regular(0.0, 86_400.0, 7_200.0).n_intervals == 12
    odd = EmpiricalModel.regular(0.0, 10_000.0, 3_000.0)
    np.testing.assert_array_equal(odd.boundaries_s, [0, 3000, 6000, 9000, 10000])


def test_model_validation():
    with pytest.raises(ValueError, match="increasing"):
        EmpiricalModel(np.array([0.0, 10.0, 10.0]))
    with pytest.raises(ValueError, match="directions"):
        EmpiricalModel(np.array([0.0, 10.0]), directions=("T", "X"))
    with pytest.raises(ValueError, match="terms"):
        EmpiricalModel(np.array([0.0, 10.0]), terms=())
    model = EmpiricalModel(np.array([0.0, 10.0]))
    with pytest.raises(ValueError, match="coefficients"):
        empirical_acceleration(0.0, *STATE[:2], np.zeros(5), model)


# ---------------------------------------------------------------------------- acceleration


def test_acceleration_components():
    # Analytic: a = Mᵀ [C_R + A_R cos u + B_R sin u, ...] of the active interval only
    pos, vel, _ = STATE
    u = np.radians(123.0)
    model = EmpiricalModel(np.array([0.0, 100.0, 200.0]), directions=("R", "T", "N"))
    coef = np.zeros(model.n_params)
    coef[model.index(1, "R", "const")] = 1e-8
    coef[model.index(1, "T", "cos")] = 2e-8
    coef[model.index(1, "T", "sin")] = -3e-8
    coef[model.index(1, "N", "sin")] = 4e-8
    coef[model.index(0, "T", "const")] = 5e-8  # interval 0: inactive at t = 150 s
    m = rtn_matrix(pos, vel)
    expected = m.T @ [1e-8, 2e-8 * np.cos(u) - 3e-8 * np.sin(u), 4e-8 * np.sin(u)]
    acc, da_dr, da_dv, da_dp = empirical_acceleration(150.0, pos, vel, coef, model)
    np.testing.assert_allclose(acc, expected, rtol=0, atol=1e-22)
    np.testing.assert_array_equal(da_dr, 0.0)
    np.testing.assert_array_equal(da_dv, 0.0)
    # linear in the coefficients: a = (∂a/∂p) p, zero outside the active interval
    np.testing.assert_allclose(da_dp @ coef, acc, rtol=0, atol=1e-22)
    assert not da_dp[:, model.active(50.0)].any()
    np.testing.assert_allclose(da_dp[:, model.index(1, "T", "const")], m[1], atol=1e-15)


def test_default_directions_along_and_cross_track():
    # Peng et al. (2021) Table II: along- and cross-track only; a constant C_T is along the velocity
    # of a circular orbit
    pos, vel, _ = STATE
    model = EmpiricalModel(np.array([0.0, 1.0]))
    coef = np.zeros(6)
    coef[model.index(0, "T", "const")] = 3e-8
    acc = empirical_acceleration(0.5, pos, vel, coef, model)[0]
    np.testing.assert_allclose(acc, 3e-8 * vel / np.linalg.norm(vel), rtol=0, atol=1e-22)


def test_neglected_state_partials_are_small():
    # Finite differences bound the neglected frame partials: for 1e-7 m/s² terms they are
    # below 1e-13 s⁻² (position) and 1e-10 s⁻¹ (velocity), vs. ~1e-6 s⁻² for gravity
    pos, vel, _ = STATE
    model = EmpiricalModel(np.array([0.0, 1.0]), directions=("R", "T", "N"))
    coef = np.full(model.n_params, 1e-7)

    def acc(p, v):
        return empirical_acceleration(0.5, p, v, coef, model)[0]

    d_r = np.column_stack([(acc(pos + 10 * e, vel) - acc(pos - 10 * e, vel)) / 20
                           for e in np.eye(3)])
    d_v = np.column_stack([(acc(pos, vel + 0.01 * e) - acc(pos, vel - 0.01 * e)) / 0.02
                           for e in np.eye(3)])
    assert 0.0 < np.abs(d_r).max() < 1e-13
    assert 0.0 < np.abs(d_v).max() < 1e-10

"""LEO yaw-steering attitude with yaw-fixed mode and flips (leopod.frames.leo_attitude).

Authorities: analytic truths of ideal yaw steering (Bar-Sever 1996; Kouba 2009, GPS Solut.,
eq. 1: +Y perpendicular to the Sun), the HY-2D thresholds of Jiang et al. (2023, sec. 2: yaw
steering for |beta| <= 75 deg, yaw-fixed +-90 deg beyond, 180-deg flip about +Z at beta = -1.5
deg), and the orthonormality of a rotation. Orbit in the inertial x-y plane (N = +z), the Sun
placed at a chosen beta and orbit angle.
"""

import numpy as np
import pytest

from leopod.frames.attitude import nominal_axes_inertial, nominal_body_axes
from leopod.frames.leo_attitude import (
    LeoAttitude,
    below_flip,
    leo_body_axes,
    leo_body_axes_ef,
    yaw_flip_epochs,
)

A_M, V_M_S = 7_335e3, 7_372.0
SUN_M = 1e20      # far enough that beta seen from the satellite is the geocentric one
LAW = LeoAttitude.of({"attitude": "yaw_steering"})


def _state(beta_deg, mu_deg):
    """Satellite at orbit angle mu from midnight, Sun at elevation beta (N = +z)."""
    beta, mu = np.radians(np.atleast_1d(beta_deg)), np.radians(np.atleast_1d(mu_deg))
    beta, mu = np.broadcast_arrays(beta, mu)
    # Sun at azimuth 180 deg in the orbit plane: midnight (mu = 0) at +x
    sun = SUN_M * np.stack([-np.cos(beta), np.zeros_like(beta), np.sin(beta)], axis=-1)
    pos = A_M * np.stack([np.cos(mu), np.sin(mu), np.zeros_like(mu)], axis=-1)
    vel = V_M_S * np.stack([-np.sin(mu), np.cos(mu), np.zeros_like(mu)], axis=-1)
    return pos, vel, sun


def _sun_dir(pos, sun):
    s = sun - pos
    return s / np.linalg.norm(s, axis=-1, keepdims=True)


@pytest.mark.parametrize("beta_deg", [-74.0, -20.0, -1.6, -1.4, 0.3, 10.0, 45.0, 74.9])
def test_y_axis_perpendicular_to_the_sun_in_yaw_steering(beta_deg):
    mu = np.linspace(-179.5, 179.5, 360)
    pos, vel, sun = _state(beta_deg, mu)
    axes = leo_body_axes(LAW, pos, vel, sun)
    np.testing.assert_allclose(np.einsum("ni,ni->n", axes[:, 1], _sun_dir(pos, sun)), 0.0,
                               atol=1e-12)
    np.testing.assert_allclose(axes[:, 2], -pos / A_M, atol=1e-12)        # Z to the geocentre


@pytest.mark.parametrize("beta_deg", [75.5, 89.0, -75.5, -89.0])
def test_yaw_fixed_mode_beyond_beta_max(beta_deg):
    """|beta| > 75 deg: yaw +-90 deg, +X along the orbit normal (+N on both sides with the
    default branches: sunward above the flip threshold, anti-sunward below)."""
    pos, vel, sun = _state(beta_deg, np.linspace(-180, 180, 37))
    axes = leo_body_axes(LAW, pos, vel, sun)
    np.testing.assert_allclose(axes[:, 0], np.tile([0, 0, 1.0], (37, 1)), atol=1e-12)


def test_nominal_yaw_where_the_ideal_law_gives_it():
    """beta = 0: at mu = +-90 deg the ideal yaw is 0 (X along track) and 180 deg (X backwards)."""
    pos, vel, sun = _state(0.0, [90.0, -90.0])
    axes = leo_body_axes(LAW, pos, vel, sun)
    nominal = nominal_axes_inertial(pos, vel)
    np.testing.assert_allclose(axes[0], nominal[0], atol=1e-12)
    np.testing.assert_allclose(axes[1], nominal[1] * [[-1], [-1], [1]], atol=1e-12)


def test_flip_by_180_deg_about_z_at_the_threshold():
    mu = np.linspace(-170, 170, 35)
    above = leo_body_axes(LAW, *_state(-1.5 + 1e-7, mu))
    below = leo_body_axes(LAW, *_state(-1.5 - 1e-7, mu))
    np.testing.assert_allclose(below, above * np.array([-1, -1, 1])[:, None], atol=1e-6)
    # no flip across beta = 0: the law is continuous there away from noon and midnight
    mu = np.array([30.0, 90.0, 150.0, -30.0, -90.0, -150.0])
    np.testing.assert_allclose(leo_body_axes(LAW, *_state(1e-7, mu)),
                               leo_body_axes(LAW, *_state(-1e-7, mu)), atol=1e-6)


def test_below_flip_is_the_branch_the_law_flips_into():
    # Jiang et al. (2023): HY-2D flips when beta crosses -1.5 deg; the branch test the simulated
    # yaw_branch maps use changes exactly where the body axes turn by 180 deg about +Z
    beta = np.radians([-1.5 + 1e-7, -1.5 - 1e-7, 10.0, -10.0])
    np.testing.assert_array_equal(below_flip(beta, LAW.yaw_steering), [False, True, False, True])


def test_swapped_branches_are_the_law_rotated_by_180_deg():
    swapped = LeoAttitude.of({"attitude": "yaw_steering",
                              "yaw_steering": {"x_sunward_above_flip": False}})
    state = _state(np.linspace(-89, 89, 50), np.linspace(-180, 180, 50))
    np.testing.assert_allclose(leo_body_axes(swapped, *state),
                               leo_body_axes(LAW, *state) * np.array([-1, -1, 1])[:, None],
                               atol=1e-12)


def test_axes_are_right_handed_and_orthonormal():
    rng = np.random.default_rng(7)
    pos, vel, sun = _state(rng.uniform(-90, 90, 500), rng.uniform(-180, 180, 500))
    axes = leo_body_axes(LAW, pos, vel, sun)
    np.testing.assert_allclose(axes @ axes.transpose(0, 2, 1), np.broadcast_to(np.eye(3),
                               axes.shape), atol=1e-12)
    np.testing.assert_allclose(np.linalg.det(axes), 1.0, atol=1e-12)


def test_nominal_law_is_the_nominal_attitude():
    pos, vel, _ = _state(10.0, np.linspace(-180, 180, 13))
    times = np.datetime64("2021-07-14T00:00") + np.arange(13) * np.timedelta64(60, "s")
    np.testing.assert_allclose(leo_body_axes_ef(LeoAttitude.of(None), times, pos, vel),
                               nominal_body_axes(pos, vel), atol=0)


def test_flip_epochs_interpolate_the_threshold_crossings():
    t0 = np.datetime64("2021-07-14T18:00", "ns")
    times = t0 + np.arange(0, 3600, 30) * np.timedelta64(1, "s")
    s = (times - t0).astype("int64") * 1e-9
    # beta decreasing through -1.5 deg at 18:21:00 (the HY-2D flip of Jiang et al. 2023)
    beta = np.radians(-1.5 - 1e-3 * (s - 1260.0))
    flips = yaw_flip_epochs(times, beta, LAW.yaw_steering)
    assert flips.size == 1
    assert abs((flips[0] - np.datetime64("2021-07-14T18:21:00", "ns")).astype("int64")) < 1e3
    assert yaw_flip_epochs(times, np.full(s.size, -0.01), LAW.yaw_steering).size == 0


def test_unknown_law_is_rejected():
    with pytest.raises(ValueError, match="attitude"):
        LeoAttitude.of({"attitude": "sun_pointing"})


def test_earth_fixed_and_inertial_evaluations_agree():
    """The simulator and the observation model evaluate the law in the GCRF, the quality and
    ingest steps from Earth-fixed states (velocity + omega x r, low-precision Sun): the same
    axes (IERS Conventions 2010 ITRF->GCRF rotation, leopod.frames.earth_rotation)."""
    from leopod.astro.sun import sun_position_ef
    from leopod.frames.earth_rotation import gcrf_to_itrf, itrf_to_gcrf

    times = (np.datetime64("2021-07-12T00:00", "ns")
             + np.arange(0, 6000, 60) * np.timedelta64(1, "s"))
    mu = np.radians(np.arange(times.size) * 3.6)
    inc = np.radians(66.0)
    pos = A_M * np.stack([np.cos(mu), np.sin(mu) * np.cos(inc), np.sin(mu) * np.sin(inc)], -1)
    vel = V_M_S * np.stack([-np.sin(mu), np.cos(mu) * np.cos(inc), np.cos(mu) * np.sin(inc)],
                           -1)
    pos_ef, vel_ef = gcrf_to_itrf(times, pos, vel)
    sun_gcrf, _ = itrf_to_gcrf(times, sun_position_ef(times))
    gcrf = leo_body_axes(LAW, pos, vel, sun_gcrf)
    ef = leo_body_axes_ef(LAW, times, pos_ef, vel_ef)
    ef_in_gcrf = np.stack([itrf_to_gcrf(times, ef[:, k])[0] for k in range(3)], axis=1)
    np.testing.assert_allclose(ef_in_gcrf, gcrf, atol=1e-6)
    # and the law is yaw steering there, not the nominal attitude
    assert np.abs(gcrf - nominal_axes_inertial(pos, vel)).max() > 0.5

"""Tests of leopod.dynamics.srp: radiation pressure on spheres and plates, conical shadow."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

from leopod.constants import GM_EARTH_M3_S2, R_EARTH_EQUATOR_M
from leopod.dynamics.srp import (
    AU_M,
    R_SUN_M,
    SOLAR_PRESSURE_1AU_N_M2,
    MacroModel,
    plate_normals,
    shadow_function,
    srp_cannonball,
    srp_plates,
)

P_SUN = SOLAR_PRESSURE_1AU_N_M2
POS = np.array([7.0e6, 0.0, 0.0])  # day side, Sun along +x
SUN_1AU = POS + np.array([AU_M, 0.0, 0.0])  # exactly 1 AU from the satellite
ATOL_ACC = 1e-15  # [m/s²], 1e-8 of the accelerations tested


def _plate(normal, spec=0.0, diff=0.0, area=2.0, mass=100.0):
    return MacroModel(normal_body=[normal], area_m2=[area], specular=[spec], diffuse=[diff],
                      drag_coefficient=[2.2], mass_kg=mass)


def _box(mass=500.0):
    normals = [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1], [0, 0, 1],
               [0, 0, -1]]
    return MacroModel(normal_body=normals, area_m2=[1.0, 1.1, 2.0, 2.1, 3.0, 3.1, 9.0, 9.0],
                      specular=[0.2, 0.2, 0.3, 0.3, 0.1, 0.1, 0.05, 0.0],
                      diffuse=[0.1, 0.1, 0.2, 0.2, 0.3, 0.3, 0.05, 0.1],
                      drag_coefficient=2.3, mass_kg=mass, panel=[0, 0, 0, 0, 0, 0, 1, -1])


# ------------------------------------------------------------------------- analytic cases


def test_sphere_at_one_au():
    # Analytic (M&G 2000 sec. 3.4.1): |a| = P☉ C_R A/m at 1 AU, directed away from the Sun
    cr_am = 1.3 * 4.0 / 600.0
    acc, _, da_dv, da_ds = srp_cannonball(POS, SUN_1AU, cr_am)
    np.testing.assert_allclose(acc, [-P_SUN * cr_am, 0.0, 0.0], rtol=1e-12, atol=ATOL_ACC)
    np.testing.assert_array_equal(da_dv, np.zeros((3, 3)))
    np.testing.assert_allclose(da_ds[:, 0], acc)
    # inverse-square law: at 2 AU a quarter; the scale factor multiplies
    acc2 = srp_cannonball(POS, POS + [2 * AU_M, 0, 0], cr_am, scale=0.8)[0]
    np.testing.assert_allclose(acc2, 0.8 * acc / 4.0, rtol=1e-12)


@pytest.mark.parametrize(
    ("spec", "diff", "factor_e", "factor_n"),
    [(0.0, 0.0, 1.0, 0.0), (1.0, 0.0, 0.0, 2.0), (0.0, 1.0, 1.0, 2.0 / 3.0),
     (0.3, 0.2, 0.7, 2 * (0.3 + 0.2 / 3))],
    ids=["absorbing", "specular", "diffuse", "mixed"],
)
def test_plate_normal_incidence(spec, diff, factor_e, factor_n):
    # M&G (2000) sec. 3.4.1 at cos θ = 1: F = −P A [(1 − ρs) e + 2 (ρs + ρd/3) n]
    model = _plate([1.0, 0.0, 0.0], spec, diff)
    normals = plate_normals(model, np.eye(3), POS, SUN_1AU)
    acc = srp_plates(POS, SUN_1AU, normals, model)[0]
    expected = -P_SUN * 2.0 / 100.0 * (factor_e + factor_n)
    np.testing.assert_allclose(acc, [expected, 0.0, 0.0], rtol=1e-12, atol=ATOL_ACC)


def test_plate_oblique_and_unlit():
    # Tilted specular plate (θ = 30°): F = −2 P A cos²θ n (M&G sec. 3.4.1)
    theta = np.radians(30.0)
    n = np.array([np.cos(theta), np.sin(theta), 0.0])
    model = _plate(n, spec=1.0)
    acc = srp_plates(POS, SUN_1AU, model.normal_body, model)[0]
    np.testing.assert_allclose(acc, -2 * P_SUN * 2.0 / 100.0 * np.cos(theta) ** 2 * n,
                               rtol=1e-12, atol=ATOL_ACC)
    # absorbing plate: the force is along −e with the projected area A cos θ
    model = _plate(n)
    acc = srp_plates(POS, SUN_1AU, model.normal_body, model)[0]
    np.testing.assert_allclose(acc, [-P_SUN * 2.0 / 100.0 * np.cos(theta), 0, 0], atol=ATOL_ACC)
    # plate facing away from the Sun: not lit
    model = _plate([-1.0, 0.0, 0.0])
    np.testing.assert_array_equal(srp_plates(POS, SUN_1AU, model.normal_body, model)[0], 0.0)


def test_absorbing_box_equals_projected_cannonball():
    # Independent: an absorbing cube seen face-on (one face lit) is a cannonball with C_R = 1
    # and A = face area; the attitude matrix rotates the body so that −Y faces the Sun.
    normals = [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]]
    cube = MacroModel(normal_body=normals, area_m2=1.5, specular=0.0, diffuse=0.0,
                      drag_coefficient=2.2, mass_kg=300.0)
    rot = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # body Y = GCRF −X
    acc = srp_plates(POS, SUN_1AU, plate_normals(cube, rot, POS, SUN_1AU), cube)[0]
    np.testing.assert_allclose(acc, srp_cannonball(POS, SUN_1AU, 1.5 / 300.0)[0], rtol=1e-12)


def test_sun_tracking_panels():
    # Jiang et al. (2023) eq. 4: n = y × (e☉ × y) / |...|: orthogonal to y,
    # cos θ = sqrt(1 − (e☉·y)²)
    model = _box()
    rot = np.linalg.qr(np.array([[0.3, 0.5, 0.8], [0.9, -0.2, 0.1], [0.1, 0.7, -0.4]]))[0].T
    sun = np.array([1.0e11, 9.0e10, 4.0e10])
    normals = plate_normals(model, rot, POS, sun)
    e_sun = (sun - POS) / np.linalg.norm(sun - POS)
    y_axis = rot[1]
    front, back = normals[6], normals[7]
    assert abs(front @ y_axis) < 1e-15
    assert front @ e_sun == pytest.approx(np.sqrt(1 - (e_sun @ y_axis) ** 2), abs=1e-14)
    np.testing.assert_allclose(back, -front)
    np.testing.assert_allclose(normals[:6], model.normal_body[:6] @ rot)  # v_gcrf = Rᵀ v_body


def test_macro_model_validation():
    with pytest.raises(ValueError, match="reflectivities"):
        _plate([1, 0, 0], spec=0.8, diff=0.3)
    with pytest.raises(ValueError, match="zero normal"):
        _plate([0, 0, 0])
    with pytest.raises(ValueError, match="mass"):
        _plate([1, 0, 0], mass=0.0)


# -------------------------------------------------------------------------------- partials


@pytest.mark.parametrize("kind", ["cannonball", "plates"])
def test_position_partials_finite_differences(kind):
    pos = np.array([6.9e6, 1.2e6, -0.8e6])
    sun = np.array([1.2e11, -8.0e10, -3.0e10])
    model = _box()
    normals = plate_normals(model, np.eye(3), pos, sun)

    def acc(p):
        if kind == "cannonball":
            return srp_cannonball(p, sun, 0.02, 1.1)
        return srp_plates(p, sun, normals, model, 1.1)  # attitude held fixed, as documented

    a0, da_dr, _, da_ds = acc(pos)
    assert shadow_function(pos, sun) == 1.0
    step = 1.0e4  # [m]; the fields vary on the scale of 1 AU
    fd = np.column_stack([(acc(pos + step * e)[0] - acc(pos - step * e)[0]) / (2 * step)
                          for e in np.eye(3)])
    np.testing.assert_allclose(da_dr, fd, rtol=0, atol=1e-6 * np.abs(da_dr).max())
    np.testing.assert_allclose(da_ds[:, 0] * 1.1, a0, rtol=1e-14)


# ------------------------------------------------------------------------------------ shadow

R_ORBIT = R_EARTH_EQUATOR_M + 450.0e3
N_ORBIT = np.sqrt(GM_EARTH_M3_S2 / R_ORBIT**3)  # mean motion [rad/s]
SUN_X = np.array([AU_M, 0.0, 0.0])


def _orbit(t_s):
    """Circular orbit in the x-y plane (the Sun in the plane); t = 0 at the anti-Sun point."""
    angle = np.pi + N_ORBIT * np.asarray(t_s, dtype=float)
    return R_ORBIT * np.stack([np.cos(angle), np.sin(angle), np.zeros_like(angle)], axis=-1)


def _nu(t_s):
    return shadow_function(_orbit(t_s), SUN_X)


def _cone_margin(t_s, umbra: bool):
    """Independent geometry: signed distance [m] of the satellite from the umbral (external
    tangent) or penumbral (internal tangent) cone of the Sun and Earth spheres, negative
    inside (M&G 2000 Fig. 3.9; similar triangles)."""
    pos = _orbit(t_s)
    d = np.linalg.norm(SUN_X)
    axis = -SUN_X / d  # anti-Sun direction
    x = pos @ axis  # distance behind the Earth's centre along the axis
    rho = np.linalg.norm(pos - x * axis)
    if umbra:
        apex = d * R_EARTH_EQUATOR_M / (R_SUN_M - R_EARTH_EQUATOR_M)  # behind the Earth
        half = np.arcsin((R_SUN_M - R_EARTH_EQUATOR_M) / d)
        return rho - (apex - x) * np.tan(half)
    apex = d * R_EARTH_EQUATOR_M / (R_SUN_M + R_EARTH_EQUATOR_M)  # towards the Sun
    half = np.arcsin((R_SUN_M + R_EARTH_EQUATOR_M) / d)
    return rho - (apex + x) * np.tan(half)


def test_shadow_limits():
    # Analytic: full Sun on the day side, deep umbra at the anti-Sun point of a LEO
    assert _nu(0.0) == 0.0
    assert shadow_function(-_orbit(0.0), SUN_X) == 1.0
    assert shadow_function(np.array([0.0, 0.0, R_ORBIT]), SUN_X) == 1.0  # over the pole


def test_shadow_monotonic_through_penumbra():
    t = np.linspace(-1400.0, -1000.0, 4001)  # leaving the Sun towards the umbra (t < 0)
    nu = _nu(t)
    assert nu[0] == 1.0 and nu[-1] == 0.0
    assert np.all(np.diff(nu) <= 0.0)
    assert np.count_nonzero((nu > 0.0) & (nu < 1.0)) > 50  # a resolved penumbra


def test_shadow_entry_times_match_cone_geometry():
    # The penumbra (umbra) begins where the satellite crosses the penumbral (umbral) cone;
    # times found on the independent cone geometry, checked on ν 2 ms either side.
    t_pen = brentq(_cone_margin, -1500.0, -1000.0, args=(False,), xtol=1e-6)
    t_umb = brentq(_cone_margin, -1500.0, -1000.0, args=(True,), xtol=1e-6)
    assert _nu(t_pen - 2e-3) == 1.0 and _nu(t_pen + 2e-3) < 1.0
    assert _nu(t_umb - 2e-3) > 0.0 and _nu(t_umb + 2e-3) == 0.0
    # Cylindrical limit (Sun at infinity and shrunk to a point): shadow entry at the angle
    # θ = asin(R⊕/r) from the anti-Sun point (r sin θ = R⊕); the half-lit instant (ν = 0.5) is there within 0.1 s (solar parallax
    # 3e-5 rad and the curvature of the Earth's limb); the penumbra lasts 2 a / n with
    # a = asin(R☉ / 1 AU) the apparent solar radius.
    t_cyl = -np.arcsin(R_EARTH_EQUATOR_M / R_ORBIT) / N_ORBIT
    t_half = brentq(lambda t: _nu(t) - 0.5, t_pen, t_umb, xtol=1e-6)
    assert t_half == pytest.approx(t_cyl, abs=0.1)
    assert t_umb - t_pen == pytest.approx(2 * np.arcsin(R_SUN_M / AU_M) / N_ORBIT, abs=0.1)


def test_shadow_vectorised_and_enlarged_earth():
    t = np.linspace(-1100.0, -1050.0, 301)
    nu = _nu(t)
    np.testing.assert_array_equal(nu, [_nu(x) for x in t])
    # a larger occulting radius (atmosphere) can only darken
    nu_atm = shadow_function(_orbit(t), SUN_X, R_EARTH_EQUATOR_M + 50.0e3)
    assert np.all(nu_atm <= nu) and np.any(nu_atm < nu)


def test_srp_in_umbra_is_zero():
    pos = _orbit(0.0)
    acc, _, _, da_ds = srp_cannonball(pos, SUN_X, 0.02)
    np.testing.assert_array_equal(acc, 0.0)
    np.testing.assert_array_equal(da_ds, 0.0)
    # shadow=False ignores the Earth
    assert np.linalg.norm(srp_cannonball(pos, SUN_X, 0.02, shadow=False)[0]) > 0.0

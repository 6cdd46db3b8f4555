"""Tests of leopod.dynamics.earth_radiation: Earth radiation pressure (albedo + infrared).

Authorities: the analytic irradiance of a uniform Lambertian sphere of exitance E at distance r,
``E (R/r)²`` along the radius (the view factor of a sphere seen from a point; Montenbruck &
Gill 2000, sec. 3.4.3; Knocke, Ries & Tapley 1988), which the ring sum approaches as the rings
multiply; the plate formula of Montenbruck & Gill (2000, sec. 3.4.1) at normal incidence;
symmetry of a uniform Earth; Knocke et al. (1988) for the albedo and emissivity model; finite
differences for the partials.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad

from leopod.constants import AU_M, R_EARTH_EQUATOR_M, SOLAR_PRESSURE_1AU_N_M2
from leopod.dynamics.earth_radiation import (
    KNOCKE_1988,
    EarthRadiation,
    earth_radiation,
    knocke_albedo_emissivity,
)
from leopod.dynamics.environment import ArcEnvironment
from leopod.dynamics.forces import interval_edges
from leopod.dynamics.srp import MacroModel

R = R_EARTH_EQUATOR_M
ALT_M = 480e3
POS = np.array([R + ALT_M, 0.0, 0.0])
VEL = np.array([0.0, 7600.0, 0.0])
SUN_AU = np.array([0.0, 0.0, AU_M])          # the Sun over the pole
UNIFORM_IR = np.array([0.0, 0.0, 0.0, 0.68, 0.0, 0.0])       # e = 0.68 everywhere, a = 0
GRACE_CR_AM = 1.3 * 3.0 / 480.0              # C_R A/m of the GRACE cannonball of the campaign


def _uniform_ir(pos, rings=2, **kw):
    return earth_radiation(pos, VEL, SUN_AU, 0.0, GRACE_CR_AM, rings=rings,
                           coefficients=UNIFORM_IR, **kw)


def test_uniform_infrared_magnitude_and_direction():
    """Uniform emission e/4: a = C_R (A/m) P☉ (e/4) (R/r)² radially outward (the view factor
    of a sphere), ≈ 5e-9 m/s² for GRACE at 480 km, within 1e-9…1e-8 m/s² as Knocke et al.
    (1988) report for ERP on LEOs; the equal-share elements make the sum exact for any
    number of rings."""
    r = np.linalg.norm(POS)
    expected = GRACE_CR_AM * SOLAR_PRESSURE_1AU_N_M2 * 0.68 / 4.0 * (R / r) ** 2
    assert 1e-9 < expected < 1e-8
    for rings in (0, 1, 2, 10):
        acc = _uniform_ir(POS, rings)
        assert acc[0] > 0.0                                   # away from the Earth
        assert np.hypot(acc[1], acc[2]) < 1e-12 * acc[0]      # radial (symmetric rings)
        assert abs(acc[0] / expected - 1.0) < 1e-12, rings


def test_uniform_earth_symmetry():
    """A uniform Earth: the same magnitude in any direction, radial, the inverse-square of
    the view factor with height."""
    rng = np.random.default_rng(3)
    ref = np.linalg.norm(_uniform_ir(POS))
    for _ in range(5):
        u = rng.normal(size=3)
        u /= np.linalg.norm(u)
        pos = np.linalg.norm(POS) * u
        acc = _uniform_ir(pos)
        assert abs(np.linalg.norm(acc) / ref - 1.0) < 1e-12
        assert np.linalg.norm(np.cross(acc, u)) < 1e-9 * ref
    high = np.array([R + 2 * ALT_M, 0.0, 0.0])
    ratio = np.linalg.norm(_uniform_ir(high, 10)) / np.linalg.norm(_uniform_ir(POS, 10))
    assert ratio == pytest.approx((np.linalg.norm(POS) / np.linalg.norm(high)) ** 2, rel=1e-12)


def test_albedo_only_on_the_day_side():
    """Uniform albedo with the Sun overhead: radial, below a E (R/r)² (cos θ☉ < 1 away from
    the sub-satellite point) and converging with the rings (19 elements within 1 % of 30
    rings); zero with the Sun behind the Earth."""
    albedo = np.array([0.3, 0.0, 0.0, 0.0, 0.0, 0.0])
    sun = POS / np.linalg.norm(POS) * AU_M

    def overhead(rings):
        return earth_radiation(POS, VEL, sun, 0.0, GRACE_CR_AM, coefficients=albedo,
                               rings=rings)
    r = np.linalg.norm(POS)
    bound = GRACE_CR_AM * SOLAR_PRESSURE_1AU_N_M2 * 0.3 * (R / r) ** 2
    fine = overhead(30)
    assert 0.8 * bound < fine[0] < bound
    assert np.hypot(fine[1], fine[2]) < 1e-9 * fine[0]
    errors = [abs(overhead(n)[0] / fine[0] - 1.0) for n in (1, 2, 5)]
    assert errors[1] < 0.01
    assert errors[0] > errors[1] > errors[2]
    night = earth_radiation(POS, VEL, -sun, 0.0, GRACE_CR_AM, coefficients=albedo)
    np.testing.assert_array_equal(night, 0.0)


def test_knocke_model():
    """Knocke et al. (1988): a = 0.34 + 0.29 P₂ at the equinox nodes of the seasonal term
    (cos = 0), e = 0.68 − 0.18 P₂; the P₁ term is ±0.10 (a) and ∓0.07 (e) at t₀."""
    quarter = 365.25 * 86400.0 / 4
    t0 = (2444960.5 - 2451545.0) * 86400.0
    sin_lat = np.array([-1.0, 0.0, 1.0])
    a, e = knocke_albedo_emissivity(sin_lat, t0 + quarter)
    np.testing.assert_allclose(a, [0.34 + 0.29, 0.34 - 0.145, 0.34 + 0.29], atol=1e-12)
    np.testing.assert_allclose(e, [0.68 - 0.18, 0.68 + 0.09, 0.68 - 0.18], atol=1e-12)
    a, e = knocke_albedo_emissivity(sin_lat, t0)
    np.testing.assert_allclose(a, [0.63 - 0.10, 0.195, 0.63 + 0.10], atol=1e-12)
    np.testing.assert_allclose(e, [0.50 + 0.07, 0.77, 0.50 - 0.07], atol=1e-12)
    assert KNOCKE_1988.shape == (6,)


def test_plate_facing_nadir():
    """An absorbing plate facing the Earth in a uniform infrared field feels, radially,
    (A/m) P☉ E ∫ cos α cos²β dA / (π ρ²) (projected area cos β = cos θ, force component
    cos β; M&G 2000, sec. 3.4.1), integrated here by quadrature over cos ψ: the rings converge
    to it (19 elements within 3 %, 20 rings within 0.1 %); a plate facing away feels
    nothing."""
    nadir = MacroModel(normal_body=[[-1.0, 0.0, 0.0]], area_m2=2.0, specular=0.0, diffuse=0.0,
                       drag_coefficient=2.3, mass_kg=400.0)
    r = np.linalg.norm(POS)

    def integrand(u):
        rho = np.sqrt(r * r + R * R - 2.0 * r * R * u)
        return 2.0 * R * R * (r * u - R) * (r - R * u) ** 2 / rho**5
    expected = 2.0 / 400.0 * SOLAR_PRESSURE_1AU_N_M2 * 0.68 / 4.0 * quad(integrand, R / r, 1.0,
                                                                        epsabs=0.0)[0]
    for rings, tol in ((2, 0.03), (20, 1e-3)):
        acc = _uniform_ir(POS, rings, normals=nadir.normal_body, model=nadir)
        assert acc[0] == pytest.approx(expected, rel=tol), rings
        assert np.hypot(acc[1], acc[2]) < 1e-12 * acc[0]
    zenith = MacroModel(normal_body=[[1.0, 0.0, 0.0]], area_m2=2.0, specular=0.0, diffuse=0.0,
                        drag_coefficient=2.3, mass_kg=400.0)
    np.testing.assert_array_equal(_uniform_ir(POS, normals=zenith.normal_body, model=zenith),
                                  0.0)


def test_infrared_uses_the_infrared_reflectivities():
    """A nadir plate black in the visible and a Lambertian reflector in the infrared, albedo
    off: the diffuse term adds (2/3) P A cos θ n per element (M&G 2000, sec. 3.4.1), whose sum
    is (2/3) (A/m) P☉ E (R/r)² along the normal (Σ irradiance × cos θ = the view factor of a
    plate facing the sphere); black in the infrared it would add nothing."""
    def plate(**ir):
        return MacroModel(normal_body=[[-1.0, 0.0, 0.0]], area_m2=2.0, specular=0.0,
                          diffuse=0.0, drag_coefficient=2.3, mass_kg=400.0, **ir)
    black, white_ir = plate(), plate(specular_ir=0.0, diffuse_ir=1.0)
    a_black = _uniform_ir(POS, normals=black.normal_body, model=black)
    a_white = _uniform_ir(POS, normals=white_ir.normal_body, model=white_ir)
    r = np.linalg.norm(POS)
    expected = 2.0 / 3.0 * 2.0 / 400.0 * SOLAR_PRESSURE_1AU_N_M2 * 0.68 / 4.0 * (R / r) ** 2
    assert a_white[0] - a_black[0] == pytest.approx(expected, rel=1e-12)
    white_visible = MacroModel(normal_body=[[-1.0, 0.0, 0.0]], area_m2=2.0, specular=0.0,
                               diffuse=1.0, drag_coefficient=2.3, mass_kg=400.0,
                               specular_ir=0.0, diffuse_ir=0.0)
    np.testing.assert_array_equal(
        _uniform_ir(POS, normals=white_visible.normal_body, model=white_visible), a_black)


def _env():
    return ArcEnvironment(np.datetime64("2007-03-21T00:00", "ns"), 0.0, 3600.0)


def test_force_partials_against_finite_differences():
    """∂a/∂s = a/s exactly (finite difference of the scale); the neglected ∂a/∂r is below
    1e-14 s⁻² (central differences over ±100 m; 1e-8 of the gravity gradient 2.4e-6 s⁻²)."""
    env = _env()
    force = EarthRadiation(env, GRACE_CR_AM, interval_edges(0.0, 3600.0, None), estimate=True)
    t, pos = 1200.0, np.array([R + ALT_M, 1.0e5, 2.0e5])
    vel = np.cross([0.1, -0.2, 1.0], pos)
    vel *= 7600.0 / np.linalg.norm(vel)
    acc, da_dr, da_dv, da_dp = force.evaluate(t, pos, vel, np.array([0.9]))
    assert 1e-10 < np.linalg.norm(acc) < 1e-7
    h = 0.01
    up = force.evaluate(t, pos, vel, np.array([0.9 + h]))[0]
    down = force.evaluate(t, pos, vel, np.array([0.9 - h]))[0]
    np.testing.assert_allclose((up - down) / (2 * h), da_dp[:, 0], rtol=1e-10)
    np.testing.assert_array_equal(da_dr, 0.0)
    np.testing.assert_array_equal(da_dv, 0.0)
    step = 100.0
    for j in range(3):
        dp = np.zeros(3)
        dp[j] = step
        fd = (force.evaluate(t, pos + dp, vel, np.array([0.9]))[0]
              - force.evaluate(t, pos - dp, vel, np.array([0.9]))[0]) / (2 * step)
        assert np.abs(fd).max() < 1e-14

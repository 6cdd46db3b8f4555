"""Tests of the configurable GCRF force model of an arc: leopod.dynamics.force_config, the grids
of leopod.dynamics.environment and the forces beside their physics.

Authorities: direct (non-interpolated) evaluation of the same inputs — the IAU 2006/2000A
ITRF -> GCRF matrices of :func:`leopod.frames.earth_rotation.gcrf_from_itrf_matrices`, DE421
positions of :class:`leopod.dynamics.third_body.Ephemeris`, tidal coefficients of
:class:`leopod.dynamics.tides.TideModel`; the reference implementations of each force
(:class:`GravityField` in the ITRF, ``third_body_acceleration``, ``relativistic_acceleration``,
``drag_cannonball``, ``srp_cannonball``, ``empirical_acceleration``); central finite
differences for the partials; the permanent tide of IERS Conventions 2010 eq. (6.14).
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from leopod.astro.ephemeris import Ephemeris
from leopod.constants import GM_MOON_M3_S2, GM_SUN_M3_S2, OMEGA_EARTH_RAD_S
from leopod.dynamics.drag import Drag, HarrisPriesterDensity, drag_cannonball
from leopod.dynamics.empirical import Empirical, empirical_acceleration
from leopod.dynamics.environment import ArcEnvironment
from leopod.dynamics.force_config import (
    ForceModelSettings,
    build_force_model,
)
from leopod.dynamics.forces import (
    PointMassGravity,
    apriori_parameters,
    constraint_sigmas,
    estimated_parameters,
    interval_edges,
)
from leopod.dynamics.gravity_field import EarthGravity, GravityField
from leopod.dynamics.relativity import Relativity, relativistic_acceleration
from leopod.dynamics.solid_tides import permanent_tide_c20
from leopod.dynamics.srp import SolarRadiation, srp_cannonball
from leopod.dynamics.third_body import ThirdBodies, third_body_acceleration
from leopod.dynamics.tides import TideModel
from leopod.settings import schema_defaults

T_REF = np.datetime64("2023-01-01T00:00:00", "ns")
ARC_S = 6 * 3600.0
#: A Swarm-A state of 2023-01-01 00:00 GPST (GCRF, from its ESA SP3 orbit) [m, m/s].
POS = np.array([6131381.0, -3041979.0, 96752.65])
VEL = np.array([258.5907, 255.4880, -7623.774])


def egm2008_degree4(tide_system: str = "tide_free") -> xr.Dataset:
    """EGM2008 to degree 4 (coefficients of the ICGEM file EGM2008_120.gfc), as read_icgem."""
    c, s = np.zeros((5, 5)), np.zeros((5, 5))
    c[0, 0] = 1.0
    c[2, :3] = -0.484165143790815e-03, -0.206615509074176e-09, 0.243938357328313e-05
    s[2, 1:3] = 0.138441389137979e-08, -0.140027370385934e-05
    c[3, :4] = (0.957161207093473e-06, 0.203046201047864e-05, 0.904787894809528e-06,
                0.721321757121568e-06)
    s[3, 1:4] = 0.248200415856872e-06, -0.619005475177618e-06, 0.141434926192941e-05
    c[4, 0] = 0.539965866638991e-06
    return xr.Dataset({"C": (("n", "m"), c), "S": (("n", "m"), s)},
                      coords={"n": np.arange(5), "m": np.arange(5)},
                      attrs={"gm_m3_s2": 3.986004415e14, "radius_m": 6378136.3,
                             "max_degree": 4, "tide_system": tide_system,
                             "modelname": "EGM2008 degree 4"})


@pytest.fixture(scope="module")
def env():
    return ArcEnvironment(T_REF, 0.0, ARC_S)


@pytest.fixture
def rng():
    """A generator of its own for each test (same seed): results do not depend on test order."""
    return np.random.default_rng(20230101)


def _times(rng, n=200):
    return np.sort(rng.uniform(0.0, ARC_S, n))


def _build(config, env=None):
    return build_force_model(ForceModelSettings.from_config(config), T_REF, 0.0, ARC_S, environment=env)


# ------------------------------------------------------------------------ environment


def test_rotation_interpolation_matches_direct_computation(env, rng):
    t = _times(rng, 500)
    # authority: gcrf_from_itrf_matrices at each epoch. Its own floor is ~1e-13 (epochs are
    # rounded to 1 ns = 7e-14 rad of Earth rotation; erfa.era00 resolves ~3e-14 rad).
    err = np.abs(env.rotation(t) - env.rotation_direct(t)[0]).max()
    assert err < 2e-13


def test_sun_moon_interpolation_matches_de421(env, rng):
    t = _times(rng)
    eph = Ephemeris()
    tt = env.tt_j2000_s(t)
    # authority: DE421 evaluated directly at each epoch (jplephem)
    assert np.abs(env.sun_m(t) - eph.sun_m(tt)).max() < 0.01
    assert np.abs(env.moon_m(t) - eph.moon_m(tt)).max() < 0.001
    # Sun velocity (~30 km/s): central difference of DE421 over ±10 s (truncation 2e-8 m/s,
    # round-off of the 0.03-mm position noise 2e-6 m/s), independent of the ±60-s one
    vel = (eph.sun_m(tt + 10.0) - eph.sun_m(tt - 10.0)) / 20.0
    assert np.abs(env.body_grid(t)[:, 3:6] - vel).max() < 5e-6


def test_tt_reference_epoch(env):
    # 2023-01-01 00:00 GPST = 00:00:51.184 TT; J2000.0 = 2000-01-01 12:00 TT: 8400.5 days
    # + 51.184 s (calendar arithmetic)
    assert env.tt_j2000_ref_s == pytest.approx(8400.5 * 86400.0 + 51.184, abs=1e-6)


def test_epoch_outside_arc_raises(env):
    force = ThirdBodies(env)
    with pytest.raises(ValueError, match="outside the arc"):
        force.evaluate(ARC_S + 3600.0, POS, VEL, np.empty(0))


# ----------------------------------------------------------------------------- gravity


def test_earth_gravity_matches_field_in_itrf(env, rng):
    field = GravityField(egm2008_degree4(), 4)
    force = EarthGravity(field, env)
    for t in _times(rng, 5):
        acc, grad, da_dv, da_dp = force.evaluate(t, POS, VEL, np.empty(0))
        rot = env.rotation_direct([t])[0][0]
        # authority: GravityField in the ITRF with the directly computed rotation
        a_ef, g_ef = field.acceleration_and_gradient(rot.T @ POS)
        np.testing.assert_allclose(acc, rot @ a_ef, rtol=0, atol=1e-12 * 8.5)
        np.testing.assert_allclose(grad, rot @ g_ef @ rot.T, rtol=0, atol=1e-12 * 2.6e-6)
        assert not da_dv.any() and da_dp.shape == (3, 0)


def test_gravity_gradient_equals_finite_differences(env):
    force = EarthGravity(GravityField(egm2008_degree4(), 4), env)
    t = 1234.5
    grad = force.evaluate(t, POS, VEL, np.empty(0))[1]
    step = 1.0
    fd = np.column_stack([(force.evaluate(t, POS + step * e, VEL, np.empty(0))[0]
                           - force.evaluate(t, POS - step * e, VEL, np.empty(0))[0]) / (2 * step)
                          for e in np.eye(3)])
    np.testing.assert_allclose(grad, fd, rtol=0, atol=1e-13)     # |grad| ~ 2.6e-6 s⁻²


def test_gradient_degree_option(env):
    ds = egm2008_degree4()
    full = EarthGravity(GravityField(ds, 4), env)
    low = EarthGravity(GravityField(ds, 4), env, gradient_field=GravityField(ds, 2))
    a1, g1 = full.evaluate(10.0, POS, VEL, np.empty(0))[:2]
    a2, g2 = low.evaluate(10.0, POS, VEL, np.empty(0))[:2]
    np.testing.assert_allclose(a2, a1, rtol=1e-14)
    # the degree 3-4 part of the gradient: C̄3m ~ 1e-6 times (n+1)(n+2) (R/r)^n ~ 2e-5
    np.testing.assert_allclose(g2, g1, rtol=0, atol=5e-5 * np.abs(g1).max())
    assert np.abs(g2 - g1).max() > 1e-6 * np.abs(g1).max()


def test_tidal_tables_interpolation_and_acceleration(env):
    field = GravityField(egm2008_degree4(), 4)
    tides = TideModel("tide_free", solid=True, solid_pole=True, ocean_pole=True,
                         gm_earth_m3_s2=field.gm_m3_s2, radius_m=field.radius_m)
    force = EarthGravity(field, env, tides)
    t = np.array([1000.0, 7777.7, 20000.0])            # off the 300-s grid
    dc, ds = force.tide_coefficients(t)
    direct = force.tide_tables(dc, ds)
    interpolated = force.tide_grid(t)
    assert np.abs(interpolated - direct).max() < 1e-9 * np.abs(direct).max()
    pos_ef = env.rotation_direct(t)[0][0].T @ POS
    for i, ti in enumerate(t):
        # authority: a GravityField of the directly computed ΔC̄, ΔS̄ (public API)
        n = dc.shape[1]
        delta = xr.Dataset({"C": (("n", "m"), dc[i]), "S": (("n", "m"), ds[i])},
                           coords={"n": np.arange(n), "m": np.arange(n)},
                           attrs={"gm_m3_s2": field.gm_m3_s2, "radius_m": field.radius_m,
                                  "max_degree": n - 1})
        expected = GravityField(delta, n - 1).acceleration(pos_ef)
        assert np.linalg.norm(expected) > 1e-8                  # solid tides ~1e-7 m/s²
        got = force.tide_acceleration_itrf(ti, pos_ef)
        np.testing.assert_allclose(got, expected, rtol=0, atol=1e-9 * np.linalg.norm(expected))


def test_tide_system_of_the_field_is_used(env):
    # IERS 2010 eq. (6.13)-(6.14): for a zero-tide field the permanent tide A0 H0 k20
    # (−4.2e-9 for R_e = 6378136.6 m) is removed from ΔC̄20; nothing else changes.
    cfg = {"gravity": {"field": None}, "tides": {"solid": True}}
    dc20 = {}
    for system in ("tide_free", "zero_tide"):
        cfg["gravity"]["field"] = egm2008_degree4(system)
        force = _build(cfg, env).forces[0]
        dc, _ = force.tide_coefficients([100.0])
        dc20[system] = dc[0, 2, 0]
    expected = -permanent_tide_c20(radius_m=6378136.3)
    assert expected == pytest.approx(4.2007e-9, rel=1e-4)
    assert dc20["zero_tide"] - dc20["tide_free"] == pytest.approx(expected, rel=1e-12)


def test_tides_need_a_known_tide_system(env):
    cfg = {"gravity": {"field": egm2008_degree4("unknown")}, "tides": {"solid": True}}
    with pytest.raises(ValueError, match="tide system"):
        _build(cfg, env)
    # without tides any field is fine
    assert isinstance(_build({"gravity": cfg["gravity"]}, env).forces[0], EarthGravity)


# ------------------------------------------------------------ third bodies, relativity


def test_third_bodies_match_reference(env, rng):
    force = ThirdBodies(env)
    eph = Ephemeris()
    for t in _times(rng, 3):
        acc, grad = force.evaluate(t, POS, VEL, np.empty(0))[:2]
        tt = env.tt_j2000_s(t)
        ref_a = np.zeros(3)
        ref_g = np.zeros((3, 3))
        for body, gm in ((eph.sun_m(tt)[0], GM_SUN_M3_S2), (eph.moon_m(tt)[0], GM_MOON_M3_S2)):
            a, g = third_body_acceleration(POS, body, gm)
            ref_a, ref_g = ref_a + a, ref_g + g
        np.testing.assert_allclose(acc, ref_a, rtol=1e-9)
        np.testing.assert_allclose(grad, ref_g, rtol=1e-9)
    moon_only = ThirdBodies(env, sun=False)
    a = moon_only.evaluate(50.0, POS, VEL, np.empty(0))[0]
    ref = third_body_acceleration(POS, eph.moon_m(env.tt_j2000_s(50.0))[0], GM_MOON_M3_S2,
                                  with_gradient=False)
    np.testing.assert_allclose(a, ref, rtol=1e-9)


@pytest.mark.parametrize("lense_thirring, de_sitter", [(True, True), (False, False)])
def test_relativity_matches_reference(env, lense_thirring, de_sitter):
    force = Relativity(env, lense_thirring, de_sitter)
    t = 4321.0
    eph = Ephemeris()
    tt = env.tt_j2000_s(t)
    sun = eph.sun_m(tt)[0]
    sun_vel = (eph.sun_m(tt + 1.0)[0] - eph.sun_m(tt - 1.0)[0]) / 2.0
    ref = relativistic_acceleration(POS, VEL, sun if de_sitter else None,
                                    sun_vel if de_sitter else None,
                                    lense_thirring=lense_thirring)
    acc = force.evaluate(t, POS, VEL, np.empty(0))[0]
    np.testing.assert_allclose(acc, ref, rtol=1e-9, atol=1e-20)


# ------------------------------------------------------------------- non-gravitational


def test_interval_edges():
    np.testing.assert_array_equal(interval_edges(0.0, 86390.0, 10800.0),
                                  10800.0 * np.arange(9).clip(max=86390 / 10800))
    np.testing.assert_array_equal(interval_edges(5.0, 10.0, None), [5.0, 10.0])
    np.testing.assert_array_equal(interval_edges(0.0, 21600.0, 10800.0), [0, 10800, 21600])
    with pytest.raises(ValueError):
        interval_edges(0.0, 1.0, 0.0)


def test_drag_matches_reference_per_interval(env):
    density = HarrisPriesterDensity()
    cd_am = 2.3 / 470.0
    force = Drag(env, density, cd_am, [0.0, 7200.0, ARC_S])
    assert force.parameters == ["drag_scale_0", "drag_scale_1"]
    np.testing.assert_array_equal(force.breakpoints_s, [7200.0])
    scales = np.array([1.3, 0.6])
    for t, k in ((100.0, 0), (7200.0, 1), (ARC_S + 1.0, 1)):
        acc, _, da_dv, da_dp = force.evaluate(t, POS, VEL, scales)
        rot = env.rotation_direct([t])[0][0]
        sun = env.bodies_direct([t])[0, :3]
        rho, grad = density(env.tt_j2000_s(t), POS, rot.T, sun)
        ref = drag_cannonball(POS, VEL, rho, grad, cd_am, scales[k],
                              omega_rad_s=OMEGA_EARTH_RAD_S * rot[:, 2])
        np.testing.assert_allclose(acc, ref[0], rtol=1e-9)
        np.testing.assert_allclose(da_dv, ref[2], rtol=1e-9)
        np.testing.assert_allclose(da_dp[:, k], acc / scales[k], rtol=1e-12)
        assert not da_dp[:, 1 - k].any()


def test_srp_matches_reference(env):
    force = SolarRadiation(env, 1.3 / 470.0, [0.0, ARC_S])
    assert force.parameters == ["srp_scale_0"] and not force.estimate
    t = 2000.0
    acc, _, _, da_dp = force.evaluate(t, POS, VEL, np.array([0.9]))
    ref = srp_cannonball(POS, env.bodies_direct([t])[0, :3], 1.3 / 470.0, 0.9)
    np.testing.assert_allclose(acc, ref[0], rtol=1e-9)
    np.testing.assert_allclose(da_dp, ref[3], rtol=1e-9)


def test_empirical_force(env, rng):
    force = _build({"gravity": None, "empirical": {"interval_s": 7200.0}}, env).forces[1]
    assert force.parameters[:6] == ["emp_const_T_0", "emp_cos_T_0", "emp_sin_T_0",
                                    "emp_const_N_0", "emp_cos_N_0", "emp_sin_N_0"]
    np.testing.assert_array_equal(force.breakpoints_s, [7200.0, 14400.0])
    p = rng.normal(0.0, 1e-8, len(force.parameters))
    got = force.evaluate(9000.0, POS, VEL, p)
    ref = empirical_acceleration(9000.0, POS, VEL, p, force.model)
    for a, b in zip(got, ref):
        np.testing.assert_array_equal(a, b)


# ------------------------------------------------------------------------------ builder


FULL = {"gravity": {"field": egm2008_degree4()}, "tides": {"solid": True},
        "third_body": True, "relativity": {"lense_thirring": True},
        "drag": {"area_m2": 1.0, "mass_kg": 470.0, "interval_s": 10800.0},
        "srp": {"cr_area_mass_m2_kg": 0.003},
        "empirical": {"interval_s": 10800.0, "sigma": 1e-7}}


def test_build_every_force_switchable(env):
    model = _build(FULL, env)
    kinds = [type(f) for f in model.forces]
    assert kinds == [EarthGravity, ThirdBodies, Relativity, Drag,
                     SolarRadiation, Empirical]
    assert model.n_params == 2 + 1 + 12
    for name, kind in (("third_body", ThirdBodies), ("relativity", Relativity),
                       ("drag", Drag), ("srp", SolarRadiation),
                       ("empirical", Empirical)):
        for off in (None, False, {"enabled": False}):
            reduced = _build({**FULL, name: off}, env)
            assert kind not in [type(f) for f in reduced.forces]
    assert _build({**FULL, "tides": None}, env).forces[0].tide_grid is None
    assert isinstance(_build({**FULL, "gravity": None}, env).forces[0], PointMassGravity)


def test_build_parameters_and_ratios(env):
    model = _build(FULL, env)
    drag = model.forces[3]
    assert drag.cd_area_mass_m2_kg == pytest.approx(schema_defaults("force_drag")["drag_coefficient"] / 470.0)
    ap = apriori_parameters(model)
    est = estimated_parameters(model)
    sig = constraint_sigmas(model)
    names = model.parameters
    assert ap[names.index("drag_scale_1")] == 1.0 and ap[names.index("srp_scale_0")] == 1.0
    assert ap[names.index("emp_cos_N_1")] == 0.0
    assert not est[names.index("srp_scale_0")] and est[names.index("drag_scale_0")]
    assert sig[names.index("emp_sin_T_0")] == 1e-7 and np.isinf(sig[names.index("drag_scale_0")])


@pytest.mark.parametrize("config, message", [
    ({"gravity": None, "drag": {"area_m2": 1.0}}, "mass_kg"),
    ({"gravity": None, "dragg": {}}, "unknown sections"),
    ({"gravity": None, "drag": {"cd_area_mass_m2_kg": 0.005, "interval": 3}}, "unknown keys"),
    ({"gravity": None, "drag": {"cd_area_mass_m2_kg": 0.005, "density": "jacchia"}}, "density"),
    ({"gravity": None, "drag": {"cd_area_mass_m2_kg": 0.005, "density": "msis"}},
     "space_weather"),
    ({"gravity": {"max_degree": 4}}, "field"),
])
def test_build_rejects_bad_config(env, config, message):
    with pytest.raises(ValueError, match=message):
        _build(config, env)


def test_total_partials_equal_finite_differences(env):
    cfg = {**FULL, "relativity": None}                 # relativity partials are neglected
    model = _build(cfg, env)
    params = apriori_parameters(model)              # empirical terms 0: no frame partials
    t = 12345.0
    _, da_dr, da_dv, _ = model.evaluate(t, POS, VEL, params)

    def jac(fun, x, step):
        return np.column_stack([(fun(x + step * e) - fun(x - step * e)) / (2 * step)
                                for e in np.eye(3)])

    fd_r = jac(lambda r: model.evaluate(t, r, VEL, params)[0], POS, 1.0)
    fd_v = jac(lambda v: model.evaluate(t, POS, v, params)[0], VEL, 1.0)
    np.testing.assert_allclose(da_dr, fd_r, rtol=0, atol=2e-13)      # |A| ~ 2.6e-6 s⁻²
    assert np.abs(da_dv).max() > 1e-11                                # drag ~ a/v ~ 5e-11 s⁻¹
    # round-off of |a| = 8.5 m/s² over a 2-m/s difference: ~1e-15 s⁻¹
    np.testing.assert_allclose(da_dv, fd_v, rtol=0, atol=2e-14)


@pytest.mark.shared
def test_egm2008_fes2004_model(shared):
    models = shared / "models"
    cfg = {"gravity": {"field": models / "gravity" / "EGM2008_120.gfc"},
           "tides": {"ocean": models / "ocean_tides" / "fes2004_Cnm-Snm.dat"}}
    env = ArcEnvironment(T_REF, 0.0, 3600.0)
    force = _build_short(cfg, env)
    assert force.field.tide_system == "tide_free" and force.tides.max_degree == 30
    t = np.array([1111.1, 2222.2])
    direct = force.tide_tables(*force.tide_coefficients(t))
    assert np.abs(force.tide_grid(t) - direct).max() < 1e-9 * np.abs(direct).max()
    acc = force.evaluate(1000.0, POS, VEL, np.empty(0))[0]
    # |a| = GM/r² (1 + O(J2)) at |r| = 6.83e6 m: 8.55 m/s² within 0.3 %
    assert np.linalg.norm(acc) == pytest.approx(3.986004415e14 / np.sum(POS**2), rel=3e-3)


def _build_short(cfg, env):
    return build_force_model(ForceModelSettings.from_config(cfg), T_REF, 0.0, 3600.0, environment=env).forces[0]

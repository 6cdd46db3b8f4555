"""Tests of leopod.simulate.world: nominal constellations (BDS-3 MEO, Walker), Kepler orbits.

Authorities: the published BDS-3 MEO constellation (Yang et al. 2019, Navigation 66(1):7-18:
altitude 21 528 km, inclination 55°, Walker 24/3/1, ground track repeating after 13
revolutions in 7 sidereal days), the MGEX list of BDS-3 MEO PRNs, Kepler's third law, Walker's
definition of a delta constellation (Walker 1984) checked on node and argument of latitude
recomputed from the position and velocity vectors; for KeplerOrbit the circular limit
(CircularOrbit), vis-viva, finite differences and the relativistic clock formula of
IS-GPS-200.
"""

from __future__ import annotations

import numpy as np
import pytest

from leopod.constants import GM_EARTH_M3_S2, R_EARTH_EQUATOR_M
from leopod.dynamics.empirical import argument_of_latitude
from leopod.gnss.corrections import relativistic_clock_s
from leopod.simulate.world import (
    CircularOrbit,
    KeplerOrbit,
    beidou3_constellation,
    walker_constellation,
)

#: Sidereal day [s] (IERS Conventions 2010, Table 1.2 note: 86164.0905 s mean sidereal day).
SIDEREAL_DAY_S = 86_164.0905


@pytest.fixture(scope="module")
def bds():
    return beidou3_constellation()


#: Tolerance of angles recomputed from r × v [deg]: the velocity of CircularOrbit includes the
#: secular J2 node drift (Ω̇ ≈ 1e-4 n for BDS-3), which tilts r × v by up to 0.003°.
ANGLE_ATOL_DEG = 0.005


def _states(orbits):
    pos, vel = zip(*(o.inertial(0.0) for o in orbits.values()))
    return np.array(pos), np.array(vel)


def _node_deg(pos, vel):
    h = np.cross(pos, vel)
    return np.degrees(np.arctan2(h[:, 0], -h[:, 1])) % 360.0


def test_bds3_prns_are_the_24_meo_satellites(bds):
    # authority: IGS MGEX BDS status — BDS-3 MEO PRNs C19-C30, C32-C37, C41-C46
    expected = [f"C{k:02d}" for k in [*range(19, 31), *range(32, 38), *range(41, 47)]]
    assert sorted(bds) == expected


def test_bds3_radius_and_inclination(bds):
    pos, vel = _states(bds)
    # authority: Yang et al. (2019): altitude 21 528 km (a ≈ 27 906 km), inclination 55°
    assert np.allclose(np.linalg.norm(pos, axis=1), 27_906.1e3, atol=1.0e3)
    h = np.cross(pos, vel)
    inc_deg = np.degrees(np.arccos(h[:, 2] / np.linalg.norm(h, axis=1)))
    assert np.allclose(inc_deg, 55.0, atol=ANGLE_ATOL_DEG)


def test_bds3_period_repeats_in_seven_sidereal_days(bds):
    a_m = np.linalg.norm(next(iter(bds.values())).inertial(0.0)[0])
    # authority: Kepler's third law, T = 2π sqrt(a³/GM) ≈ 12 h 53 min (Yang et al. 2019)
    period_s = 2.0 * np.pi * np.sqrt(a_m**3 / GM_EARTH_M3_S2)
    assert abs(period_s - (12 * 3600 + 53 * 60)) < 60.0
    # authority: the BDS-3 MEO ground track repeats after 13 revolutions in 7 sidereal days
    assert abs(13 * period_s - 7 * SIDEREAL_DAY_S) < 60.0


def test_bds3_speed_is_circular(bds):
    pos, vel = _states(bds)
    # authority: circular orbit, |v| = sqrt(GM/a) (J2 drift changes it by < 1e-4)
    v_circ = np.sqrt(GM_EARTH_M3_S2 / np.linalg.norm(pos, axis=1))
    assert np.allclose(np.linalg.norm(vel, axis=1), v_circ, rtol=1e-4)


def test_bds3_walker_24_3_1_spacing(bds):
    pos, vel = _states(bds)
    node = _node_deg(pos, vel)
    u = np.degrees(argument_of_latitude(pos, vel)) % 360.0
    planes = np.round(node / 120.0).astype(int) % 3
    # authority: Walker 24/3/1: 3 planes 120° apart, 8 satellites per plane 45° apart,
    # satellites of adjacent planes shifted by F·360°/T = 15°
    assert np.allclose((node - 120.0 * planes + 180.0) % 360.0 - 180.0, 0.0, atol=ANGLE_ATOL_DEG)
    assert np.bincount(planes).tolist() == [8, 8, 8]
    for p in range(3):
        phase = (u[planes == p] - 15.0 * p) % 45.0
        assert np.allclose(np.minimum(phase, 45.0 - phase), 0.0, atol=ANGLE_ATOL_DEG)
        assert np.unique(np.round((u[planes == p] - 15.0 * p) % 360.0 / 45.0) % 8).size == 8


def test_walker_rejects_inconsistent_patterns():
    # authority: Walker T/P/F needs T divisible by P and 0 <= F < P
    with pytest.raises(ValueError):
        walker_constellation(["C01", "C02", "C03"], 2, 0, R_EARTH_EQUATOR_M + 2e7, 55.0)
    with pytest.raises(ValueError):
        walker_constellation(["C01", "C02"], 2, 2, R_EARTH_EQUATOR_M + 2e7, 55.0)


# ------------------------------------------------------------------------- KeplerOrbit
#: A GPS-like ellipse (a 26 560 km, e 0.015, i 55°) without and with the J2 drift.
KEPLER = {"a_m": 26_560e3, "eccentricity": 0.015, "inc_deg": 55.0, "raan_deg": 40.0,
          "argp_deg": 70.0, "m0_deg": 10.0}


def test_kepler_circular_limit_is_circular_orbit():
    # e = 0: same motion as CircularOrbit with u0 = ω0 + M0 (the J2 rates of both reduce to
    # the same secular rates, Vallado eq. 9-41)
    t = np.linspace(0.0, 2 * 86400.0, 97)
    kep = KeplerOrbit(**{**KEPLER, "eccentricity": 0.0})
    circ = CircularOrbit(KEPLER["a_m"], 55.0, 40.0, 80.0)
    for got, want in zip(kep.inertial(t), circ.inertial(t)):
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-6)


def _eccentric_anomaly(t):
    """E(t) of the two-body KEPLER orbit by fixed-point iteration of Kepler's equation."""
    mean = np.radians(KEPLER["m0_deg"]) + np.sqrt(GM_EARTH_M3_S2 / KEPLER["a_m"]**3) * t
    ecc = mean.copy()
    for _ in range(30):
        ecc = mean + KEPLER["eccentricity"] * np.sin(ecc)
    return ecc


def test_kepler_vis_viva_and_radius():
    # two-body motion (j2 off): vis-viva v²/2 − GM/r = −GM/(2a), r = a (1 − e cos E)
    orbit = KeplerOrbit(**KEPLER, j2=False)
    t = np.linspace(0.0, 43_200.0, 1001)
    pos, vel = orbit.inertial(t)
    r = np.linalg.norm(pos, axis=-1)
    energy = 0.5 * np.sum(vel**2, axis=-1) - GM_EARTH_M3_S2 / r
    np.testing.assert_allclose(energy, -GM_EARTH_M3_S2 / (2 * KEPLER["a_m"]), rtol=1e-12)
    want = KEPLER["a_m"] * (1 - KEPLER["eccentricity"] * np.cos(_eccentric_anomaly(t)))
    np.testing.assert_allclose(r, want, rtol=0, atol=1e-6)


def test_kepler_velocity_is_the_derivative_of_position():
    # central differences (h = 0.1 s: truncation a n³ h² / 6 ~ 1.4e-7 m/s, rounding
    # ~3e-8 m/s), with the J2 drift
    orbit = KeplerOrbit(**KEPLER)
    t = np.linspace(0.0, 86400.0, 13)
    _, vel = orbit.inertial(t)
    fd = (orbit.inertial(t + 0.1)[0] - orbit.inertial(t - 0.1)[0]) / 0.2
    np.testing.assert_allclose(vel, fd, rtol=0, atol=1e-6)


def test_kepler_relativistic_clock_term():
    # IS-GPS-200 20.3.3.3.3.1: Δt_r = F e sqrt(a) sin E with F = −2 sqrt(GM)/c², which
    # equals −2 r·v/c² (leopod.gnss.corrections.relativistic_clock_s)
    orbit = KeplerOrbit(**KEPLER, j2=False)
    t = np.linspace(0.0, 43_200.0, 25)
    pos, vel = orbit.inertial(t)
    ecc = _eccentric_anomaly(t)
    c = 299_792_458.0
    want = (-2.0 * np.sqrt(GM_EARTH_M3_S2) / c**2 * KEPLER["eccentricity"]
            * np.sqrt(KEPLER["a_m"]) * np.sin(ecc))
    np.testing.assert_allclose(relativistic_clock_s(pos, vel), want, rtol=0, atol=1e-15)
    assert np.max(np.abs(want)) * c > 9.0            # ~10 m at e = 0.015

"""LEO nominal attitude and the signs of the corrections as the estimator's model applies them.

``nominal_axes_inertial`` is shared by the simulator and the estimator, and so are the signs of
the LEO antenna offset, the satellite relativistic clock, the Shapiro delay and the wind-up in
``compute_model``: a closed loop cannot see them flipped in both. These tests take them from
hand geometry with a GNSS satellite fixed in the Earth-fixed frame (a stand-in for
``GnssProducts`` with zero clock).

Authorities: the nominal LEO attitude of the mission documents (GRACE: +Z to nadir, +X along
the flight direction, SRF of the GRACE L1B product description, Case et al. 2010; the same
convention in ../shared/data/MANIFEST.md); the IGS/ANTEX convention that the phase centre is
``r_com + R_body→frame · PCO`` (Rothacher & Schmid 2010, ANTEX 1.4); IS-GPS-200 20.3.3.3.3.1
(the relativistic term is part of the satellite clock offset, ``ρ − c dt^s``); IERS Conventions
2010 eq. 11.17 (the Shapiro delay lengthens the path); Wu et al. 1993 / Kouba 2009 sec. 5.3
for the wind-up (sign derived in tests/estimation/test_corrections.py).
"""

import numpy as np
import pytest

from leopod.constants import C_LIGHT_M_S, GM_EARTH_M3_S2
from leopod.estimation.obsmodel import Pairs, compute_model
from leopod.frames.attitude import nominal_axes_inertial

R_LEO = 6_878e3          # 500 km altitude
R_GPS = 26_560e3
V_LEO = np.sqrt(GM_EARTH_M3_S2 / R_LEO)
NL = 0.10695             # narrow-lane wavelength c/(f1+f2) of GPS L1/L2 [m]
SUN = np.array([[0.3e11, 1.4e11, 0.2e11]])


class _FixedSatellite:
    """One GNSS satellite at a fixed Earth-fixed position and velocity, clock zero."""

    def __init__(self, pos, vel=(0.0, 0.0, 0.0)):
        self.pos, self.vel = np.asarray(pos, float), np.asarray(vel, float)

    def position(self, isv, t_s):
        n = np.size(isv)
        return np.tile(self.pos, (n, 1)), np.tile(self.vel, (n, 1)), np.zeros(n, bool)

    def clock(self, isv, t_s):
        return np.zeros(np.size(isv))


def _model(sat, pos, vel, **kw):
    one = np.zeros(1, int)
    return compute_model(Pairs(epoch=one, isv=one, sat=one), np.zeros(1), np.atleast_2d(pos),
                         np.atleast_2d(vel), np.eye(3)[None], sat, SUN, **kw)


# ----------------------------------------------------------------------------- attitude
def _inclined():
    """Circular orbit at the ascending node, inclination 60°: r = R x̂, v = V(0, cos i, sin i)."""
    inc = np.radians(60.0)
    return np.array([R_LEO, 0.0, 0.0]), V_LEO * np.array([0.0, np.cos(inc), np.sin(inc)])


def test_nominal_axes_hand_built_circular_orbit():
    """Nominal attitude (GRACE SRF, Case et al. 2010): Z = −r̂ (geocentre), X = v̂ for a circular
    orbit, Y = Z × X completing a right-handed frame, i.e. −(orbit normal). At the ascending node
    with i = 60°: Z = (−1, 0, 0), X = (0, ½, √3/2), Y = (−1,0,0) × (0,½,√3/2) = (0, √3/2, −½);
    the orbit normal r × v ∝ (0, −√3/2, ½) = −Y (worked by hand)."""
    pos, vel = _inclined()
    x, y, z = nominal_axes_inertial(pos[None], vel[None])[0]
    h = np.sqrt(3.0) / 2
    np.testing.assert_allclose(z, [-1, 0, 0], atol=1e-15)
    np.testing.assert_allclose(x, [0, 0.5, h], atol=1e-15)
    np.testing.assert_allclose(y, [0, h, -0.5], atol=1e-15)
    np.testing.assert_allclose(np.cross(pos, vel) / np.linalg.norm(np.cross(pos, vel)), -y,
                               atol=1e-15)


def test_nominal_axes_orthonormal_right_handed_for_any_orbit():
    """Any state (eccentric too): rows orthonormal with det +1, Z towards the geocentre, X in
    the orbit plane ⟂ r with a positive velocity component (definition of the nominal frame)."""
    rng = np.random.default_rng(5)
    pos = rng.normal(size=(100, 3)) * 7e6
    vel = rng.normal(size=(100, 3)) * 7.5e3
    axes = nominal_axes_inertial(pos, vel)
    np.testing.assert_allclose(np.einsum("nij,nkj->nik", axes, axes),
                               np.broadcast_to(np.eye(3), (100, 3, 3)), atol=1e-12)
    np.testing.assert_allclose(np.linalg.det(axes), 1.0, atol=1e-12)
    np.testing.assert_allclose(axes[:, 2], -pos / np.linalg.norm(pos, axis=1, keepdims=True),
                               atol=1e-15)
    assert np.all(np.einsum("ni,ni->n", axes[:, 0], vel) > 0)
    np.testing.assert_allclose(np.einsum("ni,ni->n", axes[:, 0], pos), 0.0, atol=1e-6)
    np.testing.assert_allclose(np.einsum("ni,ni->n", axes[:, 1], vel), 0.0, atol=1e-6)


# ------------------------------------------------------------------ LEO antenna offset
@pytest.mark.parametrize("pco,direction", [
    ((0.0, 0.0, 0.45), "zenith"),    # +Z offset: antenna 0.45 m nearer the geocentre
    ((0.1, 0.0, 0.0), "x"),          # +X offset towards a satellite in the +X direction
    ((0.0, 0.1, 0.0), "y"),
])
def test_leo_pco_moves_the_antenna_along_the_body_axis(pco, direction):
    """ANTEX convention (Rothacher & Schmid 2010): phase centre = r_com + Σ PCO_i e_i with the
    body axes e_i. With the inclined orbit of the test above (non-symmetric axes matrix, so a
    transposed rotation is caught): a +Z offset of 0.45 m puts the antenna 0.45 m farther from
    a satellite at the zenith (range +0.45 m); a +X (+Y) offset of 0.1 m towards a satellite
    seen along +X (+Y) shortens the range by 0.1 m."""
    pos, vel = _inclined()
    axes = {"x": np.array([0, 0.5, np.sqrt(3) / 2]), "y": np.array([0, np.sqrt(3) / 2, -0.5])}
    if direction == "zenith":
        sat, expected = _FixedSatellite([R_GPS, 0.0, 0.0]), 0.45
    else:
        sat, expected = _FixedSatellite(pos + 2.0e7 * axes[direction]), -0.1
    base = _model(sat, pos, vel).code_m[0]
    moved = _model(sat, pos, vel, leo_pco_body_m=np.array(pco)).code_m[0]
    assert moved - base == pytest.approx(expected, abs=1e-5)


# ------------------------------------------------- clock, Shapiro, wind-up at the zenith
def _polar(beta=0.0):
    """LEO over the pole moving along (cos β, sin β, 0): the Earth rotation during the light
    time leaves a satellite on the z axis in place, so the geometry is exact."""
    return np.array([0.0, 0.0, R_LEO]), V_LEO * np.array([np.cos(beta), np.sin(beta), 0.0])


def test_model_adds_shapiro_and_relativistic_clock_with_their_signs():
    """Code model = ρ + Shapiro − c (dt_product + Δt_rel) (IS-GPS-200 20.3.3.3.3.1, IERS
    Conventions 2010 eq. 11.17). Satellite at the zenith, radial path: ρ = r2 − r1 and Shapiro
    2GM/c² ln(r2/r1) = 11.984 mm (test_corrections). A satellite velocity v with r·v = r2 v_z
    makes Δt_rel = −2 r2 v_z/c², i.e. the modelled code longer by +2 r2 v_z/c (v_z = 10 m/s:
    +1.7719 m, by hand)."""
    pos, vel = _polar()
    at_rest = _model(_FixedSatellite([0.0, 0.0, R_GPS]), pos, vel)
    shapiro = 2 * GM_EARTH_M3_S2 / C_LIGHT_M_S**2 * np.log(R_GPS / R_LEO)
    assert at_rest.code_m[0] - (R_GPS - R_LEO) == pytest.approx(shapiro, abs=1e-6)
    assert at_rest.code_m[0] - (R_GPS - R_LEO) == pytest.approx(0.011984, abs=2e-6)
    moving = _model(_FixedSatellite([0.0, 0.0, R_GPS], [0.0, 0.0, 10.0]), pos, vel)
    assert moving.code_m[0] - at_rest.code_m[0] == pytest.approx(1.7719, abs=1e-4)
    assert moving.code_m[0] - at_rest.code_m[0] == pytest.approx(
        2 * R_GPS * 10.0 / C_LIGHT_M_S, rel=1e-9)


@pytest.mark.parametrize("alpha", [0.4, -1.0, 2.0])
def test_model_windup_of_a_leo_turning_about_its_boresight(alpha):
    """The LEO antenna looks to the zenith (−Z). Turning the flight direction by +α about the
    radial (up) axis turns the antenna by +α about its boresight towards a satellite at the
    zenith: wind-up −α/2π cycles (derivation in test_corrections), phase model −λ_NL α/2π
    (Kouba 2009 sec. 5.3), the code unchanged."""
    pos, vel0 = _polar(0.3)
    _, vel1 = _polar(0.3 + alpha)
    sat = _FixedSatellite([0.0, 0.0, R_GPS])
    m0 = _model(sat, pos, vel0, nl_wavelength_m=NL)
    m1 = _model(sat, pos, vel1, nl_wavelength_m=NL)
    assert m1.code_m[0] == pytest.approx(m0.code_m[0], abs=1e-9)
    wind0 = (m0.phase_m[0] - m0.code_m[0]) / NL
    wind1 = (m1.phase_m[0] - m1.code_m[0]) / NL
    wrap = lambda x: (x + 0.5) % 1.0 - 0.5  # noqa: E731
    assert wrap(wind1 - wind0 + alpha / (2 * np.pi)) == pytest.approx(0.0, abs=1e-6)

"""Yaw attitude laws of eclipsing GNSS satellites (leopod.gnss.attitude).

Authorities: Kouba (2009, GPS Solut. 13:1, "A simplified yaw-attitude model for eclipsing GPS
satellites": nominal yaw ψ = atan2(−tan β, sin μ), eq. 1, its rate, eq. 2; Block IIR turns at
the maximum rate 0.20 °/s, the turn starting where the nominal rate reaches the maximum, about
sqrt(|β| β₀ − β²) of orbit angle before noon with β₀ = atan(μ̇/R)); Dilssner (2010, Inside GNSS
5(5):59) and the IGS workshop 2010 slides of Dilssner et al. (GPS IIF: noon turns at 0.11 °/s
"if |β| < 4.5°", constant yaw rate through the shadow); European GNSS Service Centre (2017),
Galileo IOV and FOC satellite metadata, sec. 3 (attitude laws); Wang et al. (2018) and Xia et
al. (2019) for BDS-3 CAST and SECM; Montenbruck et al. (2015, ASR 56:1015) for the IGS axes.
"""

import numpy as np
import pytest

from leopod.gnss.attitude import (
    GAL_FOC_PERIOD_S,
    attitude_family,
    gnss_attitude_axes,
    gnss_body_axes,
    model_yaw_rad,
    nominal_yaw_rad,
    nominal_yaw_rate_rad_s,
    orbit_angles,
    turn_half_width_rad,
    yaw_body_axes,
)

MU_DOT_GPS = 2 * np.pi / 43_082.0       # GPS: half a sidereal day [rad/s]
MU_DOT_GAL = 2 * np.pi / 50_680.0       # Galileo: 14 h 04 min 40 s
MU_DOT_BDS = 2 * np.pi / 46_404.0       # BDS-3 MEO: 12 h 53 min 24 s


def _sweep(family, beta_deg, centre, mu_dot, half_deg=40.0, n=160_001):
    """Yaw [rad], time [s] across ±half_deg of orbit angle around ``centre`` (0 midnight, π noon)."""
    mu = centre + np.radians(np.linspace(-half_deg, half_deg, n))
    yaw = model_yaw_rad(family, np.radians(beta_deg), mu, mu_dot)
    return yaw, (mu - centre) / mu_dot, mu


def _rate_deg_s(yaw, t):
    step = (np.diff(yaw) + np.pi) % (2 * np.pi) - np.pi
    return np.degrees(step / np.diff(t))


# --------------------------------------------------------------------------- nominal law
def test_nominal_yaw_kouba_eq1_hand_values():
    """Kouba 2009 eq. 1: ψ = atan2(−tan β, sin μ). At μ = 90° (six hours past midnight),
    ψ = −β; at the noon point (sin μ = 0) ψ = −90° sgn β; for β = 45°, μ = 30°:
    atan2(−1, ½) = −63.4349°."""
    assert np.degrees(nominal_yaw_rad(np.radians(10.0), np.pi / 2)) == pytest.approx(-10.0)
    assert np.degrees(nominal_yaw_rad(np.radians(5.0), np.pi)) == pytest.approx(-90.0)
    assert np.degrees(nominal_yaw_rad(np.radians(45.0), np.radians(30.0))) == pytest.approx(
        -63.43494882, abs=1e-8)


def test_nominal_yaw_rate_is_derivative_and_peaks_at_mu_dot_over_tan_beta():
    """Kouba 2009 eq. 2 is dψ/dt of eq. 1; its peak at noon/midnight is μ̇/|tan β|: for GPS at
    β = 1° that is 0.00836/0.01746 = 0.479 °/s, beyond the 0.2 °/s of IIR (hence the turns)."""
    beta = np.radians(1.0)
    mu = np.radians(np.linspace(100, 260, 32001))
    num = np.gradient(np.unwrap(nominal_yaw_rad(beta, mu)), mu) * MU_DOT_GPS
    np.testing.assert_allclose(nominal_yaw_rate_rad_s(beta, mu, MU_DOT_GPS), num, rtol=2e-3,
                               atol=1e-7)
    peak = abs(np.degrees(nominal_yaw_rate_rad_s(beta, np.pi, MU_DOT_GPS)))
    assert peak == pytest.approx(np.degrees(MU_DOT_GPS) / np.tan(beta))
    assert peak == pytest.approx(0.479, abs=2e-3)


def test_orbit_angles_and_axes_reproduce_yaw_steering():
    """β = asin(ŝ·n̂), μ from midnight (Kouba 2009, sec. 2); the axes rebuilt from the nominal
    yaw are those of the yaw-steering definition (Montenbruck et al. 2015)."""
    rng = np.random.default_rng(3)
    pos = rng.normal(size=(300, 3))
    pos *= 26_560e3 / np.linalg.norm(pos, axis=1, keepdims=True)
    vel = np.cross(rng.normal(size=(300, 3)), pos)
    vel *= 3_874.0 / np.linalg.norm(vel, axis=1, keepdims=True)
    sun = rng.normal(size=(300, 3)) * 1.5e11
    beta, mu, mu_dot = orbit_angles(pos, vel, sun)
    np.testing.assert_allclose(mu_dot, 3_874.0 / 26_560e3, rtol=1e-12)
    axes = yaw_body_axes(pos, vel, nominal_yaw_rad(beta, mu))
    np.testing.assert_allclose(axes, gnss_body_axes(pos, sun), atol=1e-12)
    np.testing.assert_allclose(gnss_attitude_axes(pos, vel, sun, np.full(300, "nominal")),
                               gnss_body_axes(pos, sun), atol=1e-12)


# --------------------------------------------------------------------------- GPS IIR/IIF/III
@pytest.mark.parametrize("rate_deg_s,beta0_deg", [(0.20, 2.39), (0.11, 4.35)])
def test_turn_threshold_beta0(rate_deg_s, beta0_deg):
    """β₀ = atan(μ̇/R) (Kouba 2009): no turn beyond it. IIR 0.20 °/s: 2.39°; IIF 0.11 °/s: 4.35°,
    the "|β| < 4.5°" noon-turn regime that Dilssner et al. (2010) observed for IIF."""
    rate = np.radians(rate_deg_s)
    assert np.degrees(np.arctan(MU_DOT_GPS / rate)) == pytest.approx(beta0_deg, abs=0.01)
    assert np.isfinite(turn_half_width_rad(np.radians(beta0_deg - 0.02), MU_DOT_GPS, rate))
    assert np.isnan(turn_half_width_rad(np.radians(beta0_deg + 0.02), MU_DOT_GPS, rate))
    if rate_deg_s == 0.11:
        assert beta0_deg == pytest.approx(4.5, abs=0.2)


@pytest.mark.parametrize("beta_deg", [0.2, 0.5, 1.0, 1.5, 2.0])
def test_turn_start_matches_kouba_small_angle_formula(beta_deg):
    """Kouba 2009 (and the eclipse model that goes with it): the IIR turn starts
    |β| sqrt(β₀/|β| − 1) = sqrt(|β| β₀ − β²) of orbit angle before noon/midnight; leopod solves
    the rate condition exactly, equal to the small-angle form within 1 %."""
    rate = np.radians(0.20)
    beta0 = np.degrees(np.arctan(MU_DOT_GPS / rate))
    d = np.degrees(turn_half_width_rad(np.radians(beta_deg), MU_DOT_GPS, rate))
    assert d == pytest.approx(np.sqrt(beta_deg * beta0 - beta_deg ** 2), rel=0.01)


@pytest.mark.parametrize("family,rate,centres", [
    ("gps_iir", 0.20, (np.pi, 0.0)), ("gps_iii", 0.20, (np.pi, 0.0)), ("gps_iif", 0.11, (np.pi,))])
@pytest.mark.parametrize("beta_deg", [0.002, 0.8, -1.7])
def test_gps_turns_at_max_rate_continuous_and_complete(family, rate, centres, beta_deg):
    """Kouba 2009: through the noon (IIR, IIF) and midnight (IIR) turns the yaw changes at the
    maximum rate R and never faster, is continuous, and returns to the nominal yaw; the turn
    lasts at most 180°/R (15 min for IIR at β → 0: 900 s; 27.3 min for IIF)."""
    for centre in centres:
        yaw, t, mu = _sweep(family, beta_deg, centre, MU_DOT_GPS)
        rates = np.abs(_rate_deg_s(yaw, t))
        assert rates.max() <= rate * (1 + 1e-6)                           # limit respected
        nominal = nominal_yaw_rad(np.radians(beta_deg), mu)
        off = np.abs((yaw - nominal + np.pi) % (2 * np.pi) - np.pi) > 1e-9
        assert off.any()                                                  # a turn happened
        assert not off[0] and not off[-1]                                 # nominal again
        duration = t[off][-1] - t[off][0]
        assert duration <= 180.0 / rate + 1.0
        if abs(beta_deg) < 0.01:
            assert duration == pytest.approx(180.0 / rate, rel=0.02)      # 900 s / 1636 s
            assert np.median(rates[off[1:]]) == pytest.approx(rate, rel=1e-6)


def test_iif_shadow_constant_rate_to_nominal_exit():
    """Dilssner (2010), Kouba 2009 IIF: through the Earth's shadow the IIF yaws at a constant
    rate from the nominal yaw at entry to the nominal yaw at exit; at β = 1° the cylindrical
    shadow is ±13.85° of orbit angle (r = 26 560 km) and the rate ≈ 0.05 °/s (Dilssner: up to
    0.06 °/s)."""
    yaw, t, mu = _sweep("gps_iif", 1.0, 0.0, MU_DOT_GPS)
    nominal = nominal_yaw_rad(np.radians(1.0), mu)
    off = np.abs((yaw - nominal + np.pi) % (2 * np.pi) - np.pi) > 1e-9
    half = np.degrees(mu[off][-1])
    assert half == pytest.approx(13.85, abs=0.05)
    rates = _rate_deg_s(yaw, t)[off[1:] & off[:-1]]
    np.testing.assert_allclose(rates, rates[0], rtol=1e-6)
    assert 0.04 < abs(rates[0]) < 0.06
    assert np.abs(_rate_deg_s(yaw, t)).max() < 0.11


# --------------------------------------------------------------------------- Galileo
def test_galileo_foc_cosine_law():
    """European GNSS Service Centre (2017), FOC metadata: for |β| < 4.1° within ±10° of
    noon/midnight ψ = 90° sgn ψ₀ + (ψ₀ − 90° sgn ψ₀) cos(2π t/5656 s): at t = 5656/2 s the yaw
    is 180° sgn ψ₀ − ψ₀ (the nominal exit yaw, mirror of the entry); at β → 0 the peak rate is
    90° · 2π/5656 s = 0.09998 °/s; the switch off beyond |β| = 4.1°."""
    beta = np.radians(0.01)
    mu_in = np.pi - np.radians(10.0)
    psi0 = nominal_yaw_rad(beta, mu_in)
    t_half = GAL_FOC_PERIOD_S / 2 - 1e-3             # just inside the window
    yaw_end = model_yaw_rad("galileo_foc", beta, mu_in + MU_DOT_GAL * t_half, MU_DOT_GAL)
    assert np.degrees(yaw_end) == pytest.approx(
        np.degrees(np.sign(psi0) * np.pi - psi0), abs=1e-6)
    yaw, t, _ = _sweep("galileo_foc", 0.01, np.pi, MU_DOT_GAL)
    rates = np.abs(_rate_deg_s(yaw, t))
    assert rates.max() == pytest.approx(90.0 * 2 * np.pi / 5656.0, rel=1e-3)
    for b in (4.0, -4.0):
        # the law ends at t = 2828 s, 10.09° past the point: a step back to the nominal yaw
        # remains (inherent to the published law), 0.2° at |β| = 4°, 0 at β = 0
        yaw, t, mu = _sweep("galileo_foc", b, 0.0, MU_DOT_GAL)
        step = np.abs(np.degrees((np.diff(yaw) + np.pi) % (2 * np.pi) - np.pi))
        assert step.max() < 0.25
        assert np.sort(np.abs(_rate_deg_s(yaw, t)))[-2] < 0.1   # elsewhere smooth
    yaw, t, mu = _sweep("galileo_foc", 4.2, 0.0, MU_DOT_GAL)
    np.testing.assert_allclose(yaw, nominal_yaw_rad(np.radians(4.2), mu), atol=1e-12)


def test_galileo_iov_auxiliary_sun_law():
    """GSC (2017) IOV metadata: for |β| < 2° and |S_x| < sin 15° the yaw follows an auxiliary
    Sun vector whose cross-track component is sin 2° sgn β at noon/midnight: ψ = −90° sgn β
    there, as nominal would be; continuous at the window edges; peak rate at β → 0 bounded
    (μ̇/tan 2° = 0.204 °/s, about the IOV's actuator limit)."""
    assert np.degrees(model_yaw_rad("galileo_iov", np.radians(0.3), np.pi, MU_DOT_GAL)) == \
        pytest.approx(-90.0)
    for b in (0.01, -0.7, 1.9):
        yaw, t, _ = _sweep("galileo_iov", b, np.pi, MU_DOT_GAL)
        rates = np.abs(_rate_deg_s(yaw, t))
        assert rates.max() < np.degrees(MU_DOT_GAL) / np.tan(np.radians(2.0)) * 1.25
    yaw, t, mu = _sweep("galileo_iov", 2.1, 0.0, MU_DOT_GAL)
    np.testing.assert_allclose(yaw, nominal_yaw_rad(np.radians(2.1), mu), atol=1e-12)


# --------------------------------------------------------------------------- BeiDou
def test_bds3_secm_beta_floor_and_cast_linear_turn():
    """Xia et al. (2019), SECM: yaw steering with |β| held at 3° below 3°; Wang et al. (2018),
    CAST: a constant-rate turn between the nominal yaws at ∓6° of orbit angle when |β| < 3°.
    Both stay continuous and slower than the nominal law."""
    yaw, t, mu = _sweep("bds3_secm", 0.5, np.pi, MU_DOT_BDS)
    np.testing.assert_allclose(yaw, nominal_yaw_rad(np.radians(3.0), mu), atol=1e-12)
    yaw, t, mu = _sweep("bds3_cast", -1.0, np.pi, MU_DOT_BDS)
    rates = _rate_deg_s(yaw, t)
    inside = np.abs(np.degrees(mu[1:] - np.pi)) < 5.9
    np.testing.assert_allclose(rates[inside], rates[inside][0], rtol=1e-6)
    assert np.abs(rates).max() < np.degrees(MU_DOT_BDS) / np.tan(np.radians(1.0))
    yaw, t, mu = _sweep("bds3_cast", 3.1, np.pi, MU_DOT_BDS)
    np.testing.assert_allclose(yaw, nominal_yaw_rad(np.radians(3.1), mu), atol=1e-12)


def test_orbit_normal_modes():
    """Guo et al. (2013), Dai et al. (2015): BDS-2 IGSO/MEO orbit-normal (ψ = 0, +X along track)
    for |β| < 4°, yaw steering above; GEO always orbit-normal (Montenbruck et al. 2015)."""
    mu = np.radians(np.linspace(-180, 180, 73))
    assert np.all(model_yaw_rad("bds2", np.radians(3.0), mu, MU_DOT_BDS) == 0.0)
    np.testing.assert_allclose(model_yaw_rad("bds2", np.radians(5.0), mu, MU_DOT_BDS),
                               nominal_yaw_rad(np.radians(5.0), mu))
    assert np.all(model_yaw_rad("orbit_normal", np.radians(40.0), mu, MU_DOT_BDS) == 0.0)


@pytest.mark.parametrize("antenna_type,family", [
    ("BLOCK IIR-M", "gps_iir"), ("BLOCK IIR-B", "gps_iir"), ("BLOCK IIF", "gps_iif"),
    ("BLOCK IIIA", "gps_iii"), ("GALILEO-1", "galileo_iov"), ("GALILEO-2", "galileo_foc"),
    ("BEIDOU-3M-CAST", "bds3_cast"), ("BEIDOU-3M-SECM", "bds3_secm"), ("BEIDOU-3SI-SECM",
    "bds3_secm"), ("BEIDOU-3I", "bds3_cast"), ("BEIDOU-3G-CAST", "orbit_normal"),
    ("BEIDOU-2G", "orbit_normal"), ("BEIDOU-2M", "bds2"), ("BLOCK IIA", "nominal"),
    ("GLONASS-M", "nominal"), ("SIMULATED", "nominal")])
def test_antex_block_types(antenna_type, family):
    """IGS ANTEX satellite antenna types (igs20.atx, ../shared/data/antex/igs20-small.atx)."""
    assert attitude_family(antenna_type) == family


def test_unknown_family_raises():
    with pytest.raises(ValueError, match="unknown GNSS attitude family"):
        model_yaw_rad("gps_iv", 0.0, 0.0, MU_DOT_GPS)

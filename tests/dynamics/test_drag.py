"""Tests of leopod.dynamics.drag: drag formula, partials, Harris–Priester and MSIS densities."""

from __future__ import annotations

import numpy as np
import pytest

from leopod.constants import OMEGA_EARTH_RAD_S
from leopod.dynamics import drag
from leopod.dynamics.drag import (
    HarrisPriesterDensity,
    MsisDensity,
    drag_cannonball,
    drag_plates,
    harris_priester_density,
)
from leopod.dynamics.srp import MacroModel, plate_normals

POS = np.array([6.2e6, 2.1e6, 1.3e6])  # |r| ≈ 6.67e6 m (≈ 300 km height)
VEL = np.array([-2.5e3, 4.0e3, 5.6e3])
SUN = np.array([1.1e11, -8.0e10, -3.5e10])


def _rot(axis: int, angle_rad: float) -> np.ndarray:
    """Frame rotation about a coordinate axis (IERS 2010 sec. 5.1 convention R_i)."""
    c, s = np.cos(angle_rad), np.sin(angle_rad)
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    rot = np.eye(3)
    rot[i, i] = rot[j, j] = c
    rot[i, j], rot[j, i] = s, -s
    return rot


# an arbitrary GCRF → ITRF rotation: Earth angle 40°, pole tilt 1 mrad
ROT = _rot(1, 1e-3) @ _rot(2, np.radians(40.0))


def _jacobian(fun, x, step):
    """Central finite differences of fun (3,) -> (3,) at x."""
    return np.column_stack([(fun(x + step * e) - fun(x - step * e)) / (2 * step)
                            for e in np.eye(3)])


# -------------------------------------------------------------------------- drag formula


def test_cannonball_formula():
    # Analytic (M&G 2000 sec. 3.5.1): r = (7000 km, 0, 0), v = (0, 7.5 km/s, 0):
    # v_r = v − ω × r = (0, 7500 − ω 7e6, 0); a = −½ ρ (C_D A/m) v_r² ŷ
    rho, bc = 3.0e-12, 2.2 * 1.2 / 500.0
    vr = 7500.0 - OMEGA_EARTH_RAD_S * 7.0e6
    acc, _, _, da_ds = drag_cannonball([7.0e6, 0, 0], [0, 7500.0, 0], rho, None, bc)
    np.testing.assert_allclose(acc, [0.0, -0.5 * rho * bc * vr**2, 0.0], rtol=1e-14, atol=0)
    np.testing.assert_allclose(da_ds[:, 0], acc, rtol=1e-15)
    # scale factor: linear
    acc2 = drag_cannonball([7.0e6, 0, 0], [0, 7500.0, 0], rho, None, bc, scale=1.7)[0]
    np.testing.assert_allclose(acc2, 1.7 * acc, rtol=1e-15)
    # a non-rotating atmosphere (ω = 0) sees the full inertial velocity
    acc0 = drag_cannonball([7.0e6, 0, 0], [0, 7500.0, 0], rho, None, bc, omega_rad_s=[0, 0, 0])[0]
    assert acc0[1] == pytest.approx(-0.5 * rho * bc * 7500.0**2, rel=1e-14)


def test_plates_against_cannonball():
    # Analytic: one plate facing the flow is a cannonball with C_D A/m; tilted by θ its
    # projected area is A cos θ; a plate facing away feels nothing; the force stays along v_r.
    vr = VEL - np.cross([0, 0, OMEGA_EARTH_RAD_S], POS)
    e_v = vr / np.linalg.norm(vr)
    other = np.cross(e_v, [0.0, 0.0, 1.0])
    other /= np.linalg.norm(other)
    theta = np.radians(35.0)
    tilted = np.cos(theta) * e_v + np.sin(theta) * other
    model = MacroModel(normal_body=[e_v, tilted, -e_v], area_m2=[1.5, 2.0, 4.0], specular=0.0,
                       diffuse=0.0, drag_coefficient=[2.1, 2.4, 3.0], mass_kg=420.0)
    acc = drag_plates(POS, VEL, 4e-12, None, model.normal_body, model)[0]
    bc = (2.1 * 1.5 + 2.4 * 2.0 * np.cos(theta)) / 420.0
    np.testing.assert_allclose(acc, drag_cannonball(POS, VEL, 4e-12, None, bc)[0], rtol=1e-13)


# ------------------------------------------------------------------------------ partials


@pytest.mark.parametrize("kind", ["cannonball", "plates"])
def test_partials_finite_differences(kind):
    hp = HarrisPriesterDensity()
    box = MacroModel(normal_body=[[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1],
                                  [0, 0, -1]],
                     area_m2=[1.0, 1.2, 2.0, 2.2, 3.0, 3.3], specular=0.0, diffuse=0.0,
                     drag_coefficient=[2.0, 2.1, 2.2, 2.3, 2.4, 2.5], mass_kg=600.0)
    normals = plate_normals(box, np.eye(3), POS, SUN)

    def acc(pos, vel):
        rho, grad = hp(0.0, pos, ROT, SUN)
        if kind == "cannonball":
            return drag_cannonball(pos, vel, rho, grad, 0.006, scale=1.3)
        return drag_plates(pos, vel, rho, grad, normals, box, scale=1.3)

    a0, da_dr, da_dv, da_ds = acc(POS, VEL)
    # Independent: central differences (steps 100 m and 0.1 m/s; the density varies on
    # ~50 km, the set of plates facing the flow does not change)
    fd_r = _jacobian(lambda p: acc(p, VEL)[0], POS, 100.0)
    fd_v = _jacobian(lambda v: acc(POS, v)[0], VEL, 0.1)
    np.testing.assert_allclose(da_dr, fd_r, rtol=0, atol=1e-5 * np.abs(fd_r).max())
    np.testing.assert_allclose(da_dv, fd_v, rtol=0, atol=1e-7 * np.abs(fd_v).max())
    np.testing.assert_allclose(da_ds[:, 0] * 1.3, a0, rtol=1e-15)
    assert np.abs(da_dr).max() > 0.0


# --------------------------------------------------------------------- Harris–Priester


def test_harris_priester_table():
    # M&G (2000) Table 3.8 (mean solar activity, g/km³ = 1e-12 kg/m³): at 400 km
    # ρ_m = 2.249, ρ_M = 7.492; at the apex of the bulge (ψ = 0) ρ = ρ_M, at the antapex ρ_m
    assert harris_priester_density(400e3, 1.0)[0] == pytest.approx(7.492e-12, rel=1e-12)
    assert harris_priester_density(400e3, -1.0)[0] == pytest.approx(2.249e-12, rel=1e-12)
    # exponential interpolation: midway between 400 and 420 km (ρ_m 2.249 → 1.558) the
    # geometric mean
    rho = harris_priester_density(410e3, -1.0)[0]
    assert rho == pytest.approx(np.sqrt(2.249 * 1.558) * 1e-12, rel=1e-12)
    # cos^n(ψ/2) weighting, n = 6: at ψ = 90°, weight (1/2)³
    rho = harris_priester_density(400e3, 0.0, exponent=6.0)[0]
    assert rho == pytest.approx((2.249 + (7.492 - 2.249) / 8) * 1e-12, rel=1e-12)
    assert harris_priester_density(1200e3, 0.3) == (0.0, 0.0, 0.0)
    with pytest.raises(ValueError, match="below 100 km"):
        harris_priester_density(90e3, 0.0)


def test_harris_priester_derivatives():
    # Independent: central differences of the table interpolation and of the full model
    h, c = 433.0e3, 0.37
    _, drho_dh, drho_dc = harris_priester_density(h, c)
    assert drho_dh == pytest.approx((harris_priester_density(h + 10, c)[0]
                                     - harris_priester_density(h - 10, c)[0]) / 20, rel=1e-6)
    assert drho_dc == pytest.approx((harris_priester_density(h, c + 1e-5)[0]
                                     - harris_priester_density(h, c - 1e-5)[0]) / 2e-5, rel=1e-6)
    hp = HarrisPriesterDensity(exponent=2.0)
    grad = hp(0.0, POS, ROT, SUN)[1]
    fd = _jacobian(lambda p: np.array([hp(0.0, p, ROT, SUN)[0]] * 3), POS, 50.0)[0]
    np.testing.assert_allclose(grad, fd, rtol=0, atol=1e-5 * np.abs(fd).max())


def test_harris_priester_bulge_follows_sun():
    # The apex lags the Sun by 30° in right ascension (M&G sec. 3.5.2): at 400 km the
    # density is largest 30° east of the subsolar direction, smallest opposite.
    hp = HarrisPriesterDensity()
    r = 6378.137e3 + 400e3  # on the equator (pole of ROT ~ GCRF pole)
    sun = np.array([1.5e11, 0.0, 0.0])
    angles = np.radians(np.arange(0.0, 360.0, 5.0))
    rho = [hp(0.0, r * np.array([np.cos(a), np.sin(a), 0.0]), np.eye(3), sun)[0]
           for a in angles]
    assert np.degrees(angles[np.argmax(rho)]) == pytest.approx(30.0)
    assert np.degrees(angles[np.argmin(rho)]) == pytest.approx(210.0)


# ----------------------------------------------------------------------------------- MSIS


def _synthetic_space_weather(f107=150.0, ap=15.0):
    """Constant solar and geomagnetic activity over a few days (Dataset of the reader)."""
    import xarray as xr

    dates = np.arange("2008-06-01", "2008-06-11", dtype="datetime64[D]").astype("datetime64[ns]")
    n = dates.size
    daily = {name: (("date",), np.full(n, value)) for name, value in (
        ("f107_obs_sfu", f107), ("f107_obs_center81_sfu", f107), ("ap_daily", ap))}
    return xr.Dataset({**daily, "ap": (("date", "slot"), np.full((n, 8), ap)),
                       "f107_data_type": (("date",), np.full(n, "OBS"))}, coords={"date": dates})


@pytest.mark.parametrize("version", [0, 2.1])
def test_msis_density_moderate_activity(version):
    # CIRA-2012 / NRLMSISE-00 tables: at 400 km and moderate activity (F10.7 = F10.7a = 150,
    # Ap = 15) the density is a few 1e-12 kg/m³ (day-night and latitude variation included):
    # every point of a latitude x local-time grid lies in 1e-12 .. 1e-11 kg/m³
    model = MsisDensity(_synthetic_space_weather(), version=version)
    lon, lat = np.meshgrid(np.arange(-180.0, 180.0, 30.0), np.arange(-80.0, 81.0, 20.0))
    rho = model.density_geodetic(np.datetime64("2008-06-05T12:00"), lon.ravel(), lat.ravel(),
                                 np.full(lon.size, 400e3))
    assert np.all((rho > 1e-12) & (rho < 1e-11))
    assert rho.max() / rho.min() > 1.5  # a diurnal bulge


def test_msis_gradient_is_vertical_log_derivative():
    # Independent: ρ at ±2.5 and ±5 km along the geodetic vertical (Richardson-extrapolated
    # central difference, error O(h⁴)); the gradient points down along the vertical with its
    # magnitude (horizontal gradients neglected by design; the ±1 km difference of the model
    # has a truncation error (1 km / H)²/6 ≈ 1e-4 for a scale height H ≈ 40 km)
    model = MsisDensity(_synthetic_space_weather())
    # UTC -> TT seconds since J2000: TAI − UTC = 33 s in 2008 (IERS Bulletin C)
    t_tt = (np.datetime64("2008-06-05T12:00:33") - np.datetime64("2000-01-01T12:00")) / \
        np.timedelta64(1, "s") + 32.184
    rho, grad = model(t_tt, POS, ROT)
    lon, lat, h, up_ef = drag._geodetic_ef(ROT @ POS)
    lo = model.density_geodetic(np.datetime64("2008-06-05T12:00"), np.degrees(lon),
                                np.degrees(lat), [h - 5e3, h - 2.5e3, h, h + 2.5e3, h + 5e3])
    assert rho == pytest.approx(lo[2], rel=1e-6)
    d5, d25 = (lo[4] - lo[0]) / 10e3, (lo[3] - lo[1]) / 5e3
    np.testing.assert_allclose(grad, (4 * d25 - d5) / 3 * (up_ef @ ROT), rtol=3e-4)
    assert grad @ POS < 0.0


def test_tt_to_utc():
    # IERS Bulletin C: TAI − UTC = 33 s from 2006-01-01 to 2008-12-31; TT − TAI = 32.184 s
    t_tt = (np.datetime64("2007-03-21T12:01:05.184") - np.datetime64("2000-01-01T12:00")) / \
        np.timedelta64(1, "s")
    assert drag._tt_to_utc(t_tt, {}) == np.datetime64("2007-03-21T12:00:00", "ns")


@pytest.mark.shared
@pytest.mark.filterwarnings("ignore:There is data that was either interpolated")
def test_msis_density_matches_pymsis_own_indices(shared, monkeypatch):
    # Independent: pymsis reads the same file itself (pymsis.utils, pointed at ../shared)
    from pymsis import calculate, utils

    from leopod.io.space_weather import read_space_weather

    path = shared / "models" / "space_weather" / "SW-All.csv"
    monkeypatch.setattr(utils._SPACE_WEATHER, "path", path)
    monkeypatch.setattr(utils._SPACE_WEATHER, "data", None)
    model = MsisDensity(read_space_weather(path), version=0)
    t = np.datetime64("2007-03-21T13:30")
    lon, lat, alt = np.array([10.0, -120.0]), np.array([45.0, -30.0]), np.array([470e3, 480e3])
    ours = model.density_geodetic(t, lon, lat, alt)
    ref = calculate(np.full(2, t), lon, lat, alt / 1e3, version=0, geomagnetic_activity=-1)
    np.testing.assert_allclose(ours, ref[:, 0], rtol=1e-6)
    # GRACE altitude at solar minimum (F10.7 ≈ 73): a few 1e-13 kg/m³
    assert np.all((ours > 1e-14) & (ours < 1e-12))

"""Tidal corrections to the geopotential (IERS Conventions 2010, chapter 6).

Authorities:
* analytic cases of eq. (6.6)/(6.7) (a body on the z axis) and a brute-force spherical-harmonic
  projection of the tide-generating potential (scipy's Legendre functions, the addition
  theorem is not used by the test);
* the permanent tide of eq. (6.14), A0 H0 k20, against the 18.6-year mean of step 1 computed
  from the DE421 Sun and Moon;
* the Cartwright & Edden (1973) tidal amplitudes H_f (K1 0.36878, its nodal line 165.565
  0.05001, M2 0.63192, 255.545 −0.02358, Mf −0.06663, 075.565 −0.02762, 075.575 −0.00258 m;
  the K1 values agree with ip/(A1 δk^R) of Table 6.5a to 0.1 %): the K1, M2, Mf lines of
  step 1 (computed from the ephemeris) must have the amplitude and phase that the Doodson
  arguments predict;
* the wave frequencies printed in Tables 6.5a-c (deg/h) and the consistency of their Doodson
  and Delaunay columns;
* the δk_f columns of Table 6.5a against its ip/op amplitudes (K1 line of step 2 / step 1),
  i.e. the effective K1 Love number near the free-core-nutation resonance, 0.2983 − 0.0408;
* eq. (6.22), (6.24) and the secular pole typed from the Conventions, and the monthly solid
  pole tide of the ITSG-Grace2018 background models (TU Graz, file
  model_poleTide_2015-12.gfc: C̄21 = −6.2775e-12, S̄21 = −1.64617e-10) from the IERS 20 C04
  pole of December 2015;
* ocean tides: eq. (6.15) in complex form evaluated independently; the global equilibrium
  tide (load Love number k'2 of Love_load_cm.dat) for the 18.6-year line Om1; the known
  M2 (2,2) phase lag of the ocean tide (~130°, dissipative: 0° < lag < 180°).
"""

from __future__ import annotations

import erfa
import numpy as np
import pytest
from scipy.special import eval_legendre, lpmv, roots_legendre

from leopod.astro.arguments import doodson_arguments, fundamental_arguments
from leopod.astro.ephemeris import Ephemeris
from leopod.constants import GM_EARTH_M3_S2, R_EARTH_EQUATOR_M
from leopod.dynamics.ocean_tides import OceanTides
from leopod.dynamics.pole_tides import (
    ocean_pole_tide,
    secular_pole_rad,
    solid_pole_tide,
    wobble_rad,
)
from leopod.dynamics.solid_tides import (
    STEP2_TABLES,
    permanent_tide_c20,
    solid_earth_tides,
    solid_tide_step1,
    solid_tide_step2,
)
from leopod.dynamics.third_body import GM_MOON_M3_S2, GM_SUN_M3_S2
from leopod.dynamics.tides import TideModel
from leopod.io.fes import doodson_multipliers, read_fes_cnm

MAS = np.pi / 180 / 3600e3
ARCSEC = MAS * 1e3
YEAR_S = 365.25 * 86400.0
A0 = 1 / (R_EARTH_EQUATOR_M * np.sqrt(4 * np.pi))     # IERS 2010 eq. (6.8): 4.4228e-8 /m
A1 = -1 / (R_EARTH_EQUATOR_M * np.sqrt(8 * np.pi))    # A_m = (−1)^m/(R_e √(8π)), 3.1274e-8
A2 = -A1
Q_MOON = GM_MOON_M3_S2 / GM_EARTH_M3_S2
Q_SUN = GM_SUN_M3_S2 / GM_EARTH_M3_S2


def _earth_fixed_year(t0_s: float, days: float, step_h: float):
    """Times, GMST and Earth-fixed Sun/Moon from DE421 and ERFA (UT1 = TT − 65 s, xp = yp = 0).

    Independent of leopod.frames: IAU 2006/2000A ``c2t06a`` and ``gmst06`` from ERFA.
    """
    t = t0_s + np.arange(0.0, days * 86400.0, step_h * 3600.0)
    jd1 = 2451545.0 + np.floor(t / 86400.0)
    jd2 = (t - np.floor(t / 86400.0) * 86400.0) / 86400.0
    ut2 = jd2 - 65.0 / 86400.0
    c2t = erfa.c2t06a(jd1, jd2, jd1, ut2, 0.0, 0.0)
    eph = Ephemeris()
    sun = np.einsum("nij,nj->ni", c2t, eph.sun_m(t))
    moon = np.einsum("nij,nj->ni", c2t, eph.moon_m(t))
    return t, erfa.gmst06(jd1, ut2, jd1, jd2), sun, moon


@pytest.fixture(scope="module")
def year_2007():
    """One year (2007) at 3-h steps: 2922 epochs."""
    return _earth_fixed_year(7 * YEAR_S, 365.25, 3.0)


def _line(z: np.ndarray, theta: np.ndarray) -> complex:
    """Complex amplitude of the line e^{iθ} in the series z (least-squares for many cycles)."""
    return complex(np.mean(z * np.exp(-1j * theta)))


# ------------------------------------------------------------------------------ step 1


def test_step1_bodies_on_the_z_axis():
    # eq. (6.6)/(6.7) with Φ = ±90°: P̄n0(±1) = (±1)^n √(2n+1), all m > 0 terms vanish
    r_moon, r_sun = 3.844e8, 1.496e11
    moon = np.array([[0.0, 0.0, r_moon]])
    sun = np.array([[0.0, 0.0, -r_sun]])
    dc, ds = solid_tide_step1(sun, moon)
    deg2 = Q_MOON * (R_EARTH_EQUATOR_M / r_moon) ** 3 + Q_SUN * (R_EARTH_EQUATOR_M / r_sun) ** 3
    deg3 = Q_MOON * (R_EARTH_EQUATOR_M / r_moon) ** 4 - Q_SUN * (R_EARTH_EQUATOR_M / r_sun) ** 4
    assert dc[0, 2, 0] == pytest.approx(0.30190 / 5 * deg2 * np.sqrt(5), rel=1e-12)
    assert dc[0, 3, 0] == pytest.approx(0.093 / 7 * deg3 * np.sqrt(7), rel=1e-12)
    assert dc[0, 4, 0] == pytest.approx(-0.00089 / 5 * deg2 * np.sqrt(5), rel=1e-12)
    mask = np.ones((5, 5), bool)
    mask[2:, 0] = False
    assert np.abs(dc[0][mask]).max() < 1e-30 and np.abs(ds[0]).max() < 1e-30
    assert 1e-8 < dc[0, 2, 0] < 3e-8                     # magnitude ~1e-8 (brief)


def _projected(pos: np.ndarray, q: float, n: int) -> np.ndarray:
    """c̄nm − i s̄nm of the degree-n tide potential of one body by Gauss-Legendre quadrature.

    V_n(φ, λ)/(GM_E/R) = q (R/r)^(n+1) P_n(cos ψ), projected on P̄nm(sin φ) (cos mλ, sin mλ)
    / 4π; P̄nm from scipy's lpmv without the Condon-Shortley phase.
    """
    x, w = roots_legendre(12)
    lam = np.arange(24) * 2 * np.pi / 24
    xx, ll = np.meshgrid(x, lam, indexing="ij")
    cphi = np.sqrt(1 - xx**2)
    unit = np.stack([cphi * np.cos(ll), cphi * np.sin(ll), xx], axis=-1)
    r = np.linalg.norm(pos)
    v = q * (R_EARTH_EQUATOR_M / r) ** (n + 1) * eval_legendre(n, unit @ pos / r)
    out = np.zeros(n + 1, complex)
    for m in range(n + 1):
        norm = np.sqrt((2 - (m == 0)) * (2 * n + 1) * np.exp(
            np.sum(np.log(np.arange(1, n - m + 1))) - np.sum(np.log(np.arange(1, n + m + 1)))))
        pbar = (-1) ** m * lpmv(m, n, xx) * norm
        weights = w[:, None] * (2 * np.pi / 24) / (4 * np.pi)
        c = np.sum(weights * v * pbar * np.cos(m * ll))
        s = np.sum(weights * v * pbar * np.sin(m * ll))
        out[m] = c - 1j * s
    return out


def test_step1_against_brute_force_projection_of_the_tide_potential():
    moon = np.array([2.1e8, -2.9e8, 1.2e8])
    sun = np.array([-0.9e11, 1.1e11, 0.5e11])
    dc, ds = solid_tide_step1(sun[None], moon[None])
    love = {2: (0.30190 - 0.0j, 0.29830 - 0.00144j, 0.30102 - 0.00130j),
            3: (0.093, 0.093, 0.093, 0.094)}
    k_plus = (-0.00089, -0.00080, -0.00057)
    for n in (2, 3):
        proj = _projected(moon, Q_MOON, n) + _projected(sun, Q_SUN, n)
        for m in range(n + 1):
            expect = love[n][m] * proj[m]            # IERS (6.6): ΔC̄ − iΔS̄ = k × (c̄ − is̄)
            assert dc[0, n, m] == pytest.approx(expect.real, abs=1e-22)
            assert ds[0, n, m] == pytest.approx(-expect.imag, abs=1e-22)
            if n == 2:                               # (6.7): degree 4 from the degree-2 tide
                assert dc[0, 4, m] == pytest.approx(k_plus[m] * proj[m].real, abs=1e-22)
                assert ds[0, 4, m] == pytest.approx(-k_plus[m] * proj[m].imag, abs=1e-22)
    assert np.all(ds[0, :, 0] == 0.0)


def test_permanent_tide_is_the_18_6_year_mean_of_step1():
    # eq. (6.14): A0 H0 k20 = 4.4228e-8 × (−0.31460) × 0.30190
    perm = permanent_tide_c20()
    assert A0 == pytest.approx(4.4228e-8, rel=2e-5)
    assert perm == pytest.approx(4.4228e-8 * -0.31460 * 0.30190, rel=2e-5)
    # mean over one nodal period (18.6 yr) of step 1 + step 2, sampled every 0.9137 d
    # (incommensurate with the lunar month); only z (CIP axis) matters for m = 0
    t = np.arange(-9.3 * YEAR_S, 9.3 * YEAR_S, 0.9137 * 86400.0)
    jd1 = 2451545.0 + np.floor(t / 86400.0)
    npb = erfa.pnm06a(jd1, (t - np.floor(t / 86400.0) * 86400.0) / 86400.0)
    eph = Ephemeris()
    sun = np.einsum("nij,nj->ni", npb, eph.sun_m(t))
    moon = np.einsum("nij,nj->ni", npb, eph.moon_m(t))
    gmst = np.zeros_like(t)                      # irrelevant for m = 0
    dc, _ = solid_earth_tides(t, gmst, sun, moon, tide_system="tide_free")
    assert dc[:, 2, 0].mean() == pytest.approx(perm, rel=2e-3)
    dc_zero, _ = solid_earth_tides(t, gmst, sun, moon, tide_system="zero_tide")
    assert abs(dc_zero[:, 2, 0].mean()) < 1e-11      # zero-tide: no permanent part added
    np.testing.assert_allclose(dc_zero[:, 2, 0] - dc[:, 2, 0], -perm, rtol=1e-12)


def test_step1_tidal_lines_match_the_doodson_arguments(year_2007):
    # step 1 from the ephemeris against k × A_m × H_f e^{iθ_f} of the main waves (and their
    # 18.6-year nodal lines) with θ_f from doodson_arguments: checks τ = θ_g + π − s, the
    # Delaunay-to-Doodson relations and the sign conventions of (6.6) and (6.8a-c)
    t, gmst, sun, moon = year_2007
    dc, ds = solid_tide_step1(sun, moon)
    beta = doodson_arguments(t, gmst)
    node = beta[:, 4]                                  # N'
    k21, k22 = 0.29830 - 0.00144j, 0.30102 - 0.00130j
    # K1 (165.555) in ΔC̄21 − iΔS̄21 = −i Σ k21 A1 H_f e^{iθ_f} (form of eq. 6.8b)
    k1 = _line(dc[:, 2, 1] - 1j * ds[:, 2, 1], beta @ doodson_multipliers("165.555"))
    expect = -1j * k21 * A1 * (0.36878 + 0.05001 * np.mean(np.exp(1j * node)))
    assert abs(k1 - expect) < 0.03 * abs(expect)
    # M2 (255.555) in ΔC̄22 − iΔS̄22 = Σ k22 A2 H_f e^{iθ_f} (form of eq. 6.8c)
    m2 = _line(dc[:, 2, 2] - 1j * ds[:, 2, 2], beta @ doodson_multipliers("255.555"))
    expect = k22 * A2 * (0.63192 - 0.02358 * np.mean(np.exp(-1j * node)))
    assert abs(m2 - expect) < 0.005 * abs(expect)
    # Mf (075.555) in ΔC̄20 = Re Σ k20 A0 H_f e^{iθ_f} (form of eq. 6.8a)
    zonal = dc[:, 2, 0] - dc[:, 2, 0].mean()             # the permanent tide would leak
    mf = 2 * _line(zonal, beta @ doodson_multipliers("075.555"))
    expect = 0.30190 * A0 * (-0.06663 - 0.02762 * np.mean(np.exp(1j * node))
                             - 0.00258 * np.mean(np.exp(2j * node)))
    assert abs(mf - expect) < 0.04 * abs(expect)     # leakage of near lines over 1 year


# ------------------------------------------------------------------------------ step 2


def test_step2_tables_doodson_and_delaunay_columns_agree():
    # θ_f = n·β (Doodson number) = m(θ_g + π) − N·F (Delaunay columns), every row of 6.5a-c
    t = np.array([-3.1e8, 2.2e8, 7.3e8])
    gmst = np.array([0.3, 2.9, 5.1])
    beta = doodson_arguments(t, gmst)
    fund = fundamental_arguments(t)
    rows = 0
    for m, table in STEP2_TABLES.items():
        for number, delaunay in zip(table["doodson"], table["delaunay"]):
            mult = doodson_multipliers(number)
            assert mult[0] == m
            diff = beta @ mult - (m * (gmst + np.pi) - fund @ delaunay)
            np.testing.assert_allclose(np.angle(np.exp(1j * diff)), 0.0, atol=1e-9)
            rows += 1
    assert rows == 48 + 21 + 2


@pytest.mark.parametrize("number, deg_per_hour", [
    ("165.555", 15.04107), ("145.555", 13.94303), ("163.555", 14.95893),  # K1 O1 P1, 6.5a
    ("255.555", 28.98410), ("245.655", 28.43973),                           # M2 N2, 6.5c
    ("075.555", 1.09804), ("065.455", 0.54438), ("055.565", 0.00221),      # Mf Mm, 6.5b
])
def test_doodson_argument_rates_match_the_tabulated_frequencies(number, deg_per_hour):
    t = np.array([2.4e8, 2.4e8 + 86400.0])
    jd2 = t / 86400.0
    gmst = erfa.gmst06(2451545.0, jd2, 2451545.0, jd2)
    gmst[1] += 2 * np.pi                    # unwrapped: one sidereal turn more in a solar day
    theta = doodson_arguments(t, gmst) @ doodson_multipliers(number)
    assert np.degrees(theta[1] - theta[0]) / 24.0 == pytest.approx(deg_per_hour, abs=2e-5)


def test_step2_is_the_complex_form_of_eq_6_8():
    t = np.array([1.23e8, 4.56e8])
    gmst = np.array([1.0, 4.0])
    dc, ds = solid_tide_step2(t, gmst)
    fund = fundamental_arguments(t)
    sums = {}
    for m, table in STEP2_TABLES.items():
        theta = m * (gmst[:, None] + np.pi) - fund @ table["delaunay"].T
        sums[m] = np.exp(1j * theta) @ (table["ip"] + 1j * table["op"])
    np.testing.assert_allclose(dc[:, 2, 0], sums[0].real, atol=1e-24)          # (6.8a)
    np.testing.assert_allclose(dc[:, 2, 1] - 1j * ds[:, 2, 1], -1j * sums[1], atol=1e-24)
    np.testing.assert_allclose(dc[:, 2, 2] - 1j * ds[:, 2, 2], sums[2], atol=1e-24)
    assert np.all(ds[:, 2, 0] == 0) and np.all(dc[:, 3:] == 0) and np.all(dc[:, :2] == 0)


def test_step2_k1_line_is_delta_k_over_k_of_step1(year_2007):
    # Table 6.5a, K1: δk_f = (−4084 + 262 i) 1e-5 relative to k21 = 0.29830 − 0.00144 i; the K1
    # line of step 2 is δk_f/k21 times that of step 1 (ip = A1 δk^R H, op = A1 δk^I H), and
    # the effective K1 Love number near the free-core-nutation resonance is 0.2575
    t, gmst, sun, moon = year_2007
    dc1, ds1 = solid_tide_step1(sun, moon)
    dc2, ds2 = solid_tide_step2(t, gmst)
    theta = doodson_arguments(t, gmst) @ doodson_multipliers("165.555")
    step1 = _line(dc1[:, 2, 1] - 1j * ds1[:, 2, 1], theta)
    step2 = _line(dc2[:, 2, 1] - 1j * ds2[:, 2, 1], theta)
    k21 = 0.29830 - 0.00144j
    assert abs(step2 / step1 - (-0.04084 + 0.00262j) / k21) < 0.004
    assert (k21 * (1 + step2 / step1)).real == pytest.approx(0.2575, abs=0.002)


def test_solid_earth_tides_rejects_unknown_tide_systems():
    with pytest.raises(ValueError, match="mean_tide"):
        solid_earth_tides([0.0], [0.0], [[1e11, 0, 0]], [[4e8, 0, 0]], tide_system="mean_tide")


# ------------------------------------------------------------------------------ pole tides


def test_secular_pole():
    # IERS 2010 sec. 7.1.4 (2018): xs = 55.0 + 1.677 (t − 2000), ys = 320.5 + 3.460 (t − 2000)
    xs, ys = secular_pole_rad(np.array([0.0, 10 * YEAR_S, -5 * YEAR_S]))
    np.testing.assert_allclose(xs / MAS, [55.0, 71.77, 46.615], atol=1e-9)
    np.testing.assert_allclose(ys / MAS, [320.5, 355.1, 303.2], atol=1e-9)


def test_pole_tide_equations():
    t = np.array([10 * YEAR_S])
    xs, ys = secular_pole_rad(t)
    xp, yp = xs + 0.1 * ARCSEC, ys - 0.2 * ARCSEC      # m1 = 0.1", m2 = 0.2"
    m1, m2 = wobble_rad(xp, yp, t)
    np.testing.assert_allclose([m1[0] / ARCSEC, m2[0] / ARCSEC], [0.1, 0.2], rtol=1e-12)
    c21, s21 = solid_pole_tide(xp, yp, t)                     # eq. (6.22)
    assert c21[0] == pytest.approx(-1.333e-9 * (0.1 + 0.0115 * 0.2), rel=1e-12)
    assert s21[0] == pytest.approx(-1.333e-9 * (0.2 - 0.0115 * 0.1), rel=1e-12)
    c21, s21 = ocean_pole_tide(xp, yp, t)                     # eq. (6.24), n = 2
    assert c21[0] == pytest.approx(-2.1778e-10 * (0.1 - 0.01724 * 0.2), rel=1e-12)
    assert s21[0] == pytest.approx(-1.7232e-10 * (0.2 - 0.03365 * 0.1), rel=1e-12)


def test_solid_pole_tide_against_itsg_grace2018_monthly_mean():
    from astropy_iers_data import IERS_B_FILE

    eop = np.loadtxt(IERS_B_FILE, comments="#", usecols=(0, 1, 4, 5, 6))
    month = eop[(eop[:, 0] == 2015) & (eop[:, 1] == 12)]
    t = (month[:, 2] + 0.5 - 51544.5) * 86400.0            # noon of each day, TT ≈ UTC here
    c21, s21 = solid_pole_tide(month[:, 3] * ARCSEC, month[:, 4] * ARCSEC, t)
    # 2e-13 ≈ 0.15 mas of pole: different C04 release and averaging
    assert c21.mean() == pytest.approx(-6.277524694764e-12, abs=3e-13)
    assert s21.mean() == pytest.approx(-1.646169415216e-10, abs=3e-13)


# ------------------------------------------------------------------------------ ocean tides


@pytest.fixture(scope="module")
def fes(shared):
    return read_fes_cnm(shared / "models" / "ocean_tides" / "fes2004_Cnm-Snm.dat",
                        max_degree=30)


@pytest.mark.shared
def test_ocean_tides_are_the_complex_sum_of_eq_6_15(fes):
    model = OceanTides(fes, max_degree=8)
    t = np.array([2.2e8, 2.2e8 + 5400.0, 6.1e8])
    gmst = np.array([0.7, 2.1, 5.9])
    dc, ds = model.coefficients(t, gmst)
    assert dc.shape == ds.shape == (3, 9, 9)
    beta = doodson_arguments(t, gmst)
    expect = np.zeros((3, 9, 9), complex)
    for wave in fes.wave.values:
        theta = beta @ fes.doodson_multipliers.sel(wave=wave).values
        w = fes.sel(wave=wave, n=slice(0, 8), m=slice(0, 8))
        plus = (w.C_plus - 1j * w.S_plus).values
        minus = (w.C_minus + 1j * w.S_minus).values
        expect += (plus[None] * np.exp(1j * theta)[:, None, None]
                   + minus[None] * np.exp(-1j * theta)[:, None, None])
    np.testing.assert_allclose(dc, expect.real, atol=1e-20)
    np.testing.assert_allclose(ds[:, :, 1:], -expect.imag[:, :, 1:], atol=1e-20)
    assert np.all(ds[:, :, 0] == 0.0)                       # S̄n0 do not exist
    # magnitudes (brief): degree 2 ocean tides 1e-10 to 1e-9
    assert 1e-10 < np.abs(dc[:, 2, :3]).max() < 3e-9


@pytest.mark.shared
def test_ocean_tide_selection_and_truncation(fes):
    t, gmst = np.array([3.3e8]), np.array([1.2])
    full = OceanTides(fes, max_degree=30)
    m2 = OceanTides(fes, max_degree=30, waves=["M2"])
    rest = OceanTides(fes, max_degree=30, waves=[w for w in fes.wave.values if w != "M2"])
    np.testing.assert_allclose(m2.coefficients(t, gmst)[0] + rest.coefficients(t, gmst)[0],
                               full.coefficients(t, gmst)[0], atol=1e-22)
    low = OceanTides(fes, max_degree=4)
    # truncation leaves the low-degree coefficients unchanged (analytic), up to the rounding
    # of matrix products whose BLAS kernel depends on the array shapes (1 ulp seen)
    np.testing.assert_allclose(low.coefficients(t, gmst)[1],
                               full.coefficients(t, gmst)[1][:, :5, :5], rtol=1e-14, atol=0)
    with pytest.raises(ValueError, match="XX"):
        OceanTides(fes, waves=["M2", "XX"])


@pytest.mark.shared
def test_ocean_m2_tide_lags_the_potential(fes):
    # ΔC̄22 − iΔS̄22 (prograde) = |A| e^{i(θ − δ)}: δ = atan2(S⁺, C⁺) is the phase lag of the
    # ocean's degree-2 M2 bulge behind the potential (A2 H > 0); about 130° in tide models
    # from altimetry (e.g. Ray, Eanes & Lemoine 2001, Geophys. J. Int. 144), and in
    # (0°, 180°) because tidal friction dissipates energy (the lunar orbit recedes)
    w = fes.sel(wave="M2", n=2, m=2)
    lag = np.degrees(np.arctan2(w.S_plus.item(), w.C_plus.item()))
    assert 120.0 < lag < 140.0
    assert np.hypot(w.S_plus.item(), w.C_plus.item()) == pytest.approx(6.1e-10, rel=0.02)


@pytest.mark.shared
def test_om1_is_the_equilibrium_tide_with_load_love_number(fes, shared):
    # Global equilibrium ocean tide of the 18.6-year line 055.565 (H = 0.02793 m, Cartwright &
    # Edden 1973): ΔC̄20 = (4πGρ_w/g_e)(1 + k'2)/5 γ2 H/√(4π) (IERS 2010 eq. 6.21 with the
    # equilibrium height γ2 H Ȳ20/√(4π)), γ2 = 1 + k2 − h2 = 1 + 0.29525 − 0.6078 (elastic),
    # ρ_w = 1025 kg/m³, G = 6.67428e-11, g_e = 9.7803278 m/s² (IERS Table 1.1); k'2 from the
    # load Love numbers of the Conventions' file. Without (1 + k'2) the value would be 44 %
    # larger. The file's sign is opposite to this equilibrium (the Conventions flag the phase
    # of these lines as under discussion), so only the magnitude is tested.
    text = (shared / "models" / "ocean_tides" / "Love_load_cm.dat").read_text("utf-8")
    row = next(line.split() for line in text.splitlines() if line.split()[:1] == ["2"])
    k2_load = float(row[3].replace("D", "E"))          # n, h', l', k'
    assert k2_load == pytest.approx(-0.30577, abs=1e-5)
    gamma2 = 1 + 0.29525 - 0.6078
    expect = (4 * np.pi * 6.67428e-11 * 1025 / 9.7803278 * (1 + k2_load) / 5 * gamma2
              * 0.02793 / np.sqrt(4 * np.pi))
    om1 = fes.sel(wave="Om1", n=2, m=0)
    assert abs(om1.C_plus.item()) == pytest.approx(expect, rel=0.01)
    assert om1.S_plus.item() == 0.0


# ------------------------------------------------------------------------------ all together


@pytest.mark.shared
def test_tide_model_sums_the_components(fes, year_2007):
    t, gmst, sun, moon = (x[:40] for x in year_2007)
    xp, yp = np.full(40, 0.05 * ARCSEC), np.full(40, 0.38 * ARCSEC)
    ocean = OceanTides(fes, max_degree=12)
    model = TideModel("zero_tide", ocean=ocean)
    assert model.max_degree == 12
    dc, ds = model.coefficients(t, gmst, sun, moon, xp, yp)
    sc, ss = solid_earth_tides(t, gmst, sun, moon, tide_system="zero_tide")
    oc, os_ = ocean.coefficients(t, gmst)
    pc = sum(f(xp, yp, t)[0] for f in (solid_pole_tide, ocean_pole_tide))
    ps = sum(f(xp, yp, t)[1] for f in (solid_pole_tide, ocean_pole_tide))
    expect_c, expect_s = oc.copy(), os_.copy()
    expect_c[:, :5, :5] += sc
    expect_s[:, :5, :5] += ss
    expect_c[:, 2, 1] += pc
    expect_s[:, 2, 1] += ps
    np.testing.assert_allclose(dc, expect_c, atol=1e-22)
    np.testing.assert_allclose(ds, expect_s, atol=1e-22)
    tide_free = TideModel("tide_free", ocean=ocean).coefficients(t, gmst, sun, moon, xp, yp)
    np.testing.assert_allclose(tide_free[0][:, 2, 0] - dc[:, 2, 0], permanent_tide_c20(),
                               rtol=1e-9)
    solid_only = TideModel("tide_free", solid_pole=False, ocean_pole=False)
    assert solid_only.max_degree == 4
    with pytest.raises(ValueError, match="unknown"):
        TideModel("unknown")

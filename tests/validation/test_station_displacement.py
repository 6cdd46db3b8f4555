"""Tests of the station displacements: solid Earth tide (IERS DEHANTTIDEINEL test cases), pole
tide (IERS 2010 eq. 7.26 and its potential), ocean loading (IERS ARG2 test case, analytic
single-constituent cases) and the BLQ reader."""

from __future__ import annotations

import erfa
import numpy as np
import pytest

import leopod.validation.station_displacement as sd
from leopod.astro.ephemeris import Ephemeris
from leopod.constants import OMEGA_EARTH_RAD_S, R_EARTH_EQUATOR_M
from leopod.frames.earth_rotation import gcrf_to_itrf
from leopod.io._text import FormatError
from leopod.io.blq import BLQ_CONSTITUENTS, read_blq
from leopod.time.eop import default_earth_orientation, jd_ut1
from leopod.time.scales import jd_tt, tai_minus_utc_s, utc_to_gps
from leopod.validation.station_displacement import (
    local_axes,
    ocean_loading_arguments,
    ocean_loading_displacement,
    pole_tide_displacement,
    solid_tide_displacement,
    station_displacements,
    tt_seconds_j2000,
)

MAS = np.pi / (180.0 * 3600.0 * 1000.0)
ARCSEC = MAS * 1000.0

#: Test cases printed in the header of the IERS Conventions routine DEHANTTIDEINEL.F
#: (IERS 2010 software, chapter 7): date (0 h UTC), station, Sun and Moon (ITRF) [m] and the
#: displacement [m]. (The fourth printed case repeats the output of the third with other
#: inputs and is not usable.)
DEHANT_CASES = [
    ("2009-04-13", (4075578.385, 931852.890, 4801570.154),
     (137859926952.015, 54228127881.4350, 23509422341.6960),
     (-179996231.920342, -312468450.131567, -169288918.592160),
     (0.07700420357108125891, 0.06304056321824967613, 0.05516568152597246810)),
    ("2012-07-13", (1112189.660, -4842955.026, 3985352.284),
     (-54537460436.2357, 130244288385.279, 56463429031.5996),
     (300396716.912, 243238281.451, 120548075.939),
     (-0.02036831479592075833, 0.05658254776225972449, -0.07597679676871742227)),
    ("2015-07-15", (1112200.5696, -4842957.8511, 3985345.9122),
     (100210282451.6279, 103055630398.3160, 56855096480.4475),
     (369817604.4348, 1897917.5258, 120804980.8284),
     (0.00509570869172363845, 0.0828663025983528700, -0.0636634925404189617)),
]


def _epoch(date: str):
    """GPS-time epoch, TT seconds since J2000 and GMST (IAU 2006) of 0 h UTC of a date."""
    t = utc_to_gps(np.array([np.datetime64(date, "ns")]))
    eop = default_earth_orientation()
    return t, tt_seconds_j2000(t), erfa.gmst06(*jd_ut1(t, eop), *jd_tt(t))


# ----------------------------------------------------------------------------- solid tide
@pytest.mark.parametrize("date, sta, sun, moon, expected", DEHANT_CASES)
def test_solid_tide_dehanttideinel_cases(date, sta, sun, moon, expected):
    # IERS DEHANTTIDEINEL test cases. The routine's step-2 arguments differ from IERS 2010
    # eq. (5.43) by its extra precession term 1.397°·T in the lunar longitude s (0.13° in
    # 2009: 0.03 mm on K1's 12 mm) and it uses UTC for UT1; its table row "156.564" is read
    # here as 166.564 (0.01 mm). Measured agreement 0.04 mm; tolerance 0.05 mm.
    _, tt, gmst = _epoch(date)
    disp = solid_tide_displacement(np.array(sta), np.array([sun]), np.array([moon]), tt, gmst)
    np.testing.assert_allclose(disp[0], expected, rtol=0, atol=5e-5)


def _dehant_arguments(t_cy: float) -> np.ndarray:
    """Doodson arguments (τ, s, h, p, N', p_s) [rad] of DEHANTTIDEINEL (subroutine STEP2DIU)
    at 0 h UTC, T in TT Julian centuries: the polynomials printed in the routine, with its
    precession term added to s after τ is formed."""
    t = t_cy
    s = 218.31664563 + (481267.88194 + (-0.0014663889 + 0.00000185139 * t) * t) * t
    tau = 280.4606184 + (36000.7700536 + (0.00038793 - 0.0000000258 * t) * t) * t - s
    s += (1.396971278 + (0.000308889 + (0.000000021 + 0.000000007 * t) * t) * t) * t
    h = 280.46645 + (36000.7697489 + (0.00030322222 + (0.000000020 - 0.00000000654 * t)
                                      * t) * t) * t
    p = 83.35324312 + (4069.01363525 + (-0.01032172222 + (-0.0000124991 + 0.00000005263 * t)
                                        * t) * t) * t
    n_prime = 234.95544499 + (1934.13626197 + (-0.00207561111 + (-0.00000213944
                                                                + 0.00000001650 * t) * t)
                              * t) * t
    p_s = 282.93734098 + (1.71945766667 + (0.00045688889 + (-0.00000001778
                                                           - 0.00000000334 * t) * t) * t) * t
    return np.radians([[tau, s, h, p, n_prime, p_s]])


@pytest.mark.parametrize("date, sta, sun, moon, expected", DEHANT_CASES)
def test_solid_tide_formulas_reproduce_dehanttideinel(monkeypatch, date, sta, sun, moon,
                                                      expected):
    # With the routine's own tidal arguments and its table row 156.564 (multipliers
    # 1 0 1 0 1 -1 of τ s h p N' p_s), steps 1 and 2 reproduce the printed values to the
    # level of the mass ratios (the routine's 332946.0482 and 0.0123000371 vs IERS/DE421
    # GM values): 2e-9 m measured, tolerance 1e-8 m.
    t_utc = np.array([np.datetime64(date, "ns")])
    tai_utc = tai_minus_utc_s(utc_to_gps(t_utc))[0]
    days = (t_utc[0] - np.datetime64("2000-01-01T12:00", "ns")) / np.timedelta64(1, "D")
    t_cy = (days + (tai_utc + 32.184) / 86400.0) / 36525.0
    mult, amp = sd._STEP2_DIURNAL
    mult = mult.copy()
    mult[np.flatnonzero((mult == [1, 1, 1, 0, 1, -1]).all(axis=1))[0]] = [1, 0, 1, 0, 1, -1]
    monkeypatch.setattr(sd, "_STEP2_DIURNAL", (mult, amp))
    monkeypatch.setattr(sd, "doodson_arguments", lambda t, g: _dehant_arguments(t_cy))
    disp = solid_tide_displacement(np.array(sta), np.array([sun]), np.array([moon]), 0.0, 0.0)
    np.testing.assert_allclose(disp[0], expected, rtol=0, atol=1e-8)


def test_station_displacements_use_de421_and_eop():
    # The GPS-time interface equals the formula fed with DE421 Sun and Moon rotated to the
    # ITRF by leopod.frames.earth_rotation.gcrf_to_itrf (IAU 2006/2000A + EOP); Graz over
    # one day: displacement of decimetres (IERS 2010 sec. 7.1.1: up to ~0.4 m).
    t = np.datetime64("2021-03-01T00:00", "ns") + np.arange(0, 86400, 3600) * \
        np.timedelta64(1, "s")
    graz = np.array([4194426.0, 1162694.0, 4647247.0])
    tt = tt_seconds_j2000(t)
    eph = Ephemeris()
    sun, _ = gcrf_to_itrf(t, eph.sun_m(tt))
    moon, _ = gcrf_to_itrf(t, eph.moon_m(tt))
    eop = default_earth_orientation()
    gmst = erfa.gmst06(*jd_ut1(t, eop), *jd_tt(t))
    disp = station_displacements(t, graz)
    np.testing.assert_allclose(disp.solid_tide_m,
                               solid_tide_displacement(graz, sun, moon, tt, gmst),
                               rtol=0, atol=1e-9)
    radial = disp.solid_tide_m @ (graz / np.linalg.norm(graz))
    assert 0.1 < np.ptp(radial) < 0.6
    np.testing.assert_array_equal(disp.ocean_loading_m, 0.0)
    np.testing.assert_allclose(disp.total_m, disp.solid_tide_m + disp.pole_tide_m, atol=0)


# ------------------------------------------------------------------------------ pole tide
def test_pole_tide_hand_evaluation():
    # IERS 2010 eq. (7.26) by hand at 45° N, 0° E, at J2000.0 where the secular pole of the
    # 2018 update is (55.0, 320.5) mas: x_p = 0.155", y_p = 0.4205" give m1 = 0.1",
    # m2 = -0.1"; S_r = -33 sin 90° m1 = -3.3 mm, S_θ = -9 cos 90° (...) = 0,
    # S_λ = 9 cos 45° (m1 sin 0 - m2 cos 0) = +0.6364 mm (east).
    c = np.sqrt(0.5)
    pos = R_EARTH_EQUATOR_M * np.array([c, 0.0, c])
    disp = pole_tide_displacement(pos, [0.155 * ARCSEC], [0.4205 * ARCSEC], [0.0])[0]
    expected = -3.3e-3 * np.array([c, 0.0, c]) + 9.0 * c * 0.1e-3 * np.array([0.0, 1.0, 0.0])
    np.testing.assert_allclose(disp, expected, rtol=0, atol=1e-9)


def test_pole_tide_from_its_potential():
    # IERS 2010 eqs. (7.24), (7.25): ΔV = -(Ω² r²/2) sin 2θ (m1 cos λ + m2 sin λ),
    # S_r = h ΔV/g, S_θ = (l/g) ∂ΔV/∂θ, S_λ = (l/(g sin θ)) ∂ΔV/∂λ with h = 0.6207,
    # l = 0.0836, g = 9.7803 m/s², r = a; derivatives by central differences. The
    # coefficients -33 and 9 mm of eq. (7.26) are this rounded to 2 digits: tolerance 2 %
    # of the largest component + 0.02 mm.
    h, l, g = 0.6207, 0.0836, 9.7803
    rng = np.random.default_rng(5)
    m1, m2 = 0.12, -0.27                                              # arcsec
    xp = np.array([(55.0 + 1000 * m1) * MAS])
    yp = np.array([(320.5 - 1000 * m2) * MAS])
    for _ in range(5):
        theta, lam = rng.uniform(0.2, np.pi - 0.2), rng.uniform(-np.pi, np.pi)

        def dv(th, la):
            return (-(OMEGA_EARTH_RAD_S**2 * R_EARTH_EQUATOR_M**2 / 2) * np.sin(2 * th)
                    * (m1 * np.cos(la) + m2 * np.sin(la)) * ARCSEC)

        e = 1e-6
        s_r = h * dv(theta, lam) / g
        s_th = l / g * (dv(theta + e, lam) - dv(theta - e, lam)) / (2 * e)
        s_la = l / (g * np.sin(theta)) * (dv(theta, lam + e) - dv(theta, lam - e)) / (2 * e)
        pos = R_EARTH_EQUATOR_M * np.array([np.sin(theta) * np.cos(lam),
                                            np.sin(theta) * np.sin(lam), np.cos(theta)])
        r_hat, e_hat, n_hat = (v[0] for v in local_axes(pos))
        disp = pole_tide_displacement(pos, xp, yp, [0.0])[0]
        got = np.array([disp @ r_hat, -(disp @ n_hat), disp @ e_hat])
        ref = np.array([s_r, s_th, s_la])
        np.testing.assert_allclose(got, ref, rtol=0, atol=0.02 * np.abs(ref).max() + 2e-5)


# -------------------------------------------------------------------------- ocean loading
#: IERS Conventions software ARG2.F (revision of 7 October 2011), test case: year 2008,
#: day 311.5 (6 November, 12 h UT) -> angles of M2 S2 N2 K2 K1 O1 P1 Q1 Mf Mm Ssa [rad].
ARG2_CASE = np.array([2.849663065753787805, 6.28318080000000023, 4.926040134021299366,
                      1.608450491115348768, 2.375021572352622456, 0.4746414933980958040,
                      3.908159227647345801, 2.551018561669245344, 5.041990012540757959,
                      4.206816878908014701, 1.608463638294885811])


def test_ocean_loading_arguments_arg2_case():
    # ARG2 uses mean longitudes of 1900-based series and rounded speeds; the Doodson
    # arguments of IERS 2010 eq. (5.43) with GMST (IAU 2006) differ by 0.017° at most
    # (measured); tolerance 0.03° (BLQ phases are given to 0.1°).
    _, tt, gmst = _epoch("2008-11-06T12:00")
    chi, _, _ = ocean_loading_arguments(tt, gmst)
    diff = (chi[0] - ARG2_CASE + np.pi) % (2 * np.pi) - np.pi
    np.testing.assert_allclose(diff, 0.0, atol=np.radians(0.03))


def test_ocean_loading_single_constituent():
    # Analytic: one constituent (M2), amplitude 10 mm, phase lag equal to its ARG2 argument at
    # the ARG2 test epoch -> Δc = f A cos(u) with Pugh (1987) Table 4.3:
    # f = 1 - 0.037 cos N, u = -2.1° sin N, N = Ω from erfa.faom03 (IERS 2003 eq. 5.43).
    t, tt, gmst = _epoch("2008-11-06T12:00")
    node = erfa.faom03(tt[0] / (86400.0 * 36525.0))
    f, u = 1 - 0.037 * np.cos(node), np.radians(-2.1 * np.sin(node))
    expected = 0.010 * f * np.cos(u)
    pos = np.array([4075578.385, 931852.890, 4801570.154])
    r_hat, e_hat, n_hat = (v[0] for v in local_axes(pos))
    phase = np.zeros((3, 11))
    phase[:, 0] = np.degrees(ARG2_CASE[0])
    for comp, axis in ((0, r_hat), (1, -e_hat), (2, -n_hat)):     # up, west, south
        amp = np.zeros((3, 11))
        amp[comp, 0] = 0.010
        disp = ocean_loading_displacement(pos, amp, phase, tt, gmst)[0]
        # the M2 argument differs by 0.012° from ARG2 (test above): < 1e-7 m here
        np.testing.assert_allclose(disp, expected * axis, rtol=0, atol=1e-7)
    # a quarter of the M2 period (12.4206012 h, speed 28.9841042°/h) later the argument has
    # turned by 90°: Δc = f A cos(u + 90°) = -f A sin u; here the 0.012° M2 argument
    # difference to ARG2 enters fully: 0.012° × 10 mm = 2 µm, tolerance 3 µm
    later = t + np.timedelta64(round(12.4206012 * 3600 / 4 * 1e9), "ns")
    eop = default_earth_orientation()
    amp = np.zeros((3, 11))
    amp[0, 0] = 0.010
    disp = ocean_loading_displacement(pos, amp, phase, tt_seconds_j2000(later),
                                      erfa.gmst06(*jd_ut1(later, eop), *jd_tt(later)))[0]
    assert disp @ r_hat == pytest.approx(-0.010 * f * np.sin(u), abs=3e-6)


def test_ocean_loading_through_station_displacements():
    # NaN coefficients (station not in the BLQ file) give no loading; finite ones the
    # displacement of ocean_loading_displacement (same epoch, same arguments).
    t = np.array(["2021-03-01T03:00", "2021-03-01T04:00"], dtype="datetime64[ns]")
    pos = np.array([4194426.0, 1162694.0, 4647247.0])
    amp = np.full((2, 3, 11), 0.004)
    phase = np.full((2, 3, 11), 30.0)
    amp[1] = np.nan
    disp = station_displacements(t, pos, solid_tide=False, pole_tide=False,
                                 blq_amplitude_m=amp, blq_phase_deg=phase)
    eop = default_earth_orientation()
    direct = ocean_loading_displacement(pos, amp[0], phase[0], tt_seconds_j2000(t[:1]),
                                        erfa.gmst06(*jd_ut1(t[:1], eop), *jd_tt(t[:1])))
    np.testing.assert_allclose(disp.ocean_loading_m[0], direct[0], rtol=0, atol=1e-12)
    np.testing.assert_array_equal(disp.ocean_loading_m[1], 0.0)
    np.testing.assert_array_equal(disp.solid_tide_m, 0.0)


# ------------------------------------------------------------------------------------ BLQ
BLQ_TEXT = """$$ Ocean loading displacement
$$
$$ Ocean tide model: FES2004 (synthetic numbers for the test)
$$ END HEADER
$$
  ONSA
$$ Computed by OLMPP by H G Scherneck, Onsala Space Observatory
$$ ONSA,                 RADI TANG  lon/lat:   11.9264   57.3958   45.0000
  .00344 .00121 .00078 .00034 .00170 .00095 .00056 .00015 .00019 .00010 .00009
  .00093 .00026 .00020 .00007 .00033 .00024 .00011 .00004 .00002 .00002 .00001
  .00071 .00013 .00016 .00004 .00042 .00021 .00014 .00003 .00003 .00001 .00001
   -64.6  -38.7  -83.1  -39.3   71.6  -13.0   70.2  -21.5   -6.9   -5.6   -1.2
   -80.2  -52.4 -102.5  -51.3  104.1   32.4  100.5   15.9 -170.3 -154.0   -3.9
   -52.0  -21.4  -61.5  -23.0   11.2   -5.8   14.0  -26.5  174.6  178.2  179.8
  7090
$$ comment inside a block
  .00100 .00200 .00300 .00400 .00500 .00600 .00700 .00800 .00900 .01000 .01100
  .00100 .00200 .00300 .00400 .00500 .00600 .00700 .00800 .00900 .01000 .01100
  .00100 .00200 .00300 .00400 .00500 .00600 .00700 .00800 .00900 .01000 .01100
    10.0   20.0   30.0   40.0   50.0   60.0   70.0   80.0   90.0  100.0  110.0
    10.0   20.0   30.0   40.0   50.0   60.0   70.0   80.0   90.0  100.0  110.0
    10.0   20.0   30.0   40.0   50.0   60.0   70.0   80.0   90.0  100.0 -110.0
$$ END TABLE
"""


def test_read_blq(tmp_path):
    # Format of the Onsala loading service (IERS 2010 sec. 7.1.2): amplitudes [m] up, west,
    # south, then phases [deg], constituents M2 S2 N2 K2 K1 O1 P1 Q1 Mf Mm Ssa.
    path = tmp_path / "stations.blq"
    path.write_text(BLQ_TEXT)
    ds = read_blq(path)
    assert list(ds["site"].values) == ["ONSA", "7090"]
    assert tuple(ds["constituent"].values) == BLQ_CONSTITUENTS
    assert ds["amplitude_m"].sel(site="ONSA", component="up", constituent="M2") == 0.00344
    assert ds["amplitude_m"].sel(site="ONSA", component="south", constituent="K1") == 0.00042
    assert ds["phase_deg"].sel(site="ONSA", component="west", constituent="Q1") == 15.9
    assert ds["phase_deg"].sel(site="7090", component="south", constituent="SSA") == -110.0


@pytest.mark.parametrize("text, message", [
    # a missing line: the block runs into the next station name
    (BLQ_TEXT.replace("  .00071 .00013 .00016 .00004 .00042 .00021 .00014 .00003 .00003 "
                      ".00001 .00001\n", ""), "1 fields, expected 11"),
    (BLQ_TEXT.replace("-52.0  -21.4", "-52.0"), "10 fields, expected 11"),
    (BLQ_TEXT.replace("$$ END TABLE", "  .001 .001 .001 .001 .001 .001 .001 .001 .001 .001 "
                      ".001"), "numbers before any station name"),
    (BLQ_TEXT.split("  7090")[0] + "  7090\n", "needs 6 lines"),
    (BLQ_TEXT.replace("  7090", "  ONSA"), "twice"),
    ("$$ nothing\n", "no station"),
])
def test_read_blq_errors(tmp_path, text, message):
    path = tmp_path / "bad.blq"
    path.write_text(text)
    with pytest.raises(FormatError, match=message):
        read_blq(path)
